"""
The car-like vehicle of the course's parallel-parking planner (seed catalogue Part 14.1).

slides: the vehicle is an Ackermann car simulated as the equivalent tricycle, described by
a1 (rear axle to the front end), b1 (rear axle to the rear end), h1 (rear axle to the centre
of the equivalent steering wheel: the wheelbase), d1 (between the centres of the rear wheels:
the track), c1 (width), r (wheel radius), θ_dmax (the largest angle of the equivalent steering
wheel) and P_f, the midpoint of the rear axle, the point that follows the path. The turning
radius of P_f for the steering angle φ_d is ρ = h1 / tan(φ_d) (catalogue §14.2), hence
ρ_min = h1 / tan(θ_dmax). The names here are the slides' (``a1``, ``b1``, ``h1``, ``d1``, ``c1``,
``r``, ``theta_dmax``); d1 and r play no part in the planning and are kept for the simulated
vehicle (:meth:`ParkingVehicle.geometry`: the track and wheel radius of
:class:`robotica_kin.mobile.vehicles.VehicleGeometry`).

The body frame is ``base_link`` at P_f (REP-103: x forward, y left); the footprint is the
rectangle from x = -b1 to a1 and y = -c1/2 to c1/2 [m].
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import NDArray
from robotica_kin.finite import finite_real
from robotica_kin.mobile.bicycle import steering_from_curvature
from robotica_kin.mobile.vehicles import VehicleGeometry

__all__ = ['ParkingVehicle']


@dataclass(frozen=True)
class ParkingVehicle:
    """
    The slides' car-like vehicle: overhangs, wheelbase, width and steering limit [m, rad].

    The defaults are a compact car (4.5 m x 1.7 m, wheelbase 2.6 m, 34° of steering).

    >>> round(ParkingVehicle().rho_min, 3)   # ρ_min = h1 / tan(θ_dmax)
    3.8
    """

    a1: float = 3.6            # [m] rear axle to the front end
    b1: float = 0.9            # [m] rear axle to the rear end
    h1: float = 2.6            # [m] rear axle to the equivalent steering wheel (wheelbase)
    c1: float = 1.7            # [m] width
    theta_dmax: float = 0.6    # [rad] largest angle of the equivalent steering wheel
    d1: float = 1.45           # [m] track: between the rear wheels' centres (not planned on)
    r: float = 0.3             # [m] wheel radius (not planned on)

    def __post_init__(self) -> None:
        for name in ('a1', 'h1', 'c1', 'd1', 'r'):
            value = finite_real(name, getattr(self, name))
            if not value > 0.0:
                raise ValueError(f'{name} must be > 0 m, got {value!r}')
        if not finite_real('b1', self.b1) >= 0.0:
            raise ValueError(f'b1 must be >= 0 m, got {self.b1!r}')
        if not 0.0 < finite_real('theta_dmax', self.theta_dmax) < 0.5 * math.pi:
            raise ValueError(f'theta_dmax must be in (0, pi/2) rad, got {self.theta_dmax!r}')

    @property
    def length(self) -> float:
        """Return the vehicle's length a1 + b1 [m]."""
        return self.a1 + self.b1

    @property
    def rho_min(self) -> float:
        """Return the smallest turning radius of P_f, ρ_min = h1 / tan(θ_dmax) [m]."""
        return self.h1 / math.tan(self.theta_dmax)

    def turning_radius(self, steering: float) -> float:
        """
        Return P_f's turning radius ρ = h1 / tan|φ_d| [m] for the steering angle φ_d [rad].

        Catalogue §14.2; ``inf`` for φ_d = 0; ValueError beyond θ_dmax.

        >>> ParkingVehicle(h1=2.0).turning_radius(math.atan(0.5))
        4.0
        """
        phi = abs(finite_real('steering', steering))
        if phi > self.theta_dmax:
            raise ValueError(f'|steering| must be <= theta_dmax = {self.theta_dmax} rad, '
                             f'got {steering!r}')
        return math.inf if phi == 0.0 else self.h1 / math.tan(phi)

    def steering_angle(self, radius: float) -> float:
        """
        Return the steering angle φ_d = atan(h1 / ρ) [rad] >= 0 that turns P_f on radius ρ [m].

        The inverse of :meth:`turning_radius`; ValueError for ρ < ρ_min (beyond θ_dmax).

        >>> round(ParkingVehicle(h1=2.0).steering_angle(4.0), 6) == round(math.atan(0.5), 6)
        True
        """
        rho = finite_real('radius', radius)
        if not rho >= self.rho_min * (1.0 - 1e-12):
            raise ValueError(f'radius must be >= rho_min = {self.rho_min} m, got {radius!r}')
        return min(steering_from_curvature(1.0 / rho, self.h1), self.theta_dmax)

    @property
    def footprint(self) -> NDArray[np.float64]:
        """
        Return the body rectangle (4, 2) [m] in ``base_link``, counter-clockwise.

        Rear-right, front-right, front-left, rear-left corners.

        >>> ParkingVehicle(a1=3.0, b1=1.0, c1=2.0).footprint.tolist()
        [[-1.0, -1.0], [3.0, -1.0], [3.0, 1.0], [-1.0, 1.0]]
        """
        half = 0.5 * self.c1
        return np.array([[-self.b1, -half], [self.a1, -half], [self.a1, half],
                         [-self.b1, half]])

    def geometry(self) -> VehicleGeometry:
        """
        Return the simulator's geometry of this vehicle (wheelbase h1, track d1, radius r).

        >>> ParkingVehicle().geometry().wheelbase
        2.6
        """
        return VehicleGeometry(wheel_radius=self.r, track=self.d1, wheelbase=self.h1,
                               max_steering_angle=self.theta_dmax)
