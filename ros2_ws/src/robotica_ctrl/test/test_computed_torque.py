"""Tests of robotica_ctrl.joint_control.computed_torque (seed catalogue Part 6, §6.3 and §6.8)."""

import math

import numpy as np
import pytest
from robotica_ctrl.joint_control import (ComputedTorque, ComputedTorqueGains, JointReference,
                                         JointState)
from robotica_kin.dynamics import fdyn, inertia
from robotica_kin.robots import two_link_arm

GRAV = [0.0, -9.81, 0.0]  # the book's planar examples (catalogue Part 6)
A, PERIOD = 0.15, 4.0     # Ej. 8.1 reference (8.47)
W = 2.0 * math.pi / PERIOD


def ej_8_1_reference(t: float) -> JointReference:
    """Return the Ej. 8.1 reference (8.47) at t [s]: θ1d = A sin(2πt/T), θ2d = A cos(2πt/T)."""
    s, c = math.sin(W * t), math.cos(W * t)
    return JointReference([A * s, A * c], [A * W * c, -A * W * s],
                          [-A * W * W * s, -A * W * W * c])


def simulate(law: ComputedTorque, plant: np.ndarray, tf: float, t_eval: list[float]):
    """Integrate the 2R plant from rest at q = 0 under the stateless (PD) law."""
    def torque(t, q, qd):
        return law.update(ej_8_1_reference(t), JointState(q, qd), 1e-3)
    return fdyn(plant, 0.0, tf, torque, [0.0, 0.0], [0.0, 0.0], GRAV, max_step=0.05,
                t_eval=t_eval)


def plant_accel(q, qd, tau, m1=2.0, m2=1.0, l1=3.0, l2=1.0, g=9.81):
    """Return q'' of the true 2R of Ej. 5.1 from its closed form (5.76)-(5.77), not Pinocchio."""
    s2, c2 = math.sin(q[1]), math.cos(q[1])
    c1, c12 = math.cos(q[0]), math.cos(q[0] + q[1])
    m12 = l2 ** 2 * m2 + l1 * l2 * m2 * c2
    mass = np.array([[l2 ** 2 * m2 + 2 * l1 * l2 * m2 * c2 + l1 ** 2 * (m1 + m2), m12],
                     [m12, l2 ** 2 * m2]])
    bias = np.array([-m2 * l1 * l2 * s2 * qd[1] ** 2 - 2 * m2 * l1 * l2 * s2 * qd[0] * qd[1]
                     + m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1,
                     m2 * l1 * l2 * s2 * qd[0] ** 2 + m2 * l2 * g * c12])
    return np.linalg.solve(mass, tau - bias)


def rk4_step(q, qd, tau, dt):
    """Advance the true 2R by dt with constant torque (zero-order hold), classical RK4."""
    k1q, k1v = qd, plant_accel(q, qd, tau)
    k2q, k2v = qd + 0.5 * dt * k1v, plant_accel(q + 0.5 * dt * k1q, qd + 0.5 * dt * k1v, tau)
    k3q, k3v = qd + 0.5 * dt * k2v, plant_accel(q + 0.5 * dt * k2q, qd + 0.5 * dt * k2v, tau)
    k4q, k4v = qd + dt * k3v, plant_accel(q + dt * k3q, qd + dt * k3v, tau)
    return (q + dt / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q),
            qd + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))


def test_ejemplo_8_1():
    """Catalogue §6.8, Ej. 8.1: exact model → e'' + 10 e' + 25 e = 0, |e| < 1e-6 after 5 s."""
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    law = ComputedTorque(dyn, ComputedTorqueGains(kp=25.0, kv=10.0), GRAV)
    times = [0.5, 1.0, 2.0, 3.0, 5.0, 8.0]
    run = simulate(law, dyn, 8.0, times)
    e0 = np.array([0.0, A])           # e(0) = q_d(0) - q(0)
    ed0 = np.array([A * W, 0.0])      # e'(0) = [0.2356, 0]
    for k, t in enumerate(run.t):
        expected = (e0 + (ed0 + 5.0 * e0) * t) * math.exp(-5.0 * t)   # critically damped, ω_n = 5
        error = np.asarray(ej_8_1_reference(t).q_d) - run.q[k]
        np.testing.assert_allclose(error, expected, atol=1e-6)
        if t >= 5.0:
            assert np.abs(error).max() < 1e-6


