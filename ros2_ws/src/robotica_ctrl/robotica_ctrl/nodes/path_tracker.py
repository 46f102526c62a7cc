"""
Path tracker node: follows a ``nav_msgs/Path`` with a law of book ch. 9 chosen by ``law``.

Laws (:mod:`robotica_ctrl.mobile.tracking_laws`): ``pure_pursuit`` (§9.3.1),
``adaptive_pure_pursuit`` (look-ahead by speed, curvature or error), ``reversing_pure_pursuit``
(pure pursuit forward and in reverse: the path's poses are the vehicle's postures, the yaw of
each orientation its heading; a step against the heading is driven in reverse, v < 0, and the
vehicle stops at each cusp; a path whose poses face along it is driven forward), ``quintic``
(§9.3.2), ``trajectory_tracking`` (Canudas de Wit, §9.4.2: linear, scheduled or nonlinear),
``frenet`` (§9.4.3: linear or nonlinear), ``gpc`` (§9.5) and ``open_loop`` (a profile of (v, ω)
played against the pose's time stamp without feedback, the book's Simulink examples, Ej. 4.8 and
4.9); each reads its gains from the parameters ``<law>.<gain>`` (descriptions, units and ranges
with ``ros2 param describe``), which can be changed at run time (an invalid value is refused
with the reason).

Topics: the pose in, from ``odom`` (nav_msgs/Odometry, the estimate) or, with ``pose_source``
= ``ground_truth``, from ``ground_truth/odom`` (the simulator's truth); ``~/path``
(nav_msgs/Path, transient-local) in: when its poses carry strictly increasing stamps they are
the timing of a trajectory (trajectory tracking; otherwise it moves along the path at
``trajectory_tracking.reference_speed``); an empty path in a frame cancels the path (a
planner that finds none sends one): the tracker stops and holds still (an empty path without a
frame is malformed: refused, the previous path kept). Out: ``cmd_vel`` (geometry_msgs/Twist or,
with ``enable_stamped_cmd_vel`` (Nav2's parameter), geometry_msgs/TwistStamped in ``base_frame_id``
stamped with the pose it answers, as Jazzy's diff_drive_controller takes it) and
``~/tracking_error`` (robotica_msgs/TrackingError, stamped with the pose it was computed from;
none from a law that follows no path, whose errors are NaN: ``open_loop``).
With ``command_type`` = ``steering`` (tricycle, bicycle, Ackermann) the command goes out on
``vehicle_command`` (robotica_msgs/VehicleCommand) instead: the law's speed v and the steering
angle of its curvature, α = atan(l ω / v) (book (4.119), (4.121)), l = ``wheelbase``, which
keeps its sign in reverse (v < 0: the bicycle's θ' = v tan α / l is the law's ω).

With ``control_rate`` = 0 the law runs once per pose message (what a lockstep simulation needs:
every step is answered exactly once; with ``wait_for_path``, which ``robotica run`` sets, none
before the first message on ``~/path``, so that a path delivered a few steps late does not
leave the robot standing for them); with ``control_rate`` > 0 it runs on a timer from the
newest pose and brakes when that pose is older than ``pose_timeout``. The node commands a stop
and says why when: there is no path yet (for every law, ``open_loop`` too; a refused path keeps
the previous one), the path is finished, the robot is farther than ``max_cross_track`` from the
path (lost), the pose is stale, not finite (for a law that reads it) or in another frame than
the path (the ground truth's world frame is taken as the path's: the simulator starts the
odometry frame at the true pose).
"""
import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Twist, TwistStamped
from nav_msgs.msg import Odometry, Path
from rcl_interfaces.msg import SetParametersResult
from rclpy.experimental import EventsExecutor
from robotica_ctrl.mobile.tracker_base import TrackingLaw
from robotica_ctrl.mobile.tracking_laws import (check_gains, law_for_path, LAW_PARAMETERS,
                                                steering_angle, TRACKER_PARAMETERS)
from robotica_kin.parameter_specs import check_parameters, ParameterError
from robotica_kin.ros.convert import path_postures, pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import (COMMAND_PUB_QOS, INPUT_QOS_OVERRIDES, LATCHED_QOS,
                                  STREAM_PUB_QOS, STREAM_SUB_QOS)
from robotica_msgs.msg import TrackingError, VehicleCommand

POSE_TOPICS = {'odom': 'odom', 'ground_truth': 'ground_truth/odom'}   # by pose_source


