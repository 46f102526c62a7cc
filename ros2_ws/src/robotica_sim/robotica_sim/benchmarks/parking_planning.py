"""
Issue 21: how long the course's parallel-parking planner takes (seed catalogue Part 14).

The parking part of ``robotica bench planning`` (its grid A* part is
:mod:`robotica_sim.benchmarks.planning`). The scene is the canonical one of the parking tests,
written here: the default car (:class:`~robotica_ctrl.planning.parking.ParkingVehicle`, a1 3.6,
b1 0.9, h1 2.6, c1 1.7 m, θ_dmax 0.6 rad), a right-hand space in the frame of the map
(origin (0, 0, 0): the parked obstacles' sides on y = 0, the space 0 ≤ x ≤ H below them) of
depth J = :data:`DEPTH` and margin MS = :data:`MARGIN`, so H' = H − 2 MS; the spaces of
:data:`RATIOS` (H' = 1.2, 1.5 and 2.0 (a1 + b1)) and P_f's start :data:`START` on the pass.
Three things are timed per space:

- ``plan_parallel_parking``: :func:`robotica_ctrl.planning.parking.plan_parallel_parking`
  from :data:`START`, in both execution modes (geometric: stop and re-orient the wheels
  between arcs; progressive steering), with the planner's defaults (30 manoeuvres at most)
  and the space's own obstacles as the world;
- ``ParkingSearch``: what the planner node's parking mode runs,
  :class:`robotica_ctrl.planning.parking.parking_search.ParkingSearch`: a pass started at the
  first pose of :func:`side_pass`, fed its readings one by one (each ``add_reading`` runs the
  detection on the pass so far) until a space is taken, then ``plan`` into the detected space
  from that sample's pose, in both modes; the time is the readings fed and the plan;
- ``detect_spaces``: :func:`robotica_ctrl.planning.parking.detect_spaces` on the whole pass of
  :data:`PASS_READINGS` readings (one call).

The pass (:func:`side_pass`): P_f along y = 1.4 m (the start's dx2) with heading 0, a reading
every :data:`READING_SPACING` m, the side sonar at :data:`SENSOR_POSE` in ``base_link`` (the
front-right corner, looking right) cast against the space's obstacles
(:meth:`~robotica_ctrl.planning.parking.ParkingSpace.obstacle_world`) with
:func:`robotica_kin.world.raycast.cast_rays` (one ray per reading, no noise), from the sensor
3 m before the space to 11.95 m past its rear end (past the front end of every space here).

Per case: found or the reason ("no path" is a row, never an exception), the parking
manoeuvres (``details['parking_manoeuvres']``), the path's poses, its cost (length driven
[m]), the candidate manoeuvres evaluated (``plan.expansions``), and the minimum and median
wall-clock time (``time.perf_counter``) over ``repeats`` runs, the garbage collector run before
each round (untimed), the calls of one space taking turns run by run as in the grid part.
"""
import dataclasses
from dataclasses import dataclass
from functools import partial
import math
from typing import Any, Callable, Optional, Sequence

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.planning.parking import (detect_spaces, ParkingParams, ParkingSpace,
                                            ParkingVehicle, plan_parallel_parking)
from robotica_ctrl.planning.parking.parking_search import ParkingSearch
from robotica_ctrl.planning.plan_result import PlanResult
from robotica_kin.world.raycast import cast_rays
from robotica_sim.benchmarks.planning import alternate_runs, format_ms, Progress, REPEATS

__all__ = ['DEPTH', 'MARGIN', 'MODES', 'PASS_READINGS', 'ParkingRow', 'RATIOS',
           'READING_SPACING', 'SENSOR_POSE', 'START', 'format_parking_table',
           'parking_benchmark', 'parking_rows_json', 'parking_space', 'side_pass']

