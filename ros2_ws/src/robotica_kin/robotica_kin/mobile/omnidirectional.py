"""
Omnidirectional bases: three omni wheels at 120° and four mecanum wheels.

Book §2.3.1.7 (Uranus) and §9.4.1 (type (3, 0), z' = B(z) u), slides [S] (catalog §13.1):
Swedish wheels let the contact point slide freely along their rollers, so the base moves in any
direction and the body twist (v_x, v_y, ω) in ``base_link`` (x forward, y left) is a linear
function of the wheel speeds. Each wheel i at (x_i, y_i) drives its contact point along a unit
direction d_i and lets it slide along the rollers' free direction; the rim speed r ω_i is the
component of the contact point's velocity (v_x - ω y_i, v_y + ω x_i) along d_i corrected for
the rollers (Lynch & Park, *Modern Robotics*, 2017, §13.2.1, whose general wheel model gives
both matrices below). Seed catalog sections 0.2, 7.4 and 13.1.

* Three omni wheels (rollers perpendicular to the wheel, free direction = the wheel's axle) at
  angles β_i around a circle of radius L, each driving tangentially, d_i = (-sin β_i, cos β_i):
  r ω_i = -sin β_i v_x + cos β_i v_y + L ω. A positive wheel speed turns the base
  counter-clockwise.
* Four mecanum wheels (rollers at 45°) at (±a, ±b) in the order FL, FR, RL, RR, all driving
  along x, in the usual layout that strafes left (v_y > 0) with FL and RR turning backwards:
  r ω = [v_x - v_y - (a + b) ω, v_x + v_y + (a + b) ω, v_x + v_y - (a + b) ω,
  v_x - v_y + (a + b) ω].

The direct models are the exact (Moore-Penrose) pseudo-inverses of these wheel Jacobians, so
wheel speeds that no rigid motion produces (a slipping wheel) give the least-squares twist.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.finite import finite_real
from robotica_kin.mobile.unicycle import _vector, forward_direction
from robotica_kin.types import Vector

__all__ = [
    'MecanumParams',
    'OmniThreeParams',
    'mecanum_direct',
    'mecanum_inverse',
    'omni_deriv',
    'omni_three_direct',
    'omni_three_inverse',
]

_MIN_SINGULAR_VALUE = 1e-9  # relative; below it three omni wheels cannot control 3 DOF


@dataclass(frozen=True)
class OmniThreeParams:
    """
    Geometry of a base with three omni wheels (rollers perpendicular to the wheel).

    ``__post_init__`` raises ValueError unless r and L are finite and > 0 and the three
    ``wheel_angles`` are finite and place the wheels so that the base has three degrees of
    freedom (e.g. not all three on one diameter).

    >>> OmniThreeParams(wheel_radius=0.05, base_radius=0.2).wheel_angles
    (0.0, 2.0943951023931953, 4.1887902047863905)
    """

    wheel_radius: float  # r [m]
    base_radius: float  # L [m], from the base centre to each wheel's contact point
    wheel_angles: tuple[float, float, float] = (0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)
    # β_i [rad]: angle of each wheel's position from the x axis, counter-clockwise

    def __post_init__(self) -> None:
        """Reject bad dimensions and wheel placements without three degrees of freedom."""
        for name in ('wheel_radius', 'base_radius'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')
        angles = np.asarray(self.wheel_angles, dtype=np.float64)
        if angles.shape != (3,) or not np.all(np.isfinite(angles)):
            raise ValueError(
                f'wheel_angles must be three finite angles, got {self.wheel_angles!r}')
        object.__setattr__(self, 'wheel_angles', tuple(float(a) for a in angles))
        singular = np.linalg.svd(_omni_matrix(self), compute_uv=False)
        if singular[-1] < _MIN_SINGULAR_VALUE * singular[0]:
            raise ValueError(f'wheel_angles {self.wheel_angles!r} do not give the base three '
                             'degrees of freedom')


@dataclass(frozen=True)
class MecanumParams:
    """
    Geometry of a base with four mecanum wheels (rollers at 45°), order FL, FR, RL, RR.

    All dimensions must be finite and > 0; ``__post_init__`` raises ValueError otherwise.

    >>> MecanumParams(wheel_radius=0.05, half_length=0.2, half_width=0.15)
    MecanumParams(wheel_radius=0.05, half_length=0.2, half_width=0.15)
    """

    wheel_radius: float  # r [m]
    half_length: float  # a [m], from the centre to each axle along x
    half_width: float  # b [m], from the centre to each wheel's contact point along y

    def __post_init__(self) -> None:
        """Reject non-finite or non-positive dimensions."""
        for name in ('wheel_radius', 'half_length', 'half_width'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')


def _omni_matrix(params: OmniThreeParams) -> Vector:
    """Return the (3, 3) matrix H with ω_wheels = H (v_x, v_y, ω)."""
    beta = np.asarray(params.wheel_angles, dtype=np.float64)
    rows = np.column_stack([-np.sin(beta), np.cos(beta), np.full(3, params.base_radius)])
    return rows / params.wheel_radius


def _twist(vx: float, vy: float, omega: float) -> Vector:
    return np.array([finite_real('vx', vx), finite_real('vy', vy), finite_real('omega', omega)])


def omni_three_inverse(params: OmniThreeParams, vx: float, vy: float, omega: float) -> Vector:
    """
    Return the three omni wheels' speeds for a body twist (inverse kinematics).

    ω_i = (-sin β_i v_x + cos β_i v_y + L ω) / r: each wheel drives tangentially; its
    rollers let the contact point slide freely along the wheel's axle (radially).

    Parameters
    ----------
    params : OmniThreeParams
        Wheel radius r [m], base radius L [m], wheel angles β_i [rad].
    vx, vy : float
        Velocity [m/s] of the base centre along ``base_link`` x (forward) and y (left).
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    ndarray, shape (3,)
        Wheel angular speeds [rad/s], positive turning the base counter-clockwise.

    Raises
    ------
    ValueError
        If an input is not finite.

    Examples
    --------
    >>> omni_three_inverse(OmniThreeParams(0.05, 0.2), 0.0, 0.0, 1.0)  # spin: L ω / r
    array([4., 4., 4.])

    """
    return _omni_matrix(params) @ _twist(vx, vy, omega)


def omni_three_direct(
    params: OmniThreeParams, wheel_speeds: ArrayLike
) -> tuple[float, float, float]:
    """
    Return the body twist of a three-omni-wheel base from its wheel speeds.

    Solves the (invertible) system of :func:`omni_three_inverse`; with three wheels every
    triple of wheel speeds is a rigid motion.

    Parameters
    ----------
    params : OmniThreeParams
        Wheel radius r [m], base radius L [m], wheel angles β_i [rad].
    wheel_speeds : array_like, shape (3,)
        Wheel angular speeds [rad/s] in the order of ``wheel_angles``.

    Returns
    -------
    tuple of float
        (v_x [m/s], v_y [m/s], ω [rad/s]) in ``base_link``.

    Raises
    ------
    ValueError
        On a wrong shape or a non-finite value.

    Examples
    --------
    >>> vx, vy, omega = omni_three_direct(OmniThreeParams(0.05, 0.2), [4.0, 4.0, 4.0])
    >>> round(vx, 12), round(vy, 12), round(omega, 12)
    (0.0, 0.0, 1.0)

    """
    speeds = _vector(wheel_speeds, 3, 'wheel_speeds')
    vx, vy, omega = np.linalg.solve(_omni_matrix(params), speeds)
    return float(vx), float(vy), float(omega)


def mecanum_inverse(params: MecanumParams, vx: float, vy: float, omega: float) -> Vector:
    """
    Return the four mecanum wheels' speeds for a body twist (inverse kinematics).

    With k = a + b: ω_FL = (v_x - v_y - k ω)/r, ω_FR = (v_x + v_y + k ω)/r,
    ω_RL = (v_x + v_y - k ω)/r, ω_RR = (v_x - v_y + k ω)/r (Modern Robotics §13.2.1, whose
    wheel order is FL, FR, RR, RL).

    Parameters
    ----------
    params : MecanumParams
        Wheel radius r [m], half length a [m], half width b [m].
    vx, vy : float
        Velocity [m/s] of the base centre along ``base_link`` x (forward) and y (left).
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    ndarray, shape (4,)
        Wheel angular speeds [rad/s] (FL, FR, RL, RR), positive rolling forwards.

    Raises
    ------
    ValueError
        If an input is not finite.

    Examples
    --------
    >>> mecanum_inverse(MecanumParams(0.05, 0.2, 0.15), 0.0, 0.1, 0.0)  # strafe left
    array([-2.,  2.,  2., -2.])

    """
    twist = _twist(vx, vy, omega)
    return _mecanum_matrix(params) @ twist


def _mecanum_matrix(params: MecanumParams) -> Vector:
    k = params.half_length + params.half_width
    return np.array([
        [1.0, -1.0, -k],
        [1.0, 1.0, k],
        [1.0, 1.0, -k],
        [1.0, -1.0, k],
    ]) / params.wheel_radius


def mecanum_direct(
    params: MecanumParams, wheel_speeds: ArrayLike
) -> tuple[float, float, float]:
    """
    Return the body twist of a mecanum base from its four wheel speeds.

    The columns of the wheel Jacobian H of :func:`mecanum_inverse` are orthogonal
    (HᵀH = diag(4, 4, 4k²)/r²), so its pseudo-inverse is exact and closed-form:
    v_x = r (ω_FL + ω_FR + ω_RL + ω_RR)/4, v_y = r (-ω_FL + ω_FR + ω_RL - ω_RR)/4,
    ω = r (-ω_FL + ω_FR - ω_RL + ω_RR)/(4k). Four speeds that no rigid motion produces (one
    degree of redundancy) give the least-squares twist.

    Parameters
    ----------
    params : MecanumParams
        Wheel radius r [m], half length a [m], half width b [m].
    wheel_speeds : array_like, shape (4,)
        Wheel angular speeds [rad/s] (FL, FR, RL, RR).

    Returns
    -------
    tuple of float
        (v_x [m/s], v_y [m/s], ω [rad/s]) in ``base_link``.

    Raises
    ------
    ValueError
        On a wrong shape or a non-finite value.

    Examples
    --------
    >>> mecanum_direct(MecanumParams(0.05, 0.2, 0.15), [-2.0, 2.0, 2.0, -2.0])
    (0.0, 0.1, 0.0)

    """
    fl, fr, rl, rr = (float(speed) for speed in _vector(wheel_speeds, 4, 'wheel_speeds'))
    quarter_r = 0.25 * params.wheel_radius
    k = params.half_length + params.half_width
    return (quarter_r * (fl + fr + rl + rr), quarter_r * (-fl + fr + rl - rr),
            quarter_r * (-fl + fr - rl + rr) / k)


def omni_deriv(
    t: float, state: ArrayLike, twist: ArrayLike, convention: str = 'rep103'
) -> Vector:
    """
    Return the time derivative of a holonomic base's pose for a body twist.

    The twist (v_x, v_y, ω) in ``base_link`` rotated into the world frame:
    x' = v_x cos θ - v_y sin θ, y' = v_x sin θ + v_y cos θ, θ' = ω (book (9.43) with B(z) of
    full rank). With ``convention='book'`` the state's heading is the book's φ; the twist
    stays in ``base_link`` (x forward, y left). Fits ``rk4_step(omni_deriv, t, state, h,
    twist, convention)``.

    Parameters
    ----------
    t : float
        Time [s]; unused (the model is autonomous), present for the integrator.
    state : array_like, shape (3,)
        Pose (x [m], y [m], heading [rad]) of the base centre in the world frame.
    twist : array_like, shape (3,)
        (v_x [m/s], v_y [m/s], ω [rad/s]) in ``base_link``.
    convention : str
        Heading convention of ``state``, ``'rep103'`` or ``'book'``.

    Returns
    -------
    ndarray, shape (3,)
        (x' [m/s], y' [m/s], heading' [rad/s]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value or an unknown convention.

    Examples
    --------
    >>> omni_deriv(0.0, [0.0, 0.0, 0.5 * math.pi], [0.0, 1.0, 0.0]).round(12)  # left = -x
    array([-1.,  0.,  0.])

    """
    pose = _vector(state, 3, 'state')
    vx, vy, omega = _vector(twist, 3, 'twist')
    cx, cy = forward_direction(pose[2], convention)
    return np.array([vx * cx - vy * cy, vx * cy + vy * cx, omega])
