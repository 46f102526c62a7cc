"""
The recent poses of a vehicle by time stamp, to place a sensor reading taken at another stamp.

A node that fuses readings (a scan, a sonar echo) needs the pose at each reading's stamp: the
simulator's sensor emulators sample on the truth's stamps, so the nearest kept pose is exact
there, and a pose farther than a tolerance from the reading is no pose for it.
"""
from collections import deque
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['PoseHistory']


class PoseHistory:
    """
    The last ``size`` poses (x [m], y [m], θ [rad]) with their stamps [s].

    >>> history = PoseHistory(size=2)
    >>> history.add(0.0, (0.0, 0.0, 0.0)); history.add(0.1, (0.1, 0.0, 0.0))
    >>> history.nearest(0.09, tolerance=0.02).tolist(), history.nearest(0.5, 0.02)
    ([0.1, 0.0, 0.0], None)
    >>> history.latest
    0.1
    """

    def __init__(self, size: int = 200) -> None:
        if not (isinstance(size, int) and size > 0):
            raise ValueError(f'size must be an integer > 0, got {size!r}')
        self._poses: deque[tuple[float, NDArray[np.float64]]] = deque(maxlen=size)

    def __len__(self) -> int:
        """Return how many poses are kept."""
        return len(self._poses)

    @property
    def latest(self) -> float:
        """Return the stamp [s] of the newest pose (-inf when there is none)."""
        return self._poses[-1][0] if self._poses else -math.inf

    def add(self, stamp: float, pose: ArrayLike) -> None:
        """Keep ``pose`` (x, y, θ) of time ``stamp`` [s]; ValueError if it is not finite."""
        p = np.asarray(pose, dtype=np.float64)
        if p.shape != (3,) or not np.isfinite(p).all() or not np.isfinite(stamp):
            raise ValueError(f'a pose must be a finite (x, y, theta) at a finite stamp, got '
                             f'{p.tolist()} at {stamp!r}')
        self._poses.append((float(stamp), p))

    def nearest(self, stamp: float, tolerance: float) -> Optional[NDArray[np.float64]]:
        """Return the kept pose nearest ``stamp`` [s], or None if none is within ``tolerance``."""
        if not self._poses:
            return None
        gap, pose = min(((abs(s - stamp), p) for s, p in self._poses), key=lambda g: g[0])
        return pose if gap <= tolerance else None
