"""
Open-loop commands: a velocity profile played against time, as the book's Simulink examples do.

Ejemplo 4.9 (§4.7.5) drives a differential robot with given wheel speeds, among them a ramp;
Ejemplo 4.8 (§4.7.4) gives a tricycle the (v, ω) of a circle. A profile is a table of times
t_k [s] with the forward speed v_k [m/s] and the yaw rate ω_k [rad/s] of the guide point,
interpolated linearly between the rows (so a ramp is two rows) and held after the last one. No
feedback: what the vehicle does with it is what the book plots.

:class:`OpenLoop` plays a profile as a tracking law (the ``path_tracker`` node's ``open_loop``,
gains ``times``, ``linear`` and ``angular``): it reads only the time, never the pose or a path,
so it measures no tracking error.
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.tracker_base import replace_gains, TrackerOutput

__all__ = ['OpenLoop', 'OpenLoopProfile']


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


class OpenLoop:
    """
    The tracking law that plays an :class:`OpenLoopProfile` against time, without feedback.

    :meth:`update` returns the profile's (v, ω) at its ``time``; the pose and the speed are not
    read. The errors and the target point of its :class:`TrackerOutput` are NaN (no path is
    followed) and it never finishes.

    >>> law = OpenLoop(OpenLoopProfile([0.0, 10.0], [0.125, 0.25], [-0.25, 0.0]))
    >>> out = law.update([0.0, 0.0, 0.0], 5.0)
    >>> out.linear, out.angular, out.cross_track, out.finished
    (0.1875, -0.125, nan, False)
    """

    def __init__(self, profile: OpenLoopProfile) -> None:
        self._profile = profile
        self._no_target = np.full(2, math.nan)
        self._no_target.flags.writeable = False

    @property
    def profile(self) -> OpenLoopProfile:
        """Return the profile played."""
        return self._profile

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """Return the profile's (v [m/s], ω [rad/s]) at ``time`` [s]; no errors (NaN)."""
        linear, angular = self._profile.command(time)
        return TrackerOutput(linear, angular, math.nan, math.nan, math.nan, self._no_target,
                             False)

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace ``times``, ``linear`` or ``angular``; ValueError keeps the old profile."""
        self._profile = replace_gains(self._profile, gains)

    def reset(self) -> None:
        """Do nothing: the profile is played against the time of each update."""
