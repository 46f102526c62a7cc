"""Tests of robotica_kin.mobile.unicycle (book §4.7.2-§4.7.4; catalog §2.7, §2.8, §12.3)."""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book, heading_to_book, wrap_to_pi
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.odometry import odometry_increment
from robotica_kin.mobile.unicycle import (
    arc_update,
    forward_direction,
    HEADING_CONVENTIONS,
    instantaneous_centre_of_rotation,
    nonholonomic_residual,
    path_heading,
    path_twist,
    synchronous_drive_direct,
    synchronous_drive_inverse,
    unicycle_deriv,
)
from scipy.integrate import solve_ivp

COORD = st.floats(-10.0, 10.0)
ANGLE = st.floats(-math.pi, math.pi)
SPEED = st.floats(-5.0, 5.0)
RATE = st.floats(-3.0, 3.0)


def book_arc(pose, v, omega, dt):
    """Book (4.93) as printed (φ from the y axis), R = v/ω; the line (4.95)-(4.96) at ω = 0."""
    x, y, phi = pose
    ds, dphi = v * dt, omega * dt
    if dphi == 0.0:
        return np.array([x - ds * math.sin(phi), y + ds * math.cos(phi), phi])
    r = ds / dphi
    dx = r * (math.cos(dphi) - 1.0) * math.cos(phi) - r * math.sin(dphi) * math.sin(phi)
    dy = r * (math.cos(dphi) - 1.0) * math.sin(phi) + r * math.sin(dphi) * math.cos(phi)
    return np.array([x + dx, y + dy, phi + dphi])


def close_pose(pose, expected, atol):
    np.testing.assert_allclose(pose[:2], expected[:2], atol=atol)
    assert abs(wrap_to_pi(pose[2] - expected[2])) <= atol


def test_forward_direction_conventions():
    assert forward_direction(0.3) == pytest.approx((math.cos(0.3), math.sin(0.3)))
    assert forward_direction(0.3, 'book') == pytest.approx((-math.sin(0.3), math.cos(0.3)))
    with pytest.raises(ValueError, match='convention'):
        forward_direction(0.0, 'ned')
    with pytest.raises(ValueError, match='heading'):
        forward_direction(math.nan)


@given(COORD, COORD, ANGLE, SPEED, RATE)
def test_deriv_book_is_4_97_to_4_99_and_matches_rep103(x, y, phi, v, omega):
    book = unicycle_deriv(0.0, [x, y, phi], [v, omega], convention='book')
    np.testing.assert_allclose(book, [-v * math.sin(phi), v * math.cos(phi), omega], atol=1e-12)
    rep = unicycle_deriv(0.0, [x, y, heading_from_book(phi)], [v, omega])
    np.testing.assert_allclose(rep, book, atol=1e-12)
    assert rep.dtype == np.float64 and rep.shape == (3,)


@pytest.mark.parametrize(('state', 'command', 'convention'), [
    ([0.0, 0.0], [1.0, 0.0], 'rep103'),
    ([0.0, 0.0, 0.0], [1.0], 'rep103'),
    ([0.0, math.nan, 0.0], [1.0, 0.0], 'rep103'),
    ([0.0, 0.0, 0.0], [math.inf, 0.0], 'rep103'),
    ([0.0, 0.0, 0.0], [1.0, 0.0], 'enu'),
])
def test_deriv_rejects_bad_input(state, command, convention):
    with pytest.raises(ValueError):
        unicycle_deriv(0.0, state, command, convention)


@given(COORD, COORD, ANGLE, SPEED, RATE.filter(lambda w: w == 0.0 or abs(w) > 1e-3),
       st.floats(0.0, 2.0))
def test_arc_update_is_book_4_93(x, y, phi, v, omega, dt):
    """
    The printed (4.93) in the book convention, and the same arc in REP-103.

    |ω| <= 1e-3 rad/s is left out (bar ω = 0): there the printed form itself loses digits
    (R (cos Δφ - 1) with R = v/ω large); the limit is tested below.
    """
    expected = book_arc((x, y, phi), v, omega, dt)
    close_pose(arc_update([x, y, phi], v, omega, dt, convention='book'), expected, 1e-9)
    rep = arc_update([x, y, heading_from_book(phi)], v, omega, dt)
    close_pose(rep, [expected[0], expected[1], heading_from_book(expected[2])], 1e-9)
    assert -math.pi < rep[2] <= math.pi


@given(COORD, COORD, ANGLE, SPEED, RATE.filter(lambda w: w == 0.0 or abs(w) > 1e-3),
       st.floats(0.5, 2.0))
