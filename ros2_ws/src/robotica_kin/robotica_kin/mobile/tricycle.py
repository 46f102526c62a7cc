"""
Classic tricycle kinematics: one front wheel drives and steers (Romeo 3R, fig. 4.17c).

Book §4.7.4 (Ollero 2001): the front wheel of radius c turns at ω_t (rim speed v_t = c ω_t)
and is steered by α from the vehicle's axis at rate ω_α; the guide point is the midpoint of
the passive rear axle, a wheelbase l behind it. Direct model (4.115)-(4.117), state model
(4.118), inverse (4.119)-(4.120) and the pseudo-inverse of Ejemplo 4.8 (4.122)-(4.123) in the
corrected form of HEMERO's inverse blocks [H] (3.32)-(3.33); HEMERO's "triciclo clásico" and
"bicicleta" blocks share these equations. Slides [S] (catalog §13.3) write the same model with
d for l. Seed catalog sections 2.8, 2.11, 12.3, 13.3 and Part 17.

Headings follow :data:`~robotica_kin.mobile.unicycle.HEADING_CONVENTIONS`.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.finite import finite_real
from robotica_kin.mobile.unicycle import _vector, forward_direction, path_heading
from robotica_kin.types import Vector

__all__ = [
    'TricycleParams',
    'tricycle_deriv',
    'tricycle_direct',
    'tricycle_inverse',
    'tricycle_inverse_velocity',
    'tricycle_path_inverse',
]


@dataclass(frozen=True)
class TricycleParams:
    """
    Geometry of a classic tricycle (book fig. 4.17c).

    Both dimensions must be finite and > 0; ``__post_init__`` raises ValueError otherwise.

    >>> TricycleParams(wheelbase=1.5, wheel_radius=0.3)  # Ejemplo 4.8's l
    TricycleParams(wheelbase=1.5, wheel_radius=0.3)
    """

    wheelbase: float  # l [m], rear-axle midpoint to the front wheel's contact point
    wheel_radius: float  # c [m], of the driven front wheel

    def __post_init__(self) -> None:
        """Reject non-finite or non-positive dimensions."""
        for name in ('wheelbase', 'wheel_radius'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')


def tricycle_direct(
    params: TricycleParams, wheel_speed: float, steering_angle: float
) -> tuple[float, float]:
    """
    Return the body twist of the rear-axle midpoint from the front wheel's speed and angle.

    Book (4.115), (4.117): v = c ω_t cos α, ω = φ' = (c ω_t / l) sin α.

    Parameters
    ----------
    params : TricycleParams
        Wheelbase l [m] and front wheel radius c [m].
    wheel_speed : float
        Front wheel angular speed ω_t [rad/s], positive rolling forwards.
    steering_angle : float
        Steering angle α [rad] of the front wheel from the vehicle's axis, positive to the
        left; any angle (at ±π/2 the vehicle turns on the spot about the rear-axle midpoint).

    Returns
    -------
    tuple of float
        (v [m/s] along ``base_link`` x, ω [rad/s] counter-clockwise).

    Raises
    ------
    ValueError
        If an input is not finite.

    Examples
    --------
    >>> tricycle_direct(TricycleParams(1.0, 0.5), 4.0, 0.0)
    (2.0, 0.0)
    >>> v, omega = tricycle_direct(TricycleParams(1.0, 0.5), 4.0, 0.5 * math.pi)
    >>> round(v, 12), omega  # α = π/2: spin about the rear-axle midpoint
    (0.0, 2.0)

    """
    v_t = params.wheel_radius * finite_real('wheel_speed', wheel_speed)
    alpha = finite_real('steering_angle', steering_angle)
    return v_t * math.cos(alpha), v_t * math.sin(alpha) / params.wheelbase


def tricycle_inverse(
    params: TricycleParams, v: float, omega: float
) -> tuple[float, float]:
    """
    Return the front wheel's speed and steering angle that produce a body twist (v, ω).

    Book (4.119)-(4.120): α = atan(l ω / v), ω_t = sqrt(v² + l² ω²) / c; with the signs
    resolved so that every (v, ω) is reachable with α in [-π/2, π/2]: forwards (v > 0) the
    wheel rolls forwards, in reverse (v < 0) it rolls backwards (ω_t < 0) with the same
    formula for α, and turning on the spot (v = 0, ω ≠ 0) takes α = ±π/2 (sign of ω) with
    the wheel rolling forwards. At rest (v = ω = 0) α = 0. No command is impossible.

    Parameters
    ----------
    params : TricycleParams
        Wheelbase l [m] and front wheel radius c [m].
    v : float
        Forward speed [m/s] of the rear-axle midpoint.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float
        (ω_t [rad/s] front wheel speed, α [rad] steering angle in [-π/2, π/2]).

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> wheel_speed, alpha = tricycle_inverse(TricycleParams(1.5, 0.5), 1.0, 1.0)  # Ej. 4.8
    >>> round(wheel_speed * 0.5, 4), round(math.degrees(alpha), 2)  # v_t [m/s], α [deg]
    (1.8028, 56.31)

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    sign = -1.0 if v_ < 0.0 else 1.0
    lateral = params.wheelbase * omega_  # v_t sin α
    alpha = math.atan2(sign * lateral, abs(v_))
    v_t = sign * math.hypot(v_, lateral)
    return v_t / params.wheel_radius, alpha


