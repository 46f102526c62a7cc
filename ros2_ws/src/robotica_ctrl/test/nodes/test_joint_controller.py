"""
Node tests of joint_controller: torques from real messages, holding, refused input and laws.

References computed here by hand: a decoupled PD (book (8.10)) on a constant reference gives
``tau = K_p e - K_v q'``; computed torque holding the planar 2R of Ej. 5.1 at rest gives its
gravity torques ``G1 = m2 l2 g c12 + (m1 + m2) l1 g c1``, ``G2 = m2 l2 g c12`` (5.77).
"""
import math

from builtin_interfaces.msg import Duration
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_msgs.msg import JointControllerState
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
PUMA_JOINTS = [f'joint_{i}' for i in range(1, 7)]
M1, M2, L1, L2, G = 2.0, 1.0, 1.0, 0.5, 9.81


def _state(names, q, qd, t=1.0):
    msg = JointState(name=list(names), position=list(q), velocity=list(qd))
    msg.header.stamp.sec = int(t)
    msg.header.stamp.nanosec = int(round((t - int(t)) * 1e9))
    return msg


def _constant_trajectory(names, q):
    msg = JointTrajectory(joint_names=list(names))
    msg.points = [JointTrajectoryPoint(positions=list(q), time_from_start=Duration(sec=s))
                  for s in (0, 100)]
    return msg


def _controller(start_node, ros_node, spin, *arguments):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'joint_controller', *arguments)
    torques, states = [], []
    node.create_subscription(Float64MultiArray, 'joint_torques', torques.append, QOS)
    node.create_subscription(JointControllerState, '/joint_controller/controller_state',
                             states.append, QOS)
    joint_states = node.create_publisher(JointState, 'joint_states', QOS)
    trajectory = node.create_publisher(JointTrajectory, '/joint_controller/joint_trajectory',
                                       LATCHED)
    assert spin(executor, lambda: joint_states.get_subscription_count() > 0 and
                trajectory.get_subscription_count() > 0)
    return proc, executor, joint_states, trajectory, torques, states


def test_pd_on_a_constant_reference(start_node, ros_node, spin, publish):
    proc, executor, joint_states, trajectory, torques, states = _controller(
        start_node, ros_node, spin, '-p', 'law:=pid', '-p', 'pid.kp:=[25.0]', '-p',
        'pid.kv:=[10.0]')
    reference = [0.1, -0.2, 0.3, 0.0, 0.05, -0.1]
    trajectory.publish(_constant_trajectory(PUMA_JOINTS, reference))
    qd = [0.0, 0.1, 0.0, -0.2, 0.0, 0.0]
    # The reference arrives latched; resend the state until a torque for it comes back.
    expected = 25.0 * np.array(reference) - 10.0 * np.array(qd)
    assert publish(executor, joint_states, _state(PUMA_JOINTS, [0.0] * 6, qd),
                   lambda: torques and np.allclose(torques[-1].data, expected, atol=1e-12))
    # The state of that answer comes on its own topic, possibly after older ones (holding).
    assert spin(executor, lambda: states and np.allclose(states[-1].position_error, reference,
                                                         rtol=0.0, atol=1e-12))
    np.testing.assert_allclose(states[-1].effort, expected, atol=1e-12)
    np.testing.assert_allclose(states[-1].reference_position, reference, atol=1e-12)
    assert states[-1].law == 'pid'


def test_computed_torque_holds_the_two_link_arm_against_gravity(start_node, ros_node, spin,
                                                                publish, read_output):
    table = np.zeros((2, 20))
    table[:, 5], table[:, 6], table[:, 16] = [M1, M2], [L1, L2], 1.0
    table[1, 1] = L1
    proc, executor, joint_states, trajectory, torques, states = _controller(
        start_node, ros_node, spin, '-p', "robot:=''", '-p',
        'dyn_table:=[' + ', '.join(f'{v:.6f}' for v in table.ravel()) + ']', '-p',
        'gravity:=[0.0, -9.81, 0.0]', '-p', 'joint_names:=[shoulder, elbow]')
    q = [0.3, 0.4]
    c1, c12 = math.cos(q[0]), math.cos(q[0] + q[1])
    expected = [M2 * L2 * G * c12 + (M1 + M2) * L1 * G * c1, M2 * L2 * G * c12]
    # Names in another order than the controller's: matched by name.
    assert publish(executor, joint_states, _state(['elbow', 'shoulder'], q[::-1], [0.0, 0.0]),
                   lambda: torques)
    np.testing.assert_allclose(torques[-1].data, expected, rtol=1e-9)
    assert 'holding q' in read_output(proc)


