"""
Node tests of the simulator: motion under a command, the stale-command brake, refused input.

With a world, a circle of radius r = 0.3 m driven at 1 m/s towards a wall at x = 1.005 m stops
at x = 0.705 m (t = 0.705 s, in step 36 of 20 ms); steps 37 to 75 (end_time 1.5 s) begin in
contact: 39 steps, 0.78 s in contact (hand computation).

A 0.5 m/s forward command for the differential drive of the default parameters moves the robot
along +x (REP-103); once no command arrives for cmd_timeout, the ground-truth twist is zero.
"""
import math
import time
from xml.etree import ElementTree

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.urdf import vehicle_urdf
from robotica_msgs.msg import Contact, SimulatorStatus, VehicleCommand
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
CMD_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)


def test_drives_then_brakes_when_commands_stop(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'simulator', '-p', 'cmd_timeout:=0.3')
    truth, clock = [], []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    node.create_subscription(Clock, '/clock', clock.append, QOS)
    cmd = node.create_publisher(Twist, 'cmd_vel', CMD_QOS)
    assert spin(executor, lambda: cmd.get_subscription_count() > 0 and truth)
    forward = Twist()
    forward.linear.x = 0.5
    for _ in range(20):                          # 1 s of commands at 20 Hz (wall clock)
        cmd.publish(forward)
        spin(executor, lambda: False, timeout=0.05)
    moving = truth[-1]
    assert moving.twist.twist.linear.x == pytest.approx(0.5, abs=1e-9)
    assert moving.pose.pose.position.x > 0.1
    assert abs(moving.pose.pose.position.y) < 1e-9
    n = len(truth)
    assert spin(executor, lambda: len(truth) > n + 30)   # > 0.6 s later: stale
    assert truth[-1].twist.twist.linear.x == 0.0
    assert 'command stale' in read_output(proc)
    stamps = [c.clock.sec + c.clock.nanosec * 1e-9 for c in clock]
    assert all(b > a for a, b in zip(stamps, stamps[1:])), 'simulated time must increase'


def test_nan_command_brakes(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'simulator')
    truth = []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    cmd = node.create_publisher(Twist, 'cmd_vel', CMD_QOS)
    assert spin(executor, lambda: cmd.get_subscription_count() > 0 and truth)
    bad = Twist()
    bad.linear.x = math.nan
    for _ in range(10):
        cmd.publish(bad)
        spin(executor, lambda: False, timeout=0.05)
    assert truth[-1].twist.twist.linear.x == 0.0
    assert math.isfinite(truth[-1].pose.pose.position.x)
    assert proc.poll() is None
    assert 'cmd_vel: ValueError' in read_output(proc)


def stamped(x, frame_id='base_link'):
    msg = TwistStamped()
    msg.header.frame_id = frame_id
    msg.twist.linear.x = x
    return msg


def test_stamped_commands_drive_and_bad_ones_brake(start_node, ros_node, spin, publish,
                                                   read_output):
    # enable_stamped_cmd_vel: TwistStamped in base_link drives (0.5 m/s along +x); one in
    # another frame or with a NaN is refused as a bad Twist is: one log line, a brake.
    node, executor = ros_node
    proc = start_node('robotica_sim', 'simulator', '-p', 'enable_stamped_cmd_vel:=true')
    truth = []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    cmd = node.create_publisher(TwistStamped, 'cmd_vel', CMD_QOS)
    assert spin(executor, lambda: cmd.get_subscription_count() > 0 and truth)
    for bad in (stamped(0.5, 'odom'), stamped(math.nan)):
        quiet = time.monotonic() + 1.1   # the guard logs a source at most once a second
        assert publish(executor, cmd, stamped(0.5), lambda: time.monotonic() > quiet and
                       truth[-1].twist.twist.linear.x == pytest.approx(0.5, abs=1e-9),
                       period=0.05)
        assert publish(executor, cmd, bad, lambda: truth[-1].twist.twist.linear.x == 0.0,
                       period=0.05)
    assert truth[-1].pose.pose.position.x > 0.1
    assert proc.poll() is None
    text = read_output(proc)
    assert "cmd_vel: ValueError: TwistStamped in frame 'odom', not 'base_link'" in text
    assert text.count('cmd_vel: ValueError') == 2   # one line each: the guard throttles


def test_truth_is_a_frame_on_tf_stamped_with_its_step(start_node, ros_node, spin):
    # map -> base_link_truth is the ground-truth pose of the same step: same stamp, same pose.
    node, executor = ros_node
    start_node('robotica_sim', 'simulator', '-p', 'initial_pose.x:=1.5',
               '-p', 'initial_pose.theta:=0.5')
    truth, tf = [], []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    node.create_subscription(TFMessage, '/tf', tf.append, QOS)
    assert spin(executor, lambda: len(tf) >= 5 and len(truth) >= 5)
    poses = {(o.header.stamp.sec, o.header.stamp.nanosec): o.pose.pose for o in truth}
    for msg in tf[-3:]:
        [transform] = msg.transforms
        assert (transform.header.frame_id, transform.child_frame_id) == ('map', 'base_link_truth')
        pose = poses[(transform.header.stamp.sec, transform.header.stamp.nanosec)]
        assert transform.transform.translation.x == pose.position.x == 1.5
        assert transform.transform.rotation.z == pose.orientation.z == pytest.approx(
            math.sin(0.25), abs=1e-15)


