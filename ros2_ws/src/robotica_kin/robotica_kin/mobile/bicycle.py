"""
The bicycle model used for tricycle and Ackermann vehicles (Shin & Singh 1990).

Book (4.121), fig. 4.16 (Ollero 2001, §4.7.4): the guide point is the rear-axle midpoint,
which moves at speed v along the vehicle's axis; the front wheel, a wheelbase l ahead, is
steered by α, so the path's curvature is γ = tan α / l and φ' = v γ. (The book's Ackermann
paragraph prints "α = (tg α)/l", a typo for γ: catalog Part 17.) Chapter 9's trackers use it
with the steering α as input. Seed catalog sections 2.8 and 7.

Unlike HEMERO's "bicicleta" blocks ([H] (3.28), (3.32), i.e. :mod:`.tricycle`), whose input
is the *front* wheel's speed, here the input is the guide point's speed v = v_t cos α.
Headings follow :data:`~robotica_kin.mobile.unicycle.HEADING_CONVENTIONS`.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.finite import finite_real
from robotica_kin.mobile.unicycle import _positive, _vector, forward_direction
from robotica_kin.types import Vector

__all__ = [
    'bicycle_deriv',
    'bicycle_direct',
    'bicycle_inverse',
    'curvature_from_steering',
    'steering_from_curvature',
]

_HALF_PI = 0.5 * math.pi


def _steering(steering_angle: float) -> float:
    alpha = finite_real('steering_angle', steering_angle)
    if not abs(alpha) < _HALF_PI:
        raise ValueError(f'steering_angle must be in (-π/2, π/2) rad, got {steering_angle!r}')
    return alpha


def curvature_from_steering(steering_angle: float, wheelbase: float) -> float:
    """
    Return the path curvature γ = tan α / l [1/m] of the rear-axle midpoint.

    Book (4.121); γ > 0 turns left (counter-clockwise). The turning radius is R = 1/γ.

    Parameters
    ----------
    steering_angle : float
        Front-wheel steering angle α [rad] from the vehicle's axis, positive to the left,
        in (-π/2, π/2).
    wheelbase : float
        Distance l [m] from the rear axle to the front wheel, > 0.

    Returns
    -------
    float
        Curvature γ [1/m].

    Raises
    ------
    ValueError
        If an input is not finite, |α| >= π/2 or l <= 0.

    Examples
    --------
    >>> curvature_from_steering(math.atan(0.5), 2.0)
    0.25

    """
    return math.tan(_steering(steering_angle)) / _positive(wheelbase, 'wheelbase')


def steering_from_curvature(curvature: float, wheelbase: float) -> float:
    """
    Return the steering angle α = atan(l γ) [rad] that gives the curvature γ.

    The inverse of :func:`curvature_from_steering`; book (4.119) α = atan(l/R) with R = 1/γ.

    Parameters
    ----------
    curvature : float
        Path curvature γ [1/m] of the rear-axle midpoint, positive to the left.
    wheelbase : float
        Wheelbase l [m], > 0.

    Returns
    -------
    float
        Steering angle α [rad] in (-π/2, π/2).

    Raises
    ------
    ValueError
        If an input is not finite or l <= 0.

    Examples
    --------
    >>> round(math.degrees(steering_from_curvature(1.0, 1.5)), 2)  # Ejemplo 4.8
    56.31

    """
    return math.atan(_positive(wheelbase, 'wheelbase') * finite_real('curvature', curvature))


def bicycle_direct(
    v: float, steering_angle: float, wheelbase: float
) -> tuple[float, float]:
    """
    Return the body twist (v, ω) of the rear-axle midpoint for a speed and a steering angle.

    Book (4.121): ω = φ' = v tan α / l.

    Parameters
    ----------
    v : float
        Speed [m/s] of the rear-axle midpoint along the vehicle's axis (negative reverses).
    steering_angle : float
        Front steering angle α [rad], positive to the left, in (-π/2, π/2).
    wheelbase : float
        Wheelbase l [m], > 0.

    Returns
    -------
    tuple of float
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If an input is not finite, |α| >= π/2 or l <= 0.

    Examples
    --------
    >>> bicycle_direct(2.0, math.atan(0.5), 2.0)
    (2.0, 0.5)

    """
    v_ = finite_real('v', v)
    return v_, v_ * curvature_from_steering(steering_angle, wheelbase)


def bicycle_inverse(v: float, omega: float, wheelbase: float) -> tuple[float, float]:
    """
    Return the (speed, steering angle) that produce a body twist (v, ω).

    Book (4.119): α = atan(l ω / v), valid forwards (v > 0) and in reverse (v < 0). With v = 0
    a standing vehicle (ω = 0) keeps α = 0; turning on the spot (ω ≠ 0) needs α = ±π/2,
    where the rear-axle speed no longer determines the motion: impossible in this model.

    Parameters
    ----------
    v : float
        Speed [m/s] of the rear-axle midpoint.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.
    wheelbase : float
        Wheelbase l [m], > 0.

    Returns
    -------
    tuple of float
        (v [m/s], α [rad] in (-π/2, π/2)).

    Raises
    ------
    ValueError
        If an input is not finite, l <= 0, or v = 0 with ω ≠ 0.

    Examples
    --------
    >>> v, alpha = bicycle_inverse(2.0, 0.5, 2.0)
    >>> v, math.tan(alpha)
    (2.0, 0.5)

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    length = _positive(wheelbase, 'wheelbase')
    if v_ == 0.0:
        if omega_ != 0.0:
            raise ValueError(
                f'the bicycle model cannot turn on the spot: v = 0 with omega = {omega!r}')
        return 0.0, 0.0
    return v_, math.atan(length * omega_ / v_)


def bicycle_deriv(
    t: float,
    state: ArrayLike,
    command: ArrayLike,
    wheelbase: float,
    convention: str = 'rep103',
) -> Vector:
    """
    Return the time derivative of the bicycle model's pose.

    Book (4.121): x' = -v sin φ, y' = v cos φ, φ' = v tan α / l; in REP-103 x' = v cos θ,
    y' = v sin θ, θ' = v tan α / l. The signature fits
    ``rk4_step(bicycle_deriv, t, state, h, command, wheelbase, convention)``.

    Parameters
    ----------
    t : float
        Time [s]; unused (the model is autonomous), present for the integrator.
    state : array_like, shape (3,)
        Pose (x [m], y [m], heading [rad]) of the rear-axle midpoint in the world frame.
    command : array_like, shape (2,)
        (v [m/s] rear-axle midpoint speed, α [rad] front steering angle in (-π/2, π/2)).
    wheelbase : float
        Wheelbase l [m], > 0.
    convention : str
        Heading convention of ``state``, ``'rep103'`` or ``'book'``.

    Returns
    -------
    ndarray, shape (3,)
        (x' [m/s], y' [m/s], heading' [rad/s]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, |α| >= π/2, l <= 0 or an unknown convention.

    Examples
    --------
    >>> bicycle_deriv(0.0, [0.0, 0.0, 0.0], [2.0, math.atan(0.5)], 2.0)
    array([2. , 0. , 0.5])

    """
    pose = _vector(state, 3, 'state')
    v, alpha = _vector(command, 2, 'command')
    _, omega = bicycle_direct(v, alpha, wheelbase)
    cx, cy = forward_direction(pose[2], convention)
    return np.array([v * cx, v * cy, omega])