class PathTrackerNode(GuardedNode):
    """ROS shell around the tracking laws of :mod:`robotica_ctrl.mobile.tracking_laws`."""

    def __init__(self) -> None:
        super().__init__('path_tracker')
        specs = TRACKER_PARAMETERS
        params = {**declare_specs(self, {k: spec for k, spec in specs.items()
                                         if k != 'max_cross_track'}),
                  **declare_specs(self, {'max_cross_track': specs['max_cross_track']},
                                  read_only=False)}
        check_parameters(specs, params)   # the choices
        self._law_name = params['law']
        prefix = f'{self._law_name}.'
        self._gains = {name.removeprefix(prefix): value for name, value in declare_specs(
            self, {prefix + k: v for k, v in LAW_PARAMETERS[self._law_name].items()},
            read_only=False).items()}
        check_gains(self._law_name, self._gains)   # refused at start-up, not at the first path
        self._command_type = params['command_type']
        self._wheelbase = params['wheelbase']
        pose_source = params['pose_source']
        self._ground_truth = pose_source == 'ground_truth'
        self._max_cross_track = params['max_cross_track']
        self._control_rate = params['control_rate']
        self._pose_timeout = params['pose_timeout']
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._apply_parameters)

        self._law: TrackingLaw | None = None
        self._path_frame = ''
        self._pose_msg = None
        self._reported: set[str] = set()
        self._stamped = declare(self, 'enable_stamped_cmd_vel', False,
                                'cmd_vel is geometry_msgs/TwistStamped (in base_frame_id, '
                                'stamped with its pose), else Twist', read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link',
                                   'Frame of a stamped cmd_vel: the robot body', read_only=True)
        self._wait_for_path = declare(
            self, 'wait_for_path', False, 'Answer no pose before the first message on ~/path '
            '(a path, or an empty one that cancels): a lockstep simulator repeats its first step '
            'meanwhile; false: command a stop meanwhile', read_only=True)
        self._path_seen = False
        self._stamp = Time()   # of the pose last answered: a stop answers it again
        if self._command_type == 'twist':
            self._cmd_pub = self.create_publisher(TwistStamped if self._stamped else Twist,
                                                  'cmd_vel', COMMAND_PUB_QOS)
        else:
            self._cmd_pub = self.create_publisher(VehicleCommand, 'vehicle_command',
                                                  COMMAND_PUB_QOS)
        self._error_pub = self.create_publisher(TrackingError, '~/tracking_error',
                                                STREAM_PUB_QOS)
        self.create_subscription(Path, '~/path', self._on_path, LATCHED_QOS)
        self.create_subscription(Odometry, POSE_TOPICS[pose_source], self._on_odom,
                                 STREAM_SUB_QOS, qos_overriding_options=INPUT_QOS_OVERRIDES)
        if self._control_rate > 0.0:
            self.create_timer(1.0 / self._control_rate, self._on_timer)
        self.get_logger().info(f'law {self._law_name}, pose from '
                               f'{POSE_TOPICS[pose_source]}, command {self._command_type}')

    # -- parameters --------------------------------------------------------------------------
    def _changes(self, parameters) -> dict:
        prefix = self._law_name + '.'
        return {p.name.removeprefix(prefix): p.value for p in parameters
                if p.name.startswith(prefix)}

    def _validate_parameters(self, parameters) -> SetParametersResult:
        changes = self._changes(parameters)
        if changes:
            try:   # the ranges and the law's own checks, on a throw-away copy
                check_gains(self._law_name, {**self._gains, **changes})
            except (ValueError, TypeError) as err:
                named = isinstance(err, ParameterError)   # a gain's name: give the parameter's
                return SetParametersResult(successful=False, reason=(
                    f'{self._law_name}.{err}' if named else str(err)))
        return SetParametersResult(successful=True)

    def _apply_parameters(self, parameters) -> None:
        changes = self._changes(parameters)
        if changes:
            self._gains.update(changes)
            if self._law is not None:
                self._law.set_gains(changes)
            self.get_logger().info(f'gains changed: {changes}')

    # -- inputs ------------------------------------------------------------------------------
    def _on_path(self, msg: Path) -> None:
        self._path_seen = True
        if not msg.poses and msg.header.frame_id:   # a planner with no path cancels: stop
            self._law = None
            self._reported.clear()
            self.get_logger().warn('an empty path on ~/path: no path to follow, stopping')
            return
        times = [stamp_to_seconds(p.header.stamp) for p in msg.poses]
        postures = path_postures(msg)   # the headings: reversing pure pursuit's directions
        try:
            law, path, timed = law_for_path(self._law_name, postures[:, :2], self._gains,
                                            times, postures[:, 2])
        except ValueError as err:   # one bad message must not stop a run whose path came once
            self.get_logger().error(f'path refused: {err}; '
                                    + ('keeping the previous path' if self._law is not None
                                       else 'no path'))
            return
        self._law = law
        self._path_frame = msg.header.frame_id
        self._reported.clear()
        timing = f', timed from {times[0]:.2f} s to {times[-1]:.2f} s' if timed else ''
        self.get_logger().info(f'following a path of {path.length:.2f} m in frame '
                               f'{self._path_frame!r}{timing}')

    def _on_odom(self, msg: Odometry) -> None:
        self._pose_msg = msg
        if self._wait_for_path and not self._path_seen:
            self.get_logger().info('waiting for a path on ~/path: pose not answered',
                                   throttle_duration_sec=1.0)
            return
        if self._control_rate == 0.0:
            self._control(msg)

    def _on_timer(self) -> None:
        msg = self._pose_msg
        now = self.get_clock().now().nanoseconds * 1e-9
        if msg is None or now - stamp_to_seconds(msg.header.stamp) > self._pose_timeout:
            self._stop('no pose newer than pose_timeout: stopping')
            return
        self._control(msg)

    # -- control -----------------------------------------------------------------------------
    def _report(self, key: str, text: str, warn: bool = True) -> None:
        """Log ``text`` once until the next path."""
        if key not in self._reported:
            self._reported.add(key)
            if warn:   # one call site per severity: rclpy refuses a site that changes it
                self.get_logger().warn(text)
            else:
                self.get_logger().info(text)

    def on_callback_error(self, source: str) -> None:
        """Command a stop: the guard dropped an input (or a non-finite command) on ``source``."""
        self._publish_command(0.0, 0.0)

    def _stop(self, reason: str) -> None:
        self._report(reason, reason)
        self._publish_command(0.0, 0.0)

    def _publish_command(self, linear: float, angular: float) -> None:
        """Publish (v [m/s], ω [rad/s]) as a Twist or as a speed and a steering angle."""
        if self._command_type == 'twist':
            twist = Twist()
            twist.linear.x = linear
            twist.angular.z = angular
            if self._stamped:
                command = TwistStamped(twist=twist)
                command.header.stamp = self._stamp
                command.header.frame_id = self._base_frame
                self._cmd_pub.publish(command)
            else:
                self._cmd_pub.publish(twist)
            return
        self._cmd_pub.publish(VehicleCommand(
            speed=linear, steering_angle=steering_angle(linear, angular, self._wheelbase)))

    def _control(self, msg: Odometry) -> None:
        time = stamp_to_seconds(msg.header.stamp)
        self._stamp = msg.header.stamp
        if self._law is None:
            self._stop('no path received on ~/path yet: holding still')
            return
        if self._ground_truth and msg.header.frame_id != self._path_frame:
            self._report('frames', f'ground truth in frame {msg.header.frame_id!r} taken as the '
                         f'path frame {self._path_frame!r} (the simulator starts the odometry '
                         'at the true pose)', warn=False)
        elif msg.header.frame_id != self._path_frame:
            self._stop(f'pose frame {msg.header.frame_id!r} differs from path frame '
                       f'{self._path_frame!r}: stopping')
            return
        pose = pose2d_from_odometry(msg)
        speed = msg.twist.twist.linear.x
        try:
            output = self._law.update(pose, time, speed if math.isfinite(speed) else None)
        except ValueError as err:
            self._stop(f'pose refused ({err}): stopping')
            return
        if abs(output.cross_track) > self._max_cross_track:   # never for NaN: no path
            self._stop(f'path lost: {abs(output.cross_track):.2f} m from it, more than '
                       f'max_cross_track ({self._max_cross_track} m): stopping')
        else:
            self._publish_command(output.linear, output.angular)
        if output.finished:
            self._report('finished', 'path finished: stopped at its end', warn=False)
        if math.isnan(output.cross_track):   # a law that follows no path measures no error
            return
        error = TrackingError(cross_track=output.cross_track, heading=output.heading_error,
                              along_track=output.along_track,
                              target_point=Point(x=float(output.target_point[0]),
                                                 y=float(output.target_point[1])))
        error.header = msg.header
        self._error_pub.publish(error)


def main(args=None) -> None:
    """Run the path tracker until Ctrl-C."""
    run_node(PathTrackerNode, args, executor_factory=EventsExecutor)