@pytest.mark.parametrize('vehicle_type', ['bicycle', 'mecanum'])
def test_joint_states_name_joints_of_the_vehicle_urdf(start_node, ros_node, spin, vehicle_type):
    # The state publisher draws the wheels turning only if joint_states names URDF joints.
    node, executor = ros_node
    start_node('robotica_sim', 'simulator', '-p', f'vehicle.type:={vehicle_type}')
    joints = []
    node.create_subscription(JointState, 'joint_states', joints.append, QOS)
    assert spin(executor, lambda: joints)
    moving = {j.get('name') for j in ElementTree.fromstring(vehicle_urdf(vehicle_type)).iter(
        'joint') if j.get('type') != 'fixed'}
    assert set(joints[-1].name) <= moving
    assert {'left_odometry_wheel_joint', 'right_odometry_wheel_joint'} <= set(joints[-1].name)


def test_unknown_pacing_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'simulator', '-p', 'pacing:=fast')
    assert proc.wait(timeout=30) == 2
    assert 'pacing must be one of' in read_output(proc)


def test_tricycle_takes_vehicle_commands(start_node, ros_node, spin):
    # (v, α) = (0.5 m/s, 0.3 rad) with l = 0.5 m: yaw rate v tan α / l (4.121), lockstep.
    node, executor = ros_node
    start_node('robotica_sim', 'simulator', '-p', 'vehicle.type:=tricycle',
               '-p', 'vehicle.wheelbase:=0.5', '-p', 'pacing:=lockstep', '-p', 'end_time:=1.0')
    truth = []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    cmd = node.create_publisher(VehicleCommand, 'vehicle_command', CMD_QOS)

    def answer(msg):
        cmd.publish(VehicleCommand(speed=0.5, steering_angle=0.3))

    node.create_subscription(Odometry, 'ground_truth/odom', answer, QOS)
    assert spin(executor, lambda: truth and truth[-1].header.stamp.sec >= 1, timeout=30)
    last = truth[-1]
    assert last.twist.twist.angular.z == pytest.approx(0.5 * math.tan(0.3) / 0.5, rel=1e-9)
    assert last.pose.pose.position.y > 0.05          # turned left


def test_unknown_vehicle_type_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'simulator', '-p', 'vehicle.type:=hovercraft')
    assert proc.wait(timeout=30) == 2
    assert 'vehicle.type must be one of' in read_output(proc)


def test_slip_beyond_its_range_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'simulator', '-p', 'longitudinal_slip:=0.95')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'longitudinal_slip' in text and 'Traceback' not in text


def test_a_world_stops_the_robot_at_a_wall_and_the_bumper_reports_it(start_node, ros_node,
                                                                     spin, tmp_path):
    node, executor = ros_node
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[1.005, -2.0, 1.005, 2.0]]\n')
    start_node('robotica_sim', 'simulator', '-p', f'world_file:={world}',
               '-p', 'footprint.radius:=0.3', '-p', 'pacing:=lockstep', '-p', 'end_time:=1.5')
    truth, bumper, status = [], [], []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, QOS)
    node.create_subscription(Contact, 'bumper', bumper.append, QOS)
    node.create_subscription(SimulatorStatus, '/simulator/status', status.append, QOS)
    cmd = node.create_publisher(Twist, 'cmd_vel', CMD_QOS)
    forward = Twist()
    forward.linear.x = 1.0
    node.create_subscription(Odometry, 'ground_truth/odom', lambda _: cmd.publish(forward), QOS)
    assert spin(executor, lambda: status and status[-1].finished, timeout=60)
    assert truth[-1].pose.pose.position.x == pytest.approx(0.705, abs=1e-9)
    assert truth[-1].twist.twist.linear.x == 0.0
    last = bumper[-1]
    assert last.in_contact and last.contacts == 1 and last.header.frame_id == 'map'
    assert (last.point.x, last.point.y) == pytest.approx((1.005, 0.0), abs=1e-9)
    assert (last.normal.x, last.normal.y) == pytest.approx((-1.0, 0.0), abs=1e-9)
    assert not bumper[0].in_contact and math.isnan(bumper[0].point.x)
    assert status[-1].contacts == 1
    assert status[-1].time_in_contact == pytest.approx(0.78, abs=1e-9)


def test_a_missing_world_file_is_one_line_and_exit_2(start_node, read_output, tmp_path):
    proc = start_node('robotica_sim', 'simulator', '-p', f'world_file:={tmp_path}/none.yaml')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'none.yaml: cannot read the world file' in text and 'Traceback' not in text
