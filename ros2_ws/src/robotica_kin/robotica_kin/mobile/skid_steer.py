"""
Skid-steer kinematics with an ICR-based slip model.

Book §2.3.1.4-§2.3.1.5 (catalog §0.2): several wheels (or a track) per side driven together,
"kinematically like a differential drive with slip" (Terregator, AURIGA). Turning a
skid-steered vehicle makes its wheels slide sideways, and the ground contacts of the two sides
rotate about instantaneous centres that lie *outside* the wheels: the ICR-based kinematic model
of Martínez et al. (2005, "Approximating kinematics for tracked mobile robots", IJRR 24(10))
takes them at constant lateral positions ±χ b/2, with χ >= 1 the ICR expansion factor of
Mandow et al. (2007, "Experimental kinematics for wheeled skid-steer mobile robots", IROS),
and symmetric about the longitudinal axis (no lateral velocity of the guide point). A constant
longitudinal slip fraction s makes each side's ground speed (1 - s) times its rim speed.

    v = (1 - s) r (ω_l + ω_r) / 2,    ω = (1 - s) r (ω_r - ω_l) / (χ b)

With χ = 1 and s = 0 this is the differential drive (4.109)-(4.110) with c = r and b = track.
The guide point is the vehicle's geometric centre, ``base_link`` x forward, y left.
"""

from dataclasses import dataclass
import math

from robotica_kin.finite import finite_real

__all__ = ['SkidSteerParams', 'skid_steer_direct', 'skid_steer_inverse']


@dataclass(frozen=True)
class SkidSteerParams:
    """
    Geometry and slip of a skid-steered vehicle.

    ``__post_init__`` raises ValueError unless r and b are finite and > 0, χ is finite and
    >= 1, and s is in [0, 1).

    >>> SkidSteerParams(wheel_radius=0.1, track=0.5, icr_scale=1.2).effective_track
    0.6
    """

    wheel_radius: float  # r [m]
    track: float  # b [m], lateral distance between the left and right wheel (track) centres
    icr_scale: float = 1.0  # χ [-], >= 1: the sides' ICRs lie at ±χ b/2 (Mandow et al. 2007)
    longitudinal_slip: float = 0.0  # s [-] in [0, 1): ground speed = (1 - s) rim speed

    def __post_init__(self) -> None:
        """Reject non-finite or out-of-range values."""
        for name in ('wheel_radius', 'track'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 m, got {value!r}')
        if not (math.isfinite(self.icr_scale) and self.icr_scale >= 1.0):
            raise ValueError(f'icr_scale must be finite and >= 1, got {self.icr_scale!r}')
        if not 0.0 <= self.longitudinal_slip < 1.0:
            raise ValueError(
                f'longitudinal_slip must be in [0, 1), got {self.longitudinal_slip!r}')

    @property
    def effective_track(self) -> float:
        """Distance χ b [m] between the two sides' instantaneous centres of rotation."""
        return self.icr_scale * self.track


def skid_steer_direct(
    params: SkidSteerParams, omega_left: float, omega_right: float
) -> tuple[float, float]:
    """
    Return the body twist from the wheel speeds of the two sides.

    v = (1 - s) r (ω_l + ω_r)/2, ω = (1 - s) r (ω_r - ω_l)/(χ b) (Martínez et al. 2005 with
    symmetric ICRs at ±χ b/2 and equal slip on both sides).

    Parameters
    ----------
    params : SkidSteerParams
        Wheel radius r [m], track b [m], ICR scale χ, slip s.
    omega_left, omega_right : float
        Wheel angular speeds [rad/s] of the left and right sides, positive forwards.

    Returns
    -------
    tuple of float
        (v [m/s] along ``base_link`` x, ω [rad/s] counter-clockwise).

    Raises
    ------
    ValueError
        If a wheel speed is not finite.

    Examples
    --------
    >>> skid_steer_direct(SkidSteerParams(0.1, 0.5, icr_scale=2.0), -2.0, 2.0)
    (0.0, 0.4)

    """
    w_left = finite_real('omega_left', omega_left)
    w_right = finite_real('omega_right', omega_right)
    rim = (1.0 - params.longitudinal_slip) * params.wheel_radius
    return rim * (w_left + w_right) / 2.0, rim * (w_right - w_left) / params.effective_track


def skid_steer_inverse(
    params: SkidSteerParams, v: float, omega: float
) -> tuple[float, float]:
    """
    Return the wheel speeds of the two sides that produce a body twist (v, ω).

    The inverse of :func:`skid_steer_direct`: ω_l = (v - ω χ b/2) / ((1 - s) r),
    ω_r = (v + ω χ b/2) / ((1 - s) r). Slip and the wider effective track make the wheels
    turn faster than a differential drive's for the same twist.

    Parameters
    ----------
    params : SkidSteerParams
        Wheel radius r [m], track b [m], ICR scale χ, slip s.
    v : float
        Forward speed [m/s].
    omega : float
        Yaw rate [rad/s], positive counter-clockwise.

    Returns
    -------
    tuple of float
        (ω_left [rad/s], ω_right [rad/s]).

    Raises
    ------
    ValueError
        If ``v`` or ``omega`` is not finite.

    Examples
    --------
    >>> skid_steer_inverse(SkidSteerParams(0.1, 0.5, icr_scale=2.0), 0.0, 0.4)
    (-2.0, 2.0)

    """
    v_, omega_ = finite_real('v', v), finite_real('omega', omega)
    rim = (1.0 - params.longitudinal_slip) * params.wheel_radius
    half = 0.5 * params.effective_track * omega_
    return (v_ - half) / rim, (v_ + half) / rim
