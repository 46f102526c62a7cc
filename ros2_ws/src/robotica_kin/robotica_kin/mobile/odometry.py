"""
Dead-reckoning odometry of a differential-drive robot from wheel encoders.

Book §4.7.5 (dead reckoning (4.131)) with the exact circular-arc update (4.93) of §4.7.2, and
the encoder update of the mobile-robotics slides [S]: conversion factor C_m = π D / (n C_e)
[m per tick], ΔU_c = (ΔU_i + ΔU_d)/2, Δθ = (ΔU_d - ΔU_i)/b. Seed catalog sections 2.7, 2.9 and
13.6. Everything is in REP-103 (θ from the world x axis); the pose lives in ``odom``, the twist
in ``base_link``.
"""

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.angles import wrap_to_pi
from robotica_kin.mobile.differential_drive import DifferentialDriveParams
from robotica_kin.types import Pose2D

__all__ = ['DiffDriveOdometry', 'ODOMETRY_METHODS', 'odometry_increment']

ODOMETRY_METHODS = ('euler', 'midpoint', 'exact_arc')
"""Pose-update rules of :func:`odometry_increment`."""


def _as_pose(pose: ArrayLike) -> Pose2D:
    array = np.asarray(pose, dtype=np.float64)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise ValueError(f'pose must be a finite (x, y, theta) of shape (3,), got {pose!r}')
    return array


def odometry_increment(
    pose: ArrayLike,
    delta_left: float,
    delta_right: float,
    wheel_separation: float,
    method: str = 'exact_arc',
) -> Pose2D:
    """
    Return the pose after the wheels travel ``delta_left`` and ``delta_right``.

    With ΔU_c = (ΔU_i + ΔU_d)/2 and Δθ = (ΔU_d - ΔU_i)/b (slides [S]):

    * ``'euler'``: the slides' update, with the *updated* heading θ_c = θ + Δθ:
      x += ΔU_c cos θ_c, y += ΔU_c sin θ_c.
    * ``'midpoint'``: the same with the heading θ + Δθ/2.
    * ``'exact_arc'``: the circular arc of book (4.93) in REP-103 form,
      x += (ΔU_c/Δθ)(sin(θ+Δθ) - sin θ), y -= (ΔU_c/Δθ)(cos(θ+Δθ) - cos θ); exact when the
      wheel speeds are constant over the sample (§4.7.1). It is evaluated as the equal chord
      along the mid-heading, x += ΔU_c (sin h / h) cos(θ + h), y += ΔU_c (sin h / h) sin(θ + h)
      with h = Δθ/2, which has no 0/0 at Δθ = 0 and none of the cancellation of the difference
      of sines for small turns.

    Parameters
    ----------
    pose : array_like, shape (3,)
        Pose (x [m], y [m], θ [rad]) of ``base_link`` in ``odom`` before the motion.
    delta_left, delta_right : float
        Distances ΔU_i, ΔU_d [m] travelled by the left and right wheels, positive forwards.
    wheel_separation : float
        Track b [m], > 0.
    method : str
        One of :data:`ODOMETRY_METHODS`.

    Returns
    -------
    ndarray, shape (3,)
        Pose after the motion, θ wrapped to (-π, π].

    Raises
    ------
    ValueError
        On a non-finite input, a pose of the wrong shape, b <= 0 or an unknown method.

    Examples
    --------
    >>> odometry_increment([0.0, 0.0, 0.0], 0.4 * math.pi, 0.6 * math.pi, 0.4)  # R = 1 m
    array([1.        , 1.        , 1.57079633])

    """
    x, y, theta = _as_pose(pose)
    if not (math.isfinite(delta_left) and math.isfinite(delta_right)):
        raise ValueError(f'wheel travels must be finite, got {delta_left!r}, {delta_right!r}')
    if not (math.isfinite(wheel_separation) and wheel_separation > 0.0):
        raise ValueError(f'wheel_separation must be finite and > 0 m, got {wheel_separation!r}')
    if method not in ODOMETRY_METHODS:
        raise ValueError(f'method must be one of {ODOMETRY_METHODS}, got {method!r}')
    delta_c = 0.5 * (delta_left + delta_right)
    delta_theta = (delta_right - delta_left) / wheel_separation
    if method == 'exact_arc':
        half = 0.5 * delta_theta
        chord = delta_c * (math.sin(half) / half if half != 0.0 else 1.0)
        x += chord * math.cos(theta + half)
        y += chord * math.sin(theta + half)
    else:
        heading = theta + (delta_theta if method == 'euler' else 0.5 * delta_theta)
        x += delta_c * math.cos(heading)
        y += delta_c * math.sin(heading)
    return np.array([x, y, wrap_to_pi(theta + delta_theta)])


