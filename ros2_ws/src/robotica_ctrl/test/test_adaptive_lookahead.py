"""
Tests of robotica_ctrl.mobile.adaptive_lookahead: look-ahead rules for pure pursuit (§9.3.1).

Rule values are worked by hand; the closed loop integrates the unicycle x' = v cos θ,
y' = v sin θ, θ' = ω written below on the straight path with a lateral offset of
Ejemplo 9.1 (seed catalogue §7.10), where the lateral error is the robot's y coordinate.
"""

import math

from hypothesis import given
from hypothesis import strategies as st
import numpy as np
import pytest

from robotica_ctrl.mobile.adaptive_lookahead import (
    adaptive_params, AdaptivePurePursuit, lookahead_by_curvature, lookahead_by_error,
    lookahead_by_speed, LookaheadRule)
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuitParams

# (rule, input, gain, minimum, maximum, L by hand)
TABLE = [
    (lookahead_by_speed, 1.0, 1.5, 0.3, 5.0, 1.5),
    (lookahead_by_speed, -2.0, 1.5, 0.3, 5.0, 3.0),     # magnitude of v
    (lookahead_by_speed, 0.1, 1.5, 0.3, 5.0, 0.3),      # 0.15 clamped up
    (lookahead_by_speed, 10.0, 1.5, 0.3, 5.0, 5.0),     # 15 clamped down
    (lookahead_by_curvature, 0.5, 0.4, 0.3, 5.0, 0.8),  # 0.4 · 2 m
    (lookahead_by_curvature, -0.25, 0.4, 0.3, 5.0, 1.6),
    (lookahead_by_curvature, 0.0, 0.4, 0.3, 5.0, 5.0),  # straight: maximum
    (lookahead_by_curvature, 4.0, 0.4, 0.3, 5.0, 0.3),  # 0.1 clamped up
    (lookahead_by_error, 0.5, 2.0, 0.5, 5.0, 1.5),
    (lookahead_by_error, -1.0, 2.0, 0.5, 5.0, 2.5),
    (lookahead_by_error, 0.0, 2.0, 0.5, 5.0, 0.5),
    (lookahead_by_error, 4.0, 2.0, 0.5, 5.0, 5.0),      # 8.5 clamped down
]


@pytest.mark.parametrize('rule, value, gain, minimum, maximum, expected', TABLE)
def test_rule_values_by_hand(rule, value, gain, minimum, maximum, expected):
    assert rule(value, gain, minimum, maximum) == pytest.approx(expected)


RULES = [lookahead_by_speed, lookahead_by_curvature, lookahead_by_error]


@pytest.mark.parametrize('rule', RULES)
@given(a=st.floats(-20.0, 20.0), b=st.floats(-20.0, 20.0), gain=st.floats(0.0, 5.0))
def test_rules_clamped_and_monotonic_in_magnitude(rule, a, b, gain):
    low, high = sorted((abs(a), abs(b)))
    l_low, l_high = rule(low, gain, 0.3, 4.0), rule(-high, gain, 0.3, 4.0)
    assert 0.3 <= l_low <= 4.0 and 0.3 <= l_high <= 4.0
    if rule is lookahead_by_curvature:
        assert l_high <= l_low  # tighter bend, shorter look-ahead
    else:
        assert l_high >= l_low  # faster or farther off, longer look-ahead


@pytest.mark.parametrize('rule', RULES)
@pytest.mark.parametrize('args', [
    (math.nan, 1.0, 0.3, 4.0), (1.0, -1.0, 0.3, 4.0), (1.0, 1.0, 0.0, 4.0),
    (1.0, 1.0, 5.0, 4.0), (1.0, 1.0, 0.3, math.inf)])
def test_rules_reject_bad_input(rule, args):
    with pytest.raises(ValueError):
        rule(*args)


def test_rule_object_validates_and_dispatches():
    assert LookaheadRule('speed', 2.0, 0.5, 3.0).lookahead(1.0) == 2.0
    assert LookaheadRule('curvature', 0.5, 0.5, 3.0).lookahead(0.25) == 2.0
    with pytest.raises(ValueError, match='kind'):
        LookaheadRule('fuzzy')
    with pytest.raises(ValueError):
        LookaheadRule('error', 1.0, 2.0, 1.0)
    with pytest.raises(ValueError):
        LookaheadRule('curvature', curvature_spacing=0.0)


