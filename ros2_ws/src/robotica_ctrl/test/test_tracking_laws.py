"""
Tests of robotica_ctrl.mobile.tracking_laws: every law built by name, behind one interface.

References: a unicycle (and a bicycle with the steering lag (9.9)) integrated here, a bicycle
x' = v cos θ, y' = v sin θ, θ' = v tan α / l (book (4.119)) driven in reverse; Ejemplo
9.1's finding (book §9.3.1) that the actuator lag accentuates the oscillation of a small
look-ahead L; the ramp of Ejemplo 4.9 (c) worked by hand.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import straight_line
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.reversing_pure_pursuit import ReversingPurePursuit
from robotica_ctrl.mobile.tracker_base import TrackerOutput
from robotica_ctrl.mobile.tracking_laws import (check_gains, law_defaults, law_for_path,
                                                LAW_PARAMETERS, LAWS, make_law, steering_angle)
from robotica_kin.parameter_specs import ParameterError

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
    assert set(LAW_PARAMETERS) == {*LAWS, 'reversing_pure_pursuit', 'open_loop'}
    for law in LAW_PARAMETERS:
        for name, spec in LAW_PARAMETERS[law].items():
            assert spec.description
            if spec.choices:
                assert spec.default in spec.choices
            elif isinstance(spec.default, tuple):   # a list of numbers: no range
                assert spec.low is None and spec.high is None
            else:
                assert spec.low <= spec.default <= spec.high, (law, name)
        make_law(law, PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0])), law_defaults(law))


@pytest.mark.parametrize('law', LAW_PARAMETERS)
def test_every_law_answers_the_one_output_and_takes_its_gains(law):
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    tracker = make_law(law, path)
    out = tracker.update([0.0, 0.1, 0.0], 0.0, 0.5)
    assert isinstance(out, TrackerOutput) and out.target_point.shape == (2,)
    with pytest.raises(ValueError):
        out.target_point[0] = 1.0
    with pytest.raises(AttributeError):
        out.linear = 1.0  # type: ignore[misc]
    tracker.set_gains(law_defaults(law))   # every gain by its parameter's name
    tracker.reset()
    assert tracker.update([0.0, 0.1, 0.0], 0.0, 0.5)[:3] == pytest.approx(out[:3], nan_ok=True)


def test_open_loop_is_a_law_of_the_registry():
    # Ej. 4.9 (c): c = 0.25 m, b = 1 m, left wheel 1 rad/s, right 0.1 t rad/s:
    # v = c (0.1 t + 1) / 2, w = c (0.1 t - 1) / b; at t = 7.5 s: 0.21875 m/s, -0.0625 rad/s.
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    law = make_law('open_loop', path, {'times': [0.0, 30.0], 'linear': [0.125, 0.5],
                                       'angular': [-0.25, 0.5]})
    out = law.update([9.0, -9.0, 3.0], 7.5)   # the pose is not read
    assert (out.linear, out.angular) == pytest.approx((0.21875, -0.0625), abs=1e-15)
    assert math.isnan(out.cross_track) and math.isnan(out.heading_error)
    assert np.isnan(out.target_point).all() and not out.finished
    law.set_gains({'linear': [0.0, 0.0]})
    assert law.update([0.0, 0.0, 0.0], 7.5).linear == 0.0
    with pytest.raises(ValueError, match='same length'):
        law.set_gains({'times': [0.0]})
    assert law_defaults('open_loop') == {'times': (0.0,), 'linear': (0.0,), 'angular': (0.0,)}
    with pytest.raises(ValueError, match='increase'):
        make_law('open_loop', path, {'times': [0.0, 0.0], 'linear': [1.0, 1.0],
                                     'angular': [0.0, 0.0]})


def test_a_path_is_timed_when_its_stamps_increase_strictly():
    points = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]]   # a duplicate point (a stop)
    _, path, timed = law_for_path('trajectory_tracking', points, times=[0.0, 1.0, 2.0, 3.0])
    assert timed and path.length == 2.0
    assert not law_for_path('trajectory_tracking', points, times=[0.0, 1.0, 1.0, 3.0])[2]
    assert not law_for_path('pure_pursuit', points)[2]
    with pytest.raises(ValueError, match='at least 2 distinct points'):
        law_for_path('pure_pursuit', [[1.0, 1.0], [1.0, 1.0]])


def test_gains_are_checked_against_their_specs_then_together():
    with pytest.raises(ParameterError) as info:
        check_gains('pure_pursuit', {'lookahead_distance': 0.0})
    assert (info.value.name, info.value.reason) == ('lookahead_distance',
                                                    'must be in [0.01, 100], got 0.0')
    with pytest.raises(ValueError, match='minimum <= maximum'):
        check_gains('adaptive_pure_pursuit', {'min_lookahead': 3.0, 'max_lookahead': 1.0})


def test_reversing_pure_pursuit_is_built_by_name_with_pure_pursuits_gains():
    assert LAW_PARAMETERS['reversing_pure_pursuit'] == LAW_PARAMETERS['pure_pursuit']
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    law = make_law('reversing_pure_pursuit', path, {'lookahead_distance': 1.0})
    assert isinstance(law, ReversingPurePursuit) and law.pieces == 1
    # Without postures they face along the path: pure pursuit itself, command for command.
    plain = PurePursuit(path, PurePursuitParams(lookahead_distance=1.0))
    for pose in ([0.0, 0.3, 0.0], [1.0, -0.2, 0.4], [2.5, 0.1, -0.3]):
        assert law.update(pose, 0.0)[:4] == pytest.approx(plain.update(pose, 0.0)[:4])
    check_gains('reversing_pure_pursuit', {'lookahead_distance': 1.0})
    with pytest.raises(ParameterError) as info:
        check_gains('reversing_pure_pursuit', {'desired_linear_velocity': -0.5})
    assert info.value.name == 'desired_linear_velocity'
    with pytest.raises(ValueError, match='must not exceed'):
        check_gains('reversing_pure_pursuit', {'desired_linear_velocity': 0.1,
                                               'min_approach_velocity': 0.2})
    with pytest.raises(ValueError, match='has no gain'):
        check_gains('reversing_pure_pursuit', {'k1': 1.0})


def test_headings_that_reverse_make_the_law_reverse_after_the_cusp():
    # Forward 1 m along +x, then back to the start, the heading 0 throughout (the cusp point
    # repeated, as a planner may give it): forward commands on the way out, one stop at the
    # cusp, then v < 0. Other laws ignore the headings.
    x = np.concatenate([np.linspace(0.0, 1.0, 11), np.linspace(1.0, 0.0, 11)])
    points = np.column_stack([x, np.zeros_like(x)])
    law, path, timed = law_for_path('reversing_pure_pursuit', points,
                                    headings=np.zeros(len(x)))
    assert law.pieces == 2 and path.length == pytest.approx(2.0) and not timed
    commands = [law.update([xk, 0.0, 0.0], 0.0).linear for xk in np.arange(0.0, 1.0, 0.25)]
    assert min(commands) > 0.0
    assert law.update([1.0, 0.0, 0.0], 0.0)[:2] == (0.0, 0.0)   # the stop at the cusp
    out = law.update([1.0, 0.0, 0.0], 0.0)
    assert out.linear == pytest.approx(-0.5) and out.angular == pytest.approx(0.0, abs=1e-12)
    assert out.extras['direction'] == -1 and not out.finished
    assert law_for_path('pure_pursuit', points, headings=np.zeros(len(x)))[0].update(
        [0.0, 0.0, 0.0], 0.0).linear > 0.0
    with pytest.raises(ValueError, match='headings must be one per point'):
        law_for_path('reversing_pure_pursuit', points, headings=[0.0])
    with pytest.raises(ValueError, match='finite'):
        law_for_path('reversing_pure_pursuit', points, headings=np.full(len(x), math.nan))


def test_a_bicycle_reversing_onto_a_path_with_the_steering_of_the_laws_yaw_rate():
    # A reverse path from (3, 0) to (0, 0), heading 0 (the car backs along -x). The car starts
    # 0.3 m left of it (+y) facing +x: the law's ω through α = atan(l ω / v) of the node gives
    # the bicycle exactly θ' = v tan α / l = ω with v < 0, and it backs onto the path.
    wheelbase, dt = 1.5, 0.01
    x = np.linspace(3.0, 0.0, 31)
    law, _, _ = law_for_path('reversing_pure_pursuit', np.column_stack([x, np.zeros(31)]),
                             {'lookahead_distance': 1.0}, headings=np.zeros(31))
    pose = np.array([3.0, 0.3, 0.0])
    first = law.update(pose, 0.0)
    assert first.cross_track == pytest.approx(0.3) and first.heading_error == 0.0
    assert first.linear < 0.0 and first.angular > 0.0   # backing to the right: nose turns left
    law.reset()
    cross = []
    for k in range(2000):
        out = law.update(pose, k * dt)
        if out.finished:
            break
        v, w = out.linear, out.angular
        alpha = steering_angle(v, w, wheelbase)
        assert v < 0.0 and v * math.tan(alpha) / wheelbase == pytest.approx(w, abs=1e-12)
        pose = pose + dt * np.array([v * math.cos(pose[2]), v * math.sin(pose[2]),
                                     v * math.tan(alpha) / wheelbase])
        cross.append(out.cross_track)
    assert out.finished and pose[0] < 0.1
    assert abs(pose[1]) < 0.02 and abs(pose[2]) < 0.05
    assert max(abs(c) for c in cross[len(cross) // 2:]) < 0.05
