"""
Tests of robotica_ctrl.mobile.pure_pursuit: the book's pure-pursuit tracker (§9.3.1).

Closed-loop tests integrate the unicycle x' = v cos θ, y' = v sin θ, θ' = ω written below,
independent of the code under test; the lateral error on the straight path of Ejemplo 9.1
(seed catalogue §7.10) is the robot's own y coordinate.
"""

import dataclasses
import math

import numpy as np
import pytest

from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import rounded_rectangle, straight_line
from robotica_ctrl.mobile.pure_pursuit import curvature_to_point, PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.tracker_base import TrackerOutput


def simulate(tracker, pose, duration, dt):
    """
    Drive a unicycle with the tracker's commands for ``duration`` [s] in steps of dt [s].

    Each step applies (v, ω) with the heading taken at mid-step; the run stops early once
    the tracker reports finished. Returns the times (K,), the poses (K, 3) at which the
    commands were computed, and the commands.
    """
    pose = np.asarray(pose, dtype=float)
    times, poses, commands = [], [], []
    for k in range(round(duration / dt)):
        command = tracker.update(pose, k * dt)
        times.append(k * dt)
        poses.append(pose)
        commands.append(command)
        if command.finished:
            break
        heading = pose[2] + 0.5 * dt * command.angular
        pose = pose + dt * np.array([command.linear * math.cos(heading),
                                     command.linear * math.sin(heading), command.angular])
    return np.array(times), np.array(poses), commands


def circle_path(radius, direction, n=720):
    """Return a closed circle through (radius, 0), counter-clockwise for direction = +1."""
    angles = direction * np.linspace(0.0, 2.0 * math.pi, n + 1)
    points = radius * np.column_stack((np.cos(angles), np.sin(angles)))
    points[-1] = points[0]
    return PolylinePath(points)


# curvature_to_point: (goal point in base_link, γ = 2 y / (x² + y²) worked by hand).
CURVATURE_TABLE = [
    ((1.0, 1.0), 1.0),
    ((1.0, -1.0), -1.0),
    ((2.0, 0.0), 0.0),
    ((0.0, 1.0), 2.0),     # beside: a half circle of radius 0.5
    ((3.0, 4.0), 0.32),    # 8 / 25
    ((0.5, -0.5), -2.0),
    ((-1.0, 1.0), 1.0),    # behind: the law itself does not care
    ((-4.0, 0.0), 0.0),
]


@pytest.mark.parametrize(('point', 'gamma'), CURVATURE_TABLE)
def test_curvature_to_point_table(point, gamma):
    result = curvature_to_point(point)
    assert result == pytest.approx(gamma, abs=1e-15)
    if gamma == 0.0:
        assert point[1] == 0.0  # straight ahead or behind: the x axis itself
    else:
        # The circle of curvature γ tangent to the x axis at the origin (centre (0, 1/γ))
        # passes through the goal point.
        assert math.dist(point, (0.0, 1.0 / result)) == pytest.approx(abs(1.0 / result))


@pytest.mark.parametrize('point', [(0.0, 0.0), (math.nan, 1.0), (1.0, math.inf), (1.0,),
                                   (1.0, 2.0, 3.0)])
def test_curvature_to_point_rejects_bad_points(point):
    with pytest.raises(ValueError):
        curvature_to_point(point)


def test_default_params():
    params = PurePursuitParams()
    assert dataclasses.astuple(params) == (0.5, 0.5, 1.5, 0.05, 0.5, 0.05, 2.0)


@pytest.mark.parametrize('bad', [0.0, -1.0, math.nan, math.inf])
@pytest.mark.parametrize('name', [f.name for f in dataclasses.fields(PurePursuitParams)])
def test_params_reject_non_positive_or_non_finite(name, bad):
    with pytest.raises(ValueError, match=name):
        PurePursuitParams(**{name: bad})


def test_params_reject_min_approach_above_desired_velocity():
    with pytest.raises(ValueError):
        PurePursuitParams(desired_linear_velocity=0.3, min_approach_velocity=0.4)
    assert PurePursuitParams(desired_linear_velocity=0.3, min_approach_velocity=0.3)


def straight_tracker(**params):
    return PurePursuit(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), PurePursuitParams(**params))


def test_on_a_straight_path_it_drives_straight():
    command = straight_tracker().update([1.0, 0.0, 0.0], 0.0)
    assert (command.linear, command.angular, command.extras['curvature']) == (0.5, 0.0, 0.0)
    np.testing.assert_array_equal(command.target_point, [1.5, 0.0])
    assert not command.finished