def test_update_sets_the_lookahead_of_the_wrapped_tracker():
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    params = PurePursuitParams(desired_linear_velocity=1.0, max_angular_velocity=10.0)
    tracker = AdaptivePurePursuit(path, params, LookaheadRule('speed', 2.0, 0.3, 5.0))
    command = tracker.update([0.0, 0.0, 0.0], 0.0)
    assert tracker.lookahead_distance == 2.0  # 2 s · 1 m/s (desired speed at first)
    np.testing.assert_allclose(command.target_point, [2.0, 0.0])
    tracker.update([0.0, 0.0, 0.0], 0.1, speed=0.5)
    assert tracker.lookahead_distance == 1.0
    assert tracker.tracker.params.desired_linear_velocity == 1.0  # the rest is kept
    with pytest.raises(ValueError):
        tracker.update([0.0, 0.0, 0.0], 0.2, speed=math.nan)
    with pytest.raises(ValueError):
        tracker.update([0.0, 0.0], 0.2)


def test_curvature_rule_on_a_circle():
    radius = 2.0
    angles = np.linspace(0.0, math.pi, 361)
    path = PolylinePath(radius * np.column_stack((np.cos(angles), np.sin(angles))))
    tracker = AdaptivePurePursuit(path, PurePursuitParams(),
                                  LookaheadRule('curvature', 0.5, 0.3, 5.0))
    tracker.update([radius, 0.0, math.pi / 2], 0.0)  # at the start: one-sided, straight
    assert tracker.lookahead_distance == 5.0
    tracker.tracker.set_params(PurePursuitParams(search_window=10.0))
    tracker.update([0.0, radius, math.pi], 0.0)
    assert tracker.lookahead_distance == pytest.approx(0.5 * radius, rel=1e-2)


def simulate(tracker, pose, duration, dt):
    """Drive a unicycle with the tracker's commands; return poses (K, 3) and L (K,)."""
    pose = np.asarray(pose, dtype=float)
    poses, lookaheads = [], []
    for k in range(round(duration / dt)):
        command = tracker.update(pose, k * dt)
        poses.append(pose)
        lookaheads.append(tracker.lookahead_distance)
        heading = pose[2] + 0.5 * dt * command.angular
        pose = pose + dt * np.array([command.linear * math.cos(heading),
                                     command.linear * math.sin(heading), command.angular])
    return np.array(poses), np.array(lookaheads)


@pytest.mark.parametrize('rule', [
    LookaheadRule('speed', 1.0, 0.3, 3.0), LookaheadRule('curvature', 0.5, 0.3, 1.5),
    LookaheadRule('error', 2.0, 0.5, 3.0)])
def test_closed_loop_converges_on_a_straight_line_with_offset(rule):
    path = PolylinePath([[0.0, 0.0], [40.0, 0.0]])
    params = PurePursuitParams(desired_linear_velocity=1.0, max_angular_velocity=2.0)
    poses, lookaheads = simulate(AdaptivePurePursuit(path, params, rule), [0.0, 0.5, 0.0],
                                 15.0, 0.02)
    late = poses[len(poses) // 2:]
    assert np.max(np.abs(late[:, 1])) < 0.01
    assert np.max(np.abs(late[:, 2])) < 0.01
    if rule.kind == 'error':
        assert lookaheads[0] == pytest.approx(1.5)  # 0.5 + 2 · 0.5
        assert lookaheads[-1] == pytest.approx(0.5, abs=0.02)  # on the path: minimum


def test_gains_by_the_node_names():
    params, rule = adaptive_params({'rule': 'curvature', 'gain': 0.5, 'min_lookahead': 0.4,
                                    'max_lookahead': 2.0, 'curvature_spacing': 0.3,
                                    'desired_linear_velocity': 0.8})
    assert rule == LookaheadRule('curvature', 0.5, 0.4, 2.0, 0.3)
    assert params == PurePursuitParams(lookahead_distance=0.4, desired_linear_velocity=0.8)
    path = PolylinePath([[0.0, 0.0], [10.0, 0.0]])
    tracker = AdaptivePurePursuit(path, params, rule)
    tracker.set_gains({'rule': 'error', 'gain': 2.0})
    assert tracker.rule == LookaheadRule('error', 2.0, 0.4, 2.0, 0.3)
    tracker.update([0.0, 0.5, 0.0], 0.0)
    assert tracker.lookahead_distance == pytest.approx(1.4)   # 0.4 + 2 · 0.5
    with pytest.raises(ValueError):
        tracker.set_gains({'min_lookahead': 3.0})   # above max_lookahead
    with pytest.raises(ValueError):
        adaptive_params({'lookahead': 1.0})
    assert tracker.rule.minimum == 0.4
