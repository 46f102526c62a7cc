"""
Tests of robotica_ctrl.force_control: task frame, laws and steady state (catalog §6.7, §6.8).

References: Ej. 8.10's task coordinates (8.185)-(8.186) and steady state (8.176)-(8.179); the
closed-form dynamics of the Ej. 5.1 arm (5.76)-(5.77) and its tip kinematics, written out
here, against which the laws' torques are checked: (8.168) term by term, and ``x'' = p``
(8.194) for the linearising law (8.193) of the hybrid (8.197)-(8.205) and impedance laws.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.force_control import (HybridForcePosition, HybridGains, ImpedanceControl,
                                         ImpedanceGains, stiffness_set_point,
                                         stiffness_steady_state, StiffnessControl, StiffnessGains,
                                         TaskFrame, TaskKinematics, TaskReference)
from robotica_ctrl.joint_control import JointState
from robotica_kin.dh import dh_model
from robotica_kin.robots import pp_robot, two_link_arm
from robotica_kin.transforms import transl

S = 1.0 / math.sqrt(2.0)
EJ_8_10_FRAME = TaskFrame([[S, S], [-S, S], [0.0, 0.0]])
PLANAR = [0.0, -9.81, 0.0]
M1, M2, L1, L2, G = 2.0, 1.0, 3.0, 1.0, 9.81


def _two_link_robot():
    """Return the Ej. 5.1 arm (m = 2, 1 kg; l = 3, 1 m) with its tip as the tool frame."""
    dh, dyn = two_link_arm(M1, M2, L1, L2)
    return dh_model(dh, dyn=dyn, tool=transl(L2, 0.0, 0.0))


def _two_link_closed_form(q, qd):
    """Return M, V, G (5.76)-(5.77) and the tip's p, J, J' q' of the Ej. 5.1 arm."""
    c1, s1 = math.cos(q[0]), math.sin(q[0])
    c2, s2 = math.cos(q[1]), math.sin(q[1])
    c12, s12 = math.cos(q[0] + q[1]), math.sin(q[0] + q[1])
    m12 = L2 ** 2 * M2 + L1 * L2 * M2 * c2
    M = np.array([[L2 ** 2 * M2 + 2 * L1 * L2 * M2 * c2 + L1 ** 2 * (M1 + M2), m12],
                  [m12, L2 ** 2 * M2]])
    h = M2 * L1 * L2 * s2
    V = np.array([-h * qd[1] ** 2 - 2 * h * qd[0] * qd[1], h * qd[0] ** 2])
    Gv = np.array([G * ((M1 + M2) * L1 * c1 + M2 * L2 * c12), G * M2 * L2 * c12])
    p = np.array([L1 * c1 + L2 * c12, L1 * s1 + L2 * s12, 0.0])
    J = np.array([[-L1 * s1 - L2 * s12, -L2 * s12], [L1 * c1 + L2 * c12, L2 * c12],
                  [0.0, 0.0]])
    w12 = qd[0] + qd[1]
    Jdqd = np.array([-L1 * c1 * qd[0] ** 2 - L2 * c12 * w12 ** 2,
                     -L1 * s1 * qd[0] ** 2 - L2 * s12 * w12 ** 2, 0.0])
    return M, V, Gv, p, J, Jdqd


def _turned_frame(beta=0.4, normal_axes=1):
    """Return a task frame turned by beta in the XY plane, origin away from {0}."""
    c, s = math.cos(beta), math.sin(beta)
    return TaskFrame([[c, -s], [s, c], [0.0, 0.0]], origin=[0.5, -0.2, 0.0],
                     normal_axes=normal_axes)


STATES = [([0.3, 0.9], [0.4, -0.7]), ([-1.2, 2.0], [-0.5, 1.1]), ([2.5, -0.6], [0.0, 0.0])]


@pytest.mark.parametrize(('d1', 'd2'), [(3 * math.sqrt(2.0), math.sqrt(2.0)), (0.4, -1.3)])
def test_ej_8_10_task_coordinates_and_jacobian(d1, d2):
    # (8.185)-(8.186) in the book's order [d1, d2]; the chain's is [d2, d1].
    x, x_dot, J = TaskKinematics(pp_robot(), EJ_8_10_FRAME).evaluate(
        np.array([d2, d1]), np.array([0.5, -0.25]))
    np.testing.assert_allclose(x, S * np.array([d1 - d2, d1 + d2]), atol=1e-12)
    np.testing.assert_allclose(J[:, [1, 0]], S * np.array([[1, -1], [1, 1]]), atol=1e-12)
    np.testing.assert_allclose(x_dot, S * np.array([-0.25 - 0.5, -0.25 + 0.5]), atol=1e-12)


