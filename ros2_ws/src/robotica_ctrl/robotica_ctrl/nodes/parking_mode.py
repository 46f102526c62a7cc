"""
The planner node's ``parking`` mode: the course's parallel parking from pass to plan (Part 14).

The ROS side of :class:`~robotica_ctrl.planning.parking.parking_search.ParkingSearch`: a
search starts at the first pose (``parking.autostart``) or when the ``park`` service
(std_srvs/Trigger) is called, and publishes the pass on the planner's ``plan`` (postures whose
orientations are the vehicle's headings, for ``reversing_pure_pursuit``). Each side reading
(``side_range``, sensor_msgs/Range: remap it to the sonar that looks at the parked cars) is
placed at the pose of its stamp (``odom``, within ``pose_tolerance``). When a space is taken
its plan is published on ``plan`` (the pass's rest, the approach, the manoeuvres with their
direction of travel, the centring) with its ``~/status`` and ``~/markers`` (the space, the
path); a space without a plan is reported on ``~/status`` and the pass goes on; a pass that
ends with no plan is reported too.

``~/progress`` (std_msgs/Header) carries the stamp of each pose handled, so that a lockstep
simulator can follow the planner (``lockstep.follow_topics``) and not drive on while a plan
is being made.
"""
import math
import time
from typing import Callable, Optional

from geometry_msgs.msg import Point
from nav_msgs.msg import Odometry, Path
import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.planning.parking.parking_search import (PARKING_PARAMETERS, parking_search,
                                                           ParkingSearch)
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_kin.mobile.pose_history import PoseHistory
from robotica_kin.ros.convert import path_message, pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_kin.world.shapes import World
from sensor_msgs.msg import Range
from std_msgs.msg import ColorRGBA, Header
from std_srvs.srv import Trigger
from visualization_msgs.msg import Marker

__all__ = ['ParkingMode']

POSES_KEPT = 500
"""Poses kept to place the readings (10 s of 50 Hz odometry)."""
PENDING_KEPT = 50
"""Readings kept while their pose has not arrived (newer than every pose)."""