def test_arc_update_matches_odometry_exact_arc(x, y, theta, v, omega, dt):
    """
    Cross-check with the odometry's exact arc (wheel travels of a b = 0.5 m base).

    Turns below 1e-3 rad are left out: there ``odometry_increment``'s R (sin(θ + Δθ) - sin θ)
    loses digits (up to 1e-7 m at Δθ ~ 1e-9 rad), while the chord form here does not.
    """
    b = 0.5
    delta_left, delta_right = (v - 0.5 * b * omega) * dt, (v + 0.5 * b * omega) * dt
    expected = odometry_increment([x, y, theta], delta_left, delta_right, b, 'exact_arc')
    close_pose(arc_update([x, y, theta], v, omega, dt), expected, 1e-9)


def test_arc_update_quarter_circle_and_straight_line():
    close_pose(arc_update([0.0, 0.0, 0.0], 1.0, 0.5 * math.pi, 1.0),
               [2.0 / math.pi, 2.0 / math.pi, 0.5 * math.pi], 1e-15)
    close_pose(arc_update([1.0, 2.0, 0.7], 0.5, 0.0, 2.0),
               [1.0 + math.cos(0.7), 2.0 + math.sin(0.7), 0.7], 1e-15)
    close_pose(arc_update([1.0, 2.0, 0.7], 0.0, 1.0, 2.0), [1.0, 2.0, 2.7], 1e-15)  # spin


def test_arc_update_is_continuous_at_the_straight_line_limit():
    straight = arc_update([0.0, 0.0, 1.0], 1.0, 0.0, 0.5)
    for omega in (1e-15, 1e-12, 1e-9, 1e-7):
        np.testing.assert_allclose(arc_update([0.0, 0.0, 1.0], 1.0, omega, 0.5), straight,
                                   atol=1e-7)


def test_arc_update_is_exact_for_constant_commands():
    """Twenty arc steps equal one long one (the arc is the exact solution), and solve_ivp."""
    pose = np.array([0.5, -1.0, 2.0])
    for _ in range(20):
        pose = arc_update(pose, 0.8, -0.6, 0.1)
    close_pose(pose, arc_update([0.5, -1.0, 2.0], 0.8, -0.6, 2.0), 1e-12)
    sol = solve_ivp(unicycle_deriv, (0.0, 2.0), [0.5, -1.0, 2.0], args=([0.8, -0.6],),
                    rtol=1e-11, atol=1e-12)
    close_pose(pose, sol.y[:, -1], 1e-9)


@pytest.mark.parametrize(('pose', 'v', 'omega', 'dt', 'match'), [
    ([0.0, 0.0, 0.0], 1.0, 0.0, -0.1, 'dt'),
    ([0.0, 0.0, 0.0], math.nan, 0.0, 0.1, 'v'),
    ([0.0, 0.0, 0.0], 1.0, math.inf, 0.1, 'omega'),
    ([0.0, 0.0], 1.0, 0.0, 0.1, 'pose'),
    ([0.0, 0.0, 0.0], 1.0, 0.0, 0.1, 'convention'),
])
def test_arc_update_rejects_bad_input(pose, v, omega, dt, match):
    convention = 'xyz' if match == 'convention' else 'rep103'
    with pytest.raises(ValueError, match=match):
        arc_update(pose, v, omega, dt, convention)


