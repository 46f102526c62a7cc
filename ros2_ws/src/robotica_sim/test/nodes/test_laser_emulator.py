"""
Node tests of laser_emulator: a scan of a wall, a NaN pose survived, a missing world refused.

The world is one wall x = 3 m from y = -5 to 5 m; the scanner at the robot's origin looks
along x with the default 180° fan at 0.5° (361 beams, beam 180 straight ahead). By hand: the
beam at angle a meets the wall at 3 / cos a while 3 |tan a| <= 5 (|a| <= 59.04°), else nothing
(+inf, REP-117).
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import LaserScan

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def truth(t, x, y=0.0):
    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    msg.header.frame_id = 'map'
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.w = 1.0
    return msg


def test_scan_of_a_wall_and_a_nan_pose_survived(tmp_path, start_node, ros_node, spin):
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[3.0, -5.0, 3.0, 5.0]]\n')
    node, executor = ros_node
    start_node('robotica_sim', 'laser_emulator', '-p', f'world_file:={world}',
               '-p', 'range_noise:=0.0', '-p', 'seed:=3')
    scans = []
    node.create_subscription(LaserScan, 'scan', scans.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('scan') > 0)
    pub.publish(truth(0.0, 0.0))
    assert spin(executor, lambda: len(scans) >= 1, timeout=10.0)
    scan = scans[0]
    assert scan.header.frame_id == 'laser_link' and len(scan.ranges) == 361
    assert scan.ranges[180] == pytest.approx(3.0, abs=1e-5)
    assert scan.ranges[240] == pytest.approx(3.0 / math.cos(math.radians(30.0)), abs=1e-5)
    assert scan.ranges[0] == math.inf and scan.ranges[360] == math.inf
    assert scan.range_max == pytest.approx(80.0) and scan.range_min == pytest.approx(0.3)
    pub.publish(truth(0.1, math.nan))     # refused by the guard, the node goes on
    pub.publish(truth(0.2, 1.0))          # a sample time (75 Hz): 1 m nearer the wall
    assert spin(executor, lambda: len(scans) >= 2, timeout=10.0)
    assert scans[1].ranges[180] == pytest.approx(2.0, abs=1e-5)
    assert scans[1].header.stamp.nanosec == 200_000_000


def test_a_missing_world_file_exits_2(start_node, read_output):
    proc = start_node('robotica_sim', 'laser_emulator')
    assert proc.wait(timeout=30) == 2
    assert 'world_file is required' in read_output(proc)
