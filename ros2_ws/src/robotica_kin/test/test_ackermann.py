"""Tests of robotica_kin.mobile.ackermann (slides [S], catalog §13.4; book §2.3.1.1, (4.121))."""

import dataclasses
import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.mobile.ackermann import (
    ackermann_equivalent_angle,
    ackermann_front_wheel_speeds,
    ackermann_icr,
    ackermann_left_right,
    ackermann_rear_wheel_speeds,
    ackermann_wheel_angles,
    AckermannParams,
)
from robotica_kin.mobile.bicycle import bicycle_direct
from robotica_kin.mobile.differential_drive import DifferentialDriveParams, twist_to_wheel_speeds

CAR = AckermannParams(wheelbase=2.5, track=1.5, wheel_radius=0.3)
STEERING = st.floats(-1.5, 1.5)
DIMENSION = st.floats(0.2, 4.0)


def cot(angle):
    return math.cos(angle) / math.sin(angle)


def test_params_validation_and_frozen():
    for field in ('wheelbase', 'track', 'wheel_radius'):
        values = {'wheelbase': 2.5, 'track': 1.5, 'wheel_radius': 0.3}
        for bad in (0.0, -1.0, math.nan, math.inf):
            values[field] = bad
            with pytest.raises(ValueError, match=field):
                AckermannParams(**values)
    with pytest.raises(dataclasses.FrozenInstanceError):
        CAR.track = 1.0  # type: ignore[misc]


def test_slides_formulas_by_hand():
    """
    [S] §13.4 with d = 2.5 m (wheelbase), L = 1.5 m (track), R = 5 m (left turn).

    cot θ_i = (R - L/2)/d = 1.7, cot θ_o = (R + L/2)/d = 2.3, cot θ_s = R/d = 2.
    """
    theta_s = math.atan(1.0 / 2.0)
    inner, outer = ackermann_wheel_angles(CAR, theta_s)
    assert inner == pytest.approx(math.atan(1.0 / 1.7))
    assert outer == pytest.approx(math.atan(1.0 / 2.3))
    assert ackermann_left_right(CAR, theta_s) == pytest.approx((inner, outer))
    assert ackermann_icr(CAR, theta_s) == pytest.approx((0.0, 5.0))
    assert inner > theta_s > outer > 0.0


@given(STEERING.filter(lambda a: abs(a) > 1e-6), DIMENSION, DIMENSION)
def test_ackermann_condition(theta_s, wheelbase, track):
    """Ackermann condition cot θ_o - cot θ_i = track/wheelbase ([S]: L/d) on magnitudes."""
    params = AckermannParams(wheelbase, track, 0.3)
    left, right = ackermann_left_right(params, theta_s)
    assert cot(right) - cot(left) == pytest.approx(track / wheelbase, rel=1e-7, abs=1e-9)
    inner, outer = ackermann_wheel_angles(params, theta_s)
    assert (inner, outer) == ((left, right) if theta_s > 0 else (right, left))
    # cot θ_s is the mean of the two wheels' cotangents: R / wheelbase
    assert cot(theta_s) == pytest.approx(0.5 * (cot(left) + cot(right)), rel=1e-7, abs=1e-9)
    radius = abs(wheelbase * cot(theta_s))
    if radius > 0.5 * track:  # ICR outside the track: inner wheel steers more, same side
        assert abs(inner) > abs(theta_s) > abs(outer)
        sign = math.copysign(1.0, theta_s)
        assert math.copysign(1.0, inner) == math.copysign(1.0, outer) == sign
        magnitude_gap = cot(abs(outer)) - cot(abs(inner))
        assert magnitude_gap == pytest.approx(track / wheelbase, rel=1e-7)


def test_straight_ahead_and_limits():
    """R -> ∞: all angles -> 0 ([S]); θ_s = ±π/2: ICR at the rear-axle midpoint."""
    assert ackermann_left_right(CAR, 0.0) == (0.0, 0.0)
    assert ackermann_wheel_angles(CAR, 0.0) == (0.0, 0.0)
    assert ackermann_icr(CAR, 0.0) is None
    tiny = ackermann_left_right(CAR, 1e-9)
    assert tiny == pytest.approx((1e-9, 1e-9), rel=1e-6)
    left, right = ackermann_left_right(CAR, 0.5 * math.pi)
    assert right == pytest.approx(math.atan(2 * 2.5 / 1.5))
    assert left == pytest.approx(-math.atan(2 * 2.5 / 1.5))  # toe-in, the wheel rolls back
    assert ackermann_icr(CAR, 0.5 * math.pi) == pytest.approx((0.0, 0.0), abs=1e-15)


@given(STEERING, DIMENSION, DIMENSION)
def test_equivalent_angle_round_trip(theta_s, wheelbase, track):
    params = AckermannParams(wheelbase, track, 0.3)
    left, right = ackermann_left_right(params, theta_s)
    assert ackermann_equivalent_angle(params, left, right) == pytest.approx(theta_s, abs=1e-9)