@pytest.mark.parametrize(('q', 'qd'), STATES)
def test_task_kinematics_and_bias_acceleration_match_the_closed_form(q, qd):
    frame = _turned_frame()
    kinematics = TaskKinematics(_two_link_robot(), frame)
    q, qd = np.array(q), np.array(qd)
    _, _, _, p, J_p, Jdqd = _two_link_closed_form(q, qd)
    R = np.asarray(frame.rotation)
    x, x_dot, J = kinematics.evaluate(q, qd)
    np.testing.assert_allclose(x, R.T @ (p - [0.5, -0.2, 0.0]), atol=1e-12)
    np.testing.assert_allclose(J, R.T @ J_p, atol=1e-12)
    np.testing.assert_allclose(x_dot, R.T @ J_p @ qd, atol=1e-12)
    np.testing.assert_allclose(kinematics.bias_acceleration(q, qd), R.T @ Jdqd, atol=1e-12)


def test_ej_8_10_steady_state_and_set_point():
    # Catalog §6.8: x_d1 = 3/10 + 2 = 2.3 m; x1(∞) = 2.00248 m, ψ1(∞) = 2.975 N; along the
    # surface (K_e = 0) x2(∞) = x_d2 (8.180).
    assert float(stiffness_set_point(3.0, 10.0, 2.0)) == pytest.approx(2.3, abs=1e-12)
    x, psi = stiffness_steady_state([10.0, 10.0], [1200.0, 0.0], [2.3, 2.0], [2.0, 0.0])
    np.testing.assert_allclose(x, [2.00248, 2.0], atol=5e-6)
    np.testing.assert_allclose(psi, [2.975, 0.0], atol=5e-4)
    assert psi[0] == pytest.approx(1200.0 * 10.0 / 1210.0 * 0.3, rel=1e-12)   # (8.178)
    # K_e ≫ K_p: ψ(∞) -> K_p (x_d - x_e) (8.179).
    _, stiff = stiffness_steady_state(10.0, 1e9, 2.3, 2.0)
    assert float(stiff) == pytest.approx(3.0, rel=1e-7)


@pytest.mark.parametrize(('q', 'qd'), STATES)
def test_stiffness_law_is_8_168(q, qd):
    frame = _turned_frame()
    law = StiffnessControl(_two_link_robot(), frame, StiffnessGains(kp=[12.0, 30.0], kv=4.0),
                           grav=PLANAR)
    q, qd = np.array(q), np.array(qd)
    _, _, Gv, p, J_p, _ = _two_link_closed_form(q, qd)
    R = np.asarray(frame.rotation)
    x, J = R.T @ (p - [0.5, -0.2, 0.0]), R.T @ J_p
    x_d = np.array([0.7, -1.1])
    psi = np.array([2.0, 0.5])        # measured: enters only the telemetry
    tau = law.update(TaskReference(x_d, xd_d=[9.0, 9.0]), JointState(q, qd), psi, 1e-3)
    expected = J.T @ (-4.0 * (J @ qd) + np.array([12.0, 30.0]) * (x_d - x)) + Gv
    np.testing.assert_allclose(tau, expected, rtol=1e-10, atol=1e-10)
    telemetry = law.telemetry
    np.testing.assert_allclose(telemetry.position, x, atol=1e-12)
    np.testing.assert_array_equal(telemetry.force, psi)
    np.testing.assert_array_equal(telemetry.effort, tau)
    assert telemetry.law == 'stiffness' and np.isnan(telemetry.force_reference).all()
    law.reset()
    assert law.telemetry is None


def _plant_task_acceleration(tau, q, qd, frame, psi):
    """Return x'' of the true arm under tau and the contact load J_pᵀ R ψ (8.165)."""
    M, V, Gv, _, J_p, Jdqd = _two_link_closed_form(q, qd)
    R = np.asarray(frame.rotation)
    qdd = np.linalg.solve(M, tau - V - Gv - J_p.T @ (R @ psi))
    return R.T @ (J_p @ qdd + Jdqd)


