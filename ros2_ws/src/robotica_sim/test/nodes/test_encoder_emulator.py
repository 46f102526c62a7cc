"""
Node tests of encoder_emulator: a real process on a private domain, talked to through DDS.

Reference counts are computed by hand: an angle of pi rad on a 1024-count encoder is half a
revolution, 512 counts; -pi/2 rad is -256 counts (256 pulses per revolution, x4 decoding).
"""
import math

import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from robotica_msgs.msg import WheelEncoders
from sensor_msgs.msg import JointState

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def test_ticks_from_wheel_angles(start_node, ros_node, spin, publish):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'encoder_emulator', '-p', 'pulses_per_revolution:=256',
                      '-p', 'decoding:=4')
    received = []
    node.create_subscription(WheelEncoders, 'wheel_encoders', received.append, QOS)
    pub = node.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0 and
                node.count_publishers('wheel_encoders') > 0)
    msg = JointState(name=['right_wheel_joint', 'left_wheel_joint'],
                     position=[-math.pi / 2, math.pi])
    msg.header.stamp.sec = 7
    assert publish(executor, pub, msg, lambda: received)
    out = received[0]
    assert (out.left_ticks, out.right_ticks) == (512, -256)
    assert out.ticks_per_revolution == 1024
    assert out.header.stamp.sec == 7
    assert proc.poll() is None


def test_missing_joint_and_nan_are_skipped(start_node, ros_node, spin, publish, read_output):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'encoder_emulator')
    received = []
    node.create_subscription(WheelEncoders, 'wheel_encoders', received.append, QOS)
    pub = node.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    pub.publish(JointState(name=['left_wheel_joint'], position=[1.0]))
    pub.publish(JointState(name=['left_wheel_joint', 'right_wheel_joint'],
                           position=[math.nan, 1.0]))
    valid = JointState(name=['left_wheel_joint', 'right_wheel_joint'], position=[0.0, 0.0])
    assert publish(executor, pub, valid, lambda: received)
    spin(executor, lambda: False, timeout=0.5)
    assert all((out.left_ticks, out.right_ticks) == (0, 0) for out in received), \
        'only the valid reading gives a count'
    assert proc.poll() is None, 'bad readings must not crash the node'
    assert 'lacks positions' in read_output(proc)


def test_out_of_range_parameter_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'encoder_emulator', '-p', 'pulses_per_revolution:=0')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'invalid configuration' in text and 'Traceback' not in text


def test_sigint_exits_cleanly(start_node, ros_node, spin):
    import signal

    node, executor = ros_node
    proc = start_node('robotica_sim', 'encoder_emulator')
    assert spin(executor, lambda: node.count_publishers('wheel_encoders') > 0)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=20) == 0


def test_fractional_counts_per_revolution_are_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'encoder_emulator', '-p', 'pulses_per_revolution:=1023',
                      '-p', 'decoding:=1', '-p', 'gear_ratio:=1.5')
    assert proc.wait(timeout=30) == 2
    assert 'pulses_per_revolution x decoding x gear_ratio must be an integer' in read_output(proc)
