"""
The course's parallel-parking planner: the manoeuvre list and a path (catalogue §14.4).

After Gómez-Bravo, Cuesta & Ollero (2001), as the slides ("Planificador de Estacionamiento en
línea") give it; seed catalogue Part 14.

slides: (1) detect the parking space with one pass (:mod:`.space_detection`); (2) stop after
dy3 and reverse to the positioning point, on the prolongation of the side of the front
obstacle at the lateral offset dx1, as close to it as the first backward manoeuvre allows
(:mod:`.positioning_point`); (3) alternate backward and forward manoeuvres until the goal is
reached, each two circular arcs with the equivalent steering wheel going from one extreme to
the other between them, the vehicle parallel to the space at the start and end of each, with
no lateral, front or rear collision (:mod:`.collision_predicates`); (4) execute them stopping
between the arcs to re-orient the wheels, or steering progressively (:mod:`.execution_modes`).

completion (ours), everything the slides leave open, in the canonical frame of the space
(:mod:`.space`: the parked obstacles' sides on y = 0, the space 0 ≤ x ≤ H below it):

* Feasibility: a space with H' = H − 2 MS < a1 + b1 is refused (the vehicle does not fit: no
  first manoeuvre can take its front past the front obstacle with its rear inside the space).
  The limits of the body are the effective space: x ≥ MS (rear), x ≤ H − MS (front) and
  y ≥ −J' + MS (the curb), the whole body held to them (conservative where it is still in
  the street); the front obstacle's corner is at (H − MS, 0).
* The lateral goal of P_f is the centre of J', y = −J'/2, moved towards the street when the
  play is less than the overshoot of a reverse manoeuvre's rear-outer corner beyond its end
  line (d_1 − ρ − c1/2 for the arcs), so that the last manoeuvre can reach it; a goal whose
  body would stick out of the space (y + c1/2 > 0) is refused as too narrow. The goal is
  reached within ``lateral_tolerance``; a final straight move centres the body in H.
* The first manoeuvre (reverse, from the positioning point) has the largest size whose
  shift does not pass the goal, that takes the front past the corner (Y ≥ a1), keeps the
  rear within the space and the body off the curb, with dx1 recomputed for each size (a
  scan of 64 sizes, then bisection next to the largest that fits).
* Each next manoeuvre reverses the direction of travel; its size is the one that reaches
  the goal (ξ = arccos(1 − ΔX/2ρ) for the arcs) if it fits, else the largest that fits
  (bisection: the swept extents grow with the size). One that shifts less than
  ``min_progress`` means the planner is stuck: "no path" with the reason. At most
  ``max_manoeuvres`` manoeuvres, and the evaluations of candidate manoeuvres are bounded by
  a :class:`~robotica_ctrl.planning.plan_result.SearchBudget` (expansions, and seconds on
  a caller's clock): either bound reported when hit.
* The whole path (the rest of the pass to the stop point, the approach, the manoeuvres, the
  centring) is swept with the footprint against the world (the given one, else the
  space's own obstacles, :meth:`.ParkingSpace.obstacle_world`) with
  :func:`~robotica_ctrl.planning.path_collision.pose_collision`: a contact is "no path"
  with where it happens. This checks the predicates; it does not replace them.

The result is a :class:`~robotica_ctrl.planning.plan_result.PlanResult` in the map frame:
``path`` (N, 3) postures of P_f (x [m], y [m], θ [rad]) every ``path_step`` at most,
``directions`` (N − 1,) +1 forward / −1 reverse, ``cost`` the length driven [m], and in
``details`` the manoeuvre list (:class:`Manoeuvre`), the steering per segment, the stops (the
cusps, and in the geometric mode the changes of steering between arcs), dx1, dx2, dy3, the
positioning and stop points, the goal and the least clearance to the world.
"""

from dataclasses import dataclass, replace
import math
from typing import Any, Literal, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.parking.execution_modes import (
    ExecutionMode, make_mode, ManoeuvreShape, Piece, sample_pieces)
