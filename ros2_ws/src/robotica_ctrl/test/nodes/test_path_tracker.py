"""
Node tests of path_tracker: commands from real messages, safe stops, refused gains.

Reference: a robot at (0, 0.5) heading +x beside the straight path y = 0 is left of the path,
so its cross-track error is +0.5 m and pure pursuit turns it right (negative yaw rate). Reversing
pure pursuit: the book's curvature (9.5) γ = 2 y / L² of the goal point (x, y) seen from the
vehicle turned round, worked in the test.
"""
import math

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry, Path
import numpy as np
import pytest
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.convert import path_message
from robotica_msgs.msg import TrackingError, VehicleCommand

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _odom(x, y, theta, frame='odom'):
    msg = Odometry()
    msg.header.frame_id = frame
    msg.pose.pose.position.x = x
    msg.pose.pose.position.y = y
    msg.pose.pose.orientation.z = math.sin(theta / 2)
    msg.pose.pose.orientation.w = math.cos(theta / 2)
    return msg


def _straight_path():
    """Return 101 poses along x, 0.1 m apart, in odom."""
    return path_message(np.column_stack([0.1 * np.arange(101), np.zeros(101)]), 'odom')


def _start_tracker(start_node, ros_node, spin, *params, command=Twist):
    """Start a path tracker with ``params`` (-p ...); return it and the test's ends."""
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'path_tracker', '-r', '/path_tracker/path:=/path',
                      *params)
    cmds, errors = [], []
    node.create_subscription(command, 'cmd_vel', cmds.append, QOS)
    node.create_subscription(TrackingError, '/path_tracker/tracking_error', errors.append, QOS)
    odom = node.create_publisher(Odometry, 'odom', QOS)
    path = node.create_publisher(Path, '/path', LATCHED)
    assert spin(executor, lambda: odom.get_subscription_count() > 0 and
                path.get_subscription_count() > 0 and node.count_publishers('cmd_vel') > 0)
    return proc, node, executor, odom, path, cmds, errors


@pytest.fixture
def tracker(start_node, ros_node, spin):
    return _start_tracker(start_node, ros_node, spin)


def test_no_path_means_stop(tracker, publish, read_output):
    proc, node, executor, odom, path, cmds, errors = tracker
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0), lambda: cmds)
    assert cmds[-1].linear.x == 0.0 and cmds[-1].angular.z == 0.0
    assert 'no path' in read_output(proc)


def test_waiting_for_a_path_answers_no_pose_until_one_comes(start_node, ros_node, spin, publish,
                                                            read_output):
    # What robotica run sets: in lockstep the simulator repeats its first step meanwhile, so a
    # path delivered late does not leave the robot standing for the steps it missed.
    proc, node, executor, odom, path, cmds, _ = _start_tracker(
        start_node, ros_node, spin, '-p', 'wait_for_path:=true')
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0),
                   lambda: 'waiting for a path on ~/path: pose not answered' in read_output(proc))
    assert cmds == []                                  # no pose answered, not even a stop
    path.publish(_straight_path())
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0), lambda: cmds and cmds[-1].linear.x > 0)


def test_turns_towards_the_path(tracker, publish, spin):
    proc, node, executor, odom, path, cmds, errors = tracker
    path.publish(_straight_path())
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0), lambda: errors)
    assert errors[-1].cross_track == pytest.approx(0.5, abs=1e-9)
    assert errors[-1].heading == pytest.approx(0.0, abs=1e-9)
    assert spin(executor, lambda: cmds and cmds[-1].linear.x != 0.0)   # after any 'no path' stop
    assert cmds[-1].linear.x > 0.0
    assert cmds[-1].angular.z < 0.0


def test_an_empty_path_cancels_the_path_and_stops(tracker, publish, spin, read_output):
    proc, node, executor, odom, path, cmds, errors = tracker
    path.publish(_straight_path())
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0), lambda: cmds and cmds[-1].linear.x > 0)
    path.publish(Path(header=_straight_path().header))   # a planner with no path sends this
    assert spin(executor, lambda: 'empty path' in read_output(proc))
    assert publish(executor, odom, _odom(0.1, 0.5, 0.0),
                   lambda: cmds and cmds[-1].linear.x == 0.0 and cmds[-1].angular.z == 0.0)
    assert proc.poll() is None


