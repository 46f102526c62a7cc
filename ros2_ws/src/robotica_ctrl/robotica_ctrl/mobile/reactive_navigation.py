"""
Reactive navigation: the behaviours of §9.6 and §12.7 arbitrated into one command per step.

One :class:`ReactiveNavigator` turns the obstacle points of the range sensors (in
``base_link``, :mod:`robotica_ctrl.mobile.range_perception`) and the robot's pose into a
:class:`~robotica_ctrl.mobile.reactive.VelocityCommand`, with the laws of
:mod:`robotica_ctrl.mobile.reactive`. The ``behaviour``:

* ``wall_following`` (§9.6): law (9.93) on the line parallel to the wall on ``wall.side`` at
  ``wall.desired_distance`` (the manoeuvre "parallel line at a given distance"). Two more
  manoeuvres the book names: where the wall ends (no wall points beside the robot) the robot
  turns the outer corner around its end on a circle of the set distance, ω = ±v / d_ref;
  where a wall closes the way ahead (clearance below ``wall.desired_distance`` +
  ``corner_margin``) it turns the inner corner, away from the wall side at the largest rate.
* ``corridor_centring`` (§9.6): (9.93) on the centre line between the two walls; with one wall
  only, it follows that one at ``wall.desired_distance``; with none, straight on.
* ``vff`` (Borenstein & Koren, (12.9)-(12.15)) or ``potential`` (Krogh's generalised potential,
  (12.3)-(12.8)) towards ``goal``: an arbitration between goal seeking and avoidance. With no
  obstacle point within ``avoidance_distance`` the robot seeks the goal (ω proportional to the
  goal's bearing, full speed); otherwise the avoidance law of the behaviour steers. A local
  minimum (the trap where potential methods stall: the goal's distance decreased less than
  ``stall.min_progress`` over the last ``stall.window`` seconds) is detected and reported
  (:attr:`NavigatorOutput.state` ``stalled``); the command is then a stop: the method failed,
  and the report says so instead of letting the robot dither.

In every behaviour the speed is then modulated by the clearance ahead (:func:`speed_modulation`,
§9.6). Time comes in as an argument; the navigator holds only the stall detector's history.
"""
from collections import deque
from dataclasses import dataclass, fields
import math
from typing import Any, Mapping, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.range_perception import (clearance_ahead, nearest_distance,
                                                   side_wall, WallEstimate)
from robotica_ctrl.mobile.reactive import (corridor_centring, CorridorCentringParams,
                                           generalised_potential, GeneralisedPotentialParams,
                                           speed_modulation, SpeedModulationParams,
                                           VelocityCommand, virtual_force_field,
                                           VirtualForceFieldParams, wall_following,
                                           WallFollowingParams)
from robotica_kin.angles import wrap_to_pi
from robotica_kin.parameter_specs import parameter_values, ParameterSpec

__all__ = ['BEHAVIOURS', 'NAVIGATOR_PARAMETERS', 'NavigatorOutput', 'NavigatorParams',
           'ReactiveNavigator', 'navigator_params']

BEHAVIOURS = ('wall_following', 'corridor_centring', 'vff', 'potential')
_GROUPS = {'wall': WallFollowingParams, 'corridor': CorridorCentringParams,
           'vff': VirtualForceFieldParams, 'potential': GeneralisedPotentialParams,
           'speed': SpeedModulationParams}
_DESCRIPTIONS = {
    'desired_distance': 'Set distance to the wall [m], §9.6',
    'linear_velocity': 'Speed v [m/s]',
    'k_distance': 'k1 of (9.93) [1/m^2]',
    'k_angle': 'k2 of (9.93) [1/m]',
    'max_angular_velocity': 'Largest |angular velocity| [rad/s]',
    'repulsive_gain': 'Repulsion gain: F_cr of (12.9) (vff) [N m^2], scale of -grad P_i (12.8)'
                      ' (potential) [N m/s]',
    'attractive_gain': 'Constant goal pull F_ca (12.13) [N]',
    'window_radius': 'Obstacle points farther than this are ignored [m] (VFF active window)',
    'max_linear_velocity': 'V_max [m/s]',
    'k_heading': 'Angular velocity per radian of the resultant force bearing [1/s]',
    'goal_tolerance': 'Stop within this distance of the goal [m]',
    'max_deceleration': 'alpha of (12.3), the largest deceleration [m/s^2]',
    'safety_distance': 'Stop when the clearance ahead is at most this [m], §9.6',
    'slowdown_distance': 'Full speed when the clearance ahead is at least this [m], §9.6',
}