from robotica_ctrl.planning.parking.positioning_point import approach, positioning_offset
from robotica_ctrl.planning.parking.space import ParkingSpace
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_ctrl.planning.path_collision import pose_collision
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.search_setup import BudgetMeter, Clock
from robotica_kin.finite import finite_real
from robotica_kin.world import footprint_distance, World

__all__ = ['Manoeuvre', 'ParkingParams', 'plan_parallel_parking']

ManoeuvreKind = Literal['pass', 'approach', 'parking', 'centring']
_FIRST_SCAN = 64           # sizes tried for the first manoeuvre before the bisection
_BISECTIONS = 50           # halvings of a size interval
_SLACK = 1e-9              # [m] rounding allowed on a limit


@dataclass(frozen=True)
class ParkingParams:
    """
    Tunables of the parking planner (module docstring) [m, rad, s].

    >>> ParkingParams().mode, ParkingParams(mode='progressive').steering_per_metre
    ('geometric', 0.8)
    """

    mode: str = 'geometric'              # 'geometric' (stop between arcs) or 'progressive'
    steering: Optional[float] = None     # φ_d [rad] of the arcs; None: θ_dmax (ρ_min)
    steering_rate: float = 0.4           # [rad/s] of the progressive mode's steering
    manoeuvre_speed: float = 0.5         # [m/s] of the progressive mode: σ = rate / speed
    max_manoeuvres: int = 30             # backward and forward manoeuvres, at most
    lateral_tolerance: float = 0.02      # [m] the lateral goal is reached within this
    min_progress: float = 1e-3           # [m] a manoeuvre shifting less is no progress
    heading_tolerance: float = 0.1       # [rad] the start's heading off the street, at most
    path_step: float = 0.05              # [m] between the path's postures, at most
    centre: bool = True                  # end with a straight move centring the body in H

    def __post_init__(self) -> None:
        if self.mode not in ('geometric', 'progressive'):
            raise ValueError(f"mode must be 'geometric' or 'progressive', got {self.mode!r}")
        if self.steering is not None and not (
                0.0 < finite_real('steering', self.steering) < 0.5 * math.pi):
            raise ValueError(f'steering must be in (0, pi/2) rad, got {self.steering!r}')
        for name in ('steering_rate', 'manoeuvre_speed', 'lateral_tolerance', 'min_progress',
                     'heading_tolerance', 'path_step'):
            if not finite_real(name, getattr(self, name)) > 0.0:
                raise ValueError(f'{name} must be > 0, got {getattr(self, name)!r}')
        if not (isinstance(self.max_manoeuvres, int) and self.max_manoeuvres > 0):
            raise ValueError(f'max_manoeuvres must be an integer > 0, got '
                             f'{self.max_manoeuvres!r}')

    @property
    def steering_per_metre(self) -> float:
        """Return σ = steering_rate / manoeuvre_speed [rad/m] of the progressive mode."""
        return self.steering_rate / self.manoeuvre_speed


@dataclass(frozen=True)
class Manoeuvre:
    """
    One element of the plan: what is driven, how, and where it lies on the path.

    ``kind`` 'pass' (the rest of the reconnaissance pass, straight), 'approach' (reverse to
    the positioning point), 'parking' (a two-arc manoeuvre) or 'centring' (straight);
    ``direction`` +1 forward, −1 reverse; ``pieces`` the stretches in the map's sense of
    steering (positive left); ``size`` ξ [rad] of the arcs (geometric) or the progressive
    size (0 for a straight); ``radius`` ρ [m] at the largest steering (inf for a straight),
    ``steering`` that angle φ_d [rad]; ``lateral_shift`` [m] of P_f towards the space (< 0
    away from it) and ``longitudinal_shift`` [m] along the street (> 0 in the direction of
    the pass); ``first_posture`` and ``last_posture`` index the path.
    """

    kind: ManoeuvreKind
    direction: int
    pieces: tuple[Piece, ...]
    size: float
    radius: float
    steering: float
    lateral_shift: float
    longitudinal_shift: float
    first_posture: int = 0
    last_posture: int = 0

    @property
    def length(self) -> float:
        """Return the length driven by P_f [m]."""
        return float(sum(piece.length for piece in self.pieces))

    def as_dict(self) -> dict[str, Any]:
        """Return the manoeuvre as plain numbers and strings (for reports and messages)."""
        return {'kind': self.kind, 'direction': self.direction, 'size': self.size,
                'radius': self.radius, 'steering': self.steering, 'length': self.length,
                'lateral_shift': self.lateral_shift,
                'longitudinal_shift': self.longitudinal_shift,
                'first_posture': self.first_posture, 'last_posture': self.last_posture,
                'pieces': [{'direction': p.direction, 'length': p.length,
                            'steering_start': p.steering_start,
                            'steering_end': p.steering_end, 'kind': p.kind}
                           for p in self.pieces]}


