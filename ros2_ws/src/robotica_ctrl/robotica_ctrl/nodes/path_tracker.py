"""
Path tracker node: follows a ``nav_msgs/Path`` from the pose on ``odom``; publishes ``cmd_vel``.

The control law is chosen by ``law`` (book chapter 9; ``pure_pursuit``, §9.3.1, for now) and
lives in :mod:`robotica_ctrl.mobile`; ``open_loop`` plays the profile ``open_loop.times``,
``open_loop.linear`` and ``open_loop.angular`` against the pose's time stamp instead, without
feedback or path (the book's Simulink examples, Ej. 4.8 and 4.9). Topics: ``odom``
(nav_msgs/Odometry) and ``~/path`` (nav_msgs/Path, transient-local) in; ``cmd_vel``
(geometry_msgs/Twist) and ``~/tracking_error`` (robotica_msgs/TrackingError, stamped with the
pose it was computed from) out. With
``command_type`` = ``steering`` (tricycle, bicycle, Ackermann) the command goes out on
``vehicle_command`` (robotica_msgs/VehicleCommand) instead: the law's speed v and the steering
angle of its curvature, α = atan(l ω / v) (book (4.119), (4.121)), l = ``wheelbase``.

With ``control_rate`` = 0 the law runs once per pose message (what a lockstep simulation needs:
every step is answered exactly once); with ``control_rate`` > 0 it runs on a timer from the
newest pose and brakes when that pose is older than ``pose_timeout``. Gains can be changed at
run time; an invalid value is refused with the reason. Without a path, with a path in another
frame than the pose, or with a non-finite pose, the node commands a stop and says why.
"""
import dataclasses
import math

from geometry_msgs.msg import Point, Twist
from nav_msgs.msg import Odometry, Path
from rcl_interfaces.msg import SetParametersResult
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from robotica_ctrl.mobile.open_loop import OpenLoopProfile
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_kin.nodes.convert import path_points, pose2d_from_odometry, stamp_to_seconds
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_kin.nodes.qos import COMMAND_PUB_QOS, LATCHED_QOS, STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_msgs.msg import TrackingError, VehicleCommand

LAWS = ('pure_pursuit', 'open_loop')
COMMAND_TYPES = ('twist', 'steering')
GAIN_DESCRIPTIONS = {
    'lookahead_distance': ('Look-ahead arc distance L [m], book (9.7)', 0.01, 100.0),
    'desired_linear_velocity': ('Cruise speed [m/s]', 1e-3, 100.0),
    'max_angular_velocity': ('Yaw-rate limit [rad/s]; speed is reduced to keep the curvature',
                             1e-3, 100.0),
    'goal_tolerance': ('Distance to the path end at which the path is finished [m]',
                       1e-4, 100.0),
    'approach_distance': ('Distance to the path end over which the speed ramps down [m]',
                          1e-3, 1000.0),
    'min_approach_velocity': ('Lowest speed while approaching the end [m/s]', 1e-4, 100.0),
    'search_window': ('Window of the closest-point search around the progress [m]',
                      1e-3, 1000.0),
}


