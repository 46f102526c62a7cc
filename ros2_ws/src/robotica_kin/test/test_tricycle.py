"""Tests of robotica_kin.mobile.tricycle (book §4.7.4, Ej. 4.8; catalog §2.8, §2.11, §12.3)."""

import dataclasses
import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book, wrap_to_pi
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.tricycle import (
    tricycle_deriv,
    tricycle_direct,
    tricycle_inverse,
    tricycle_inverse_velocity,
    tricycle_path_inverse,
    TricycleParams,
)
from robotica_kin.mobile.unicycle import (
    HEADING_CONVENTIONS,
    instantaneous_centre_of_rotation,
    nonholonomic_residual,
)
from scipy.integrate import solve_ivp

EJ_4_8 = TricycleParams(wheelbase=1.5, wheel_radius=0.3)  # l = 1.5 m; c is not given (any)
ALPHA_4_8 = math.radians(56.31)  # printed steering angle
V_T_4_8 = 1.8028  # printed front wheel speed [m/s]
SPEED = st.floats(-5.0, 5.0)
RATE = st.floats(-3.0, 3.0)
DIMENSION = st.floats(0.1, 3.0)


def unit_circle(t):
    """Ejemplo 4.8's path x = cos t, y = sin t and its first three derivatives."""
    c, s = math.cos(t), math.sin(t)
    return [c, s], [-s, c], [-c, -s], [s, -c]


def ellipse(t):
    """Path x = 2 cos t, y = sin t + 0.3 t of varying curvature, and its derivatives."""
    c, s = math.cos(t), math.sin(t)
    return [2.0 * c, s + 0.3 * t], [-2.0 * s, c + 0.3], [-2.0 * c, -s], [2.0 * s, -c]


