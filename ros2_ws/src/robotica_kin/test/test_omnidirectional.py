"""Tests of robotica_kin.mobile.omnidirectional (book §2.3.1.7, §9.4.1; slides [S] §13.1)."""

import dataclasses
import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book, wrap_to_pi
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.omnidirectional import (
    mecanum_direct,
    mecanum_inverse,
    MecanumParams,
    omni_deriv,
    omni_three_direct,
    omni_three_inverse,
    OmniThreeParams,
)
from scipy.integrate import solve_ivp

OMNI = OmniThreeParams(wheel_radius=0.05, base_radius=0.2)
MECANUM = MecanumParams(wheel_radius=0.05, half_length=0.2, half_width=0.15)
VELOCITY = st.floats(-3.0, 3.0)
RATE = st.floats(-5.0, 5.0)
DIMENSION = st.floats(0.02, 1.0)
S3 = math.sqrt(3.0) / 2.0


def general_wheel_matrix(positions, drive_angles, roller_angles, radius):
    """
    Wheel Jacobian of Modern Robotics' general wheel model, built independently here.

    Wheel i at (x_i, y_i) drives along angle β_i; its rollers let it slide freely at γ_i from
    the driving direction: u_i = (1/r) [1, tan γ_i] R(β_i)ᵀ [v_x - ω y_i, v_y + ω x_i].
    Rows act on (v_x, v_y, ω).
    """
    rows = []
    for (x, y), beta, gamma in zip(positions, drive_angles, roller_angles):
        c, s = math.cos(beta), math.sin(beta)
        along = np.array([c, s])
        across = np.array([-s, c])
        direction = (along + math.tan(gamma) * across) / radius
        rows.append([direction[0], direction[1], -direction[0] * y + direction[1] * x])
    return np.array(rows)


def omni_reference(params):
    beta = params.wheel_angles
    positions = [(params.base_radius * math.cos(b), params.base_radius * math.sin(b))
                 for b in beta]
    return general_wheel_matrix(positions, [b + 0.5 * math.pi for b in beta], [0.0] * 3,
                                params.wheel_radius)


def mecanum_reference(params):
    a, b = params.half_length, params.half_width
    positions = [(a, b), (a, -b), (-a, b), (-a, -b)]  # FL, FR, RL, RR
    rollers = [-0.25 * math.pi, 0.25 * math.pi, 0.25 * math.pi, -0.25 * math.pi]
    return general_wheel_matrix(positions, [0.0] * 4, rollers, params.wheel_radius)


def test_omni_params():
    assert OMNI.wheel_angles == pytest.approx((0.0, 2 * math.pi / 3, 4 * math.pi / 3))
    custom = OmniThreeParams(0.05, 0.2, [0.5, 2.0, 4.0])  # type: ignore[arg-type]
    assert custom.wheel_angles == (0.5, 2.0, 4.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        OMNI.base_radius = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'wheel_radius': 0.0, 'base_radius': 0.2}, 'wheel_radius'),
    ({'wheel_radius': 0.05, 'base_radius': math.nan}, 'base_radius'),
    ({'wheel_radius': 0.05, 'base_radius': 0.2, 'wheel_angles': (0.0, 1.0)}, 'wheel_angles'),
    ({'wheel_radius': 0.05, 'base_radius': 0.2, 'wheel_angles': (0.0, 1.0, math.inf)},
     'wheel_angles'),
    ({'wheel_radius': 0.05, 'base_radius': 0.2, 'wheel_angles': (0.0, 0.0, math.pi)},
     'degrees of freedom'),
])
def test_omni_params_reject_bad_values(kwargs, match):
    with pytest.raises(ValueError, match=match):
        OmniThreeParams(**kwargs)


def test_omni_pure_translation_and_rotation_by_hand():
    """β = 0, 120°, 240°: r ω_i = -sin β_i v_x + cos β_i v_y + L ω."""
    r, big_l = 0.05, 0.2
    np.testing.assert_allclose(omni_three_inverse(OMNI, 1.0, 0.0, 0.0),
                               np.array([0.0, -S3, S3]) / r, atol=1e-12)
    np.testing.assert_allclose(omni_three_inverse(OMNI, 0.0, 1.0, 0.0),
                               np.array([1.0, -0.5, -0.5]) / r, atol=1e-12)
    np.testing.assert_allclose(omni_three_inverse(OMNI, 0.0, 0.0, 1.0),
                               np.full(3, big_l / r), atol=1e-12)
    assert omni_three_direct(OMNI, np.array([0.0, -S3, S3]) / r) == pytest.approx(
        (1.0, 0.0, 0.0), abs=1e-12)
    assert omni_three_direct(OMNI, [4.0, 4.0, 4.0]) == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)


@given(VELOCITY, VELOCITY, RATE, DIMENSION, DIMENSION,
       st.lists(st.floats(-math.pi, math.pi), min_size=3, max_size=3))
def test_omni_matches_the_general_wheel_model(vx, vy, omega, radius, base, angles):
    """Each wheel's rim speed is its contact point's velocity along its driving direction."""
    try:
        params = OmniThreeParams(radius, base, tuple(angles))  # type: ignore[arg-type]
    except ValueError:
        return  # a placement without three degrees of freedom
    expected = omni_reference(params) @ np.array([vx, vy, omega])
    np.testing.assert_allclose(omni_three_inverse(params, vx, vy, omega), expected, atol=1e-9)


