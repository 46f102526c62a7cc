"""
Potential-field planners: Krogh's generalised potential and VFF, integrated from the start (§12.7).

The book's planning loop for potential methods: each obstacle pushes the robot away from it,
the goal pulls it; compute the resultant R, move under it, repeat. Here the forces and the
command they give are the reactive laws of :mod:`robotica_ctrl.mobile.reactive`, unchanged:

* the generalised potential (Krogh 1984, (12.3)-(12.8), :func:`generalised_potential`): the
  obstacle points are the closest point of each obstacle within ``sensing_range`` (each wall,
  polygon and circle, moved towards the robot by the world's inflation; each occupied cell of
  a grid, its centre), and v the law's ``max_linear_velocity``, the speed the robot travels
  at (as the reactive navigator does: with the speed of the step before, a stop would switch
  the repulsion off at the next step, and the robot would creep into the obstacle);
* the Virtual Force Field (Borenstein and Koren 1989, (12.9)-(12.15),
  :func:`virtual_force_field`): the points are the occupied cells of the certainty grid within
  the active window, the world's grid or its geometry drawn at ``cell_size``
  (:func:`robotica_kin.world.rasterise.world_grid`).

The robot is a unicycle from ``start`` (x, y [m], θ [rad]; θ towards the goal when only (x, y)
is given): each step of ``step`` seconds moves it on the exact arc of the command (v, ω)
(:func:`robotica_kin.mobile.unicycle.arc_update`, book (4.93)). A disc of ``robot_radius``
that would touch an obstacle on the way ends the plan (:func:`robotica_kin.world.swept_collision`),
with the reason: a potential method guarantees no clearance.

Potential methods have local minima, where the pushes balance the pull (the U-shaped trap of
``scenarios/potential_trap.yaml``). Two tests find them and the plan reports the trap, with
its position, as its reason (``details['trap']``), never a path that pretends: the robot stands
still (|v| and |ω| below ``min_speed`` and ``min_turn``: the resultant has vanished or points
back) away from the goal, or the goal came less than ``min_progress`` closer over the last
``stall_steps`` steps (the robot dithers or circles). Work: the steps, counted as expansions
against the :class:`~.plan_result.SearchBudget`.
"""

from dataclasses import dataclass, replace
import math
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.reactive import (generalised_potential, GeneralisedPotentialParams,
                                           VelocityCommand, virtual_force_field,
                                           VirtualForceFieldParams)
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.search_setup import BudgetMeter, Clock, IN_OBSTACLE, planar_point
from robotica_kin.mobile.unicycle import arc_update
from robotica_kin.world import distance_to_obstacles, footprint_distance, swept_collision, World
from robotica_kin.world.rasterise import world_grid

__all__ = ['LawParams', 'PotentialPlannerParams', 'potential_planner']

LawParams = Union[GeneralisedPotentialParams, VirtualForceFieldParams]
"""The law a planner integrates, chosen by its tunables' type."""

_CLOCK_EVERY = 64   # steps between two readings of the clock


@dataclass(frozen=True)
class PotentialPlannerParams:
    """
    Tunables of :func:`potential_planner` (the law's own are its params).

    Examples
    --------
    >>> PotentialPlannerParams().stall_steps
    50

    """

    step: float = 0.1               # Δt [s] of one integration step
    robot_radius: float = 0.2       # r [m] of the disc that must not touch an obstacle
    sensing_range: float = 3.0      # [m] generalised potential: obstacles farther are ignored
    cell_size: float = 0.1          # [m] VFF: the certainty grid's cells (geometric worlds)
    stall_steps: int = 50           # N: the window of the progress test [steps]
    min_progress: float = 0.05      # [m] the goal must come this much closer over N steps
    min_speed: float = 1e-3         # [m/s] below this and min_turn: standing still
    min_turn: float = 1e-3          # [rad/s]
    field_step: float = 0.0         # [m] lattice of details['field']; 0: none

    def __post_init__(self) -> None:
        for name in ('step', 'robot_radius', 'sensing_range', 'cell_size', 'min_progress',
                     'min_speed', 'min_turn'):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        if not (isinstance(self.stall_steps, int) and self.stall_steps >= 2):
            raise ValueError(f'stall_steps must be an integer >= 2, got {self.stall_steps!r}')
        if not (math.isfinite(self.field_step) and self.field_step >= 0.0):
            raise ValueError(f'field_step must be >= 0 m, got {self.field_step!r}')


