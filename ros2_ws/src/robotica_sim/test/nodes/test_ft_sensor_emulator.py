"""
Node tests of ft_sensor_emulator: a contact wrench in, the wrench recovered from the gauges out.

The gauges' volts are checked against the Maltese cross's closed form (module docstring of
robotica_sim.sensors.force_torque, written out here): gauge 2k reads
s ((-f_x sin φ_k + f_y cos φ_k) / 2 + m_z / (4 ρ)), gauge 2k + 1 reads
s (f_z / 4 + (m_x sin φ_k - m_y cos φ_k) / (2 ρ)), s = G V K c / 4 = 500 · 5 · 2 · 4e-6 / 4
= 5e-3 V/N for the metal-foil preset (ρ = 0.02 m).
"""
import math

from geometry_msgs.msg import WrenchStamped
import numpy as np
import pytest
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from std_msgs.msg import Float64MultiArray

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)
WRENCH = [120.0, -80.0, 300.0, 4.0, -2.5, 1.5]   # [N, N m]


def contact(t, wrench):
    msg = WrenchStamped()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    msg.header.frame_id = 'tool0'
    f, m = msg.wrench.force, msg.wrench.torque
    f.x, f.y, f.z, m.x, m.y, m.z = wrench
    return msg


def as_array(msg):
    f, m = msg.wrench.force, msg.wrench.torque
    return np.array([f.x, f.y, f.z, m.x, m.y, m.z])


def gauge_volts(wrench, scale=5e-3, rho=0.02):
    fx, fy, fz, mx, my, mz = wrench
    volts = []
    for k in range(4):
        s, c = math.sin(k * math.pi / 2), math.cos(k * math.pi / 2)
        volts += [scale * ((-fx * s + fy * c) / 2 + mz / (4 * rho)),
                  scale * (fz / 4 + (mx * s - my * c) / (2 * rho))]
    return volts


IDEAL = ('-p', 'noise_stddev:=0.0', '-p', 'adc_bits:=0')   # no noise, no ADC


def _start(start_node, ros_node, spin, *arguments):
    """Start the node with ``arguments``; return the probe, its executor, publisher, inboxes."""
    node, executor = ros_node
    start_node('robotica_sim', 'ft_sensor_emulator', *arguments)
    wrenches, gauges = [], []
    node.create_subscription(WrenchStamped, 'ft_sensor/wrench', wrenches.append, QOS)
    node.create_subscription(Float64MultiArray, 'ft_sensor/gauges', gauges.append, QOS)
    pub = node.create_publisher(WrenchStamped, 'contact_wrench', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('ft_sensor/wrench') > 0)
    return node, executor, pub, wrenches, gauges


def test_noise_free_sensor_recovers_the_wrench(start_node, ros_node, spin):
    _, executor, pub, wrenches, gauges = _start(start_node, ros_node, spin,
                                                '-p', 'preset:=metal_foil', *IDEAL)
    for _ in range(50):   # a first message can go before the node has matched the topic
        pub.publish(contact(12.25, WRENCH))
        if spin(executor, lambda: wrenches and gauges, timeout=0.2):
            break
    assert spin(executor, lambda: wrenches and gauges, timeout=10.0)
    out = wrenches[0]
    assert (out.header.stamp.sec, out.header.stamp.nanosec) == (12, 250_000_000)
    assert out.header.frame_id == 'ft_sensor_link'
    np.testing.assert_allclose(as_array(out), WRENCH, rtol=1e-9)
    np.testing.assert_allclose(gauges[0].data, gauge_volts(WRENCH), rtol=1e-12, atol=1e-15)
    assert gauges[0].layout.dim[0].size == 8