def tricycle_deriv(
    t: float,
    state: ArrayLike,
    command: ArrayLike,
    params: TricycleParams,
    convention: str = 'rep103',
) -> Vector:
    """
    Return the time derivative of the tricycle's state.

    Book (4.118) (printed garbled; intended form, catalog Part 17) and [H] (3.29):
    x' = -c ω_t cos α sin φ, y' = c ω_t cos α cos φ, φ' = (c ω_t / l) sin α, α' = ω_α;
    in REP-103 x' = c ω_t cos α cos θ, y' = c ω_t cos α sin θ. The signature fits
    ``rk4_step(tricycle_deriv, t, state, h, command, params, convention)``.

    Parameters
    ----------
    t : float
        Time [s]; unused (the model is autonomous), present for the integrator.
    state : array_like, shape (4,)
        (x [m], y [m], heading [rad], α [rad]): pose of the rear-axle midpoint in the world
        frame and the front wheel's steering angle.
    command : array_like, shape (2,)
        (ω_t [rad/s] front wheel speed, ω_α [rad/s] steering rate).
    params : TricycleParams
        Wheelbase l [m] and front wheel radius c [m].
    convention : str
        Heading convention of ``state``, ``'rep103'`` or ``'book'``.

    Returns
    -------
    ndarray, shape (4,)
        (x' [m/s], y' [m/s], heading' [rad/s], α' [rad/s]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value or an unknown convention.

    Examples
    --------
    >>> tricycle_deriv(0.0, [0.0, 0.0, 0.0, 0.0], [2.0, 0.1], TricycleParams(1.0, 0.5))
    array([1. , 0. , 0. , 0.1])

    """
    x = _vector(state, 4, 'state')
    wheel_speed, steering_rate = _vector(command, 2, 'command')
    v, omega = tricycle_direct(params, wheel_speed, x[3])
    cx, cy = forward_direction(x[2], convention)
    return np.array([v * cx, v * cy, omega, steering_rate])


def tricycle_inverse_velocity(
    params: TricycleParams,
    heading: float,
    steering_angle: float,
    pose_dot: ArrayLike,
    convention: str = 'rep103',
) -> tuple[float, float]:
    """
    Return (v_t, ω_α) from the state's rate by the pseudo-inverse of the tricycle Jacobian.

    Ejemplo 4.8, (4.122)-(4.123): with J = [[-sin φ cos α, 0], [cos φ cos α, 0],
    [sin α / l, 0], [0, 1]] on (v_t, ω_α), (JᵀJ)⁻¹Jᵀ gives

        v_t = l (-l cos α sin φ x' + l cos α cos φ y' + sin α φ') / ((l cos α)² + sin² α),
        ω_α = α',

    as HEMERO's inverse blocks print it ([H] (3.32)-(3.33)); the book's (4.123) lost the
    factor cos α of the x', y' terms (catalog §2.11, Part 17). In REP-103 the bracket reads
    l cos α (cos θ x' + sin θ y') + sin α θ'. For a rate the tricycle can follow, v_t is exact
    (v_t = sqrt(v² + (l φ')²) on a consistent path); otherwise it is the least-squares value
    of that unweighted Jacobian, which mixes m/s and rad/s.

    Parameters
    ----------
    params : TricycleParams
        Wheelbase l [m]; the wheel radius is not used (ω_t = v_t / c).
    heading : float
        Heading [rad] of the vehicle (θ or φ per ``convention``).
    steering_angle : float
        Current steering angle α [rad].
    pose_dot : array_like, shape (3,) or (4,)
        (x' [m/s], y' [m/s], heading' [rad/s]) of the rear-axle midpoint, optionally
        followed by α' [rad/s]. Without α' the steering is taken as held (α' = 0, ω_α = 0),
        as in Ejemplo 4.8.
    convention : str
        Heading convention, ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (v_t [m/s] front wheel rim speed, ω_α [rad/s] steering rate).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value or an unknown convention.

    Examples
    --------
    Ejemplo 4.8: unit circle at t = 0, x' = 0, y' = 1, φ' = 1 (book φ = 0), l = 1.5 m:

    >>> params = TricycleParams(wheelbase=1.5, wheel_radius=0.3)
    >>> v_t, omega_alpha = tricycle_inverse_velocity(
    ...     params, 0.0, math.atan(1.5), [0.0, 1.0, 1.0], convention='book')
    >>> round(v_t, 4), omega_alpha
    (1.8028, 0.0)

    """
    rates = np.asarray(pose_dot, dtype=np.float64)
    if rates.shape not in ((3,), (4,)):
        raise ValueError(f'pose_dot must have shape (3,) or (4,), got {rates.shape}')
    rates = _vector(rates, rates.shape[0], 'pose_dot')
    alpha = finite_real('steering_angle', steering_angle)
    cx, cy = forward_direction(heading, convention)
    length, cos_a, sin_a = params.wheelbase, math.cos(alpha), math.sin(alpha)
    along = cx * rates[0] + cy * rates[1]  # velocity along the vehicle's axis
    v_t = length * (length * cos_a * along + sin_a * rates[2]) / (
        (length * cos_a) ** 2 + sin_a**2)
    omega_alpha = float(rates[3]) if rates.shape == (4,) else 0.0
    return float(v_t), omega_alpha