@dataclass
class _Search:
    """The state of one planning run: the mode, the limits and the work done."""

    mode: ExecutionMode
    meter: BudgetMeter
    front: float            # [m] largest x of the body (H − MS)
    rear: float             # [m] least x of the body (MS)
    curb: float             # [m] least y of the body (−J' + MS)
    goal: float             # [m] P_f's lateral goal
    evaluations: int = 0

    def shape(self, size: float, direction: int) -> ManoeuvreShape:
        self.evaluations += 1
        return self.mode.shape(size, direction)

    def stopped(self) -> str:
        return self.meter.exhausted(self.evaluations)


def _straight(kind: ManoeuvreKind, x_from: float, x_to: float) -> Optional[Manoeuvre]:
    length = abs(x_to - x_from)
    if length <= _SLACK:
        return None
    direction = 1 if x_to > x_from else -1
    return Manoeuvre(kind, direction, (Piece(direction, length, 0.0, 0.0, 'straight'),),
                     0.0, math.inf, 0.0, 0.0, direction * length)


def _parking(search: _Search, size: float, direction: int) -> Manoeuvre:
    shape = search.mode.shape(size, direction)
    steering = search.mode.steering
    return Manoeuvre('parking', direction, search.mode.pieces(size, direction), size,
                     search.mode.vehicle.turning_radius(steering), steering, shape.lateral,
                     direction * shape.longitudinal)


def _first_fits(search: _Search, size: float, margin: float) -> tuple[bool, str]:
    """Return whether the first manoeuvre of ``size`` fits, else which limit it breaks."""
    vehicle = search.mode.vehicle
    shape = search.shape(size, -1)
    dx1 = positioning_offset(search.mode, size, margin)
    if shape.longitudinal < vehicle.a1 - _SLACK:
        return False, 'front'
    if search.front - shape.extents.back < search.rear - _SLACK:
        return False, 'rear'
    if dx1 - shape.extents.curb < search.curb - _SLACK:
        return False, 'curb'
    if dx1 - shape.lateral < search.goal - _SLACK:
        return False, 'goal'
    return True, ''


def _first_size(search: _Search, margin: float) -> tuple[Optional[float], str]:
    """Return the first manoeuvre's size, or None and why no size fits."""
    top = search.mode.max_size
    sizes = top * np.arange(1, _FIRST_SCAN + 1) / _FIRST_SCAN
    verdicts = [_first_fits(search, float(s), margin) for s in sizes]
    fitting = [k for k, (fits, _) in enumerate(verdicts) if fits]
    if not fitting:
        broken = {why for _, why in verdicts}
        return None, ', '.join(sorted(broken))
    k = fitting[-1]
    if k == len(sizes) - 1:
        return float(sizes[k]), ''
    lo, hi = float(sizes[k]), float(sizes[k + 1])
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _first_fits(search, mid, margin)[0]:
            lo = mid
        else:
            hi = mid
    return lo, ''