@given(SPEED, RATE.filter(lambda w: abs(w) > 1e-3), st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
def test_icr_by_geometry(v, omega, px, py):
    """Every point of the body moves perpendicular to its line to the ICR, at |ω| · distance."""
    icr = instantaneous_centre_of_rotation(v, omega)
    assert icr is not None and icr[0] == 0.0
    velocity = np.array([v - omega * py, omega * px])  # rigid body, twist (v, 0, ω) at origin
    arm = np.array([px, py]) - np.array(icr)
    assert float(velocity @ arm) == pytest.approx(0.0, abs=1e-9)
    assert np.linalg.norm(velocity) == pytest.approx(abs(omega) * np.linalg.norm(arm), rel=1e-9,
                                                     abs=1e-12)


def test_icr_straight_line_and_spin():
    assert instantaneous_centre_of_rotation(1.0, 0.0) is None
    assert instantaneous_centre_of_rotation(0.0, 1.0) == (0.0, 0.0)
    assert instantaneous_centre_of_rotation(-1.0, 0.5) == (0.0, -2.0)
    with pytest.raises(ValueError):
        instantaneous_centre_of_rotation(math.nan, 1.0)


@given(ANGLE, SPEED, RATE, SPEED)
def test_nonholonomic_residual_is_the_lateral_velocity(theta, v, omega, lateral):
    """Book (4.104) and its REP-103 form: zero for (4.102)'s velocities, else the slip."""
    c, s = math.cos(theta), math.sin(theta)
    pose_dot = [v * c - lateral * s, v * s + lateral * c, omega]
    pose = [1.0, 2.0, theta]
    assert nonholonomic_residual(pose, pose_dot) == pytest.approx(lateral, abs=1e-12)
    phi = heading_to_book(theta)
    book = [1.0, 2.0, phi]
    assert nonholonomic_residual(book, pose_dot, 'book') == pytest.approx(
        pose_dot[0] * math.cos(phi) + pose_dot[1] * math.sin(phi), abs=1e-12)
    assert nonholonomic_residual(book, pose_dot, 'book') == pytest.approx(-lateral, abs=1e-12)


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
def test_nonholonomic_residual_vanishes_along_a_trajectory(convention):
    """rk4_step of the model under time-varying commands; (4.104) holds at every step."""
    def command(t):
        return [1.0 + 0.5 * math.sin(t), 0.8 * math.cos(0.7 * t)]

    state = np.array([0.0, 0.0, 0.3])
    h = 0.01
    for k in range(500):
        t = k * h
        rate = unicycle_deriv(t, state, command(t), convention)
        assert abs(nonholonomic_residual(state, rate, convention)) < 1e-12
        state = rk4_step(lambda tt, xx: unicycle_deriv(tt, xx, command(tt), convention),
                         t, state, h)
    # and the pose agrees with solve_ivp
    sol = solve_ivp(lambda tt, xx: unicycle_deriv(tt, xx, command(tt), convention), (0.0, 5.0),
                    [0.0, 0.0, 0.3], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(state, sol.y[:, -1], atol=1e-8)


@given(st.floats(-100.0, 100.0), st.floats(-5.0, 5.0), st.floats(0.01, 1.0))
def test_synchronous_drive_round_trip(wheel_speed, steering_rate, radius):
    v, omega = synchronous_drive_direct(wheel_speed, steering_rate, radius)
    assert (v, omega) == pytest.approx((radius * wheel_speed, steering_rate))
    back = synchronous_drive_inverse(v, omega, radius)
    assert back == pytest.approx((wheel_speed, steering_rate), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize('radius', [0.0, -0.1, math.nan, math.inf])
def test_synchronous_drive_rejects_bad_radius(radius):
    with pytest.raises(ValueError, match='wheel_radius'):
        synchronous_drive_direct(1.0, 0.0, radius)
    with pytest.raises(ValueError, match='wheel_radius'):
        synchronous_drive_inverse(1.0, 0.0, radius)


def test_synchronous_heading_follows_the_steering():
    """Fig. 4.17a: the heading is the wheels' steering angle, integrated from its rate."""
    radius, state = 0.2, np.array([0.0, 0.0, 0.0])
    steering = 0.0
    for _ in range(100):
        twist = synchronous_drive_direct(5.0, 0.4, radius)
        state = rk4_step(unicycle_deriv, 0.0, state, 0.01, twist)
        steering += 0.4 * 0.01
    assert state[2] == pytest.approx(steering)


@pytest.mark.parametrize(('velocity', 'theta', 'phi'), [
    ([1.0, 0.0], 0.0, -0.5 * math.pi),
    ([0.0, 1.0], 0.5 * math.pi, 0.0),
    ([-1.0, -1.0], -0.75 * math.pi, 0.75 * math.pi),
    ([0.0, -2.0], -0.5 * math.pi, math.pi),  # HEMERO's atan(-x'/y') would give 0 (reverse)
])
def test_path_heading(velocity, theta, phi):
    assert path_heading(velocity) == pytest.approx(theta)
    assert path_heading(velocity, 'book') == pytest.approx(phi)


def test_path_heading_rejects_standing_vehicle():
    with pytest.raises(ValueError, match='velocity'):
        path_heading([0.0, 0.0])
    with pytest.raises(ValueError, match='convention'):
        path_heading([1.0, 0.0], 'ros')


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
def test_path_twist_drives_the_unicycle_along_an_ellipse(convention):
    """
    Inverse model ([H] (3.35)) then direct model: the unicycle retraces the path.

    Ellipse x = 2 cos t, y = sin t; (v, ω, heading) from the path's derivatives at each time,
    the pose integrated with solve_ivp from the path's start.
    """
    def derivatives(t):
        return ([-2.0 * math.sin(t), math.cos(t)], [-2.0 * math.cos(t), -math.sin(t)])

    def f(t, state):
        v, omega, _ = path_twist(*derivatives(t), convention)
        return unicycle_deriv(t, state, [v, omega], convention)

    start = [2.0, 0.0, path_twist(*derivatives(0.0), convention)[2]]
    sol = solve_ivp(f, (0.0, 4.0), start, rtol=1e-10, atol=1e-12, dense_output=True)
    for t in np.linspace(0.0, 4.0, 9):
        x, y, heading = sol.sol(t)
        assert (x, y) == pytest.approx((2.0 * math.cos(t), math.sin(t)), abs=1e-7)
        expected = path_twist(*derivatives(t), convention)
        assert wrap_to_pi(heading - expected[2]) == pytest.approx(0.0, abs=1e-7)
        assert expected[0] == pytest.approx(math.hypot(2.0 * math.sin(t), math.cos(t)))
