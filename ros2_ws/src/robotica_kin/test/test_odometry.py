"""
Tests of robotica_kin.mobile.odometry (book §4.7.2, §4.7.5; catalog §2.7, §2.9, §13.6).

The encoder front end (ticks, twist, time) is tested in test_odometry_fusion.py.
"""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import wrap_to_pi
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.differential_drive import (
    differential_drive_deriv,
    DifferentialDriveParams,
)
from robotica_kin.mobile.odometry import odometry_increment, ODOMETRY_METHODS

PARAMS = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)


def arc_end(pose, distance, turn):
    """
    Closed-form end of a circular arc, built in the body frame and rotated into the world.

    In ``base_link`` (x forward) an arc of length s and turn Δθ ends at
    (R sin Δθ, R (1 - cos Δθ)) with R = s / Δθ: book (4.91)-(4.92) in REP-103.
    """
    x0, y0, theta0 = pose
    if turn == 0.0:
        forward, left = distance, 0.0
    else:
        radius = distance / turn
        forward, left = radius * math.sin(turn), radius * (1.0 - math.cos(turn))
    c, s = math.cos(theta0), math.sin(theta0)
    return np.array([x0 + c * forward - s * left, y0 + s * forward + c * left, theta0 + turn])


def pose_error(pose, expected):
    position = np.hypot(pose[0] - expected[0], pose[1] - expected[1])
    return max(position, abs(wrap_to_pi(pose[2] - expected[2])))


@pytest.mark.parametrize('method', ODOMETRY_METHODS)
def test_increment_straight_line(method):
    pose = odometry_increment([1.0, 2.0, 0.7], 0.3, 0.3, 0.4, method)
    np.testing.assert_allclose(pose, [1.0 + 0.3 * math.cos(0.7), 2.0 + 0.3 * math.sin(0.7), 0.7],
                               atol=1e-15)


@pytest.mark.parametrize('method', ODOMETRY_METHODS)
def test_increment_spin_in_place(method):
    pose = odometry_increment([1.0, 2.0, 0.7], -0.1, 0.1, 0.4, method)
    np.testing.assert_allclose(pose, [1.0, 2.0, 0.7 + 0.2 / 0.4], atol=1e-15)


def test_increment_exact_quarter_circle():
    """R = 1 m, Δθ = π/2 from the origin ends at (1, 1, π/2)."""
    b = 0.4
    quarter = 0.5 * math.pi
    pose = odometry_increment([0.0, 0.0, 0.0], (1.0 - b / 2) * quarter, (1.0 + b / 2) * quarter, b)
    np.testing.assert_allclose(pose, [1.0, 1.0, quarter], atol=1e-12)


@given(
    st.floats(-5.0, 5.0), st.floats(-5.0, 5.0), st.floats(-math.pi, math.pi),
    st.floats(-2.0, 2.0), st.floats(-3.0, 3.0).filter(lambda turn: abs(turn) > 1e-6),
)
def test_increment_exact_arc_matches_body_frame_arc(x0, y0, theta0, distance, turn):
    b = 0.5
    delta_left, delta_right = distance - 0.5 * b * turn, distance + 0.5 * b * turn
    pose = odometry_increment([x0, y0, theta0], delta_left, delta_right, b, 'exact_arc')
    assert -math.pi < pose[2] <= math.pi
    assert pose_error(pose, arc_end((x0, y0, theta0), distance, turn)) < 1e-9


def test_increment_exact_arc_is_continuous_at_the_small_angle_guard():
    b, distance = 0.4, 0.5
    poses = [
        odometry_increment([0.0, 0.0, 1.0], distance - 0.5 * b * turn, distance + 0.5 * b * turn,
                           b, 'exact_arc')
        for turn in (0.0, 0.5e-9, 2.0e-9, 1.0e-7)
    ]
    for pose in poses[1:]:
        np.testing.assert_allclose(pose, poses[0], atol=1e-7)
    np.testing.assert_allclose(poses[0], [distance * math.cos(1.0), distance * math.sin(1.0), 1.0])


@pytest.mark.parametrize('method', ODOMETRY_METHODS)
def test_increment_wraps_heading(method):
    pose = odometry_increment([0.0, 0.0, 3.0], 0.0, 0.2, 0.4, method)
    assert pose[2] == pytest.approx(3.5 - 2.0 * math.pi)


def test_increment_methods_differ_as_documented():
    """One step of the slides' update uses θ + Δθ, the midpoint θ + Δθ/2."""
    b, delta_left, delta_right = 0.4, 0.1, 0.3
    delta_c, delta_theta = 0.2, 0.5
    euler = odometry_increment([0.0, 0.0, 0.0], delta_left, delta_right, b, 'euler')
    midpoint = odometry_increment([0.0, 0.0, 0.0], delta_left, delta_right, b, 'midpoint')
    np.testing.assert_allclose(
        euler, [delta_c * math.cos(delta_theta), delta_c * math.sin(delta_theta), delta_theta])
    np.testing.assert_allclose(
        midpoint,
        [delta_c * math.cos(delta_theta / 2), delta_c * math.sin(delta_theta / 2), delta_theta])


@pytest.mark.parametrize(('pose', 'deltas', 'b', 'method', 'match'), [
    ([0.0, 0.0], (0.1, 0.1), 0.4, 'exact_arc', 'pose'),
    ([0.0, math.nan, 0.0], (0.1, 0.1), 0.4, 'exact_arc', 'pose'),
    ([0.0, 0.0, 0.0], (math.inf, 0.1), 0.4, 'exact_arc', 'wheel travels'),
    ([0.0, 0.0, 0.0], (0.1, math.nan), 0.4, 'exact_arc', 'wheel travels'),
    ([0.0, 0.0, 0.0], (0.1, 0.1), 0.0, 'exact_arc', 'wheel_separation'),
    ([0.0, 0.0, 0.0], (0.1, 0.1), -0.4, 'exact_arc', 'wheel_separation'),
    ([0.0, 0.0, 0.0], (0.1, 0.1), math.nan, 'exact_arc', 'wheel_separation'),
    ([0.0, 0.0, 0.0], (0.1, 0.1), 0.4, 'rk4', 'method'),
])
def test_increment_rejects_bad_input(pose, deltas, b, method, match):
    with pytest.raises(ValueError, match=match):
        odometry_increment(pose, *deltas, b, method)


def test_odometry_matches_simulated_piecewise_constant_wheel_speeds():
    """Cross-check with the model: wheel angles from rk4_step, exact arc per segment."""
    segments = [(1.0, 3.0, 2.0), (2.0, 2.0, 1.0), (-1.0, 1.0, 0.5), (4.0, -0.5, 1.5)]
    state = np.array([0.5, -1.0, 2.0, 0.0, 0.0])
    pose = state[:3].copy()
    for omega_left, omega_right, duration in segments:
        previous = state.copy()
        for _ in range(round(duration / 0.01)):
            state = rk4_step(differential_drive_deriv, 0.0, state, 0.01,
                             (omega_left, omega_right), PARAMS)
        travel = PARAMS.wheel_radius * (state[3:] - previous[3:])
        pose = odometry_increment(pose, travel[0], travel[1], PARAMS.wheel_separation)
    assert pose_error(pose, state[:3]) < 1e-9
