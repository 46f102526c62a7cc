"""
Ackermann (car-like) steering geometry: two steered front wheels, a driven rear axle.

Book §2.3.1.1 and §4.7.4 (the bicycle model (4.121) stands for the whole vehicle) and slides
[S] (catalog §13.4): both front wheels' axles meet on the prolonged rear axle at the ICR, so
the inner wheel steers more than the outer one and

    cot θ_o - cot θ_i = track / wheelbase        (Ackermann condition)

The slides write it ``cot θ_o - cot θ_i = L/d`` with L the *lateral* separation of the front
wheels (our ``track``) and d the *longitudinal* one (our ``wheelbase``); the car literature's
``d/L`` names them the other way round. The equivalent ("imaginary") central wheel of the
bicycle model steers by θ_s with cot θ_s = R/wheelbase = (cot θ_i + cot θ_o)/2, R the turning
radius of the rear-axle midpoint (the guide point). Seed catalog sections 0.2, 2.8, 13.4.

``base_link`` has its origin at the rear-axle midpoint, x forward, y left; the steering pivots
sit at the front wheels' contact points (wheelbase, ±track/2), the rear wheels at
(0, ±track/2). Angles are positive to the left (counter-clockwise); a left turn has θ_s > 0
and its inner wheel on the left.
"""

from dataclasses import dataclass
import math

from robotica_kin.finite import finite_real

__all__ = [
    'AckermannParams',
    'ackermann_equivalent_angle',
    'ackermann_front_wheel_speeds',
    'ackermann_icr',
    'ackermann_left_right',
    'ackermann_rear_wheel_speeds',
    'ackermann_wheel_angles',
]

_HALF_PI = 0.5 * math.pi


