"""
Node tests of compass_emulator: the heading of a noise-free, iron-free compass is the true yaw.

The field in the body frame is computed here from the declination D (magnetic north D east of
true north), the inclination I and the intensity F: the horizontal component H = F cos I points
to magnetic north, at the angle π/2 - D - ψ counter-clockwise from the body x axis for a yaw ψ
(REP-103, from east), and the vertical one, F sin I, points down.
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import Imu, MagneticField

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def truth(t, yaw):
    msg = Odometry()
    msg.header.stamp.sec = t
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


def test_heading_equals_true_yaw_without_errors(start_node, ros_node, spin, publish):
    node, executor = ros_node
    start_node('robotica_sim', 'compass_emulator', '-p', 'noise_stddev:=0.0',
               '-p', 'declination:=0.1', '-p', 'inclination:=0.9', '-p', 'field_strength:=4e-5')
    headings, fields = [], []
    node.create_subscription(Imu, 'compass/heading', headings.append, QOS)
    node.create_subscription(MagneticField, 'compass/magnetic_field', fields.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    yaw = 0.7
    assert publish(executor, pub, truth(3, yaw), lambda: headings and fields)
    q = headings[-1].orientation
    heading = math.atan2(2.0 * q.w * q.z, 1.0 - 2.0 * q.z * q.z)
    assert heading == pytest.approx(yaw, abs=1e-9)
    assert headings[-1].header.stamp.sec == 3
    assert headings[-1].angular_velocity_covariance[0] == -1.0
    horizontal = 4e-5 * math.cos(0.9)
    to_north = math.pi / 2 - 0.1 - yaw        # body x axis -> magnetic north, counter-clockwise
    field = fields[-1].magnetic_field
    assert field.x == pytest.approx(horizontal * math.cos(to_north), abs=1e-12)
    assert field.y == pytest.approx(horizontal * math.sin(to_north), abs=1e-12)
    assert abs(field.z) == pytest.approx(4e-5 * math.sin(0.9), abs=1e-12)


def test_bad_soft_iron_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'compass_emulator', '-p', 'soft_iron:=[1.0, 0.0]')
    assert proc.wait(timeout=30) == 2
    assert 'soft_iron must have 9 values' in read_output(proc)


def test_tilt_beyond_its_range_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'compass_emulator', '-p', 'tilt_error:=0.6')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'tilt_error' in text and 'Traceback' not in text