@pytest.mark.parametrize(('q', 'qd'), STATES)
def test_hybrid_law_linearises_to_x_dd_equal_p(q, qd):
    frame = _turned_frame()
    gains = HybridGains(kp_tangential=9.0, kv_tangential=6.0, kp_normal=16.0, kv_normal=8.0)
    law = HybridForcePosition(_two_link_robot(), frame, 1500.0, gains, grav=PLANAR)
    q, qd = np.array(q), np.array(qd)
    reference = TaskReference(x_d=[0.0, 1.3], xd_d=[0.0, -0.4], xdd_d=[0.0, 0.2],
                              psi_d=[4.0, 0.0], psid_d=[1.5, 0.0], psidd_d=[-2.0, 0.0])
    psi = np.array([3.2, 0.0])
    tau = law.update(reference, JointState(q, qd), psi, 1e-3)
    _, _, _, p_0, J_p, _ = _two_link_closed_form(q, qd)
    R = np.asarray(frame.rotation)
    x, x_dot = R.T @ (p_0 - [0.5, -0.2, 0.0]), R.T @ J_p @ qd
    # (8.197) on the tangential axis, (8.205) with ψ' = K_e x_N' on the normal one.
    p_t = 0.2 + 6.0 * (-0.4 - x_dot[1]) + 9.0 * (1.3 - x[1])
    p_n = (-2.0 + 8.0 * (1.5 - 1500.0 * x_dot[0]) + 16.0 * (4.0 - 3.2)) / 1500.0
    np.testing.assert_allclose(law.telemetry.acceleration_command, [p_n, p_t], rtol=1e-10)
    np.testing.assert_allclose(_plant_task_acceleration(tau, q, qd, frame, psi), [p_n, p_t],
                               rtol=1e-8, atol=1e-9)
    assert law.force_rate == pytest.approx([1500.0 * x_dot[0]])
    np.testing.assert_array_equal(np.isnan(law.telemetry.position_reference), [True, False])
    np.testing.assert_array_equal(np.isnan(law.telemetry.force_reference), [False, True])


def test_hybrid_force_axis_is_8_214_of_ej_8_11():
    # (8.214), force line: x_N1'' = (1/1200)[-4e^{-2t} + 15(2e^{-2t} - 1200 x_N1')
    # + 15(1 - e^{-2t} - 1200(x_N1 - 2))], with ψ = 1200 (x_N1 - 2) measured.
    law = HybridForcePosition(pp_robot(), EJ_8_10_FRAME, 1200.0, grav=PLANAR)
    t, x_n, x_n_dot = 0.3, 2.0004, 0.01
    d1, d2 = S * (x_n + 3.0), S * (3.0 - x_n)
    e = math.exp(-2 * t)
    reference = TaskReference([0.0, 2 + math.cos(t)], [0.0, -math.sin(t)], [0.0, -math.cos(t)],
                              [1 - e, 0.0], [2 * e, 0.0], [-4 * e, 0.0])
    state = JointState([d2, d1], [-S * x_n_dot, S * x_n_dot])    # x' = (x_n_dot, 0)
    law.update(reference, state, [1200.0 * (x_n - 2.0), 0.0], 1e-3)
    expected = (-4 * e + 15 * (2 * e - 1200 * x_n_dot)
                + 15 * (1 - e - 1200 * (x_n - 2))) / 1200
    assert law.telemetry.acceleration_command[0] == pytest.approx(expected, rel=1e-9)
    assert law.telemetry.acceleration_command[1] == pytest.approx(
        -math.cos(t) + 15 * (-math.sin(t)) + 15 * (2 + math.cos(t) - 3.0), rel=1e-9)


@pytest.mark.parametrize(('q', 'qd'), STATES)
def test_impedance_law_gives_the_target_impedance(q, qd):
    frame = _turned_frame(beta=-0.8)
    gains = ImpedanceGains(inertia=[2.0, 0.5], damping=[10.0, 3.0], stiffness=[40.0, 7.0])
    law = ImpedanceControl(_two_link_robot(), frame, gains, grav=PLANAR)
    q, qd = np.array(q), np.array(qd)
    x_d, xd_d, xdd_d = np.array([0.3, 1.0]), np.array([0.2, -0.1]), np.array([0.05, 0.4])
    psi = np.array([6.0, -1.0])
    tau = law.update(TaskReference(x_d, xd_d, xdd_d), JointState(q, qd), psi, 1e-3)
    _, _, _, p_0, J_p, _ = _two_link_closed_form(q, qd)
    R = np.asarray(frame.rotation)
    x, x_dot = R.T @ (p_0 - [0.5, -0.2, 0.0]), R.T @ J_p @ qd
    x_dd = _plant_task_acceleration(tau, q, qd, frame, psi)
    # M_d x̃'' + B_d x̃' + K_d x̃ = ψ with x̃ = x_d - x.
    lhs = (np.array([2.0, 0.5]) * (xdd_d - x_dd) + np.array([10.0, 3.0]) * (xd_d - x_dot)
           + np.array([40.0, 7.0]) * (x_d - x))
    np.testing.assert_allclose(lhs, psi, rtol=1e-8, atol=1e-8)


def test_joint_friction_of_the_model_is_added():
    dh, dyn = two_link_arm(M1, M2, L1, L2)
    dyn[:, 17] = [0.5, 0.2]        # viscous B, gear ratio 1: F = B q'
    robot = dh_model(dh, dyn=dyn, tool=transl(L2, 0.0, 0.0))
    state, reference = JointState([0.3, 0.9], [0.4, -0.7]), TaskReference([1.0, 2.0])
    with_f = StiffnessControl(robot, _turned_frame(), grav=PLANAR)
    without = StiffnessControl(robot, _turned_frame(), grav=PLANAR, use_friction=False)
    difference = (with_f.update(reference, state, [0.0, 0.0], 1e-3)
                  - without.update(reference, state, [0.0, 0.0], 1e-3))
    np.testing.assert_allclose(difference, [0.5 * 0.4, 0.2 * -0.7], rtol=1e-12)