class _Sensing:
    """The obstacle points a law sees from a position, in the map frame."""

    def __init__(self, world: World, law: LawParams, params: PotentialPlannerParams) -> None:
        self.world = world
        self.vff = isinstance(law, VirtualForceFieldParams)
        if self.vff:
            assert isinstance(law, VirtualForceFieldParams)
            self.reach = law.window_radius
            empty = not (len(world.segments) or len(world.circles) or world.grid is not None)
            grid = None if empty else world_grid(world, params.cell_size, law.window_radius)
            self.cells = grid.occupied_centres if grid is not None else np.zeros((0, 2))
            self.tree = grid.occupied_tree if grid is not None and len(self.cells) else None
            return
        self.reach = params.sensing_range
        segments = world.segments
        self.a, self.e = segments[:, 0:2], segments[:, 2:4] - segments[:, 0:2]
        # The obstacle of each segment (world.segments: the walls, then each polygon's edges):
        # a wall is one, a polygon another, whose nearest edge gives its closest point.
        group = list(range(len(world.walls)))
        for k, polygon in enumerate(world.polygons):
            group.extend([len(world.walls) + k] * len(polygon))
        self.group = np.array(group, dtype=np.intp)
        grid = world.grid
        self.cells = grid.occupied_centres if grid is not None else np.zeros((0, 2))
        self.tree = grid.occupied_tree if grid is not None and len(self.cells) else None

    def points(self, p: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the obstacle points that act on a robot at p: (k, 2) [m], map frame."""
        found = []
        if self.tree is not None:
            found.append(self.cells[self.tree.query_ball_point(p, self.reach)])
        if not self.vff:
            found.append(self._closest(p))
        return np.vstack(found) if found else np.zeros((0, 2))

    def _closest(self, p: NDArray[np.float64]) -> NDArray[np.float64]:
        world = self.world
        nearest = []
        if len(self.a):
            t = np.clip(((p - self.a) * self.e).sum(axis=1)
                        / np.maximum((self.e * self.e).sum(axis=1), 1e-300), 0.0, 1.0)
            q = self.a + t[:, None] * self.e
            d = np.hypot(*(q - p).T)
            best = np.full(self.group.max() + 1, np.inf)
            np.minimum.at(best, self.group, d)
            winner = (d == best[self.group])
            _, first = np.unique(self.group[winner], return_index=True)
            nearest.append(q[np.flatnonzero(winner)[first]])
        if len(world.circles):
            c, rho = world.circles[:, 0:2], world.circles[:, 2]
            u = p - c
            nearest.append(c + (rho / np.maximum(np.hypot(*u.T), 1e-300))[:, None] * u)
        if not nearest:
            return np.zeros((0, 2))
        q = np.vstack(nearest)
        u = p - q
        d = np.hypot(*u.T)
        q = q + (np.minimum(world.inflation, d) / np.maximum(d, 1e-300))[:, None] * u
        return q[np.hypot(*(q - p).T) <= self.reach]


def _command(law: LawParams, sensing: _Sensing, pose: NDArray[np.float64],
             goal: NDArray[np.float64], speed: float) -> VelocityCommand:
    """Return the law's command at ``pose`` (its points and the goal put in base_link)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    to_base = np.array([[c, s], [-s, c]])
    points = (sensing.points(pose[:2]) - pose[:2]) @ to_base.T
    points = points[np.hypot(*points.T) > 0.0]
    goal_base = to_base @ (goal - pose[:2])
    if isinstance(law, VirtualForceFieldParams):
        return virtual_force_field(points, goal_base, law)
    return generalised_potential(points, goal_base, speed, law)


def _field(world: World, law: LawParams, sensing: _Sensing, goal: NDArray[np.float64],
           params: PotentialPlannerParams, low: NDArray[np.float64],
           high: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return (k, 3) rows (x, y, direction of R [rad]) on a lattice; nan where R is nil."""
    steer = replace(law, k_heading=1.0, max_angular_velocity=2.0 * math.pi)
    xs = np.arange(low[0], high[0] + 1e-9, params.field_step)
    ys = np.arange(low[1], high[1] + 1e-9, params.field_step)
    lattice = np.array([(x, y) for y in ys for x in xs])
    free = distance_to_obstacles(world, lattice) > 0.0
    rows = []
    for x, y in lattice[free]:
        heading = math.atan2(goal[1] - y, goal[0] - x)
        command = _command(steer, sensing, np.array([x, y, heading]), goal,
                           law.max_linear_velocity)
        still = command.linear == 0.0 and command.angular == 0.0
        rows.append((x, y, math.nan if still else heading + command.angular))
    return np.array(rows).reshape(-1, 3)


def potential_planner(world: World, start: ArrayLike, goal: ArrayLike,
                      law: LawParams = GeneralisedPotentialParams(),
                      params: PotentialPlannerParams = PotentialPlannerParams(),
                      budget: SearchBudget = SearchBudget(max_expansions=20000),
                      clock: Optional[Clock] = None) -> PlanResult:
    """
    Return the path of a unicycle moved by a potential-field law from start to goal (§12.7).

    Parameters
    ----------
    world : World
        Walls, polygons, circles and/or a grid, map frame.
    start : array_like, shape (2,) or (3,)
        (x, y) [m] or (x, y [m], θ [rad]), map frame; without θ the robot faces the goal.
    goal : array_like, shape (2,)
        (x, y) [m], map frame.
    law : GeneralisedPotentialParams or VirtualForceFieldParams
        The law and its gains: Krogh's generalised potential (12.3)-(12.8) or VFF
        (12.9)-(12.15); its ``goal_tolerance`` is when the goal is reached.
    params : PotentialPlannerParams
        Integration step, robot radius, the sensing of each law, the trap tests.
    budget : SearchBudget
        At most ``max_expansions`` steps (20000 by default) and ``max_seconds`` by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only the steps are bounded.

    Returns
    -------
    PlanResult
        ``path`` (k, 2) [m] the positions from the start to the goal (its last point; the
        last pose, within the law's ``goal_tolerance``, if the last bit is blocked) and
        ``cost`` its length [m]; or none with the reason: the start in collision, the goal in
        an obstacle (within r), a collision on the way, a local minimum (trapped at (x, y)),
        the budget exhausted. ``details``: ``poses`` (k, 3) [m, rad] and ``commands`` (k - 1, 2)
        [m/s, rad/s] of the run, ``trap`` (2,) [m] or None, ``law`` ('potential' or 'vff'),
        ``field`` (f, 3) [m, m, rad] when ``params.field_step`` > 0.

    Raises
    ------
    ValueError
        For a non-finite start or goal, or a law that is neither of the two.

    Examples
    --------
    >>> plan = potential_planner(World(circles=[[2.0, 0.6, 0.3]]), [0.0, 0.0], [4.0, 0.0])
    >>> plan.found, bool(np.hypot(*(plan.path[-1] - [4.0, 0.0])) < 1e-9)
    (True, True)

    """
    if not isinstance(law, (GeneralisedPotentialParams, VirtualForceFieldParams)):
        raise ValueError('law must be GeneralisedPotentialParams or VirtualForceFieldParams, '
                         f'got {type(law).__name__}')
    if not isinstance(params, PotentialPlannerParams):
        raise ValueError(f'params must be PotentialPlannerParams, got {type(params).__name__}')
    target = planar_point('goal', goal)
    pose = _start_pose(start, target)
    meter = BudgetMeter(budget, clock)
    name = 'VFF' if isinstance(law, VirtualForceFieldParams) else 'generalised potential'
    r = params.robot_radius
    details: dict[str, Any] = {'law': 'vff' if name == 'VFF' else 'potential', 'trap': None}
    if footprint_distance(world, r, pose) <= 0.0:
        return PlanResult.none(f'{IN_OBSTACLE["start"]}: a disc of {r:g} m at ({pose[0]:g}, '
                               f'{pose[1]:g}) m touches an obstacle', **details)
    if distance_to_obstacles(world, target[None, :])[0] <= r:
        return PlanResult.none(f'{IN_OBSTACLE["goal"]}: a disc of {r:g} m at ({target[0]:g}, '
                               f'{target[1]:g}) m touches an obstacle', **details)
    sensing = _Sensing(world, law, params)
    if params.field_step > 0.0:
        corners = np.vstack([pose[None, :2], target[None, :]])
        details['field'] = _field(world, law, sensing, target, params,
                                  corners.min(axis=0) - sensing.reach,
                                  corners.max(axis=0) + sensing.reach)
    return _integrate(world, law, sensing, pose, target, params, meter, name, details)


def _start_pose(start: ArrayLike, goal: NDArray[np.float64]) -> NDArray[np.float64]:
    value = np.asarray(start, dtype=np.float64)
    if value.shape == (3,) and np.isfinite(value).all():
        return value
    p = planar_point('start', start)
    return np.array([p[0], p[1], math.atan2(goal[1] - p[1], goal[0] - p[0])])


def _integrate(world: World, law: LawParams, sensing: _Sensing, pose: NDArray[np.float64],
               goal: NDArray[np.float64], params: PotentialPlannerParams, meter: BudgetMeter,
               name: str, details: dict[str, Any]) -> PlanResult:
    """Move the unicycle under the law until the goal, a trap, a collision or the budget."""
    poses = [pose]
    commands: list[tuple[float, float]] = []
    distances = [float(np.hypot(*(goal - pose[:2])))]
    reason = ''
    while distances[-1] > law.goal_tolerance:
        steps = len(commands)
        if steps >= meter.budget.max_expansions or (meter.clock is not None
                                                    and not steps % _CLOCK_EVERY):
            reason = meter.exhausted(steps)
            if reason:
                break
        command = _command(law, sensing, pose, goal, law.max_linear_velocity)
        if abs(command.linear) < params.min_speed and abs(command.angular) < params.min_turn:
            reason = _trap(name, pose, distances, 'it stands still: the forces balance')
            break
        after = arc_update(pose, command.linear, command.angular, params.step)
        contact = swept_collision(world, params.robot_radius, pose, after)
        if contact is not None:
            at = pose[:2] + contact * (after[:2] - pose[:2])
            reason = (f'collision: the {name} drives a disc of {params.robot_radius:g} m into '
                      f'an obstacle at ({at[0]:.3f}, {at[1]:.3f}) m after {steps + 1} steps')
            break
        pose = after
        poses.append(pose)
        commands.append((command.linear, command.angular))
        distances.append(float(np.hypot(*(goal - pose[:2]))))
        window = params.stall_steps
        if len(distances) > window and distances[-1 - window] - distances[-1] < \
                params.min_progress:
            reason = _trap(name, pose, distances, f'the goal came '
                           f'{distances[-1 - window] - distances[-1]:.3g} m closer in the last '
                           f'{window} steps, less than {params.min_progress:g} m')
            break
    path_poses = np.array(poses)
    details.update(poses=path_poses, commands=np.array(commands).reshape(-1, 2))
    if reason:
        if reason.startswith('local minimum'):
            details['trap'] = path_poses[-1, :2].copy()
        return PlanResult.none(reason, len(commands), **details)
    path = path_poses[:, :2]
    if np.hypot(*(goal - path[-1])) > 0.0 and swept_collision(
            world, params.robot_radius, [*path[-1], 0.0], [*goal, 0.0]) is None:
        path = np.vstack([path, goal])
    return PlanResult(path, float(np.hypot(*np.diff(path, axis=0).T).sum()),
                      expansions=len(commands), details=details)


def _trap(name: str, pose: NDArray[np.float64], distances: list[float], why: str) -> str:
    return (f'local minimum of the {name}: trapped at ({pose[0]:.3f}, {pose[1]:.3f}) m, '
            f'{distances[-1]:.3f} m from the goal ({why})')
