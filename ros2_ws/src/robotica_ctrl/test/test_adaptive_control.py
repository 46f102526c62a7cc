"""
Adaptive computed torque and Slotine-Li on the book's examples (catalogue §6.4, Ej. 8.7, 8.8).

Each plant is written here: the 2R of Ej. 5.1 by its closed form (5.76)-(5.77)
(``tests/reference_models.py``) and the PUMA 560 by ``robotica_kin.dynamics``, integrated by a
fixed-step RK4 with the law's torque held over each control period (zero-order hold).
"""

import math

import numpy as np
import pytest
from reference_models import closed_form_2r
from robotica_ctrl.joint_control.acceleration_estimate import AccelerationEstimate
from robotica_ctrl.joint_control.adaptive_computed_torque import (AdaptiveComputedTorque,
                                                                  AdaptiveComputedTorqueGains,
                                                                  lyapunov_p)
from robotica_ctrl.joint_control.law import JointReference, JointState
from robotica_ctrl.joint_control.regressor import LinkMassRegressor, TwoLinkRegressor
from robotica_ctrl.joint_control.slotine_li import SlotineLi, SlotineLiGains
from robotica_kin.dynamics import inertia, rne
from robotica_kin.integrators import rk4_step
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import puma560, two_link_arm


def two_link_plant(m1, m2, l1, l2, g):
    """Return q''(q, q', tau) of the true 2R by its closed form (5.76)-(5.77)."""
    def acceleration(q, qd, tau):
        mass, coriolis, grav, _ = closed_form_2r(m1, m2, l1, l2, q, qd, [0.0, 0.0], g)
        return np.linalg.solve(mass, tau - coriolis - grav)
    return acceleration


def simulate(law, acceleration, reference, n, dt, steps):
    """
    Run ``law`` on the plant from rest at q = 0 for ``steps`` periods ``dt``.

    Returns the times (k + 1,), the errors q_d - q (k + 1, n) and the estimates φ̂ (k + 1, p)
    at each period's start (the last row is the end).
    """
    def derivative(t, x, tau):
        return np.concatenate([x[n:], acceleration(x[:n], x[n:], tau)])

    x = np.zeros(2 * n)
    times, errors, estimates = [], [], []
    for k in range(steps + 1):
        t = k * dt
        ref = reference(t)
        times.append(t)
        errors.append(ref.q_d - x[:n])
        estimates.append(law.estimates)
        if k == steps:
            break
        tau = law.update(ref, JointState(x[:n], x[n:]), dt)
        x = rk4_step(derivative, t, x, dt, tau)
    return np.array(times), np.array(errors), np.array(estimates)


def sine_reference(n):
    """Return q_d = sin t on every joint (Ej. 8.8, (8.137))."""
    def reference(t):
        s, c = math.sin(t), math.cos(t)
        return JointReference(np.full(n, s), np.full(n, c), np.full(n, -s))
    return reference


# --- Ej. 8.8: Slotine and Li on the 2R -----------------------------------------------------

EJ_8_8_MASSES = (0.8, 2.3)      # true m1, m2 [kg]; l1 = l2 = 1 m, g = 9.8 (Lewis et al.)


@pytest.mark.parametrize('path', ['closed form (8.134)', 'LinkMassRegressor'])
def test_ejemplo_8_8(path):
    """
    Catalogue §6.8, Ej. 8.8 (8.137): k_v = 10, λ = 2.5, γ = 20, m̂(0) = [30, 100], q_d = sin t.

    Catalogue (computed, continuous time): e(5 s) ≈ [0.0004, -0.015] rad, m̂ → [0.800, 2.300],
    m̂1 negative around t = 1-2 s. This discrete law at 1 kHz gives e(5) = [0.0003, -0.0160]
    and m̂(10) = [0.8019, 2.2978] (its explicit step of φ̂ and the held torque).
    """
    g = 9.8
    regressor = (TwoLinkRegressor(1.0, 1.0, g) if path.startswith('closed')
                 else LinkMassRegressor(two_link_arm(*EJ_8_8_MASSES, 1.0, 1.0)[1], [0.0, -g, 0.0]))
    law = SlotineLi(regressor, [30.0, 100.0], SlotineLiGains(kv=10.0, lam=2.5, gamma=20.0))
    dt = 1e-3
    t, e, m = simulate(law, two_link_plant(*EJ_8_8_MASSES, 1.0, 1.0, g), sine_reference(2), 2,
                       dt, 10_000)
    np.testing.assert_allclose(e[5_000], [0.0004, -0.015], atol=0.002)
    np.testing.assert_allclose(m[-1], [0.800, 2.300], atol=0.01)
    assert m[(t >= 1.0) & (t <= 2.0), 0].min() < 0.0
    assert np.abs(e[t >= 9.0]).max() < 1e-3


