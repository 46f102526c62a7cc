"""
Tests of robotica_ctrl.mobile.reactive_navigation: behaviours, arbitration, stall detection.

Commands are checked against the laws computed by hand: wall following (9.93) with ξ = d_ref - d
(wall on the left) and ω = -k1 v ξ - k2 v φ̃; the outer corner ω = v / d_ref; the speed of
§9.6's modulation, v (d - d_s) / (d_f - d_s) between the two distances.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.reactive_navigation import (NAVIGATOR_PARAMETERS, navigator_params,
                                                      ReactiveNavigator)
from robotica_kin.parameter_specs import ParameterError

NONE = np.zeros((0, 2))


def wall(y, x0=-0.7, x1=0.7, n=15):
    return np.array([[x, y] for x in np.linspace(x0, x1, n)])


def navigator(**values):
    return ReactiveNavigator(navigator_params(values))


def test_wall_following_law():
    nav = navigator(**{'wall.desired_distance': 0.5, 'wall.linear_velocity': 0.3})
    out = nav.update(0.0, [0.0, 0.0, 0.0], wall(0.7))
    # ξ = 0.5 - 0.7 = -0.2, φ̃ = 0: ω = -4 · 0.3 · (-0.2) = 0.24, towards the wall.
    assert out.state == 'following'
    assert out.command.linear == pytest.approx(0.3)
    assert out.command.angular == pytest.approx(0.24)
    right = navigator(**{'wall.side': 'right'}).update(0.0, [0.0, 0.0, 0.0], wall(-0.7))
    assert right.command.angular == pytest.approx(-0.24)


def test_outer_and_inner_corners():
    nav = navigator(**{'wall.desired_distance': 0.5, 'wall.linear_velocity': 0.3})
    outer = nav.update(0.0, [0.0, 0.0, 0.0], NONE)      # the wall ended
    assert outer.state == 'outer_corner'
    assert outer.command.angular == pytest.approx(0.3 / 0.5)
    front = np.array([[0.6, y] for y in np.linspace(-1.0, 1.0, 21)])
    inner = nav.update(0.0, [0.0, 0.0, 0.0], np.vstack([wall(0.5), front]))
    assert inner.state == 'inner_corner'
    assert inner.command.angular == pytest.approx(-1.5)    # away from the left wall
    # Clearance 0.6 m, between safety 0.3 and slow-down 1.0: v = 0.3 (0.6 - 0.3) / 0.7.
    assert inner.command.linear == pytest.approx(0.3 * 0.3 / 0.7)


def test_corridor_centring():
    nav = navigator(behaviour='corridor_centring')
    out = nav.update(0.0, [0.0, 0.0, 0.0], np.vstack([wall(1.0), wall(-0.6)]))
    # ξ = (0.6 - 1.0) / 2 = -0.2 (right of the centre): ω = -4 · 0.3 · (-0.2) = 0.24, left.
    assert out.state == 'centring'
    assert out.command.angular == pytest.approx(0.24)
    assert nav.update(0.0, [0.0, 0.0, 0.0], NONE).state == 'no_wall'


def test_goal_seeking_then_avoiding():
    nav = navigator(behaviour='vff', goal=[5.0, 5.0], avoidance_distance=1.0)
    out = nav.update(0.0, [0.0, 0.0, 0.0], NONE)
    assert out.state == 'goal_seeking' and out.goal_distance == pytest.approx(5 * math.sqrt(2))
    bearing = math.pi / 4
    assert out.command.angular == pytest.approx(min(1.5, 2.0 * bearing))
    assert out.command.linear == pytest.approx(0.5 * math.cos(bearing))
    near = nav.update(0.1, [0.0, 0.0, 0.0], np.array([[0.5, 0.5]]))
    assert near.state == 'avoiding'
    assert navigator(behaviour='potential', goal=[1.0, 0.0]).update(
        0.0, [0.98, 0.0, 0.0], NONE).state == 'goal_reached'


def test_a_local_minimum_is_detected_and_reported():
    stall = {'stall.window': 2.0, 'stall.min_progress': 0.1}
    nav = navigator(behaviour='potential', goal=[4.0, 0.0], **stall)
    trap = np.array([[0.6, y] for y in np.linspace(-0.8, 0.8, 17)])
    states = [nav.update(0.1 * k, [1.0, 0.0, 0.0], trap).state for k in range(21)]
    assert states[:20] == ['avoiding'] * 20    # the window is not full yet
    assert states[20] == 'stalled'             # 2 s without 0.1 m of progress
    moving = navigator(behaviour='potential', goal=[40.0, 0.0], **{'stall.window': 2.0})
    states = [moving.update(0.1 * k, [0.1 * k, 0.0, 0.0], NONE).state for k in range(40)]
    assert 'stalled' not in states


def test_parameters_are_checked():
    assert set(NAVIGATOR_PARAMETERS) >= {'behaviour', 'wall.k_distance', 'vff.window_radius',
                                         'potential.max_deceleration', 'speed.safety_distance'}
    with pytest.raises(ParameterError, match='behaviour must be one of'):
        navigator_params({'behaviour': 'bug'})
    with pytest.raises(ParameterError, match='wall.k_distance must be in'):
        navigator_params({'wall.k_distance': -1.0})
    with pytest.raises(ValueError, match='safety_distance'):
        navigator_params({'speed.safety_distance': 2.0, 'speed.slowdown_distance': 1.0})
    with pytest.raises(ValueError, match='must be finite'):
        navigator().update(0.0, [math.nan, 0.0, 0.0], NONE)
