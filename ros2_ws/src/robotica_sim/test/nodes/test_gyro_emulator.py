"""
Node tests of gyro_emulator: readings of a constant yaw rate, their honest covariance.

The consumer MEMS preset (noise density 0.005 °/s/√Hz, 1 % scale factor, a turn-on bias of
0.05 °/s spread) at 50 Hz: each reading's white-noise standard deviation is
N / sqrt(dt) = 0.0873e-3 rad/s/√Hz / sqrt(0.02 s) = 6.2e-4 rad/s, which, with the quantum
(200 °/s / 2^16) over sqrt(12), is what the covariance must say.
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import Imu

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)
DEG = math.pi / 180.0


def truth(t, rate):
    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    msg.twist.twist.angular.z = rate
    return msg


def test_constant_rate_is_read_with_its_noise(start_node, ros_node, spin):
    node, executor = ros_node
    start_node('robotica_sim', 'gyro_emulator', '-p', 'preset:=mems_consumer', '-p', 'seed:=5')
    readings = []
    node.create_subscription(Imu, 'imu/data', readings.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('imu/data') > 0)
    spin(executor, lambda: False, timeout=1.0)
    rate = 0.5
    for k in range(201):
        pub.publish(truth(0.02 * k, rate))
        spin(executor, lambda: False, timeout=0.003)
    assert spin(executor, lambda: len(readings) >= 200, timeout=10.0)
    z = [r.angular_velocity.z for r in readings]
    mean = sum(z) / len(z)
    # 1 % scale factor, a turn-on bias of a few 1e-3 rad/s, noise averaging to 4e-5 rad/s.
    assert mean == pytest.approx(rate * 1.01, abs=0.005)
    white = (0.005 * DEG) ** 2 / 0.02 + (200.0 * DEG / 2 ** 16) ** 2 / 12.0
    for r in readings:
        assert r.angular_velocity_covariance[8] == pytest.approx(white, rel=1e-6)
        assert r.orientation_covariance[0] == -1.0
    spread = math.sqrt(sum((v - mean) ** 2 for v in z) / (len(z) - 1))
    assert 0.5 * math.sqrt(white) < spread < 2.0 * math.sqrt(white)


def test_unknown_preset_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'gyro_emulator', '-p', 'preset:=ring_laser')
    assert proc.wait(timeout=30) == 2
    assert 'preset must be one of' in read_output(proc)


def _set(node, executor, call, name, value):
    client = node.create_client(SetParameters, '/gyro_emulator/set_parameters')
    response = call(executor, client, SetParameters.Request(parameters=[Parameter(
        name=name, value=ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                        double_value=value))]))
    assert response is not None
    return response.results[0]


def test_terms_override_the_preset_and_are_checked_when_set(start_node, ros_node, spin, call):
    # An ideal gyro but for its white noise: -p terms override the preset's values, so each
    # reading's covariance is the given N² / dt (no quantum), and a set changes it.
    node, executor = ros_node
    start_node('robotica_sim', 'gyro_emulator', '-p', 'preset:=fog', '-p', 'seed:=1',
               '-p', 'noise_density:=0.01', '-p', 'resolution:=0.0')
    readings = []
    node.create_subscription(Imu, 'imu/data', readings.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('imu/data') > 0)
    pub.publish(truth(0.0, 0.0))
    pub.publish(truth(0.02, 0.0))
    assert spin(executor, lambda: len(readings) >= 1, timeout=10.0)
    assert readings[0].angular_velocity_covariance[8] == pytest.approx(0.01 ** 2 / 0.02)
    refused = _set(node, executor, call, 'bias_correlation_time', 0.0)
    assert not refused.successful and 'bias_correlation_time' in refused.reason
    assert _set(node, executor, call, 'noise_density', 0.02).successful
    pub.publish(truth(0.04, 0.0))
    assert spin(executor, lambda: len(readings) >= 2, timeout=10.0)
    assert readings[1].angular_velocity_covariance[8] == pytest.approx(0.02 ** 2 / 0.02)


def test_a_term_out_of_range_is_refused_at_start_up(start_node, read_output):
    proc = start_node('robotica_sim', 'gyro_emulator', '-p', 'scale_factor_error:=0.9')
    assert proc.wait(timeout=30) == 2
    assert 'scale_factor_error' in read_output(proc)
