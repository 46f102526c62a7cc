"""Tests of robotica_kin.mobile.differential_drive (book §4.7.4-§4.7.5, catalog §2.8, §13.2)."""

import dataclasses
import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book, heading_to_book, wrap_to_pi
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.differential_drive import (
    differential_drive_deriv,
    DifferentialDriveParams,
    twist_to_wheel_speeds,
    wheel_speeds_to_twist,
)

EJ_4_9 = DifferentialDriveParams(wheel_radius=0.25, wheel_separation=1.0)
SPEEDS = st.floats(min_value=-50.0, max_value=50.0, allow_nan=False)
LENGTHS = st.floats(min_value=0.01, max_value=5.0, allow_nan=False)


def simulate(params, state0, wheel_speeds_at, duration, h):
    """Integrate the model with rk4_step, wheel speeds evaluated at each stage time."""
    def f(t, state):
        return differential_drive_deriv(t, state, wheel_speeds_at(t), params)

    state = np.asarray(state0, dtype=np.float64)
    for k in range(round(duration / h)):
        state = rk4_step(f, k * h, state, h)
    return state


def test_params_defaults():
    params = DifferentialDriveParams()
    assert (params.wheel_radius, params.wheel_separation) == (0.1, 0.4)


@pytest.mark.parametrize('field', ['wheel_radius', 'wheel_separation'])
@pytest.mark.parametrize('value', [0.0, -0.1, math.nan, math.inf])
def test_params_reject_bad_dimensions(field, value):
    with pytest.raises(ValueError, match=field):
        DifferentialDriveParams(**{field: value})


def test_params_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        EJ_4_9.wheel_radius = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(('omega_left', 'omega_right', 'v', 'omega'), [
    (1.0, 1.0, 0.25, 0.0),     # Ejemplo 4.9 (a): straight
    (1.0, 1.2, 0.275, 0.05),   # (b): v = 0.25 (2.2)/2, ω = 0.25 (0.2)/1
    (-1.0, 1.0, 0.0, 0.5),     # (d): spin in place, ω = 0.25 (2)/1
    (2.0, 0.0, 0.25, -0.5),    # right wheel stopped: clockwise about it
])
def test_wheel_speeds_to_twist_book_values(omega_left, omega_right, v, omega):
    """Book (4.109)-(4.110) with c = 0.25 m, b = 1 m (Ejemplo 4.9), computed by hand."""
    assert wheel_speeds_to_twist(EJ_4_9, omega_left, omega_right) == pytest.approx((v, omega))
    assert twist_to_wheel_speeds(EJ_4_9, v, omega) == pytest.approx((omega_left, omega_right))


def test_twist_to_wheel_speeds_turning_radius():
    """Turning about the left wheel (R = b/2) stops it; the right one moves at ω b / c."""
    params = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)
    omega_left, omega_right = twist_to_wheel_speeds(params, 0.2 * 1.5, 1.5)
    assert omega_left == pytest.approx(0.0, abs=1e-12)
    assert omega_right == pytest.approx(1.5 * 0.4 / 0.1)


@given(SPEEDS, SPEEDS, LENGTHS, LENGTHS)
def test_twist_roundtrip_is_identity(omega_left, omega_right, radius, separation):
    params = DifferentialDriveParams(radius, separation)
    v, omega = wheel_speeds_to_twist(params, omega_left, omega_right)
    back = twist_to_wheel_speeds(params, v, omega)
    assert back == pytest.approx((omega_left, omega_right), abs=1e-9)


@given(SPEEDS, SPEEDS, LENGTHS, LENGTHS)
def test_wheel_speed_roundtrip_is_identity(v, omega, radius, separation):
    params = DifferentialDriveParams(radius, separation)
    omega_left, omega_right = twist_to_wheel_speeds(params, v, omega)
    back = wheel_speeds_to_twist(params, omega_left, omega_right)
    assert back == pytest.approx((v, omega), abs=1e-9)


@pytest.mark.parametrize('bad', [math.nan, math.inf, -math.inf])
def test_twist_conversions_reject_non_finite(bad):
    with pytest.raises(ValueError):
        wheel_speeds_to_twist(EJ_4_9, bad, 1.0)
    with pytest.raises(ValueError):
        twist_to_wheel_speeds(EJ_4_9, 1.0, bad)


