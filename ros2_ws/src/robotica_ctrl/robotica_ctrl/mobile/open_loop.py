"""
Open-loop commands: a velocity profile played against time, as the book's Simulink examples do.

Ejemplo 4.9 (§4.7.5) drives a differential robot with given wheel speeds, among them a ramp;
Ejemplo 4.8 (§4.7.4) gives a tricycle the (v, ω) of a circle. A profile is a table of times
t_k [s] with the forward speed v_k [m/s] and the yaw rate ω_k [rad/s] of the guide point,
interpolated linearly between the rows (so a ramp is two rows) and held after the last one. No
feedback: what the vehicle does with it is what the book plots.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['OpenLoopProfile']


@dataclass(frozen=True, eq=False)
class OpenLoopProfile:
    """
    A piecewise-linear profile of (v [m/s], ω [rad/s]) over time [s].

    Raises ValueError unless the three sequences have the same length >= 1, are finite and the
    times strictly increase.

    >>> profile = OpenLoopProfile([0.0, 10.0], [0.125, 0.25], [-0.25, 0.0])   # Ej. 4.9 (c)
    >>> profile.command(5.0)
    (0.1875, -0.125)
    >>> profile.command(30.0)
    (0.25, 0.0)
    """

    times: ArrayLike
    linear: ArrayLike
    angular: ArrayLike

    def __post_init__(self) -> None:
        arrays = []
        for name in ('times', 'linear', 'angular'):
            array = np.array(getattr(self, name), dtype=np.float64)
            if array.ndim != 1 or array.size == 0 or not np.isfinite(array).all():
                raise ValueError(f'{name} must be a non-empty list of finite numbers, got '
                                 f'{getattr(self, name)!r}')
            array.setflags(write=False)
            object.__setattr__(self, name, array)
            arrays.append(array)
        if len({a.size for a in arrays}) != 1:
            raise ValueError('times, linear and angular must have the same length, got '
                             f'{[a.size for a in arrays]}')
        if (np.diff(arrays[0]) <= 0.0).any():
            raise ValueError(f'times must increase strictly, got {arrays[0].tolist()}')

    def command(self, t: float) -> tuple[float, float]:
        """Return (v [m/s], ω [rad/s]) at time ``t`` [s] (held outside the table)."""
        times: NDArray[np.float64] = np.asarray(self.times)
        return (float(np.interp(t, times, np.asarray(self.linear))),
                float(np.interp(t, times, np.asarray(self.angular))))
