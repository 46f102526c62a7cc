"""
The appendix's learning control on the PUMA 560 (seed catalogue Part 12.6, (A.2)-(A.4); §8.5).

Plant: robotica_sim's ArmSimulation (Pinocchio's ABA and RK4 at 1 kHz, torque held over the step)
of ``robots.puma560()`` with the appendix's viscous friction of 0.1 N m s on joint 1 that the
controller's model does not have, and the joint stops off (sin t leaves the ranges of joints 2
and 3, as the puma_computed_torque_friction scenario notes). Controller: IterativeLearningControl
on the PUMA's own model, K_p = 125 I₆, K_v = 50 I₆, μ = 2 I₆ (A.4); reference θ_i(t) = sin t
(A.2). A trial is one period of the reference, 2π s, and starts on it (q = 0, q' = 1 rad/s): from
rest, the response to e'(0) = 1 rad/s (an overdamped pole at -2.7 rad/s) would be 1000 times the
friction's error in the mean (8.153), and the learning leaves it (the fixed point keeps the
response to a trial's initial error).
"""

import math

import numpy as np
import pytest
from robotica_ctrl.joint_control import (IterativeLearningControl, JointReference, JointState,
                                         LearningGains)
from robotica_kin.dynamics import inertia
from robotica_kin.robots import puma560
from robotica_sim.simulation.arm import arm_simulation
from scipy.integrate import solve_ivp

FRICTION_1 = 0.1                       # [N m s] on joint 1, unknown to the controller (App. A)
GAINS = LearningGains(kp=125.0, kv=50.0, mu=2.0)   # (A.4)
STEP = 1e-3                            # [s] 1 kHz, plant and law
STEPS = int(round(2.0 * math.pi / STEP))   # one period of sin t per trial
TRIALS = 5                             # fig. A.14 compares iterations 1 and 5


def reference(t):
    """Return θ_d = sin t on every joint (A.2), with its rates."""
    s, c = math.sin(t), math.cos(t)
    return JointReference([s] * 6, [c] * 6, [-s] * 6)


@pytest.fixture(scope='module')
def puma_trials():
    """Run the trials; return (errors (trials, steps, 6) [rad], MSE of each trial (trials, 6))."""
    robot = puma560()
    sim = arm_simulation(robot, {'unmodelled_viscous': [FRICTION_1, 0, 0, 0, 0, 0],
                                 'respect_limits': False}, STEP)
    law = IterativeLearningControl(robot, GAINS)
    errors = np.empty((TRIALS, STEPS, 6))
    for trial in range(TRIALS):
        sim.reset(np.zeros(6), np.ones(6))
        for j in range(STEPS):
            desired = reference(j * STEP)
            errors[trial, j] = desired.q_d - sim.q
            sim.step(law.update(desired, JointState(sim.q, sim.qd), STEP))
        law.end_trial()
    return errors, np.array(law.trial_errors)


def test_trial_1_error_is_the_unmodelled_friction(puma_trials):
    """
    Trial 1: e'' + K_v e' + K_p e = M⁻¹ F (8.139)-(8.141), F = [0.1 q1', 0, ...], integrated here.

    The error is ~1e-4 rad, so M and q' are taken on the reference; the friction is felt mostly
    on joint 1, whose mean error is 80 times the others' (measured 1.7e-8 rad² against <= 2.1e-10).
    """
    errors, mse = puma_trials
    robot = puma560()

    def error_dynamics(t, x):
        disturbance = np.linalg.solve(inertia(robot, [math.sin(t)] * 6),
                                      [FRICTION_1 * math.cos(t), 0, 0, 0, 0, 0])
        return np.concatenate([x[6:], disturbance - 50.0 * x[6:] - 125.0 * x[:6]])

    times = np.arange(STEPS) * STEP
    predicted = solve_ivp(error_dynamics, (0.0, times[-1]), np.zeros(12), t_eval=times,
                          rtol=1e-8, atol=1e-12).y[:6].T
    # Within 5 % of its peak (2.1e-4 rad; measured 3.5 %): the 1 ms hold of the torque alone
    # leaves an error of that size (4e-6 rad rms on joint 1 with an exact model, no friction).
    peak = np.abs(predicted[:, 0]).max()
    assert 1.5e-4 < peak < 3e-4
    np.testing.assert_allclose(errors[0, :, 0], predicted[:, 0], atol=0.05 * peak)
    assert mse[0, 0] > 50.0 * mse[0, 1:].max()


def test_learning_removes_the_friction_error(puma_trials):
    """Fig. A.14: the errors at iteration 5 are much smaller than at iteration 1."""
    errors, mse = puma_trials
    # Joint 1's mean squared error falls trial by trial to round-off: measured 1.7e-8, 9.3e-12,
    # 9.1e-15, then ~1e-15 rad² (trial 5 / trial 1 = 5.5e-8).
    assert mse[1, 0] < 1e-2 * mse[0, 0] and mse[2, 0] < 1e-2 * mse[1, 0]
    assert mse[4, 0] < 1e-6 * mse[0, 0]
    assert np.abs(errors[4, :, 0]).max() < 1e-3 * np.abs(errors[0, :, 0]).max()
    # The other joints do not get worse than their trial 1 (their error is the coupling's).
    assert (mse[4, 1:] < mse[0, 1:]).all()
