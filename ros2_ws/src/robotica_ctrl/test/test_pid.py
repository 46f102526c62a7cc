"""Tests of robotica_ctrl.joint_control.pid: decoupled PID, book (8.10), catalogue §6.1."""

import math

import numpy as np
import pytest
from robotica_ctrl.joint_control import DecoupledPID, JointReference, JointState, PIDGains
from scipy.integrate import solve_ivp


def run_double_integrator(pid, q_d, tf, t_eval):
    """Integrate the unit-inertia double integrator q'' = u from rest under a memoryless law."""
    def derivative(t, x):
        u = pid.update(JointReference([q_d]), JointState([x[0]], [x[1]]), 1e-3)
        return [x[1], u[0]]
    return solve_ivp(derivative, (0.0, tf), [0.0, 0.0], t_eval=t_eval, rtol=1e-10, atol=1e-12)


def test_p_control_closed_form():
    """P only, K_p = 4 on q'' = u from rest towards q_d = 1: q(t) = 1 - cos(2t) (undamped)."""
    times = np.linspace(0.0, 5.0, 11)
    run = run_double_integrator(DecoupledPID(PIDGains(kp=4.0, kv=0.0)), 1.0, 5.0, times)
    np.testing.assert_allclose(run.y[0], 1.0 - np.cos(2.0 * times), atol=1e-7)


def test_pd_control_closed_form():
    """PD, K_p = 25, K_v = 10 (ω_n = 5, δ = 1, (8.21)-(8.24)): e(t) = (1 + 5t) exp(-5t)."""
    times = np.linspace(0.0, 3.0, 13)
    run = run_double_integrator(DecoupledPID(PIDGains(kp=25.0, kv=10.0)), 1.0, 3.0, times)
    np.testing.assert_allclose(1.0 - run.y[0], (1.0 + 5.0 * times) * np.exp(-5.0 * times),
                               atol=1e-7)


def test_integral_rejects_constant_disturbance():
    """With q'' = u - d, PD leaves e = d / K_p; PID drives e to 0 with K_i ∫e → d (500 Hz loop)."""
    d, dt = 2.0, 2e-3
    finals = []
    for ki in (0.0, 20.0):
        pid = DecoupledPID(PIDGains(kp=25.0, kv=10.0, ki=ki))
        q, qd = 0.0, 0.0
        for _ in range(int(round(12.0 / dt))):
            u = pid.update(JointReference([1.0]), JointState([q], [qd]), dt)[0]
            qd += (u - d) * dt        # semi-implicit Euler
            q += qd * dt
        finals.append((1.0 - q, pid.integral))
    assert finals[0][0] == pytest.approx(d / 25.0, abs=1e-6)
    assert abs(finals[1][0]) < 1e-6
    assert finals[1][1][0] == pytest.approx(d / 20.0, abs=1e-6)


def test_anti_windup_conditional_integration():
    """Saturated at tau_max with a blocked joint: the integral does not grow; output = tau_max."""
    pid = DecoupledPID(PIDGains(kp=1.0, kv=0.0, ki=10.0, tau_max=[0.5, 200.0]))
    for _ in range(1000):
        tau = pid.update(JointReference([1.0, 1.0]), JointState([0.0, 0.0], [0.0, 0.0]), 0.01)
    np.testing.assert_allclose(tau, [0.5, 1.0 + 10.0 * 10.0])   # joint 2 never saturates
    np.testing.assert_allclose(pid.integral, [0.0, 10.0])
    # Error reverses: the output leaves saturation and joint 1 integrates again at once.
    tau = pid.update(JointReference([0.0, 0.0]), JointState([0.01, 0.0], [0.0, 0.0]), 0.01)
    np.testing.assert_allclose(pid.integral[0], -1e-4)
    np.testing.assert_allclose(tau[0], -0.01 - 1e-3)


def test_anti_windup_integral_clamp():
    pid = DecoupledPID(PIDGains(kp=0.0, kv=0.0, ki=1.0, integral_max=0.25))
    for _ in range(100):
        tau = pid.update(JointReference([1.0]), JointState([0.0], [0.0]), 0.01)
    np.testing.assert_allclose(pid.integral, [0.25])
    np.testing.assert_allclose(tau, [0.25])