def test_params_validation_and_frozen():
    with pytest.raises(ValueError, match='wheelbase'):
        TricycleParams(wheelbase=0.0, wheel_radius=0.3)
    with pytest.raises(ValueError, match='wheel_radius'):
        TricycleParams(wheelbase=1.0, wheel_radius=math.nan)
    with pytest.raises(ValueError, match='wheelbase'):
        TricycleParams(wheelbase=math.inf, wheel_radius=0.3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        EJ_4_8.wheelbase = 2.0  # type: ignore[misc]


def test_ejemplo_4_8_inverse_4_119_4_120():
    """Ejemplo 4.8 (catalog §2.11): v = 1 m/s, ω = 1 rad/s on the unit circle, l = 1.5 m."""
    wheel_speed, alpha = tricycle_inverse(EJ_4_8, 1.0, 1.0)
    assert math.degrees(alpha) == pytest.approx(56.31, abs=5e-3)
    assert wheel_speed * EJ_4_8.wheel_radius == pytest.approx(V_T_4_8, abs=5e-5)


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
@pytest.mark.parametrize('t', [0.0, 0.3, math.pi / 4.0, 1.2, math.pi / 2.0])
def test_ejemplo_4_8_pseudo_inverse(convention, t):
    """
    Ejemplo 4.8 with [H] (3.33): along the unit circle α = 56.31°, v_t = 1.8028, ω_α = 0.

    The book's heading on the circle is φ = atan2(-x', y') = t (θ = t + π/2 in REP-103),
    φ' = 1; the steering angle is the printed one, so v_t is compared at the printed precision.
    """
    _, (dx, dy), _, _ = unit_circle(t)
    heading = t if convention == 'book' else heading_from_book(t)
    v_t, omega_alpha = tricycle_inverse_velocity(EJ_4_8, heading, ALPHA_4_8, [dx, dy, 1.0],
                                                 convention)
    assert v_t == pytest.approx(V_T_4_8, abs=1e-4)
    assert omega_alpha == 0.0
    v_t4, omega_alpha4 = tricycle_inverse_velocity(
        EJ_4_8, heading, math.atan(1.5), [dx, dy, 1.0, 0.0], convention)
    assert v_t4 == pytest.approx(math.sqrt(1.0 + 1.5**2), rel=1e-12)  # = 1.80277...
    assert omega_alpha4 == 0.0


def test_book_4_123_as_printed_is_a_misprint():
    """
    The printed (4.123) drops cos α from the x', y' terms (catalog §2.11, Part 17).

    Evaluated on Ejemplo 4.8 (t = 0, φ = 0, x' = 0, y' = 1, φ' = 1) it gives 2.526 m/s, not the
    book's own 1.8028; HEMERO's [H] (3.33), written out here, gives 1.8028.
    """
    l, alpha, phi, dx, dy, dphi = 1.5, ALPHA_4_8, 0.0, 0.0, 1.0, 1.0
    den = (l * math.cos(alpha)) ** 2 + math.sin(alpha) ** 2
    printed = (-l**2 * math.sin(phi) * dx + l**2 * math.cos(phi) * dy
               + l * math.sin(alpha) * dphi) / den
    hemero = (-l**2 * math.sin(phi) * math.cos(alpha) * dx
              + l**2 * math.cos(phi) * math.cos(alpha) * dy + l * math.sin(alpha) * dphi) / den
    assert printed == pytest.approx(2.526, abs=1e-3)
    assert hemero == pytest.approx(V_T_4_8, abs=1e-4)
    v_t, _ = tricycle_inverse_velocity(EJ_4_8, phi, alpha, [dx, dy, dphi], 'book')
    assert v_t == pytest.approx(hemero, rel=1e-12)


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
def test_ejemplo_4_8_forward_simulation_follows_the_unit_circle(convention):
    """
    The book's controls (v_t = 1.8028 m/s, α = 56.31°, ω_α = 0) drive (1, 0) -> (0, 1).

    Direct model (4.118) integrated with rk4_step over t in [0, π/2] (v = 1 m/s); compared
    with the circle x = cos t, y = sin t at the printed precision (the printed controls are
    rounded), and the non-holonomic residual (4.104) is zero at every step.
    """
    heading0 = 0.5 * math.pi if convention == 'rep103' else 0.0
    state = np.array([1.0, 0.0, heading0, ALPHA_4_8])
    command = [V_T_4_8 / EJ_4_8.wheel_radius, 0.0]
    n = 1000
    h = 0.5 * math.pi / n
    for k in range(n):
        rate = tricycle_deriv(0.0, state, command, EJ_4_8, convention)
        assert abs(nonholonomic_residual(state[:3], rate[:3], convention)) < 1e-12
        state = rk4_step(tricycle_deriv, k * h, state, h, command, EJ_4_8, convention)
    np.testing.assert_allclose(state[:2], [0.0, 1.0], atol=5e-4)
    assert state[2] == pytest.approx(heading0 + 0.5 * math.pi, abs=5e-4)
    assert state[3] == ALPHA_4_8


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
@pytest.mark.parametrize('t', np.linspace(0.0, 0.5 * math.pi, 5))
def test_ejemplo_4_8_path_inverse(convention, t):
    """Inverse block of HEMERO from the path itself: constant α = 56.31°, v_t, ω_α = 0."""
    _, velocity, acceleration, jerk = unit_circle(t)
    v_t, omega_alpha, alpha, heading = tricycle_path_inverse(EJ_4_8, velocity, acceleration,
                                                             jerk, convention)
    assert math.degrees(alpha) == pytest.approx(56.31, abs=5e-3)
    assert v_t == pytest.approx(V_T_4_8, abs=5e-5)
    assert omega_alpha == pytest.approx(0.0, abs=1e-12)
    expected = t if convention == 'book' else heading_from_book(t)
    assert wrap_to_pi(heading - expected) == pytest.approx(0.0, abs=1e-12)


def test_path_inverse_steering_rate_matches_finite_differences():
    """α' of the path inverse against central differences of its α along the ellipse."""
    eps = 1e-5
    for t in np.linspace(0.0, 6.0, 13):
        _, omega_alpha, _, _ = tricycle_path_inverse(EJ_4_8, *ellipse(t)[1:])
        alpha_plus = tricycle_path_inverse(EJ_4_8, *ellipse(t + eps)[1:])[2]
        alpha_minus = tricycle_path_inverse(EJ_4_8, *ellipse(t - eps)[1:])[2]
        assert omega_alpha == pytest.approx((alpha_plus - alpha_minus) / (2 * eps), abs=1e-6)


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
def test_path_inverse_then_direct_model_retraces_the_path(convention):
    """
    Inverse blocks then direct model: the tricycle driven by (ω_t, ω_α) retraces the ellipse.

    solve_ivp integrates (4.118) with the controls computed at each time from the path;
    position, heading and steering angle stay on the path's, and v_t = sqrt(v² + (l φ')²).
    """
    params = EJ_4_8

    def f(t, state):
        v_t, omega_alpha, _, _ = tricycle_path_inverse(params, *ellipse(t)[1:],
                                                       convention=convention)
        return tricycle_deriv(t, state, [v_t / params.wheel_radius, omega_alpha], params,
                              convention)

    _, _, alpha0, heading0 = tricycle_path_inverse(params, *ellipse(0.0)[1:],
                                                   convention=convention)
    sol = solve_ivp(f, (0.0, 5.0), [2.0, 0.0, heading0, alpha0], rtol=1e-10, atol=1e-12,
                    dense_output=True)
    for t in np.linspace(0.0, 5.0, 11):
        x, y, heading, alpha = sol.sol(t)
        position, velocity, acceleration, jerk = ellipse(t)
        v_t, _, alpha_path, heading_path = tricycle_path_inverse(
            params, velocity, acceleration, jerk, convention)
        assert (x, y) == pytest.approx(position, abs=1e-6)
        assert wrap_to_pi(heading - heading_path) == pytest.approx(0.0, abs=1e-6)
        assert alpha == pytest.approx(alpha_path, abs=1e-6)
        speed = math.hypot(*velocity)
        heading_rate = (velocity[0] * acceleration[1] - acceleration[0] * velocity[1]) / speed**2
        assert v_t == pytest.approx(math.hypot(speed, params.wheelbase * heading_rate))


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
@given(heading=st.floats(-math.pi, math.pi), alpha=st.floats(-1.5, 1.5),
       rates=st.lists(st.floats(-3.0, 3.0), min_size=4, max_size=4), wheelbase=DIMENSION)
def test_pseudo_inverse_is_least_squares(convention, heading, alpha, rates, wheelbase):
    """(4.106) on the Jacobian (4.122) built here, solved by numpy's lstsq (independent)."""
    fx, fy = ((math.cos(heading), math.sin(heading)) if convention == 'rep103'
              else (-math.sin(heading), math.cos(heading)))
    jacobian = np.array([[fx * math.cos(alpha), 0.0], [fy * math.cos(alpha), 0.0],
                         [math.sin(alpha) / wheelbase, 0.0], [0.0, 1.0]])
    expected, *_ = np.linalg.lstsq(jacobian, np.array(rates), rcond=None)
    params = TricycleParams(wheelbase, 0.2)
    result = tricycle_inverse_velocity(params, heading, alpha, rates, convention)
    np.testing.assert_allclose(result, expected, atol=1e-9)


@given(SPEED, RATE, DIMENSION, DIMENSION)
def test_inverse_direct_round_trip(v, omega, wheelbase, radius):
    """(v, ω) -> (ω_t, α) -> (v, ω), including reverse and turning on the spot (v = 0)."""
    params = TricycleParams(wheelbase, radius)
    wheel_speed, alpha = tricycle_inverse(params, v, omega)
    assert -0.5 * math.pi <= alpha <= 0.5 * math.pi
    assert tricycle_direct(params, wheel_speed, alpha) == pytest.approx((v, omega), abs=1e-9)


@given(st.floats(-20.0, 20.0).filter(lambda w: abs(w) > 1e-6), st.floats(-1.5, 1.5),
       DIMENSION, DIMENSION)
def test_direct_inverse_round_trip(wheel_speed, alpha, wheelbase, radius):
    params = TricycleParams(wheelbase, radius)
    v, omega = tricycle_direct(params, wheel_speed, alpha)
    assert tricycle_inverse(params, v, omega) == pytest.approx((wheel_speed, alpha), abs=1e-9)


def test_inverse_special_cases():
    params = TricycleParams(wheelbase=2.0, wheel_radius=0.5)
    assert tricycle_inverse(params, 0.0, 0.0) == (0.0, 0.0)
    assert tricycle_inverse(params, 1.0, 0.0) == (2.0, 0.0)
    assert tricycle_inverse(params, -1.0, 0.0) == (-2.0, 0.0)  # reverse: wheel rolls back
    assert tricycle_inverse(params, 0.0, 0.5) == (2.0, 0.5 * math.pi)  # spin: l ω / c
    assert tricycle_inverse(params, 0.0, -0.5) == (2.0, -0.5 * math.pi)
    wheel_speed, alpha = tricycle_inverse(params, -1.0, 0.5)  # reversing, turning left
    assert wheel_speed < 0.0 and alpha < 0.0
    with pytest.raises(ValueError):
        tricycle_inverse(params, math.nan, 0.0)


@given(st.floats(-math.pi, math.pi), st.floats(-20.0, 20.0), st.floats(-1.5, 1.5), RATE,
       DIMENSION, DIMENSION)
def test_deriv_is_hemero_3_29(phi, wheel_speed, alpha, steering_rate, wheelbase, radius):
    """[H] (3.29) written out in the book convention; REP-103 gives the same velocities."""
    params = TricycleParams(wheelbase, radius)
    c = radius
    expected = [-c * math.sin(phi) * math.cos(alpha) * wheel_speed,
                c * math.cos(phi) * math.cos(alpha) * wheel_speed,
                c * math.sin(alpha) / wheelbase * wheel_speed, steering_rate]
    book = tricycle_deriv(0.0, [0.0, 0.0, phi, alpha], [wheel_speed, steering_rate], params,
                          'book')
    np.testing.assert_allclose(book, expected, atol=1e-9)
    rep = tricycle_deriv(0.0, [0.0, 0.0, heading_from_book(phi), alpha],
                         [wheel_speed, steering_rate], params)
    np.testing.assert_allclose(rep, book, atol=1e-9)


@given(st.floats(-1.5, 1.5).filter(lambda a: abs(a) > 1e-3),
       st.floats(-10.0, 10.0).filter(lambda w: w == 0.0 or abs(w) > 1e-6), DIMENSION)
def test_icr_by_geometry(alpha, wheel_speed, wheelbase):
    """
    The front wheel's velocity is along its own direction and perpendicular to its ICR line.

    The ICR (0, v/ω) lies on the rear axle at l / tan α (catalog §13.3: R = d cot α); the
    front contact point (l, 0) moves at (v, ω l) in ``base_link``.
    """
    params = TricycleParams(wheelbase, 0.25)
    v, omega = tricycle_direct(params, wheel_speed, alpha)
    icr = instantaneous_centre_of_rotation(v, omega)
    if icr is None:
        assert wheel_speed == 0.0
        return
    assert icr[1] == pytest.approx(wheelbase / math.tan(alpha), rel=1e-9)
    velocity = np.array([v, omega * wheelbase])
    assert velocity[0] * math.sin(alpha) - velocity[1] * math.cos(alpha) == pytest.approx(
        0.0, abs=1e-9)
    assert float(velocity @ (np.array([wheelbase, 0.0]) - np.array(icr))) == pytest.approx(
        0.0, abs=1e-9 * (1.0 + abs(icr[1])))
    assert np.linalg.norm(velocity) == pytest.approx(abs(wheel_speed) * 0.25)


@pytest.mark.parametrize(('state', 'command', 'match'), [
    ([0.0, 0.0, 0.0], [1.0, 0.0], 'state'),
    ([0.0, 0.0, 0.0, 0.0], [1.0], 'command'),
    ([0.0, 0.0, 0.0, math.nan], [1.0, 0.0], 'state'),
])
def test_deriv_rejects_bad_input(state, command, match):
    with pytest.raises(ValueError, match=match):
        tricycle_deriv(0.0, state, command, EJ_4_8)


@pytest.mark.parametrize(('pose_dot', 'match'), [
    ([0.0, 1.0], 'pose_dot'),
    ([0.0, 1.0, 1.0, 0.0, 0.0], 'pose_dot'),
    ([0.0, math.inf, 1.0], 'pose_dot'),
])
def test_inverse_velocity_rejects_bad_input(pose_dot, match):
    with pytest.raises(ValueError, match=match):
        tricycle_inverse_velocity(EJ_4_8, 0.0, 0.5, pose_dot)


def test_path_inverse_rejects_a_standing_vehicle():
    with pytest.raises(ValueError, match='velocity'):
        tricycle_path_inverse(EJ_4_8, [0.0, 0.0], [1.0, 0.0], [0.0, 0.0])
