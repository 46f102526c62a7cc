"""
Node tests of mapper: readings of a wall fused from the robot's pose make the wall occupied.

The robot stands at (1, 1) facing +x; an ideal laser sees a wall along x = 3 m (every beam's
range is the distance to the line, computed here): the cells at x = 3 become occupied, those
between robot and wall free, those behind the wall stay unknown. With the sonar alone, the robot
at (1, 1) faces +y and two transducers on its right side and its front see the wall x = 3 m and
a wall y = 1.8 m (their places in the map and their readings computed here from the pose and
the mounts): each cone marks the cells about its wall point occupied and those on its axis
before the wall free, and nothing outside the cones.
"""
import math

from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.convert import seconds_to_stamp
from sensor_msgs.msg import LaserScan, Range

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
    # The first messages may go before the node has matched the topics (under load, for
    # seconds): publish pose-scan pairs until five maps have come back.
    for k in range(200):
        odom.publish(_odom(1.0 + k))
        spin(executor, lambda: False, 0.05)
        scan.publish(_scan(1.0 + k))
        if spin(executor, lambda: len(maps) >= 5, 0.05):
            break
    assert len(maps) >= 5, read_output(proc)
    grid = np.array(maps[-1].data, dtype=np.int16).reshape(20, 40)
    row = 10                                   # y = 1.05 m, the beam straight ahead
    assert grid[row, 30] >= 65                 # x = 3.05 m: the wall's cells
    assert all(0 <= v < 20 for v in grid[row, 12:28])   # x = 1.2-2.8 m: free
    assert all(v == -1 for v in grid[row, 32:])          # behind the wall: never observed
    assert maps[-1].header.frame_id == 'map'
    assert math.isclose(maps[-1].info.resolution, 0.1, rel_tol=1e-6)


SONAR_POSE = (1.0, 1.0, math.pi / 2)    # the robot (x [m], y [m], theta [rad]) in the map
SONAR_MOUNTS = ((0.0, -0.2, -math.pi / 2), (0.2, 0.0, 0.0))   # right side and front, base_link
CONE = math.radians(15.0)               # the transducers' half-angle [rad]


def _sonar_in_map(mount: tuple[float, float, float]) -> tuple[float, float, float]:
    """Return a transducer's (x, y, yaw) in the map: SONAR_POSE composed with ``mount``."""
    x, y, theta = SONAR_POSE
    c, s = math.cos(theta), math.sin(theta)
    return x + c * mount[0] - s * mount[1], y + s * mount[0] + c * mount[1], theta + mount[2]


def _range(t: float, reading: float, **fields) -> Range:
    msg = Range(radiation_type=Range.ULTRASOUND, field_of_view=2.0 * CONE, min_range=0.15,
                max_range=5.0, range=reading)
    for name, value in fields.items():
        setattr(msg, name, value)
    msg.header.stamp = seconds_to_stamp(t)
    return msg


def _posed_odom(t: float) -> Odometry:
    msg = _odom(t)
    msg.pose.pose.orientation.z = math.sin(SONAR_POSE[2] / 2)
    msg.pose.pose.orientation.w = math.cos(SONAR_POSE[2] / 2)
    return msg


