"""Array type aliases of the core modules (REP-103 frames, SI units, radians)."""  # noqa: A005

from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

__all__ = ['Pose2D', 'Vector']

Vector: TypeAlias = NDArray[np.float64]
"""A float64 vector of shape (n,), never (n, 1)."""

Pose2D: TypeAlias = NDArray[np.float64]
"""A planar pose of shape (3,): x [m], y [m], θ [rad] from the x axis (REP-103)."""
