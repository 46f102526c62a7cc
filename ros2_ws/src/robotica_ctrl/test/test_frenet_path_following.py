"""
Tests of robotica_ctrl.mobile.frenet_path_following: path following, book §9.4.3–§9.4.4.

References are independent of the code under test: the Frenet rates against the derivatives
of polar coordinates about a circle's centre, the linearised poles against the design
|v| b (-δ ± sqrt(δ² - 1)) of (9.97)-(9.98), the lateral error against the closed-form solution
of (9.97), the characteristic polynomial against numpy's polynomial of the book's closed-loop
matrix (9.112)-(9.114) and Routh's criterion against numpy's roots (seed catalogue §7.6, §7.7,
§7.10). Closed loops integrate the unicycle x' = v cos θ, y' = v sin θ, θ' = ω (and the bicycle
with first-order steering lag) written below with ``rk4_step``, the law evaluated at each stage.
"""

import itertools
import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_ctrl.mobile.frenet_path_following import (
    characteristic_polynomial, frenet_angular_velocity, frenet_error_rates, frenet_errors,
    FrenetErrors, FrenetParams, FrenetPathFollower, gains_from_damping, in_convergence_region,
    MIN_FRENET_SCALE, path_following_input, routh_stable, routh_table, steering_feedback,
    steering_state_matrices)
from robotica_ctrl.mobile.path import PolylinePath
from robotica_kin.angles import heading_from_book, wrap_to_pi
from robotica_kin.integrators import rk4_step

LAWS = ('linear', 'nonlinear')


def circle_path(radius, direction, n=720):
    """Return a closed n-gon circle about the origin through (radius, 0); direction > 0: CCW."""
    angles = direction * np.linspace(0.0, 2.0 * math.pi, n + 1)
    points = radius * np.column_stack((np.cos(angles), np.sin(angles)))
    points[-1] = points[0]
    return PolylinePath(points)


def run_unicycle(follower, pose, duration, dt):
    """
    Integrate the unicycle under the follower's command (evaluated at every RK4 stage).

    Returns the times (K,), poses (K, 3) and the commands at those poses.
    """
    def deriv(t, state):
        cmd = follower.update(state, t)
        return [cmd.linear * math.cos(state[2]), cmd.linear * math.sin(state[2]), cmd.angular]

    pose = np.asarray(pose, dtype=float)
    times, poses, commands = [], [], []
    steps = round(duration / dt)
    for k in range(steps + 1):
        times.append(k * dt)
        poses.append(pose)
        commands.append(follower.update(pose, k * dt))
        if k < steps:
            pose = rk4_step(deriv, k * dt, pose, dt)
    return np.array(times), np.array(poses), commands


# ---------------------------------------------------------------- error model (9.83)-(9.87)

def test_errors_straight_line_by_hand():
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    errors = frenet_errors([2.0, 1.0, 0.3], path.project([2.0, 1.0]))
    assert (errors.lateral_error, errors.path_curvature) == (1.0, 0.0)
    assert errors.heading_error == pytest.approx(0.3, abs=1e-15)
    # Right of the path, heading backwards: d < 0 and θ̃ wraps into (-π, π].
    errors = frenet_errors([5.0, -0.5, -3.0], path.project([5.0, -0.5]))
    assert errors.lateral_error == -0.5
    assert errors.heading_error == pytest.approx(-3.0, abs=1e-15)


def test_errors_oblique_line_by_hand():
    """Path along (3, 4)/5; the point (0, 5) lies 3 m to its left, (4, -3) 5 m to its right."""
    path = PolylinePath([[0.0, 0.0], [30.0, 40.0]])
    heading = math.atan2(4.0, 3.0)
    left = frenet_errors([0.0, 5.0, heading + 0.1], path.project([0.0, 5.0]))
    right = frenet_errors([4.0, -3.0, heading], path.project([4.0, -3.0]))
    assert left.lateral_error == pytest.approx(3.0, abs=1e-12)
    assert left.heading_error == pytest.approx(0.1, abs=1e-12)
    assert right.lateral_error == pytest.approx(-5.0, abs=1e-12)