def _ej_8_11_law():
    return HybridForcePosition(pp_robot(), EJ_8_10_FRAME, 1200.0, grav=PLANAR)


STATE = JointState([math.sqrt(2.0), 3 * math.sqrt(2.0)], [0.0, 0.0])
REFERENCE = TaskReference([2.0, 4.0])


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: TaskFrame([[1.0, 0.5], [0.0, 1.0], [0.0, 0.0]]), 'orthonormal'),
    (lambda: TaskFrame(np.eye(3)[:, :0]), 'shape'),
    (lambda: TaskFrame(np.eye(2)), 'shape'),
    (lambda: TaskFrame(np.eye(3), origin=[0.0, math.nan, 0.0]), 'origin'),
    (lambda: TaskFrame(np.eye(3), normal_axes=4), 'normal_axes'),
    (lambda: TaskFrame(np.eye(3), normal_axes=True), 'normal_axes'),
    (lambda: EJ_8_10_FRAME.to_task([1.0, 2.0]), 'vector'),
    (lambda: TaskReference([1.0, 2.0], xd_d=[1.0]), 'same shape'),
    (lambda: TaskReference([1.0, math.inf]), 'finite'),
    (lambda: StiffnessGains(kp=0.0), 'kp'),
    (lambda: StiffnessGains(kv=[-1.0, 1.0]), 'kv'),
    (lambda: HybridGains(kp_normal=math.nan), 'kp_normal'),
    (lambda: ImpedanceGains(inertia=0.0), 'inertia'),
    (lambda: ImpedanceGains(stiffness=-5.0), 'stiffness'),
    (lambda: stiffness_steady_state(0.0, 1200.0, 2.3, 2.0), 'kp'),
    (lambda: stiffness_steady_state(10.0, -1.0, 2.3, 2.0), 'ke'),
    (lambda: stiffness_steady_state(10.0, [1.0, 2.0, 3.0], [2.3, 2.0], 2.0), 'same size'),
    (lambda: stiffness_set_point(math.nan, 10.0, 2.0), 'psi_d'),
    (lambda: StiffnessControl(pp_robot(), EJ_8_10_FRAME, gains=HybridGains()), 'gains'),
    (lambda: StiffnessControl(pp_robot(), np.eye(3)), 'task_frame'),
    (lambda: StiffnessControl(pp_robot(), EJ_8_10_FRAME, StiffnessGains(kp=[1.0, 2.0, 3.0])),
     'kp'),
    (lambda: HybridForcePosition(pp_robot(), TaskFrame(np.eye(3)), 1200.0), 'axes'),
    (lambda: HybridForcePosition(pp_robot(), EJ_8_10_FRAME, 0.0), 'environment_stiffness'),
    (lambda: HybridForcePosition(pp_robot(), EJ_8_10_FRAME, [1.0, 2.0]),
     'environment_stiffness'),
    (lambda: ImpedanceControl(pp_robot(), TaskFrame(np.eye(3)[:, :1])), 'axes'),
    (lambda: _ej_8_11_law().update(REFERENCE, STATE, [0.0], 1e-3), 'force'),
    (lambda: _ej_8_11_law().update(REFERENCE, STATE, [math.nan, 0.0], 1e-3), 'force'),
    (lambda: _ej_8_11_law().update(REFERENCE, STATE, 'push', 1e-3), 'force'),
    (lambda: _ej_8_11_law().update(REFERENCE, STATE, [0.0, 0.0], 0.0), 'dt'),
    (lambda: _ej_8_11_law().update(TaskReference([1.0, 2.0, 3.0]), STATE, [0.0, 0.0], 1e-3),
     'axes'),
    (lambda: _ej_8_11_law().update(REFERENCE, JointState([0.0], [0.0]), [0.0, 0.0], 1e-3),
     'joints'),
    (lambda: _ej_8_11_law().update([2.0, 4.0], STATE, [0.0, 0.0], 1e-3), 'TaskReference'),
    # The Ej. 5.1 arm stretched out (q2 = 0) has a singular Jacobian: Ĵ⁻¹ does not exist.
    (lambda: ImpedanceControl(_two_link_robot(), _turned_frame()).update(
        TaskReference([0.0, 0.0]), JointState([0.3, 0.0], [0.0, 0.0]), [0.0, 0.0], 1e-3),
     'singular'),
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
