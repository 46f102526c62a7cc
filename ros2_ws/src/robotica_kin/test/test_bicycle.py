"""Tests of robotica_kin.mobile.bicycle (book (4.119), (4.121); catalog §2.8, §7, Part 17)."""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.bicycle import (
    bicycle_deriv,
    bicycle_direct,
    bicycle_inverse,
    curvature_from_steering,
    steering_from_curvature,
)
from robotica_kin.mobile.unicycle import HEADING_CONVENTIONS, nonholonomic_residual
from scipy.integrate import solve_ivp

STEERING = st.floats(-1.5, 1.5)
WHEELBASE = st.floats(0.1, 5.0)
SPEED = st.floats(-10.0, 10.0)


@pytest.mark.parametrize(('alpha', 'wheelbase', 'curvature'), [
    (0.0, 2.0, 0.0),
    (math.pi / 4.0, 2.0, 0.5),
    (-math.pi / 4.0, 0.5, -2.0),
    (math.atan(1.5), 1.5, 1.0),  # Ejemplo 4.8: l = 1.5 m on the unit circle, α = 56.31°
])
def test_curvature_from_steering_by_hand(alpha, wheelbase, curvature):
    assert curvature_from_steering(alpha, wheelbase) == pytest.approx(curvature)
    assert steering_from_curvature(curvature, wheelbase) == pytest.approx(alpha)


def test_ejemplo_4_8_steering_angle():
    """Ejemplo 4.8 (catalog §2.11): α = atan(l/R) = atan(1.5/1) = 56.31°."""
    assert math.degrees(steering_from_curvature(1.0, 1.5)) == pytest.approx(56.31, abs=5e-3)


@given(STEERING, WHEELBASE)
def test_steering_curvature_round_trip(alpha, wheelbase):
    gamma = curvature_from_steering(alpha, wheelbase)
    assert steering_from_curvature(gamma, wheelbase) == pytest.approx(alpha, abs=1e-12)


@given(SPEED.filter(lambda v: v == 0.0 or abs(v) > 1e-6), STEERING, WHEELBASE)
def test_direct_inverse_round_trip(v, alpha, wheelbase):
    """(v, α) -> (v, ω) -> (v, α), forwards and in reverse (v < 0; subnormal v left out)."""
    twist = bicycle_direct(v, alpha, wheelbase)
    assert twist[1] == pytest.approx(v * math.tan(alpha) / wheelbase)
    back_v, back_alpha = bicycle_inverse(*twist, wheelbase)
    assert back_v == v
    if v != 0.0:
        assert back_alpha == pytest.approx(alpha, abs=1e-9)


@given(SPEED.filter(lambda v: abs(v) > 1e-3), st.floats(-5.0, 5.0), WHEELBASE)
def test_inverse_direct_round_trip(v, omega, wheelbase):
    v_, alpha = bicycle_inverse(v, omega, wheelbase)
    assert abs(alpha) < 0.5 * math.pi
    assert bicycle_direct(v_, alpha, wheelbase) == pytest.approx((v, omega), rel=1e-9, abs=1e-12)


def test_inverse_at_rest_and_impossible_spin():
    assert bicycle_inverse(0.0, 0.0, 2.0) == (0.0, 0.0)
    with pytest.raises(ValueError, match='turn on the spot'):
        bicycle_inverse(0.0, 0.5, 2.0)


def test_reverse_turns_the_other_way():
    """Backing up with the wheel to the left turns the vehicle clockwise (ω < 0)."""
    assert bicycle_direct(-1.0, 0.3, 2.0)[1] < 0.0
    assert bicycle_inverse(-1.0, -0.5, 2.0)[1] > 0.0


@pytest.mark.parametrize('bad', [0.5 * math.pi, -0.5 * math.pi, 2.0, math.nan])
def test_rejects_steering_at_or_beyond_a_right_angle(bad):
    with pytest.raises(ValueError, match='steering_angle'):
        curvature_from_steering(bad, 1.0)
    with pytest.raises(ValueError, match='steering_angle|command'):
        bicycle_deriv(0.0, [0.0, 0.0, 0.0], [1.0, bad], 1.0)


@pytest.mark.parametrize('wheelbase', [0.0, -1.0, math.inf, math.nan])
def test_rejects_bad_wheelbase(wheelbase):
    with pytest.raises(ValueError, match='wheelbase'):
        curvature_from_steering(0.1, wheelbase)
    with pytest.raises(ValueError, match='wheelbase'):
        steering_from_curvature(0.1, wheelbase)
    with pytest.raises(ValueError, match='wheelbase'):
        bicycle_inverse(1.0, 0.1, wheelbase)


@given(st.floats(-math.pi, math.pi), SPEED, STEERING, WHEELBASE)
def test_deriv_is_book_4_121(phi, v, alpha, wheelbase):
    """(4.121) as printed, φ from the y axis; and the same velocities in REP-103."""
    book = bicycle_deriv(0.0, [1.0, 2.0, phi], [v, alpha], wheelbase, 'book')
    expected = [-v * math.sin(phi), v * math.cos(phi), v * math.tan(alpha) / wheelbase]
    np.testing.assert_allclose(book, expected, rtol=1e-12, atol=1e-12)
    rep = bicycle_deriv(0.0, [1.0, 2.0, heading_from_book(phi)], [v, alpha], wheelbase)
    np.testing.assert_allclose(rep, book, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize('convention', HEADING_CONVENTIONS)
def test_constant_steering_drives_a_circle_of_radius_l_cot_alpha(convention):
    """
    Constant (v, α): circle of radius R = l / tan α about the ICR on the rear axle's line.

    From the origin, heading along +x (θ = 0, φ = -π/2): centre (0, R); rk4_step and
    solve_ivp agree with the closed form x = R sin(v t / R), y = R (1 - cos(v t / R)), and
    the non-holonomic residual (4.104) stays zero.
    """
    wheelbase, v, alpha = 2.0, 1.5, 0.4
    radius = wheelbase / math.tan(alpha)
    heading0 = 0.0 if convention == 'rep103' else -0.5 * math.pi
    state, h = np.array([0.0, 0.0, heading0]), 0.01
    for _ in range(600):
        rate = bicycle_deriv(0.0, state, [v, alpha], wheelbase, convention)
        assert abs(nonholonomic_residual(state, rate, convention)) < 1e-12
        state = rk4_step(bicycle_deriv, 0.0, state, h, [v, alpha], wheelbase, convention)
    turn = v * 6.0 / radius
    np.testing.assert_allclose(state[:2], [radius * math.sin(turn),
                                           radius * (1.0 - math.cos(turn))], atol=1e-9)
    assert state[2] == pytest.approx(heading0 + turn)
    sol = solve_ivp(bicycle_deriv, (0.0, 6.0), [0.0, 0.0, heading0],
                    args=([v, alpha], wheelbase, convention), rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(state, sol.y[:, -1], atol=1e-8)


def test_deriv_rejects_bad_shapes():
    with pytest.raises(ValueError, match='state'):
        bicycle_deriv(0.0, [0.0, 0.0], [1.0, 0.1], 1.0)
    with pytest.raises(ValueError, match='command'):
        bicycle_deriv(0.0, [0.0, 0.0, 0.0], [1.0], 1.0)
    with pytest.raises(ValueError, match='convention'):
        bicycle_deriv(0.0, [0.0, 0.0, 0.0], [1.0, 0.1], 1.0, 'ned')