def test_rates_straight_line_by_hand():
    v, w, heading = 1.5, 0.2, 0.3
    rates = frenet_error_rates(FrenetErrors(1.0, heading, 0.0), v, w)
    np.testing.assert_allclose(rates, [v * math.cos(heading), v * math.sin(heading), w],
                               atol=1e-15)


def test_rates_circle_by_hand():
    """
    Circle R = 2 m counter-clockwise, vehicle at (0, 1.5) heading π + 0.2, v = 1, ω = 0.

    By hand: d = 0.5, θ̃ = 0.2, c = 0.5, 1 - c d = 0.75; s' = cos 0.2 / 0.75,
    d' = sin 0.2, θ̃' = -0.5 s'.
    """
    path = circle_path(2.0, +1)
    follower = FrenetPathFollower(path, FrenetParams())
    projection = path.project([0.0, 1.5])
    errors = frenet_errors([0.0, 1.5, math.pi + 0.2], projection,
                           follower.path_curvature(projection.s))
    # A polyline of n = 720 chords: d within the sagitta R (1 - cos(π/n)) ~ 2e-5 m of the
    # circle's, the chord heading within π/n of the tangent's.
    assert errors.lateral_error == pytest.approx(0.5, abs=1e-4)
    assert errors.heading_error == pytest.approx(0.2, abs=math.pi / 720.0 + 1e-12)
    assert errors.path_curvature == pytest.approx(0.5, rel=1e-4)
    rates = frenet_error_rates([0.5, 0.2, 0.5], 1.0, 0.0)
    s_rate = math.cos(0.2) / 0.75
    np.testing.assert_allclose(rates, [s_rate, math.sin(0.2), -0.5 * s_rate], rtol=1e-14)


@settings(max_examples=40, deadline=None)
@given(radius=st.floats(0.5, 20.0), direction=st.sampled_from([-1.0, 1.0]),
       fraction=st.floats(-0.9, 0.9), angle=st.floats(-math.pi, math.pi),
       heading=st.floats(-3.0, 3.0), v=st.floats(-3.0, 3.0), w=st.floats(-2.0, 2.0))
def test_rates_circle_match_polar_derivatives(radius, direction, fraction, angle, heading, v,
                                              w):
    """
    On a circle about the origin the Frenet rates are derivatives of polar coordinates.

    With r = |p|, α the polar angle: s = ±R α, d = ±(R - r) (left is inside when turning
    left), θ_c = α ± π/2, so s' = ±R α', d' = ∓r', θ̃' = ω - α'.
    """
    r = radius * (1.0 - direction * fraction)  # d = fraction R
    x, y = r * math.cos(angle), r * math.sin(angle)
    theta = angle + direction * 0.5 * math.pi + heading
    xd, yd = v * math.cos(theta), v * math.sin(theta)
    r_rate = (x * xd + y * yd) / r
    angle_rate = (x * yd - y * xd) / (r * r)
    expected = [direction * radius * angle_rate, -direction * r_rate, w - angle_rate]
    rates = frenet_error_rates([fraction * radius, heading, direction / radius], v, w)
    np.testing.assert_allclose(rates, expected, rtol=1e-9, atol=1e-9)


def test_rates_reject_singular_frame():
    with pytest.raises(ValueError, match='centre of curvature'):
        frenet_error_rates([2.0, 0.0, 0.5], 1.0, 0.0)  # at the centre: 1 - c d = 0


# ---------------------------------------------------------------- path curvature of a polyline

@pytest.mark.parametrize('direction', [1.0, -1.0])
def test_curvature_of_sampled_circle(direction):
    follower = FrenetPathFollower(circle_path(3.0, direction), FrenetParams())
    length = follower.path.length
    for s in np.linspace(0.0, length, 37):  # includes both ends of the closed path
        assert follower.path_curvature(s) == pytest.approx(direction / 3.0, rel=1e-4)


def test_curvature_of_straight_and_corner():
    """Zero away from a right-angle corner; its integral over the path is the turn π/2."""
    follower = FrenetPathFollower(PolylinePath([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]]),
                                  FrenetParams(curvature_window=0.5))
    assert follower.path_curvature(1.0) == 0.0
    assert follower.path_curvature(7.0) == 0.0
    s = np.linspace(0.0, 8.0, 8001)
    c = np.array([follower.path_curvature(si) for si in s])
    assert np.max(c) == pytest.approx(math.pi / 2.0, rel=1e-9)  # turn / (2 w) at the vertex
    assert np.sum(0.5 * (c[1:] + c[:-1]) * np.diff(s)) == pytest.approx(math.pi / 2.0, rel=1e-4)
    assert FrenetPathFollower(PolylinePath([[0.0, 0.0], [1.0, 1.0]]),
                              FrenetParams()).path_curvature(0.5) == 0.0


