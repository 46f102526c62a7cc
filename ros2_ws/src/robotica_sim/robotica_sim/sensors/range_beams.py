"""
What the range sensors share: where a mounted sensor is, its beam's rays, its sample times.

A range sensor is mounted at (x, y, yaw) in ``base_link`` (REP-103: x forward, yaw
counter-clockwise); the robot's pose (x, y, θ) is in the map frame, where the world model is.
A beam is cast as a few rays across its cone (book §7.4: the cone of a sonar or infrared
sensor; a laser beam is one ray). Sample times follow a rate on the time that comes in (the
truth's stamps): :class:`SampleSchedule`.
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['SampleSchedule', 'check_mounts', 'cone_offsets', 'mounted_frames', 'noisy_readings']


def check_mounts(mounts: ArrayLike, name: str = 'mounts') -> NDArray[np.float64]:
    """
    Return the mount poses as an (n, 3) float64 array of (x [m], y [m], yaw [rad]).

    Raises ValueError naming ``name`` for a wrong shape, no sensor or a non-finite value.

    >>> check_mounts([0.1, 0.0, 0.0]).shape
    (1, 3)
    """
    m = np.atleast_2d(np.asarray(mounts, dtype=np.float64))
    if m.ndim != 2 or m.shape[1] != 3 or len(m) == 0:
        raise ValueError(f'{name} must be (x, y, yaw) triples, got shape {np.shape(mounts)}')
    if not np.isfinite(m).all():
        raise ValueError(f'{name} must be finite')
    return m


def mounted_frames(pose: ArrayLike, mounts: NDArray[np.float64],
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return each sensor's origin (n, 2) [m] and heading (n,) [rad] in the map frame.

    ``pose`` is the robot's (x, y, θ) in the map frame; ``mounts`` (n, 3) each sensor's
    (x, y, yaw) in ``base_link``. Raises ValueError for a non-finite pose.

    >>> origins, yaws = mounted_frames([1.0, 0.0, math.pi / 2], np.array([[0.5, 0.0, 0.0]]))
    >>> origins.round(6).tolist(), yaws.round(6).tolist()
    ([[1.0, 0.5]], [1.570796])
    """
    p = np.asarray(pose, dtype=np.float64)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f'pose must be a finite (x, y, theta), got {pose!r}')
    c, s = math.cos(p[2]), math.sin(p[2])
    origins = np.column_stack([p[0] + c * mounts[:, 0] - s * mounts[:, 1],
                               p[1] + s * mounts[:, 0] + c * mounts[:, 1]])
    return origins, p[2] + mounts[:, 2]


def cone_offsets(half_angle: float, rays: int) -> NDArray[np.float64]:
    """
    Return ``rays`` angles [rad] evenly across the cone [-half_angle, half_angle].

    One ray is the axis alone; an odd count includes the axis.

    >>> np.degrees(cone_offsets(math.radians(15.0), 5)).round(6).tolist()
    [-15.0, -7.5, 0.0, 7.5, 15.0]
    """
    if rays == 1:
        return np.zeros(1)
    return np.linspace(-half_angle, half_angle, rays)


def noisy_readings(rng: np.random.Generator, nearest: NDArray[np.float64],
                   detected: NDArray[np.bool_], min_range: float, max_range: float,
                   sigma0: float, sigma_per_metre: float) -> NDArray[np.float64]:
    """
    Return a Range sensor's readings (n,) [m] of its ``nearest`` ranges (n,) [m].

    Where ``detected``: the range (``min_range`` if nearer) plus normal noise of standard
    deviation σ = σ0 + k·r, clipped to [min_range, max_range]; elsewhere ``max_range``, no
    noise (the sensor's "nothing"). One normal draw per sensor whatever it detected, so that
    the draws do not depend on the world.

    >>> noisy_readings(np.random.default_rng(0), np.array([0.05, 2.0, np.inf]),
    ...                np.array([True, True, False]), 0.1, 5.0, 0.0, 0.0).tolist()
    [0.1, 2.0, 5.0]
    """
    w = rng.standard_normal(nearest.shape)
    r = np.where(detected, np.maximum(nearest, min_range), 0.0)
    noisy = np.clip(r + (sigma0 + sigma_per_metre * r) * w, min_range, max_range)
    return np.where(detected, noisy, max_range)


class SampleSchedule:
    """
    Sample times at ``rate`` [Hz] on the time that comes in (a truth message's stamp).

    :meth:`due` says whether a time t crosses the next sample time: the first t starts the
    schedule (a sample), then every t at or beyond the next sample time is one, the next one
    moving on by whole periods (samples the input skipped are not made up). A t earlier than
    the last sample (time restarted) starts the schedule again.

    >>> schedule = SampleSchedule(10.0)
    >>> [schedule.due(t) for t in (0.0, 0.05, 0.1, 0.12, 0.35)]
    [True, False, True, False, True]
    """

    def __init__(self, rate: float) -> None:
        if not (math.isfinite(rate) and rate > 0.0):
            raise ValueError(f'rate must be finite and > 0 Hz, got {rate!r}')
        self._period = 1.0 / rate
        self._next: float | None = None
        self._last = -math.inf

    def due(self, t: float) -> bool:
        """Return True when time ``t`` [s] is a sample time (class docstring)."""
        if self._next is None or t < self._last:
            self._next, self._last = t + self._period, t
            return True
        # Tolerance of a nanosecond: stamps in whole nanoseconds of a period such as 1/75 s.
        if t < self._next - 1e-9:
            return False
        periods = math.floor((t - self._next) / self._period + 1e-9) + 1
        self._next += periods * self._period
        self._last = t
        return True
