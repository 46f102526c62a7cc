"""
Tests of robotica_ctrl.cartesian_control: Cartesian-space control of book §8.6 (catalogue §6.6).

The plants are simulated here, independently of the laws: the 2R of Ej. 5.1 (point masses
m1 = 2, m2 = 1 kg at l1 = 3, l2 = 1 m, gravity [0, −9.81, 0]) by its closed form (5.76)-(5.77)
(tests/reference_models.py), with its tip, Jacobian and inverse kinematics written out below;
the PUMA 560 by Pinocchio's ABA on a model of its own, its pose by the product of Craig's link
transforms (4.5). A stateless law is integrated in continuous time with SciPy (the error is then
the analytic solution to the solver's tolerance); the resolved rate, which integrates q_d, runs
at 1 kHz with the plant advanced by RK4 and the torque held over each step.
"""

import math

import numpy as np
import pinocchio as pin
import pytest
from reference_models import closed_form_2r, fk_by_link_product
from robotica_ctrl.cartesian_control import (CartesianGains, CartesianReference,
                                             damping_factor, joint_rates, line_references,
                                             OperationalSpace, ResolvedRate, ResolvedRateParams,
                                             task_mask, TransposeJacobian)
from robotica_ctrl.joint_control import DecoupledPID, JointState
from robotica_ctrl.trajectory import cartesian_line, pol5
from robotica_kin.dh import dh_model
from robotica_kin.integrators import rk4_step
from robotica_kin.jacobian import manipulability
from robotica_kin.pinocchio_model import build_model
from robotica_kin.robots import planar_rr, puma560, two_link_arm
from robotica_kin.transforms import rotz, transl
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve
from scipy.spatial.transform import Rotation

M1, M2, L1, L2 = 2.0, 1.0, 3.0, 1.0   # Ej. 5.1 / Ej. 8.1
GRAV = [0.0, -9.81, 0.0]              # the book's planar examples
DT = 1e-3                             # [s] control period of the sampled runs
_DH, _DYN = two_link_arm(M1, M2, L1, L2)
ARM_2R = dh_model(_DH, dyn=_DYN, tool=transl(L2, 0.0, 0.0), name='ej_5_1')   # tool at the tip
PUMA = puma560()
Q_PUMA = np.array([0.1, -0.5, 0.6, 0.2, 0.4, -0.3])   # σ_min(J) = 0.16: far from singular


def tip(q):
    """Return the position [m] of the 2R's tip: l1 (c1, s1) + l2 (c12, s12)."""
    return np.array([L1 * math.cos(q[0]) + L2 * math.cos(q[0] + q[1]),
                     L1 * math.sin(q[0]) + L2 * math.sin(q[0] + q[1])])


def jacobian_2r(q):
    """Return the 2R tip Jacobian (4.73): d(x, y)/d(q1, q2)."""
    s1, c1 = math.sin(q[0]), math.cos(q[0])
    s12, c12 = math.sin(q[0] + q[1]), math.cos(q[0] + q[1])
    return np.array([[-L1 * s1 - L2 * s12, -L2 * s12], [L1 * c1 + L2 * c12, L2 * c12]])


def ik_2r(p, elbow=1.0):
    """Return the 2R joint angles reaching the tip p (elbow = ±1 picks sin q2's sign)."""
    c2 = (p[0] ** 2 + p[1] ** 2 - L1 ** 2 - L2 ** 2) / (2.0 * L1 * L2)
    q2 = elbow * math.acos(c2)
    return np.array([math.atan2(p[1], p[0]) - math.atan2(L2 * math.sin(q2), L1 + L2 * c2), q2])


def plant_2r(t, x, tau):
    """Return [q', q''] of the true 2R under tau by the closed form (5.76)-(5.77)."""
    q, qd = x[:2], x[2:]
    M, V, G, _ = closed_form_2r(M1, M2, L1, L2, q, qd, [0.0, 0.0])
    return np.concatenate([qd, np.linalg.solve(M, tau - V - G)])


def puma_plant():
    """Return [q', q''](t, x, tau) of the PUMA 560 by ABA on a model of its own (g along -z)."""
    model = build_model(PUMA)
    data = model.createData()

    def derivative(t, x, tau):
        return np.concatenate([x[6:], pin.aba(model, data, x[:6], x[6:], tau)])
    return derivative


