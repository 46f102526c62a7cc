"""
The arcs of a parking manoeuvre: corner distances to the ICR and the two-arc displacement (A).

Seed catalogue Part 14.2, slides "Relación entre el ángulo θ y la posición de P_i" and
"Ecuaciones (A)".

slides: P_f turns on radius ρ about the instantaneous centre of rotation (ICR); the corners of
the body, P1 rear-outer, P2 front-outer, P3 rear-inner, P4 front-inner ("outer" = on the side
away from the ICR), lie at the distances

    d_1 = √(b1² + (ρ + c1/2)²)   d_2 = √(a1² + (ρ + c1/2)²)
    d_3 = √(b1² + (ρ − c1/2)²)   d_4 = √(a1² + (ρ − c1/2)²)

and angles δ_1 = atan(b1/(ρ + c1/2)), δ_2 = atan(a1/(ρ + c1/2)), δ_3 = atan(b1/(ρ − c1/2)),
δ_4 = atan(a1/(ρ − c1/2)) from the ICR–P_f line, so that in the ICR frame, with P_f at the
polar angle θ, (x_Pi, y_Pi) = (d_i cos(θ − δ_i), d_i sin(θ − δ_i)) and (x_Pj, y_Pj) =
(d_j cos(θ + δ_j), d_j sin(θ + δ_j)). A manoeuvre is two symmetric arcs of angle ξ and
opposite curvature, the vehicle parallel to the space at both ends: equations (A)

    X = 2ρ(1 − cos ξ)   (lateral displacement)
    Y = 2ρ sin ξ        (longitudinal displacement)
    Z = ρ(1 − 2 cos ξ)  (lateral coordinate of the second arc's ICR, from the start).

completion (ours), the reading of the indices: the slides print "i = 1, 2; j = 2, 3" and the
catalogue proposes i ∈ {1, 2}, j ∈ {3, 4}; direct geometry (the test places the rectangle on
the arc) gives instead i ∈ {1, 3} (the rear corners at θ − δ) and j ∈ {2, 4} (the front
corners at θ + δ) when the vehicle's front points towards increasing θ (the ICR on its left
as it drives forward). The slides' lateral formula X_Pi = d_i cos(θ − δ_i) + Z for i = 1, 2
(:mod:`.collision_predicates`) is consistent with this: each is the leading corner of its own
direction of motion, where θ counts the turn still to go. δ_3, δ_4 are taken in [0, π]
(atan2), as the slides' front/rear test needs (0 ≤ δ_3 ≤ π) for ρ < c1/2.

completion (ours): :func:`arc_extreme` gives, in closed form, how far a corner on its circle
reaches in any direction over an arc, which is every extreme the predicates need: the
slides' X̂_Pi (lateral) and θ̂_3 (front/rear) are two cases of it.

Frames: the manoeuvre's start frame has P_f at the origin, x along the vehicle's heading and
y to its left (REP-103); distances in metres, angles in radians.
"""

import math

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_kin.finite import finite_real

__all__ = ['arc_extreme', 'corner_distances', 'corner_positions', 'two_arc_centres',
           'two_arc_displacement']

_TWO_PI = 2.0 * math.pi


def _radius(rho: float) -> float:
    value = finite_real('rho', rho)
    if not value > 0.0:
        raise ValueError(f'rho must be > 0 m, got {rho!r}')
    return value


