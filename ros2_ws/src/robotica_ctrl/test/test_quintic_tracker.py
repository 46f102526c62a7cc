"""
Tests of robotica_ctrl.mobile.quintic_tracker: the quintic geometric tracker (§9.3.2).

The coefficients are checked against the six boundary conditions (9.18)-(9.23) evaluated with
``numpy.polyval``/``numpy.polyder`` and against a numeric solve of the 6×6 linear system (the
test the seed catalogue §7.3 suggests); the printed a5 of (9.40) is shown to violate a
boundary condition (catalogue Part 17). Closed-loop tests integrate the unicycle
x' = v cos θ, y' = v sin θ, θ' = ω written below, independent of the code under test.
"""

import dataclasses
import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.quintic_tracker import (
    path_curvature, quintic_coefficients, quintic_curvature, QuinticTracker, QuinticTrackerParams)
from robotica_ctrl.mobile.tracker_base import TrackerOutput


def boundary_values(c, x_f):
    """Return (y, y', y'') at 0 and at x_f of y = Σ c_i x^i, with numpy.polyval/polyder."""
    p = np.asarray(c)[::-1]  # polyval wants the highest power first
    d1, d2 = np.polyder(p), np.polyder(p, 2)
    return ([np.polyval(p, 0.0), np.polyval(d1, 0.0), np.polyval(d2, 0.0)],
            [np.polyval(p, x_f), np.polyval(d1, x_f), np.polyval(d2, x_f)])


def solve_system(x_f, y_f, phi_f, g_in, g_f):
    """Solve the 6×6 linear system of the boundary conditions for c0..c5 (REP-103 form)."""
    rows, rhs = [], []
    for x, value, slope, second in ((0.0, 0.0, 0.0, g_in),
                                    (x_f, y_f, math.tan(phi_f), g_f / math.cos(phi_f) ** 3)):
        rows.append([x**i for i in range(6)])
        rows.append([i * x ** (i - 1) if i >= 1 else 0.0 for i in range(6)])
        rows.append([i * (i - 1) * x ** (i - 2) if i >= 2 else 0.0 for i in range(6)])
        rhs += [value, slope, second]
    return np.linalg.solve(np.array(rows), np.array(rhs))


goals = st.tuples(
    st.floats(0.3, 5.0), st.floats(-2.0, 2.0), st.floats(-1.2, 1.2),
    st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))