def test_slotine_li_paths_agree():
    """The closed form (8.134) and the Pinocchio regressor give the same law on the 2R."""
    g, dt = 9.8, 1e-3
    laws = [SlotineLi(regressor, [30.0, 100.0])
            for regressor in (TwoLinkRegressor(1.0, 1.0, g),
                              LinkMassRegressor(two_link_arm(0.8, 2.3, 1.0, 1.0)[1],
                                                [0.0, -g, 0.0]))]
    state = JointState([0.1, -0.3], [0.4, 0.2])
    for k in range(3):
        ref = sine_reference(2)(k * dt)
        tau = [law.update(ref, state, dt) for law in laws]
        np.testing.assert_allclose(tau[0], tau[1], rtol=1e-12)
    np.testing.assert_allclose(laws[0].estimates, laws[1].estimates, rtol=1e-12)
    np.testing.assert_allclose(laws[0].filtered_error, laws[1].filtered_error, rtol=1e-12)


def test_puma_slotine_li_tracks_with_wrong_masses():
    """PUMA 560, masses 1.5 × its table's, q_d = sin t: adaptation cuts the error ≥ 10×."""
    robot = puma560()
    arm = pinocchio_arm(robot)
    data = arm.model.createData()
    zero = np.zeros(6)

    def acceleration(q, qd, tau):
        return np.linalg.solve(inertia(arm, q, data=data), tau - rne(arm, q, qd, zero, data=data))

    regressor = LinkMassRegressor(robot)
    worst = {}
    for gamma in (20.0, 1e-9):     # adaptive, and in effect a fixed wrong model
        law = SlotineLi(regressor, 1.5 * regressor.masses,
                        SlotineLiGains(kv=50.0, lam=5.0, gamma=gamma))
        t, e, _ = simulate(law, acceleration, sine_reference(6), 6, 1e-3, 3_000)
        worst[gamma] = np.abs(e[t >= 2.0]).max(axis=0)
    assert worst[20.0].max() < 0.005                   # measured 0.0020 rad (joint 1)
    assert worst[20.0].max() < 0.1 * worst[1e-9].max()  # fixed model: 0.080 rad (joint 2)


def test_slotine_li_step_and_reset():
    """One step at rest, (8.111), (8.123), (8.125): r = Λ e, tau = Y φ̂ + K_v r, φ̂' = Γ Yᵀ r."""
    regressor = TwoLinkRegressor(1.0, 1.0, 9.8)
    law = SlotineLi(regressor, [1.0, 2.0], SlotineLiGains(kv=[10.0, 20.0], lam=2.0, gamma=3.0))
    tau = law.update(JointReference([0.1, -0.2]), JointState([0.0, 0.0], [0.0, 0.0]), 0.01)
    r = np.array([0.2, -0.4])
    y, _ = regressor.slotine_li_terms([0, 0], [0, 0], 2.0 * np.array([0.1, -0.2]), [0, 0])
    np.testing.assert_allclose(law.filtered_error, r)
    np.testing.assert_allclose(tau, y @ [1.0, 2.0] + [10.0, 20.0] * r)
    np.testing.assert_allclose(law.estimates, [1.0, 2.0] + 0.01 * 3.0 * y.T @ r)
    law.reset()
    np.testing.assert_array_equal(law.estimates, [1.0, 2.0])
    np.testing.assert_array_equal(law.filtered_error, [0.0, 0.0])
    assert law.parameter_names == ('link_1.mass', 'link_2.mass')


# --- Ej. 8.7: adaptive computed torque on the 2R -----------------------------------------------

def ej_8_1_reference(t):
    """Ej. 8.1's reference (8.47): θ1d = 0.15 sin(2πt/4), θ2d = 0.15 cos(2πt/4)."""
    a, w = 0.15, 2.0 * math.pi / 4.0
    s, c = math.sin(w * t), math.cos(w * t)
    return JointReference([a * s, a * c], [a * w * c, -a * w * s],
                          [-a * w * w * s, -a * w * w * c])