def test_nan_pose_and_wrong_frame_stop(tracker, publish, read_output):
    proc, node, executor, odom, path, cmds, errors = tracker
    path.publish(_straight_path())
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0), lambda: errors)   # path received

    def stopped_since(count):
        return lambda: len(cmds) > count and (cmds[-1].linear.x, cmds[-1].angular.z) == (0, 0)

    assert publish(executor, odom, _odom(math.nan, 0.5, 0.0), stopped_since(len(cmds)))
    assert publish(executor, odom, _odom(0.0, 0.5, 0.0, frame='map'), stopped_since(len(cmds)))
    assert proc.poll() is None
    text = read_output(proc)
    assert 'pose refused' in text and 'differs from path frame' in text


def test_stamped_commands_carry_the_pose_stamp_and_base_link(start_node, ros_node, spin, publish):
    # enable_stamped_cmd_vel: the same command as a Twist (left of the path: turn right), as a
    # TwistStamped in base_link stamped with the pose it answers (t = 3.25 s).
    _, node, executor, odom, path, cmds, _ = _start_tracker(
        start_node, ros_node, spin, '-p', 'enable_stamped_cmd_vel:=true', command=TwistStamped)
    [info] = node.get_publishers_info_by_topic('/cmd_vel')
    assert info.topic_type == 'geometry_msgs/msg/TwistStamped'
    path.publish(_straight_path())
    msg = _odom(0.0, 0.5, 0.0)
    msg.header.stamp.sec, msg.header.stamp.nanosec = 3, 250_000_000
    assert publish(executor, odom, msg, lambda: cmds and cmds[-1].twist.linear.x != 0.0)
    assert cmds[-1].header.frame_id == 'base_link'
    assert (cmds[-1].header.stamp.sec, cmds[-1].header.stamp.nanosec) == (3, 250_000_000)
    assert cmds[-1].twist.linear.x > 0.0 and cmds[-1].twist.angular.z < 0.0


def test_stamped_commands_drive_a_consumer_configured_as_diff_drive_controller(
        start_node, ros_node, spin):
    # Jazzy's diff_drive_controller takes TwistStamped in base_link; the simulator configured
    # so (enable_stamped_cmd_vel, base_frame_id base_link) refuses anything else and brakes.
    # Tracker and simulator together: the robot, at the start of a straight path along +x,
    # moves along it.
    node, executor = ros_node
    stamped = ('-p', 'enable_stamped_cmd_vel:=true')
    start_node('robotica_sim', 'simulator', *stamped, '-p', 'base_frame_id:=base_link')
    start_node('robotica_ctrl', 'path_tracker', *stamped, '-r', '/path_tracker/path:=/path',
               '-p', 'pose_source:=ground_truth')
    truth = []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    path = node.create_publisher(Path, '/path', LATCHED)
    assert spin(executor, lambda: path.get_subscription_count() > 0)
    path.publish(_straight_path())
    assert spin(executor, lambda: truth and truth[-1].pose.pose.position.x > 0.2, timeout=20)
    assert abs(truth[-1].pose.pose.position.y) < 1e-6
    assert truth[-1].twist.twist.linear.x > 0.0


def test_invalid_gain_is_refused_with_reason(tracker, call):
    proc, node, executor, odom, path, cmds, errors = tracker
    client = node.create_client(SetParameters, '/path_tracker/set_parameters')
    value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=5.0)
    request = SetParameters.Request(parameters=[
        Parameter(name='pure_pursuit.min_approach_velocity', value=value)])
    response = call(executor, client, request)
    assert response is not None
    result = response.results[0]
    assert not result.successful
    assert 'min_approach_velocity' in result.reason


