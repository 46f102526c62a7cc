"""
Tests of robotica_sim.simulation.arm: fixed-step RK4 on Pinocchio's ABA (catalog §3.6, §3.8).

References: the catalog's values of Ej. 5.2 computed from the closed form (5.76), and the
energy balance of the free Ej. 5.3 arm.
"""
import math

import numpy as np
import pinocchio as pin
import pytest
from robotica_ctrl.joint_control import (ComputedTorque, ComputedTorqueGains, JointReference,
                                         JointState)
from robotica_kin.dh import dh_model
from robotica_kin.dynamics import inertia
from robotica_kin.robots import puma560, two_link_arm
from robotica_sim.simulation.arm import ArmSimulation, ArmSimulationParams

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
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