# ---------------------------------------------------------------- laws (9.90)-(9.99)

def test_laws_by_hand():
    params = FrenetParams(k1=4.0, k2=3.0)
    assert path_following_input(0.5, 0.2, 2.0, params) == pytest.approx(-4.0 - 1.2)
    assert path_following_input(0.5, 0.2, -2.0, params) == pytest.approx(4.0 - 1.2)
    nonlinear = FrenetParams(law='nonlinear', k1=4.0, k2=3.0)
    assert path_following_input(0.5, 0.2, 2.0, nonlinear) == pytest.approx(
        -4.0 * math.sin(0.2) / 0.2 - 1.2)
    assert path_following_input(0.5, 0.0, 2.0, nonlinear) == pytest.approx(-4.0)
    # Feed-forward (9.90): ω = u + v c cos θ̃ / (1 - c d).
    omega = frenet_angular_velocity([0.5, 0.2, 0.4], 2.0, params)
    assert omega == pytest.approx(-5.2 + 2.0 * 0.4 * math.cos(0.2) / 0.8)
    # Near the centre of curvature the factor 1 - c d is held at MIN_FRENET_SCALE.
    omega = frenet_angular_velocity([2.4, 0.0, 0.5], 1.0, params)
    assert omega == pytest.approx(-4.0 * 2.4 + 0.5 / MIN_FRENET_SCALE)


@pytest.mark.parametrize('law', LAWS)
@pytest.mark.parametrize('c', [0.0, 0.3, -0.5])
@pytest.mark.parametrize('v', [0.5, 2.0, -1.0])
@pytest.mark.parametrize(('b', 'delta'), [(1.0, 0.5), (2.0, 0.7), (0.8, 1.6)])
def test_linearised_poles_match_design(law, c, v, b, delta):
    """Jacobian of (d', θ̃') at (0, 0) has the poles |v| b (-δ ± sqrt(δ² - 1)) of (9.97)-(9.98)."""
    k1, k2 = gains_from_damping(b, delta)
    params = FrenetParams(law=law, k1=k1, k2=k2)

    def closed_loop(x):
        errors = [x[0], x[1], c]
        return frenet_error_rates(errors, v, frenet_angular_velocity(errors, v, params))[1:]

    h = 1e-6
    jac = np.column_stack([(closed_loop(h * e) - closed_loop(-h * e)) / (2.0 * h)
                           for e in np.eye(2)])
    poles = np.sort_complex(np.linalg.eigvals(jac))
    root = np.sqrt(complex(delta * delta - 1.0))
    design = np.sort_complex(abs(v) * b * np.array([-delta + root, -delta - root]))
    np.testing.assert_allclose(poles, design, rtol=1e-6, atol=1e-8)


def test_gains_from_damping_and_region():
    assert gains_from_damping(1.0, 1.0) == (1.0, 2.0)
    assert in_convergence_region(10.0, 3.0, 1.0, 0.0)  # straight path: everywhere
    assert in_convergence_region(0.5, 0.0, 1.0, 1.9)  # 0.25 < 1/3.61
    assert not in_convergence_region(0.5, 0.0, 1.0, 2.1)  # 0.25 > 1/4.41
    assert not in_convergence_region(0.0, 1.0, 1.0, 1.0)  # θ̃²/k1 = 1


# ---------------------------------------------------------------- closed loop, unicycle