def _group_specs() -> dict[str, ParameterSpec]:
    specs = {}
    for group, kind in _GROUPS.items():
        for field in fields(kind):
            specs[f'{group}.{field.name}'] = ParameterSpec(
                float(getattr(kind(), field.name)), _DESCRIPTIONS[field.name], 1e-6, 1e6)
    return specs


NAVIGATOR_PARAMETERS: dict[str, ParameterSpec] = {
    'behaviour': ParameterSpec('wall_following', 'Reactive behaviour', choices=BEHAVIOURS),
    'wall.side': ParameterSpec('left', 'Side of the followed wall', choices=('left', 'right')),
    'wall.max_distance': ParameterSpec(
        1.5, 'Points farther sideways than this are not the wall [m]', 0.05, 50.0),
    'wall.reach': ParameterSpec(
        0.8, 'Points within this distance ahead and behind make the wall line [m]', 0.05, 50.0),
    'corner_margin': ParameterSpec(
        0.2, 'Turn an inner corner when the clearance ahead is below the set distance plus '
        'this [m]', 0.0, 10.0),
    'robot_radius': ParameterSpec(
        0.25, 'Half width of the lane ahead that counts as the way ahead [m]', 0.01, 10.0),
    'goal': ParameterSpec((0.0, 0.0), 'Goal (x, y) [m] in the pose frame (odom): vff and '
                          'potential', -1e6, 1e6),
    'avoidance_distance': ParameterSpec(
        1.0, 'vff, potential: seek the goal while no obstacle point is this close [m], else '
        'avoid', 0.0, 100.0),
    'k_goal': ParameterSpec(2.0, 'Goal seeking: angular velocity per radian of the goal '
                            'bearing [1/s]', 1e-6, 1e6),
    'stall.window': ParameterSpec(
        5.0, 'Local-minimum detection: the window of goal progress [s]', 0.1, 1e4),
    'stall.min_progress': ParameterSpec(
        0.05, 'Local-minimum detection: the goal must come this much closer per window [m]',
        0.0, 1e3),
    **_group_specs(),
}
"""The navigator's parameters: a node declares them, a plan checks a scenario against them."""


@dataclass(frozen=True)
class NavigatorParams:
    """All tunables of :class:`ReactiveNavigator`, validated (ValueError) when built."""

    behaviour: str
    side: str
    max_distance: float
    reach: float
    corner_margin: float
    robot_radius: float
    goal: tuple[float, float]
    avoidance_distance: float
    k_goal: float
    stall_window: float
    stall_min_progress: float
    wall: WallFollowingParams
    corridor: CorridorCentringParams
    vff: VirtualForceFieldParams
    potential: GeneralisedPotentialParams
    speed: SpeedModulationParams


def navigator_params(values: Mapping[str, Any]) -> NavigatorParams:
    """
    Return the navigator's tunables from parameter values by name (defaults for the others).

    Raises ParameterError (a ValueError naming the parameter) for a value out of its range,
    ValueError for values the laws refuse together (safety_distance >= slowdown_distance).

    >>> navigator_params({'behaviour': 'vff', 'goal': [4.0, 1.0]}).goal
    (4.0, 1.0)
    """
    v = parameter_values(NAVIGATOR_PARAMETERS, values)
    goal = tuple(float(x) for x in v['goal'])
    if len(goal) != 2:
        raise ValueError(f'goal must be [x, y], got {v["goal"]!r}')
    groups = {group: kind(**{f.name: v[f'{group}.{f.name}'] for f in fields(kind)})
              for group, kind in _GROUPS.items()}
    return NavigatorParams(
        v['behaviour'], v['wall.side'], v['wall.max_distance'], v['wall.reach'],
        v['corner_margin'], v['robot_radius'], (goal[0], goal[1]), v['avoidance_distance'],
        v['k_goal'], v['stall.window'], v['stall.min_progress'], **groups)


@dataclass(frozen=True)
class NavigatorOutput:
    """One step's command and what the navigator is doing."""

    command: VelocityCommand
    state: str              # following, outer_corner, inner_corner, centring, goal_seeking,
    #                         avoiding, goal_reached, stalled, no_wall
    clearance: float        # [m] ahead (inf: none seen)
    goal_distance: float    # [m] (nan for the wall behaviours)


