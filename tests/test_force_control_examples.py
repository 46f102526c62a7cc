"""
Ej. 8.10 and 8.11 (catalog §6.8): the force laws on the PP robot in the arm simulation.

The plant is ``robotica_sim``'s ArmSimulation of ``pp_robot(2, 0.35)`` at 1 ms with the
compliant plane of (8.164), x_e1 = 2 m, K_e1 = 1200 N/m, frictionless, from x(0) = (2, 4) m at
rest; the law is fed the simulated contact force in task coordinates at every step. References:
the catalog's computed values of Ej. 8.10 (t = 4 s: ψ1 = 2.979 N, x2 = 2.0105 m; steady state
x1 = 2.00248 m, ψ1 = 2.975 N) and Ej. 8.11 (t = 5 s: position error -0.0050 m, ψ = 0.99924 N),
at their printed precision; the closed loop (8.214) and the Cartesian PD without contact
integrated here with SciPy; the steady state (8.176) written out. Against the continuous loops
the 1 ms zero-order hold of the torque lags by about h/2: |x'| h/2 <= 1e-3 m (N/1200) early
in the runs, hence that tolerance there.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.force_control import (HybridForcePosition, HybridGains, ImpedanceControl,
                                         ImpedanceGains, stiffness_set_point,
                                         stiffness_steady_state, StiffnessControl, StiffnessGains,
                                         TaskFrame, TaskReference)
from robotica_ctrl.joint_control import JointState
from robotica_kin.robots import pp_robot
from robotica_sim.simulation.arm import ArmSimulation, ArmSimulationParams
from robotica_sim.simulation.compliant_environment import CompliantPlane
from scipy.integrate import solve_ivp

S = 1.0 / math.sqrt(2.0)
FRAME = TaskFrame([[S, S], [-S, S], [0.0, 0.0]])    # x = (1/√2)[d1 - d2; d1 + d2] (8.185)
PLANAR = (0.0, -9.81, 0.0)
DT = 1e-3
M1, M2 = 2.0, 0.35


def _joints(x):
    """Return the chain's q = [d2, d1] of task coordinates x (8.185) inverted."""
    return [S * (x[1] - x[0]), S * (x[0] + x[1])]


def _simulation(surface=True, x0=(2.0, 4.0)):
    plane = CompliantPlane(2.0 * np.array([S, -S, 0.0]), [1.0, -1.0, 0.0], 1200.0)
    return ArmSimulation(pp_robot(M1, M2), ArmSimulationParams(gravity=PLANAR), _joints(x0),
                         [0.0, 0.0], environment=plane if surface else None)


def _run(sim, law, reference_at, until, record=()):
    """Step the loop until time ``until``; return {t: (x, ψ)} at the times in ``record``."""
    out = {}
    while sim.time < until - 1e-9:
        psi = FRAME.to_task(sim.contact_wrench().force)
        tau = law.update(reference_at(sim.time), JointState(sim.q, sim.qd), psi, DT)
        sim.step(tau)
        for t in record:
            if abs(sim.time - t) < 1e-9:
                out[t] = (FRAME.position([sim.q[1], sim.q[0], 0.0]),
                          FRAME.to_task(sim.contact_wrench().force))
    return out


def test_ejemplo_8_10_stiffness_control():
    # x_d1 = ψ_d1 / K_p1 + x_e1 = 2.3 m (8.179), x_d2 = 2 m; K_v = K_p = diag(10, 10).
    x_d = [float(stiffness_set_point(3.0, 10.0, 2.0)), 2.0]
    law = StiffnessControl(pp_robot(M1, M2), FRAME, StiffnessGains(kp=10.0, kv=10.0),
                           grav=PLANAR)
    reference = TaskReference(x_d)
    states = _run(_simulation(), law, lambda t: reference, 10.0, record=(4.0, 10.0))
    x, psi = states[4.0]
    assert psi[0] == pytest.approx(2.979, abs=5e-4)
    assert x[1] == pytest.approx(2.0105, abs=5e-5)
    # Steady state (8.176)-(8.178), reached to 2e-6 m by t = 10 s (slowest mode ~ e^(-1.5 t)):
    # the catalog's numbers and the predictor's.
    x, psi = states[10.0]
    x_inf, psi_inf = stiffness_steady_state(10.0, [1200.0, 0.0], x_d, [2.0, 0.0])
    assert psi[0] == pytest.approx(2.975, abs=5e-4)
    assert x[0] == pytest.approx(2.00248, abs=5e-6)
    np.testing.assert_allclose(x, x_inf, atol=1e-5)
    np.testing.assert_allclose(psi, psi_inf, atol=1e-5)
    assert x[1] == pytest.approx(2.0, abs=1e-5)          # along the surface x2 -> x_d2 (8.180)
    assert psi[1] == 0.0                                 # frictionless