def test_open_loop_profile_as_steering_commands(start_node, ros_node, spin, publish, call):
    # Ej. 4.8: v = 1 m/s, ω = 1 rad/s on a tricycle of l = 1.5 m: α = atan(l ω / v) = 56.31°.
    # The profile ramps v from 1 to 2 m/s over 10 s: at t = 5 s, v = 1.5 m/s. Like every law
    # it starts with the first path; it publishes no tracking error (it follows none).
    node, executor = ros_node
    start_node('robotica_ctrl', 'path_tracker', '-r', '/path_tracker/path:=/path',
               '-p', 'law:=open_loop', '-p', 'command_type:=steering', '-p', 'wheelbase:=1.5',
               '-p', 'open_loop.times:=[0.0, 10.0]', '-p', 'open_loop.linear:=[1.0, 2.0]',
               '-p', 'open_loop.angular:=[1.0, 1.0]')
    commands, errors = [], []
    node.create_subscription(VehicleCommand, 'vehicle_command', commands.append, QOS)
    node.create_subscription(TrackingError, '/path_tracker/tracking_error', errors.append, QOS)
    odom = node.create_publisher(Odometry, 'odom', QOS)
    path = node.create_publisher(Path, '/path', LATCHED)
    assert spin(executor, lambda: odom.get_subscription_count() > 0 and
                path.get_subscription_count() > 0)
    path.publish(_straight_path())
    msg = _odom(0.0, 0.0, 0.0)
    assert publish(executor, odom, msg, lambda: commands and commands[-1].speed != 0.0)
    assert commands[-1].speed == pytest.approx(1.0, abs=1e-12)
    assert math.degrees(commands[-1].steering_angle) == pytest.approx(56.3099, abs=1e-4)
    msg.header.stamp.sec = 5
    # Answers to stamp-0 poses still in flight may come first: wait past them (speed 1.0).
    n = len(commands)
    assert publish(executor, odom, msg, lambda: len(commands) > n and commands[-1].speed != 1.0)
    assert commands[-1].speed == pytest.approx(1.5, abs=1e-12)
    assert commands[-1].steering_angle == pytest.approx(math.atan(1.5 / 1.5), abs=1e-12)
    assert not errors
    # Its profile is a gain like any other: checked when changed.
    client = node.create_client(SetParameters, '/path_tracker/set_parameters')
    value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[1.0])
    response = call(executor, client, SetParameters.Request(parameters=[
        Parameter(name='open_loop.linear', value=value)]))
    assert response is not None
    assert not response.results[0].successful
    assert 'same length' in response.results[0].reason


def test_bad_open_loop_profile_is_refused(start_node, read_output):
    proc = start_node('robotica_ctrl', 'path_tracker', '-p', 'law:=open_loop',
                      '-p', 'open_loop.times:=[0.0, 0.0]', '-p', 'open_loop.linear:=[1.0, 2.0]',
                      '-p', 'open_loop.angular:=[1.0, 1.0]')
    assert proc.wait(timeout=30) == 2
    assert 'times must increase strictly' in read_output(proc)


def test_frenet_law_on_ground_truth_and_lost_path_stop(start_node, ros_node, spin, publish,
                                                       read_output):
    # Frenet linear law (9.93) with k1 = 1, k2 = 2, v = 0.5: u = -k1 v d = -0.25 at d = 0.5 m.
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'path_tracker', '-r', '/path_tracker/path:=/path',
                      '-p', 'law:=frenet', '-p', 'pose_source:=ground_truth',
                      '-p', 'frenet.k1:=1.0', '-p', 'frenet.k2:=2.0',
                      '-p', 'max_cross_track:=1.0')
    cmds, errors = [], []
    node.create_subscription(Twist, 'cmd_vel', cmds.append, QOS)
    node.create_subscription(TrackingError, '/path_tracker/tracking_error', errors.append, QOS)
    truth = node.create_publisher(Odometry, 'ground_truth/odom', QOS)
    path = node.create_publisher(Path, '/path', LATCHED)
    assert spin(executor, lambda: truth.get_subscription_count() > 0 and
                path.get_subscription_count() > 0)
    path.publish(_straight_path())
    assert publish(executor, truth, _odom(0.0, 0.5, 0.0, frame='map'), lambda: errors)
    assert errors[-1].cross_track == pytest.approx(0.5, abs=1e-9)
    assert spin(executor, lambda: cmds and cmds[-1].linear.x != 0.0)
    assert cmds[-1].linear.x == pytest.approx(0.5)
    assert cmds[-1].angular.z == pytest.approx(-0.25, abs=0.02)   # c(s) = 0 on a line
    n = len(cmds)
    assert publish(executor, truth, _odom(1.0, 1.5, 0.0, frame='map'),
                   lambda: len(cmds) > n and cmds[-1].linear.x == 0.0)
    text = read_output(proc)
    assert 'path lost' in text and 'taken as the path frame' in text
    assert proc.poll() is None


def test_unknown_pose_source_is_refused(start_node, read_output):
    proc = start_node('robotica_ctrl', 'path_tracker', '-p', 'pose_source:=bogus')
    assert proc.wait(timeout=30) == 2
    assert "pose_source must be one of ('odom', 'ground_truth')" in read_output(proc)


def _there_and_back():
    """Return a path of postures 1 m forward along x and back, heading 0 throughout, in odom."""
    x = np.concatenate([np.linspace(0.0, 1.0, 11), np.linspace(0.9, 0.0, 10)])
    return path_message(np.column_stack([x, np.zeros_like(x), np.zeros_like(x)]), 'odom')