class ReactiveNavigator:
    """The behaviours of §9.6/§12.7 with their arbitration; call :meth:`update` every step."""

    def __init__(self, params: NavigatorParams) -> None:
        self.params = params
        self._progress: deque[tuple[float, float]] = deque()   # (t [s], goal distance [m])

    def reset(self) -> None:
        """Forget the stall detector's history (a new goal, a restarted run)."""
        self._progress.clear()

    def update(self, t: float, pose: ArrayLike, points: NDArray[np.float64]) -> NavigatorOutput:
        """
        Return the command for the pose (x, y, θ) [m, rad] in odom and the obstacle points.

        ``points`` (N, 2) [m] in ``base_link``; ``t`` [s] the time of the pose. Raises
        ValueError for a non-finite pose or points.
        """
        pose = np.asarray(pose, dtype=np.float64)
        if pose.shape != (3,) or not np.all(np.isfinite(pose)) \
                or not np.all(np.isfinite(points)):
            raise ValueError('the pose and the obstacle points must be finite')
        p = self.params
        clearance = clearance_ahead(points, p.robot_radius)
        if p.behaviour in ('vff', 'potential'):
            command, state, goal_distance = self._to_goal(t, pose, points)
        else:
            command, state = self._along_walls(points, clearance)
            goal_distance = math.nan
        if state not in ('goal_reached', 'stalled'):
            command = VelocityCommand(speed_modulation(command.linear, clearance, p.speed),
                                      command.angular)
        return NavigatorOutput(command, state, clearance, goal_distance)

    def _along_walls(self, points: NDArray[np.float64], clearance: float
                     ) -> tuple[VelocityCommand, str]:
        p = self.params
        sign = 1.0 if p.side == 'left' else -1.0
        v = p.wall.linear_velocity
        if clearance < p.wall.desired_distance + p.corner_margin:   # a wall across the way
            return VelocityCommand(v, -sign * p.wall.max_angular_velocity), 'inner_corner'
        walls = {side: _usable(side_wall(points, side, p.max_distance, p.reach))
                 for side in ('left', 'right')}
        if p.behaviour == 'corridor_centring' and walls['left'] and walls['right']:
            left, right = walls['left'], walls['right']
            return corridor_centring(left.distance, right.distance,
                                     0.5 * (left.angle + right.angle), p.corridor), 'centring'
        side = p.side if p.behaviour == 'wall_following' else next(
            (s for s, w in walls.items() if w), p.side)
        wall = walls[side]
        if wall is None:
            if p.behaviour == 'corridor_centring':
                return VelocityCommand(p.corridor.linear_velocity, 0.0), 'no_wall'
            # The wall ended: round its end on a circle of the set distance.
            return VelocityCommand(v, sign * v / p.wall.desired_distance), 'outer_corner'
        return wall_following(wall.distance, wall.angle, side, p.wall), 'following'

    def _to_goal(self, t: float, pose: NDArray[np.float64], points: NDArray[np.float64]
                 ) -> tuple[VelocityCommand, str, float]:
        p = self.params
        dx, dy = p.goal[0] - pose[0], p.goal[1] - pose[1]
        c, s = math.cos(pose[2]), math.sin(pose[2])
        goal = np.array([c * dx + s * dy, -s * dx + c * dy])    # in base_link
        distance = float(np.hypot(dx, dy))
        tolerance = p.vff.goal_tolerance if p.behaviour == 'vff' else p.potential.goal_tolerance
        if distance <= tolerance:
            return VelocityCommand(0.0, 0.0), 'goal_reached', distance
        if self._stalled(t, distance):
            return VelocityCommand(0.0, 0.0), 'stalled', distance
        if nearest_distance(points) > p.avoidance_distance:
            bearing = math.atan2(goal[1], goal[0])
            limit = p.vff.max_angular_velocity
            speed = p.vff.max_linear_velocity if p.behaviour == 'vff' \
                else p.potential.max_linear_velocity
            return (VelocityCommand(speed * max(math.cos(bearing), 0.0),
                                    max(-limit, min(limit, p.k_goal * bearing))),
                    'goal_seeking', distance)
        if p.behaviour == 'vff':
            return virtual_force_field(points, goal, p.vff), 'avoiding', distance
        return (generalised_potential(points, goal, p.potential.max_linear_velocity,
                                      p.potential), 'avoiding', distance)

    def _stalled(self, t: float, distance: float) -> bool:
        """Return whether the goal came closer by less than stall.min_progress in a window."""
        history = self._progress
        if history and t < history[-1][0]:   # the time went back: a new run
            history.clear()
        history.append((t, distance))
        while len(history) > 1 and history[1][0] <= t - self.params.stall_window:
            history.popleft()
        first_t, first_distance = history[0]
        return (t - first_t >= self.params.stall_window
                and first_distance - distance < self.params.stall_min_progress)


def _usable(wall: Optional[WallEstimate]) -> Optional[WallEstimate]:
    """Return the wall if it runs along the robot (not across the way), else None."""
    return wall if wall is not None and abs(wrap_to_pi(wall.angle)) < 0.45 * math.pi else None
