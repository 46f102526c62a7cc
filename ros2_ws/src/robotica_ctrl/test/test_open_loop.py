"""Tests of robotica_ctrl.mobile.open_loop against values worked out by hand."""

import math

import numpy as np
import pytest
from robotica_ctrl.mobile.open_loop import OpenLoop, OpenLoopProfile


def test_ramp_of_ejemplo_4_9_c():
    # c = 0.25 m, b = 1 m; ω_i = 1 rad/s, ω_d = 0.1 t:
    # v = c (ω_d + ω_i) / 2, ω = c (ω_d - ω_i) / b.
    profile = OpenLoopProfile([0.0, 30.0], [0.125, 0.25 * 4.0 / 2.0], [-0.25, 0.25 * 2.0])
    for t in (0.0, 7.5, 10.0, 22.0, 30.0):
        w_right = 0.1 * t
        assert profile.command(t) == pytest.approx(
            (0.25 * (w_right + 1.0) / 2.0, 0.25 * (w_right - 1.0)), abs=1e-12)


def test_single_row_is_a_constant_and_the_last_row_is_held():
    assert OpenLoopProfile([0.0], [1.0], [1.0]).command(12.3) == (1.0, 1.0)
    profile = OpenLoopProfile([0.0, 1.0, 3.0], [0.0, 1.0, 1.0], [0.0, 0.0, 2.0])
    assert profile.command(2.0) == (1.0, 1.0)
    assert profile.command(100.0) == (1.0, 2.0)
    assert profile.command(-1.0) == (0.0, 0.0)


@pytest.mark.parametrize('times, linear, angular, key', [
    ([], [], [], 'times'),
    ([0.0, 1.0], [1.0], [0.0, 0.0], 'same length'),
    ([0.0, 0.0], [1.0, 1.0], [0.0, 0.0], 'increase'),
    ([0.0, math.nan], [1.0, 1.0], [0.0, 0.0], 'times'),
    ([0.0], [math.inf], [0.0], 'linear'),
    ([0.0], [1.0], [[0.0]], 'angular'),
])
def test_bad_profiles_are_refused(times, linear, angular, key):
    with pytest.raises(ValueError, match=key):
        OpenLoopProfile(times, linear, angular)


def test_the_law_plays_the_profile_against_time_only():
    # Ej. 4.8: v = 1 m/s, w = 1 rad/s, whatever the pose; no path, so no errors (NaN).
    law = OpenLoop(OpenLoopProfile([0.0], [1.0], [1.0]))
    for t, pose in ((0.0, [1.0, 0.0, 1.57]), (3.0, [math.nan, 0.0, 0.0])):
        out = law.update(pose, t)
        assert (out.linear, out.angular, out.finished) == (1.0, 1.0, False)
        assert math.isnan(out.cross_track) and math.isnan(out.along_track)
        assert math.isnan(out.heading_error) and np.isnan(out.target_point).all()
    law.set_gains({'times': [0.0, 2.0], 'linear': [0.0, 1.0], 'angular': [0.0, 0.0]})
    law.reset()
    assert law.update([0.0, 0.0, 0.0], 1.0)[:2] == (0.5, 0.0)
    with pytest.raises(ValueError, match='same length'):
        law.set_gains({'angular': [0.0]})
    assert law.profile.angular.tolist() == [0.0, 0.0]   # the old profile is kept