@pytest.mark.parametrize(('k1', 'k2'), [(1.0, 2.0), (4.0, 2.0)])
def test_ejemplo_9_5_straight_path(k1, k2):
    """
    Ejemplo 9.5 (catalogue §7.10): start at (0, 0), book heading φ0 = 0, v = 1 m/s.

    The straight path runs along the book's y axis 0.05 m to the left of the robot
    (REP-103 heading π/2); the printed figure gives no gains, so two pairs are used:
    (b, δ) = (1, 1) and (2, 0.5). The lateral error must follow the closed-form solution of
    (9.97) d_ρρ + k2 d_ρ + k1 d = 0, d(0) = -0.05, d_ρ(0) = 0, in the distance ρ = t.
    """
    d0 = -0.05
    path = PolylinePath([[-0.05, -1.0], [-0.05, 20.0]])
    params = FrenetParams(k1=k1, k2=k2, desired_linear_velocity=1.0, max_angular_velocity=10.0)
    follower = FrenetPathFollower(path, params)
    times, poses, commands = run_unicycle(follower, [0.0, 0.0, heading_from_book(0.0)], 10.0,
                                          0.04)
    d = np.array([cmd.cross_track for cmd in commands])
    assert d[0] == pytest.approx(d0)
    b, delta = math.sqrt(k1), k2 / (2.0 * math.sqrt(k1))
    rho = times
    if delta == 1.0:
        expected = d0 * (1.0 + b * rho) * np.exp(-b * rho)
    else:
        wd = b * math.sqrt(1.0 - delta * delta)
        expected = d0 * np.exp(-delta * b * rho) * (np.cos(wd * rho)
                                                    + delta * b / wd * np.sin(wd * rho))
    np.testing.assert_allclose(d, expected, atol=2e-5)  # small-angle error O(d0 θ̃²)
    assert abs(d[-1]) < 1e-4


@pytest.mark.parametrize('law', LAWS)
def test_straight_path_speed_independent_in_distance(law):
    """(9.97): d as a function of the distance travelled is the same at 0.5 and 2 m/s."""
    path = PolylinePath([[-5.0, 0.0], [40.0, 0.0]])
    results = []
    for v in (0.5, 2.0):
        params = FrenetParams(law=law, k1=1.0, k2=1.4, desired_linear_velocity=v,
                              max_angular_velocity=50.0)
        times, poses, commands = run_unicycle(FrenetPathFollower(path, params),
                                              [0.0, 1.0, 0.6], 12.0 / v, 0.04 / v)
        results.append((v * times, poses[:, 1]))
    (rho, d_slow), (rho_fast, d_fast) = results
    np.testing.assert_allclose(rho, rho_fast, atol=1e-12)
    np.testing.assert_allclose(d_slow, d_fast, atol=1e-6)
    assert abs(d_slow[-1]) < 0.02
    assert np.max(np.abs(d_slow)) > 1.0  # the large initial heading error first overshoots


def test_nonlinear_law_large_heading_error():
    """Straight path: (9.101) holds for any start; from θ̃ = 2.5 rad the vehicle turns back."""
    path = PolylinePath([[-20.0, 0.0], [60.0, 0.0]])
    params = FrenetParams(law='nonlinear', k1=1.0, k2=2.0, desired_linear_velocity=1.0,
                          max_angular_velocity=10.0, search_window=5.0)
    assert in_convergence_region(2.0, 2.5, params.k1, 0.0)
    _, poses, commands = run_unicycle(FrenetPathFollower(path, params), [0.0, 2.0, 2.5], 20.0,
                                      0.02)
    assert abs(commands[-1].cross_track) < 1e-3
    assert abs(commands[-1].heading_error) < 1e-3
    assert abs(poses[-1, 1]) < 1e-3


