"""
A Cartesian reference in time: the straight line from T0 to T1, rest to rest, in a given time.

The path parameter s(t) goes from 0 to 1 in ``duration`` seconds along HEMERO's quintic
``pol5([0, 1], [0, 0], [0, 0], 0, duration, dt)`` (book §10.3.1, zero velocity and acceleration
at both ends), and the poses, twists and accelerations are those of
:func:`~.cartesian_reference.line_references` (book §10.5) at the samples. Before t = 0 the
reference is T0 at rest, after ``duration`` T1 at rest.
"""

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.trajectory.polynomial import pol5

from .cartesian_reference import CartesianReference, line_references

__all__ = ['TimedLine']


class TimedLine:
    """
    The line from ``T0`` to ``T1`` [4x4, {0}] in ``duration`` [s], sampled every ``dt`` [s].

    Raises
    ------
    ValueError
        For poses that are not homogeneous transforms, ``duration <= 0`` or ``dt <= 0`` (or more
        than 10⁶ samples).

    Examples
    --------
    >>> from robotica_kin.transforms import transl
    >>> line = TimedLine(transl(0, 0, 0), transl(1, 0, 0), 2.0, 0.5)
    >>> float(line.at(1.0).T_d[0, 3]), float(line.at(1.0).xd_d[0]), float(line.at(9.0).T_d[0, 3])
    (0.5, 0.9375, 1.0)

    """

    def __init__(self, T0: ArrayLike, T1: ArrayLike, duration: float, dt: float) -> None:
        if not (np.isfinite(duration) and duration > 0.0 and np.isfinite(dt) and dt > 0.0):
            raise ValueError(f'duration and dt must be > 0 s, got {duration!r} and {dt!r}')
        if duration / dt > 1e6:
            raise ValueError(f'duration / dt must be at most 1e6 samples, got {duration / dt:g}')
        _, _, s, sd, sdd = pol5([0.0, 1.0], [0.0, 0.0], [0.0, 0.0], 0.0, duration, dt)
        self.duration = float(duration)
        self.dt = float(dt)
        self._references = line_references(T0, T1, np.clip(s, 0.0, 1.0), sd, sdd)

    def at(self, t: float) -> CartesianReference:
        """Return the reference at ``t`` [s] since the start (the nearest sample)."""
        k = int(round(min(max(t, 0.0), self.duration) / self.dt))
        return self._references[min(k, len(self._references) - 1)]
