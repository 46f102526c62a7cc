"""
Unicycle and synchronous-drive kinematics, and the geometry every wheeled model shares.

Book §4.7.2-§4.7.4 (Ollero 2001): the arc motion model (4.87)-(4.99), the exact arc update
(4.93), the Jacobian model (4.102)-(4.103) with its non-holonomic constraint (4.104), and the
synchronous drive of fig. 4.17a, whose wheels are all driven and steered together; HEMERO's
"config. síncrona" blocks ([H] (3.31), (3.35)). Seed catalog sections 2.7, 2.8 and 12.3.

Heading conventions (``convention=``): ``'rep103'`` (default) measures θ from the world x axis,
x' = v cos θ, y' = v sin θ; ``'book'`` measures the book's φ from the world y axis,
x' = -v sin φ, y' = v cos φ (4.97)-(4.98); θ = φ + π/2 (:mod:`robotica_kin.angles`). The world
x, y axes are the same in both; only the heading's zero differs.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import all_finite, finite_real
from robotica_kin.types import Pose2D, Vector

__all__ = [
    'HEADING_CONVENTIONS',
    'arc_update',
    'forward_direction',
    'instantaneous_centre_of_rotation',
    'nonholonomic_residual',
    'path_heading',
    'path_twist',
    'synchronous_drive_direct',
    'synchronous_drive_inverse',
    'unicycle_deriv',
]

HEADING_CONVENTIONS = ('rep103', 'book')
"""Heading conventions: θ from the world x axis (REP-103) or the book's φ from the y axis."""


def _vector(value: ArrayLike, size: int, name: str) -> Vector:
    array = np.asarray(value, dtype=np.float64)
    if array.shape != (size,):
        raise ValueError(f'{name} must have shape ({size},), got {array.shape}')
    if not all_finite(array):
        raise ValueError(f'{name} must be finite, got {array!r}')
    return array


def _positive(value: float, name: str) -> float:
    number = float(value)
    if not (math.isfinite(number) and number > 0.0):
        raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')
    return number


def forward_direction(heading: float, convention: str = 'rep103') -> tuple[float, float]:
    """
    Return the unit vector of the robot's forward axis in the world frame.

    REP-103: (cos θ, sin θ); book: (-sin φ, cos φ), the first column of (4.102). Every model of
    :mod:`robotica_kin.mobile` moves its guide point along it: (x', y') = v · forward.

    Parameters
    ----------
    heading : float
        θ [rad] from the world x axis (``'rep103'``) or φ [rad] from the y axis (``'book'``).
    convention : str
        One of :data:`HEADING_CONVENTIONS`.

    Returns
    -------
    tuple of float
        (x, y) components [-] in the world frame.

    Raises
    ------
    ValueError
        If ``heading`` is not finite or ``convention`` is unknown.

    Examples
    --------
    >>> forward_direction(0.0)
    (1.0, 0.0)
    >>> forward_direction(0.0, convention='book')  # φ = 0 faces the world y axis
    (-0.0, 1.0)

    """
    angle = finite_real('heading', heading)
    if convention == 'rep103':
        return math.cos(angle), math.sin(angle)
    if convention == 'book':
        return -math.sin(angle), math.cos(angle)
    raise ValueError(f'convention must be one of {HEADING_CONVENTIONS}, got {convention!r}')


def unicycle_deriv(
    t: float, state: ArrayLike, command: ArrayLike, convention: str = 'rep103'
) -> Vector:
    """
    Return the time derivative of the unicycle (synchronous-drive) pose.

    Book (4.97)-(4.99) and (4.102)-(4.103): x' = -v sin φ, y' = v cos φ, φ' = ω; in REP-103
    x' = v cos θ, y' = v sin θ, θ' = ω. The signature fits
    ``rk4_step(unicycle_deriv, t, state, h, command, convention)``.

    Parameters
    ----------
    t : float
        Time [s]; unused (the model is autonomous), present for the integrator.
    state : array_like, shape (3,)
        Pose (x [m], y [m], heading [rad]) of the guide point in the world frame.
    command : array_like, shape (2,)
        (v [m/s] forward speed along the robot's forward axis, ω [rad/s] yaw rate, positive
        counter-clockwise), held constant over a step.
    convention : str
        Heading convention of ``state``, one of :data:`HEADING_CONVENTIONS`.

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
    >>> unicycle_deriv(0.0, [0.0, 0.0, 0.0], [2.0, 0.5])
    array([2. , 0. , 0.5])
    >>> unicycle_deriv(0.0, [0.0, 0.0, 0.0], [2.0, 0.5], convention='book')
    array([-0. ,  2. ,  0.5])

    """
    pose = _vector(state, 3, 'state')
    v, omega = _vector(command, 2, 'command')
    cx, cy = forward_direction(pose[2], convention)
    return np.array([v * cx, v * cy, omega])


