"""
Differential-drive kinematics (Ollero 2001, §4.7.4, fig. 4.17b; slides [S]).

Two coaxial drive wheels of radius c [m], track b [m]; the guide point is the midpoint of the
wheel axle. Wheel speeds to body twist (4.109)-(4.110), the inverse (4.111)-(4.112), and the
state model (4.113)-(4.114) written in REP-103 (θ from the world x axis; the book's φ = θ - π/2,
see :mod:`robotica_kin.angles`). Seed catalog sections 2.8 and 13.2.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.mobile.unicycle import _vector
from robotica_kin.types import Vector

__all__ = [
    'DifferentialDriveParams',
    'differential_drive_deriv',
    'twist_to_wheel_speeds',
    'wheel_speeds_to_twist',
]


@dataclass(frozen=True)
class DifferentialDriveParams:
    """
    Geometry of a differential-drive robot (book fig. 4.17b).

    Both dimensions must be finite and > 0; ``__post_init__`` raises ValueError otherwise.

    >>> DifferentialDriveParams(wheel_radius=0.25, wheel_separation=1.0)  # Ejemplo 4.9
    DifferentialDriveParams(wheel_radius=0.25, wheel_separation=1.0)
    """

    wheel_radius: float = 0.1  # c [m]
    wheel_separation: float = 0.4  # b [m], track between the wheel contact points

    def __post_init__(self) -> None:
        """Reject non-finite or non-positive dimensions."""
        for name in ('wheel_radius', 'wheel_separation'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')


def wheel_speeds_to_twist(
    params: DifferentialDriveParams, omega_left: float, omega_right: float
) -> tuple[float, float]:
    """
    Return the body twist of the guide point from the wheel speeds.

    Book (4.109)-(4.110): v = c (ω_d + ω_i) / 2, ω = c (ω_d - ω_i) / b, with ω_i the left
    ("izquierda") and ω_d the right ("derecha") wheel.

    Parameters
    ----------
    params : DifferentialDriveParams
        Wheel radius c [m] and track b [m].
    omega_left, omega_right : float
        Wheel angular speeds ω_i, ω_d [rad/s], positive driving forwards.

    Returns
    -------
    tuple of float
        (v, ω): forward speed [m/s] along the ``base_link`` x axis and yaw rate [rad/s],
        positive counter-clockwise.

    Raises
    ------
    ValueError
        If a wheel speed is not finite.

    Examples
    --------
    >>> wheel_speeds_to_twist(DifferentialDriveParams(0.25, 1.0), 1.0, 1.2)
    (0.275, 0.05)

    """
    w_left, w_right = _vector((omega_left, omega_right), 2, 'wheel speeds')
    c, b = params.wheel_radius, params.wheel_separation
    return float(c * (w_right + w_left) / 2.0), float(c * (w_right - w_left) / b)


def twist_to_wheel_speeds(
    params: DifferentialDriveParams, v: float, omega: float
) -> tuple[float, float]:
    """
    Return the wheel speeds that produce a body twist (inverse kinematics).

    Book (4.111)-(4.112): ω_i = (v - (b/2) ω) / c, ω_d = (v + (b/2) ω) / c.

    Parameters
    ----------
    params : DifferentialDriveParams
        Wheel radius c [m] and track b [m].
    v : float
        Forward speed [m/s] along the ``base_link`` x axis.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float
        (ω_left, ω_right) = (ω_i, ω_d) [rad/s].

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> twist_to_wheel_speeds(DifferentialDriveParams(0.25, 1.0), 0.275, 0.05)
    (1.0, 1.2)

    """
    v_, w_ = _vector((v, omega), 2, 'twist')
    c, half_b = params.wheel_radius, 0.5 * params.wheel_separation
    return float((v_ - half_b * w_) / c), float((v_ + half_b * w_) / c)


def differential_drive_deriv(
    t: float, state: ArrayLike, wheel_speeds: ArrayLike, params: DifferentialDriveParams
) -> Vector:
    """
    Return the time derivative of the differential-drive state.

    Book (4.113)-(4.114) in REP-103 form: x' = v cos θ, y' = v sin θ, θ' = ω with (v, ω) from
    (4.109)-(4.110), plus the wheel angle rates. Integrating it is the dead reckoning (4.131)
    of §4.7.5. The signature fits ``rk4_step(differential_drive_deriv, t, state, h,
    wheel_speeds, params)``.

    Parameters
    ----------
    t : float
        Time [s]; unused (the model is autonomous), present for the integrator.
    state : array_like, shape (5,)
        [x [m], y [m], θ [rad], left wheel angle [rad], right wheel angle [rad]]; pose of
        ``base_link`` in the world frame, θ from the x axis.
    wheel_speeds : array_like, shape (2,)
        [ω_left, ω_right] [rad/s], held constant over an integration step.
    params : DifferentialDriveParams
        Wheel radius c [m] and track b [m].

    Returns
    -------
    ndarray, shape (5,)
        d state / dt: [x' [m/s], y' [m/s], θ' [rad/s], ω_left, ω_right [rad/s]].

    Raises
    ------
    ValueError
        If ``state`` or ``wheel_speeds`` has the wrong shape or a non-finite value.

    Examples
    --------
    >>> params = DifferentialDriveParams(wheel_radius=0.25, wheel_separation=1.0)
    >>> differential_drive_deriv(0.0, [0.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.2], params)
    array([0.275, 0.   , 0.05 , 1.   , 1.2  ])

    """
    x = _vector(state, 5, 'state')
    w_left, w_right = _vector(wheel_speeds, 2, 'wheel_speeds')
    v, omega = wheel_speeds_to_twist(params, w_left, w_right)
    theta = x[2]
    return np.array([v * np.cos(theta), v * np.sin(theta), omega, w_left, w_right])
