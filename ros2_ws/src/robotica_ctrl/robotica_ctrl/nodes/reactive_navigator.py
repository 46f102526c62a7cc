"""
Reactive navigator node: drives from the range sensors with the behaviours of §9.6 and §12.7.

The behaviour and every gain are parameters (``behaviour``: ``wall_following``,
``corridor_centring``, ``vff``, ``potential``; groups ``wall.*``, ``corridor.*``, ``vff.*``,
``potential.*``, ``speed.*``, ``stall.*``; ``ros2 param describe`` gives units and ranges); the
core is :class:`robotica_ctrl.mobile.reactive_navigation.ReactiveNavigator`. Parameters are
read-only: the behaviours keep no state a change could be applied to mid-manoeuvre except the
stall detector, so a change means a restart.

Topics in: the pose from ``odom`` (nav_msgs/Odometry; ``pose_source`` = ``ground_truth``:
``ground_truth/odom``), a laser ``scan`` (sensor_msgs/LaserScan, mounted at ``laser.pose``
(x, y, yaw) in ``base_link``) and the sonars or infrared sensors of ``range.topics``
(sensor_msgs/Range, each at its pose of ``range.poses``, three numbers a sensor). Out:
``cmd_vel`` (geometry_msgs/Twist) and ``~/state`` (std_msgs/String, transient local: the
behaviour's state each time it changes: following, outer_corner, inner_corner, centring,
goal_seeking, avoiding, goal_reached, stalled, no_wall, no_ranges, unreliable_ranges).

Each pose is answered with exactly one command (what a lockstep simulation needs), computed
from the newest readings: a laser scan or range reading older than ``range_timeout`` [s] against
the pose's stamp is not used. With ``wait_for_ranges`` (a lockstep run sets it) a pose is
answered only once every sensor has published each reading due by the pose's time: a sensor
samples on the grid ``offset + k period`` (``laser.period``, ``range.periods``,
``range.offsets`` [s]: a sonar ring's groups fire in turn), and its next sample after its newest
reading is due when it is not later than the pose. The sensor emulators are off the loop and
their readings arrive a moment after the pose: answering with whatever had arrived made two runs
of one seed differ (an RMS cross-track of 0.014 m in one, 0.043 m in another). A newer pose
answers a waiting one with the readings it has. A stop is commanded, and said once on the log
and on ``~/state``, when no reading is recent (``no_ranges``), when more than
``max_unknown_fraction`` of the newest readings are NaN (REP-117: erroneous;
``unreliable_ranges``), at the goal and in a local minimum
(``stalled``, reported as a warning). A message the guard refuses (a non-finite pose, a scan of
the wrong size) costs that message and commands a stop.
"""
import math

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_ctrl.mobile.range_perception import range_points, RangePoints
from robotica_ctrl.mobile.reactive_navigation import (NAVIGATOR_PARAMETERS, navigator_params,
                                                      ReactiveNavigator)
from robotica_kin.ros.convert import pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import (COMMAND_PUB_QOS, INPUT_QOS_OVERRIDES, LATCHED_QOS,
                                  STREAM_SUB_QOS)
from sensor_msgs.msg import LaserScan, Range
from std_msgs.msg import String

POSE_TOPICS = {'odom': 'odom', 'ground_truth': 'ground_truth/odom'}   # by pose_source
MAX_BEAMS = 100_000   # beams of one scan: beyond, the scan is refused