def arc_update(
    pose: ArrayLike, v: float, omega: float, dt: float, convention: str = 'rep103'
) -> Pose2D:
    """
    Return the pose after moving with constant (v, ω) for ``dt`` seconds: the exact arc.

    Book (4.93) (§4.7.2): with Δs = v dt, Δφ = ω dt and R = Δs/Δφ, the guide point moves by
    Δx = R (cos Δφ - 1) cos φ - R sin Δφ sin φ, Δy = R (cos Δφ - 1) sin φ + R sin Δφ cos φ;
    in REP-103 Δx = R (sin(θ + Δθ) - sin θ), Δy = -R (cos(θ + Δθ) - cos θ). It is computed
    as the chord Δs · sin(Δθ/2)/(Δθ/2) along the mid heading θ + Δθ/2, the same vector,
    which tends continuously to the straight line Δs along θ (4.95)-(4.96) as |ω dt| → 0
    (no division by Δθ, no threshold).

    Parameters
    ----------
    pose : array_like, shape (3,)
        Start pose (x [m], y [m], heading [rad]) in the world frame.
    v : float
        Forward speed [m/s].
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.
    dt : float
        Duration [s], finite and >= 0.
    convention : str
        Heading convention of ``pose`` and of the result, one of :data:`HEADING_CONVENTIONS`.

    Returns
    -------
    ndarray, shape (3,)
        Pose after ``dt``, heading wrapped to (-π, π].

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, ``dt < 0`` or an unknown convention.

    Examples
    --------
    >>> arc_update([0.0, 0.0, 0.0], 1.0, 0.5 * math.pi, 1.0)  # quarter circle, R = 2/π m
    array([0.63661977, 0.63661977, 1.57079633])

    """
    x, y, heading = _vector(pose, 3, 'pose')
    v_, omega_, dt_ = (finite_real('v', v), finite_real('omega', omega), finite_real('dt', dt))
    if dt_ < 0.0:
        raise ValueError(f'dt must be >= 0 s, got {dt!r}')
    distance, turn = v_ * dt_, omega_ * dt_
    chord = distance * float(np.sinc(turn / (2.0 * math.pi)))  # sinc(x) = sin(πx)/(πx)
    cx, cy = forward_direction(heading + 0.5 * turn, convention)
    return np.array([x + chord * cx, y + chord * cy, wrap_to_pi(heading + turn)])