def corner_distances(vehicle: ParkingVehicle,
                     rho: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the corners' distances d_i [m] and angles δ_i [rad] to the ICR, P1..P4 in order.

    Catalogue §14.2: P1 rear-outer, P2 front-outer, P3 rear-inner, P4 front-inner for the
    turning radius ``rho`` [m] of P_f; δ_3, δ_4 in [0, π] (> π/2 when ρ < c1/2).

    >>> d, delta = corner_distances(ParkingVehicle(a1=4.0, b1=0.0, c1=2.0), 2.0)
    >>> d.round(6).tolist(), delta.round(6).tolist()
    ([3.0, 5.0, 1.0, 4.123106], [0.0, 0.927295, 0.0, 1.325818])
    """
    r = _radius(rho)
    half = 0.5 * vehicle.c1
    along = np.array([vehicle.b1, vehicle.a1, vehicle.b1, vehicle.a1])
    across = np.array([r + half, r + half, r - half, r - half])
    return np.hypot(along, across), np.arctan2(along, across)


def corner_positions(vehicle: ParkingVehicle, rho: float, theta: float) -> NDArray[np.float64]:
    """
    Return the corners P1..P4 (4, 2) [m] in the ICR frame with P_f at polar angle ``theta``.

    Our reading of the slides' formulas (see the module): the rear corners P1, P3 at
    θ − δ, the front corners P2, P4 at θ + δ, the front pointing towards increasing θ.

    >>> corner_positions(ParkingVehicle(a1=4.0, b1=0.0, c1=2.0), 2.0, 0.0).round(6).tolist()
    [[3.0, 0.0], [3.0, 4.0], [1.0, 0.0], [1.0, 4.0]]
    """
    d, delta = corner_distances(vehicle, rho)
    angle = finite_real('theta', theta) + np.array([-1.0, 1.0, -1.0, 1.0]) * delta
    return np.column_stack([d * np.cos(angle), d * np.sin(angle)])


def two_arc_displacement(rho: float, xi: float) -> tuple[float, float, float]:
    """
    Return (X, Y, Z) [m] of two symmetric arcs of radius ρ [m] and angle ξ [rad]: (A).

    X lateral displacement, Y longitudinal displacement, Z lateral coordinate of the second
    arc's ICR, all from P_f's start and towards the side the manoeuvre shifts to.

    >>> [round(v, 6) for v in two_arc_displacement(1.0, math.pi / 2)]
    [2.0, 2.0, 1.0]
    """
    r, angle = _radius(rho), finite_real('xi', xi)
    return (2.0 * r * (1.0 - math.cos(angle)), 2.0 * r * math.sin(angle),
            r * (1.0 - 2.0 * math.cos(angle)))


def arc_extreme(radius: float, angle_from: float, angle_to: float, direction: float) -> float:
    """
    Return how far a point on a circle reaches along a direction over an arc [m].

    The point is at ``radius`` [m] from the centre, at polar angles from ``angle_from`` to
    ``angle_to`` [rad] (either order); the result is max cos(α − ψ)·radius over that
    interval for the direction ψ = ``direction`` [rad]: ``radius`` when the interval holds ψ
    (mod 2π), else the larger of its ends. The slides' X̂_Pi = d_i + Z at θ̂ = δ_i and their
    front/rear singular point θ̂_3 = δ_3 − π/2 are this test (catalogue §14.3).

    >>> arc_extreme(2.0, 0.0, 1.0, 0.5), round(arc_extreme(2.0, 0.0, 1.0, 2.0), 6)
    (2.0, 1.080605)
    """
    lo, hi = sorted((finite_real('angle_from', angle_from), finite_real('angle_to', angle_to)))
    psi = finite_real('direction', direction)
    turns = math.ceil((lo - psi) / _TWO_PI)
    if psi + turns * _TWO_PI <= hi:
        return float(radius)
    return float(radius) * max(math.cos(lo - psi), math.cos(hi - psi))


def two_arc_centres(rho: float, xi: float,
                    direction: int) -> tuple[tuple[NDArray[np.float64], float, float, bool], ...]:
    """
    Return each arc's ICR (2,) [m] and P_f's polar angles about it, in the start frame.

    The manoeuvre shifts P_f to the right (towards -y) by X of (A): the first arc turns
    about an ICR on the right (steering right), the second about one on the left. For each
    arc: (centre, angle_from, angle_to, front_ccw), ``front_ccw`` True when the vehicle's front
    points towards increasing polar angle (the ICR on its left). ``direction`` +1 drives
    forward (P_f ends at x = +Y), -1 in reverse (x = -Y).

    >>> [(c.round(6).tolist(), round(a, 6), round(b, 6), ccw)
    ...  for c, a, b, ccw in two_arc_centres(1.0, math.pi / 2, -1)]
    [([0.0, -1.0], 1.570796, 3.141593, False), ([-2.0, -1.0], 6.283185, 4.712389, True)]
    """
    if direction not in (-1, 1):
        raise ValueError(f'direction must be +1 (forward) or -1 (reverse), got {direction!r}')
    r, angle = _radius(rho), finite_real('xi', xi)
    first = np.array([0.0, -r])
    end_first = 0.5 * math.pi - direction * angle
    middle = first + r * np.array([math.cos(end_first), math.sin(end_first)])
    second = 2.0 * middle - first
    start_second = end_first + math.pi
    return ((first, 0.5 * math.pi, end_first, False),
            (second, start_second, start_second + direction * angle, True))
