"""
Tests of robotica_sim.arm_simulation: fixed-step RK4 on Pinocchio's ABA (catalog §3.6, §3.8).

References: the catalog's values of Ej. 5.2 computed from the closed form (5.76), and the
energy balance of the free Ej. 5.3 arm.
"""
import math

import numpy as np
import pytest

from robotica_kin.dh import dh_model
from robotica_kin.dynamics import inertia
from robotica_kin.robots import puma560, two_link_arm
from robotica_sim.arm_simulation import ArmSimulation, ArmSimulationParams

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


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: ArmSimulationParams(step_period=0.0), 'step_period'),
    (lambda: ArmSimulationParams(tau_max=(0.0,)), 'tau_max'),
    (lambda: ArmSimulationParams(unmodelled_viscous=(-1.0,)), 'unmodelled'),
    (lambda: ArmSimulation(puma560(), ArmSimulationParams(tau_max=(1.0,)), np.zeros(6),
                           np.zeros(6)), '6 values'),
    (lambda: ArmSimulation(puma560(), ArmSimulationParams(), np.zeros(5), np.zeros(6)), 'q0'),
    (lambda: _two_link().step([0.0, math.nan]), 'finite'),
    (lambda: _two_link().step([0.0]), 'finite'),
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
