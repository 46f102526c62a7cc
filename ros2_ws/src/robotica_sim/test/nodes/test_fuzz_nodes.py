"""
Fuzz tests of every subscriber of the robotica_sim nodes: hostile messages, then valid ones.

Each node gets a seeded burst of hostile messages on each of its inputs (every field NaN, ±inf,
±1e308, extreme integers, absurd stamps, empty or wrong-size arrays; half of them a valid message
with some fields corrupted), bounded in count and wall time. The node must stay alive, publish
nothing non-finite (except the fields its docs declare NaN, "not known"), and answer valid input
normally afterwards.
"""
import random
import signal

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import pytest
from robotica_kin.ros.hostile import fuzz
from robotica_msgs.msg import VehicleCommand, WheelEncoders
from sensor_msgs.msg import Imu, JointState, NavSatFix
from std_msgs.msg import Float64MultiArray

pytestmark = pytest.mark.ros


def _stamped(msg, t):
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    return msg


def _truth(t, v=0.5):
    msg = _stamped(Odometry(), t)
    msg.header.frame_id, msg.child_frame_id = 'map', 'base_link'
    msg.pose.pose.position.x = v * t
    msg.pose.pose.orientation.w = 1.0
    msg.twist.twist.linear.x = v
    msg.twist.twist.angular.z = 0.1
    return msg


def _fix(t):
    msg = _stamped(NavSatFix(latitude=37.41, longitude=-6.0, altitude=10.0), t)
    msg.position_covariance = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    msg.position_covariance_type = NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN
    return msg


def _heading(t):
    msg = _stamped(Imu(), t)
    msg.orientation.w = 1.0
    msg.orientation_covariance[8] = 0.01
    return msg


def _twist(t):
    msg = Twist()
    msg.linear.x = 0.5
    return msg


def _wheels(t):
    return _stamped(JointState(name=['left_wheel_joint', 'right_wheel_joint'],
                               position=[5.0 * t, 5.0 * t], velocity=[5.0, 5.0]), t)


def _ticks(t):
    return _stamped(WheelEncoders(left_ticks=int(1000 * t), right_ticks=int(1000 * t),
                                  ticks_per_revolution=1000), t)


# node, parameters, inputs {topic: (type, valid message of time t)}, outputs {topic: (type,
# fields that may be NaN)}, the output that shows recovery and what it must satisfy.
CASES = {
    'simulator': (['-p', 'cmd_timeout:=0.2'], {'cmd_vel': (Twist, _twist)},
                  {'ground_truth/odom': (Odometry, ()), 'joint_states': (JointState, ())},
                  'ground_truth/odom', lambda m: m.twist.twist.linear.x == pytest.approx(0.5)),
    'simulator_tricycle': (
        ['-p', 'vehicle.type:=tricycle', '-p', 'cmd_timeout:=0.2'],
        {'vehicle_command': (VehicleCommand, lambda t: VehicleCommand(speed=0.5))},
        {'ground_truth/odom': (Odometry, ()), 'joint_states': (JointState, ('velocity',))},
        'ground_truth/odom', lambda m: m.twist.twist.linear.x == pytest.approx(0.5)),
    'arm_simulator': (
        ['-p', 'robot:=puma560', '-p', 'initial_positions:=[0.0, 0.5, -0.5, 0.0, 0.0, 0.0]'],
        {'joint_torques': (Float64MultiArray, lambda t: Float64MultiArray(data=[0.0] * 6))},
        {'joint_states': (JointState, ())}, 'joint_states',
        lambda m: any(v != 0.0 for v in m.velocity)),   # brakes off: it falls
    'odometry': (
        ['-p', 'fuse_gps:=true', '-p', 'fuse_compass:=true', '-p', 'initial_stddev.position:=1.0',
         '-p', 'initial_stddev.heading:=0.1'],
        {'wheel_encoders': (WheelEncoders, _ticks), 'gps/fix': (NavSatFix, _fix),
         'compass/heading': (Imu, _heading)},
        {'odom': (Odometry, ())}, 'odom', lambda m: m.header.stamp.sec >= 100),
    'encoder_emulator': ([], {'joint_states': (JointState, _wheels)},
                         {'wheel_encoders': (WheelEncoders, ())}, 'wheel_encoders',
                         lambda m: m.header.stamp.sec >= 100),
    'gyro_emulator': ([], {'ground_truth/odom': (Odometry, _truth)}, {'imu/data': (Imu, ())},
                      'imu/data', lambda m: m.header.stamp.sec >= 100),
    'compass_emulator': ([], {'ground_truth/odom': (Odometry, _truth)},
                         {'compass/heading': (Imu, ())}, 'compass/heading',
                         lambda m: m.header.stamp.sec >= 100),
    'gps_emulator': ([], {'ground_truth/odom': (Odometry, _truth)}, {'gps/fix': (NavSatFix, ())},
                     'gps/fix', lambda m: m.header.stamp.sec >= 100),
}


@pytest.mark.parametrize('case', sorted(CASES))
def test_hostile_messages_neither_kill_nor_poison_the_node(case, start_node, ros_node,
                                                           fuzz_survived):
    parameters, inputs, outputs, witness, recovered = CASES[case]
    node, executor = ros_node
    proc = start_node('robotica_sim', case.split('_tricycle')[0], *parameters)
    received, ok = fuzz(node, executor, inputs, {t: m for t, (m, _) in outputs.items()},
                        lambda got: any(recovered(m) for m in got[witness][-20:]),
                        random.Random(f'{case}-16'))
    fuzz_survived(proc, received, ok, {t: nan for t, (_, nan) in outputs.items()})


@pytest.mark.parametrize('name, parameters', [
    ('arm_simulator', ['-p', 'robot:=puma560']),   # 1 kHz of publishing when SIGINT comes
    ('simulator', []),
])
def test_sigint_while_publishing_ends_cleanly(name, parameters, start_node, ros_node, spin,
                                              read_output):
    node, executor = ros_node
    proc = start_node('robotica_sim', name, *parameters)
    received = []
    node.create_subscription(JointState, 'joint_states', received.append, 10)
    assert spin(executor, lambda: len(received) > 20)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=15) == 0
    text = read_output(proc)
    assert 'Traceback' not in text and 'context is invalid' not in text, text
