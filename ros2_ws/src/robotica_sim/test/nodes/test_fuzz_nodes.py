"""
Fuzz tests of every subscriber of the robotica_sim nodes: hostile messages, then valid ones.

Each node gets a seeded burst of hostile messages on each of its inputs (every field NaN, ±inf,
±1e308, extreme integers, absurd stamps, empty or wrong-size arrays; half of them a valid message
with some fields corrupted), bounded in count and wall time. The node must stay alive, publish
nothing non-finite (except the fields its docs declare NaN, "not known"), and answer valid input
normally afterwards.
"""
import pathlib
import random
import signal
import time

from geometry_msgs.msg import Twist, Vector3, WrenchStamped
from nav_msgs.msg import Odometry, Path
import pytest
from rcl_interfaces.msg import Log
from robotica_kin.ros.convert import path_message, seconds_to_stamp
from robotica_kin.ros.hostile import fuzz
from robotica_kin.ros.qos import LATCHED_QOS
from robotica_msgs.msg import (JointControllerState, SimulatorStatus, TrackingError,
                               VehicleCommand, WheelEncoders)
from robotica_sim.bags.info import bag_info
from robotica_sim.runs.plan import (ARM_RECORDED_TOPICS, CONTROLLER_STATE_TOPIC, RECORDED_TOPICS,
                                    SENSOR_TOPICS, STATUS_TOPIC, TRACKING_ERROR_TOPIC,
                                    TRAJECTORY_TOPIC)
from rosbags.highlevel import AnyReader
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState, LaserScan, MagneticField, NavSatFix, Range
from std_msgs.msg import Float64MultiArray, String
from tf2_msgs.msg import TFMessage
from trajectory_msgs.msg import JointTrajectory
from visualization_msgs.msg import MarkerArray

pytestmark = pytest.mark.ros


def _stamped(msg, t):
    msg.header.stamp = seconds_to_stamp(t)
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


def _gyro(t):
    msg = _stamped(Imu(), t)
    msg.angular_velocity_covariance[8] = 1e-4
    return msg


def _ticks(t):
    return _stamped(WheelEncoders(left_ticks=int(1000 * t), right_ticks=int(1000 * t),
                                  ticks_per_revolution=1000), t)


def _target(t):
    msg = _stamped(TrackingError(), t)
    msg.header.frame_id = 'map'
    msg.target_point.x = t
    return msg


def _reference(t):
    return _stamped(JointControllerState(reference_position=[0.1 * t] * 6), t)


def _wrench(t):
    msg = _stamped(WrenchStamped(), t)
    msg.wrench.force.z, msg.wrench.torque.x = -20.0, 0.5
    return msg


ROOM = pathlib.Path(__file__).resolve().parents[2] / 'scenarios' / 'room_laser_vff.yaml'
"""A closed room (a scenario with a world: section): every beam from inside it meets a wall."""


def _in_the_room(t):
    return _truth(t, v=0.0)   # at (0, 0), inside the room's walls, still


def _footprint_at(sec):
    return lambda m: any(marker.ns == 'footprint' and marker.header.stamp.sec >= sec
                         for marker in m.markers)


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
    'odometry_gyro': (
        ['-p', 'heading_source:=gyro'],
        {'wheel_encoders': (WheelEncoders, _ticks), 'imu/data': (Imu, _gyro)},
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
    'ft_sensor_emulator': ([], {'contact_wrench': (WrenchStamped, _wrench)},
                           {'ft_sensor/wrench': (WrenchStamped, ()),
                            'ft_sensor/gauges': (Float64MultiArray, ())}, 'ft_sensor/wrench',
                           lambda m: m.header.stamp.sec >= 100),
    'markers': (
        ['-p', 'vehicle.type:=differential', '-p', 'publish_rate:=50.0'],
        {'path': (Path, lambda t: path_message([[0.0, 0.0], [t, 1.0]], 'map', t)),
         'odom': (Odometry, _truth), 'ground_truth/odom': (Odometry, _truth),
         'gps/fix': (NavSatFix, _fix), 'path_tracker/tracking_error': (TrackingError, _target),
         'joint_controller/controller_state': (JointControllerState, _reference)},
        {'markers': (MarkerArray, ())}, 'markers', _footprint_at(100)),
    'laser_emulator': (['-p', f'world_file:={ROOM}', '-p', 'preset:=sick_lms200'],   # 80 m
                       {'ground_truth/odom': (Odometry, _in_the_room)},
                       {'scan': (LaserScan, ('ranges',))}, 'scan',
                       lambda m: m.header.stamp.sec >= 100),
    'sonar_emulator': (['-p', f'world_file:={ROOM}', '-p', 'firing_groups:=1'],
                       {'ground_truth/odom': (Odometry, _in_the_room)},
                       {'sonar_0': (Range, ())}, 'sonar_0', lambda m: m.header.stamp.sec >= 100),
    'infrared_emulator': (['-p', f'world_file:={ROOM}'],
                          {'ground_truth/odom': (Odometry, _in_the_room)},
                          {'infrared_0': (Range, ())}, 'infrared_0',
                          lambda m: m.header.stamp.sec >= 100),
}

# Fields whose ±inf is documented (REP-117): a hostile but finite pose may put the laser outside
# the room (+inf, no return) or against a wall (-inf, nearer than range_min).
INFINITE = {'scan': ('ranges',)}
NODES = {'simulator_tricycle': 'simulator', 'odometry_gyro': 'odometry'}   # else the case's name