def continuous_run(law, plant, reference, x0, t_eval):
    """Integrate ``plant`` under the stateless ``law`` with reference(t), in continuous time."""
    n = len(x0) // 2

    def closed_loop(t, x):
        return plant(t, x, law.update(reference(t), JointState(x[:n], x[n:]), DT))
    return solve_ivp(closed_loop, (0.0, t_eval[-1]), x0, method='DOP853', rtol=1e-10,
                     atol=1e-12, t_eval=t_eval)


def quintic_profile(t, duration):
    """Return s, s', s'' of the rest-to-rest quintic 10u³ − 15u⁴ + 6u⁵, u = t / duration."""
    u = min(t / duration, 1.0)
    return (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5,
            30 * u ** 2 * (1 - u) ** 2 / duration, 60 * u * (1 - u) * (1 - 2 * u) / duration ** 2)


def timed_line(T0, T1, duration, end):
    """Return the references of the line T0 → T1 every DT from 0 to ``end`` s (held after)."""
    _, _, s, sd, sdd = pol5([0.0, 1.0], [0.0, 0.0], [0.0, 0.0], 0.0, duration, DT)
    hold = int(round((end - duration) / DT))
    ones, zeros = np.ones(hold), np.zeros(hold)
    return line_references(T0, T1, np.concatenate([s, ones]), np.concatenate([sd, zeros]),
                           np.concatenate([sdd, zeros]))


def pose(p, rotvec, R=np.eye(3)):
    """Return the pose with origin p [m] and rotation Rot(rotvec) R (rotvec = ε k̂ [rad])."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix() @ R
    T[:3, 3] = p
    return T


def critically_damped(e0, ed0, omega, t):
    """Return the solution of e'' + 2ω e' + ω² e = 0 from e(0) = e0, e'(0) = ed0."""
    return (e0 + (ed0 + omega * e0) * t) * np.exp(-omega * t)


# --- the reference ----------------------------------------------------------------------------

def test_line_references_are_cartesian_line_poses_with_exact_twist():
    """(10.86)-(10.88): poses of cartesian_line; twist and acceleration match differences."""
    T0 = transl(0.5, 0.1, 0.3) @ rotz(0.2)
    T1 = pose([0.2, 0.4, 0.6], [0.3, -0.4, 0.9])
    duration, h = 2.0, 1e-5
    times = [0.3, 1.0, 1.7]
    profiles = np.array([quintic_profile(t, duration) for t in times]).T
    refs = line_references(T0, T1, *profiles)
    np.testing.assert_allclose([r.T_d for r in refs], cartesian_line(T0, T1, profiles[0]),
                               atol=1e-15)
    for t, ref in zip(times, refs):
        before, after = (cartesian_line(T0, T1, [quintic_profile(t + d, duration)[0]])[0]
                         for d in (-h, h))
        velocity = (after[:3, 3] - before[:3, 3]) / (2 * h)
        omega = Rotation.from_matrix(after[:3, :3] @ before[:3, :3].T).as_rotvec() / (2 * h)
        np.testing.assert_allclose(ref.xd_d, np.concatenate([velocity, omega]), atol=1e-8)
        rate_after, rate_before = (line_references(T0, T1, *np.array(
            [quintic_profile(t + d, duration)]).T)[0].xd_d for d in (h, -h))
        np.testing.assert_allclose(ref.xdd_d, (rate_after - rate_before) / (2 * h), atol=1e-6)


@pytest.mark.parametrize('build, match', [
    (lambda: CartesianReference(np.diag([1.0, 1.0, -1.0, 1.0])), 'T_d'),
    (lambda: CartesianReference(np.eye(3)), 'T_d'),
    (lambda: CartesianReference(np.eye(4), [0.0] * 5 + [np.nan]), 'xd_d'),
    (lambda: CartesianReference(np.eye(4), [0.0] * 3, [0.0] * 3), r'\(6,\)'),
    (lambda: line_references(np.eye(4), transl(1, 0, 0), [0.0, 1.2], [0, 0], [0, 0]), 's'),
    (lambda: line_references(np.eye(4), transl(1, 0, 0), [0.0, 1.0], [0.0], [0, 0]), 'sd'),
    (lambda: line_references(np.eye(4), transl(1, 0, 0), 3, 0.0, 0.0), 's must be a vector'),
])
def test_bad_references_raise(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_reference_is_read_only():
    ref = CartesianReference(transl(1.0, 2.0, 3.0), np.ones(6))
    with pytest.raises(ValueError):
        ref.xd_d[0] = 2.0
    with pytest.raises(AttributeError):
        ref.T_d = np.eye(4)


# --- task rows and the resolution of rates ----------------------------------------------------

def test_task_mask_defaults_and_refusals():
    assert task_mask(None, 6).all() and task_mask(None, 7).all()
    assert task_mask(None, 4).tolist() == [True, True, True, False, False, False]
    assert task_mask(None, 2).tolist() == [True, True, False, False, False, False]
    assert task_mask([1, 1, 0, 0, 0, 1], 3).tolist() == [True, True, False, False, False, True]
    for bad, match in (([1, 1, 1, 0, 0, 0], 'at most 2'), ([0] * 6, 'at least one'),
                       ([1, 0.5, 0, 0, 0, 0], '0/1'), ([1, 1], '0/1')):
        with pytest.raises(ValueError, match=match):
            task_mask(bad, 2)
    with pytest.raises(ValueError, match='1-joint'):
        task_mask(None, 1)


def test_joint_rates_modes_against_numpy():
    """(8.156) J⁻¹, J⁺ and (JᵀJ + λ²I) q' = Jᵀ x' (Wampler), checked with numpy's solvers."""
    rng = np.random.default_rng(3)
    J, x = rng.normal(size=(6, 6)), rng.normal(size=6)
    np.testing.assert_allclose(joint_rates(J, x, 'inverse'), np.linalg.solve(J, x), rtol=1e-10)
    wide = J[:4]
    np.testing.assert_allclose(joint_rates(wide, x[:4], 'pseudo_inverse'),
                               np.linalg.pinv(wide) @ x[:4], rtol=1e-10)
    for matrix, rate in ((J, x), (wide, x[:4])):
        lam = 0.3
        expected = np.linalg.solve(matrix.T @ matrix + lam ** 2 * np.eye(6), matrix.T @ rate)
        np.testing.assert_allclose(joint_rates(matrix, rate, 'damped_least_squares', lam),
                                   expected, rtol=1e-10)