def test_walls_seen_by_the_sonar_are_mapped(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    mounts = ', '.join(repr(v) for m in SONAR_MOUNTS for v in m)
    proc = start_node('robotica_ctrl', 'mapper', '-p', 'size:=[4.0, 2.0]', '-p',
                      'resolution:=0.1', '-p', 'publish_period:=0.0', '-p',
                      'laser.enabled:=false', '-p', f'sonar.mounts:=[{mounts}]')
    side, front = (_sonar_in_map(m) for m in SONAR_MOUNTS)
    assert np.allclose(side, (1.2, 1.0, 0.0)) and np.allclose(front, (1.0, 1.2, math.pi / 2))
    readings = (3.0 - side[0], 1.8 - front[1])   # the walls x = 3 m and y = 1.8 m: 1.8, 0.6 m
    maps = []
    node.create_subscription(OccupancyGrid, 'map', maps.append, LATCHED)
    odom = node.create_publisher(Odometry, 'odom', 10)
    sonar = [node.create_publisher(Range, f'sonar_{i}', 10) for i in range(2)]
    assert spin(executor, lambda: odom.get_subscription_count()
                and all(p.get_subscription_count() for p in sonar)), read_output(proc)
    # The first messages may go before the node has matched the topics (under load, for
    # seconds): publish a pose and a reading of each transducer until 30 maps have come back,
    # one map per fused reading; only the topics' late matching loses readings, so that is at
    # least 10 of each transducer.
    for k in range(200):
        odom.publish(_posed_odom(1.0 + k))
        spin(executor, lambda: False, 0.05)
        for pub, reading in zip(sonar, readings):
            pub.publish(_range(1.0 + k, reading))
        if spin(executor, lambda: len(maps) >= 30, 0.05):
            break
    assert len(maps) >= 30, (len(maps), read_output(proc))
    grid = np.array(maps[-1].data, dtype=np.int16).reshape(20, 40)
    x, y = np.meshgrid(0.05 + 0.1 * np.arange(40), 0.05 + 0.1 * np.arange(20))   # centres
    reached = np.zeros(grid.shape, dtype=bool)
    for (sx, sy, yaw), r in zip((side, front), readings):
        rho = np.hypot(x - sx, y - sy)
        phi = np.abs(np.angle(np.exp(1j * (np.arctan2(y - sy, x - sx) - yaw))))
        wall = (phi <= CONE / 2) & (np.abs(rho - r) <= 0.06)     # about the wall point
        assert wall.sum() >= 4 and (grid[wall] >= 65).all(), grid[wall]
        between = (phi <= 0.8 * CONE) & (rho <= r - 0.2)        # before it, in the cone
        assert between.sum() >= 4 and ((grid[between] >= 0) & (grid[between] < 50)).all()
        near = (phi <= 0.6 * CONE) & (rho <= 0.6 * r)            # map_server's free: < 19.6 %
        assert near.sum() >= 2 and ((grid[near] >= 0) & (grid[near] < 20)).all(), grid[near]
        reached |= (phi <= CONE + 0.02) & (rho <= r + 0.1)
    assert (grid[~reached] == -1).all(), np.argwhere((grid != -1) & ~reached)[:5]
    assert maps[-1].header.frame_id == 'map'


def test_a_bad_sonar_reading_is_refused(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'mapper', '-p', 'sonar.mounts:=[0.2, 0.0, 0.0]')
    odom = node.create_publisher(Odometry, 'odom', 10)
    sonar = node.create_publisher(Range, 'sonar_0', 10)
    assert spin(executor, lambda: odom.get_subscription_count()
                and sonar.get_subscription_count())
    for k, (bad, reason) in enumerate((
            ({'field_of_view': math.nan}, 'cone_half_angle must lie in (0, pi/2)'),
            ({'min_range': math.nan, 'max_range': math.nan}, 'min_range, max_range must'),
            ({'radiation_type': Range.INFRARED}, 'is not ULTRASOUND'))):
        for repeat in range(40):   # resend: the first messages may go before the match
            t = 1.0 + 10 * k + 0.1 * repeat
            odom.publish(_odom(t))
            spin(executor, lambda: False, 0.05)
            sonar.publish(_range(t, 1.0, **bad))
            if spin(executor, lambda: reason in read_output(proc), 0.25):
                break
        assert reason in read_output(proc), read_output(proc)
        assert proc.poll() is None
    maps = []   # still mapping: a good reading after the bad ones makes the first map
    node.create_subscription(OccupancyGrid, 'map', maps.append, LATCHED)
    for repeat in range(40):
        odom.publish(_odom(50.0 + repeat))
        spin(executor, lambda: False, 0.05)
        sonar.publish(_range(50.0 + repeat, 1.0))
        if spin(executor, lambda: maps, 0.25):
            break
    assert maps and max(maps[-1].data) >= 50, read_output(proc)


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
    (('-p', 'sonar.mounts:=[0.2, 0.0]'), 'sonar.mounts must hold'),
    (('-p', 'laser.enabled:=false'), 'nothing to map from'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'mapper', *arguments)
    assert proc.wait(timeout=30) == 2
    assert reason in read_output(proc)