@dataclass(frozen=True)
class AckermannParams:
    """
    Geometry of an Ackermann-steered vehicle (slides [S]: d = wheelbase, L = track).

    All dimensions must be finite and > 0; ``__post_init__`` raises ValueError otherwise.

    >>> AckermannParams(wheelbase=2.5, track=1.5, wheel_radius=0.3)
    AckermannParams(wheelbase=2.5, track=1.5, wheel_radius=0.3)
    """

    wheelbase: float  # d [m] in [S], l in the book: rear axle to front axle
    track: float  # L [m] in [S]: lateral distance between the wheels of an axle (both axles)
    wheel_radius: float  # [m], of every wheel

    def __post_init__(self) -> None:
        """Reject non-finite or non-positive dimensions."""
        for name in ('wheelbase', 'track', 'wheel_radius'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')


def _axle_angle(angle: float) -> float:
    """Return the wheel-axle orientation ``angle`` modulo π, in (-π/2, π/2]."""
    if angle > _HALF_PI:
        return angle - math.pi
    if angle <= -_HALF_PI:
        return angle + math.pi
    return angle


def _equivalent(steering_angle: float) -> float:
    angle = finite_real('steering_angle', steering_angle)
    if not abs(angle) <= _HALF_PI:
        raise ValueError(f'steering_angle must be in [-π/2, π/2] rad, got {steering_angle!r}')
    return angle


def ackermann_left_right(
    params: AckermannParams, steering_angle: float
) -> tuple[float, float]:
    """
    Return the left and right front wheels' steering angles for an equivalent angle θ_s.

    With R = wheelbase · cot θ_s ([S]), cot θ_left = (R - track/2)/wheelbase and
    cot θ_right = (R + track/2)/wheelbase: each wheel's axle points at the ICR (0, R), so
    cot θ_right - cot θ_left = track/wheelbase for every θ_s. Computed without dividing by
    θ_s (θ_s = 0 gives 0, 0). When the ICR lies between the front wheels (|R| < track/2) the
    inner wheel's axle angle passes ±π/2; angles are returned modulo π in (-π/2, π/2] (the
    wheel then rolls backwards), which keeps the cot relation.

    Parameters
    ----------
    params : AckermannParams
        Wheelbase and track [m].
    steering_angle : float
        Equivalent (bicycle) steering angle θ_s [rad] in [-π/2, π/2], positive to the left.

    Returns
    -------
    tuple of float
        (θ_left [rad], θ_right [rad]), positive to the left.

    Raises
    ------
    ValueError
        If ``steering_angle`` is not finite or |θ_s| > π/2.

    Examples
    --------
    >>> params = AckermannParams(wheelbase=2.0, track=1.0, wheel_radius=0.3)
    >>> left, right = ackermann_left_right(params, math.atan(0.5))  # R = 4 m
    >>> round(1 / math.tan(left), 12), round(1 / math.tan(right), 12)  # (R ∓ 0.5) / 2
    (1.75, 2.25)

    """
    theta_s = _equivalent(steering_angle)
    k = 0.5 * params.track / params.wheelbase
    sin_s, cos_s = math.sin(theta_s), math.cos(theta_s)
    left = _axle_angle(math.atan2(sin_s, cos_s - k * sin_s))
    right = _axle_angle(math.atan2(sin_s, cos_s + k * sin_s))
    return left, right


def ackermann_wheel_angles(
    params: AckermannParams, steering_angle: float
) -> tuple[float, float]:
    """
    Return the inner and outer front wheels' steering angles for an equivalent angle θ_s.

    [S]: cot θ_i = (R - track/2)/wheelbase, cot θ_o = (R + track/2)/wheelbase for |R| the
    turning radius, so |θ_i| > |θ_o| and cot|θ_o| - cot|θ_i| = track/wheelbase. The inner
    wheel is the left one for a left turn (θ_s > 0), the right one for a right turn; both
    angles carry the sign of the turn (see :func:`ackermann_left_right` for |R| < track/2).

    Parameters
    ----------
    params : AckermannParams
        Wheelbase and track [m].
    steering_angle : float
        Equivalent steering angle θ_s [rad] in [-π/2, π/2], positive to the left.

    Returns
    -------
    tuple of float
        (θ_i [rad], θ_o [rad]).

    Raises
    ------
    ValueError
        If ``steering_angle`` is not finite or |θ_s| > π/2.

    Examples
    --------
    >>> params = AckermannParams(wheelbase=2.0, track=1.0, wheel_radius=0.3)
    >>> inner, outer = ackermann_wheel_angles(params, -math.atan(0.5))  # right turn, R = 4 m
    >>> round(math.degrees(inner), 2), round(math.degrees(outer), 2)
    (-29.74, -23.96)

    """
    left, right = ackermann_left_right(params, steering_angle)
    return (left, right) if steering_angle >= 0.0 else (right, left)


def ackermann_equivalent_angle(params: AckermannParams, left: float, right: float) -> float:
    """
    Return the equivalent (bicycle) steering angle θ_s of a pair of front wheel angles.

    [S]: cot θ_s = R/wheelbase = (cot θ_left + cot θ_right)/2, the mean of the two wheels'
    estimates of the ICR, computed as θ_s = atan2(2 sin θ_l sin θ_r, sin(θ_l + θ_r)) modulo π
    (no division; 0, 0 gives 0). For a pair that satisfies the Ackermann condition this is
    the inverse of :func:`ackermann_left_right`; for measured angles that do not, it is the
    angle of the mean ICR distance.

    Parameters
    ----------
    params : AckermannParams
        Vehicle geometry (the result does not depend on it; kept for a uniform API).
    left, right : float
        Steering angles [rad] of the left and right front wheels, positive to the left.

    Returns
    -------
    float
        θ_s [rad] in (-π/2, π/2].

    Raises
    ------
    ValueError
        If an angle is not finite.

    Examples
    --------
    >>> params = AckermannParams(wheelbase=2.0, track=1.0, wheel_radius=0.3)
    >>> theta_s = ackermann_equivalent_angle(params, math.atan(1 / 1.75), math.atan(1 / 2.25))
    >>> round(math.tan(theta_s), 12)  # cot θ_s = (1.75 + 2.25)/2 = R / wheelbase, R = 4 m
    0.5

    """
    theta_l, theta_r = finite_real('left', left), finite_real('right', right)
    return _axle_angle(math.atan2(2.0 * math.sin(theta_l) * math.sin(theta_r),
                                  math.sin(theta_l + theta_r)))


def ackermann_icr(params: AckermannParams, steering_angle: float) -> tuple[float, float] | None:
    """
    Return the instantaneous centre of rotation in ``base_link`` for an equivalent angle.

    On the prolonged rear axle at (0, R), R = wheelbase · cot θ_s ([S]); None when driving
    straight (θ_s = 0, ICR at infinity); (0, 0) at θ_s = ±π/2 (to rounding).

    Parameters
    ----------
    params : AckermannParams
        Wheelbase [m].
    steering_angle : float
        Equivalent steering angle θ_s [rad] in [-π/2, π/2], positive to the left.

    Returns
    -------
    tuple of float or None
        (x [m], y [m]) of the ICR in ``base_link`` (origin at the rear-axle midpoint).

    Raises
    ------
    ValueError
        If ``steering_angle`` is not finite or |θ_s| > π/2.

    Examples
    --------
    >>> ackermann_icr(AckermannParams(2.0, 1.0, 0.3), math.atan(0.5))
    (0.0, 4.0)

    """
    theta_s = _equivalent(steering_angle)
    if theta_s == 0.0:
        return None
    return 0.0, params.wheelbase * math.cos(theta_s) / math.sin(theta_s)


def ackermann_rear_wheel_speeds(
    params: AckermannParams, v: float, omega: float
) -> tuple[float, float]:
    """
    Return the rear wheels' angular speeds for a body twist (v, ω) of the rear-axle midpoint.

    The rear wheels sit on the axle at y = ±track/2 and roll without slip along x, so, as for
    a differential drive (4.111)-(4.112): ω_rl = (v - ω track/2)/r, ω_rr = (v + ω track/2)/r.
    A driven rear axle needs a differential to allow it.

    Parameters
    ----------
    params : AckermannParams
        Track [m] and wheel radius r [m].
    v : float
        Forward speed [m/s] of the rear-axle midpoint.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float
        (ω_rear_left [rad/s], ω_rear_right [rad/s]), positive rolling forwards.

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> ackermann_rear_wheel_speeds(AckermannParams(2.0, 1.0, 0.25), 1.0, 0.5)
    (3.0, 5.0)

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    half = 0.5 * params.track * omega_
    return (v_ - half) / params.wheel_radius, (v_ + half) / params.wheel_radius


def ackermann_front_wheel_speeds(
    params: AckermannParams, v: float, omega: float
) -> tuple[float, float]:
    """
    Return the front wheels' angular speeds for a body twist (v, ω) of the rear-axle midpoint.

    The contact point of the front wheel at (wheelbase, y_w) moves at (v - ω y_w, ω wheelbase)
    (rigid body); the wheel, steered as :func:`ackermann_left_right` gives, rolls along it at
    that point's speed, signed positive when the wheel rolls forwards (its axle angle taken in
    (-π/2, π/2]). The front wheels turn faster than the rear ones on a curve.

    Parameters
    ----------
    params : AckermannParams
        Wheelbase, track and wheel radius r [m].
    v : float
        Forward speed [m/s] of the rear-axle midpoint.
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float
        (ω_front_left [rad/s], ω_front_right [rad/s]).

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> params = AckermannParams(wheelbase=2.0, track=1.0, wheel_radius=0.25)
    >>> [round(speed, 4) for speed in ackermann_front_wheel_speeds(params, 1.0, 0.5)]
    [5.0, 6.4031]

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    speeds = []
    for y_wheel in (0.5 * params.track, -0.5 * params.track):
        vx, vy = v_ - omega_ * y_wheel, omega_ * params.wheelbase
        angle = _axle_angle(math.atan2(vy, vx))
        speeds.append((vx * math.cos(angle) + vy * math.sin(angle)) / params.wheel_radius)
    return speeds[0], speeds[1]