def test_joint_rates_at_the_stretched_2r():
    """q2 = 0: J⁻¹ does not exist; J⁺ drops the lost direction; DLS obeys |q'| <= |x'|/(2λ)."""
    q = np.array([0.4, 0.0])
    J = jacobian_2r(q)
    radial = np.array([math.cos(0.4), math.sin(0.4)])
    with pytest.raises(ValueError, match='singular'):
        joint_rates(J, radial, 'inverse')
    np.testing.assert_allclose(joint_rates(J, radial, 'pseudo_inverse'), [0.0, 0.0], atol=1e-12)
    for lam in (0.01, 0.05, 0.2):
        for direction in (radial, np.array([-radial[1], radial[0]]), np.array([1.0, 0.0])):
            rate = joint_rates(J, direction, 'damped_least_squares', lam)
            assert np.linalg.norm(rate) <= 1.0 / (2.0 * lam) + 1e-12
    # Just off the singularity the inverse resolves a radial motion into a huge rate.
    near = jacobian_2r([0.4, 1e-4])
    assert np.abs(joint_rates(near, radial, 'inverse')).max() > 1e3
    assert np.abs(joint_rates(near, radial, 'damped_least_squares', 0.05)).max() < 10.0


def test_damping_factor_schedule():
    """λ² = λ_max² (1 − (σ/ε)²) inside σ < ε, 0 outside; constant without variable damping."""
    assert damping_factor(0.0, 0.05, 0.1) == 0.05
    assert damping_factor(0.1, 0.05, 0.1) == 0.0
    assert damping_factor(0.5, 0.05, 0.1) == 0.0
    assert math.isclose(damping_factor(0.08, 0.05, 0.1), 0.05 * 0.6)
    assert damping_factor(0.5, 0.05, 0.1, variable=False) == 0.05
    assert damping_factor(0.5, 0.05, 0.0) == 0.0


