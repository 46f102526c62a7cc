"""
Tests of robotica_ctrl.mobile.gpc_tracker: the GPC path tracker of book §9.5.

References are independent of the code under test: the sampled lateral model against
``scipy.signal.cont2discrete`` and the closed-form continuous step response. Closed-loop tests
drive a bicycle x' = v cos θ, y' = v sin θ, θ' = v γ with the steering lag γ' = (u - γ)/τ
(book (9.113); γ = u when τ = 0), written here and integrated with ``rk4_step``. The numbers of
the NavLab experiment of §9.5 (seed catalogue §7.8: τ = 0.4 s, v = 3.4 m/s, 18 points, NU = 1,
N = 10 vs 25) are used where they apply; the book gives no worked GPC example with numbers
(catalogue §7.10), and the sampling period (0.1 s) is ours.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.gpc import prediction_polynomials
from robotica_ctrl.mobile.gpc_tracker import (GpcPathTracker, GpcTrackerParams,
                                              lateral_carima_model)
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import straight_line
from robotica_ctrl.mobile.tracker_base import TrackerOutput
from robotica_kin.integrators import rk4_step
from scipy.signal import cont2discrete, ss2tf


# --- Sampled lateral model (9.109)-(9.113) ----------------------------------------------

def test_lateral_model_without_lag_is_the_sampled_double_integrator():
    # e'' = v² u with ZOH: (v T)²/2 (1 + q^-1) q^-1 / (1 - q^-1)² (worked by hand).
    a, b = lateral_carima_model(2.0, 0.05)
    np.testing.assert_allclose(a, [1.0, -2.0, 1.0])
    np.testing.assert_allclose(b, [0.005, 0.005], rtol=1e-14)


@pytest.mark.parametrize(('v', 't', 'tau'), [(1.0, 0.1, 0.5), (3.4, 0.1, 0.4),
                                             (0.5, 0.02, 2.0)])
def test_lateral_model_with_lag_matches_scipy_and_the_continuous_step(v, t, tau):
    a, b = lateral_carima_model(v, t, tau)
    A = np.array([[0.0, v, 0.0], [0.0, 0.0, v], [0.0, 0.0, -1.0 / tau]])
    B = np.array([[0.0], [0.0], [1.0 / tau]])
    C = np.array([[1.0, 0.0, 0.0]])
    Ad, Bd, Cd, Dd, _ = cont2discrete((A, B, C, np.zeros((1, 1))), t, method='zoh')
    num, den = ss2tf(Ad, Bd, Cd, Dd)
    np.testing.assert_allclose(a, den, rtol=1e-12)
    np.testing.assert_allclose(b, num[0, 1:], rtol=1e-7)  # ss2tf goes through eigenvalues
    p = math.exp(-t / tau)
    np.testing.assert_allclose(a, np.convolve([1.0, -2.0, 1.0], [1.0, -p]), rtol=1e-12)
    # Step response at the samples equals v² (t²/2 - τ t + τ² (1 - e^(-t/τ))).
    times = t * np.arange(1, 30)
    exact = v * v * (times ** 2 / 2 - tau * times + tau ** 2 * (1.0 - np.exp(-times / tau)))
    g = prediction_polynomials(a, b, 29)[0]
    np.testing.assert_allclose(g, exact, rtol=1e-8, atol=1e-14)


def test_lateral_model_rejects_bad_input():
    for args in [(0.0, 0.1), (-1.0, 0.1), (math.nan, 0.1), (1.0, 0.0), (1.0, 0.1, -0.1),
                 (1.0, 0.1, math.inf)]:
        with pytest.raises(ValueError):
            lateral_carima_model(*args)


# --- Bad parameters ---------------------------------------------------------------------

@pytest.mark.parametrize('change', [
    {'linear_velocity': 0.0}, {'linear_velocity': math.inf}, {'sample_time': -0.1},
    {'steering_time_constant': -0.1}, {'n1': 0}, {'n1': 5, 'n2': 4}, {'nu': 19},
    {'n2': 2.5}, {'control_weight': -1.0}, {'softening': 1.0}, {'max_curvature': 0.0},
    {'max_curvature': math.nan}, {'goal_tolerance': 0.0}, {'search_window': math.nan},
    {'model_speed_tolerance': -0.1},
])
def test_tracker_params_reject_bad_values(change):
    with pytest.raises(ValueError):
        GpcTrackerParams(**change)


def test_tracker_rejects_bad_poses_and_keeps_the_model_for_bad_speeds():
    tracker = GpcPathTracker(PolylinePath([[0.0, 0.0], [10.0, 0.0]]), GpcTrackerParams())
    for pose in [[0.0, 0.0], [0.0, 0.0, math.nan], [0.0, 0.0, 0.0, 0.0]]:
        with pytest.raises(ValueError):
            tracker.update(pose, 0.0)
    model = tracker.controller
    for k, speed in enumerate([0.0, -1.0, math.nan, 0.2, None]):   # at most v / 5: commanded
        tracker.update([0.0, 0.0, 0.0], 0.1 * k, speed=speed)
        assert tracker.controller is model
    with pytest.raises(ValueError):  # λ = 0 with NU > rows: singular
        tracker.set_params(GpcTrackerParams(n1=18, nu=2, control_weight=0.0))
    assert tracker.params == GpcTrackerParams()  # the old params are kept


# --- Path tracker -----------------------------------------------------------------------

def bicycle(_t, state, v, u, tau):
    """Bicycle with first-order steering (9.113): state (x, y, θ, γ)."""
    x, y, theta, gamma = state
    curvature = gamma if tau > 0.0 else u
    return [v * math.cos(theta), v * math.sin(theta), v * curvature,
            (u - gamma) / tau if tau > 0.0 else 0.0]


def drive(tracker, pose, duration, tau=0.0, substeps=10):
    """
    Close the loop for ``duration`` [s]: commands every T, the bicycle held in between.

    Returns rows (t, x, y, θ, γ) and the commands at the periods; ``progress`` lists the
    tracker's arc length s [m] at each.
    """
    params = tracker.params
    period = params.sample_time
    state = np.array([*pose, 0.0])
    rows, commands = [], []
    drive.progress = []
    for k in range(round(duration / period)):
        command = tracker.update(state[:3], k * period)
        rows.append((k * period, *state))
        commands.append(command)
        drive.progress.append(tracker.progress)
        if command.finished:
            break
        for i in range(substeps):
            state = rk4_step(bicycle, 0.0, state, period / substeps, command.linear,
                             command.extras['curvature'], tau)
    return np.array(rows), commands


@pytest.mark.parametrize(('v', 'tau', 'n2'), [(1.0, 0.0, 18), (3.4, 0.4, 18), (3.4, 0.4, 10)])
def test_converges_to_a_straight_line_from_a_1_m_offset(v, tau, n2):
    path = PolylinePath(straight_line([0.0, 0.0], [150.0, 0.0], spacing=1.0))
    params = GpcTrackerParams(linear_velocity=v, steering_time_constant=tau, n2=n2)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 1.0, 0.0], 20.0, tau)
    error = rows[:, 2]   # lateral error: the path is the x axis
    cross_track = np.array([c.cross_track for c in commands])
    np.testing.assert_allclose(cross_track, error, atol=1e-12)
    assert commands[0].extras['curvature'] < 0.0              # turns right, towards the path
    assert error.min() > -0.1                       # overshoot below 10 % of the offset
    late = rows[:, 0] > 15.0
    assert np.abs(error[late]).max() < 1e-3
    assert np.abs(rows[late, 3]).max() < 1e-3       # heading along the path
    assert np.abs([c.extras['curvature'] for c in commands[-20:]]).max() < 1e-3
    for c in commands:
        assert c.angular == pytest.approx(c.linear * c.extras['curvature'], rel=1e-12)


def arc_path(radius, start_straight, sweep, spacing=0.05):
    """Straight of ``start_straight`` [m] (may be 0) along +x from the origin, then a left arc."""
    straight = np.arange(0.0, start_straight, spacing)
    points = [np.column_stack((straight, np.zeros_like(straight)))]
    angles = np.linspace(-math.pi / 2, -math.pi / 2 + sweep, math.ceil(radius * sweep / spacing))
    points.append(np.column_stack((start_straight + radius * np.cos(angles),
                                   radius + radius * np.sin(angles))))
    return PolylinePath(np.vstack(points))


@pytest.mark.parametrize('tau', [0.0, 0.4])
def test_steering_settles_on_the_path_curvature_on_an_arc(tau):
    # Book §9.5 (NavLab, fig. 9.30): the steering command stays close to the path
    # curvature. On a circle of radius 5 m the lateral model is exact in the unrolled frame,
    # so γ → 1/R with no steady-state error (up to the polyline's chords).
    radius = 5.0
    path = arc_path(radius, 0.0, 4.0 * math.pi, spacing=0.03)
    params = GpcTrackerParams(linear_velocity=3.4, steering_time_constant=tau)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 0.5, 0.0], 15.0, tau)
    late = rows[:, 0] > 10.0
    curvature = np.array([c.extras['curvature'] for c in commands])[late]
    cross_track = np.array([c.cross_track for c in commands])[late]
    np.testing.assert_allclose(curvature, 1.0 / radius, rtol=0.01)
    assert np.abs(cross_track).max() < 5e-3
    # Independently of the tracker's own errors: distance of the robot to the circle.
    distance = np.hypot(rows[late, 1], rows[late, 2] - radius) - radius
    assert np.abs(distance).max() < 5e-3


def test_reference_on_an_arc_is_the_unrolled_circle():
    # On the circle, heading along it: Y(σ) = ∫ σ'/R dσ' = σ² / (2 R) at σ = v T j.
    radius = 4.0
    # The polyline's first chord is turned by half its angle, spacing / (2 R), from the
    # circle's tangent: an error up to σ spacing / (2 R) < 3e-4 m here.
    path = arc_path(radius, 0.0, math.pi, spacing=0.001)
    params = GpcTrackerParams(linear_velocity=2.0, n2=10)
    command = GpcPathTracker(path, params).update([0.0, 0.0, 0.0], 0.0)
    sigma = 2.0 * 0.1 * np.arange(1, 11)
    reference = command.extras['reference']
    np.testing.assert_allclose(reference, sigma ** 2 / (2.0 * radius), atol=3e-4)
    assert reference.shape == command.extras['prediction'].shape == (10,)


def test_navlab_horizon_effect():
    # Book §9.5, fig. 9.31 (NavLab: τ = 0.4 s, v = 3.4 m/s, NU = 1): a longer horizon
    # anticipates a curve (turns earlier, cuts the corner), a shorter one reacts late.
    # Straight of 20 m, then a left arc of radius 5 m (near the vehicle's limit).
    path = arc_path(5.0, 20.0, math.pi, spacing=0.1)
    starts, cuts = [], []
    for n2 in [10, 18, 25]:
        params = GpcTrackerParams(linear_velocity=3.4, steering_time_constant=0.4, n2=n2)
        rows, commands = drive(GpcPathTracker(path, params), [0.0, 0.0, 0.0], 9.0, 0.4)
        s = np.array(drive.progress)
        curvature = np.array([c.extras['curvature'] for c in commands])
        starts.append(s[np.argmax(curvature > 0.02)])  # 10 % of the arc's curvature
        cuts.append(max(c.cross_track for c in commands))  # > 0: inside the left turn
    assert starts[0] > starts[1] > starts[2]
    assert starts[0] < 20.0                                # even N = 10 previews the arc
    assert 20.0 - starts[2] > 2.0 * (20.0 - starts[0])     # N = 25 turns much earlier
    assert cuts[0] < cuts[1] < cuts[2]


def test_model_is_rebuilt_when_the_speed_changes():
    path = PolylinePath([[0.0, 0.0], [50.0, 0.0]])
    tracker = GpcPathTracker(path, GpcTrackerParams(steering_time_constant=0.4))
    first = tracker.controller
    tracker.update([0.0, 0.2, 0.0], 0.0)
    assert tracker.controller is first
    tracker.update([0.1, 0.2, 0.0], 0.1, speed=2.0)
    assert tracker.controller is not first
    np.testing.assert_allclose(tracker.controller.b, lateral_carima_model(2.0, 0.1, 0.4)[1])
    # With a tolerance, small speed changes keep the model.
    tracker.set_params(GpcTrackerParams(steering_time_constant=0.4,
                                        model_speed_tolerance=0.05))
    kept = tracker.controller
    tracker.update([0.2, 0.2, 0.0], 0.2, speed=1.04)
    assert tracker.controller is kept
    tracker.update([0.3, 0.2, 0.0], 0.3, speed=1.1)
    assert tracker.controller is not kept


def test_softening_and_curvature_limit_in_the_tracker():
    path = PolylinePath(straight_line([0.0, 0.0], [60.0, 0.0], spacing=1.0))
    first = [GpcPathTracker(path, GpcTrackerParams(softening=alpha)).update(
        [0.0, 1.0, 0.0], 0.0).extras['curvature'] for alpha in [0.0, 0.5, 0.9]]
    assert first[0] < first[1] < first[2] < 0.0
    params = GpcTrackerParams(max_curvature=0.2)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 1.0, 0.0], 30.0)
    curvature = np.array([c.extras['curvature'] for c in commands])
    assert np.abs(curvature).max() == pytest.approx(0.2)  # the limit is reached, not passed
    assert abs(rows[-1, 2]) < 1e-3                         # and the path is still reached


def test_finishes_at_the_end_and_stays_finished_until_reset():
    path = PolylinePath([[0.0, 0.0], [3.0, 0.0]])
    tracker = GpcPathTracker(path, GpcTrackerParams())
    rows, commands = drive(tracker, [0.0, 0.0, 0.0], 10.0)
    assert commands[-1].finished and not commands[0].finished
    assert (commands[-1].linear, commands[-1].angular,
            commands[-1].extras['curvature']) == (0, 0, 0)
    assert rows[-1, 1] == pytest.approx(3.0, abs=0.1)
    assert tracker.update([1.0, 0.3, 0.0], 20.0).finished
    tracker.reset()
    assert tracker.progress == 0.0
    assert not tracker.update([0.0, 0.0, 0.0], 20.0).finished


def test_command_is_immutable_and_defaults_follow_navlab():
    params = GpcTrackerParams()
    assert (params.n1, params.n2, params.nu) == (1, 18, 1)
    assert dataclasses.replace(params, n2=25).n2 == 25
    command = GpcPathTracker(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), params).update(
        [0.0, 0.0, 0.0], 0.0)
    assert isinstance(command, TrackerOutput)
    with pytest.raises(ValueError):
        command.extras['reference'][0] = 1.0
    with pytest.raises(ValueError):
        command.extras['prediction'][0] = 1.0
    with pytest.raises(AttributeError):
        command.linear = 2.0  # type: ignore[misc]


def test_holds_its_command_between_periods():
    # T = 0.1 s: the updates at 0.03 and 0.06 s hold the command of 0 s and report their own
    # pose's errors; the law runs again at 0.1 s (within 1 ns) with the period's history.
    path = PolylinePath(straight_line([0.0, 0.0], [20.0, 0.0]))
    held = GpcPathTracker(path, GpcTrackerParams())
    every = GpcPathTracker(path, GpcTrackerParams())
    first = held.update([0.0, 0.5, 0.0], 0.0)
    assert every.update([0.0, 0.5, 0.0], 0.0)[:2] == first[:2]
    for t, y in ((0.03, 0.45), (0.06, 0.42)):
        out = held.update([0.3 * t, y, 0.0], t)
        assert out[:2] == first[:2] and out.extras is first.extras
        assert out.cross_track == pytest.approx(y)
        np.testing.assert_allclose(out.target_point, [0.3 * t, 0.0])
    fresh = held.update([0.1, 0.4, 0.0], 0.1 - 1e-10)
    assert fresh.angular != first.angular
    assert fresh.angular == every.update([0.1, 0.4, 0.0], 0.1).angular
    held.reset()
    assert held.update([0.0, 0.5, 0.0], 0.0).angular == first.angular
