"""
Node tests of arm_simulator: free fall in lockstep against an independent ODE solution, brakes.

Reference: the planar 2R of Ej. 5.1 (point masses at the link ends, gravity along -y) given as
a ``dyn_table`` parameter. Its closed form (5.76)-(5.77) (``tests/reference_models.py``),
integrated by SciPy's ``solve_ivp`` at tight tolerances, is what the simulator's Pinocchio ABA
and RK4 at 1 kHz must reproduce when every step is answered with zero torque.
"""
import math

import numpy as np
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from reference_models import closed_form_2r
from scipy.integrate import solve_ivp
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
M1, M2, L1, L2, G = 2.0, 1.0, 1.0, 0.5, 9.81


def _dyn_table_parameter() -> str:
    rows = [[0.0] * 20, [0.0] * 20]
    rows[0][5], rows[0][6], rows[0][16] = M1, L1, 1.0
    rows[1][1], rows[1][5], rows[1][6], rows[1][16] = L1, M2, L2, 1.0
    return 'dyn_table:=[' + ', '.join(f'{v:.6f}' for row in rows for v in row) + ']'


def _two_link_free_fall(t_end: float) -> np.ndarray:
    """Integrate M(q) q'' + V(q, q') + G(q) = 0 of the 2R (5.76)-(5.77) from rest."""
    def rhs(_, x):
        m, v, g, _ = closed_form_2r(M1, M2, L1, L2, x[:2], x[2:], [0.0, 0.0], G)
        return np.concatenate([x[2:], np.linalg.solve(m, -v - g)])
    return solve_ivp(rhs, (0.0, t_end), [0.0, 0.0, 0.0, 0.0], rtol=1e-11, atol=1e-12).y[:, -1]


def _stamp(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def test_free_fall_in_lockstep_matches_the_closed_form(start_node, ros_node, spin):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'arm_simulator', '-p', "robot:=''", '-p',
                      _dyn_table_parameter(), '-p', 'gravity:=[0.0, -9.81, 0.0]', '-p',
                      'pacing:=lockstep', '-p', 'end_time:=0.2')
    torques = node.create_publisher(Float64MultiArray, 'joint_torques', QOS)
    states = []

    def answer(msg: JointState) -> None:
        states.append(msg)
        torques.publish(Float64MultiArray(data=[0.0, 0.0]))

    node.create_subscription(JointState, 'joint_states', answer, QOS)
    assert spin(executor, lambda: proc.poll() is not None, timeout=60.0)
    assert proc.returncode == 0
    last = states[-1]
    assert _stamp(last) == pytest.approx(0.2, abs=1e-9)
    expected = _two_link_free_fall(0.2)
    np.testing.assert_allclose(last.position, expected[:2], atol=1e-7)
    np.testing.assert_allclose(last.velocity, expected[2:], atol=1e-6)
    assert last.velocity[0] < -0.5     # it did fall: joint 1 turns towards -y
    assert list(last.effort) == [0.0, 0.0]
    assert list(last.name) == ['joint_1', 'joint_2']


def test_brakes_hold_without_commands_and_on_nan(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'arm_simulator', '-p', 'robot:=puma560', '-p',
                      'initial_positions:=[0.0, 0.5, -0.5, 0.0, 0.0, 0.0]')
    states = []
    node.create_subscription(JointState, 'joint_states', states.append, QOS)
    torques = node.create_publisher(Float64MultiArray, 'joint_torques', QOS)
    assert spin(executor, lambda: len(states) > 50 and torques.get_subscription_count() > 0)
    assert 'brakes on' in read_output(proc)
    np.testing.assert_allclose(states[-1].position, [0.0, 0.5, -0.5, 0.0, 0.0, 0.0], atol=1e-12)
    assert list(states[-1].velocity) == [0.0] * 6
    for _ in range(10):
        torques.publish(Float64MultiArray(data=[math.nan] * 6))
        spin(executor, lambda: False, timeout=0.02)
    assert 'joint_torques: ValueError' in read_output(proc)
    np.testing.assert_allclose(states[-1].position, [0.0, 0.5, -0.5, 0.0, 0.0, 0.0], atol=1e-12)
    assert proc.poll() is None


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'robot:=scara'), 'unknown robot'),
    (('-p', "robot:=''", '-p', 'dyn_table:=[1.0, 2.0]'), 'rows of 20 values'),
    (('-p', 'tau_max:=[1.0, 2.0]'), 'tau_max needs 1 or 6 values'),
    (('-p', 'tau_max:=[0.0]'), 'tau_max must be > 0 N m per joint'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_sim', 'arm_simulator', *arguments)
    assert proc.wait(timeout=30) == 2
    assert reason in read_output(proc)