def test_bad_states_are_not_answered(start_node, ros_node, spin, publish, read_output):
    proc, executor, joint_states, trajectory, torques, states = _controller(
        start_node, ros_node, spin, '-p', 'law:=pid')
    for bad, reason in ((_state(PUMA_JOINTS, [math.nan] * 6, [0.0] * 6),
                         'non-finite joint position'),
                        (_state(PUMA_JOINTS[:5], [0.0] * 5, [0.0] * 5),
                         "lacks positions and velocities of ['joint_6']")):
        # The guard logs one refusal per topic and second: resend until this one is logged.
        assert publish(executor, joint_states, bad, lambda: reason in read_output(proc)), reason
    assert not torques
    assert publish(executor, joint_states, _state(PUMA_JOINTS, [0.0] * 6, [0.0] * 6),
                   lambda: torques)   # and it still answers good states
    assert proc.poll() is None


def test_a_trajectory_without_our_joints_is_refused(start_node, ros_node, spin, publish,
                                                    read_output):
    proc, executor, joint_states, trajectory, torques, states = _controller(
        start_node, ros_node, spin, '-p', 'law:=pid')
    trajectory.publish(_constant_trajectory(['a', 'b'], [1.0, 1.0]))
    assert spin(executor, lambda: 'trajectory refused' in read_output(proc))
    assert publish(executor, joint_states, _state(PUMA_JOINTS, [0.2] * 6, [0.0] * 6),
                   lambda: torques)
    np.testing.assert_allclose(torques[-1].data, [0.0] * 6, atol=1e-12)   # holds q


def test_waiting_for_a_trajectory_answers_no_state_before_it(start_node, ros_node, spin,
                                                             publish, read_output):
    # A lockstep run's controller got its trajectory 0.14 s after the steps began and held
    # q = 0 meanwhile: with wait_for_trajectory it answers nothing until the trajectory.
    proc, executor, joint_states, trajectory, torques, states = _controller(
        start_node, ros_node, spin, '-p', 'law:=pid', '-p', 'wait_for_trajectory:=true')
    joint_states.publish(_state(PUMA_JOINTS, [0.2] * 6, [0.0] * 6))
    assert spin(executor, lambda: 'waiting for a trajectory' in read_output(proc))
    assert not torques
    trajectory.publish(_constant_trajectory(PUMA_JOINTS, [0.5] * 6))
    assert publish(executor, joint_states, _state(PUMA_JOINTS, [0.2] * 6, [0.0] * 6, t=2.0),
                   lambda: states)
    np.testing.assert_allclose(states[-1].reference_position, [0.5] * 6)


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'law:=lqr'), 'law must be one of'),
    (('-p', 'robot:=planar_rr'), 'no dynamic parameters'),
    (('-p', 'first_period:=0.0'), 'first_period'),
    (('-p', 'law:=pid', '-p', 'pid.kp:=[1.0, 2.0]'), 'kp must be a scalar or have shape (6,)'),
    (('-p', 'law:=slotine_li', '-p', 'slotine_li.gamma:=[1.0, 2.0]'),
     'gamma must be a scalar or have shape (5,)'),   # one per link mass: link 1 has none
    (('-p', 'law:=learning', '-p', 'learning.mu:=[300.0]'), 'makes the learning diverge'),
    (('-p', 'law:=stiffness', '-p', 'task.axes:=[1.0, 0.0]'), 'task.axes must be 3, 6 or 9'),
    (('-p', 'law:=hybrid'), 'needs 6 axes (one per joint), got 1'),
    (('-p', 'law:=operational_space', '-p', 'cartesian.goal:=[0.5, 0.1]'),
     'cartesian.goal must be 6 numbers'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'joint_controller', *arguments)
    assert proc.wait(timeout=30) == 2
    assert reason in read_output(proc)
