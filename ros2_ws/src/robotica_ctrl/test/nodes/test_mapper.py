"""
Node tests of mapper: scans of a wall fused from the robot's pose make the wall occupied.

The robot stands at (1, 1) facing +x; an ideal laser sees a wall along x = 3 m (every beam's
range is the distance to the line, computed here): the cells at x = 3 become occupied, those
between robot and wall free, those behind the wall stay unknown.
"""
import math

from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.convert import seconds_to_stamp
from sensor_msgs.msg import LaserScan

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _scan(t: float) -> LaserScan:
    msg = LaserScan(angle_min=-0.5, angle_increment=0.01, range_min=0.05, range_max=10.0)
    msg.header.stamp = seconds_to_stamp(t)
    msg.header.frame_id = 'laser_link'
    angles = msg.angle_min + msg.angle_increment * np.arange(101)
    msg.ranges = (2.0 / np.cos(angles)).tolist()   # the wall x = 3 seen from x = 1
    return msg


def _odom(t: float) -> Odometry:
    msg = Odometry()
    msg.header.stamp = seconds_to_stamp(t)
    msg.header.frame_id = 'map'
    msg.pose.pose.position.x, msg.pose.pose.position.y = 1.0, 1.0
    msg.pose.pose.orientation.w = 1.0
    return msg


def test_a_wall_seen_by_the_laser_is_mapped(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'mapper', '-p', 'size:=[4.0, 2.0]', '-p',
                      'resolution:=0.1', '-p', 'publish_period:=0.0')
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append, LATCHED)
    odom = node.create_publisher(Odometry, 'odom', 10)
    scan = node.create_publisher(LaserScan, 'scan', 10)
    assert spin(executor, lambda: odom.get_subscription_count() and scan.get_subscription_count())
    for k in range(8):   # the first messages may go before the node has matched the topics
        odom.publish(_odom(1.0 + k))
        spin(executor, lambda: False, 0.05)
        scan.publish(_scan(1.0 + k))
        spin(executor, lambda: False, 0.05)
    assert spin(executor, lambda: len(maps) >= 5), read_output(proc)
    grid = np.array(maps[-1].data, dtype=np.int16).reshape(20, 40)
    row = 10                                   # y = 1.05 m, the beam straight ahead
    assert grid[row, 30] >= 65                 # x = 3.05 m: the wall's cells
    assert all(0 <= v < 20 for v in grid[row, 12:28])   # x = 1.2-2.8 m: free
    assert all(v == -1 for v in grid[row, 32:])          # behind the wall: never observed
    assert maps[-1].header.frame_id == 'map'
    assert math.isclose(maps[-1].info.resolution, 0.1, rel_tol=1e-6)


def test_a_scan_without_a_pose_is_skipped(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'mapper')
    scan = node.create_publisher(LaserScan, 'scan', 10)
    assert spin(executor, lambda: scan.get_subscription_count())
    scan.publish(_scan(1.0))
    assert spin(executor, lambda: 'before any pose' in read_output(proc))
    assert proc.poll() is None


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'size:=[1e6, 1e6]'), 'cells is more than'),
    (('-p', 'laser.mount:=[0.0, 0.0]'), 'laser.mount'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'mapper', *arguments)
    assert proc.wait(timeout=30) == 2
    assert reason in read_output(proc)