def test_derivative_uses_velocity_error_and_saturates():
    pid = DecoupledPID(PIDGains(kp=[2.0, 3.0], kv=[0.5, 1.0], tau_max=1.0))
    tau = pid.update(JointReference([0.1, 0.0], [1.0, 0.0]), JointState([0.0, 1.0], [0.0, 0.0]),
                     0.01)
    np.testing.assert_allclose(tau, [2.0 * 0.1 + 0.5 * 1.0, -1.0])   # second: -3 clipped


def test_reset_clears_state():
    pid = DecoupledPID(PIDGains(ki=1.0))
    pid.update(JointReference([1.0, 2.0]), JointState([0.0, 0.0], [0.0, 0.0]), 0.1)
    np.testing.assert_allclose(pid.integral, [0.1, 0.2])
    pid.reset()
    assert pid.integral is None
    tau = pid.update(JointReference([1.0]), JointState([0.0], [0.0]), 0.1)   # n may change now
    np.testing.assert_allclose(tau, [25.0 + 0.1])
    assert math.isclose(pid.integral[0], 0.1)


@pytest.mark.parametrize('dt', [0.0, -1e-3, math.nan, math.inf])
def test_bad_dt_raises(dt):
    with pytest.raises(ValueError, match='dt'):
        DecoupledPID().update(JointReference([1.0]), JointState([0.0], [0.0]), dt)


@pytest.mark.parametrize('bad', [
    lambda pid: pid.update(JointReference([math.nan]), JointState([0.0], [0.0]), 1e-3),
    lambda pid: pid.update(JointReference([0.0]), JointState([0.0], [math.inf]), 1e-3),
    lambda pid: pid.update(JointReference([0.0, 0.0]), JointState([0.0], [0.0]), 1e-3),
    lambda pid: pid.update(JointReference([[0.0]]), JointState([0.0], [0.0]), 1e-3),
    lambda pid: pid.update(JointReference([0.0, 0.0], [0.0]), JointState([0.0], [0.0]), 1e-3),
    lambda pid: DecoupledPID(PIDGains(kp=[1.0, 2.0, 3.0])).update(
        JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3),
    lambda pid: PIDGains(kp=-1.0),
    lambda pid: PIDGains(ki=math.nan),
    lambda pid: PIDGains(kv=math.inf),
    lambda pid: PIDGains(tau_max=0.0),
    lambda pid: PIDGains(integral_max=-1.0),
    lambda pid: DecoupledPID({'kp': 1.0}),
])
def test_bad_input_raises(bad):
    with pytest.raises(ValueError):
        bad(DecoupledPID())


def test_joint_count_is_fixed_until_reset():
    pid = DecoupledPID()
    pid.update(JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    with pytest.raises(ValueError, match='reset'):
        pid.update(JointReference([0.0]), JointState([0.0], [0.0]), 1e-3)


def test_derivative_filter_is_a_first_order_lag():
    # A velocity-error step of 1 rad/s through 1 / (T_f s + 1), backward Euler with a = dt /
    # (T_f + dt): f_k = 1 - (1 - a)^k after the first sample (which initialises the filter).
    tf, dt = 0.05, 0.01
    a = dt / (tf + dt)
    pid = DecoupledPID(PIDGains(kp=0.0, kv=1.0, derivative_time_constant=tf))
    assert pid.update(JointReference([0.0], [0.0]), JointState([0.0], [0.0]), dt)[0] == 0.0
    for k in range(1, 30):
        tau = pid.update(JointReference([0.0], [1.0]), JointState([0.0], [0.0]), dt)
        assert tau[0] == pytest.approx(1.0 - (1.0 - a) ** k, rel=1e-12)
    pid.reset()   # the filter restarts from the next sample
    assert pid.update(JointReference([0.0], [1.0]), JointState([0.0], [0.0]), dt)[0] == 1.0
    with pytest.raises(ValueError, match='derivative_time_constant'):
        PIDGains(derivative_time_constant=-0.1)
