"""
Fuzz tests of every subscriber of the robotica_ctrl nodes: hostile messages, then valid ones.

Each node gets a seeded burst of hostile messages on each of its inputs (every field NaN, ±inf,
±1e308, extreme integers, absurd stamps, empty or wrong-size arrays; half of them a valid message
with some fields corrupted), bounded in count and wall time
(:func:`robotica_kin.ros.hostile.fuzz`). The node must stay alive, publish nothing non-finite,
and answer valid input normally afterwards.
"""
import math
import random

from builtin_interfaces.msg import Duration
from geometry_msgs.msg import Twist, WrenchStamped
from nav_msgs.msg import Odometry, Path
import numpy as np
import pytest
from robotica_kin.ros.convert import path_message, seconds_to_stamp
from robotica_kin.ros.hostile import fuzz
from robotica_kin.ros.qos import LATCHED_QOS
from robotica_msgs.msg import ForceControlState, JointControllerState, TrackingError
from sensor_msgs.msg import JointState, LaserScan
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

pytestmark = pytest.mark.ros
PUMA_JOINTS = [f'joint_{i}' for i in range(1, 7)]


def _stamped(msg, t):
    msg.header.stamp = seconds_to_stamp(t)
    return msg


def _joint_state(t):
    return _stamped(JointState(name=PUMA_JOINTS, position=[0.0] * 6, velocity=[0.0] * 6), t)


def _pp_state(t):
    """Return the PP robot of Ej. 8.10 at x = (2, 4) m, at rest (joints [d2, d1])."""
    return _stamped(JointState(name=['d2_vertical', 'd1_horizontal'],
                               position=[math.sqrt(2.0), 3.0 * math.sqrt(2.0)],
                               velocity=[0.0, 0.0]), t)


def _wrench(t):
    return _stamped(WrenchStamped(), t)


def _trajectory(t):
    return JointTrajectory(joint_names=PUMA_JOINTS, points=[
        JointTrajectoryPoint(positions=[0.0] * 6, time_from_start=Duration(sec=s))
        for s in (0, 100)])


def _odom(t):
    msg = _stamped(Odometry(), t)
    msg.header.frame_id = 'odom'
    msg.pose.pose.position.y = 0.5
    msg.pose.pose.orientation.w = 1.0
    return msg


def _path(t):
    return path_message(np.column_stack([0.1 * np.arange(101), np.zeros(101)]), 'odom')


def _wall_scan(t):
    """Return a laser scan of a wall 0.7 m to the left (y = 0.7), beams from -90° to 90°."""
    msg = _stamped(LaserScan(angle_min=-math.pi / 2, angle_increment=math.pi / 180,
                             range_min=0.05, range_max=4.0), t)
    angles = [msg.angle_min + k * msg.angle_increment for k in range(181)]
    msg.ranges = [0.7 / math.sin(a) if math.sin(a) > 0.7 / 4.0 else math.inf for a in angles]
    return msg


S = 1.0 / math.sqrt(2.0)
CASES = {
    'joint_controller_hybrid': (   # a force law: it waits for the wrench of each state's stamp
        ['-p', 'law:=hybrid', '-p', 'robot:=pp_robot', '-p', 'gravity:=[0.0, -9.81, 0.0]',
         '-p', f'task.axes:=[{S}, {-S}, 0.0, {S}, {S}, 0.0]'],
        {'joint_states': (JointState, _pp_state), 'contact_wrench': (WrenchStamped, _wrench)},
        {'joint_torques': Float64MultiArray,
         '/joint_controller/force_control': ForceControlState},
        lambda got: any(m.header.stamp.sec >= 100
                        for m in got['/joint_controller/force_control'][-20:])),
    'joint_controller': (
        [], {'joint_states': (JointState, _joint_state),
             '/joint_controller/joint_trajectory': (JointTrajectory, _trajectory)},
        {'joint_torques': Float64MultiArray,
         '/joint_controller/controller_state': JointControllerState},
        lambda got: any(m.header.stamp.sec >= 100
                        for m in got['/joint_controller/controller_state'][-20:])),
    'path_tracker': (
        ['-r', '/path_tracker/path:=/path'],
        {'odom': (Odometry, _odom), '/path': (Path, _path)},
        {'cmd_vel': Twist, '/path_tracker/tracking_error': TrackingError},
        lambda got: any(m.header.stamp.sec >= 100 and m.cross_track == pytest.approx(0.5)
                        for m in got['/path_tracker/tracking_error'][-20:])
        and got['cmd_vel'][-1].linear.x > 0.0),
    'reactive_navigator': (
        [], {'odom': (Odometry, _odom), 'scan': (LaserScan, _wall_scan)},
        {'cmd_vel': Twist},
        lambda got: bool(got['cmd_vel']) and got['cmd_vel'][-1].linear.x > 0.0),
}


@pytest.mark.parametrize('case', sorted(CASES))
def test_hostile_messages_neither_kill_nor_poison_the_node(case, start_node, ros_node,
                                                           fuzz_survived):
    parameters, inputs, outputs, recovered = CASES[case]
    node, executor = ros_node
    proc = start_node('robotica_ctrl', case.partition('_hybrid')[0], *parameters)
    received, ok = fuzz(node, executor, inputs, outputs, recovered, random.Random(f'{case}-16'))
    fuzz_survived(proc, received, ok, {   # NaN: the axes without a position or force reference
        '/joint_controller/force_control': ('position_reference', 'force_reference')})