def test_lateral_offset_steers_back_by_book_9_5():
    # Robot 0.2 m left of the path: goal (L, -0.2) in base_link, γ = 2 (-0.2) / (L² + 0.2²).
    command = straight_tracker(lookahead_distance=1.0).update([1.0, 0.2, 0.0], 0.0)
    assert command.cross_track == pytest.approx(0.2)
    assert command.extras['curvature'] == pytest.approx(-0.4 / 1.04)
    assert command.angular == pytest.approx(0.5 * -0.4 / 1.04)


def test_goal_point_is_an_arc_length_ahead_of_the_closest_point():
    # L-shaped path: from s = 3.5 the goal is 1 m further along the path, round the corner.
    path = PolylinePath([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]])
    tracker = PurePursuit(path, PurePursuitParams(lookahead_distance=1.0))
    for x in np.arange(0.0, 3.6, 0.5):  # progress along, within the search window
        command = tracker.update([x, 0.1, 0.0], 0.0)
    np.testing.assert_allclose(command.target_point, [4.0, 0.5])


@pytest.mark.parametrize('radius', [0.5, 2.0, 10.0])
@pytest.mark.parametrize('direction', [1.0, -1.0])
def test_curvature_is_exact_on_a_circle(radius, direction):
    # Pure pursuit is exact on circles: with the robot on the circle, heading along its
    # tangent, and the goal point on the circle too (a vertex, 25 chords ahead), the
    # commanded curvature is the circle's, ±1/r.
    path = circle_path(radius, direction)
    chord = 2.0 * radius * math.sin(math.pi / 720)
    params = PurePursuitParams(lookahead_distance=25 * chord, max_angular_velocity=100.0)
    command = PurePursuit(path, params).update([radius, 0.0, direction * 0.5 * math.pi], 0.0)
    assert np.linalg.norm(command.target_point) == pytest.approx(radius, rel=1e-12)
    assert command.extras['curvature'] == pytest.approx(direction / radius, rel=1e-9)
    assert command.angular == pytest.approx(command.linear * direction / radius, rel=1e-9)


def test_angular_velocity_limit_keeps_the_curvature():
    # Circle of radius 0.2 m: γ = 5 1/m; 0.5 m/s would need 2.5 rad/s > 1.5 rad/s, so
    # v = 1.5 / 5 = 0.3 m/s.
    path = circle_path(0.2, 1.0)
    chord = 2.0 * 0.2 * math.sin(math.pi / 720)
    params = PurePursuitParams(lookahead_distance=10 * chord, search_window=0.5)
    command = PurePursuit(path, params).update([0.2, 0.0, 0.5 * math.pi], 0.0)
    assert command.extras['curvature'] == pytest.approx(5.0, rel=1e-9)
    assert command.linear == pytest.approx(0.3, rel=1e-9)
    assert command.angular == pytest.approx(1.5, rel=1e-12)


@pytest.mark.parametrize(('x', 'y', 'expected_v'), [
    (4.0, 0.0, 0.5),     # 1 m to go: full speed
    (4.75, 0.0, 0.25),   # 0.25 m to go: 0.5 m/s * 0.25 m / 0.5 m
    (4.9, 0.0, 0.1),
    (4.93, 0.0, 0.07),
    (4.97, 0.1, 0.05),   # 0.03 m to go: 0.03 m/s would be below min_approach_velocity
])
def test_approach_slows_down_linearly(x, y, expected_v):
    tracker = straight_tracker()
    for xi in np.arange(0.0, x, 1.0):
        tracker.update([xi, 0.0, 0.0], 0.0)
    command = tracker.update([x, y, 0.0], 0.0)
    assert command.linear == pytest.approx(expected_v)
    np.testing.assert_array_equal(command.target_point, [min(x + 0.5, 5.0), 0.0])


def test_finishes_at_the_end_and_stays_finished_until_reset():
    tracker = straight_tracker()
    for x in np.arange(0.0, 5.0, 1.0):
        tracker.update([x, 0.0, 0.0], 0.0)
    # Within tolerance along the path but 0.1 m beside its end: not finished yet.
    command = tracker.update([4.97, 0.1, 0.0], 0.0)
    assert not command.finished and command.linear == pytest.approx(0.05)
    command = tracker.update([4.98, 0.01, 0.0], 0.0)
    assert command.finished
    assert (command.linear, command.angular, command.extras['curvature']) == (0.0, 0.0, 0.0)
    assert tracker.update([4.0, 0.5, 1.0], 0.0).finished
    tracker.reset()
    assert tracker.progress == 0.0
    command = tracker.update([0.0, 0.0, 0.0], 0.0)
    assert not command.finished and command.linear == 0.5


