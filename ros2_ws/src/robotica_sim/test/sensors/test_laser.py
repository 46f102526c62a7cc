"""
Tests of robotica_sim.sensors.laser (book §7.4, §12.3; seed catalogue Part 10.2 and Part 15).

References by hand: a beam at angle a to the normal of a wall at perpendicular distance D
meets it at D / cos a; REP-117's +inf (no return), -inf (too close), NaN (erroneous).
Statistics: the mean of N readings within 5 standard errors, their variance within the
chi-square bounds (scipy.stats.chi2, two-sided level 1e-6) of the model's σ², the dropout count
within the binomial bounds (scipy.stats.binom) of its probability. Fixed seeds.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.world import make_world
from robotica_sim.sensors.laser import (laser_params, LASER_PRESETS, laser_term_specs,
                                        LaserModel, LaserParams)
from scipy.stats import binom, chi2

ALPHA = 1e-6
DEG = math.pi / 180.0


def assert_mean_and_variance(samples, mean, sigma):
    n = len(samples)
    assert abs(np.mean(samples) - mean) < 5.0 * sigma / math.sqrt(n)
    s2 = np.var(samples, ddof=1)
    low, high = chi2.ppf(0.5 * ALPHA, n - 1), chi2.ppf(1.0 - 0.5 * ALPHA, n - 1)
    assert low * sigma ** 2 / (n - 1) < s2 < high * sigma ** 2 / (n - 1)


def two_beams(**changes):
    """Return a fan of two beams, at 0 and 0.02 rad, with the given changes."""
    return dataclasses.replace(LaserParams(angle_min=0.0, angle_max=0.02,
                                           angle_increment=0.02), **changes)


WALL_AT_3 = make_world(walls=[[3.0, -10.0, 3.0, 10.0]])


def test_flat_wall_mean_and_variance_match_sigma():
    # Beams at 0 and 0.02 rad to the wall's normal: true ranges 3 and 3 / cos 0.02.
    params = two_beams(range_noise=0.02, range_noise_per_metre=0.01)
    laser = LaserModel(params, np.random.default_rng(3))
    scans = np.array([laser.scan(WALL_AT_3, [0.0, 0.0, 0.0]) for _ in range(4000)])
    assert_mean_and_variance(scans[:, 0], 3.0, 0.02 + 0.01 * 3.0)
    r = 3.0 / math.cos(0.02)
    assert_mean_and_variance(scans[:, 1], r, 0.02 + 0.01 * r)


def test_mount_and_pose_place_the_beam():
    # Robot at (1, 0) facing +y, laser 0.5 m ahead of it turned -90°: it looks along +x from
    # (1, 0.5), 2 m from the wall x = 3.
    laser = LaserModel(two_beams(range_noise=0.0), np.random.default_rng(0),
                       mount=(0.5, 0.0, -math.pi / 2))
    assert laser.scan(WALL_AT_3, [1.0, 0.0, math.pi / 2])[0] == pytest.approx(2.0)


def test_no_return_is_plus_inf_and_too_close_is_minus_inf():
    laser = LaserModel(two_beams(range_noise=0.0), np.random.default_rng(0))
    assert laser.scan(WALL_AT_3, [0.0, 0.0, math.pi])[0] == math.inf        # nothing behind
    assert laser.scan(WALL_AT_3, [2.8, 0.0, 0.0])[0] == -math.inf           # 0.2 m < 0.3 m
    far = LaserModel(two_beams(range_max=2.5), np.random.default_rng(0))
    assert far.scan(WALL_AT_3, [0.0, 0.0, 0.0])[0] == math.inf              # 3 m > 2.5 m


def test_readings_stay_within_the_interval():
    laser = LaserModel(two_beams(range_noise=0.5, range_max=3.2), np.random.default_rng(1))
    readings = np.concatenate([laser.scan(WALL_AT_3, [0.0, 0.0, 0.0]) for _ in range(500)])
    assert readings.min() >= 0.3 and readings.max() <= 3.2


def test_dropout_rate_within_binomial_bounds():
    p, n = 0.05, 40000
    laser = LaserModel(LaserParams(dropout_probability=p), np.random.default_rng(7))
    scans = np.concatenate([laser.scan(WALL_AT_3, [0.0, 0.0, 0.0]) for _ in range(100)])
    assert len(scans) == 100 * 361
    count = int(np.isnan(scans).sum())
    n = len(scans)
    assert binom.ppf(0.5 * ALPHA, n, p) <= count <= binom.ppf(1.0 - 0.5 * ALPHA, n, p)
    # Behind the scanner's 180° fan nothing is seen except the wall: ±90° beams run along it.
    assert not np.isneginf(scans).any()


def test_fan_angles_and_beam_count():
    params = LaserParams()
    assert params.beams == 361
    assert params.angles[0] == pytest.approx(-math.pi / 2)
    assert params.angles[-1] == pytest.approx(math.pi / 2)
    assert LaserParams(angle_min=0.0, angle_max=1.0, angle_increment=0.3).beams == 4


def test_same_seed_same_scan():
    a = LaserModel(LaserParams(dropout_probability=0.1), np.random.default_rng(5))
    b = LaserModel(LaserParams(dropout_probability=0.1), np.random.default_rng(5))
    np.testing.assert_array_equal(a.scan(WALL_AT_3, [0, 0, 0]), b.scan(WALL_AT_3, [0, 0, 0]))


@pytest.mark.parametrize('changes, name', [
    ({'angle_max': -2.0}, 'angle_max'), ({'angle_increment': 0.0}, 'angle_increment'),
    ({'range_min': 90.0}, 'range_min'), ({'scan_rate': 0.0}, 'scan_rate'),
    ({'range_noise': -1.0}, 'range_noise'), ({'dropout_probability': 1.0}, 'dropout'),
    ({'range_max': math.nan}, 'range_max')])
def test_bad_terms_are_refused(changes, name):
    with pytest.raises(ValueError, match=name):
        LaserParams(**changes)


def test_a_nan_pose_is_refused():
    laser = LaserModel(LaserParams(), np.random.default_rng(0))
    with pytest.raises(ValueError, match='pose'):
        laser.scan(WALL_AT_3, [math.nan, 0.0, 0.0])


def test_preset_gives_the_terms_and_a_term_overrides_it():
    assert laser_params({'preset': 'sick_lms200_mm'}) == LASER_PRESETS['sick_lms200_mm']
    assert laser_params({'preset': 'sick_lms200_mm', 'range_noise': 0.02}).range_noise == 0.02
    assert laser_term_specs('hokuyo_urg04lx')['range_max'].default == 4.0
    with pytest.raises(ParameterError, match='preset'):
        laser_params({'preset': 'lidar'})
    with pytest.raises(ParameterError) as err:
        laser_params({'range_min': 100.0})   # in its spec's range, refused by LaserParams
    assert err.value.name == 'range_min'