def tricycle_path_inverse(
    params: TricycleParams,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    jerk: ArrayLike,
    convention: str = 'rep103',
) -> tuple[float, float, float, float]:
    """
    Return the controls, steering angle and heading that make a tricycle follow a path.

    HEMERO's inverse tricycle and bicycle blocks ([H] (3.32)-(3.33)) from the path
    (x(t), y(t)) of the rear-axle midpoint: the heading (driving forwards, see
    :func:`~robotica_kin.mobile.unicycle.path_heading`), its rate φ' = (x' y'' - x'' y')/s²
    with s = sqrt(x'² + y'²), the curvature γ = φ'/s, the steering angle α = atan(l γ)
    (4.119) and its rate α' = l γ'/(1 + (l γ)²), where
    γ' = (x' y''' - x''' y')/s³ - 3 (x' y'' - x'' y')(x' x'' + y' y'')/s⁵;
    then (v_t, ω_α) by :func:`tricycle_inverse_velocity`.

    Parameters
    ----------
    params : TricycleParams
        Wheelbase l [m]; the wheel radius c is not used (ω_t = v_t / c).
    velocity, acceleration, jerk : array_like, shape (2,)
        First, second and third time derivatives of (x, y) [m/s, m/s², m/s³] in the world
        frame; the velocity must not be zero.
    convention : str
        Heading convention of the returned heading, ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (v_t [m/s] front wheel rim speed, ω_α [rad/s] steering rate, α [rad] steering angle
        in (-π/2, π/2), heading [rad]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, a zero velocity or an unknown convention.

    Examples
    --------
    Ejemplo 4.8 at t = 0 on the unit circle x = cos t, y = sin t (l = 1.5 m):

    >>> v_t, omega_alpha, alpha, phi = tricycle_path_inverse(
    ...     TricycleParams(1.5, 0.3), [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], convention='book')
    >>> round(v_t, 4), omega_alpha, round(math.degrees(alpha), 2), phi
    (1.8028, 0.0, 56.31, 0.0)

    """
    heading = path_heading(velocity, convention)
    dx, dy = (float(d) for d in _vector(velocity, 2, 'velocity'))
    ddx, ddy = (float(d) for d in _vector(acceleration, 2, 'acceleration'))
    dddx, dddy = (float(d) for d in _vector(jerk, 2, 'jerk'))
    speed_squared = dx * dx + dy * dy
    speed = math.sqrt(speed_squared)
    cross = dx * ddy - ddx * dy
    heading_rate = cross / speed_squared
    curvature = heading_rate / speed
    curvature_rate = ((dx * dddy - dddx * dy) / (speed_squared * speed)
                      - 3.0 * cross * (dx * ddx + dy * ddy) / (speed_squared**2 * speed))
    length = params.wheelbase
    alpha = math.atan(length * curvature)
    alpha_rate = length * curvature_rate / (1.0 + (length * curvature) ** 2)
    v_t, omega_alpha = tricycle_inverse_velocity(
        params, heading, alpha, [dx, dy, heading_rate, alpha_rate], convention)
    return v_t, omega_alpha, alpha, heading
