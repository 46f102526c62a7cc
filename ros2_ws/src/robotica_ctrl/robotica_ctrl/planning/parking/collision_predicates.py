"""
Collision predicates of the parking manoeuvres: lateral, front and rear (catalogue §14.3).

slides ("Caracterización de colisiones"): the vehicle may meet the lateral obstacle (the
curb), the front and the rear obstacles while manoeuvring, and the front one in the first
manoeuvre out of the positioning point (:mod:`.positioning_point`).

* Lateral: always the corner nearest the lateral obstacle in the direction of motion, P1
  reversing and P2 forward; only the second arc needs checking (it is nearer the obstacle).
  Its lateral distance from the start is X_Pi(θ) = d_i cos(θ − δ_i) + ρ(1 − 2 cos ξ), θ the
  turn still to go in the second arc, with the maximum X̂_Pi = d_i + ρ(1 − 2 cos ξ) at
  θ̂_Pi = δ_i (:func:`lateral_reach`). No lateral collision while X̂_Pi is within the lateral
  room.
* Front/rear: the corner nearest in the direction of motion (P2/P3 reversing, P1/P4
  forward); its singular point is θ̂_3 = δ_3 − π/2 (0 ≤ θ ≤ ξ, 0 ≤ δ_3 ≤ π), outside the
  arc's range when ρ ≥ c1/2 or ρ ≤ c1/2 − ab·tan ξ (ab = b1 for P1, P3 and a1 for P2, P4):
  then there is no front/rear collision (:func:`front_rear_collision_free`), i.e. the corner
  reaches no farther in the direction of motion than at an end of the arc.

completion (ours): the slides give X̂_Pi for θ̂ = δ_i inside the arc; when δ_i > ξ the
maximum is at the arc's start, d_i cos(ξ − δ_i) + Z (:func:`lateral_reach`). Where "no
front/rear collision" is decided, the check left is the arc's end against the obstacle; the
planner does not rely on which corner the slides name: :func:`two_arc_extents` takes, for
every corner on both arcs, the closed-form extreme of its circle (:func:`.arc_extreme`) in
the four directions, which is exactly how far the swept body reaches (the extremes of a
rectangle are at its corners). The slides' two predicates are cases of it, and the test
checks that they give the same numbers where they apply. :func:`sampled_extents` is the same
measure for a sampled motion (the progressive execution mode, whose curves are not arcs).

Frames: the manoeuvre's start frame (P_f at the origin, x forward, y left, REP-103); the
manoeuvre shifts the vehicle to the right (towards the curb, -y). Metres and radians.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.planning.parking.manoeuvre_arcs import (
    arc_extreme, corner_distances, two_arc_centres, two_arc_displacement)
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_kin.finite import finite_real

__all__ = ['SweptExtents', 'front_rear_collision_free', 'front_rear_singular_angle',
           'lateral_reach', 'sampled_extents', 'two_arc_extents']

_DIRECTIONS = (-0.5 * math.pi, 0.5 * math.pi, math.pi, 0.0)   # curb, street, back, ahead


@dataclass(frozen=True)
class SweptExtents:
    """
    How far the swept body reaches from P_f's start [m], in the start frame.

    ``curb`` the largest -y (towards the curb), ``street`` the largest +y, ``back`` the
    largest -x, ``ahead`` the largest +x. A vehicle at rest has (c1/2, c1/2, b1, a1).
    """

    curb: float
    street: float
    back: float
    ahead: float

    def mirrored(self) -> 'SweptExtents':
        """Return the extents of the mirror-image motion (y -> -y): curb and street swap."""
        return SweptExtents(self.street, self.curb, self.back, self.ahead)


def lateral_reach(vehicle: ParkingVehicle, rho: float, xi: float, corner: int) -> float:
    """
    Return the slides' lateral reach X̂_Pi [m] of corner P1 (reversing) or P2 (forward).

    X̂_Pi = d_i + ρ(1 − 2 cos ξ) when θ̂_Pi = δ_i lies in the second arc (δ_i ≤ ξ), else
    (completion) d_i cos(ξ − δ_i) + ρ(1 − 2 cos ξ); from P_f's start towards the curb, for
    two arcs of radius ``rho`` [m] and angle ``xi`` [rad]. Catalogue §14.3.

    >>> round(lateral_reach(ParkingVehicle(), 3.8, 0.8, 1), 4)
    3.2413
    """
    if corner not in (1, 2):
        raise ValueError(f'corner must be 1 (reversing) or 2 (forward), got {corner!r}')
    d, delta = corner_distances(vehicle, rho)
    angle = finite_real('xi', xi)
    _, _, z = two_arc_displacement(rho, angle)
    i = corner - 1
    if delta[i] <= angle:
        return float(d[i]) + z
    return float(d[i] * math.cos(angle - delta[i])) + z


def front_rear_singular_angle(vehicle: ParkingVehicle, rho: float, corner: int = 3) -> float:
    """
    Return the singular angle θ̂ = δ_i − π/2 [rad] of an inner corner (P3 or P4).

    The slides' θ̂_3 = δ_3 − π/2 with 0 ≤ δ_3 ≤ π: where the corner is farthest along the
    direction of motion; inside [0, ξ] it reaches beyond the arc's ends. Catalogue §14.3.

    >>> round(front_rear_singular_angle(ParkingVehicle(c1=2.0, b1=1.0), 0.5), 6)
    0.463648
    """
    if corner not in (3, 4):
        raise ValueError(f'corner must be 3 or 4 (the inner corners), got {corner!r}')
    _, delta = corner_distances(vehicle, rho)
    return float(delta[corner - 1]) - 0.5 * math.pi


def front_rear_collision_free(rho: float, c1: float, ab: float, xi: float) -> bool:
    """
    Return the slides' front/rear decision: True when the singular point is outside the arc.

    ``rho`` [m] ≥ c1/2 → no front/rear collision; else ``rho`` ≤ c1/2 − ab·tan ξ → none;
    else a front/rear collision (the corner passes beyond the arc's end). ``ab`` = b1 for
    P1, P3 and a1 for P2, P4 [m]; ``xi`` [rad] in [0, π/2). Catalogue §14.3.

    >>> front_rear_collision_free(3.8, 1.7, 0.9, 0.7)
    True
    >>> front_rear_collision_free(0.5, 2.0, 1.0, 0.7)   # 0.5 > 1 - tan(0.7) = 0.158
    False
    """
    values = [finite_real(name, value) for name, value in
              (('rho', rho), ('c1', c1), ('ab', ab), ('xi', xi))]
    r, width, overhang, angle = values
    if r >= 0.5 * width:
        return True
    return r <= 0.5 * width - overhang * math.tan(angle)


def two_arc_extents(vehicle: ParkingVehicle, rho: float, xi: float,
                    direction: int) -> SweptExtents:
    """
    Return the extents of the body swept by a two-arc manoeuvre, in closed form.

    The manoeuvre of :func:`.two_arc_centres` (radius ``rho`` [m], angle ``xi`` [rad] per arc,
    ``direction`` +1 forward or -1 reverse, shifting right): for every corner on both arcs,
    the extreme of its circle in the four directions (:func:`.arc_extreme`). Exact for the
    rectangle; the slides' X̂_Pi and front/rear decision are its cases (module docstring).

    >>> e = two_arc_extents(ParkingVehicle(), 3.8, 0.0, -1)
    >>> [round(v, 6) for v in (e.curb, e.street, e.back, e.ahead)]
    [0.85, 0.85, 0.9, 3.6]
    """
    d, delta = corner_distances(vehicle, rho)
    front = np.array([False, True, False, True])
    best = [-math.inf] * 4
    for centre, angle_from, angle_to, front_ccw in two_arc_centres(rho, xi, direction):
        # The outer corners (P1, P2) lie away from the ICR: on the left for a right-hand ICR.
        sign = np.where(front == front_ccw, 1.0, -1.0)
        for k, psi in enumerate(_DIRECTIONS):
            offset = float(centre[0] * math.cos(psi) + centre[1] * math.sin(psi))
            for i in range(4):
                reach = arc_extreme(float(d[i]), angle_from + sign[i] * delta[i],
                                    angle_to + sign[i] * delta[i], psi)
                best[k] = max(best[k], offset + reach)
    return SweptExtents(*best)


def sampled_extents(postures: ArrayLike, footprint: ArrayLike) -> SweptExtents:
    """
    Return the extents of a footprint carried through sampled postures (start frame).

    ``postures`` (N, 3) (x [m], y [m], θ [rad]) relative to the motion's start pose;
    ``footprint`` (v, 2) [m] in ``base_link``. The extremes of the vertices over the
    samples: exact at the samples, short by at most the sagitta of a vertex's path between
    them (under 0.1 mm for 1 cm samples on the curvatures of a car).

    >>> e = sampled_extents([[0, 0, 0], [-1, 0, 0]], [[-1, -1], [2, -1], [2, 1], [-1, 1]])
    >>> (e.curb, e.street, e.back, e.ahead)
    (1.0, 1.0, 2.0, 2.0)
    """
    q = np.asarray(postures, dtype=np.float64)
    body = np.asarray(footprint, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != 3 or not len(q) or not np.isfinite(q).all():
        raise ValueError(f'postures must be finite with shape (N, 3), got shape {q.shape}')
    c, s = np.cos(q[:, 2])[:, None], np.sin(q[:, 2])[:, None]
    x = q[:, 0:1] + c * body[:, 0] - s * body[:, 1]
    y = q[:, 1:2] + s * body[:, 0] + c * body[:, 1]
    return SweptExtents(float(-y.min()), float(y.max()), float(-x.min()), float(x.max()))
