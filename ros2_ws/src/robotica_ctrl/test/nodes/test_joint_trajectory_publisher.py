"""
Node tests of joint_trajectory_publisher: the latched trajectory it publishes, refused input.

Reference: a cubic from 0 to 1 rad in 1 s with zero end velocities is ``q = 3t² - 2t³`` (book
(10.7)-(10.10)), so q(0.5) = 0.5, q'(0.5) = 1.5 rad/s, q''(0) = 6 rad/s²; a sine reference is
``A sin(2π t / T)`` (8.47).
"""
import math

import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from trajectory_msgs.msg import JointTrajectory

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _seconds(duration) -> float:
    return duration.sec + duration.nanosec * 1e-9


def _received(start_node, ros_node, spin, *arguments) -> JointTrajectory:
    node, executor = ros_node
    start_node('robotica_ctrl', 'joint_trajectory_publisher', *arguments)
    got = []
    node.create_subscription(JointTrajectory, 'joint_trajectory', got.append, LATCHED)
    assert spin(executor, lambda: got)
    return got[0]


def test_pol3_through_two_points(start_node, ros_node, spin):
    msg = _received(start_node, ros_node, spin, '-p', 'generator:=pol3', '-p',
                    'joint_names:=[joint_1]', '-p', 'sample_period:=0.5', '-p',
                    'via.positions:=[0.0, 1.0]', '-p', 'via.segment_durations:=[1.0]')
    assert list(msg.joint_names) == ['joint_1']
    assert [_seconds(p.time_from_start) for p in msg.points] == [0.0, 0.5, 1.0]
    np.testing.assert_allclose([p.positions[0] for p in msg.points], [0.0, 0.5, 1.0],
                               atol=1e-12)
    np.testing.assert_allclose([p.velocities[0] for p in msg.points], [0.0, 1.5, 0.0],
                               atol=1e-12)
    assert msg.points[0].accelerations[0] == pytest.approx(6.0)


def test_sine_for_two_joints(start_node, ros_node, spin):
    msg = _received(start_node, ros_node, spin, '-p', 'joint_names:=[a, b]', '-p',
                    'sine.amplitude:=[0.15]', '-p', 'sine.period:=[4.0]', '-p',
                    'duration:=2.0', '-p', 'sample_period:=0.1', '-p', 'start_time:=3.0')
    assert msg.header.stamp.sec == 3
    assert len(msg.points) == 21
    for point in msg.points:
        t = _seconds(point.time_from_start)
        assert point.positions[0] == point.positions[1] == pytest.approx(
            0.15 * math.sin(2 * math.pi * t / 4.0), abs=1e-12)


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'joint_names:=[a]', '-p', 'generator:=spline'), 'generator must be one of'),
    (('-p', 'generator:=sine'), 'joint_names must name'),
    (('-p', 'joint_names:=[a, b]', '-p', 'generator:=pol3', '-p', 'via.positions:=[0.0, 1.0, 2.0]',
      '-p', 'via.segment_durations:=[1.0]'), 'via.positions must hold points x 2'),
    (('-p', 'joint_names:=[a]', '-p', 'sine.period:=[0.0]'), 'sine.period must be > 0 s'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'joint_trajectory_publisher', *arguments)
    assert proc.wait(timeout=30) == 2
    assert reason in read_output(proc)
