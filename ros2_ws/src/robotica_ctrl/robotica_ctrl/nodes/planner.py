"""
Planner node: a path from the robot to a goal on the world model, for a tracker (book ch. 12).

The world is the scenario's (``world_file``: a YAML with a ``world:`` section or a map_server
map) or, without one, the latest ``/map`` (nav_msgs/OccupancyGrid, transient local: the world
publisher's or a mapping node's). The start is the robot's pose (``odom``, nav_msgs/Odometry:
remap it to ``ground_truth/odom`` for the simulator's truth), or ``start`` before any pose
arrives; the goal is ``goal`` or the latest ``goal_pose`` (geometry_msgs/PoseStamped, in the
map frame, as RViz's and Foxglove's goal tools send it).

It plans with :func:`robotica_ctrl.planning.planners.plan_path` (``method`` and the options of
its :data:`~robotica_ctrl.planning.planners.PLANNER_PARAMETERS`) when it has a world, a start
and a goal, and again when the goal changes or a new map blocks the path it follows. Out:
``plan`` (nav_msgs/Path, transient local: a tracker's ``~/path``), empty when there is no path
so that the tracker stops; ``~/status`` (robotica_msgs/PlanStatus, transient local: found or
the reason, cost, expansions, whether the search's bound was hit, the time it took) and
``~/markers`` (visualization_msgs/MarkerArray: the path, the cells A* expanded, the visibility
graph or the Voronoi roadmap, the direction of a potential method's force on a lattice of
``field_step``, the trap it stalled in, start and goal).
Every search is bounded (``max_expansions``, ``max_seconds``): a plan never hangs the node.

With ``method`` = ``parking`` it runs the course's parallel parking instead
(:mod:`robotica_ctrl.nodes.parking_mode`): a straight pass from the pose (at the first pose with
``parking.autostart``, else when the ``park`` service, std_srvs/Trigger, is called), the space
detected from a side range sensor (``side_range``, sensor_msgs/Range) and the manoeuvres into it
published on ``plan`` as postures whose orientations are the vehicle's headings (a tracker that
reverses follows them: ``reversing_pure_pursuit``); the vehicle, the sensor's mount and the
detection thresholds are the ``parking.*`` parameters.
"""
import time
from typing import Any

from geometry_msgs.msg import Point, Pose, PoseStamped
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry, Path
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_ctrl.nodes.parking_mode import ParkingMode
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.planners import plan_path, planner_options, PLANNER_PARAMETERS
from robotica_kin.bounds import bounded_array, MAX_POSITION
from robotica_kin.ros.convert import (path_message, pose2d_from_odometry, quaternion_to_yaw,
                                      yaw_to_quaternion)
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.grid_messages import grid_from_message
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import COMMAND_QOS, LATCHED_QOS, STREAM_SUB_QOS
from robotica_kin.world.queries import swept_collision
from robotica_kin.world.shapes import World
from robotica_kin.world.world_file import load_world_file
from robotica_msgs.msg import PlanStatus
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

MAX_EXPANDED_MARKERS = 20_000
"""At most this many expanded cells are drawn (evenly spaced): a marker stays small."""


def _pose(x: float, y: float, yaw: float = 0.0) -> Pose:
    pose = Pose()
    pose.position.x, pose.position.y = float(x), float(y)
    pose.orientation = yaw_to_quaternion(float(yaw))
    return pose