def test_ejemplo_8_7_adaptive_computed_torque_learns_the_masses():
    """
    Ej. 8.7 on Ej. 8.2's case: m = [2, 1], m̂(0) = [2.1, 0.9], K_p = 25, K_v = 10, Γ = 30.

    Ej. 8.1's reference (sine and cosine, exciting both masses), 250 Hz. The fixed model of
    Ej. 8.2 leaves max |e| ≈ [0.0067, 0.0753] rad after 5 s (catalogue); adapting, m̂(20 s) =
    [2.0000, 0.9999] and max |e| over 15-20 s ≈ [0.0001, 0.0001] (measured).
    """
    law = AdaptiveComputedTorque(TwoLinkRegressor(3.0, 1.0, 9.81), [2.1, 0.9],
                                 AdaptiveComputedTorqueGains(kp=25.0, kv=10.0, gamma=30.0))
    t, e, m = simulate(law, two_link_plant(2.0, 1.0, 3.0, 1.0, 9.81), ej_8_1_reference, 2, 4e-3,
                       5_000)
    np.testing.assert_allclose(m[-1], [2.0, 1.0], atol=0.005)
    late = np.abs(e[t >= 15.0]).max(axis=0)
    assert (late < 5e-4).all()
    assert late.max() < 0.01 * np.abs(e[t <= 5.0]).max()
    assert law.refusals == 0


def test_adaptive_computed_torque_paths_agree():
    """The closed form (8.100) and the Pinocchio regressor give the same law on the 2R."""
    laws = [AdaptiveComputedTorque(regressor, [2.1, 0.9])
            for regressor in (TwoLinkRegressor(3.0, 1.0, 9.81),
                              LinkMassRegressor(two_link_arm(2.0, 1.0, 3.0, 1.0)[1],
                                                [0.0, -9.81, 0.0]))]
    for k, qd in enumerate(([0.3, -0.2], [0.5, 0.1], [0.4, 0.0])):
        state = JointState([0.1, -0.3], qd)
        tau = [law.update(ej_8_1_reference(k * 1e-3), state, 1e-3) for law in laws]
        np.testing.assert_allclose(tau[0], tau[1], rtol=1e-12)
    np.testing.assert_allclose(laws[0].estimates, laws[1].estimates, rtol=1e-12)


def test_lyapunov_p_is_8_102_and_solves_8_92_with_q_of_8_103():
    """(8.102): P = ½[[(k_p + ½k_v) I, ½ I], [½ I, I]]; Aᵀ P + P A = -Q, Q = (8.103)."""
    kp, kv = 25.0, 10.0
    law = AdaptiveComputedTorque(TwoLinkRegressor(1.0, 1.0, 9.8), [1.0, 1.0],
                                 AdaptiveComputedTorqueGains(kp=kp, kv=kv))
    eye = np.eye(2)
    book_p = 0.5 * np.block([[(kp + 0.5 * kv) * eye, 0.5 * eye], [0.5 * eye, eye]])
    np.testing.assert_allclose(law.lyapunov_p, book_p, atol=1e-12)
    a = np.block([[np.zeros((2, 2)), eye], [-kp * eye, -kv * eye]])
    book_q = np.block([[0.5 * kp * eye, np.zeros((2, 2))], [np.zeros((2, 2)), (kv - 0.5) * eye]])
    np.testing.assert_allclose(a.T @ book_p + book_p @ a, -book_q, atol=1e-12)
    assert np.linalg.eigvalsh(book_p).min() > 0.0
    # Per-joint gains and another Q: P still solves (8.92).
    p = lyapunov_p([25.0, 16.0], [10.0, 8.0], [1.0, 2.0, 3.0, 4.0])
    a = np.block([[np.zeros((2, 2)), eye], [-np.diag([25.0, 16.0]), -np.diag([10.0, 8.0])]])
    np.testing.assert_allclose(a.T @ p + p @ a, -np.diag([1.0, 2.0, 3.0, 4.0]), atol=1e-12)


def test_adaptation_error_is_8_104():
    """With the default Q, Bᵀ P ε = ¼ e + ½ e' (8.104), whatever k_p, k_v."""
    law = AdaptiveComputedTorque(TwoLinkRegressor(1.0, 1.0, 9.8), [1.0, 1.0],
                                 AdaptiveComputedTorqueGains(kp=49.0, kv=3.0))
    law.update(JointReference([0.2, -0.1], [0.0, 0.3]), JointState([0.0, 0.0], [0.1, 0.1]), 1e-3)
    np.testing.assert_allclose(law.adaptation_error,
                               0.25 * np.array([0.2, -0.1]) + 0.5 * np.array([-0.1, 0.2]))


