"""
Tests of robotica_ctrl.joint_control.reference_model: MRAC (catalogue §6.4, (8.75)-(8.78)).

The reference model's response comes from ``scipy.signal.lsim`` (zero-order hold), independent
of the law's matrix exponential; the plant, one joint of unknown inertia J (a double integrator
``J q'' = tau``), is stepped exactly over each period with the torque held.
"""

import numpy as np
import pytest
from robotica_ctrl.joint_control.law import JointReference, JointState
from robotica_ctrl.joint_control.reference_model import (ModelReferenceAdaptive,
                                                         ModelReferenceGains, ReferenceModel)
from scipy import signal

INERTIA = 2.0             # J [kg m²], unknown to the law
OMEGA, DAMPING = 2.0, 1.0  # reference model (8.76): a = 1/ω², b = 2δ/ω
MATCH = INERTIA * OMEGA ** 2, 2.0 * DAMPING * OMEGA * INERTIA   # K_p = J ω², K_v = 2 δ ω J
PERIOD = 10.0             # [s] of the square-wave command ±0.5 rad


def model_response(v, t, omega=OMEGA, damping=DAMPING):
    """Return y and y' of a y'' + b y' + y = v (8.75) for v held over each sample (lsim, ZOH)."""
    system = signal.StateSpace([[0.0, 1.0], [-omega ** 2, -2.0 * damping * omega]],
                               [[0.0], [omega ** 2]], np.eye(2), np.zeros((2, 1)))
    _, _, x = signal.lsim(system, v, t, interp=False)
    return x[:, 0], x[:, 1]


def run_double_integrator(gains, dt, duration):
    """Run the MRAC on J q'' = tau from rest; return t, v, q and the law's model output y."""
    law = ModelReferenceAdaptive(gains)
    t = np.arange(int(round(duration / dt))) * dt
    v = np.where(t % PERIOD < PERIOD / 2.0, 0.5, -0.5)
    q = qd = 0.0
    trajectory, model = np.empty_like(t), np.empty_like(t)
    for k, command in enumerate(v):
        trajectory[k] = q
        tau = law.update(JointReference([command]), JointState([q], [qd]), dt)[0]
        model[k] = law.model_output[0]        # y at t_k + dt
        q, qd = q + qd * dt + 0.5 * tau / INERTIA * dt * dt, qd + tau / INERTIA * dt
    return law, t, v, trajectory, np.concatenate([[0.0], model[:-1]])


def rms_per_period(error, dt):
    """Return the RMS of ``error`` over each period of the command."""
    samples = int(round(PERIOD / dt))
    return np.sqrt(np.mean(error.reshape(-1, samples) ** 2, axis=1))


def test_reference_model_is_the_exact_discretisation():
    """Two joints (δ = 1 and δ = 0.3) against scipy.signal.lsim with the input held (ZOH)."""
    model = ReferenceModel([2.0, 5.0], [1.0, 0.3])
    dt = 0.02
    t = np.arange(300) * dt
    inputs = np.column_stack([np.sign(np.sin(0.7 * t)), np.cos(1.3 * t)])
    state = np.zeros((2, 2))
    states = []
    for u in inputs:
        states.append(state)
        state = model.step(state, u, dt)
    states = np.array(states)
    for j, (omega, damping) in enumerate([(2.0, 1.0), (5.0, 0.3)]):
        y, yd = model_response(inputs[:, j], t, omega, damping)
        np.testing.assert_allclose(states[:, j, 0], y, atol=1e-10)
        np.testing.assert_allclose(states[:, j, 1], yd, atol=1e-10)
    one_joint = ReferenceModel([2.0], [1.0])      # y'' = ω² (u - y) - 2 δ ω y'
    np.testing.assert_allclose(one_joint.acceleration(np.array([[0.5, 0.1]]), np.array([1.0])),
                               [4.0 * 0.5 - 4.0 * 0.1])