class PlannerNode(GuardedNode):
    """Plan on the world model and publish the path, its status and its markers."""

    def __init__(self) -> None:
        super().__init__('planner')
        self._options = planner_options(declare_specs(
            self, PLANNER_PARAMETERS))   # the choices and ranges rclpy does not check
        self._frame = declare(self, 'frame_id', 'map', 'Frame of the map, the path and goals',
                              read_only=True)
        path = declare(self, 'world_file', '', 'The world: a YAML with a world: section (a '
                       'scenario) or a map_server map; empty: the latest /map', read_only=True)
        self._start = self._point(declare(self, 'start', [0.0, 0.0], 'Start (x, y) [m] until '
                                          'a pose arrives on odom', read_only=True), 'start')
        goal = declare(self, 'goal', [0.0], 'Goal (x, y) or (x, y, yaw) [m, rad]; one value: '
                       'none until goal_pose', read_only=True)
        if len(goal) not in (1, 2, 3):
            raise ValueError(f'goal must be (x, y) or (x, y, yaw), got {len(goal)} values')
        self._goal = None if len(goal) < 2 else self._point(goal[:2], 'goal')
        self._world: World | None = load_world_file(path) if path else None
        self._path: np.ndarray | None = None
        self._plan_pub = self.create_publisher(Path, 'plan', LATCHED_QOS)
        self._status_pub = self.create_publisher(PlanStatus, '~/status', LATCHED_QOS)
        self._markers_pub = self.create_publisher(MarkerArray, '~/markers', LATCHED_QOS)
        self._parking: ParkingMode | None = None
        if self._options['method'] == 'parking':
            self._parking = ParkingMode(
                self, self._frame, SearchBudget(int(self._options['max_expansions']),
                                                float(self._options['max_seconds'])),
                lambda: self._world, self._publish)
        if self._world is None:
            self.create_subscription(OccupancyGridMsg, '/map', self._on_map, LATCHED_QOS)
        self.create_subscription(Odometry, 'odom', self._on_odom, STREAM_SUB_QOS)
        # Reliable and volatile: RViz's and Foxglove's goal tools (volatile) and a latched
        # publisher are both matched (a transient-local reader refuses a volatile writer).
        self.create_subscription(PoseStamped, 'goal_pose', self._on_goal, COMMAND_QOS)
        self.get_logger().info(
            f"planner {self._options['method']!r} on "
            + (f'the world of {path}' if path else '/map') + ', goal '
            + ('of the parking search' if self._parking is not None else
               'from goal_pose' if self._goal is None else str(self._goal.tolist())))
        self._plan()

    @staticmethod
    def _point(value: Any, name: str) -> np.ndarray:
        point = bounded_array(name, value, MAX_POSITION)
        if point.shape != (2,):
            raise ValueError(f'{name} must be (x, y) [m], got {list(value)}')
        return point

    # -- inputs ---------------------------------------------------------------------------
    def _on_map(self, msg: OccupancyGridMsg) -> None:
        if msg.header.frame_id and msg.header.frame_id != self._frame:
            raise ValueError(f'/map in frame {msg.header.frame_id!r}, not {self._frame!r}')
        self._world = World(grid=grid_from_message(msg))
        self.get_logger().info('new map: '
                               f'{msg.info.width} x {msg.info.height} cells of '
                               f'{msg.info.resolution:g} m')
        if self._parking is None and (self._path is None or self._blocked(self._path)):
            self._plan()

    def _on_odom(self, msg: Odometry) -> None:
        pose = pose2d_from_odometry(msg)
        self._start = self._point(pose[:2], 'pose')
        if self._parking is not None:
            self._parking.on_odom(msg)

    def _on_goal(self, msg: PoseStamped) -> None:
        if msg.header.frame_id and msg.header.frame_id != self._frame:
            raise ValueError(f'goal_pose in frame {msg.header.frame_id!r}, not {self._frame!r}')
        goal = self._point([msg.pose.position.x, msg.pose.position.y], 'goal_pose')
        quaternion_to_yaw(msg.pose.orientation)   # a malformed quaternion is refused here
        if self._parking is not None:
            self.get_logger().warn('a goal on goal_pose is not used in the parking mode: call '
                                   'the park service', throttle_duration_sec=5.0)
            return
        self._goal = goal
        self.get_logger().info(f'new goal ({goal[0]:.3f}, {goal[1]:.3f}) m')
        self._plan()

    def _blocked(self, path: np.ndarray) -> bool:
        """Return whether the world now blocks ``path`` for the robot's disc."""
        assert self._world is not None
        radius = max(float(self._options['robot_radius']), 1e-3)
        return any(swept_collision(self._world, radius, (*a, 0.0), (*b, 0.0)) is not None
                   for a, b in zip(path[:-1], path[1:]))

    # -- planning -------------------------------------------------------------------------
    def _plan(self) -> None:
        if self._world is None or self._goal is None or self._parking is not None:
            return
        began = time.monotonic()
        result = plan_path(self._world, self._start, self._goal, self._options, time.monotonic)
        elapsed = time.monotonic() - began
        self._path = None if result.path is None else result.path[:, :2]
        self._publish(result, path_message(
            result.path[:, :2] if result.path is not None else np.zeros((0, 2)),
            self._frame), elapsed, [])   # (x, y); a curved path's θ is its tangent anyway
        if result.found:
            self.get_logger().info(f'path of {result.cost:.2f} m ({len(result.path)} poses), '
                                   f'{result.expansions} expansions in {elapsed:.3f} s')
        else:
            self.get_logger().error(f'no path: {result.reason} (after {result.expansions} '
                                    f'expansions, {elapsed:.3f} s); the tracker stops')

    def _publish(self, result: PlanResult, path: Path | None, elapsed: float,
                 extra: list[Marker]) -> None:
        """Publish ``path`` (unless None) on ``plan``, the status and the markers of ``result``."""
        stamp = self.get_clock().now().to_msg()
        if path is not None:
            path.header.stamp = stamp
            self._plan_pub.publish(path)
        self._status_pub.publish(self._status(result, elapsed, stamp))
        markers = self._markers(result, stamp)
        for marker in extra:
            marker.header.frame_id, marker.header.stamp = self._frame, stamp
        markers.markers.extend(extra)
        self._markers_pub.publish(markers)

    def _status(self, result: PlanResult, elapsed: float, stamp: Any) -> PlanStatus:
        goal = result.details.get('goal') if self._parking is not None else self._goal
        msg = PlanStatus(method=str(self._options['method']), found=result.found,
                         reason=result.reason, cost=result.cost if result.found else 0.0,
                         points=0 if result.path is None else len(result.path),
                         expansions=int(result.expansions),
                         budget_exhausted='budget was exhausted' in result.reason,
                         planning_time=elapsed, start=_pose(*self._start),
                         goal=Pose() if goal is None else _pose(*goal))
        msg.header.stamp = stamp
        msg.header.frame_id = self._frame
        return msg

    def _markers(self, result: PlanResult, stamp: Any) -> MarkerArray:
        """Return the plan's markers: the path, the expanded cells, the start and the goal."""
        markers = [Marker(ns=ns, action=Marker.DELETEALL) for ns in ('plan', 'parking_space')]
        line = Marker(ns='plan', id=0, type=Marker.LINE_STRIP, action=Marker.ADD)
        line.scale.x = 0.05
        line.color = ColorRGBA(r=0.1, g=0.8, b=0.1, a=1.0)
        if result.path is not None:
            line.points = [Point(x=float(x), y=float(y)) for x, y in result.path[:, :2]]
        markers.append(line)
        expanded = result.details.get('expanded')
        grid = result.details.get('grid')   # the grid A* searched (drawn from a world's shapes)
        if expanded is not None and grid is not None and len(expanded):
            cells = np.asarray(expanded)[::max(1, len(expanded) // MAX_EXPANDED_MARKERS)]
            centres = grid.cell_to_world(cells)
            dots = Marker(ns='plan', id=1, type=Marker.POINTS, action=Marker.ADD)
            dots.scale.x = dots.scale.y = grid.resolution
            dots.color = ColorRGBA(r=0.3, g=0.5, b=1.0, a=0.3)
            dots.points = [Point(x=float(x), y=float(y)) for x, y in centres]
            markers.append(dots)
        markers += _search_markers(result.details, float(self._options['field_step']))
        for k, (point, color) in enumerate(((self._start, ColorRGBA(g=1.0, a=1.0)),
                                            (self._goal if self._parking is None
                                             else result.details.get('goal'),
                                             ColorRGBA(r=1.0, a=1.0)))):
            if point is None:
                continue
            sphere = Marker(ns='plan', id=2 + k, type=Marker.SPHERE, action=Marker.ADD,
                            pose=_pose(*point[:2]), color=color)
            sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.2
            markers.append(sphere)
        for marker in markers:
            marker.header.frame_id = self._frame
            marker.header.stamp = stamp
        return MarkerArray(markers=markers)


def _search_markers(details: dict, field_step: float) -> list[Marker]:
    """
    Return the markers of what the search built: the graph or roadmap, the force field, a trap.

    The visibility graph's edges or the Voronoi roadmap's ridges (grey lines, id 4); the
    direction of the resultant force of a potential method on its lattice of ``field_step``
    [m] (an orange segment of 0.7 ``field_step`` from each lattice point, id 5); the local
    minimum a potential method stalled in (a red sphere, id 6). At most
    :data:`MAX_EXPANDED_MARKERS` segments of each.
    """
    markers = []
    edges = details.get('graph', details.get('roadmap'))
    if edges is not None and len(edges):
        lines = np.asarray(edges, dtype=float)[::max(1, len(edges) // MAX_EXPANDED_MARKERS)]
        graph = Marker(ns='plan', id=4, type=Marker.LINE_LIST, action=Marker.ADD)
        graph.scale.x = 0.01
        graph.color = ColorRGBA(r=0.5, g=0.5, b=0.5, a=0.6)
        graph.points = [Point(x=float(x), y=float(y)) for x, y in lines.reshape(-1, 2)]
        markers.append(graph)
    field = details.get('field')
    if field is not None and len(field):
        rows = np.asarray(field, dtype=float)
        rows = rows[np.isfinite(rows[:, 2])][::max(1, len(rows) // MAX_EXPANDED_MARKERS)]
        tips = rows[:, :2] + 0.7 * field_step * np.column_stack([np.cos(rows[:, 2]),
                                                                 np.sin(rows[:, 2])])
        arrows = Marker(ns='plan', id=5, type=Marker.LINE_LIST, action=Marker.ADD)
        arrows.scale.x = 0.015
        arrows.color = ColorRGBA(r=1.0, g=0.55, b=0.0, a=0.8)
        arrows.points = [Point(x=float(x), y=float(y))
                         for x, y in np.hstack([rows[:, :2], tips]).reshape(-1, 2)]
        markers.append(arrows)
    trap = details.get('trap')
    if trap is not None:
        sphere = Marker(ns='plan', id=6, type=Marker.SPHERE, action=Marker.ADD,
                        pose=_pose(*np.asarray(trap, dtype=float)[:2]),
                        color=ColorRGBA(r=1.0, g=0.1, b=0.1, a=0.9))
        sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.3
        markers.append(sphere)
    return markers


def main(args=None) -> None:
    """Run the planner until Ctrl-C."""
    run_node(PlannerNode, args, executor_factory=EventsExecutor)