def test_progress_never_falls_back_more_than_the_window():
    tracker = PurePursuit(PolylinePath(straight_line([0.0, 0.0], [10.0, 0.0])),
                          PurePursuitParams(search_window=2.0))
    for x in np.arange(0.0, 8.01, 0.5):
        tracker.update([x, 0.0, 0.0], 0.0)
    assert tracker.progress == pytest.approx(8.0)
    command = tracker.update([0.0, 0.0, 0.0], 0.0)  # teleported back to the start
    np.testing.assert_allclose(command.target_point, [6.5, 0.0])  # from s = 6 m
    assert tracker.progress == pytest.approx(6.0)


def test_set_params_changes_the_lookahead_and_keeps_progress():
    tracker = straight_tracker()
    tracker.update([1.0, 0.0, 0.0], 0.0)
    tracker.set_params(PurePursuitParams(lookahead_distance=2.0))
    assert tracker.params.lookahead_distance == 2.0
    assert tracker.progress == pytest.approx(1.0)
    np.testing.assert_array_equal(tracker.update([1.0, 0.0, 0.0], 0.0).target_point, [3.0, 0.0])


@pytest.mark.parametrize('pose', [[0.0, 0.0, math.nan], [math.inf, 0.0, 0.0], [0.0, 0.0],
                                  [0.0, 0.0, 0.0, 0.0]])
def test_bad_poses_are_rejected(pose):
    with pytest.raises(ValueError):
        straight_tracker().update(pose, 0.0)


def test_command_is_immutable():
    command = straight_tracker().update([0.0, 0.0, 0.0], 0.0)
    assert isinstance(command, TrackerOutput)
    with pytest.raises(ValueError):
        command.target_point[0] = 1.0
    with pytest.raises(AttributeError):
        command.linear = 1.0  # type: ignore[misc]


@pytest.mark.parametrize('side', [1.0, -1.0])
def test_reversing_safeguard_when_facing_backwards(side):
    # Robot at (1, 0.1 side) facing -x. The goal (1.5, 0) is behind it: in base_link
    # x_b = -0.5, y_b = 0.1 side, at D = sqrt(0.26) m. Plain (9.5) would give
    # 2 y_b / D² = ±0.77 1/m; the safeguard turns harder, 2 / D = 3.92 1/m, to the goal's side.
    command = straight_tracker().update([1.0, 0.1 * side, math.pi], 0.0)
    distance = math.sqrt(0.5 ** 2 + 0.1 ** 2)
    assert command.extras['curvature'] == pytest.approx(side * 2.0 / distance)
    assert abs(command.extras['curvature']) > abs(2.0 * 0.1 / distance ** 2)
    assert command.angular == pytest.approx(side * 1.5)  # limited, curvature kept
    # Facing backwards right on the path, the goal is straight behind: turn with 2 / L.
    command = straight_tracker().update([1.0, 0.0, math.pi], 0.0)
    assert abs(command.extras['curvature']) == pytest.approx(2.0 / 0.5)


def test_reversing_robot_turns_round_and_follows_the_path():
    path = PolylinePath(straight_line([0.0, 0.0], [6.0, 0.0]))
    tracker = PurePursuit(path, PurePursuitParams())
    times, poses, commands = simulate(tracker, [1.0, 0.1, math.pi], duration=30.0, dt=0.005)
    assert commands[0].angular > 0.0  # turns left, towards the path
    assert commands[-1].finished
    np.testing.assert_allclose(poses[-1, :2], [6.0, 0.0], atol=0.05)
    assert math.cos(poses[-1, 2]) == pytest.approx(1.0, abs=1e-6)  # heading +x at the end
    # A U-turn of radius about D / 2 = 0.25 m (γ = 2 / D) keeps it within 0.6 m of the path,
    # and once turned round it converges back onto the path.
    assert np.abs(poses[:, 1]).max() < 0.6
    assert np.abs(poses[poses[:, 0] > 4.0, 1]).max() < 0.01


def significant_zero_crossings(error, threshold=1e-4):
    """Count sign changes of ``error`` [m], ignoring samples within ±threshold of zero."""
    signs = np.sign(error[np.abs(error) >= threshold])
    return int(np.count_nonzero(signs[1:] != signs[:-1]))


def settling_time(times, error, band=0.05):
    """Return the time [s] after which |error| stays below ``band`` [m]."""
    outside = np.flatnonzero(np.abs(error) >= band)
    return times[outside[-1] + 1]