@pytest.mark.parametrize('call, match', [
    (lambda: joint_rates(np.eye(2), [1.0, 0.0], 'inverse_kinematics'), 'mode'),
    (lambda: joint_rates(np.ones((3, 2)), [1.0, 0.0, 0.0]), 'r <= n'),
    (lambda: joint_rates(np.eye(2), [1.0]), 'r <= n'),
    (lambda: joint_rates(np.ones((1, 2)), [1.0], 'inverse'), 'square'),
    (lambda: joint_rates(np.eye(2), [np.nan, 0.0]), 'finite'),
    (lambda: joint_rates(np.eye(2), [1.0, 0.0], damping=-0.1), 'damping'),
    (lambda: ResolvedRateParams(mode='transpose'), 'mode'),
    (lambda: ResolvedRateParams(damping=-1.0), 'damping'),
    (lambda: ResolvedRateParams(kx=-1.0), 'kx'),
    (lambda: ResolvedRateParams(variable_damping=1), 'variable_damping'),
    (lambda: CartesianGains(kp=np.nan), 'kp'),
    (lambda: ResolvedRate(ARM_2R, ResolvedRateParams(mode='inverse'), mask=[1, 0, 0, 0, 0, 0]),
     'square'),
    (lambda: ResolvedRate(planar_rr(3.0, 1.0)), 'dyn'),
    (lambda: ResolvedRate(ARM_2R, inner=object()), 'JointControlLaw'),
    (lambda: ResolvedRate(ARM_2R, ResolvedRateParams(kx=[1.0, 2.0, 3.0])), 'kx'),
    (lambda: OperationalSpace(PUMA, mask=[1, 1, 1, 0, 0, 0]), 'one task row per joint'),
    (lambda: OperationalSpace(planar_rr(3.0, 1.0)), 'dyn'),
    (lambda: OperationalSpace(ARM_2R, gains=(25.0, 10.0)), 'CartesianGains'),
    (lambda: TransposeJacobian(planar_rr(3.0, 1.0)), 'dyn'),
    (lambda: TransposeJacobian(ARM_2R, CartesianGains(kp=[1.0, 2.0, 3.0])), 'kp'),
    (lambda: TransposeJacobian(ARM_2R, grav=[0.0, 9.81]), 'grav'),
    (lambda: TransposeJacobian(ARM_2R, singular_threshold=-0.1), 'singular_threshold'),
])
def test_bad_construction_raises(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize('law', [
    lambda: ResolvedRate(ARM_2R, grav=GRAV), lambda: TransposeJacobian(ARM_2R, grav=GRAV),
    lambda: OperationalSpace(ARM_2R, grav=GRAV)])
def test_bad_update_inputs_raise(law):
    controller = law()
    ref, state = CartesianReference(transl(2.5, 1.5, 0.0)), JointState([0.2, 1.1], [0.0, 0.0])
    for args, match in (((ref, state, 0.0), 'dt'), ((ref, state, np.nan), 'dt'),
                        ((ref, JointState([0.0] * 3, [0.0] * 3), DT), '2 joints'),
                        ((transl(2.5, 1.5, 0.0), state, DT), 'CartesianReference'),
                        ((ref, ([0.2, 1.1], [0.0, 0.0]), DT), 'JointState')):
        with pytest.raises(ValueError, match=match):
            controller.update(*args)
    assert controller.telemetry is None


def test_telemetry_reports_the_singularity_of_the_2r():
    """Yoshikawa's w = l1 l2 |sin q2| (Ej. 4.5); σ_min and the flag at ε; λ from the schedule."""
    law = ResolvedRate(ARM_2R, grav=GRAV, singular_threshold=0.05)
    for q2 in (1.2, 0.3, 0.02, 0.0):
        law.reset()
        q = np.array([0.4, q2])
        law.update(CartesianReference(transl(*tip(q), 0.0)), JointState(q, [0.0, 0.0]), DT)
        sigma = np.linalg.svd(jacobian_2r(q), compute_uv=False)
        tel = law.telemetry
        assert math.isclose(tel.manipulability, L1 * L2 * abs(math.sin(q2)), abs_tol=1e-12)
        assert math.isclose(tel.manipulability, manipulability(ARM_2R, q, [1, 1, 0, 0, 0, 0]),
                            rel_tol=1e-9, abs_tol=1e-12)
        assert math.isclose(tel.min_singular_value, sigma[-1], abs_tol=1e-12)
        assert tel.near_singularity == (sigma[-1] < 0.05)
        expected = 0.05 * math.sqrt(max(0.0, 1.0 - (sigma[-1] / 0.05) ** 2))
        assert math.isclose(tel.damping, expected, abs_tol=1e-12)
    assert tel.near_singularity and tel.damping == 0.05   # stretched


# --- operational space (8.163) ----------------------------------------------------------------

def test_operational_space_force_is_8_163_with_the_closed_form_model():
    """ψ = J⁻ᵀ M J⁻¹ (x'' − J'q') + J⁻ᵀ (V + G) from (5.77) and (4.73); J'q' written out."""
    gains = CartesianGains(kp=[25.0, 36.0], kv=[10.0, 12.0])
    law = OperationalSpace(ARM_2R, gains, GRAV)
    q, qd = np.array([0.3, 1.4]), np.array([0.7, -1.1])
    ref = CartesianReference(transl(2.1, 2.0, 0.0), [0.2, -0.1, 0, 0, 0, 0.3],
                             [0.5, 0.4, 0, 0, 0, 0])
    tau = law.update(ref, JointState(q, qd), DT)
    c1, s1 = math.cos(q[0]), math.sin(q[0])
    c12, s12 = math.cos(q[0] + q[1]), math.sin(q[0] + q[1])
    jdot_qd = -np.array([L1 * c1 * qd[0] ** 2 + L2 * c12 * qd.sum() ** 2,
                         L1 * s1 * qd[0] ** 2 + L2 * s12 * qd.sum() ** 2])
    np.testing.assert_allclose(law.bias_acceleration(q, qd)[:2], jdot_qd, rtol=1e-12)
    J = jacobian_2r(q)
    error, rate_error = np.array([2.1, 2.0]) - tip(q), np.array([0.2, -0.1]) - J @ qd
    command = np.array([0.5, 0.4]) + [10.0, 12.0] * rate_error + [25.0, 36.0] * error
    M, V, G, _ = closed_form_2r(M1, M2, L1, L2, q, qd, [0.0, 0.0])
    Jinv = np.linalg.inv(J)
    force = Jinv.T @ M @ Jinv @ (command - jdot_qd) + Jinv.T @ (V + G)
    np.testing.assert_allclose(law.telemetry.cartesian_force, force, rtol=1e-10)
    np.testing.assert_allclose(tau, J.T @ force, rtol=1e-10)
    np.testing.assert_allclose(law.telemetry.pose_error, error, rtol=1e-12)
    np.testing.assert_allclose(law.telemetry.twist_error, rate_error, rtol=1e-12)


def test_operational_space_2r_line_has_decoupled_error_dynamics():
    """Exact model: x̃'' + K_v x̃' + K_p x̃ = 0 per row, ω_n = 5 on x and 10 on y (analytic)."""
    law = OperationalSpace(ARM_2R, CartesianGains(kp=[25.0, 100.0], kv=[10.0, 20.0]), GRAV)
    q0 = np.array([0.2, 1.1])
    start = tip(q0)
    T0 = transl(start[0] + 0.05, start[1] - 0.03, 0.0)   # 5.8 cm from the arm at t = 0
    T1 = transl(start[0] - 0.8, start[1] + 0.6, 0.0)

    def reference(t):
        return line_references(T0, T1, *np.array([quintic_profile(t, 2.0)]).T)[0]
    times = [0.1, 0.3, 0.5, 1.0, 2.0, 3.0]
    run = continuous_run(law, plant_2r, reference, np.concatenate([q0, [0.0, 0.0]]), times)
    e0, ed0 = reference(0.0).T_d[:2, 3] - start, reference(0.0).xd_d[:2]
    for k, t in enumerate(run.t):
        error = reference(t).T_d[:2, 3] - tip(run.y[:2, k])
        np.testing.assert_allclose(error, critically_damped(e0, ed0, np.array([5.0, 10.0]), t),
                                   atol=1e-9)


def test_operational_space_puma_set_point_position_and_rotation():
    """PUMA 560, exact model: position critically damped; rotation ε'' + 8ε' + 16 sin ε = 0."""
    law = OperationalSpace(PUMA, CartesianGains(kp=[25.0] * 3 + [16.0] * 3,
                                                kv=[10.0] * 3 + [8.0] * 3))
    start = fk_by_link_product(PUMA, Q_PUMA)
    axis = np.array([1.0, 2.0, -1.0]) / math.sqrt(6.0)
    e0, eps0 = np.array([0.02, -0.01, 0.015]), 0.3            # 2.7 cm and 17°
    T_d = pose(start[:3, 3] + e0, eps0 * axis, start[:3, :3])
    times = [0.2, 0.5, 1.0, 2.0]
    run = continuous_run(law, puma_plant(), lambda t: CartesianReference(T_d),
                         np.concatenate([Q_PUMA, np.zeros(6)]), times)
    pendulum = solve_ivp(lambda t, y: [y[1], -8.0 * y[1] - 16.0 * math.sin(y[0])], (0.0, 2.0),
                         [eps0, 0.0], rtol=1e-12, atol=1e-14, t_eval=times)
    for k, t in enumerate(run.t):
        T = fk_by_link_product(PUMA, run.y[:6, k])
        np.testing.assert_allclose(T_d[:3, 3] - T[:3, 3], critically_damped(e0, 0.0, 5.0, t),
                                   atol=1e-9)
        rotation = Rotation.from_matrix(T_d[:3, :3] @ T[:3, :3].T).as_rotvec()   # ε k̂
        np.testing.assert_allclose(rotation, pendulum.y[0, k] * axis, atol=1e-9)


def test_operational_space_refuses_a_singular_jacobian():
    law = OperationalSpace(ARM_2R, grav=GRAV)
    q = np.array([0.4, 0.0])
    with pytest.raises(ValueError, match='singular at q = \\[0.4, 0.0\\]'):
        law.update(CartesianReference(transl(*tip(q), 0.0)), JointState(q, [0.0, 0.0]), DT)


# --- transpose Jacobian (8.158)-(8.162) -------------------------------------------------------

def balance_2r(q, p_d, kp):
    """Return Jᵀ(q) K_p (p_d − tip(q)) − G(q): zero where the spring holds the 2R's weight."""
    return jacobian_2r(q).T @ (kp * (p_d - tip(q))) - closed_form_2r(
        M1, M2, L1, L2, q, [0.0, 0.0], [0.0, 0.0])[2]


@pytest.mark.parametrize('compensate', [True, False])
def test_transpose_jacobian_2r_set_point(compensate):
    """With Ĝ the tip reaches p_d; without, it rests where Jᵀ ψ = G (8.167), solved by fsolve."""
    p_d, kp, q0 = np.array([2.0, 2.5]), 400.0, np.array([0.3, 1.2])
    law = TransposeJacobian(ARM_2R, CartesianGains(kp=kp, kv=80.0), GRAV,
                            gravity_compensation=compensate)
    run = continuous_run(law, plant_2r, lambda t: CartesianReference(transl(*p_d, 0.0)),
                         np.concatenate([q0, [0.0, 0.0]]), [10.0])
    q, qd = run.y[:2, -1], run.y[2:, -1]
    np.testing.assert_allclose(qd, [0.0, 0.0], atol=1e-9)
    if compensate:
        np.testing.assert_allclose(tip(q), p_d, atol=1e-9)
    else:
        q_eq = fsolve(balance_2r, q0, args=(p_d, kp), xtol=1e-13)
        np.testing.assert_allclose(balance_2r(q_eq, p_d, kp), [0.0, 0.0], atol=1e-9)
        np.testing.assert_allclose(q, q_eq, atol=1e-9)
        assert np.linalg.norm(p_d - tip(q)) > 0.05            # the weight costs 6.4 cm
        np.testing.assert_allclose(law.telemetry.cartesian_force, kp * (p_d - tip(q)),
                                   rtol=1e-6)


def test_transpose_jacobian_puma_reaches_a_set_point_with_gravity_compensation():
    """The tool settles on T_d (Ĝ exact): the pose of q_target, 0.14 rad of joints away."""
    law = TransposeJacobian(PUMA, CartesianGains(kp=[2000.0] * 3 + [50.0] * 3,
                                                 kv=[400.0] * 3 + [10.0] * 3))
    q_target = Q_PUMA + [0.05, 0.04, -0.05, 0.1, 0.1, -0.1]
    T_d = fk_by_link_product(PUMA, q_target)
    run = continuous_run(law, puma_plant(), lambda t: CartesianReference(T_d),
                         np.concatenate([Q_PUMA, np.zeros(6)]), [6.0])
    np.testing.assert_allclose(fk_by_link_product(PUMA, run.y[:6, -1]), T_d, atol=1e-9)
    np.testing.assert_allclose(run.y[:6, -1], q_target, atol=1e-8)
    np.testing.assert_allclose(run.y[6:, -1], np.zeros(6), atol=1e-8)


def test_cartesian_robot_transpose_is_inverse_8_162():
    """A PPP robot along z, y, x of {0}: J orthonormal, so Jᵀ ψ = J⁻¹ ψ (8.162)."""
    ppp = dh_model([[0, 0, 0, 0, 1], [-math.pi / 2, 0, math.pi / 2, 0, 1],
                    [math.pi / 2, 0, 0, 0, 1]], qlim=[[-1.0, 1.0]] * 3)
    law = TransposeJacobian(ppp, CartesianGains(kp=[10.0, 20.0, 30.0], kv=2.0),
                            gravity_compensation=False)
    q, qd = np.array([0.1, -0.2, 0.3]), np.array([0.5, 0.0, -0.4])
    p, v = q[::-1], qd[::-1]                 # d3 along x, d2 along y, d1 along z
    p_d = np.array([0.4, 0.1, -0.3])
    tau = law.update(CartesianReference(transl(*p_d)), JointState(q, qd), DT)
    force = np.array([10.0, 20.0, 30.0]) * (p_d - p) - 2.0 * v
    J = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    np.testing.assert_allclose(tau, np.linalg.solve(J, force), atol=1e-12)
    np.testing.assert_allclose(joint_rates(J, force, 'inverse'), J.T @ force, atol=1e-12)
    np.testing.assert_allclose(law.telemetry.cartesian_force, force, atol=1e-12)
    assert law.telemetry.manipulability == pytest.approx(1.0)


# --- resolved rate (fig. 8.39) ----------------------------------------------------------------

def sampled_run(law, references, x0, plant):
    """Run ``law`` at 1 kHz on ``plant`` (RK4, torque held); return states and telemetries."""
    n, x = len(x0) // 2, np.asarray(x0, dtype=float)
    states, telemetry = [], []
    for k, reference in enumerate(references):
        tau = law.update(reference, JointState(x[:n], x[n:]), DT)
        telemetry.append(law.telemetry)
        x = rk4_step(plant, k * DT, x, DT, tau)
        states.append(x)
    return np.array(states), telemetry


def kinematic_run(law, references, q0):
    """
    Run the resolved rate's kinematic loop alone: the arm is taken to follow q_d exactly.

    Return the joint-reference rates (steps, n), the telemetries, and the ValueError that
    stopped the run, if any.
    """
    state, rates, telemetry = JointState(q0, np.zeros(len(q0))), [], []
    for reference in references:
        try:
            law.update(reference, state, DT)
        except ValueError as err:
            return np.array(rates), telemetry, err
        joint_reference = law.telemetry.joint_reference
        state = JointState(joint_reference.q_d, joint_reference.qd_d)
        rates.append(joint_reference.qd_d)
        telemetry.append(law.telemetry)
    return np.array(rates), telemetry, None


def assert_dls_bound(references, telemetry, mask, kx=20.0, threshold=0.05):
    """
    Check |q_d'| <= |x_d' + K_x x̃| / ε at every step (λ_max = ε, module resolved_rate).

    With λ² = ε² − σ_min² inside σ_min < ε (and J⁻¹ outside), every singular value σ of J is
    resolved with a gain σ / (σ² + λ²) <= 1 / ε.
    """
    for ref, tel in zip(references, telemetry):
        command = ref.xd_d[mask] + kx * tel.pose_error
        bound = np.linalg.norm(command) / threshold
        assert np.linalg.norm(tel.joint_reference.qd_d) <= bound * (1 + 1e-9) + 1e-12


def test_resolved_rate_2r_follows_a_cartesian_line():
    """DLS away from singularities = J⁻¹: q_d is the line's closed-form IK; the tip follows it."""
    p_a, p_b = np.array([2.5, 1.5]), np.array([1.5, 2.8])
    references = timed_line(transl(*p_a, 0.0), transl(*p_b, 0.0), 2.0, 3.0)   # 1.64 m in 2 s
    law = ResolvedRate(ARM_2R, grav=GRAV)
    states, telemetry = sampled_run(law, references, np.concatenate([ik_2r(p_a), [0, 0]]),
                                    plant_2r)
    assert all(tel.damping == 0.0 and not tel.near_singularity for tel in telemetry)
    q_line = np.array([ik_2r(ref.T_d[:2, 3]) for ref in references])
    q_d = np.array([tel.joint_reference.q_d for tel in telemetry])
    assert np.abs(q_d - q_line).max() < 2e-4                  # rad; the line at 1.2 m/s
    tracking = [np.linalg.norm(ref.T_d[:2, 3] - tip(x[:2]))
                for ref, x in zip(references[1:], states)]
    assert max(tracking) < 1e-3                                # m (measured 0.38 mm)
    assert tracking[-1] < 5e-5                                 # 1 s after the end
    np.testing.assert_allclose(states[-1, 2:], [0.0, 0.0], atol=1e-3)


def test_resolved_rate_puma_wrist_singularity_dls_bounded_inverse_blows_up():
    """The wrist crosses q5 = 0 (σ_min 6e-4): J⁻¹ asks 224 rad/s; DLS stays below |x'|/ε."""
    q_a = np.array([0.0, -0.5, 0.6, 0.0, 0.3, 0.0])
    q_b = np.array([0.0, -0.5, 0.6, 0.02, -0.3, -0.02])
    references = timed_line(fk_by_link_product(PUMA, q_a), fk_by_link_product(PUMA, q_b),
                            2.0, 2.2)
    inverse = ResolvedRate(PUMA, ResolvedRateParams(mode='inverse'), inner=DecoupledPID())
    rates, _, error = kinematic_run(inverse, references, q_a)
    assert error is not None or np.abs(rates).max() > 100.0
    law = ResolvedRate(PUMA, ResolvedRateParams(kx=20.0, damping=0.05), inner=DecoupledPID(),
                       singular_threshold=0.05)
    rates, telemetry, error = kinematic_run(law, references, q_a)
    assert error is None and np.abs(rates).max() < 2.0
    assert_dls_bound(references, telemetry, np.ones(6, dtype=bool))
    flagged = [tel.near_singularity for tel in telemetry]
    assert not flagged[0] and any(flagged) and not flagged[-1]
    assert max(tel.damping for tel in telemetry) > 0.049
    assert min(tel.min_singular_value for tel in telemetry) < 1e-3
    assert np.linalg.norm(telemetry[-1].pose_error) < 1e-6     # tracking again (8e-8)
    np.testing.assert_allclose(fk_by_link_product(PUMA, telemetry[-1].joint_reference.q_d),
                               references[-1].T_d, atol=1e-4)


def test_resolved_rate_2r_stretched_out_and_back():
    """A line to 5 cm beyond reach and back: the arm stretches (q2 → 0) and returns with DLS."""
    def radial(r):
        return transl(r * math.cos(0.4), r * math.sin(0.4), 0.0)
    references = (timed_line(radial(3.0), radial(4.05), 1.5, 1.5)
                  + timed_line(radial(4.05), radial(3.0), 1.5, 2.5))
    q0 = ik_2r(radial(3.0)[:2, 3])
    inverse = ResolvedRate(planar_rr(L1, L2), ResolvedRateParams(mode='inverse'),
                           inner=DecoupledPID())
    rates, _, error = kinematic_run(inverse, references, q0)
    assert error is not None or np.abs(rates).max() > 1000.0
    law = ResolvedRate(ARM_2R, grav=GRAV)                        # λ_max = ε = 0.05
    states, telemetry = sampled_run(law, references, np.concatenate([q0, [0, 0]]), plant_2r)
    assert_dls_bound(references, telemetry, task_mask(None, 2))
    rates = np.array([tel.joint_reference.qd_d for tel in telemetry])
    assert np.abs(rates).max() < 30.0 and np.abs(states[:, 2:]).max() < 30.0   # measured 25
    stretched = [tel.near_singularity for tel in telemetry]
    assert not stretched[0] and any(stretched) and not stretched[-1]
    assert min(tel.min_singular_value for tel in telemetry) < 1e-6
    assert np.linalg.norm(references[-1].T_d[:2, 3] - tip(states[-1, :2])) < 1e-4


def test_resolved_rate_reset_restarts_from_the_measured_q():
    pid = DecoupledPID()
    law = ResolvedRate(ARM_2R, inner=pid)
    reference = CartesianReference(transl(2.5, 1.5, 0.0))
    for _ in range(3):
        law.update(reference, JointState([0.2, 1.1], [0.0, 0.0]), DT)
    assert not np.allclose(law.telemetry.joint_reference.q_d, [0.2, 1.1])
    law.reset()
    assert law.telemetry is None and pid.integral is None
    law.update(reference, JointState([0.3, 1.0], [0.0, 0.0]), DT)
    np.testing.assert_array_equal(law.telemetry.joint_reference.q_d, [0.3, 1.0])
    np.testing.assert_array_equal(law.telemetry.joint_reference.qdd_d, [0.0, 0.0])