def test_singular_inertia_refuses_the_step():
    """m̂ = [-5, -5] kg: M̂ is not positive definite, the step is refused, φ̂ kept."""
    law = AdaptiveComputedTorque(TwoLinkRegressor(1.0, 1.0, 9.8), [-5.0, -5.0])
    law.update(JointReference([0.3, 0.1]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    assert law.refusals == 1
    np.testing.assert_array_equal(law.estimates, [-5.0, -5.0])
    law.reset()
    assert law.refusals == 0


def test_bounds_project_the_estimates():
    """A huge Γ drives φ̂ out of [0.5, 1.5] kg; the projection keeps it on the bound."""
    law = AdaptiveComputedTorque(TwoLinkRegressor(1.0, 1.0, 9.8), [1.0, 1.0],
                                 AdaptiveComputedTorqueGains(gamma=1e6), bounds=(0.5, 1.5))
    for qd in ([0.0, 0.0], [1.0, -1.0], [2.0, 1.0]):
        law.update(JointReference([1.0, 1.0]), JointState([0.0, 0.0], qd), 1e-3)
        assert ((law.estimates >= 0.5) & (law.estimates <= 1.5)).all()
    assert np.isin(law.estimates, [0.5, 1.5]).any()


def test_acceleration_estimate():
    """First zero, then (q'_k - q'_{k-1}) / dt through f_k = f_{k-1} + dt/(T + dt)(raw - f)."""
    raw = AccelerationEstimate()
    filtered = AccelerationEstimate([0.0, 0.03])
    velocities = [np.array([0.0, 0.0]), np.array([0.1, 0.1]), np.array([0.1, 0.3])]
    expected_filtered = [[0.0, 0.0], [10.0, 2.5], [0.0, 2.5 + 0.25 * (20.0 - 2.5)]]
    for qd, expected_raw, expected in zip(velocities, [[0, 0], [10, 10], [0, 20]],
                                          expected_filtered):
        np.testing.assert_allclose(raw.update(qd, 0.01), expected_raw, atol=1e-12)
        np.testing.assert_allclose(filtered.update(qd, 0.01), expected, atol=1e-12)
    raw.reset()
    np.testing.assert_array_equal(raw.update(np.array([5.0, 5.0]), 0.01), [0.0, 0.0])
    with pytest.raises(ValueError):
        raw.update(np.array([1.0]), 0.01)


@pytest.mark.parametrize('bad', [
    lambda r: SlotineLi(r, [1.0]),
    lambda r: SlotineLi(r, [1.0, np.nan]),
    lambda r: SlotineLi(r, [1.0, 1.0], SlotineLiGains(kv=[1.0, 2.0, 3.0])),
    lambda r: SlotineLi(r, [1.0, 1.0], gains=AdaptiveComputedTorqueGains()),
    lambda r: SlotineLiGains(lam=0.0),
    lambda r: SlotineLiGains(gamma=-1.0),
    lambda r: SlotineLi(r, [1.0, 1.0]).update(JointReference([0.0]), JointState([0.0], [0.0]),
                                              1e-3),
    lambda r: SlotineLi(r, [1.0, 1.0]).update(JointReference([0, 0]), JointState([0, 0], [0, 0]),
                                              0.0),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], AdaptiveComputedTorqueGains(kv=0.5)),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], AdaptiveComputedTorqueGains(gamma=[1, 2, 3])),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0],
                                     AdaptiveComputedTorqueGains(lyapunov_q=[1.0, 2.0, 3.0])),
    lambda r: AdaptiveComputedTorqueGains(lyapunov_q=[1.0, 0.0, 1.0, 1.0]),
    lambda r: AdaptiveComputedTorqueGains(acceleration_time_constant=-0.1),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], bounds=(2.0, 1.0)),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], bounds=(0.0, 0.5)),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], bounds=(0.0, [1.0, 2.0, 3.0])),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0], bounds=(np.nan, 2.0)),
    lambda r: AdaptiveComputedTorque(r, [1.0, 1.0]).update(
        JointReference([0.0, np.nan]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3),
    lambda r: AccelerationEstimate(-1.0),
])
def test_bad_input_raises(bad):
    with pytest.raises(ValueError):
        bad(TwoLinkRegressor(1.0, 1.0, 9.8))