class ParkingMode:
    """
    The parking search of a planner node (module docstring).

    ``publish`` is the node's: it publishes a plan result's status and markers with the extra
    markers given, and the path message given on ``plan`` (None: the path is left as it is);
    ``world`` returns the world the plans are checked against (None: the space's own
    obstacles); ``budget`` bounds each plan.
    """

    def __init__(self, node: GuardedNode, frame: str, budget: SearchBudget,
                 world: Callable[[], Optional[World]],
                 publish: Callable[[PlanResult, Optional[Path], float, list[Marker]], None]
                 ) -> None:
        self._node, self._frame, self._budget = node, frame, budget
        self._world, self._publish = world, publish
        values = declare_specs(node, {f'parking.{k}': v for k, v in PARKING_PARAMETERS.items()})
        self._search: ParkingSearch = parking_search(
            {k.removeprefix('parking.'): v for k, v in values.items()})
        self._autostart = bool(values['parking.autostart'])
        self._tolerance = declare(node, 'pose_tolerance', 0.05, 'Largest gap between a side '
                                  'reading and the pose it is placed at [s]', low=0.0,
                                  high=10.0, read_only=True)
        self._history = PoseHistory(POSES_KEPT)
        self._pending: list[Range] = []
        self._last_reading = -math.inf   # [s] the stamp of the last reading placed on the pass
        self._pose: Optional[NDArray[np.float64]] = None
        self._state = 'idle'   # idle, searching, planned
        self._progress = node.create_publisher(Header, '~/progress', STREAM_PUB_QOS)
        node.create_subscription(Range, 'side_range', self._on_range, STREAM_SUB_QOS)
        node.create_service(Trigger, 'park', self._on_park)
        v = self._search.vehicle
        node.get_logger().info(
            f'parking: a1 {v.a1} m, b1 {v.b1} m, h1 {v.h1} m, c1 {v.c1} m, theta_dmax '
            f'{v.theta_dmax} rad; side sensor at {self._search.sensor_pose.tolist()} in '
            'base_link; ' + ('starts at the first pose' if self._autostart
                             else 'waiting for a call of park'))

    # -- inputs -------------------------------------------------------------------------------
    def on_odom(self, msg: Odometry) -> None:
        """Keep the pose of ``msg``; start or end the pass as due; publish the progress."""
        stamp = stamp_to_seconds(msg.header.stamp)
        pose = pose2d_from_odometry(msg)
        self._history.add(stamp, pose)
        self._pose = pose
        pending, self._pending = self._pending, []
        for reading in pending:   # the readings that came before their pose: now, or kept
            try:
                self._on_range(reading)
            except ValueError as err:   # one dropped reading must not drop this pose's work
                self._node.get_logger().warn(f'side reading dropped: {err}',
                                             throttle_duration_sec=5.0)
        if self._autostart and self._state == 'idle':
            self._autostart = False
            self._start()
        elif self._state == 'searching' and self._search.finished(pose):
            self._state = 'idle'
            self._status(f'no space to park in was found along the pass of '
                         f'{self._search.params.pass_length:g} m '
                         f'({self._search.samples} side readings)')
        self._progress.publish(Header(stamp=msg.header.stamp, frame_id=self._frame))

    def _on_park(self, request: Trigger.Request, response: Trigger.Response
                 ) -> Trigger.Response:
        if self._pose is None:
            response.success, response.message = False, 'no pose yet on odom: nothing to start'
            return response
        response.success = True
        response.message = self._start()
        return response

    def _on_range(self, msg: Range) -> None:
        if self._state != 'searching':
            return
        if not (math.isfinite(msg.min_range) and math.isfinite(msg.max_range)
                and 0.0 <= msg.min_range < msg.max_range):   # the reading may be ±inf, NaN
            raise ValueError(f'a Range needs finite 0 <= min_range < max_range, got '
                             f'{msg.min_range!r}, {msg.max_range!r}')
        t = stamp_to_seconds(msg.header.stamp)
        if t > self._history.latest:   # its pose may still be on its way
            self._pending.append(msg)
            del self._pending[:-PENDING_KEPT]
            return
        if t <= self._last_reading:   # the pass is read in order: a stale one would go back
            raise ValueError(f'a side reading at {t:.3f} s, not after the last one read '
                             f'({self._last_reading:.3f} s)')
        pose = self._history.nearest(t, self._tolerance)
        if pose is None:
            self._node.get_logger().warn(f'no pose within {self._tolerance} s of the side '
                                         f'reading at {t:.3f} s: skipped',
                                         throttle_duration_sec=5.0)
            return
        self._last_reading = t
        try:
            found = self._search.add_reading(pose, msg.range, msg.min_range, msg.max_range)
        except ValueError as err:   # the pass turned or went back: no space can be measured
            self._state = 'idle'
            self._status(f'the search stopped: {err}')
            return
        if found is None:
            return
        space = found.space
        self._node.get_logger().info(
            f'space on the {space.side}: H = {space.length:.3f} m, J = {space.depth:.3f} m'
            + ('' if found.depth_measured else ' (no curb echo: J capped)')
            + f', from ({space.origin[0]:.3f}, {space.origin[1]:.3f}) m')
        began = time.monotonic()
        result = self._search.plan(found, world=self._world(), budget=self._budget,
                                   clock=time.monotonic)
        elapsed = time.monotonic() - began
        h, j = space.length, space.depth
        markers = [_space_marker(space.to_map([[0.0, 0.0, 0.0], [h, 0.0, 0.0], [h, -j, 0.0],
                                               [0.0, -j, 0.0]])[:, :2])]
        if result.found:
            self._state = 'planned'
            self._publish(result, path_message(result.path, self._frame), elapsed, markers)
            manoeuvres = result.details['manoeuvres']
            self._node.get_logger().info(
                f"parking plan: {result.details['parking_manoeuvres']} parking manoeuvre(s) "
                f'({result.details["mode"]}), {len(manoeuvres)} in all: '
                + ', '.join(f"{m.kind} {'forward' if m.direction > 0 else 'reverse'}"
                            for m in manoeuvres) + f'; {result.cost:.2f} m driven')
        else:
            self._publish(result, None, elapsed, markers)   # the tracker drives on along the pass
            self._node.get_logger().warn(f'no parking plan into this space: {result.reason}; '
                                         'searching on along the pass')

    # -- outputs ------------------------------------------------------------------------------
    def _start(self) -> str:
        assert self._pose is not None
        passing = self._search.start(self._pose)
        self._last_reading = -math.inf
        self._state = 'searching'
        text = (f'searching for a space along a pass of {self._search.params.pass_length:g} m '
                f'from ({self._pose[0]:.3f}, {self._pose[1]:.3f}) m')
        # The pass is driven, but it is no parking plan: the status says found false, searching.
        self._publish(PlanResult.none(text), path_message(passing, self._frame), 0.0, [])
        self._node.get_logger().info(text)
        return text

    def _status(self, reason: str) -> None:
        self._publish(PlanResult.none(reason), path_message(np.zeros((0, 2)), self._frame),
                      0.0, [])
        self._node.get_logger().warn(reason)


def _space_marker(corners: NDArray[np.float64]) -> Marker:
    """Return the outline of a space (its corners in the map frame) as a closed line strip."""
    marker = Marker(ns='parking_space', id=0, type=Marker.LINE_STRIP, action=Marker.ADD)
    marker.scale.x = 0.05
    marker.color = ColorRGBA(r=1.0, g=0.6, b=0.0, a=1.0)
    points = np.asarray(corners, dtype=float)
    marker.points = [Point(x=float(x), y=float(y)) for x, y in [*points, points[0]]]
    return marker
