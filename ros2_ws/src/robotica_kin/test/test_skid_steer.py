"""Tests of robotica_kin.mobile.skid_steer (book §2.3.1.4; Martínez et al. 2005)."""

import dataclasses
import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.differential_drive import (
    DifferentialDriveParams,
    twist_to_wheel_speeds,
    wheel_speeds_to_twist,
)
from robotica_kin.mobile.skid_steer import skid_steer_direct, skid_steer_inverse, SkidSteerParams
from robotica_kin.mobile.unicycle import nonholonomic_residual, unicycle_deriv

WHEEL_SPEED = st.floats(-50.0, 50.0)
DIMENSION = st.floats(0.01, 3.0)
SCALE = st.floats(1.0, 3.0)
SLIP = st.floats(0.0, 0.9)


def test_params_defaults_and_validation():
    params = SkidSteerParams(wheel_radius=0.1, track=0.5)
    assert (params.icr_scale, params.longitudinal_slip, params.effective_track) == (1.0, 0.0, 0.5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        params.track = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(('field', 'value'), [
    ('wheel_radius', 0.0), ('wheel_radius', math.nan), ('track', -0.5), ('track', math.inf),
    ('icr_scale', 0.99), ('icr_scale', math.nan), ('icr_scale', math.inf),
    ('longitudinal_slip', -0.1), ('longitudinal_slip', 1.0), ('longitudinal_slip', math.nan),
])
def test_params_reject_bad_values(field, value):
    values = {'wheel_radius': 0.1, 'track': 0.5, 'icr_scale': 1.2, 'longitudinal_slip': 0.1}
    values[field] = value
    with pytest.raises(ValueError, match=field):
        SkidSteerParams(**values)


@given(WHEEL_SPEED, WHEEL_SPEED, DIMENSION, DIMENSION)
def test_without_slip_it_is_the_differential_drive(omega_left, omega_right, radius, track):
    """χ = 1, s = 0: (4.109)-(4.112) of differential_drive, both directions."""
    skid = SkidSteerParams(radius, track)
    diff = DifferentialDriveParams(radius, track)
    assert skid_steer_direct(skid, omega_left, omega_right) == pytest.approx(
        wheel_speeds_to_twist(diff, omega_left, omega_right), rel=1e-12, abs=1e-12)
    v, omega = omega_left * radius, omega_right  # any twist
    assert skid_steer_inverse(skid, v, omega) == pytest.approx(
        twist_to_wheel_speeds(diff, v, omega), rel=1e-12, abs=1e-12)


@given(WHEEL_SPEED, WHEEL_SPEED, DIMENSION, DIMENSION, SCALE, SLIP)
def test_round_trips(omega_left, omega_right, radius, track, scale, slip):
    params = SkidSteerParams(radius, track, scale, slip)
    v, omega = skid_steer_direct(params, omega_left, omega_right)
    assert skid_steer_inverse(params, v, omega) == pytest.approx(
        (omega_left, omega_right), rel=1e-9, abs=1e-9)
    back = skid_steer_direct(params, *skid_steer_inverse(params, v, omega))
    assert back == pytest.approx((v, omega), rel=1e-9, abs=1e-12)


def test_icr_scale_and_slip_by_hand():
    """Wheel radius 0.1 m, b = 0.5 m, χ = 1.6 (effective track 0.8 m), s = 0.2."""
    params = SkidSteerParams(0.1, 0.5, icr_scale=1.6, longitudinal_slip=0.2)
    # straight: only slip matters, v = 0.8 · 0.1 · 10
    assert skid_steer_direct(params, 10.0, 10.0) == pytest.approx((0.8, 0.0))
    # spin: ω = 0.8 · 0.1 · (10 - (-10)) / 0.8 = 2, slower than the differential drive's 4
    assert skid_steer_direct(params, -10.0, 10.0) == pytest.approx((0.0, 2.0))
    assert wheel_speeds_to_twist(DifferentialDriveParams(0.1, 0.5), -10.0, 10.0)[1] == (
        pytest.approx(4.0))


@given(WHEEL_SPEED, WHEEL_SPEED, DIMENSION, SCALE, SLIP)
def test_sides_move_about_their_icrs(omega_left, omega_right, track, scale, slip):
    """
    ICR geometry of the model: the body point at (0, ±χ b/2) moves with its side's ground speed.

    That speed is (1 - s) r ω_side along x; the rigid-body velocity there is v ∓ ω χ b/2.
    """
    radius = 0.2
    params = SkidSteerParams(radius, track, scale, slip)
    v, omega = skid_steer_direct(params, omega_left, omega_right)
    half = 0.5 * scale * track
    assert v - omega * half == pytest.approx((1 - slip) * radius * omega_left, abs=1e-9)
    assert v + omega * half == pytest.approx((1 - slip) * radius * omega_right, abs=1e-9)


def test_guide_point_has_no_lateral_velocity_along_a_trajectory():
    """Symmetric ICRs: the centre moves like a unicycle, the residual (4.104) stays zero."""
    params = SkidSteerParams(0.1, 0.5, icr_scale=1.4, longitudinal_slip=0.05)
    state = np.array([0.0, 0.0, 0.0])
    for k in range(200):
        twist = skid_steer_direct(params, 5.0 + math.sin(0.1 * k), 8.0)
        rate = unicycle_deriv(0.0, state, twist)
        assert abs(nonholonomic_residual(state, rate)) < 1e-12
        state = rk4_step(unicycle_deriv, 0.0, state, 0.02, twist)


@pytest.mark.parametrize('bad', [math.nan, math.inf])
def test_rejects_non_finite(bad):
    params = SkidSteerParams(0.1, 0.5)
    with pytest.raises(ValueError, match='omega_left'):
        skid_steer_direct(params, bad, 0.0)
    with pytest.raises(ValueError, match='omega'):
        skid_steer_inverse(params, 0.0, bad)