class PathTrackerNode(Node):
    """ROS shell around :class:`robotica_ctrl.mobile.pure_pursuit.PurePursuit`."""

    def __init__(self) -> None:
        super().__init__('path_tracker')
        self._law = declare(self, 'law', 'pure_pursuit', f'Tracking law: one of {LAWS}',
                            read_only=True)
        if self._law not in LAWS:
            raise ValueError(f'law must be one of {LAWS}, got {self._law!r}')
        defaults = PurePursuitParams()
        self._params = PurePursuitParams(**{
            name: declare(self, 'pure_pursuit.' + name, float(getattr(defaults, name)),
                          description, low=low, high=high)
            for name, (description, low, high) in GAIN_DESCRIPTIONS.items()})
        self._command_type = declare(self, 'command_type', 'twist',
                                     f'Command: one of {COMMAND_TYPES} (cmd_vel Twist, or '
                                     'vehicle_command VehicleCommand for steered vehicles)',
                                     read_only=True)
        if self._command_type not in COMMAND_TYPES:
            raise ValueError(f'command_type must be one of {COMMAND_TYPES}, got '
                             f'{self._command_type!r}')
        self._wheelbase = declare(self, 'wheelbase', 0.5,
                                  'Wheelbase l [m] of a steered vehicle (command_type steering)',
                                  low=1e-3, high=100.0, read_only=True)
        self._profile = OpenLoopProfile(
            declare(self, 'open_loop.times', [0.0], 'open_loop: times of the profile rows [s]',
                    read_only=True),
            declare(self, 'open_loop.linear', [0.0], 'open_loop: forward speed v [m/s] per row',
                    read_only=True),
            declare(self, 'open_loop.angular', [0.0], 'open_loop: yaw rate [rad/s] per row',
                    read_only=True))
        self._control_rate = declare(self, 'control_rate', 0.0,
                                     'Control rate [Hz]; 0: once per pose message',
                                     low=0.0, high=1000.0, read_only=True)
        self._pose_timeout = declare(self, 'pose_timeout', 0.5,
                                     'With control_rate > 0, a pose older than this [s] stops '
                                     'the robot', low=1e-3, high=60.0, read_only=True)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)

        self._tracker = None
        self._path_frame = ''
        self._pose_msg = None
        self._reported = set()
        if self._command_type == 'twist':
            self._cmd_pub = self.create_publisher(Twist, 'cmd_vel', COMMAND_PUB_QOS)
        else:
            self._cmd_pub = self.create_publisher(VehicleCommand, 'vehicle_command',
                                                  COMMAND_PUB_QOS)
        self._error_pub = self.create_publisher(TrackingError, '~/tracking_error',
                                                STREAM_PUB_QOS)
        self.create_subscription(Path, '~/path', self._on_path, LATCHED_QOS)
        self.create_subscription(Odometry, 'odom', self._on_odom, STREAM_SUB_QOS)
        if self._control_rate > 0.0:
            self.create_timer(1.0 / self._control_rate, self._on_timer)

    # -- parameters --------------------------------------------------------------------------
    def _candidate(self, parameters) -> PurePursuitParams:
        changes = {p.name.removeprefix('pure_pursuit.'): p.value for p in parameters
                   if p.name.startswith('pure_pursuit.')}
        return dataclasses.replace(self._params, **changes)

    def _validate_parameters(self, parameters) -> SetParametersResult:
        try:
            self._candidate(parameters)
        except (ValueError, TypeError) as err:
            return SetParametersResult(successful=False, reason=str(err))
        return SetParametersResult(successful=True)

    def _apply_parameters(self, parameters) -> None:
        self._params = self._candidate(parameters)
        if self._tracker is not None:
            self._tracker.set_params(self._params)

    # -- inputs ------------------------------------------------------------------------------
    def _on_path(self, msg: Path) -> None:
        try:
            path = PolylinePath(path_points(msg))
        except ValueError as err:
            self.get_logger().error(f'path refused: {err}')
            self._tracker = None
            return
        self._tracker = PurePursuit(path, self._params)
        self._path_frame = msg.header.frame_id
        self._reported.clear()
        self.get_logger().info(f'following a path of {path.length:.2f} m in frame '
                               f'{self._path_frame!r}')

    def _on_odom(self, msg: Odometry) -> None:
        self._pose_msg = msg
        if self._control_rate == 0.0:
            self._control(msg)

    def _on_timer(self) -> None:
        msg = self._pose_msg
        now = self.get_clock().now().nanoseconds * 1e-9
        if msg is None or now - stamp_to_seconds(msg.header.stamp) > self._pose_timeout:
            self._stop('no pose newer than pose_timeout on odom: stopping')
            return
        self._control(msg)

    # -- control -----------------------------------------------------------------------------
    def _stop(self, reason: str) -> None:
        if reason not in self._reported:
            self._reported.add(reason)
            self.get_logger().warn(reason)
        self._publish_command(0.0, 0.0)

    def _publish_command(self, linear: float, angular: float) -> None:
        """Publish (v [m/s], ω [rad/s]) as a Twist or as a speed and a steering angle."""
        if self._command_type == 'twist':
            twist = Twist()
            twist.linear.x = linear
            twist.angular.z = angular
            self._cmd_pub.publish(twist)
            return
        # α = atan(l γ) with γ = ω / v; stopped (v = 0), the wheel keeps straight.
        steering = math.atan(self._wheelbase * angular / linear) if linear != 0.0 else 0.0
        self._cmd_pub.publish(VehicleCommand(speed=linear, steering_angle=steering))

    def _control(self, msg: Odometry) -> None:
        if self._law == 'open_loop':
            self._publish_command(*self._profile.command(stamp_to_seconds(msg.header.stamp)))
            return
        if self._tracker is None:
            self._stop('no path received on ~/path yet: holding still')
            return
        if msg.header.frame_id != self._path_frame:
            self._stop(f'pose frame {msg.header.frame_id!r} differs from path frame '
                       f'{self._path_frame!r}: stopping')
            return
        pose = pose2d_from_odometry(msg)
        try:
            command = self._tracker.update(pose)
        except ValueError as err:
            self._stop(f'pose refused ({err}): stopping')
            return
        self._publish_command(command.linear, command.angular)
        if command.finished and 'finished' not in self._reported:
            self._reported.add('finished')
            self.get_logger().info('path finished: stopped at its end')
        projection = command.projection
        error = TrackingError(cross_track=float(projection.cross_track),
                              heading=math.remainder(pose[2] - projection.tangent_heading,
                                                     math.tau),
                              along_track=float(projection.along_track),
                              target_point=Point(x=float(command.goal_point[0]),
                                                 y=float(command.goal_point[1])))
        error.header = msg.header
        self._error_pub.publish(error)


def main(args=None) -> None:
    """Run the path tracker until Ctrl-C."""
    run_node(PathTrackerNode, args, executor_factory=EventsExecutor)
