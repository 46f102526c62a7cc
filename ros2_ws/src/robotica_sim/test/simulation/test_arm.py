"""
Tests of robotica_sim.simulation.arm: fixed-step RK4 on Pinocchio's ABA (catalog §3.6, §3.8).

References: the catalog's values of Ej. 5.2 computed from the closed form (5.76), the
energy balance of the free Ej. 5.3 arm, and, for the compliant environment (8.164)-(8.166), a
mass on a spring in closed form.
"""
import math

import numpy as np
import pinocchio as pin
import pytest
from robotica_ctrl.joint_control import (ComputedTorque, ComputedTorqueGains, JointReference,
                                         JointState)
from robotica_kin.dh import dh_model
from robotica_kin.dynamics import inertia
from robotica_kin.robots import pp_robot, puma560, two_link_arm
from robotica_kin.transforms import transl
from robotica_sim.simulation.arm import ArmSimulation, ArmSimulationParams
from robotica_sim.simulation.compliant_environment import CompliantPlane

PLANAR = (0.0, -9.81, 0.0)


def _two_link(**kwargs):
    dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    params = ArmSimulationParams(gravity=PLANAR, respect_limits=False, **kwargs)
    return ArmSimulation(dh_model(dh, dyn=dyn), params, [0.0, 0.0], [0.0, 0.0])


def test_ejemplo_5_2_at_1_khz():
    # Catalog §3.8: t = 0.5 s: theta = [-0.3664, 3.1030], theta' = [-0.2057, 11.8385];
    # t = 1 s: theta = [-1.2169, 12.2009], theta' = [-4.4194, 29.0133].
    sim = _two_link()
    expected = {500: ([-0.3664, 3.1030], [-0.2057, 11.8385]),
                1000: ([-1.2169, 12.2009], [-4.4194, 29.0133])}
    for k in range(1000):
        t = sim.time
        sim.step([30.0 + (1.0 + math.exp(-t)) * 10.0 * math.sin(t), 10.0 + 10.0 * math.cos(t)])
        if k + 1 in expected:
            q, qd = expected[k + 1]
            # Zero-order hold over 1 ms steps: within the printed precision.
            np.testing.assert_allclose(sim.q, q, atol=2e-3)
            np.testing.assert_allclose(sim.qd, qd, atol=2e-2)
    assert sim.time == 1.0


def test_free_motion_conserves_energy_and_unmodelled_friction_dissipates():
    dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    robot = dh_model(dh, dyn=dyn)

    def energy(sim):
        q, qd = sim.q, sim.qd
        heights = [3.0 * math.sin(q[0]), 3.0 * math.sin(q[0]) + math.sin(q[0] + q[1])]
        return 0.5 * qd @ inertia(robot, q) @ qd + 9.81 * (2.0 * heights[0] + heights[1])

    free = ArmSimulation(robot, ArmSimulationParams(gravity=PLANAR, respect_limits=False),
                         [0.3, 0.2], [0.0, 0.0])
    damped = ArmSimulation(robot, ArmSimulationParams(gravity=PLANAR, respect_limits=False,
                                                      unmodelled_viscous=(0.5, 0.5)),
                           [0.3, 0.2], [0.0, 0.0])
    e0 = energy(free)
    for _ in range(2000):
        free.step([0.0, 0.0])
        damped.step([0.0, 0.0])
    assert abs(energy(free) - e0) < 1e-6 * abs(e0)
    assert energy(damped) < e0 - 1.0


def test_saturation_and_joint_limits():
    robot = puma560()
    params = ArmSimulationParams(tau_max=(1.0,) * 6)
    sim = ArmSimulation(robot, params, np.zeros(6), np.zeros(6))
    sim.step(np.full(6, 100.0))
    np.testing.assert_array_equal(sim.applied_torque, np.ones(6))
    # Joint 5 pushed hard towards its +100° limit stops there.
    sim = ArmSimulation(robot, ArmSimulationParams(), np.zeros(6), np.zeros(6))
    for _ in range(2000):
        sim.step([0, 0, 0, 0, 5.0, 0])
    assert sim.q[4] == pytest.approx(robot.qlim[4, 1])
    assert sim.qd[4] == 0.0


def test_joint_stop_holds_outward_and_releases_inward():
    # The lower stop of joint 5 (-100°): held while pushed outwards, left when pushed back.
    robot = puma560()
    push = np.array([0, 0, 0, 0, -5.0, 0])
    sim = ArmSimulation(robot, ArmSimulationParams(), np.zeros(6), np.zeros(6))
    for _ in range(2000):
        sim.step(push)
    assert sim.q[4] == robot.qlim[4, 0]
    assert sim.qd[4] == 0.0
    for _ in range(20):
        sim.step(-push)
    assert sim.q[4] > robot.qlim[4, 0] and sim.qd[4] > 0.0
    # Without the stops the same push carries the joint past its limit.
    free = ArmSimulation(robot, ArmSimulationParams(respect_limits=False), np.zeros(6),
                         np.zeros(6))
    for _ in range(2000):
        free.step(push)
    assert free.q[4] < robot.qlim[4, 0] - 0.1