def test_a_state_whose_torques_overflow_is_not_answered(start_node, ros_node, spin, read_output):
    # The issue's case: q' = 1e200 made rne return NaN and the controller publish NaN torques.
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'joint_controller')
    received, ok = fuzz(
        node, executor, {'joint_states': (JointState, _joint_state)},
        {'joint_torques': Float64MultiArray}, lambda got: bool(got['joint_torques']),
        random.Random(0), count=0)
    assert ok
    n = len(received['joint_torques'])
    pub = node.create_publisher(JointState, 'joint_states', 10)
    bad = _stamped(JointState(name=PUMA_JOINTS, position=[0.0] * 6, velocity=[1e200] * 6), 200.0)
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    pub.publish(bad)
    assert spin(executor, lambda: 'joint velocities' in read_output(proc), timeout=10.0)
    assert all(math.isfinite(v) for m in received['joint_torques'][n:] for v in m.data)
    assert proc.poll() is None


def _answering_pid(start_node, ros_node, spin):
    """Start a PID joint controller with K_i = 10 that answers; return it, what it sent, a pub."""
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'joint_controller', '-p', 'law:=pid',
                      '-p', 'pid.ki:=[10.0]')
    received, ok = fuzz(
        node, executor, {'joint_states': (JointState, _joint_state)},
        {'joint_torques': Float64MultiArray,
         '/joint_controller/controller_state': JointControllerState},
        lambda got: len(got['/joint_controller/controller_state']) > 5, random.Random(0),
        count=0)
    assert ok
    pub = node.create_publisher(JointState, 'joint_states', 10)
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    return proc, received, pub


def _offset_state(t: float) -> JointState:
    """Return a state 0.05 rad from the held one on every joint, stamped ``t`` [s]."""
    return _stamped(JointState(name=PUMA_JOINTS, position=[0.05] * 6, velocity=[0.0] * 6), t)


def test_a_state_stamped_far_ahead_is_not_integrated(start_node, ros_node, spin):
    # Campaign of issue 16: with K_i = 10, one state stamped 1e6 s after the previous one was
    # integrated over 1e6 s and answered with 5e5 N m on every joint (5e8 N m at 1e9 s).
    proc, received, pub = _answering_pid(start_node, ros_node, spin)
    for t in (1e6, 1e9):
        pub.publish(_offset_state(100.0 + t))
    pub.publish(_joint_state(200.0))   # answered after the two above: they were handled
    states = received['/joint_controller/controller_state']
    assert spin(ros_node[1], lambda: states[-1].header.stamp.sec == 200)
    assert all(m.header.stamp.sec < 1e6 for m in states)   # the far ones not answered
    assert max(abs(v) for m in received['joint_torques'] for v in m.data) < 100.0
    assert proc.poll() is None


def test_a_stamp_gap_beyond_max_period_resets_the_integral(start_node, ros_node, spin,
                                                           read_output):
    # Issue 16 leftover: a gap of 1000 s passes the stamp gate (3600 s) and was integrated:
    # K_i = 10, an error of 0.05 rad over 1000 s gave 501 N m on every joint.
    proc, received, pub = _answering_pid(start_node, ros_node, spin)
    pub.publish(_offset_state(1100.0))
    states = received['/joint_controller/controller_state']
    assert spin(ros_node[1], lambda: states[-1].header.stamp.sec == 1100)   # answered
    assert max(abs(v) for v in states[-1].effort) < 100.0
    assert 'joint_states gap of' in read_output(proc) and 'controller reset' in read_output(proc)
    assert proc.poll() is None


def test_a_refused_path_keeps_the_previous_one(start_node, ros_node, spin, read_output):
    # Campaign of issue 16: a refused path (here empty) made the tracker drop the path it had
    # and stop for good, since a run's path is published once (latched).
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'path_tracker', '-r', '/path_tracker/path:=/path')
    follows = (lambda got: any(m.header.stamp.sec >= 100 and m.cross_track == pytest.approx(0.5)
                               for m in got['/path_tracker/tracking_error'][-20:]))
    received, ok = fuzz(node, executor, {'odom': (Odometry, _odom), '/path': (Path, _path)},
                        {'cmd_vel': Twist, '/path_tracker/tracking_error': TrackingError},
                        follows, random.Random(0), count=0)
    assert ok
    bad = node.create_publisher(Path, '/path', LATCHED_QOS)
    assert spin(executor, lambda: bad.get_subscription_count() > 0)
    bad.publish(Path())
    assert spin(executor, lambda: 'keeping the previous path' in read_output(proc))
    odom = node.create_publisher(Odometry, 'odom', 10)
    assert spin(executor, lambda: odom.get_subscription_count() > 0)
    errors = received['/path_tracker/tracking_error']
    n = len(errors)
    for k in range(20):
        odom.publish(_odom(300.0 + 0.02 * k))
        spin(executor, lambda: False, 0.02)
    assert spin(executor, lambda: len(errors) > n)
    assert errors[-1].header.stamp.sec >= 300 and errors[-1].cross_track == pytest.approx(0.5)
    assert received['cmd_vel'][-1].linear.x > 0.0