@given(st.floats(-10.0, 10.0), SPEEDS, SPEEDS, LENGTHS, LENGTHS)
def test_deriv_matches_book_matrix(phi, omega_left, omega_right, radius, separation):
    """Book (4.113)-(4.114), φ from the y axis, against the REP-103 form with θ = φ + π/2."""
    c, b = radius, separation
    book = np.array([
        -(c * math.sin(phi) / 2.0) * (omega_left + omega_right),
        (c * math.cos(phi) / 2.0) * (omega_left + omega_right),
        (c / b) * (omega_right - omega_left),
    ])
    state = [1.0, -2.0, heading_from_book(phi), 0.3, -0.7]
    rates = differential_drive_deriv(0.0, state, [omega_left, omega_right],
                                     DifferentialDriveParams(c, b))
    assert rates.dtype == np.float64
    np.testing.assert_allclose(rates[:3], book, atol=1e-9)
    np.testing.assert_allclose(rates[3:], [omega_left, omega_right])


@pytest.mark.parametrize(('state', 'wheel_speeds'), [
    ([0.0, 0.0, 0.0], [1.0, 1.0]),
    ([0.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    ([0.0, 0.0, math.nan, 0.0, 0.0], [1.0, 1.0]),
    ([0.0, 0.0, 0.0, 0.0, 0.0], [math.inf, 1.0]),
])
def test_deriv_rejects_bad_input(state, wheel_speeds):
    with pytest.raises(ValueError):
        differential_drive_deriv(0.0, state, wheel_speeds, EJ_4_9)


def test_straight_line():
    params = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)
    theta0, duration = 0.3, 5.0
    state = simulate(params, [1.0, 2.0, theta0, 0.0, 0.0], lambda t: (2.0, 2.0), duration, 0.05)
    distance = 0.1 * 2.0 * duration
    expected = [1.0 + distance * math.cos(theta0), 2.0 + distance * math.sin(theta0), theta0,
                2.0 * duration, 2.0 * duration]
    np.testing.assert_allclose(state, expected, atol=1e-12)


def test_spin_in_place():
    params = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)
    duration = 4.0  # ω = c (1 - (-1)) / b = 0.5 rad/s
    state = simulate(params, [1.0, 2.0, 0.3, 0.0, 0.0], lambda t: (-1.0, 1.0), duration, 0.05)
    np.testing.assert_allclose(state, [1.0, 2.0, 0.3 + 0.5 * duration, -duration, duration],
                               atol=1e-12)


def test_exact_arc():
    """Constant (v, ω) from the origin facing +x: x = (v/ω) sin ωt, y = (v/ω)(1 - cos ωt)."""
    params = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)
    v, omega, duration = 0.2, 0.5, 5.0  # wheel speeds (1, 3) rad/s
    state = simulate(params, np.zeros(5), lambda t: (1.0, 3.0), duration, 0.01)
    radius = v / omega
    assert state[0] == pytest.approx(radius * math.sin(omega * duration), abs=1e-9)
    assert state[1] == pytest.approx(radius * (1.0 - math.cos(omega * duration)), abs=1e-9)
    assert state[2] == pytest.approx(omega * duration, abs=1e-9)
    assert state[0] ** 2 + (state[1] - radius) ** 2 == pytest.approx(radius**2, abs=1e-9)


@pytest.mark.parametrize(('wheel_speeds_at', 'x', 'y', 'phi'), [
    pytest.param(lambda t: (1.0, 1.0), 5.3033, 5.3033, -0.7854, id='a-straight'),
    pytest.param(lambda t: (1.0, 1.2), 0.2654, 7.4933, 0.7146, id='b-left-turn'),
    pytest.param(lambda t: (1.0, 0.1 * t), 2.8896, 1.0715, 2.9646, id='c-ramp'),
    pytest.param(lambda t: (-1.0, 1.0), 0.0, 0.0, 14.2146, id='d-spin'),
])
def test_ejemplo_4_9(wheel_speeds_at, x, y, phi):
    """
    Ejemplo 4.9 (book §4.7.5, fig. 4.22-4.23): dead reckoning of a differential drive.

    c = 0.25 m, b = 1 m, start at the origin with φ0 = -π/4 (book convention), 30 s;
    wheel speeds (ω_i, ω_d) [rad/s]. The book only plots the paths; the final poses are the
    table of seed catalog §2.11, derived values computed by the catalog author by integrating
    (4.131). They are compared at their printed precision (4 decimals); the heading in the
    book convention, modulo 2π (case d: 14.2146 rad unwrapped). RK4 at h = 0.01 s has a
    global error of order 1e-9 here, far below that precision.
    """
    theta0 = heading_from_book(-0.25 * math.pi)
    state = simulate(EJ_4_9, [0.0, 0.0, theta0, 0.0, 0.0], wheel_speeds_at, 30.0, 0.01)
    assert state[0] == pytest.approx(x, abs=1e-4)
    assert state[1] == pytest.approx(y, abs=1e-4)
    assert wrap_to_pi(heading_to_book(state[2]) - phi) == pytest.approx(0.0, abs=1e-4)
