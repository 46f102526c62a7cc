"""
Tests of robotica_ctrl.mobile.tracking_laws: every law behind one interface.

References: a unicycle (and a bicycle with the steering lag (9.9)) integrated here; Ejemplo
9.1's finding (book §9.3.1) that the actuator lag accentuates the oscillation of a small
look-ahead L; a circle's reference posture in closed form.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import straight_line, unicycle_trajectory
from robotica_ctrl.mobile.tracking_laws import (law_defaults, LAW_PARAMETERS, LAWS, make_law,
                                                TimedPath)

STEP = 0.01   # [s]


def drive(law, pose, steps, lag=0.0, speed=None):
    """Drive a unicycle (curvature through a first-order lag ``lag`` [s]); return the errors."""
    x, y, theta = pose
    curvature = 0.0
    errors = []
    for k in range(steps):
        out = law.update([x, y, theta], k * STEP, speed)
        v = out.linear
        wanted = out.angular / v if v else 0.0
        curvature = curvature + STEP * (wanted - curvature) / lag if lag else wanted
        w = v * curvature
        x += v * math.cos(theta + w * STEP / 2) * STEP
        y += v * math.sin(theta + w * STEP / 2) * STEP
        theta += w * STEP
        errors.append(out.cross_track)
    return np.array(errors), out


@pytest.mark.parametrize('law', LAWS)
def test_every_law_reaches_a_straight_path_from_an_offset(law):
    path = PolylinePath(straight_line([0.0, 0.0], [12.0, 0.0]))
    gains = {'trajectory_tracking': {'reference_speed': 0.5},
             'gpc': {'linear_velocity': 0.5}}.get(law, {})
    errors, _ = drive(make_law(law, path, gains), (0.0, 0.3, 0.0), 1500)
    assert errors[0] == pytest.approx(0.3, abs=1e-9)   # left of the path: > 0
    assert abs(errors[-1]) < 0.02


@pytest.mark.parametrize('law', LAWS)
def test_every_law_stops_at_the_end(law):
    path = PolylinePath(straight_line([0.0, 0.0], [2.0, 0.0]))
    gains = {'trajectory_tracking': {'reference_speed': 0.5},
             'gpc': {'linear_velocity': 0.5}}.get(law, {})
    _, out = drive(make_law(law, path, gains), (0.0, 0.0, 0.0), 1500)
    assert out.finished and out.linear == 0.0 and out.angular == 0.0


def test_ejemplo_9_1_steering_lag_accentuates_oscillation():
    # The book's second run of Ejemplo 9.1 adds the steering lag (9.9), tau = 0.5 s, K = 1:
    # the oscillation grows, most for a small L (test_pure_pursuit.py checks the run without).
    path = PolylinePath(straight_line([0.0, 0.0], [15.0, 0.0]))
    crossings = {}
    for lag in (0.0, 0.5):
        for lookahead in (0.3, 0.5, 1.0, 2.0, 4.0):
            law = make_law('pure_pursuit', path, {'lookahead_distance': lookahead,
                                                  'desired_linear_velocity': 1.0,
                                                  'max_angular_velocity': 100.0})
            e, _ = drive(law, (0.0, 0.5, 0.0), 1000, lag)
            signs = np.sign(e[np.abs(e) > 1e-3])
            crossings[lag, lookahead] = int(np.count_nonzero(np.diff(signs)))
    with_lag = [crossings[0.5, L] for L in (0.3, 0.5, 1.0, 2.0, 4.0)]
    assert with_lag == sorted(with_lag, reverse=True) and with_lag[0] >= 5 * with_lag[-1]
    assert all(crossings[0.5, L] >= crossings[0.0, L] for L in (0.3, 0.5, 1.0, 2.0, 4.0))
    assert crossings[0.5, 0.3] > crossings[0.0, 0.3]


def test_timed_reference_on_an_arc_is_exact():
    # v = 0.2 m/s, w = 0.3 rad/s from (0, 0, pi/2): the circle of radius 2/3 m about (-2/3, 0).
    samples = unicycle_trajectory([0.0, 0.0, math.pi / 2], [[0.2, 0.3, 10.0]], step=0.01)
    path = PolylinePath(samples[:, :2])
    reference = TimedPath(path, samples[:, 2]).reference(4.005)
    theta = math.pi / 2 + 0.3 * 4.005
    assert reference.x == pytest.approx(-2 / 3 + 2 / 3 * math.cos(0.3 * 4.005), abs=1e-6)
    assert reference.y == pytest.approx(2 / 3 * math.sin(0.3 * 4.005), abs=1e-6)
    assert reference.theta == pytest.approx(theta, abs=1e-5)
    assert reference.v == pytest.approx(0.2, rel=1e-4)
    assert reference.omega == pytest.approx(0.3, rel=1e-3)
    after = TimedPath(path, samples[:, 2]).reference(11.0)
    assert (after.v, after.omega) == (0.0, 0.0)


def test_untimed_reference_starts_at_the_first_update():
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    law = make_law('trajectory_tracking', path, {'reference_speed': 0.5})
    first = law.update([0.0, 0.0, 0.0], 100.0)
    later = law.update([0.0, 0.0, 0.0], 102.0)
    assert first.target_point.tolist() == [0.0, 0.0]
    assert later.target_point.tolist() == pytest.approx([1.0, 0.0])
    assert later.along_track == pytest.approx(1.0)   # the robot lags 1 m behind it


def test_gpc_holds_its_command_between_samples():
    path = PolylinePath(straight_line([0.0, 0.0], [20.0, 0.0]))
    law = make_law('gpc', path, {'sample_time': 0.1})
    first = law.update([0.0, 0.5, 0.0], 0.0)
    held = law.update([0.0, 0.4, 0.0], 0.05)
    fresh = law.update([0.0, 0.4, 0.0], 0.1)
    assert held.angular == first.angular and held.cross_track == pytest.approx(0.4)
    assert fresh.angular != first.angular


def test_bad_names_and_gains_are_refused():
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    with pytest.raises(ValueError, match='law must be one of'):
        make_law('stanley', path)
    with pytest.raises(ValueError, match='has no gain'):
        make_law('pure_pursuit', path, {'k1': 1.0})
    with pytest.raises(ValueError, match='must be one of'):
        make_law('frenet', path, {'variant': 'fuzzy'})
    law = make_law('frenet', path, {'k1': 2.0})
    with pytest.raises(ValueError):
        law.set_gains({'k1': -1.0})
    with pytest.raises(ValueError, match='pose'):
        law.update([0.0, math.nan, 0.0], 0.0)


def test_parameter_specs_cover_every_law_with_valid_defaults():
    assert set(LAW_PARAMETERS) == set(LAWS)
    for law in LAWS:
        for name, spec in LAW_PARAMETERS[law].items():
            assert spec.description
            if spec.choices:
                assert spec.default in spec.choices
            else:
                assert spec.low <= spec.default <= spec.high, (law, name)
        make_law(law, PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0])), law_defaults(law))