def _fits(search: _Search, pose: NDArray[np.float64], size: float, direction: int) -> bool:
    shape = search.shape(size, direction)
    e = shape.extents
    if pose[1] - e.curb < search.curb - _SLACK:
        return False
    if direction < 0:
        return bool(pose[0] - e.back >= search.rear - _SLACK)
    return bool(pose[0] + e.ahead <= search.front + _SLACK)


def _next_size(search: _Search, pose: NDArray[np.float64], direction: int) -> float:
    """Return the size of the next manoeuvre: the goal's if it fits, else the largest that does."""
    need = search.mode.size_for_shift(pose[1] - search.goal)
    if _fits(search, pose, need, direction):
        return need
    lo, hi = 0.0, need
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _fits(search, pose, mid, direction):
            lo = mid
        else:
            hi = mid
    return lo


_FIRST_REASONS = {
    'front': 'it cannot take the front past the front obstacle (Y < a1)',
    'rear': 'its rear leaves the space',
    'curb': 'its body reaches the curb',
    'goal': 'it passes the lateral goal',
}


def _check_inputs(space: ParkingSpace, vehicle: ParkingVehicle, start: ArrayLike,
                  params: ParkingParams, world: Optional[World]) -> NDArray[np.float64]:
    if not isinstance(space, ParkingSpace):
        raise ValueError(f'space must be a ParkingSpace, got {type(space).__name__}')
    if not isinstance(vehicle, ParkingVehicle):
        raise ValueError(f'vehicle must be a ParkingVehicle, got {type(vehicle).__name__}')
    if not isinstance(params, ParkingParams):
        raise ValueError(f'params must be ParkingParams, got {type(params).__name__}')
    if world is not None and not isinstance(world, World):
        raise ValueError(f'world must be a World, got {type(world).__name__}')
    pose = np.asarray(start, dtype=np.float64)
    if pose.shape != (3,) or not np.isfinite(pose).all():
        raise ValueError(f'start must be a finite pose (x, y, theta), got {start!r}')
    if params.steering is not None and params.steering > vehicle.theta_dmax:
        raise ValueError(f'steering {params.steering} rad exceeds theta_dmax = '
                         f'{vehicle.theta_dmax} rad')
    return pose