def _mass_matrix_2r(q2, m1, m2, l1=3.0, l2=1.0):
    """Return M(q) of the Ej. 5.1 arm by its closed form (5.76)."""
    c2 = math.cos(q2)
    m12 = l2 ** 2 * m2 + l1 * l2 * m2 * c2
    return np.array([[l2 ** 2 * m2 + 2 * l1 * l2 * m2 * c2 + l1 ** 2 * (m1 + m2), m12],
                     [m12, l2 ** 2 * m2]])


def test_payload_at_the_link_mass_point_is_a_heavier_link():
    # Ej. 8.4: 2 kg grasped at the link-2 mass point make m2 = 3 kg (CoM of link 2 unchanged).
    sim = _two_link()
    sim.add_payload(2.0, [1.0, 0.0, 0.0])
    q = np.array([0.3, 0.7])
    M = pin.crba(sim._model, sim._model.createData(), q)
    np.testing.assert_allclose(np.triu(M), np.triu(_mass_matrix_2r(0.7, 2.0, 3.0)), atol=1e-12)


def test_ejemplo_8_4_payload_spoils_tracking():
    # Catalog §6.8, Ej. 8.4: PD computed torque with m̂ = (2.1, 0.9) kg; a 2 kg object grasped at
    # t = 10 s; the catalog's independent run gives max |e| over 15-20 s ≈ [0.047; 0.66] rad.
    dh, dyn_true = two_link_arm(2.0, 1.0, 3.0, 1.0)
    model = dh_model(dh, dyn=two_link_arm(2.1, 0.9, 3.0, 1.0)[1])
    law = ComputedTorque(model, ComputedTorqueGains(kp=25.0, kv=10.0), grav=PLANAR)
    sim = _two_link()
    errors = []
    for k in range(20000):
        t = k * 1e-3
        w = 2 * math.pi / 4.0
        reference = JointReference(
            0.15 * np.array([math.sin(w * t), math.cos(w * t)]),
            0.15 * w * np.array([math.cos(w * t), -math.sin(w * t)]),
            -0.15 * w * w * np.array([math.sin(w * t), math.cos(w * t)]))
        if k == 10000:
            sim.add_payload(2.0, [1.0, 0.0, 0.0])
        if t >= 15.0:
            errors.append(np.abs(reference.q_d - sim.q))
        sim.step(law.update(reference, JointState(sim.q, sim.qd), 1e-3))
    np.testing.assert_allclose(np.max(errors, axis=0), [0.047, 0.66], rtol=0.05)


def test_brakes_hold_the_joints():
    sim = _two_link()
    sim.step([50.0, 0.0])
    q = sim.q.copy()
    sim.step_braked()
    assert sim.time == pytest.approx(2e-3)
    np.testing.assert_array_equal(sim.q, q)
    np.testing.assert_array_equal(sim.qd, [0.0, 0.0])


def _pp_on_floor(step_period=1e-3, **kwargs):
    """Return the PP robot (d2 vertical, 2.35 kg on it) over a floor y = 0, K_e = 1200."""
    floor = CompliantPlane([0.0, 0.0, 0.0], [0.0, -1.0, 0.0], 1200.0)
    params = ArmSimulationParams(step_period=step_period, gravity=PLANAR, **kwargs)
    return ArmSimulation(pp_robot(), params, [0.0, 0.0], [0.0, 0.0], environment=floor)


def test_contact_load_is_j_transpose_psi_held_over_the_step():
    # Ej. 8.10's surface pressed 2.5 mm: psi = 3 N along n = (1, -1, 0)/√2; the chain's joints
    # are [d2 (along y), d1 (along x)], so tau_e = J^T psi = (psi_y, psi_x) (8.165)-(8.166).
    s = 1.0 / math.sqrt(2.0)
    surface = CompliantPlane([2 * s, -2 * s, 0.0], [1.0, -1.0, 0.0], 1200.0)
    x = np.array([2.0025, 4.0])                      # task coordinates (8.185)
    d1, d2 = s * (x[0] + x[1]), s * (x[1] - x[0])
    q0, qd0 = [d2, d1], [0.3, -0.2]
    params = ArmSimulationParams(gravity=PLANAR)
    sim = ArmSimulation(pp_robot(), params, q0, qd0, environment=surface)
    wrench = sim.contact_wrench()
    np.testing.assert_allclose(wrench.force, [3.0 * s, -3.0 * s, 0.0], rtol=1e-9)
    np.testing.assert_allclose(wrench.force_tool, wrench.force, atol=1e-12)   # tool ∥ {0}
    np.testing.assert_array_equal(wrench.torque, 0.0)
    assert wrench.penetration == pytest.approx(0.0025, rel=1e-9)
    np.testing.assert_allclose(sim.contact_joint_torque, [-3.0 * s, 3.0 * s], rtol=1e-9)
    # One step with tau equals a step without environment with tau - tau_e (zero-order hold).
    free = ArmSimulation(pp_robot(), params, q0, qd0)
    tau = np.array([25.0, -1.0])
    sim.step(tau)
    free.step(tau - np.array([-3.0 * s, 3.0 * s]))
    np.testing.assert_allclose(sim.q, free.q, rtol=0.0, atol=1e-15)
    np.testing.assert_allclose(sim.qd, free.qd, rtol=0.0, atol=1e-15)
    np.testing.assert_array_equal(sim.applied_torque, tau)