def linearised_settling_time(lookahead, v, e0=0.5, band=0.05):
    """
    Settling time [s] of the linearised pure pursuit on a straight path (derived here).

    With γ = 2 y_b / D² linearised about the path, e' = v θ, θ' = -2 v (e + L θ) / L², so
    e'' + (2 v / L) e' + (2 v² / L²) e = 0 (ζ = 1/√2): e(t) = e0 e^{-σt} (cos σt + sin σt)
    with σ = v / L, for e(0) = e0 and e'(0) = 0.
    """
    t = np.linspace(0.0, 20.0 * lookahead / v, 200001)
    sigma = v / lookahead
    error = e0 * np.exp(-sigma * t) * (np.cos(sigma * t) + np.sin(sigma * t))
    return settling_time(t, error, band)


def test_ejemplo_9_1():
    # Ejemplo 9.1 (seed catalogue §7.10, book fig. 9.5): v = 1 m/s, straight path, start
    # 0.5 m beside it with the path's heading, 10 s, several L. Small L (high gain 2/L²)
    # oscillates more; large L converges more slowly.
    path = PolylinePath(straight_line([0.0, 0.0], [20.0, 0.0]))
    lookaheads = [0.5, 1.0, 2.0, 4.0]
    crossings, settling = [], []
    for lookahead in lookaheads:
        params = PurePursuitParams(lookahead_distance=lookahead, desired_linear_velocity=1.0,
                                   min_approach_velocity=0.05, max_angular_velocity=100.0)
        times, poses, commands = simulate(PurePursuit(path, params), [0.0, 0.5, 0.0],
                                          duration=10.0, dt=0.002)
        assert max(abs(c.angular) for c in commands) < 100.0  # never saturated
        error = poses[:, 1]  # lateral error: the path is the x axis
        assert abs(error[-1]) < 0.05  # every L has converged by 10 s
        crossings.append(significant_zero_crossings(error))
        settling.append(settling_time(times, error))
    assert crossings == sorted(crossings, reverse=True)  # never more as L grows
    assert crossings[0] > crossings[-1]
    assert settling == sorted(settling) and len(set(settling)) == len(settling)
    # For offsets small against L the linearised law predicts the settling time.
    for lookahead, t_settle in zip(lookaheads[2:], settling[2:]):
        assert t_settle == pytest.approx(linearised_settling_time(lookahead, 1.0), rel=0.05)


def test_follows_a_rounded_rectangle_and_finishes_at_its_end():
    path = PolylinePath(rounded_rectangle(4.0, 3.0, 1.0))
    params = PurePursuitParams()
    times, poses, commands = simulate(PurePursuit(path, params), [0.0, 0.0, 0.0],
                                      duration=60.0, dt=0.005)
    # The path is closed: at the start, its end is at the same point, yet a whole lap is
    # driven before finishing.
    assert not commands[0].finished
    assert commands[-1].finished
    assert times[-1] >= path.length / params.desired_linear_velocity
    assert math.hypot(*poses[-1, :2]) <= params.goal_tolerance
    # Small tracking error all the way round (independently: distance to the sampled path).
    dense = rounded_rectangle(4.0, 3.0, 1.0, spacing=0.005)
    sampled = poses[::10, np.newaxis, :2]
    gaps = np.min(np.linalg.norm(sampled - dense[np.newaxis], axis=2), axis=1)
    assert gaps.max() < 0.05
    assert max(abs(c.cross_track) for c in commands) < 0.05


def test_speed_limit_is_respected_in_closed_loop():
    # Corners of radius 1 m at 0.5 m/s need 0.5 rad/s; the limit 0.3 rad/s slows the robot
    # to 0.3 m/s there instead of widening the turn.
    path = PolylinePath(rounded_rectangle(4.0, 3.0, 1.0))
    params = PurePursuitParams(max_angular_velocity=0.3)
    times, poses, commands = simulate(PurePursuit(path, params), [0.0, 0.0, 0.0],
                                      duration=80.0, dt=0.005)
    linear = np.array([c.linear for c in commands])
    angular = np.array([c.angular for c in commands])
    curvature = np.array([c.extras['curvature'] for c in commands])
    assert commands[-1].finished
    assert np.all(np.abs(angular) <= 0.3 * (1.0 + 1e-12))
    assert np.all((linear >= 0.0) & (linear <= params.desired_linear_velocity))
    np.testing.assert_allclose(angular, linear * curvature, rtol=1e-12, atol=1e-15)
    assert np.abs(angular).max() == pytest.approx(0.3)  # the limit was reached ...
    in_corners = curvature > 0.9
    assert linear[in_corners].max() < 0.35  # ... and slowed the robot in the corners
    assert max(abs(c.cross_track) for c in commands) < 0.05  # same path