@settings(max_examples=60, deadline=None)
@given(goals)
def test_coefficients_meet_the_six_boundary_conditions(goal):
    x_f, y_f, phi_f, g_in, g_f = goal
    c = quintic_coefficients(x_f, y_f, phi_f, g_in, g_f)
    start, end = boundary_values(c, x_f)
    np.testing.assert_allclose(start, [0.0, 0.0, g_in], atol=1e-9)
    np.testing.assert_allclose(end, [y_f, math.tan(phi_f), g_f / math.cos(phi_f) ** 3],
                               rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(c, solve_system(*goal), rtol=1e-8, atol=1e-8)


def test_straight_ahead_gives_the_zero_polynomial():
    np.testing.assert_array_equal(quintic_coefficients(3.0, 0.0, 0.0, 0.0, 0.0), np.zeros(6))


def test_printed_a5_violates_a_boundary_condition():
    # Book symbols: x_f lateral (right), y_f forward, k = -γ_f / cos³ φ_f.
    y_f, x_f, phi_f, g_in, g_f = 2.0, -0.5, 0.3, 0.2, -0.1
    k = -g_f / math.cos(phi_f) ** 3
    t = math.tan(phi_f)
    numerator = 6.0 * y_f * t + 12.0 * x_f + (k + g_in) * y_f**2
    corrected, printed = numerator / (2.0 * y_f**5), numerator / (2.0 * y_f**3)
    c = quintic_coefficients(y_f, -x_f, phi_f, g_in, g_f)
    assert c[5] == pytest.approx(-corrected, rel=1e-12)
    misprinted = c.copy()
    misprinted[5] = -printed
    _, end = boundary_values(misprinted, y_f)
    assert abs(end[0] - (-x_f)) > 0.1  # the end position is missed


def test_quintic_curvature_of_a_circle_arc_and_a_cubic():
    # y = x²/2 has curvature 1 / (1 + x²)^{3/2}.
    c = [0.0, 0.0, 0.5, 0.0, 0.0, 0.0]
    for x in (0.0, 0.5, 2.0):
        assert quintic_curvature(c, x) == pytest.approx((1.0 + x * x) ** -1.5)
    # y = -x³: y' = -3x², y'' = -6x.
    assert quintic_curvature([0, 0, 0, -1.0, 0, 0], 1.0) == pytest.approx(-6.0 / 10.0**1.5)


def test_path_curvature_of_a_polyline_circle():
    radius = 2.0
    angles = np.linspace(0.0, math.pi, 361)
    left = PolylinePath(radius * np.column_stack((np.cos(angles), np.sin(angles))))
    right = PolylinePath(radius * np.column_stack((np.cos(angles), -np.sin(angles))))
    assert path_curvature(left, 3.0, 0.2) == pytest.approx(1.0 / radius, rel=2e-3)
    assert path_curvature(right, 3.0, 0.2) == pytest.approx(-1.0 / radius, rel=2e-3)
    line = PolylinePath([[0.0, 0.0], [4.0, 0.0]])
    assert path_curvature(line, 2.0, 0.5) == 0.0
    assert path_curvature(line, 4.0, 0.5) == 0.0  # clamped points at the end


@pytest.mark.parametrize('args', [
    (0.0, 1.0, 0.0), (-1.0, 1.0, 0.0), (1.0, math.nan, 0.0), (1.0, 0.0, math.pi / 2),
    (1.0, 0.0, -2.0), (math.inf, 0.0, 0.0)])
def test_coefficients_reject_bad_input(args):
    with pytest.raises(ValueError):
        quintic_coefficients(*args)


@pytest.mark.parametrize('field', [
    'lookahead_distance', 'desired_linear_velocity', 'max_angular_velocity', 'actuator_delay',
    'goal_tolerance', 'search_window', 'curvature_spacing'])
@pytest.mark.parametrize('value', [-1.0, math.nan, math.inf])
def test_params_reject_bad_values(field, value):
    with pytest.raises(ValueError, match=field):
        QuinticTrackerParams(**{field: value})


def test_params_reject_zero_and_are_frozen():
    for field in ('lookahead_distance', 'actuator_delay'):
        with pytest.raises(ValueError, match=field):
            QuinticTrackerParams(**{field: 0.0})
    with pytest.raises(dataclasses.FrozenInstanceError):
        QuinticTrackerParams().lookahead_distance = 2.0  # type: ignore[misc]


def test_update_rejects_bad_pose():
    tracker = QuinticTracker(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), QuinticTrackerParams())
    for pose in ([0.0, 0.0], [0.0, math.nan, 0.0]):
        with pytest.raises(ValueError):
            tracker.update(pose, 0.0)
    with pytest.raises(ValueError):
        tracker.update([0.0, 0.0, 0.0], 0.0, current_curvature=math.inf)


def test_one_update_by_hand():
    # Vehicle 0.5 m left of the x axis, aligned: goal (1, 0) is at forward 1, lateral -0.5,
    # heading 0, γ_f = 0, so y = -0.5 (10 x³ - 15 x⁴ + 6 x⁵) and γ(0) = 0 without delay.
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    params = QuinticTrackerParams(lookahead_distance=1.0, desired_linear_velocity=1.0,
                                  max_angular_velocity=10.0, actuator_delay=0.2)
    command = QuinticTracker(path, params).update([0.0, 0.5, 0.0], 0.0)
    assert isinstance(command, TrackerOutput)
    np.testing.assert_allclose(command.extras['coefficients'], [0, 0, 0, -5.0, 7.5, -3.0],
                               atol=1e-12)
    np.testing.assert_allclose(command.target_point, [1.0, 0.0])
    x = 0.2  # v τ
    d1 = -0.5 * (30 * x**2 - 60 * x**3 + 30 * x**4)
    d2 = -0.5 * (60 * x - 180 * x**2 + 120 * x**3)
    assert command.extras['curvature'] == pytest.approx(d2 / (1 + d1 * d1) ** 1.5)
    assert command.angular == pytest.approx(command.linear * command.extras['curvature'])
    assert command.cross_track == pytest.approx(0.5)
    assert not command.finished