RATIOS = (1.2, 1.5, 2.0)              # H' / (a1 + b1) of the spaces
MODES = ('geometric', 'progressive')  # the planner's execution modes
MARGIN = 0.2                          # MS [m]
DEPTH = 2.2                           # J [m]
START = (0.0, 1.4, 0.0)               # P_f (x [m], y [m], θ [rad]) on the pass, map frame
PASS_READINGS = 300                   # side readings of the pass
READING_SPACING = 0.05                # [m] driven between readings
SENSOR_POSE = (3.4, -0.85, -0.5 * math.pi)   # side sonar (x, y [m], yaw [rad]) in base_link
RANGE_MIN, RANGE_MAX = 0.15, 5.0      # [m] the sonar's limits
PASS_LEAD = 3.0                       # [m] the sensor's first reading before the space


@dataclass(frozen=True)
class ParkingRow:
    """One timed call on one space (module docstring)."""

    method: str                          # plan_parallel_parking, ParkingSearch, detect_spaces
    ratio: float                         # H' / (a1 + b1)
    space_length: float                  # H [m] of the scene
    mode: Optional[str]                  # execution mode; None for the detection
    found: bool                          # a plan (a space, for the detection)
    reason: str                          # why not, or ''
    parking_manoeuvres: Optional[int]    # backward and forward manoeuvres of the plan
    poses: Optional[int]                 # postures of the path
    cost: Optional[float]                # [m] length driven
    expansions: Optional[int]            # candidate manoeuvres evaluated
    min_ms: float                        # [ms] per call, fastest of the repeats
    median_ms: float                     # [ms] per call, median of the repeats
    repeats: int
    note: str


def parking_space(ratio: float, vehicle: ParkingVehicle = ParkingVehicle()) -> ParkingSpace:
    """
    Return the scene's space with H' = ``ratio`` (a1 + b1), J = :data:`DEPTH`, at the origin.

    >>> round(parking_space(1.5).length, 2), parking_space(1.5).side
    (7.15, 'right')
    """
    if not (math.isfinite(ratio) and ratio > 0.0):
        raise ValueError(f'ratio must be finite and > 0, got {ratio!r}')
    return ParkingSpace((0.0, 0.0, 0.0), length=ratio * vehicle.length + 2 * MARGIN,
                        depth=DEPTH, margin=MARGIN)


def side_pass(space: ParkingSpace, readings: int = PASS_READINGS
              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the pass beside ``space``: P_f's poses (k, 3) and the side sonar's ranges (k,) [m].

    A space frame on the map's axes is assumed (the scene's). Ranges beyond
    ``RANGE_MAX`` are +inf (no echo, REP-117).

    >>> poses, ranges = side_pass(parking_space(1.5))
    >>> poses.shape, float(ranges[0]), float(ranges[150])   # a car's side; the curb
    ((300, 3), 0.55, 2.75)
    """
    x = START[0] - SENSOR_POSE[0] - PASS_LEAD + READING_SPACING * np.arange(readings)
    poses = np.column_stack([x, np.full_like(x, START[1]), np.full_like(x, START[2])])
    sensor = poses[:, :2] + [SENSOR_POSE[0], SENSOR_POSE[1]]
    world = space.obstacle_world(extent=20.0)
    hits = cast_rays(world, sensor, np.full(readings, START[2] + SENSOR_POSE[2]), RANGE_MAX)
    return poses, np.round(hits.ranges, 12)


def _plan_row(method: str, ratio: float, space: ParkingSpace, mode: str,
              times: list[float], plan: PlanResult, note: str) -> ParkingRow:
    return ParkingRow(
        method, ratio, space.length, mode, plan.found, plan.reason,
        plan.details.get('parking_manoeuvres') if plan.found else None,
        None if plan.path is None else len(plan.path),
        plan.cost if plan.found else None, plan.expansions,
        1e3 * min(times), 1e3 * float(np.median(times)), len(times), note)


def _search(vehicle: ParkingVehicle, mode: str, poses: NDArray[np.float64],
            ranges: NDArray[np.float64]) -> tuple[PlanResult, int, Optional[ParkingSpace]]:
    """Run the parking mode's search on the pass: (plan, readings fed, space taken)."""
    search = ParkingSearch(vehicle, SENSOR_POSE, planning=ParkingParams(mode=mode))
    search.start(poses[0])
    for k, (pose, reading) in enumerate(zip(poses, ranges)):
        taken = search.add_reading(pose, float(reading), RANGE_MIN, RANGE_MAX)
        if taken is not None:
            return search.plan(taken), k + 1, taken.space
    return PlanResult.none(f'no space taken in {len(ranges)} readings'), len(ranges), None