def instantaneous_centre_of_rotation(v: float, omega: float) -> tuple[float, float] | None:
    """
    Return the instantaneous centre of rotation (ICR) of a unicycle in ``base_link``.

    The guide point moves on a circle of radius R = v/ω = 1/γ (4.89)-(4.90) about a point on
    its lateral axis: (0, v/ω) in ``base_link`` (x forward, y left), left of the robot when
    v/ω > 0. A straight motion (ω = 0) has no ICR (it is at infinity).

    Parameters
    ----------
    v : float
        Forward speed [m/s] of the guide point.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float or None
        (x [m], y [m]) of the ICR in ``base_link``, or None for ω = 0.

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> instantaneous_centre_of_rotation(1.0, 0.5)
    (0.0, 2.0)
    >>> instantaneous_centre_of_rotation(1.0, 0.0) is None
    True

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    if omega_ == 0.0:
        return None
    return 0.0, v_ / omega_


def nonholonomic_residual(
    pose: ArrayLike, pose_dot: ArrayLike, convention: str = 'rep103'
) -> float:
    """
    Return the lateral velocity of the guide point, zero when it does not slip sideways.

    Book (4.104): x' cos φ + y' sin φ = 0, the velocity along the book's local x axis (the
    robot's right). In REP-103 the residual is the velocity along ``base_link``'s y axis (the
    robot's left), -x' sin θ + y' cos θ; the two forms differ in sign only (θ = φ + π/2), and
    each convention returns its own.

    Parameters
    ----------
    pose : array_like, shape (3,)
        Pose (x [m], y [m], heading [rad]) in the world frame.
    pose_dot : array_like, shape (3,)
        Its time derivative (x' [m/s], y' [m/s], heading' [rad/s]); heading' is not used.
    convention : str
        Heading convention of ``pose``, one of :data:`HEADING_CONVENTIONS`.

    Returns
    -------
    float
        Lateral velocity [m/s]: to the left (``'rep103'``) or to the right (``'book'``).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value or an unknown convention.

    Examples
    --------
    >>> nonholonomic_residual([0.0, 0.0, 0.0], [2.0, 0.0, 1.0])  # moving forwards
    0.0
    >>> nonholonomic_residual([0.0, 0.0, 0.0], [0.0, 0.5, 0.0])  # sliding to the left
    0.5

    """
    position = _vector(pose, 3, 'pose')
    rates = _vector(pose_dot, 3, 'pose_dot')
    cx, cy = forward_direction(position[2], convention)
    lateral = float(-cy * rates[0] + cx * rates[1])  # velocity along the left axis
    return lateral if convention == 'rep103' else -lateral


def synchronous_drive_direct(
    wheel_speed: float, steering_rate: float, wheel_radius: float
) -> tuple[float, float]:
    """
    Return the body twist of a synchronous drive from its wheel and steering speeds.

    Fig. 4.17a, model (4.102)-(4.103): all wheels roll at the same speed and are steered
    together, so the heading is the wheels' steering direction: v = c ω_wheel, ω = ω_steer.

    Parameters
    ----------
    wheel_speed : float
        Common wheel angular speed ω_wheel [rad/s], positive forwards.
    steering_rate : float
        Common steering rate [rad/s], positive counter-clockwise.
    wheel_radius : float
        Wheel radius c [m], > 0.

    Returns
    -------
    tuple of float
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If an input is not finite or ``wheel_radius`` <= 0.

    Examples
    --------
    >>> synchronous_drive_direct(4.0, 0.5, 0.25)
    (1.0, 0.5)

    """
    c = _positive(wheel_radius, 'wheel_radius')
    return c * finite_real('wheel_speed', wheel_speed), finite_real('steering_rate', steering_rate)


def synchronous_drive_inverse(
    v: float, omega: float, wheel_radius: float
) -> tuple[float, float]:
    """
    Return the wheel and steering speeds of a synchronous drive for a body twist.

    The inverse of :func:`synchronous_drive_direct`: ω_wheel = v / c, ω_steer = ω; [H] (3.35)
    gives (v, ω) from the path.

    Parameters
    ----------
    v : float
        Forward speed [m/s].
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.
    wheel_radius : float
        Wheel radius c [m], > 0.

    Returns
    -------
    tuple of float
        (wheel_speed [rad/s], steering_rate [rad/s]).

    Raises
    ------
    ValueError
        If an input is not finite or ``wheel_radius`` <= 0.

    Examples
    --------
    >>> synchronous_drive_inverse(1.0, 0.5, 0.25)
    (4.0, 0.5)

    """
    c = _positive(wheel_radius, 'wheel_radius')
    return finite_real('v', v) / c, finite_real('omega', omega)


def _path_derivative(value: ArrayLike, name: str) -> tuple[float, float]:
    dx, dy = _vector(value, 2, name)
    return float(dx), float(dy)


def path_heading(velocity: ArrayLike, convention: str = 'rep103') -> float:
    """
    Return the heading of a vehicle that drives forwards along a path with this velocity.

    Book (4.105) tan φ = -x'/y', taken as φ = atan2(-x', y') (θ = atan2(y', x') in REP-103)
    so that the vehicle always drives forwards; HEMERO's inverse blocks print atan(-x'/y')
    ([H] (3.32)-(3.35)), which reverses the vehicle wherever y' < 0.

    Parameters
    ----------
    velocity : array_like, shape (2,)
        (x' [m/s], y' [m/s]) of the guide point in the world frame, not zero.
    convention : str
        Heading convention of the result, one of :data:`HEADING_CONVENTIONS`.

    Returns
    -------
    float
        Heading [rad] in (-π, π].

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, a zero velocity or an unknown convention.

    Examples
    --------
    >>> path_heading([0.0, 1.0]), path_heading([0.0, 1.0], convention='book')
    (1.5707963267948966, 0.0)

    """
    dx, dy = _path_derivative(velocity, 'velocity')
    if dx == 0.0 and dy == 0.0:
        raise ValueError('velocity must not be zero: the path does not define the heading of '
                         'a standing vehicle')
    if convention == 'rep103':
        return wrap_to_pi(math.atan2(dy, dx))
    if convention == 'book':
        return wrap_to_pi(math.atan2(-dx, dy))
    raise ValueError(f'convention must be one of {HEADING_CONVENTIONS}, got {convention!r}')


def path_twist(
    velocity: ArrayLike, acceleration: ArrayLike, convention: str = 'rep103'
) -> tuple[float, float, float]:
    """
    Return the body twist and heading of a unicycle that follows a path (inverse model).

    HEMERO's inverse synchronous block [H] (3.35), book (4.107)-(4.108): v = -sin φ x' +
    cos φ y', ω = φ', with φ from :func:`path_heading` (so v = sqrt(x'² + y'²) > 0) and
    φ' = (x' y'' - x'' y')/(x'² + y'²), the derivative of (4.105) (catalog §2.11).

    Parameters
    ----------
    velocity : array_like, shape (2,)
        (x' [m/s], y' [m/s]) of the guide point in the world frame, not zero.
    acceleration : array_like, shape (2,)
        (x'' [m/s²], y'' [m/s²]).
    convention : str
        Heading convention of the returned heading, one of :data:`HEADING_CONVENTIONS`.

    Returns
    -------
    tuple of float
        (v [m/s], ω [rad/s], heading [rad]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, a zero velocity or an unknown convention.

    Examples
    --------
    >>> path_twist([0.0, 2.0], [-4.0, 0.0])  # circle of radius 1 m at 2 m/s
    (2.0, 2.0, 1.5707963267948966)

    """
    heading = path_heading(velocity, convention)
    dx, dy = _path_derivative(velocity, 'velocity')
    ddx, ddy = _path_derivative(acceleration, 'acceleration')
    speed_squared = dx * dx + dy * dy
    return math.sqrt(speed_squared), (dx * ddy - ddx * dy) / speed_squared, heading