@pytest.mark.parametrize('law', LAWS)
@pytest.mark.parametrize('direction', [1.0, -1.0])
@pytest.mark.parametrize('offset', [0.5, -0.5])
def test_circle_from_offset(law, direction, offset):
    """Circle R = 3 m: d, θ̃ → 0 and γ → ±1/R from a 0.5 m offset (inside or outside)."""
    radius = 3.0
    path = circle_path(radius, direction)
    params = FrenetParams(law=law, k1=1.0, k2=2.0, desired_linear_velocity=1.0,
                          max_angular_velocity=10.0)
    assert in_convergence_region(offset, 0.0, params.k1, 1.0 / radius)
    start = [radius - direction * offset, 0.0, direction * 0.5 * math.pi]  # d = offset
    follower = FrenetPathFollower(path, params)
    assert follower.update(start, 0.0).cross_track == pytest.approx(offset, abs=1e-4)
    follower.reset()
    times, poses, commands = run_unicycle(follower, start, 22.0, 0.05)
    late = (times >= 12.0) & (times <= 17.0)  # s from about 12 m to 17 m of 18.85 m
    assert not any(cmd.finished for cmd, t in zip(commands, times) if t <= 17.0)
    chord = math.pi / 720.0  # a chord's heading is within π/n of the circle's tangent
    late_commands = [cmd for cmd, is_late in zip(commands, late) if is_late]
    for cmd in late_commands:
        assert abs(cmd.cross_track) < 1e-3
        assert abs(cmd.heading_error) < chord + 1e-3
        # The feedback k2 θ̃ follows the chord headings' steps of up to 2π/n.
        assert abs(cmd.extras['curvature'] - direction / radius) < params.k2 * 2.0 * chord
    curvatures = [cmd.extras['curvature'] for cmd in late_commands]
    assert np.mean(curvatures) == pytest.approx(direction / radius, rel=2e-3)
    radii = np.hypot(poses[late, 0], poses[late, 1])
    np.testing.assert_allclose(radii, radius, atol=1e-3)
    # Once round, the closed path is finished near its start, as in pure pursuit.
    assert commands[-1].finished
    assert math.dist(poses[-1, :2], path.points[0]) < 0.1


def test_angular_velocity_limit_keeps_curvature():
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    free = FrenetPathFollower(path, FrenetParams(max_angular_velocity=100.0))
    limited = FrenetPathFollower(path, FrenetParams(max_angular_velocity=0.2))
    pose = [1.0, 1.0, 0.5]
    a, b = free.update(pose, 0.0), limited.update(pose, 0.0)
    assert b.extras['curvature'] == pytest.approx(a.extras['curvature'], rel=1e-12)
    assert abs(b.angular) == pytest.approx(0.2)
    assert b.linear == pytest.approx(0.2 / abs(a.extras['curvature']))
    assert b.linear < a.linear == 0.5


def test_finishes_at_end_of_open_path():
    path = PolylinePath([[0.0, 0.0], [2.0, 0.0]])
    follower = FrenetPathFollower(path, FrenetParams())
    assert not follower.update([1.0, 0.1, 0.0], 0.0).finished
    cmd = follower.update([1.99, 0.0, 0.0], 0.1)
    assert cmd.finished and cmd.linear == cmd.angular == cmd.extras['curvature'] == 0.0
    assert follower.update([1.0, 0.0, 0.0], 0.2).finished  # latched
    follower.reset()
    assert follower.progress == 0.0
    assert not follower.update([1.0, 0.0, 0.0], 0.3).finished


def test_set_params():
    path = PolylinePath([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]])
    follower = FrenetPathFollower(path, FrenetParams(curvature_window=0.5))
    follower.set_params(FrenetParams(curvature_window=1.0))
    assert follower.path_curvature(2.0) == pytest.approx(math.pi / 4.0)
    # By the node's parameter names: 'variant' is the field law.
    follower.set_gains({'variant': 'nonlinear', 'curvature_window': 0.5})
    assert follower.params == FrenetParams(law='nonlinear', curvature_window=0.5)
    assert follower.path_curvature(2.0) == pytest.approx(math.pi / 2.0)
    with pytest.raises(ValueError, match='no gain'):
        follower.set_gains({'k4': 1.0})


# ---------------------------------------------------------------- bicycle + steering (§9.4.4)

def book_closed_loop(gains, v, tau):
    """Book (9.112)-(9.114) in its right-positive ξ: A - B K with K = (k1_book, k2, k3)."""
    a = np.array([[0.0, -v, 0.0], [0.0, 0.0, v], [0.0, 0.0, -1.0 / tau]])
    b = np.array([[0.0], [0.0], [1.0 / tau]])
    return a - b @ np.atleast_2d(gains)