def test_ejemplo_8_2_and_8_4():
    """Catalogue §6.8, Ej. 8.2 (m̂ = 2.1, 0.9 kg); Ej. 8.4 quotes q'(10) = [-0.2352, -0.0089]."""
    _, plant = two_link_arm(2.0, 1.0, 3.0, 1.0)
    _, model = two_link_arm(2.1, 0.9, 3.0, 1.0)
    law = ComputedTorque(model, ComputedTorqueGains(kp=25.0, kv=10.0), GRAV)
    run = simulate(law, plant, 10.0, [10.0])
    np.testing.assert_allclose(run.qd[-1], [-0.2352, -0.0089], atol=5e-4)
    np.testing.assert_allclose(run.q[-1], [0.00563, -0.21322], atol=5e-4)


def test_ejemplo_8_3_integral_removes_steady_error():
    """Catalogue §6.8, Ej. 8.3: PID (K_i = 100) with the mass errors, max |e| for t > 10 s."""
    _, model = two_link_arm(2.1, 0.9, 3.0, 1.0)
    law = ComputedTorque(model, ComputedTorqueGains(kp=25.0, kv=10.0, ki=100.0), GRAV)
    dt, q, qd, worst = 4e-3, np.zeros(2), np.zeros(2), np.zeros(2)
    for k in range(int(round(14.0 / dt))):   # 250 Hz loop, torque held over each period
        t = k * dt
        tau = law.update(ej_8_1_reference(t), JointState(q, qd), dt)
        q, qd = rk4_step(q, qd, tau, dt)
        if t + dt > 10.0:
            worst = np.maximum(worst, np.abs(np.asarray(ej_8_1_reference(t + dt).q_d) - q))
    # Catalogue (computed): ≈ [0.0005; 0.0059] rad; PD (Ej. 8.2) leaves ≈ [0.0067; 0.0753].
    np.testing.assert_allclose(worst, [0.0005, 0.0059], rtol=0.1, atol=1e-4)


def test_reset_clears_integral():
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    law = ComputedTorque(dyn, ComputedTorqueGains(ki=10.0), GRAV)
    law.update(JointReference([0.1, 0.2]), JointState([0.0, 0.0], [0.0, 0.0]), 0.5)
    np.testing.assert_allclose(law.integral, [0.05, 0.1])
    law.reset()
    np.testing.assert_array_equal(law.integral, [0.0, 0.0])


def test_tau_is_inertia_times_tau_r_plus_gravity():
    """(8.27)-(8.30) at rest: tau = M̂(q) (K_p e) + Ĝ(q), checked against Ej. 5.1's closed form."""
    m1, m2, l1, l2, g = 2.0, 1.0, 3.0, 1.0, 9.81
    _, dyn = two_link_arm(m1, m2, l1, l2)
    law = ComputedTorque(dyn, ComputedTorqueGains(kp=[4.0, 9.0], kv=1.0), GRAV)
    q = np.array([0.3, -0.7])
    tau = law.update(JointReference(q + [0.1, 0.2]), JointState(q, [0.0, 0.0]), 1e-3)
    c1, c12 = math.cos(q[0]), math.cos(q[0] + q[1])
    gravity = [m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12]   # (5.77)
    np.testing.assert_allclose(tau, inertia(dyn, q) @ [0.4, 1.8] + gravity, rtol=1e-12)


@pytest.mark.parametrize('bad', [
    lambda law: law.update(JointReference([0.0, np.nan]), JointState([0, 0], [0, 0]), 1e-3),
    lambda law: law.update(JointReference([0.0]), JointState([0.0], [0.0]), 1e-3),
    lambda law: law.update(JointReference([0, 0]), JointState([0, 0, 0], [0, 0, 0]), 1e-3),
    lambda law: law.update(JointReference([0, 0]), JointState([0, 0], [0, 0]), 0.0),
    lambda law: law.update(JointReference([0, 0]), JointState([0, 0], [0, 0]), -1e-3),
    lambda law: law.update([0, 0], JointState([0, 0], [0, 0]), 1e-3),
    lambda law: JointState([0, 0], [0.0]),
    lambda law: ComputedTorque(np.zeros((2, 5))),
    lambda law: ComputedTorque(law.model, grav=[0.0, np.nan, 0.0]),
    lambda law: ComputedTorque(law.model, ComputedTorqueGains(kp=[1.0, 2.0, 3.0])),
    lambda law: ComputedTorqueGains(kv=-1.0),
    lambda law: ComputedTorqueGains(kp=np.nan),
])
def test_bad_input_raises(bad):
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    with pytest.raises(ValueError):
        bad(ComputedTorque(dyn, grav=GRAV))
