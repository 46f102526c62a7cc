"""
Node test of infrared_emulator: one sensor's reading of a wall 0.5 m ahead.

By hand: the default reflectivity 0.5 at 0.5 m returns 0.5 / 0.25 = 2 >= the threshold 0.25,
so the wall is detected at its distance.
"""
from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import Range

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def test_a_reading_of_a_wall(tmp_path, start_node, ros_node, spin):
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[0.5, -5.0, 0.5, 5.0]]\n')
    node, executor = ros_node
    start_node('robotica_sim', 'infrared_emulator', '-p', f'world_file:={world}',
               '-p', 'mounts:=[0.0, 0.0, 0.0]', '-p', 'range_noise:=0.0',
               '-p', 'range_noise_per_metre:=0.0')
    readings = []
    node.create_subscription(Range, 'infrared_0', readings.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('infrared_0') > 0)
    msg = Odometry()
    msg.pose.pose.orientation.w = 1.0
    pub.publish(msg)
    assert spin(executor, lambda: len(readings) >= 1, timeout=10.0)
    assert readings[0].range == pytest.approx(0.5, abs=1e-6)
    assert readings[0].radiation_type == Range.INFRARED
    assert readings[0].header.frame_id == 'infrared_0_link'