@pytest.mark.parametrize(('gains', 'v', 'tau'), [
    ((1.0, 2.0, 0.5), 1.0, 0.5),      # Ejemplo 9.1 actuator: τ = 0.5 s, v = 1 m/s
    ((0.3, 1.2, 0.8), 3.4, 0.4),      # NavLab (§9.5): τ = 0.4 s, v = 3.4 m/s
    ((-2.0, 0.5, -1.5), -1.0, 0.2),
])
def test_characteristic_polynomial_matches_book_matrix(gains, v, tau):
    k1, k2, k3 = gains
    book = tau * np.poly(book_closed_loop([-k1, k2, k3], v, tau))
    ours = characteristic_polynomial(gains, v, None, tau)
    np.testing.assert_allclose(ours, book, atol=1e-12)
    # Printed (9.116) with the book's k1: τ s³ + (k3 + 1) s² + v k2 s - v² k1_book.
    np.testing.assert_allclose(ours, [tau, k3 + 1.0, v * k2, -v * v * (-k1)], atol=1e-12)
    a, b = steering_state_matrices(v, tau)
    np.testing.assert_allclose(tau * np.poly(a - np.outer(b, gains)), ours, atol=1e-12)


def test_characteristic_polynomial_with_wheelbase():
    """Steering-angle state: θ̃' = v α / l, so k1 and k2 enter divided by l."""
    l, v, tau, gains = 2.5, 2.0, 0.4, np.array([0.5, 1.0, 0.2])
    a = np.array([[0.0, v, 0.0], [0.0, 0.0, v / l], [0.0, 0.0, -1.0 / tau]])
    b = np.array([0.0, 0.0, 1.0 / tau])
    expected = tau * np.poly(a - np.outer(b, gains))
    np.testing.assert_allclose(characteristic_polynomial(gains, v, l, tau), expected,
                               atol=1e-12)
    np.testing.assert_allclose(steering_state_matrices(v, tau, l)[0], a, atol=1e-15)


def test_routh_agrees_with_roots_on_grid():
    """Stable by Routh ⇔ all roots of (9.116) in the open left half plane (numpy roots)."""
    k1s = (-1.0, -0.1, 0.2, 1.0, 5.0)
    k2s = (-1.0, 0.1, 0.5, 2.0, 6.0)
    k3s = (-1.5, -0.5, 0.0, 1.0, 4.0)
    cases = itertools.product(k1s, k2s, k3s, (-2.0, 0.5, 1.0, 3.4), (0.4, 0.5, 2.0),
                              (None, 2.5))
    counts = {True: 0, False: 0}
    for k1, k2, k3, v, tau, l in cases:
        gains = (k1, k2, k3)
        roots = np.roots(characteristic_polynomial(gains, v, l, tau))
        margin = float(np.max(roots.real))
        if abs(margin) < 1e-9:
            continue  # marginal: on the imaginary axis
        stable = routh_stable(gains, v, l, tau)
        assert stable == (margin < 0.0), (gains, v, tau, l, roots)
        counts[stable] += 1
        if l is None and v > 0.0:
            # The book's printed conditions (9.117), its k1 being -k1 here.
            k1_book = -k1
            book = ((k3 + 1.0) / tau > 0.0 and v * k2 / tau > 0.0 and k1_book / tau < 0.0
                    and (1.0 + k3) * k2 / (v * tau) > -k1_book)
            assert book == stable
    assert min(counts.values()) > 100


def test_routh_table_by_hand():
    """τ = 0.5, v = 2, K = (1, 2, 0.5): 0.5 s³ + 1.5 s² + 4 s + 4; s¹ row (1.5·4 - 0.5·4)/1.5."""
    table = routh_table([1.0, 2.0, 0.5], 2.0, None, 0.5)
    np.testing.assert_allclose(table, [[0.5, 4.0], [1.5, 4.0], [8.0 / 3.0, 0.0], [4.0, 0.0]])
    degenerate = routh_table([1.0, 2.0, -1.0], 2.0, None, 0.5)  # a2 = 0
    assert math.isnan(degenerate[2, 0])
    assert not routh_stable([1.0, 2.0, -1.0], 2.0, None, 0.5)


def place_poles(poles, v, tau):
    """Gains giving τ Π(s - p) = τ s³ + (1 + k3) s² + v k2 s + v² k1 (coefficient matching)."""
    a3, a2, a1, a0 = tau * np.real(np.poly(poles))
    return np.array([a0 / (v * v), a1 / v, a2 - 1.0])


def run_bicycle(gains, v, tau, state, duration, dt):
    """Nonlinear bicycle (x, y, θ, γ), steering lag γ' = (u - γ)/τ, path = the x axis."""
    def deriv(_t, s):
        u = steering_feedback(s[1], wrap_to_pi(s[2]), s[3], gains)
        return [v * math.cos(s[2]), v * math.sin(s[2]), v * s[3], (u - s[3]) / tau]

    states = [np.asarray(state, dtype=float)]
    for k in range(round(duration / dt)):
        states.append(rk4_step(deriv, k * dt, states[-1], dt))
    return np.array(states)