def _ej_8_11_reference(t):
    e = math.exp(-2.0 * t)
    return TaskReference([0.0, 2.0 + math.cos(t)], [0.0, -math.sin(t)], [0.0, -math.cos(t)],
                         [1.0 - e, 0.0], [2.0 * e, 0.0], [-4.0 * e, 0.0])


def _ej_8_11_closed_loop(t, y):
    """(8.214): x_T1 and x_N1 (the printed ψ in the force line is x_N1)."""
    x_t, v_t, x_n, v_n = y
    e = math.exp(-2.0 * t)
    a_t = -math.cos(t) + 15 * (-math.sin(t) - v_t) + 15 * (2 + math.cos(t) - x_t)
    a_n = (-4 * e + 15 * (2 * e - 1200 * v_n) + 15 * (1 - e - 1200 * (x_n - 2))) / 1200
    return [v_t, a_t, v_n, a_n]


def test_ejemplo_8_11_hybrid_force_position_control():
    law = HybridForcePosition(pp_robot(M1, M2), FRAME, 1200.0,
                              HybridGains(15.0, 15.0, 15.0, 15.0), grav=PLANAR)
    times = (0.5, 1.0, 2.0, 3.0, 4.0, 5.0)
    states = _run(_simulation(), law, _ej_8_11_reference, 5.0, record=times)
    x, psi = states[5.0]
    assert 2.0 + math.cos(5.0) - x[1] == pytest.approx(-0.0050, abs=5e-5)
    assert psi[0] == pytest.approx(0.99924, abs=1e-5)
    ode = solve_ivp(_ej_8_11_closed_loop, (0.0, 5.0), [4.0, 0.0, 2.0, 0.0], t_eval=times,
                    method='Radau', rtol=1e-10, atol=1e-12)
    for k, t in enumerate(times):
        x, psi = states[t]
        assert x[1] == pytest.approx(ode.y[0, k], abs=1e-3)
        assert psi[0] == pytest.approx(1200.0 * (ode.y[2, k] - 2.0), abs=1e-3)


def test_without_contact_stiffness_control_is_a_cartesian_pd():
    # No surface: τ = Jᵀ(K_p x̃ - K_v x') + G, so Λ x'' = K_p (x_d - x) - K_v x' with the
    # task inertia Λ = J⁻ᵀ M J⁻¹ of (8.183), constant for this robot; x -> x_d.
    kp, kv = np.array([10.0, 25.0]), np.array([10.0, 6.0])
    x_d = np.array([1.0, 3.0])
    law = StiffnessControl(pp_robot(M1, M2), FRAME, StiffnessGains(kp=kp, kv=kv), grav=PLANAR)
    reference = TaskReference(x_d)
    states = _run(_simulation(surface=False), law, lambda t: reference, 6.0,
                  record=(1.0, 6.0))
    J_book = S * np.array([[1.0, -1.0], [1.0, 1.0]])
    J_inv = np.linalg.inv(J_book)
    task_inertia = J_inv.T @ np.diag([M1, M1 + M2]) @ J_inv

    def closed_loop(t, y):
        return np.r_[y[2:], np.linalg.solve(task_inertia, kp * (x_d - y[:2]) - kv * y[2:])]

    ode = solve_ivp(closed_loop, (0.0, 1.0), [2.0, 4.0, 0.0, 0.0], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(states[1.0][0], ode.y[:2, -1], atol=1e-3)
    np.testing.assert_allclose(states[6.0][0], x_d, atol=2e-3)
    np.testing.assert_array_equal(states[6.0][1], 0.0)


def test_impedance_control_settles_at_the_stiffness_steady_state():
    # M_d x̃'' + B_d x̃' + K_d x̃ = ψ against ψ = K_e (x1 - x_e1): at rest K_d x̃ = ψ, the
    # steady state (8.176) with K_d for K_p; along the surface x2 -> x_d2.
    gains = ImpedanceGains(inertia=1.0, damping=[60.0, 20.0], stiffness=[100.0, 100.0])
    law = ImpedanceControl(pp_robot(M1, M2), FRAME, gains, grav=PLANAR)
    x_d = [2.05, 2.5]
    reference = TaskReference(x_d)
    states = _run(_simulation(), law, lambda t: reference, 3.0, record=(3.0,))
    x, psi = states[3.0]
    x_inf, psi_inf = stiffness_steady_state(100.0, [1200.0, 0.0], x_d, [2.0, 0.0])
    np.testing.assert_allclose(x, x_inf, atol=1e-6)
    assert psi[0] == pytest.approx(psi_inf[0], abs=1e-3)     # 100·1200/1300·0.05 = 4.615 N
    assert psi[0] == pytest.approx(100.0 * (x_d[0] - x[0]), abs=1e-3)
