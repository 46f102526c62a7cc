"""
Tests of robotica_sim.sensors.infrared (book §7.4; seed catalogue Part 5.5 and Part 15).

References by hand: the returned intensity ρ / r² meets the threshold I_min up to
r = √(ρ / I_min) (ρ = 0.05, I_min = 0.25: 0.447 m); a perpendicular wall at D is the axis
ray's D. Statistics: mean within 5 standard errors, variance within the chi-square bounds
(two-sided level 1e-6) of σ = σ0 + k r. Fixed seeds.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.world import make_world
from robotica_sim.sensors.infrared import (infrared_params, INFRARED_PRESETS,
                                           infrared_ranges, InfraredParams)
from scipy.stats import chi2

ALPHA = 1e-6
AXIS = [[0.0, 0.0, 0.0]]
ORIGIN = [0.0, 0.0, 0.0]


def wall_at(x):
    return make_world(walls=[[x, -5.0, x, 5.0]])


def exact(**changes):
    return dataclasses.replace(InfraredParams(range_noise=0.0, range_noise_per_metre=0.0),
                               **changes)


def read(params, world, reflectivity=None, pose=ORIGIN):
    return infrared_ranges(params, world, pose, AXIS, np.random.default_rng(0),
                           reflectivity)[0]


def test_flat_wall_mean_and_variance_match_sigma():
    params = InfraredParams()
    rng = np.random.default_rng(4)
    world = wall_at(0.5)
    samples = np.array([infrared_ranges(params, world, ORIGIN, AXIS, rng)[0]
                        for _ in range(3000)])
    sigma = 0.005 + 0.02 * 0.5
    n = len(samples)
    assert abs(samples.mean() - 0.5) < 5.0 * sigma / math.sqrt(n)
    statistic = samples.var(ddof=1) * (n - 1) / sigma ** 2
    assert chi2.ppf(0.5 * ALPHA, n - 1) < statistic < chi2.ppf(1.0 - 0.5 * ALPHA, n - 1)


def test_reflectivity_threshold():
    # A dark target (ρ = 0.05) is seen up to √(0.05 / 0.25) = 0.447 m only.
    assert read(exact(), wall_at(0.4), reflectivity=0.05) == pytest.approx(0.4)
    assert read(exact(), wall_at(0.5), reflectivity=0.05) == 0.8
    # The default ρ = 0.5 reaches past the range: seen up to max range.
    assert read(exact(), wall_at(0.75)) == pytest.approx(0.75)
    assert read(exact(intensity_threshold=2.0), wall_at(0.75)) == 0.8   # 0.5 / 0.5625 < 2


def test_out_of_range_and_too_near():
    assert read(exact(), wall_at(0.9)) == 0.8
    assert read(exact(), wall_at(0.05)) == 0.1


def test_a_bad_reflectivity_or_pose_is_refused():
    with pytest.raises(ValueError, match='reflectivity'):
        read(exact(), wall_at(0.5), reflectivity=1.5)
    with pytest.raises(ValueError, match='pose'):
        read(exact(), wall_at(0.5), pose=[0.0, 0.0, math.inf])


@pytest.mark.parametrize('changes, name', [
    ({'cone_half_angle': 2.0}, 'cone_half_angle'), ({'max_range': 0.05}, 'min_range'),
    ({'intensity_threshold': -1.0}, 'intensity_threshold'),
    ({'default_reflectivity': 2.0}, 'default_reflectivity'), ({'rate': 0.0}, 'rate')])
def test_bad_terms_are_refused(changes, name):
    with pytest.raises(ValueError, match=name):
        InfraredParams(**changes)


def test_preset_gives_the_terms_and_a_term_overrides_it():
    assert infrared_params({'preset': 'sharp_gp2y0a02'}) == INFRARED_PRESETS['sharp_gp2y0a02']
    assert infrared_params({'preset': 'sharp_gp2y0a02', 'rate': 5.0}).rate == 5.0
    with pytest.raises(ParameterError) as err:
        infrared_params({'min_range': 5.0})
    assert err.value.name == 'min_range'