class ReactiveNavigatorNode(GuardedNode):
    """ROS shell around :class:`ReactiveNavigator`."""

    def __init__(self) -> None:
        super().__init__('reactive_navigator')
        self._navigator = ReactiveNavigator(navigator_params(
            declare_specs(self, NAVIGATOR_PARAMETERS)))
        pose_source = declare(self, 'pose_source', 'odom', 'Pose topic: odom (the estimate) '
                              "or ground_truth (the simulator's truth)", read_only=True)
        if pose_source not in POSE_TOPICS:
            raise ValueError(f'pose_source must be one of {tuple(POSE_TOPICS)}, '
                             f'got {pose_source!r}')
        self._timeout = declare(self, 'range_timeout', 0.5, 'Readings older than this against '
                                'the pose are not used [s]', low=0.0, high=60.0, read_only=True)
        self._max_unknown = declare(self, 'max_unknown_fraction', 0.5, 'Stop when more than '
                                    'this fraction of the readings is NaN (erroneous)',
                                    low=0.0, high=1.0, read_only=True)
        self._laser_pose = _pose('laser.pose', declare(
            self, 'laser.pose', [0.0, 0.0, 0.0], 'Laser (x [m], y [m], yaw [rad]) in '
            'base_link', read_only=True))
        topics = [t for t in declare(self, 'range.topics', [''], 'sensor_msgs/Range topics '
                                     '(sonars, infrared); [""]: none', read_only=True) if t]
        poses = declare(self, 'range.poses', [0.0], "Each range sensor's (x [m], y [m], yaw "
                        '[rad]) in base_link, three numbers a topic of range.topics',
                        read_only=True)
        if len(poses) != 3 * len(topics) and topics:
            raise ValueError(f'range.poses needs 3 numbers for each of the {len(topics)} '
                             f'range.topics, got {len(poses)}')
        self._wait = declare(self, 'wait_for_ranges', False, 'Answer a pose only once every '
                             "sensor's reading due by its time has come (lockstep)",
                             read_only=True)
        laser_period = declare(self, 'laser.period', 0.0, 'Period of the laser scans [s]: '
                               'wait_for_ranges waits for the scan due; 0: does not wait',
                               low=0.0, high=60.0, read_only=True)
        periods = declare(self, 'range.periods', [0.0], 'Period of each range sensor of '
                          'range.topics [s], as wait_for_ranges waits for it; [0.0]: none',
                          read_only=True)
        offsets = declare(self, 'range.offsets', [0.0], 'Time of the first sample of each '
                          'range sensor of range.topics [s] (a sonar group fires later)',
                          read_only=True)
        if self._wait and topics and not len(periods) == len(offsets) == len(topics):
            raise ValueError(f'range.periods and range.offsets need one value for each of '
                             f'the {len(topics)} range.topics, got {len(periods)} and '
                             f'{len(offsets)}')
        self._grids = {'scan': (0.0, laser_period)} if laser_period > 0.0 else {}
        self._grids.update({i: (o, p) for i, (o, p) in enumerate(zip(offsets, periods))
                            if p > 0.0 and i < len(topics)})
        self._pending: Odometry | None = None   # the pose waiting for its readings
        self._scan: tuple[float, RangePoints] | None = None      # (stamp [s], points)
        self._ranges: dict[int, tuple[float, RangePoints]] = {}  # sensor -> (stamp, points)
        for i, topic in enumerate(topics):
            pose = _pose(f'range.poses[{3 * i}:{3 * i + 3}]', poses[3 * i:3 * i + 3])
            self.create_subscription(
                Range, topic, lambda msg, i=i, pose=pose: self._on_range(i, pose, msg),
                STREAM_SUB_QOS, qos_overriding_options=INPUT_QOS_OVERRIDES)
        self.create_subscription(LaserScan, 'scan', self._on_scan, STREAM_SUB_QOS,
                                 qos_overriding_options=INPUT_QOS_OVERRIDES)
        self.create_subscription(Odometry, POSE_TOPICS[pose_source], self._on_pose,
                                 STREAM_SUB_QOS, qos_overriding_options=INPUT_QOS_OVERRIDES)
        self._cmd_pub = self.create_publisher(Twist, 'cmd_vel', COMMAND_PUB_QOS)
        self._state_pub = self.create_publisher(String, '~/state', LATCHED_QOS)
        self._state = ''
        self.get_logger().info(f'behaviour {self._navigator.params.behaviour}, pose from '
                               f'{POSE_TOPICS[pose_source]}, ranges from scan'
                               + ''.join(f', {t}' for t in topics))

    # -- callbacks: store and convert only ----------------------------------------------------
    def _on_scan(self, msg: LaserScan) -> None:
        count = len(msg.ranges)
        if count > MAX_BEAMS:
            raise ValueError(f'{count} beams, more than {MAX_BEAMS}')
        angles = [msg.angle_min + k * msg.angle_increment for k in range(count)]
        self._scan = (stamp_to_seconds(msg.header.stamp),
                      range_points(msg.ranges, angles, msg.range_min, msg.range_max,
                                   self._laser_pose))
        self._answer_if_ready()

    def _on_range(self, sensor: int, pose: tuple[float, float, float], msg: Range) -> None:
        self._ranges[sensor] = (stamp_to_seconds(msg.header.stamp),
                                range_points([msg.range], [0.0], msg.min_range,
                                             msg.max_range, pose))
        self._answer_if_ready()

    def _on_pose(self, msg: Odometry) -> None:
        if not self._wait:
            self._answer(msg)
            return
        if self._pending is not None:   # its readings never came: answered with what there is
            self._answer(self._pending)
        self._pending = msg
        self._answer_if_ready()

    def _answer_if_ready(self) -> None:
        """Answer the waiting pose once each sensor's reading due by its time has come."""
        if self._pending is None:
            return
        t = stamp_to_seconds(self._pending.header.stamp)
        newest = {i: stamp for i, (stamp, _) in self._ranges.items()}
        if self._scan:
            newest['scan'] = self._scan[0]
        if all(_next_sample(newest.get(source), offset, period) > t + 1e-9
               for source, (offset, period) in self._grids.items()):
            msg, self._pending = self._pending, None
            self._answer(msg)

    def _answer(self, msg: Odometry) -> None:
        """Answer the pose with one command from the readings within range_timeout of it."""
        t = stamp_to_seconds(msg.header.stamp)
        recent = [points for stamp, points in ([self._scan] if self._scan else [])
                  + list(self._ranges.values()) if abs(t - stamp) <= self._timeout]
        readings = sum(r.readings for r in recent)
        unknown = sum(r.unknown for r in recent) / readings if readings else 0.0
        if not recent:
            self._stop('no_ranges', f'no range reading within {self._timeout} s of the pose '
                       f'at t = {t:.3f} s')
            return
        if unknown > self._max_unknown:
            self._stop('unreliable_ranges', f'{100 * unknown:.0f} % of the readings are NaN '
                       f'(erroneous), more than {100 * self._max_unknown:.0f} %')
            return
        output = self._navigator.update(t, pose2d_from_odometry(msg),
                                        np.vstack([r.points for r in recent]))
        self._set_state(output.state, f'at t = {t:.3f} s, clearance {output.clearance:.2f} m'
                        + ('' if math.isnan(output.goal_distance)
                           else f', goal {output.goal_distance:.2f} m away'))
        self._publish(output.command.linear, output.command.angular)

    def on_callback_error(self, source: str) -> None:
        """Command a stop: the guard dropped an input on ``source``."""
        self._publish(0.0, 0.0)

    # -- output ----------------------------------------------------------------------------
    def _stop(self, state: str, why: str) -> None:
        self._set_state(state, why)
        self._publish(0.0, 0.0)

    def _set_state(self, state: str, detail: str) -> None:
        if state == self._state:
            return
        self._state = state
        text = f'{state}: {detail}' + (' (a local minimum: the goal does not come closer; '
                                       'stopping)' if state == 'stalled' else '')
        if state in ('stalled', 'no_ranges', 'unreliable_ranges'):   # one call site a level:
            self.get_logger().warn(text)       # rclpy refuses a severity change at one site
        else:
            self.get_logger().info(text)
        self._state_pub.publish(String(data=state))

    def _publish(self, linear: float, angular: float) -> None:
        twist = Twist()
        twist.linear.x = linear
        twist.angular.z = angular
        self._cmd_pub.publish(twist)


def _next_sample(newest, offset: float, period: float) -> float:
    """
    Return the sensor's next sample time after its newest reading stamped ``newest`` [s].

    Samples lie on ``offset + k period`` (the emulators' schedule: the first truth stamp, then
    whole periods); a reading is stamped with the first step at or after its sample time, so
    the sample of a reading stamped s is the last grid time at or before s. None: no reading
    yet, the first sample is due at ``offset``.
    """
    if newest is None:
        return offset
    return offset + (math.floor((newest - offset) / period + 1e-9) + 1) * period


def _pose(name: str, values) -> tuple[float, float, float]:
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise ValueError(f'{name} must be 3 finite numbers (x [m], y [m], yaw [rad]), '
                         f'got {list(values)!r}')
    return (float(values[0]), float(values[1]), float(values[2]))


def main(args=None) -> None:
    """Run the reactive navigator until Ctrl-C."""
    run_node(ReactiveNavigatorNode, args, executor_factory=EventsExecutor)