def test_contact_wrench_in_the_tool_frame():
    # Ej. 5.1 arm with its tip as tool, at q = (π/2, 0): the tip (0, 4) is pressed 0.1 m into
    # the plane y = 3.9; X_tool points along y of {0}, so psi = (0, 120, 0) is (120, 0, 0).
    dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    robot = dh_model(dh, dyn=dyn, tool=transl(1.0, 0.0, 0.0))
    plane = CompliantPlane([0.0, 3.9, 0.0], [0.0, 1.0, 0.0], 1200.0)
    sim = ArmSimulation(robot, ArmSimulationParams(gravity=PLANAR, respect_limits=False),
                        [math.pi / 2, 0.0], [0.0, 0.0], environment=plane)
    wrench = sim.contact_wrench()
    np.testing.assert_allclose(wrench.force, [0.0, 120.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(wrench.force_tool, [120.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(wrench.on_tool(), [-120.0, 0, 0, 0, 0, 0], atol=1e-9)
    # tau_e = J^T psi: the tip's Jacobian at q = (π/2, 0) has y-row (0, 0): no joint load.
    np.testing.assert_allclose(sim.contact_joint_torque, [0.0, 0.0], atol=1e-9)


def test_no_environment_no_wrench():
    sim = _two_link()
    sim.step([1.0, 0.0])
    wrench = sim.contact_wrench()
    np.testing.assert_array_equal(wrench.force, 0.0)
    assert math.isnan(wrench.penetration)
    np.testing.assert_array_equal(sim.contact_joint_torque, 0.0)


def test_resting_on_the_floor_sinks_by_weight_over_stiffness():
    # Equilibrium of (8.165) at rest with tau = 0: K_e δ = (m1 + m2) g.
    sim = _pp_on_floor(unmodelled_viscous=(20.0, 20.0))
    for _ in range(3000):
        sim.step([0.0, 0.0])
    assert sim.q[0] == pytest.approx(-2.35 * 9.81 / 1200.0, rel=1e-4)   # e^(-ζωt) ≈ 4e-6 left
    assert sim.contact_wrench().force[1] == pytest.approx(-2.35 * 9.81, rel=1e-4)


def test_contact_oscillates_at_sqrt_ke_over_m_and_the_hold_adds_omega_h_over_4():
    # Around the equilibrium, d2 = -δ - A sin(ωt), ω = sqrt(K_e / (m1 + m2)) (mass on a
    # spring). The force held over each step h acts as a negative damping ratio ω h / 4
    # (compliant_environment's justification of the step): the amplitude grows as
    # exp(ω² h t / 4), 29 % in 2 s at h = 1 ms.
    h, m = 1e-3, 2.35
    omega, delta = math.sqrt(1200.0 / m), m * 9.81 / 1200.0
    amplitude = 0.5 * delta                       # stays in contact
    sim = _pp_on_floor(h)
    sim.reset([-delta, 0.0], [-amplitude * omega, 0.0])
    t = h * np.arange(1, 2001)
    d2 = np.array([sim.step([0.0, 0.0])[0] for _ in t])
    offset = d2 + delta
    crossings = t[1:][np.diff(np.sign(offset)) != 0]
    period = 2.0 * np.mean(np.diff(crossings))
    assert period == pytest.approx(2.0 * math.pi / omega, rel=2e-3)
    first, last = np.abs(offset[t < 0.3]).max(), np.abs(offset[t > 1.7]).max()
    assert last / first == pytest.approx(math.exp(omega ** 2 * h * 1.7 / 4.0), rel=0.02)


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: ArmSimulationParams(step_period=0.0), 'step_period'),
    (lambda: ArmSimulationParams(tau_max=(0.0,)), 'tau_max'),
    (lambda: ArmSimulationParams(unmodelled_viscous=(-1.0,)), 'unmodelled'),
    (lambda: ArmSimulation(puma560(), ArmSimulationParams(tau_max=(1.0,)), np.zeros(6),
                           np.zeros(6)), '6 values'),
    (lambda: ArmSimulation(puma560(), ArmSimulationParams(), np.zeros(5), np.zeros(6)), 'q0'),
    (lambda: _two_link().step([0.0, math.nan]), 'finite'),
    (lambda: _two_link().step([0.0]), 'finite'),
    (lambda: _two_link().add_payload(math.nan, [1.0, 0.0, 0.0]), 'mass'),
    (lambda: _two_link().add_payload(1.0, [1.0, 0.0]), 'com'),
    (lambda: ArmSimulation(pp_robot(), ArmSimulationParams(), [0.0, 0.0], [0.0, 0.0],
                           environment='floor'), 'environment'),
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
