"""
Dead-reckoning pose update of a differential-drive robot from its wheels' travel.

Book §4.7.5 (dead reckoning (4.131)) with the exact circular-arc update (4.93) of §4.7.2, and
the encoder update of the mobile-robotics slides [S]: ΔU_c = (ΔU_i + ΔU_d)/2,
Δθ = (ΔU_d - ΔU_i)/b, the wheel travels ΔU = C_m Δticks coming from the encoders through
:func:`robotica_kin.mobile.odometry_fusion.metres_per_tick` (C_m = π D / (n C_e) [m per tick]),
where :class:`~robotica_kin.mobile.odometry_fusion.OdometryFusion` applies this update. Seed
catalog sections 2.7, 2.9 and 13.6. Everything is in REP-103 (θ from the world x axis); the pose
lives in ``odom``.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.angles import wrap_to_pi
from robotica_kin.types import Pose2D

__all__ = ['ODOMETRY_METHODS', 'odometry_increment']

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