def test_equivalent_angle_of_measured_angles_is_the_mean_icr():
    """Two wheel angles that disagree: the ICR distance is the mean of their estimates."""
    left, right = math.atan(2.5 / 4.0), math.atan(2.5 / 6.0)  # R_left = 4.75, R_right = 5.25
    theta_s = ackermann_equivalent_angle(CAR, left, right)
    assert CAR.wheelbase * cot(theta_s) == pytest.approx(0.5 * (4.75 + 5.25))
    assert ackermann_equivalent_angle(CAR, 0.0, 0.0) == 0.0
    with pytest.raises(ValueError, match='left'):
        ackermann_equivalent_angle(CAR, math.nan, 0.0)


@pytest.mark.parametrize('bad', [1.6, -2.0, math.nan, math.inf])
def test_rejects_steering_beyond_a_right_angle(bad):
    for function in (ackermann_left_right, ackermann_wheel_angles, ackermann_icr):
        with pytest.raises(ValueError, match='steering_angle'):
            function(CAR, bad)


@given(STEERING.filter(lambda a: abs(a) > 1e-3), st.floats(-5.0, 5.0), DIMENSION, DIMENSION)
def test_icr_by_geometry_every_wheel(theta_s, v, wheelbase, track):
    """
    Each wheel's velocity is along its heading and perpendicular to its line to the ICR.

    Body twist from the bicycle model (4.121) with the equivalent angle; the rigid-body
    velocity of a wheel at (p_x, p_y) is (v - ω p_y, ω p_x); rear wheels head along x.
    """
    params = AckermannParams(wheelbase, track, 0.3)
    _, omega = bicycle_direct(v, theta_s, wheelbase)
    icr = np.array(ackermann_icr(params, theta_s))
    left, right = ackermann_left_right(params, theta_s)
    wheels = [((wheelbase, 0.5 * track), left), ((wheelbase, -0.5 * track), right),
              ((0.0, 0.5 * track), 0.0), ((0.0, -0.5 * track), 0.0)]
    for (px, py), heading in wheels:
        velocity = np.array([v - omega * py, omega * px])
        scale = 1.0 + np.linalg.norm(velocity)
        assert velocity[0] * math.sin(heading) - velocity[1] * math.cos(heading) == (
            pytest.approx(0.0, abs=1e-9 * scale))
        arm = np.array([px, py]) - icr
        assert math.cos(heading) * arm[0] + math.sin(heading) * arm[1] == pytest.approx(
            0.0, abs=1e-9 * (1.0 + np.linalg.norm(arm)))


@given(st.floats(-5.0, 5.0), st.floats(-2.0, 2.0), DIMENSION, DIMENSION)
def test_rear_wheel_speeds_are_a_differential_drive(v, omega, track, radius):
    """The rear axle is a differential drive (4.111)-(4.112) with c = r, b = track."""
    params = AckermannParams(2.0, track, radius)
    expected = twist_to_wheel_speeds(DifferentialDriveParams(radius, track), v, omega)
    assert ackermann_rear_wheel_speeds(params, v, omega) == pytest.approx(expected)


def test_rear_wheel_speeds_by_hand():
    assert ackermann_rear_wheel_speeds(CAR, 3.0, 0.0) == pytest.approx((10.0, 10.0))
    assert ackermann_rear_wheel_speeds(CAR, 3.0, 1.0) == pytest.approx((7.5, 12.5))


@given(STEERING.filter(lambda a: abs(a) > 1e-3), st.floats(-5.0, 5.0).filter(
    lambda v: abs(v) > 1e-3))
def test_front_wheel_speeds_by_geometry(theta_s, v):
    """Each front wheel rolls at |ω| times its distance to the ICR, forwards when v > 0."""
    _, omega = bicycle_direct(v, theta_s, CAR.wheelbase)
    icr = np.array(ackermann_icr(CAR, theta_s))
    speeds = ackermann_front_wheel_speeds(CAR, v, omega)
    for speed, y_wheel in zip(speeds, (0.5 * CAR.track, -0.5 * CAR.track)):
        distance = np.linalg.norm(np.array([CAR.wheelbase, y_wheel]) - icr)
        assert abs(speed) * CAR.wheel_radius == pytest.approx(abs(omega) * distance, rel=1e-9)
        lateral = abs(icr[1]) > 0.5 * CAR.track  # wheel outside the ICR: rolls with v
        if lateral:
            assert math.copysign(1.0, speed) == math.copysign(1.0, v)


def test_front_wheel_speeds_straight_and_reverse():
    assert ackermann_front_wheel_speeds(CAR, 3.0, 0.0) == pytest.approx((10.0, 10.0))
    assert ackermann_front_wheel_speeds(CAR, -3.0, 0.0) == pytest.approx((-10.0, -10.0))
    with pytest.raises(ValueError, match='omega'):
        ackermann_front_wheel_speeds(CAR, 1.0, math.nan)