class DiffDriveOdometry:
    """
    Dead reckoning from cumulative wheel-encoder tick counts (slides [S], book §4.7.5).

    The first :meth:`update` after construction or :meth:`reset` only latches the counts and
    the time. Each later one turns the tick differences into wheel travels with
    C_m = 2π c / ticks_per_revolution [m/tick] (the slides' π D / (n C_e)), moves the pose with
    :func:`odometry_increment` and, when time advanced, sets the twist v = ΔU_c/Δt,
    ω = Δθ/Δt. Time is an argument; the class never reads a clock.

    Parameters
    ----------
    params : DifferentialDriveParams
        Wheel radius c [m] and track b [m].
    ticks_per_revolution : int
        Encoder ticks per wheel revolution (after decoding and gearing), > 0.
    method : str
        Pose-update rule, one of :data:`ODOMETRY_METHODS`.

    Raises
    ------
    ValueError
        If ``ticks_per_revolution`` is not a positive integer or ``method`` is unknown.

    Examples
    --------
    >>> odom = DiffDriveOdometry(DifferentialDriveParams(0.1, 0.4), ticks_per_revolution=1000)
    >>> odom.update(0, 0, t=0.0)
    array([0., 0., 0.])
    >>> odom.update(1000, 1000, t=2.0)  # one wheel revolution each: 2π c forward
    array([0.62831853, 0.        , 0.        ])
    >>> odom.twist
    (0.3141592653589793, 0.0)

    """

    _params: DifferentialDriveParams
    _method: str
    _meters_per_tick: float
    _pose: Pose2D
    _twist: tuple[float, float]
    _latched: tuple[float, float, float] | None

    def __init__(
        self,
        params: DifferentialDriveParams,
        ticks_per_revolution: int,
        method: str = 'exact_arc',
    ) -> None:
        if (isinstance(ticks_per_revolution, bool)
                or not isinstance(ticks_per_revolution, numbers.Integral)
                or ticks_per_revolution <= 0):
            raise ValueError(
                f'ticks_per_revolution must be an integer > 0, got {ticks_per_revolution!r}')
        if method not in ODOMETRY_METHODS:
            raise ValueError(f'method must be one of {ODOMETRY_METHODS}, got {method!r}')
        self._params = params
        self._method = method
        self._meters_per_tick = 2.0 * math.pi * params.wheel_radius / int(ticks_per_revolution)
        self.reset()

    def reset(self, pose: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        """
        Set the pose (x [m], y [m], θ [rad]) in ``odom``, zero the twist, forget the ticks.

        Raises
        ------
        ValueError
            If ``pose`` is not a finite vector of shape (3,).

        """
        self._pose = _as_pose(pose).copy()
        self._pose[2] = wrap_to_pi(float(self._pose[2]))
        self._twist = (0.0, 0.0)
        self._latched = None

    def update(self, left_ticks: int, right_ticks: int, t: float) -> Pose2D:
        """
        Integrate the cumulative tick counts read at time ``t`` [s]; return the new pose.

        Parameters
        ----------
        left_ticks, right_ticks : int
            Cumulative encoder counts of the left and right wheels, increasing forwards.
        t : float
            Time of the reading [s], not earlier than the previous one.

        Returns
        -------
        ndarray, shape (3,)
            Pose (x [m], y [m], θ [rad]) of ``base_link`` in ``odom``, a copy.

        Raises
        ------
        ValueError
            If an input is not finite or ``t`` is earlier than the previous reading; the
            state is then left unchanged.

        """
        for name, value in (('left_ticks', left_ticks), ('right_ticks', right_ticks), ('t', t)):
            if not math.isfinite(value):
                raise ValueError(f'{name} must be finite, got {value!r}')
        if self._latched is not None:
            last_left, last_right, last_t = self._latched
            dt = t - last_t
            if dt < 0.0:
                raise ValueError(f'time went backwards: t = {t!r} s after {last_t!r} s')
            delta_left = self._meters_per_tick * (left_ticks - last_left)
            delta_right = self._meters_per_tick * (right_ticks - last_right)
            b = self._params.wheel_separation
            self._pose = odometry_increment(self._pose, delta_left, delta_right, b, self._method)
            if dt > 0.0:
                self._twist = (0.5 * (delta_left + delta_right) / dt,
                               (delta_right - delta_left) / b / dt)
        self._latched = (left_ticks, right_ticks, t)
        return self.pose

    @property
    def pose(self) -> Pose2D:
        """Pose (x [m], y [m], θ [rad]) of ``base_link`` in ``odom``, shape (3,), a copy."""
        return self._pose.copy()

    @property
    def twist(self) -> tuple[float, float]:
        """Body velocity (v [m/s], ω [rad/s]) in ``base_link`` over the last interval."""
        return self._twist