@pytest.mark.parametrize('case', sorted(CASES))
def test_hostile_messages_neither_kill_nor_poison_the_node(case, start_node, ros_node,
                                                           fuzz_survived):
    parameters, inputs, outputs, witness, recovered = CASES[case]
    node, executor = ros_node
    proc = start_node('robotica_sim', NODES.get(case, case), *parameters)
    received, ok = fuzz(node, executor, inputs, {t: m for t, (m, _) in outputs.items()},
                        lambda got: any(recovered(m) for m in got[witness][-20:]),
                        random.Random(f'{case}-16'))
    fuzz_survived(proc, received, ok, {t: nan for t, (_, nan) in outputs.items()}, INFINITE)


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


def test_hostile_followed_stamps_neither_advance_nor_wedge_the_lockstep(start_node, ros_node, spin,
                                                                        fuzz_survived):
    # The test is the controller (cmd_vel) and the follower (/odom, stamped with the newest
    # ground truth) of a lockstep simulator; the follower's topic also gets hostile messages.
    node, executor = ros_node
    proc = start_node('robotica_sim', 'simulator', '-p', 'pacing:=lockstep',
                      '-p', "lockstep.follow_topics:=['/odom']", '-p', 'lockstep.timeout:=0.1',
                      '-p', 'lockstep.max_lag:=0.1', '-p', 'status_period:=0.1')
    truth = []
    node.create_subscription(Odometry, 'ground_truth/odom', truth.append, 1000)

    def follow(t):
        msg = Odometry()
        if truth:
            msg.header.stamp = truth[-1].header.stamp
        return msg

    def steady(got):   # five statuses (0.4 s simulated) without a timeout, the command applied
        status = got['/simulator/status'][-5:]
        return (len(status) == 5 and len({s.lockstep_timeouts for s in status}) == 1
                and got['ground_truth/odom'][-1].twist.twist.linear.x == pytest.approx(0.5))

    received, ok = fuzz(node, executor, {'cmd_vel': (Twist, _twist), '/odom': (Odometry, follow)},
                        {'ground_truth/odom': Odometry, '/simulator/status': SimulatorStatus},
                        steady, random.Random('lockstep-follow-16'))
    fuzz_survived(proc, received, ok)
    # Not advanced: with the follower silent (the controller still answering), steps wait for
    # it again. A hostile stamp taken as the follower's newest (2**31 - 1) let it run on.
    status = received['/simulator/status']
    before = status[-1].lockstep_timeouts
    cmd = node.create_publisher(Twist, 'cmd_vel', 10)
    deadline = time.monotonic() + 10.0
    while status[-1].lockstep_timeouts < before + 3 and time.monotonic() < deadline:
        cmd.publish(_twist(0.0))
        spin(executor, lambda: False, 0.02)
    assert status[-1].lockstep_timeouts >= before + 3, (before, status[-1])


# Every topic a run records (robotica_sim.runs.plan), with its type.
RECORDED = {'/clock': Clock, '/cmd_vel': Twist, '/vehicle_command': VehicleCommand,
            '/odom': Odometry, '/ground_truth/odom': Odometry, '/joint_states': JointState,
            '/wheel_encoders': WheelEncoders, '/path': Path, TRACKING_ERROR_TOPIC: TrackingError,
            STATUS_TOPIC: SimulatorStatus, '/rosout': Log, '/imu/data': Imu,
            '/compass/heading': Imu, '/compass/magnetic_field': MagneticField,
            '/gps/fix': NavSatFix, '/joint_torques': Float64MultiArray,
            CONTROLLER_STATE_TOPIC: JointControllerState, TRAJECTORY_TOPIC: JointTrajectory,
            '/tf': TFMessage, '/tf_static': TFMessage, '/robot_description': String,
            '/markers': MarkerArray}


def _default(msg_type):
    def valid(t):
        msg = msg_type()
        if msg_type is Clock:
            msg.clock = seconds_to_stamp(t)
        elif hasattr(msg, 'header'):
            msg.header.stamp = seconds_to_stamp(t)
        return msg
    return valid


def test_hostile_messages_of_every_recorded_type_leave_a_readable_bag(start_node, ros_node, spin,
                                                                      fuzz_survived, tmp_path):
    node, executor = ros_node
    assert set(RECORDED) >= set(RECORDED_TOPICS + ARM_RECORDED_TOPICS).union(
        *SENSOR_TOPICS.values())
    out = tmp_path / 'bag'
    proc = start_node('robotica_sim', 'recorder', '-p', f'output:={out}',
                      '-p', f'topics:={list(RECORDED)}', '-p', 'use_sim_time:=true')
    received, ok = fuzz(node, executor, {t: (m, _default(m)) for t, m in RECORDED.items()}, {},
                        lambda got: True, random.Random('recorder-16'), count=40)
    fuzz_survived(proc, received, ok)
    marker = node.create_publisher(Twist, '/cmd_vel', LATCHED_QOS)   # as the recorder subscribed
    assert spin(executor, lambda: marker.get_subscription_count() > 0)
    for _ in range(5):
        marker.publish(Twist(linear=Vector3(x=42.0)))
        spin(executor, lambda: False, 0.05)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=30) == 0
    info = bag_info(out)
    with AnyReader([out]) as reader:
        messages = [(c.topic, reader.deserialize(raw, c.msgtype))
                    for c, _, raw in reader.messages()]
    assert len(messages) == info.message_count > len(RECORDED) * 40 // 2
    assert [m for topic, m in messages if topic == '/cmd_vel' and m.linear.x == 42.0]