def test_bicycle_closed_loop_converges_at_designed_rate():
    """
    Decay at the designed rate with the NavLab numbers (§9.5): v = 3.4 m/s, τ = 0.4 s.

    Gains placed at the poles -1, -2, -3 (coefficient matching): d decays like e^{-t}.
    """
    v, tau, dt = 3.4, 0.4, 0.01
    gains = place_poles([-1.0, -2.0, -3.0], v, tau)
    assert routh_stable(gains, v, None, tau)
    states = run_bicycle(gains, v, tau, [0.0, 0.5, 0.0, 0.0], 12.0, dt)
    d = states[:, 1]
    assert abs(d[-1]) < 1e-4
    ratio = d[round(11.0 / dt)] / d[round(10.0 / dt)]
    assert ratio == pytest.approx(math.exp(-1.0), rel=1e-3)


def test_bicycle_unstable_gains_diverge():
    """Routh rejects k3 = -0.9, k2 small: the same start then grows instead of decaying."""
    v, tau = 3.4, 0.4
    gains = np.array([1.0, 0.02, -0.9])
    assert not routh_stable(gains, v, None, tau)
    states = run_bicycle(gains, v, tau, [0.0, 0.01, 0.0, 0.0], 6.0, 0.005)
    assert np.max(np.abs(states[:, 1])) > 10.0 * 0.01


# ---------------------------------------------------------------- bad input

@pytest.mark.parametrize('kwargs', [
    {'law': 'pure_pursuit'}, {'k1': 0.0}, {'k2': -1.0}, {'k1': math.nan},
    {'desired_linear_velocity': 0.0}, {'max_angular_velocity': math.inf},
    {'goal_tolerance': -0.1}, {'search_window': 0.0}, {'curvature_window': math.nan},
])
def test_params_reject_bad_values(kwargs):
    with pytest.raises(ValueError):
        FrenetParams(**kwargs)


@pytest.mark.parametrize('call', [
    lambda: frenet_error_rates([0.0, 0.0], 1.0, 0.0),
    lambda: frenet_error_rates([0.0, math.nan, 0.0], 1.0, 0.0),
    lambda: frenet_error_rates([0.0, 0.0, 0.0], math.inf, 0.0),
    lambda: FrenetErrors(0.0, 4.0, 0.0),
    lambda: FrenetErrors(math.nan, 0.0, 0.0),
    lambda: path_following_input(0.0, 0.0, math.nan, FrenetParams()),
    lambda: frenet_angular_velocity([0.0, 0.0, 0.0, 0.0], 1.0, FrenetParams()),
    lambda: gains_from_damping(0.0, 1.0),
    lambda: gains_from_damping(1.0, -1.0),
    lambda: in_convergence_region(0.0, 0.0, 0.0, 1.0),
    lambda: in_convergence_region(0.0, 0.0, 1.0, -1.0),
    lambda: steering_state_matrices(1.0, 0.0),
    lambda: steering_state_matrices(math.nan, 0.5),
    lambda: characteristic_polynomial([1.0, 2.0], 1.0, None, 0.5),
    lambda: routh_stable([1.0, 2.0, 3.0], 1.0, -2.5, 0.5),
    lambda: routh_stable([1.0, 2.0, math.nan], 1.0, None, 0.5),
    lambda: steering_feedback(0.0, 0.0, math.inf, [1.0, 2.0, 3.0]),
])
def test_functions_reject_bad_input(call):
    with pytest.raises(ValueError):
        call()


@pytest.mark.parametrize('pose', [[0.0, 0.0], [0.0, math.nan, 0.0], [0.0, 0.0, 0.0, 0.0]])
def test_update_rejects_bad_pose(pose):
    follower = FrenetPathFollower(PolylinePath([[0.0, 0.0], [2.0, 0.0]]), FrenetParams())
    with pytest.raises(ValueError):
        follower.update(pose, 0.0)
    with pytest.raises(ValueError):
        follower.path_curvature(math.nan)