def test_mrac_double_integrator_approaches_the_reference_model():
    """
    A joint of unknown inertia approaches its reference model as the gains adapt.

    J = 2 unknown, K_p(0) = 2, K_v(0) = 1 (too soft); model ω_n = 2, δ = 1; MIT rule (8.78)
    with w0 = 1, w1 = 0.5, γ = 20. Measured: RMS(q - y) per 10 s period 0.121 → 0.0023 rad
    over 200 s, falling every period; K_p, K_v → 7.5, 7.6 (the match is 8, 8).
    """
    gains = ModelReferenceGains(natural_frequency=OMEGA, damping=DAMPING, kp=2.0, kv=1.0,
                                gamma_p=20.0, gamma_v=20.0, w0=1.0, w1=0.5)
    dt = 0.01
    law, t, v, q, y_law = run_double_integrator(gains, dt, 200.0)
    y, _ = model_response(v, t)
    np.testing.assert_allclose(y_law, y, atol=1e-9)     # the law's model is the model
    rms = rms_per_period(q - y, dt)
    assert rms[-1] < 0.05 * rms[0]
    assert (np.diff(rms[1:]) < 0.0).all()
    np.testing.assert_allclose([law.proportional_gain[0], law.derivative_gain[0]], MATCH,
                               rtol=0.1)
    assert law.model_error[0] == pytest.approx(y[-1] - q[-1], abs=1e-12)


def test_mrac_with_the_acceleration_term():
    """w2 = 0.1 (ε'' through the q'' estimate) also adapts: the error falls period by period."""
    gains = ModelReferenceGains(natural_frequency=OMEGA, damping=DAMPING, kp=2.0, kv=1.0,
                                gamma_p=20.0, gamma_v=20.0, w0=1.0, w1=0.5, w2=0.1)
    dt = 0.01
    law, t, v, q, _ = run_double_integrator(gains, dt, 60.0)
    rms = rms_per_period(q - model_response(v, t)[0], dt)
    assert (np.diff(rms) < 0.0).all() and rms[-1] < 0.4 * rms[0]   # measured 0.118 → 0.034
    assert (law.proportional_gain > 2.0).all() and (law.derivative_gain > 1.0).all()


def test_first_update_and_reset():
    """The torque is K_p (q_d - q) - K_v q'; the model starts at the state; reset forgets n."""
    law = ModelReferenceAdaptive(ModelReferenceGains(kp=4.0, kv=1.0))
    assert law.proportional_gain.size == 0
    tau = law.update(JointReference([0.5, -0.5]), JointState([0.1, 0.2], [0.2, -0.1]), 0.01)
    np.testing.assert_allclose(tau, [4.0 * 0.4 - 0.2, 4.0 * -0.7 + 0.1])
    np.testing.assert_array_equal(law.model_error, [0.0, 0.0])
    with pytest.raises(ValueError):
        law.update(JointReference([0.5]), JointState([0.1], [0.2]), 0.01)
    law.reset()
    assert law.update(JointReference([0.5]), JointState([0.1], [0.2]), 0.01).shape == (1,)


def test_gains_stay_nonnegative():
    """A command that pushes K_v down never drives it below zero."""
    law = ModelReferenceAdaptive(ModelReferenceGains(kp=0.0, kv=0.0, gamma_p=1e6, gamma_v=1e6))
    for k in range(50):
        law.update(JointReference([1.0]), JointState([0.0], [-1.0 if k % 2 else 1.0]), 0.01)
        assert law.proportional_gain[0] >= 0.0 and law.derivative_gain[0] >= 0.0


@pytest.mark.parametrize('bad', [
    lambda: ModelReferenceGains(natural_frequency=0.0),
    lambda: ModelReferenceGains(damping=-1.0),
    lambda: ModelReferenceGains(gamma_p=np.nan),
    lambda: ModelReferenceGains(w2=-0.1),
    lambda: ModelReferenceAdaptive(gains={'kp': 1.0}),
    lambda: ModelReferenceAdaptive(ModelReferenceGains(kp=[1.0, 2.0, 3.0])).update(
        JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 0.01),
    lambda: ModelReferenceAdaptive().update(JointReference([0.0]), JointState([0.0], [0.0]),
                                            -0.01),
])
def test_bad_input_raises(bad):
    with pytest.raises(ValueError):
        bad()