def plan_parallel_parking(space: ParkingSpace, vehicle: ParkingVehicle, start: ArrayLike,
                          params: ParkingParams = ParkingParams(),
                          world: Optional[World] = None,
                          budget: SearchBudget = SearchBudget(),
                          clock: Optional[Clock] = None) -> PlanResult:
    """
    Return the parallel-parking plan into ``space`` from ``start``, or "no path" and why.

    Parameters
    ----------
    space : ParkingSpace
        The space (H, J, MS, side) and its frame in the map (:mod:`.space`).
    vehicle : ParkingVehicle
        a1, b1, h1, c1, θ_dmax [m, rad].
    start : array_like, shape (3,)
        P_f's pose (x [m], y [m], θ [rad]) in the map frame, on the pass: parallel to the
        street within ``heading_tolerance``, its lateral offset from the parked obstacles'
        line is dx2.
    params : ParkingParams
        The execution mode and the planner's tunables.
    world : World, optional
        The obstacles the path is checked against (map frame); the space's own by default.
    budget : SearchBudget
        At most ``max_expansions`` candidate manoeuvres evaluated, ``max_seconds`` by
        ``clock``.
    clock : callable, optional
        Returns seconds (e.g. ``time.monotonic``) for the time bound.

    Returns
    -------
    PlanResult
        ``path`` (N, 3), ``directions`` (N - 1,), ``cost`` [m] and ``details`` (module
        docstring), or no path with the reason: a space too short or too narrow, a start
        off the pass, no manoeuvre that fits, no progress, a bound hit, a contact.

    Raises
    ------
    ValueError
        On input of the wrong type, shape or value.

    Examples
    --------
    >>> space = ParkingSpace((0.0, 0.0, 0.0), length=7.15, depth=2.2)
    >>> plan = plan_parallel_parking(space, ParkingVehicle(), (0.0, 1.4, 0.0))
    >>> plan.found, plan.details['parking_manoeuvres']
    (True, 1)
    >>> plan_parallel_parking(ParkingSpace((0.0, 0.0, 0.0), 4.5, 2.2), ParkingVehicle(),
    ...                       (0.0, 1.4, 0.0)).reason.startswith('the space is too short')
    True

    """
    pose_map = _check_inputs(space, vehicle, start, params, world)
    meter = BudgetMeter(budget, clock)
    margin = space.margin
    length_eff, width = space.effective_length, space.effective_width
    if length_eff < vehicle.length:
        return PlanResult.none(
            f"the space is too short: H' = H - 2 MS = {length_eff:.3f} m < a1 + b1 = "
            f'{vehicle.length:.3f} m')
    steering = vehicle.theta_dmax if params.steering is None else params.steering
    mode = make_mode(params.mode, vehicle, steering, params.steering_per_metre)
    widest = mode.shape(mode.max_size, -1)
    overshoot = max(widest.extents.curb - widest.lateral - 0.5 * vehicle.c1, 0.0)
    curb = -width + margin
    goal = max(-0.5 * width, curb + 0.5 * vehicle.c1 + overshoot)
    if goal + 0.5 * vehicle.c1 > 0.0:
        return PlanResult.none(
            f"the space is too narrow: J' - MS = {width - margin:.3f} m < c1 + "
            f"{overshoot:.3f} m (a reverse manoeuvre's overshoot) = "
            f'{vehicle.c1 + overshoot:.3f} m')
    search = _Search(mode, meter, space.length - margin, margin, curb, goal)
    start_c = space.from_map(pose_map)[0]
    dx2 = float(start_c[1])
    if abs(start_c[2]) > params.heading_tolerance:
        return PlanResult.none(
            f'the start is not parallel to the street: heading {start_c[2]:.3f} rad off it, '
            f'more than heading_tolerance = {params.heading_tolerance} rad')
    if dx2 - 0.5 * vehicle.c1 <= 0.0:
        return PlanResult.none(
            f'the start is not beside the parked obstacles: P_f {dx2:.3f} m from their line, '
            f'less than c1/2 = {0.5 * vehicle.c1:.3f} m')
    size, broken = _first_size(search, margin)
    if size is None:
        why = '; '.join(_FIRST_REASONS[b] for b in broken.split(', '))
        return PlanResult.none(f'no first manoeuvre fits the space: {why}',
                               search.evaluations)
    dx1 = positioning_offset(mode, size, margin)
    way_in = approach(mode, dx1, dx2, 0.5 * margin)
    if way_in is None:
        return PlanResult.none(
            f'the pass is too close to the parked obstacles: no approach from dx2 = '
            f'{dx2:.3f} m to the positioning point at dx1 = {dx1:.3f} m keeps MS/2 from them',
            search.evaluations)
    front = search.front
    stop_x = front + way_in.dy3
    plan: list[Manoeuvre] = []
    rest = _straight('pass', float(start_c[0]), stop_x)
    if rest is not None:
        plan.append(rest)
    if way_in.pieces:
        shift = dx2 - dx1
        plan.append(Manoeuvre('approach', -1, way_in.pieces, way_in.size,
                              vehicle.turning_radius(way_in.steering), way_in.steering,
                              shift, -way_in.dy3))
    first = _parking(search, size, -1)
    plan.append(first)
    pose = np.array([front + first.longitudinal_shift, dx1 - first.lateral_shift, 0.0])
    direction = 1
    parked = 1
    while pose[1] - goal > params.lateral_tolerance:
        stopped = search.stopped()
        if parked >= params.max_manoeuvres or stopped:
            bound = stopped or (f'the bound of {params.max_manoeuvres} manoeuvres was hit')
            return PlanResult.none(
                f'{bound} with {pose[1] - goal:.3f} m of lateral shift left',
                search.evaluations, manoeuvres=_in_map(plan, space.mirror))
        size = _next_size(search, pose, direction)
        step = _parking(search, size, direction)
        if step.lateral_shift < params.min_progress:
            name = 'forward' if direction > 0 else 'reverse'
            return PlanResult.none(
                f'no progress: manoeuvre {parked + 1} ({name}) can shift the vehicle only '
                f'{step.lateral_shift:.2e} m within the space, {pose[1] - goal:.3f} m left',
                search.evaluations, manoeuvres=_in_map(plan, space.mirror))
        plan.append(step)
        parked += 1
        pose = pose + [step.longitudinal_shift, -step.lateral_shift, 0.0]
        direction = -direction
    if params.centre:
        centring = _straight('centring', float(pose[0]),
                             0.5 * space.length - 0.5 * (vehicle.a1 - vehicle.b1))
        if centring is not None:
            plan.append(centring)
    return _result(space, vehicle, params, world, search, plan, start_c, dx1, dx2,
                   way_in.dy3, parked)