def _reversing_tracker(start_node, ros_node, spin, *params):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'path_tracker', '-r', '/path_tracker/path:=/path',
                      '-p', 'law:=reversing_pure_pursuit', *params)
    odom = node.create_publisher(Odometry, 'odom', QOS)
    path = node.create_publisher(Path, '/path', LATCHED)
    assert spin(executor, lambda: odom.get_subscription_count() > 0 and
                path.get_subscription_count() > 0)
    path.publish(_there_and_back())
    return proc, node, executor, odom


def _drive_to_the_cusp(executor, odom, publish, speeds):
    """Feed poses on the forward piece, then the cusp; return the speeds from the cusp on."""
    assert publish(executor, odom, _odom(0.0, 0.0, 0.0), lambda: speeds() and speeds()[-1] > 0)
    n = len(speeds())
    assert publish(executor, odom, _odom(0.5, 0.0, 0.0), lambda: len(speeds()) > n)
    assert speeds()[-1] == pytest.approx(0.5)   # cruise: 0.5 m from the end = approach_distance
    n = len(speeds())
    assert publish(executor, odom, _odom(1.0, 0.0, 0.0), lambda: speeds()[-1] < 0.0)
    return speeds()[n:]


def test_reversing_pure_pursuit_backs_up_after_the_cusp(start_node, ros_node, spin, publish):
    # Forward poses are answered with v > 0; the pose at the cusp ends the forward piece: a
    # stop (0, 0), then the reverse piece from the same pose: v = -0.5 m/s, straight back.
    proc, node, executor, odom = _reversing_tracker(start_node, ros_node, spin)
    cmds, errors = [], []
    node.create_subscription(Twist, 'cmd_vel', cmds.append, QOS)
    node.create_subscription(TrackingError, '/path_tracker/tracking_error', errors.append, QOS)
    assert spin(executor, lambda: node.count_publishers('cmd_vel') > 0)
    after = _drive_to_the_cusp(executor, odom, publish, lambda: [c.linear.x for c in cmds])
    turn = next(k for k, v in enumerate(after) if v <= 0.0)   # answers to 0.5 m may come first
    assert after[turn] == 0.0 and after[turn + 1] == pytest.approx(-0.5)
    assert cmds[-1].angular.z == pytest.approx(0.0, abs=1e-12)
    # Left of the path (y = +0.1) while backing, facing +x: the error is left of the heading.
    n = len(errors)
    assert publish(executor, odom, _odom(0.7, 0.1, 0.0), lambda: len(errors) > n and
                   errors[-1].cross_track != 0.0)
    assert errors[-1].cross_track == pytest.approx(0.1, abs=1e-9)
    assert errors[-1].heading == pytest.approx(0.0, abs=1e-9)
    assert cmds[-1].linear.x == pytest.approx(-0.5) and proc.poll() is None


def test_reversing_with_steering_commands_a_negative_speed(start_node, ros_node, spin, publish):
    # command_type steering on a car of l = 1.5 m: on the reverse piece the speed is < 0. At
    # (0.7, 0.1), heading 0, the turned vehicle (heading π) is 0.3 m along the reverse piece;
    # its goal point L = 0.5 m on is (0.2, 0) [odom], at (x, y) = (0.5, 0.1) in its frame:
    # γ = 2 (0.1) / (0.5² + 0.1²) = 0.769 1/m, ω = 0.5 γ, and the car's steering
    # α = atan(l ω / v) with v = -0.5 m/s: -0.857 rad (steer right, the nose swings left).
    proc, node, executor, odom = _reversing_tracker(start_node, ros_node, spin,
                                                    '-p', 'command_type:=steering',
                                                    '-p', 'wheelbase:=1.5')
    commands = []
    node.create_subscription(VehicleCommand, 'vehicle_command', commands.append, QOS)
    assert spin(executor, lambda: node.count_publishers('vehicle_command') > 0)
    after = _drive_to_the_cusp(executor, odom, publish, lambda: [c.speed for c in commands])
    assert after[-1] == pytest.approx(-0.5) and 0.0 in after
    n = len(commands)
    assert publish(executor, odom, _odom(0.7, 0.1, 0.0), lambda: len(commands) > n and
                   commands[-1].steering_angle != 0.0)
    gamma = 2.0 * 0.1 / (0.5 ** 2 + 0.1 ** 2)
    assert commands[-1].speed == pytest.approx(-0.5)
    assert commands[-1].steering_angle == pytest.approx(math.atan(1.5 * 0.5 * gamma / -0.5),
                                                        abs=1e-9)
    assert commands[-1].steering_angle == pytest.approx(-0.857, abs=1e-3)