@given(VELOCITY, VELOCITY, RATE)
def test_omni_round_trips(vx, vy, omega):
    speeds = omni_three_inverse(OMNI, vx, vy, omega)
    assert speeds.shape == (3,) and speeds.dtype == np.float64
    assert omni_three_direct(OMNI, speeds) == pytest.approx((vx, vy, omega), abs=1e-9)
    back = omni_three_inverse(OMNI, *omni_three_direct(OMNI, speeds))
    np.testing.assert_allclose(back, speeds, atol=1e-9)


def test_mecanum_params_validation():
    for field in ('wheel_radius', 'half_length', 'half_width'):
        values = {'wheel_radius': 0.05, 'half_length': 0.2, 'half_width': 0.15}
        values[field] = -1.0
        with pytest.raises(ValueError, match=field):
            MecanumParams(**values)


def test_mecanum_pure_motions_by_hand():
    """Forward: all wheels alike; strafe left: FL, RR back; spin: left side back (k = 0.35)."""
    r, k = 0.05, 0.35
    np.testing.assert_allclose(mecanum_inverse(MECANUM, 1.0, 0.0, 0.0), np.full(4, 1.0 / r))
    np.testing.assert_allclose(mecanum_inverse(MECANUM, 0.0, 1.0, 0.0),
                               np.array([-1.0, 1.0, 1.0, -1.0]) / r)
    np.testing.assert_allclose(mecanum_inverse(MECANUM, 0.0, 0.0, 1.0),
                               np.array([-k, k, -k, k]) / r)
    assert mecanum_direct(MECANUM, np.full(4, 20.0)) == pytest.approx((1.0, 0.0, 0.0))
    assert mecanum_direct(MECANUM, np.array([-k, k, -k, k]) / r) == pytest.approx(
        (0.0, 0.0, 1.0))


@given(VELOCITY, VELOCITY, RATE, DIMENSION, DIMENSION, DIMENSION)
def test_mecanum_matches_the_general_wheel_model(vx, vy, omega, radius, a, b):
    """45° rollers in the usual layout (FL, RR at -45°; FR, RL at +45°), independent matrix."""
    params = MecanumParams(radius, a, b)
    expected = mecanum_reference(params) @ np.array([vx, vy, omega])
    np.testing.assert_allclose(mecanum_inverse(params, vx, vy, omega), expected, atol=1e-9)


@given(VELOCITY, VELOCITY, RATE)
def test_mecanum_round_trip(vx, vy, omega):
    speeds = mecanum_inverse(MECANUM, vx, vy, omega)
    assert mecanum_direct(MECANUM, speeds) == pytest.approx((vx, vy, omega), abs=1e-9)


@given(st.lists(st.floats(-50.0, 50.0), min_size=4, max_size=4), DIMENSION, DIMENSION,
       DIMENSION)
def test_mecanum_direct_is_least_squares(speeds, radius, a, b):
    """Inconsistent wheel speeds (a slipping wheel): numpy's lstsq on the reference matrix."""
    params = MecanumParams(radius, a, b)
    expected, *_ = np.linalg.lstsq(mecanum_reference(params), np.array(speeds), rcond=None)
    np.testing.assert_allclose(mecanum_direct(params, speeds), expected, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize('function', [omni_three_direct, mecanum_direct])
def test_direct_rejects_bad_wheel_speeds(function):
    params = OMNI if function is omni_three_direct else MECANUM
    with pytest.raises(ValueError, match='wheel_speeds'):
        function(params, [1.0, 2.0])
    with pytest.raises(ValueError, match='wheel_speeds'):
        function(params, [math.nan] * (3 if function is omni_three_direct else 4))


def test_inverse_rejects_non_finite_twist():
    with pytest.raises(ValueError, match='vy'):
        omni_three_inverse(OMNI, 0.0, math.nan, 0.0)
    with pytest.raises(ValueError, match='omega'):
        mecanum_inverse(MECANUM, 0.0, 0.0, math.inf)


@given(st.floats(-math.pi, math.pi), VELOCITY, VELOCITY, RATE)
def test_omni_deriv_rotates_the_twist_into_the_world(theta, vx, vy, omega):
    rate = omni_deriv(0.0, [1.0, 2.0, theta], [vx, vy, omega])
    c, s = math.cos(theta), math.sin(theta)
    np.testing.assert_allclose(rate, [c * vx - s * vy, s * vx + c * vy, omega], atol=1e-12)
    phi = theta - 0.5 * math.pi
    book = omni_deriv(0.0, [1.0, 2.0, phi], [vx, vy, omega], 'book')
    np.testing.assert_allclose(book, rate, atol=1e-12)
    assert wrap_to_pi(heading_from_book(phi) - theta) == pytest.approx(0.0, abs=1e-12)


def test_holonomic_base_translates_while_spinning():
    """
    Drive a constant world velocity (1, 0.5) m/s while spinning at 1 rad/s.

    The wheel commands come from the twist in base_link (the world velocity rotated by -θ);
    rk4_step and solve_ivp agree with the straight line x = t, y = 0.5 t, θ = t.
    """
    def wheel_command(t):
        c, s = math.cos(t), math.sin(t)
        return omni_three_inverse(OMNI, c * 1.0 + s * 0.5, -s * 1.0 + c * 0.5, 1.0)

    def f(t, state):
        return omni_deriv(t, state, omni_three_direct(OMNI, wheel_command(t)))

    state, h = np.zeros(3), 0.01
    for k in range(300):
        state = rk4_step(f, k * h, state, h)
    np.testing.assert_allclose(state, [3.0, 1.5, 3.0], atol=1e-9)
    sol = solve_ivp(f, (0.0, 3.0), [0.0, 0.0, 0.0], rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(sol.y[:, -1], state, atol=1e-8)