def _in_map(plan: list[Manoeuvre], mirror: float) -> tuple[Manoeuvre, ...]:
    """Return the manoeuvres with the map's sense of steering (mirrored for a left space)."""
    if mirror > 0.0:
        return tuple(plan)
    return tuple(replace(m, pieces=tuple(p.mirrored() for p in m.pieces),
                         steering=-m.steering) for m in plan)


def _result(space: ParkingSpace, vehicle: ParkingVehicle, params: ParkingParams,
            world: Optional[World], search: _Search, plan: list[Manoeuvre],
            start_c: NDArray[np.float64], dx1: float, dx2: float, dy3: float,
            parked: int) -> PlanResult:
    """Sample the plan, map it, check it against the world and wrap it in a PlanResult."""
    pieces = [piece for m in plan for piece in m.pieces]
    motion = sample_pieces([float(start_c[0]), dx2, 0.0], tuple(pieces), vehicle.h1,
                           params.path_step)
    path = space.to_map(motion.postures)
    mirror = space.mirror
    counts = np.cumsum([0] + [len(m.pieces) for m in plan])
    placed = []
    for k, m in enumerate(_in_map(plan, mirror)):
        segments = np.flatnonzero((motion.piece >= counts[k]) & (motion.piece < counts[k + 1]))
        first, last = (int(segments[0]), int(segments[-1]) + 1) if len(segments) else (0, 0)
        placed.append(replace(m, first_posture=first, last_posture=last))
    changes = np.flatnonzero(np.diff(motion.directions) != 0) + 1
    if search.mode.stops_between_arcs:
        changes = np.union1d(changes, np.flatnonzero(np.diff(motion.steering) != 0) + 1)
    stops = np.union1d(changes, [len(path) - 1]).astype(np.int64)
    extent = 10.0 + float(np.abs(motion.postures[:, 0]).max())
    checked = world if world is not None else space.obstacle_world(extent)
    hit = pose_collision(checked, vehicle.footprint, path)
    if hit is not None:
        segment = hit[0]
        which = next(m for m in placed if m.first_posture <= segment < m.last_posture)
        x, y = path[segment, :2]
        return PlanResult.none(
            f'the {which.kind} manoeuvre meets an obstacle of the world near '
            f'({x:.3f}, {y:.3f}) m', search.evaluations, manoeuvres=tuple(placed))
    clearance = min(footprint_distance(checked, vehicle.footprint, p) for p in path)
    poses = space.to_map([[search.front, dx1, 0.0], [search.front + dy3, dx2, 0.0],
                          motion.postures[-1]])
    details = {'manoeuvres': tuple(placed), 'parking_manoeuvres': parked,
               'mode': search.mode.name, 'steering': mirror * motion.steering,
               'stops': stops, 'dx1': dx1, 'dx2': dx2, 'dy3': dy3,
               'positioning_point': poses[0], 'stop_point': poses[1], 'goal': poses[2],
               'min_clearance': clearance, 'space': space}
    return PlanResult(path=path, cost=float(sum(m.length for m in plan)),
                      expansions=search.evaluations, directions=motion.directions.copy(),
                      details=details)
