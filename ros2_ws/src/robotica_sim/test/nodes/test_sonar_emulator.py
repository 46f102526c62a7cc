"""
Node tests of sonar_emulator: a transducer's reading of a wall; a malformed world refused.

One transducer at the robot's origin faces the wall x = 3 m squarely: its echo is at 3 m,
read through the speed of sound the sensor assumes (343.2 m/s) over the air's at 20 °C,
331.3 √(1 + 20 / 273.15) m/s.
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import Range

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def test_a_reading_of_a_wall(tmp_path, start_node, ros_node, spin):
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[3.0, -5.0, 3.0, 5.0]]\n')
    node, executor = ros_node
    start_node('robotica_sim', 'sonar_emulator', '-p', f'world_file:={world}',
               '-p', 'mounts:=[0.0, 0.0, 0.0]', '-p', 'firing_groups:=1',
               '-p', 'range_noise:=0.0', '-p', 'range_noise_per_metre:=0.0')
    readings = []
    node.create_subscription(Range, 'sonar_0', readings.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('sonar_0') > 0)
    msg = Odometry()
    msg.pose.pose.orientation.w = 1.0
    pub.publish(msg)
    assert spin(executor, lambda: len(readings) >= 1, timeout=10.0)
    reading = readings[0]
    c_air = 331.3 * math.sqrt(1.0 + 20.0 / 273.15)
    assert reading.range == pytest.approx(3.0 * 343.2 / c_air, abs=1e-5)
    assert reading.radiation_type == Range.ULTRASOUND
    assert reading.header.frame_id == 'sonar_0_link'
    assert reading.field_of_view == pytest.approx(math.radians(30.0))
    assert reading.max_range == pytest.approx(10.7)


def test_a_malformed_world_file_exits_2(tmp_path, start_node, read_output):
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[3.0, -5.0]]\n')
    proc = start_node('robotica_sim', 'sonar_emulator', '-p', f'world_file:={world}')
    assert proc.wait(timeout=30) == 2
    assert 'walls' in read_output(proc)
