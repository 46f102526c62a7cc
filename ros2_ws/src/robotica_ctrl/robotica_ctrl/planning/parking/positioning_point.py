"""
The positioning point (dx1) and the stop of the reconnaissance pass (dy3), catalogue §14.3.

slides: the positioning point lies on the prolongation of the side of the front obstacle, as
close as possible to it while the first backward manoeuvre does not meet it. With the
obstacle's corner at the origin of (X, Y) (X lateral towards the curb, Y along the reversing
direction) and P_f starting at (−dx1, 0), the front-outer corner P2 follows, in the second
arc of the first manoeuvre,

    y_P2(θ) = 2ρ sin ξ − (ρ sin θ + (c1/2) sin θ + a1 cos θ)
    x_P2(θ) = ρ(1 − 2 cos ξ) + ρ cos θ + (c1/2) cos θ − a1 sin θ − dx1

and the least dx1 is the one that makes P2 pass through (0, 0). dy3 is the least length of
the initial straight motion (the reconnaissance pass) before stopping, computed from dx1 and
dx2 (the vehicle's lateral separation during the pass) avoiding lateral collisions.

completion (ours):

* dx1 (:func:`front_corner_offset`): θ* solves y_P2(θ*) = 0 in the second arc, by bisection
  where y_P2 is monotone (θ ≤ π/2 − δ_2), and dx1 = x_P2(θ*) + dx1 = ρ(1 − 2 cos ξ) +
  (ρ + c1/2) cos θ* − a1 sin θ*. The vehicle must start clear of the obstacle's side, so
  dx1 >= c1/2, and the safety margin MS is added (:func:`positioning_offset`). When P2 does not
  cross the corner's line in the second arc (no θ* in [0, ξ]), or for the progressive mode
  whose curves are not arcs, the least offset is measured on the swept body sampled every
  1 cm (:func:`sampled_corner_offset`): the deepest point of the body ahead of the corner's
  line, plus the most a point of the body moves between two samples (a bound, not an
  estimate: about 2 cm for a car). The obstacle's corner is that of the effective space
  (H' = H − 2 MS): longitudinally MS inside the space, so the first manoeuvre keeps MS from
  it both ways.
* dy3 (:func:`approach`): the vehicle, at P_f's lateral offset dx2 from the parked
  obstacles' line, reverses to the positioning point: straight when dx2 = dx1 (dy3 = 0),
  else by a two-arc lateral shift X = |dx2 − dx1| (towards the curb when dx2 > dx1); dy3 is
  its longitudinal length Y, so the approach ends exactly at the positioning point. The
  steering is the largest (the shortest dy3) that keeps the body a clearance from the
  obstacles' line where it is beside the front obstacle (ahead of its corner), measured on the
  body sampled every 1 cm (:func:`sampled_corner_offset`), found by bisection: a gentler
  steering swings the body less. The planner asks for MS/2, not MS: any reverse S that ends
  at dx1 swings the rear-outer corner beyond its final line by up to d_1 − (ρ + c1/2)
  (≈ b1²/2ρ) beside the obstacle, so with the least dx1 (c1/2 + MS) no steering keeps MS.

Frames: the planner's canonical space frame (:mod:`.space`), whose line of parked obstacles
is y = 0 with the space below it; the slides' (X, Y) is X = −y, Y = x_corner − x. Metres,
radians.
"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.planning.parking.execution_modes import (
    ExecutionMode, FINE_STEP, GeometricMode, Piece, sample_pieces)
from robotica_ctrl.planning.parking.manoeuvre_arcs import corner_distances, two_arc_displacement
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_kin.finite import finite_real

__all__ = ['Approach', 'approach', 'front_corner_offset', 'positioning_offset',
           'sampled_corner_offset']

_BISECTIONS = 60
_MIN_STEERING_FRACTION = 1e-3    # the gentlest approach steering tried, of φ_d


def front_corner_offset(vehicle: ParkingVehicle, rho: float, xi: float) -> Optional[float]:
    """
    Return the slides' least dx1 [m] (no margin): P2 through the front obstacle's corner.

    The first manoeuvre reverses on two arcs of radius ``rho`` [m] and angle ``xi`` [rad].
    None when P2 does not cross the corner's line (Y = 0) during the second arc.

    >>> round(front_corner_offset(ParkingVehicle(), 3.8, 0.78), 4)
    0.8495
    """
    d, delta = corner_distances(vehicle, rho)
    _, y_end, z = two_arc_displacement(rho, xi)
    reach = rho + 0.5 * vehicle.c1

    def y_p2(theta: float) -> float:
        return y_end - reach * math.sin(theta) - vehicle.a1 * math.cos(theta)

    deepest = min(max(0.5 * math.pi - float(delta[1]), 0.0), xi)
    if y_p2(deepest) > 0.0 or y_p2(0.0) < 0.0:
        return None
    lo, hi = 0.0, deepest          # y_p2(lo) >= 0 >= y_p2(hi), y_p2 falls on [0, deepest]
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if y_p2(mid) >= 0.0:
            lo = mid
        else:
            hi = mid
    theta = 0.5 * (lo + hi)
    return z + reach * math.cos(theta) - vehicle.a1 * math.sin(theta)


def sampled_corner_offset(postures: ArrayLike, footprint: ArrayLike) -> float:
    """
    Return the deepest reach (largest -y) [m] of the body ahead of the start (x >= 0).

    ``postures`` (N, 3) relative to the start pose; ``footprint`` (v, 2) convex in
    ``base_link``. For each sample, the body cut by the line x = 0: its vertices ahead of it
    and the crossings of its edges with it; the largest over the samples, plus the most any
    point of the body moves between two samples (|Δp| + r_max |Δθ|): a corner crossing the
    line between samples is deepest there, so the bare sampled value can fall short by that
    much, never the bound. The obstacle's corner level with P_f's start clears the body when
    P_f starts farther than this from the corner's line.

    >>> sampled_corner_offset([[0, 0, 0], [-2, -1, 0]], [[-1, -1], [2, -1], [2, 1], [-1, 1]])
    4.23606797749979
    """
    q = np.asarray(postures, dtype=np.float64)
    body = np.asarray(footprint, dtype=np.float64)
    c, s = np.cos(q[:, 2])[:, None], np.sin(q[:, 2])[:, None]
    x = q[:, 0:1] + c * body[:, 0] - s * body[:, 1]
    y = q[:, 1:2] + s * body[:, 0] + c * body[:, 1]
    deepest = np.where(x >= 0.0, -y, -np.inf).max(axis=1)
    x2, y2 = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)
    crosses = (x * x2 <= 0.0) & (x != x2)
    t = np.divide(-x, x2 - x, out=np.zeros_like(x), where=crosses)
    deepest = np.maximum(deepest, np.where(crosses, -(y + t * (y2 - y)), -np.inf).max(axis=1))
    step = np.diff(q, axis=0)
    reach = float(np.hypot(body[:, 0], body[:, 1]).max())
    moved = float((np.hypot(step[:, 0], step[:, 1]) + reach * np.abs(step[:, 2])).max(
        initial=0.0))
    return float(deepest.max()) + moved


def positioning_offset(mode: ExecutionMode, size: float, margin: float) -> float:
    """
    Return dx1 [m]: P_f's offset from the obstacles' line for a first manoeuvre of ``size``.

    max(least offset, c1/2) + ``margin`` (MS) [m]; the least offset is the slides' (P2 through
    the corner) for the arcs when it exists, else the sampled body's (module docstring).

    >>> round(positioning_offset(GeometricMode(ParkingVehicle(), 0.6), 0.78, 0.2), 4)
    1.05
    """
    vehicle = mode.vehicle
    least = None
    if isinstance(mode, GeometricMode):
        least = front_corner_offset(vehicle, mode.radius, size)
    if least is None:
        motion = sample_pieces(np.zeros(3), mode.pieces(size, -1), vehicle.h1, FINE_STEP)
        least = sampled_corner_offset(motion.postures, vehicle.footprint)
    return max(least, 0.5 * vehicle.c1) + finite_real('margin', margin)


@dataclass(frozen=True)
class Approach:
    """
    The reverse from the stop point to the positioning point.

    ``pieces`` to drive (empty when dx2 = dx1), ``dy3`` [m] the stop point's distance beyond
    the positioning point, ``steering`` [rad] the largest angle used, ``size`` the two-arc
    size, ``toward_curb`` True when it shifts towards the space (dx2 > dx1).
    """

    pieces: tuple[Piece, ...]
    dy3: float
    steering: float
    size: float
    toward_curb: bool


def approach(mode: ExecutionMode, dx1: float, dx2: float,
             clearance: float) -> Optional[Approach]:
    """
    Return the approach from the pass at offset ``dx2`` to the positioning point at ``dx1``.

    Offsets [m] of P_f from the obstacles' line; the body beside the front obstacle keeps
    ``clearance`` [m] from that line. None when no steering down to 1/1000 of φ_d keeps it
    (the pass is too close to the parked obstacles). See the module for dy3.

    >>> a = approach(GeometricMode(ParkingVehicle(), 0.6), 1.05, 1.05, 0.2)
    >>> a.dy3, a.pieces
    (0.0, ())
    >>> round(approach(GeometricMode(ParkingVehicle(), 0.6), 1.05, 1.6, 0.1).dy3, 3)
    2.954
    """
    shift = finite_real('dx2', dx2) - finite_real('dx1', dx1)
    if abs(shift) <= 1e-9:
        return Approach((), 0.0, 0.0, 0.0, True)
    toward_curb = shift > 0.0

    def attempt(steering: float) -> Optional[Approach]:
        trial = mode.with_steering(steering)
        size = trial.size_for_shift(abs(shift))
        pieces = trial.pieces(size, -1)
        if not toward_curb:
            pieces = tuple(piece.mirrored() for piece in pieces)
        postures = sample_pieces(np.zeros(3), pieces, mode.vehicle.h1, FINE_STEP).postures
        end = postures[-1]
        if abs(abs(end[1]) - abs(shift)) > 1e-6:
            return None                              # the shift is beyond this steering
        # The corner of the front obstacle is level with the positioning point, at x = end.
        deepest = sampled_corner_offset(postures - [end[0], 0.0, 0.0], mode.vehicle.footprint)
        if dx2 - deepest < clearance - 1e-9:
            return None
        return Approach(pieces, float(-end[0]), steering, size, toward_curb)

    best = attempt(mode.steering)
    if best is not None:
        return best
    lo, hi = _MIN_STEERING_FRACTION * mode.steering, mode.steering
    found = attempt(lo)
    if found is None:
        return None
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        trial = attempt(mid)
        if trial is None:
            hi = mid
        else:
            lo, found = mid, trial
    return found