def test_noisy_readings_scatter_about_the_wrench(start_node, ros_node, spin):
    # The metal-foil preset, σ = 1 mV per gauge: the columns of H are orthogonal, so each axis
    # has σ² / |column|²: σ_fx = √2 σ / s = 0.28 N, σ_fz = 2 σ / s, σ_mx = √2 ρ σ / s,
    # σ_mz = 2 ρ σ / s (the ADC's quantum adds 1 %; the model's test checks the covariance
    # exactly). 100 readings of a constant wrench average within 5 σ / √100 of it.
    _, executor, pub, wrenches, _ = _start(start_node, ros_node, spin, '-p', 'seed:=3',
                                           '-p', 'frame_id:=wrist')
    for k in range(100):
        pub.publish(contact(1.0 + 0.01 * k, WRENCH))
        spin(executor, lambda: False, timeout=0.003)
    assert spin(executor, lambda: len(wrenches) >= 100, timeout=10.0)
    readings = np.array([as_array(m) for m in wrenches])
    assert all(m.header.frame_id == 'wrist' for m in wrenches)
    assert len({tuple(r) for r in readings}) == 100
    s, rho = 5e-3, 0.02
    sigma = 1e-3 / s * np.array([math.sqrt(2), math.sqrt(2), 2, math.sqrt(2) * rho,
                                 math.sqrt(2) * rho, 2 * rho])
    assert np.all(np.abs(readings.mean(axis=0) - WRENCH) < 5.0 * sigma / 10.0)
    assert np.all(readings.std(axis=0, ddof=1) < 2.0 * sigma)


def test_a_given_calibration_matrix_and_no_gauges_topic(start_node, ros_node, spin):
    # H = I stacked on I (12 gauges, two a wrench axis): each recovered axis is the mean of two.
    node, executor, pub, wrenches, gauges = _start(
        start_node, ros_node, spin, *IDEAL, '-p', 'publish_gauges:=false',
        '-p', 'calibration_matrix:=' + str(np.vstack([np.eye(6)] * 2).ravel().tolist()))
    pub.publish(contact(5.0, [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]))
    assert spin(executor, lambda: wrenches, timeout=10.0)
    np.testing.assert_allclose(as_array(wrenches[0]), [1.0, 2.0, 3.0, 0.1, 0.2, 0.3],
                               rtol=1e-12)
    assert node.count_publishers('ft_sensor/gauges') == 0 and not gauges


def _set(client, executor, spin, name, value):
    """Return the result of setting the parameter ``name`` of the node to ``value``."""
    future = client.set_parameters([Parameter(name, value=value)])
    assert spin(executor, future.done, timeout=10.0)
    return future.result().results[0]


def test_terms_set_at_run_time_are_checked_and_change_h(start_node, ros_node, spin):
    # Twice the gauge factor (platinum 4.8 against 2.4, book (7.8)): twice the volts of
    # (7.9), the same recovered wrench; K = 0 would read nothing and is refused.
    node, executor, pub, wrenches, gauges = _start(start_node, ros_node, spin, *IDEAL,
                                                   '-p', 'gauge_factor:=2.4')
    pub.publish(contact(1.0, WRENCH))
    assert spin(executor, lambda: gauges, timeout=10.0)
    client = AsyncParameterClient(node, 'ft_sensor_emulator')
    assert client.wait_for_services(timeout_sec=10.0)
    refused = _set(client, executor, spin, 'gauge_factor', 0.0)
    assert not refused.successful and 'gauge_factor' in refused.reason
    assert _set(client, executor, spin, 'gauge_factor', 4.8).successful
    pub.publish(contact(1.01, WRENCH))
    assert spin(executor, lambda: len(gauges) >= 2 and len(wrenches) >= 2, timeout=10.0)
    np.testing.assert_allclose(gauges[1].data, gauge_volts(WRENCH, scale=1.2e-2),
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(gauges[1].data, 2.0 * np.array(gauges[0].data), rtol=1e-12,
                               atol=1e-15)
    np.testing.assert_allclose(as_array(wrenches[1]), WRENCH, rtol=1e-9)


@pytest.mark.parametrize('argument, named', [
    ('adc_bits:=40', 'adc_bits'),                      # out of its declared range
    ('gauge_factor:=0.0', 'gauge_factor'),             # in range, refused by the model
    ('preset:=capacitive', 'preset must be one of'),
    ('calibration_matrix:=[1.0, 2.0, 3.0]', 'calibration_matrix'),
    ('calibration_matrix:=[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]', 'calibration_matrix'),   # n = 1
])
def test_bad_parameters_exit_2_with_one_line(argument, named, start_node, read_output):
    proc = start_node('robotica_sim', 'ft_sensor_emulator', '-p', argument)
    assert proc.wait(timeout=30) == 2
    output = read_output(proc)
    assert named in output
    assert 'Traceback' not in output
    assert len([line for line in output.splitlines() if named in line]) == 1
