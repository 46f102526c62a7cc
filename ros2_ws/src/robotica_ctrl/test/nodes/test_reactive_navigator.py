"""
Node tests of reactive_navigator: one command per pose from real scans, safe stops, bad input.

Reference: a laser at base_link's origin sees a wall along y = 0.7 m on the left; the set
distance is 0.5 m, so wall following turns left, ω = -k1 v ξ = -4 · 0.3 · (0.5 - 0.7) = 0.24
rad/s (law (9.93), clearance ahead infinite: no slow-down).
"""
import math
import signal

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan, Range
from std_msgs.msg import String

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
BEAMS = 181   # -90° .. 90°, 1° apart


def odom(t):
    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), int(round((t % 1) * 1e9))
    msg.header.frame_id = 'odom'
    msg.pose.pose.orientation.w = 1.0
    return msg


def wall_scan(t, nan_beams=0):
    """Return a scan of the wall y = 0.7 m (left); the first ``nan_beams`` beams NaN."""
    msg = LaserScan(angle_min=-math.pi / 2, angle_increment=math.pi / 180, range_min=0.05,
                    range_max=4.0)
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), int(round((t % 1) * 1e9))
    ranges = []
    for k in range(BEAMS):
        a = msg.angle_min + k * msg.angle_increment
        ranges.append(0.7 / math.sin(a) if math.sin(a) > 0.7 / 4.0 else math.inf)
    msg.ranges = [math.nan] * nan_beams + ranges[nan_beams:]
    return msg


@pytest.fixture
def navigator(start_node, ros_node, spin):
    def start(*ros_args):
        node, executor = ros_node
        proc = start_node('robotica_ctrl', 'reactive_navigator', *ros_args)
        cmds, states = [], []
        node.create_subscription(Twist, 'cmd_vel', cmds.append, QOS)
        node.create_subscription(String, '/reactive_navigator/state',
                                 lambda m: states.append(m.data), LATCHED)
        pose = node.create_publisher(Odometry, 'odom', QOS)
        scan = node.create_publisher(LaserScan, 'scan', QOS)
        assert spin(executor, lambda: pose.get_subscription_count() > 0
                    and scan.get_subscription_count() > 0
                    and node.count_publishers('cmd_vel') > 0)
        return proc, executor, pose, scan, cmds, states
    return start


def answered(cmds, count):
    return lambda: len(cmds) > count


def test_follows_a_wall_seen_by_the_laser(navigator, publish, spin):
    proc, executor, pose, scan, cmds, states = navigator()
    assert publish(executor, pose, odom(1.0), answered(cmds, 0))   # no scan yet: a stop
    assert (cmds[-1].linear.x, cmds[-1].angular.z) == (0.0, 0.0)
    assert spin(executor, lambda: 'no_ranges' in states)
    scan.publish(wall_scan(1.0))
    assert publish(executor, pose, odom(1.02), lambda: cmds and cmds[-1].linear.x > 0.0)
    assert cmds[-1].linear.x == pytest.approx(0.3)
    assert cmds[-1].angular.z == pytest.approx(0.24, abs=1e-6)
    assert spin(executor, lambda: states[-1:] == ['following']), states


def test_nan_ranges_stop_the_robot(navigator, publish, spin, read_output):
    proc, executor, pose, scan, cmds, states = navigator()
    scan.publish(wall_scan(1.0, nan_beams=120))   # 120 of 181 erroneous
    assert publish(executor, pose, odom(1.0), lambda: 'unreliable_ranges' in states and cmds)
    assert (cmds[-1].linear.x, cmds[-1].angular.z) == (0.0, 0.0)
    assert '66 % of the readings are NaN (erroneous), more than 50 %' in read_output(proc)
    scan.publish(wall_scan(1.1))                   # a good scan: it drives again
    assert publish(executor, pose, odom(1.1), lambda: cmds[-1].linear.x > 0.0)
    assert proc.poll() is None
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=10) == 0


def test_a_sonar_ring(navigator, publish, ros_node):
    node, _ = ros_node
    proc, executor, pose, scan, cmds, states = navigator(
        '-p', 'range.topics:=[sonar_0,sonar_1]',
        '-p', 'range.poses:=[0.1,0.1,1.5707963267948966,0.1,-0.1,-1.5707963267948966]',
        '-p', 'behaviour:=corridor_centring')
    sonars = [node.create_publisher(Range, f'sonar_{i}', QOS) for i in range(2)]
    for sonar, distance in zip(sonars, (0.9, 0.5)):   # walls at y = 1.0 and y = -0.6
        msg = Range(radiation_type=Range.ULTRASOUND, min_range=0.02, max_range=3.0,
                    range=distance)
        msg.header.stamp.sec = 1
        sonar.publish(msg)
    # One point a side is no wall line (three are needed): the corridor is not seen.
    assert publish(executor, pose, odom(1.0), lambda: 'no_wall' in states)


@pytest.mark.parametrize('args, message', [
    (['-p', 'range.topics:=[a,b]', '-p', 'range.poses:=[0.0,0.0,0.0]'],
     'range.poses needs 3 numbers for each of the 2 range.topics, got 3'),
    (['-p', 'behaviour:=fly'], 'behaviour'),
    (['-p', 'wall.k_distance:=-1.0'], 'wall.k_distance'),
])
def test_bad_parameters_exit_2(start_node, args, message, read_output):
    proc = start_node('robotica_ctrl', 'reactive_navigator', *args)
    assert proc.wait(timeout=30) == 2
    out = read_output(proc)
    assert message in out and 'Traceback' not in out


def test_in_lockstep_a_pose_waits_for_the_scan_due(navigator, publish, spin):
    # Scans every 0.1 s from t = 0: the pose at 0 waits for the scan of 0, the pose at 0.06
    # needs none newer (the next is due at 0.1), the pose at 0.1 waits for the scan of 0.1.
    proc, executor, pose, scan, cmds, states = navigator(
        '-p', 'wait_for_ranges:=true', '-p', 'laser.period:=0.1')
    pose.publish(odom(0.0))
    assert not spin(executor, lambda: cmds, timeout=1.0)    # held: its scan has not come
    scan.publish(wall_scan(0.0))
    assert spin(executor, lambda: len(cmds) == 1)
    assert cmds[-1].angular.z == pytest.approx(0.24, abs=1e-6)   # answered with that scan
    pose.publish(odom(0.06))
    assert spin(executor, lambda: len(cmds) == 2)
    pose.publish(odom(0.1))
    assert not spin(executor, lambda: len(cmds) == 3, timeout=1.0)
    scan.publish(wall_scan(0.1))
    assert spin(executor, lambda: len(cmds) == 3)