def test_angular_velocity_limit_keeps_the_curvature():
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    params = QuinticTrackerParams(max_angular_velocity=0.1, actuator_delay=0.5)
    command = QuinticTracker(path, params).update([0.0, 0.8, 0.0], 0.0)
    assert abs(command.angular) == pytest.approx(0.1)
    assert command.angular == pytest.approx(command.linear * command.extras['curvature'])


def test_goal_behind_uses_the_pure_pursuit_fallback():
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    command = QuinticTracker(path, QuinticTrackerParams()).update([0.0, 0.0, math.pi], 0.0)
    assert command.extras['coefficients'] is None
    assert abs(command.extras['curvature']) == pytest.approx(2.0)  # 2 / L with L = 1


def simulate(tracker, pose, duration, dt, lag=None):
    """
    Drive a unicycle with the tracker's commands; optional first-order steering lag τ [s].

    With ``lag`` the applied curvature follows γ' = (γ_cmd - γ) / τ (book (9.9), K = 1) and
    is given back to the tracker as the measured curvature. Returns poses (K, 3).
    """
    pose = np.asarray(pose, dtype=float)
    gamma = 0.0
    poses = []
    for k in range(round(duration / dt)):
        command = tracker.update(pose, k * dt, current_curvature=gamma if lag else None)
        poses.append(pose)
        if command.finished:
            break
        if lag:
            gamma += dt * (command.extras['curvature'] - gamma) / lag
        else:
            gamma = command.extras['curvature']
        v = command.linear
        heading = pose[2] + 0.5 * dt * v * gamma
        pose = pose + dt * np.array([v * math.cos(heading), v * math.sin(heading), v * gamma])
    return np.array(poses)


@pytest.mark.parametrize('lag', [None, 0.3])
def test_closed_loop_converges_to_a_straight_line(lag):
    # Without lag τ is one control period ahead; with it, the lag plus one period.
    path = PolylinePath([[0.0, 0.0], [40.0, 0.0]])
    params = QuinticTrackerParams(lookahead_distance=1.5, desired_linear_velocity=1.0,
                                  max_angular_velocity=2.0, actuator_delay=(lag or 0.0) + 0.02)
    poses = simulate(QuinticTracker(path, params), [0.0, 1.0, 0.3], 20.0, 0.02, lag)
    late = poses[len(poses) // 2:]
    assert np.max(np.abs(late[:, 1])) < 0.01
    assert np.max(np.abs(late[:, 2])) < 0.01
    assert np.min(poses[:, 1]) > -0.2  # little overshoot


def test_closed_loop_follows_a_circle():
    radius = 3.0
    angles = np.linspace(0.0, 2.0 * math.pi, 721)
    points = radius * np.column_stack((np.cos(angles), np.sin(angles)))
    points[-1] = points[0]
    path = PolylinePath(points)
    params = QuinticTrackerParams(lookahead_distance=1.0, desired_linear_velocity=1.0,
                                  max_angular_velocity=2.0, search_window=1.5,
                                  actuator_delay=0.1)
    poses = simulate(QuinticTracker(path, params), [radius + 0.3, 0.0, math.pi / 2], 15.0,
                     0.02)
    radial = np.hypot(poses[:, 0], poses[:, 1]) - radius
    assert np.max(np.abs(radial[len(radial) // 2:])) < 0.01


def test_stops_at_the_end_of_the_path():
    path = PolylinePath([[0.0, 0.0], [3.0, 0.0]])
    params = QuinticTrackerParams(desired_linear_velocity=1.0, goal_tolerance=0.05)
    tracker = QuinticTracker(path, params)
    poses = simulate(tracker, [0.0, 0.2, 0.0], 10.0, 0.02)
    assert np.hypot(*(poses[-1, :2] - [3.0, 0.0])) <= 0.06
    command = tracker.update(poses[-1], 0.0)
    assert command.finished and command.linear == 0.0 and command.angular == 0.0
    tracker.reset()
    assert tracker.progress == 0.0