def _space_case(ratio: float, vehicle: ParkingVehicle, repeats: int,
                progress: Progress) -> list[ParkingRow]:
    space = parking_space(ratio, vehicle)
    poses, ranges = side_pass(space)
    label = f"parking: H' = {ratio:.1f} (a1 + b1), H = {space.length:.2f} m"
    progress(f'planning: {label}: plan_parallel_parking and ParkingSearch, '
             f'{" and ".join(MODES)}, and detect_spaces')
    calls: list[Callable[[], Any]] = []
    for mode in MODES:
        params = ParkingParams(mode=mode)
        calls.append(partial(plan_parallel_parking, space, vehicle, START, params))
        calls.append(partial(_search, vehicle, mode, poses, ranges))
    calls.append(lambda: detect_spaces(poses, ranges, SENSOR_POSE, RANGE_MIN, RANGE_MAX))
    timed = alternate_runs(calls, repeats)
    rows = []
    for k, mode in enumerate(MODES):
        times, plan = timed[2 * k]
        rows.append(_plan_row('plan_parallel_parking', ratio, space, mode, times, plan,
                              f"from {START}; the scene's space and obstacles"))
        times, (plan, fed, taken) = timed[2 * k + 1]
        seen = '' if taken is None else (f'; detected H = {taken.length:.3f} m, '
                                         f'J = {taken.depth:.3f} m')
        rows.append(_plan_row('ParkingSearch', ratio, space, mode, times, plan,
                              f'{fed} readings fed, then the plan{seen}'))
    times, spaces = timed[-1]
    detected = ', '.join(f'H = {d.space.length:.3f} m, J = {d.space.depth:.3f} m'
                         for d in spaces)
    rows.append(ParkingRow('detect_spaces', ratio, space.length, None, bool(spaces),
                           '' if spaces else 'no space detected', None, None, None, None,
                           1e3 * min(times), 1e3 * float(np.median(times)), len(times),
                           f'{len(ranges)} readings, one call; {len(spaces)} space(s): '
                           f'{detected}'))
    return rows


def parking_benchmark(ratios: Sequence[float] = RATIOS, repeats: int = REPEATS,
                      progress: Progress = lambda message: None) -> list[ParkingRow]:
    """
    Return the rows of the parking benchmark: every method on every space (module docstring).

    A plan that is not found is a row with its reason (at H' = 1.2 (a1 + b1) the planner
    hits its bound of manoeuvres), not an error.
    """
    if not (isinstance(repeats, int) and repeats >= 1):
        raise ValueError(f'repeats must be an integer >= 1, got {repeats!r}')
    vehicle = ParkingVehicle()
    rows: list[ParkingRow] = []
    for ratio in ratios:
        rows += _space_case(float(ratio), vehicle, repeats, progress)
    return rows


def format_parking_table(rows: Sequence[ParkingRow]) -> str:
    """Return the rows as a Markdown table (times in ms per call)."""
    lines = ["| H' / (a1 + b1) | H [m] | method | mode | found (or why not) | manoeuvres "
             '| path poses | cost [m] | evaluated | min [ms] | median [ms] | runs | note |',
             '|---:|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|']

    def cell(value: Any, fmt: str = '') -> str:
        return '' if value is None else format(value, fmt)

    for r in rows:
        found = 'yes' if r.found else f'no: {r.reason}'
        lines.append(f'| {r.ratio:.1f} | {r.space_length:.2f} | {r.method} | {r.mode or ""} '
                     f'| {found} | {cell(r.parking_manoeuvres)} | {cell(r.poses)} '
                     f'| {cell(r.cost, ".2f")} | {cell(r.expansions)} | {format_ms(r.min_ms)} '
                     f'| {format_ms(r.median_ms)} | {r.repeats} | {r.note} |')
    return '\n'.join(lines)


def parking_rows_json(rows: Sequence[ParkingRow]) -> list[dict[str, Any]]:
    """Return the rows as JSON-ready dicts."""
    return [dataclasses.asdict(row) for row in rows]
