"""
Tests of robotica_sim.sensors.sonar (book §7.4, fig. 7.19; seed catalogue Part 5.5, Part 15).

References by hand. A wall whose normal is at α from the transducer's axis, at perpendicular
distance D, is met by the ray at β from the axis with incidence |β - α| at range
D / cos(β - α). Fig. 7.19: a near object O met at a grazing incidence reflects the pulse to a
far wall O', whose echo comes back to the transducer; the reading is half the path
transducer -> O -> O' -> transducer. Statistics: mean within 5 standard errors, variance
within the chi-square bounds (two-sided level 1e-6) of σ = σ0 + k r. Fixed seeds.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.world import make_world
from robotica_sim.sensors.sonar import (sonar_params, SONAR_PRESETS, sonar_ranges,
                                        SonarParams, SonarRing)
from scipy.stats import chi2

ALPHA = 1e-6
DEG = math.pi / 180.0
C20 = 331.3 * math.sqrt(1.0 + 20.0 / 273.15)   # [m/s] the air's speed of sound at 20 °C
AXIS = [[0.0, 0.0, 0.0]]                         # one transducer at base_link, along x
ORIGIN = [0.0, 0.0, 0.0]


def exact(**changes):
    """Return a noise-free transducer whose assumed speed of sound is the air's."""
    return dataclasses.replace(SonarParams(range_noise=0.0, range_noise_per_metre=0.0,
                                           speed_of_sound=C20), **changes)


def tilted_wall(alpha, distance=2.0):
    """Return a world of one wall whose normal is at ``alpha`` from x, ``distance`` away."""
    foot = distance * np.array([math.cos(alpha), math.sin(alpha)])
    along = 10.0 * np.array([-math.sin(alpha), math.cos(alpha)])
    return make_world(walls=[[*(foot - along), *(foot + along)]])


def read(params, world, pose=ORIGIN, mounts=AXIS, seed=0):
    return sonar_ranges(params, world, pose, mounts, np.random.default_rng(seed))[0]


def test_flat_wall_mean_and_variance_match_sigma():
    # Perpendicular wall at 4 m: the axis ray is the nearest echo of the cone.
    params = SonarParams(range_noise=0.01, range_noise_per_metre=0.01, speed_of_sound=C20)
    world = tilted_wall(0.0, 4.0)
    rng = np.random.default_rng(11)
    samples = np.array([sonar_ranges(params, world, ORIGIN, AXIS, rng)[0]
                        for _ in range(3000)])
    sigma = 0.01 + 0.01 * 4.0
    n = len(samples)
    assert abs(samples.mean() - 4.0) < 5.0 * sigma / math.sqrt(n)
    statistic = samples.var(ddof=1) * (n - 1) / sigma ** 2
    assert chi2.ppf(0.5 * ALPHA, n - 1) < statistic < chi2.ppf(1.0 - 0.5 * ALPHA, n - 1)


def test_beyond_the_critical_angle_no_echo_reads_max_range():
    # Critical angle 25°, cone ±15°: a wall at 50° is met at 35° to 65° by every ray.
    assert read(exact(), tilted_wall(50.0 * DEG)) == 10.7
    # One ray (the axis): 30° is beyond, 20° within, at 2 / cos 20°.
    assert read(exact(cone_rays=1), tilted_wall(30.0 * DEG)) == 10.7
    assert read(exact(cone_rays=1), tilted_wall(20.0 * DEG)) == pytest.approx(
        2.0 / math.cos(20.0 * DEG))


def test_the_nearest_valid_echo_of_the_cone_wins():
    # Wall at 20°: rays at -15, -7.5, 0, 7.5, 15° meet it at 35, 27.5, 20, 12.5, 5°; the ray
    # at 15° is the nearest valid one, at 2 / cos 5°.
    assert read(exact(), tilted_wall(20.0 * DEG)) == pytest.approx(2.0 / math.cos(5.0 * DEG))
    assert read(exact(), tilted_wall(0.0)) == pytest.approx(2.0)


def fig_7_19_world():
    """
    Return fig. 7.19's geometry: O through (1, 0) at 10° to the axis, O' the wall x = 3.

    The axis ray meets O at (1, 0) with incidence 80° and is mirrored to 20°; it meets O' at
    (3, 2 tan 20°), whose direction from the transducer is 13.6° off the axis, within the cone
    and facing O' at 13.6°, within the critical angle; the way back passes above O.
    """
    u = np.array([math.cos(10.0 * DEG), math.sin(10.0 * DEG)])
    near_o = [*(np.array([1.0, 0.0]) - 0.5 * u), *(np.array([1.0, 0.0]) + 1.5 * u)]
    return make_world(walls=[near_o, [3.0, -5.0, 3.0, 5.0]])


def test_fig_7_19_multipath_misses_the_near_object():
    y2 = 2.0 * math.tan(20.0 * DEG)
    path = 1.0 + 2.0 / math.cos(20.0 * DEG) + math.hypot(3.0, y2)
    reading = read(exact(cone_rays=1), fig_7_19_world())
    assert reading == pytest.approx(path / 2.0)       # 3.108 m, O at 1 m is missed
    assert reading > 3.0
    # The whole cone: every ray meets O beyond the critical angle (65° to 95°) or passes it;
    # the reading is O''s, never O's 1 m.
    assert read(exact(), fig_7_19_world()) > 2.9


def test_without_the_second_surface_the_lost_echo_reads_max_range():
    u = np.array([math.cos(10.0 * DEG), math.sin(10.0 * DEG)])
    only_o = make_world(walls=[[*(np.array([1.0, 0.0]) - 0.5 * u),
                                *(np.array([1.0, 0.0]) + 1.5 * u)]])
    assert read(exact(cone_rays=1), only_o) == 10.7


def test_speed_of_sound_scales_the_range():
    # The sensor assumes 343.2 m/s; in air at 0 °C sound runs at 331.3 m/s: 3.59 % long.
    params = exact(speed_of_sound=343.2, air_temperature=0.0)
    assert read(params, tilted_wall(0.0)) == pytest.approx(2.0 * 343.2 / 331.3)


def test_too_near_reads_min_range():
    assert read(exact(), tilted_wall(0.0, 0.1)) == 0.15


def test_mounts_place_the_transducers():
    # Robot at (0, 0) facing +x; transducers ahead (0.2 m forward) and to the left.
    world = make_world(walls=[[3.0, -5.0, 3.0, 5.0], [-5.0, 2.0, 5.0, 2.0]])
    ranges = sonar_ranges(exact(), world, ORIGIN, [[0.2, 0.0, 0.0], [0.0, 0.1, math.pi / 2]],
                          np.random.default_rng(0))
    assert ranges == pytest.approx([2.8, 1.9])


def test_firing_sequence_groups_in_turn_the_rest_keep_their_reading():
    world = tilted_wall(0.0, 3.0)
    mounts = [[0.0, 0.0, 0.0], [0.0, 0.0, math.pi], [0.0, 0.0, 0.0], [0.0, 0.0, math.pi]]
    ring = SonarRing(exact(firing_groups=2), mounts, np.random.default_rng(0))
    assert ring.fire(world, ORIGIN).tolist() == [0, 2]
    assert ring.readings[0] == pytest.approx(3.0) and np.isnan(ring.readings[1])
    assert ring.fire(world, ORIGIN).tolist() == [1, 3]
    assert ring.readings[1] == 10.7
    assert ring.fire(world, [1.0, 0.0, 0.0]).tolist() == [0, 2]   # 1 m nearer the wall
    assert ring.readings.tolist() == pytest.approx([2.0, 10.7, 2.0, 10.7])
    everyone = SonarRing(exact(), mounts, np.random.default_rng(0))
    assert everyone.fire(world, ORIGIN).tolist() == [0, 1, 2, 3]


def test_a_nan_pose_is_refused():
    with pytest.raises(ValueError, match='pose'):
        read(exact(), tilted_wall(0.0), pose=[0.0, math.nan, 0.0])


@pytest.mark.parametrize('changes, name', [
    ({'cone_half_angle': 0.0}, 'cone_half_angle'), ({'cone_rays': 0}, 'cone_rays'),
    ({'min_range': 20.0}, 'min_range'), ({'critical_angle': 2.0}, 'critical_angle'),
    ({'range_noise': -0.1}, 'range_noise'), ({'speed_of_sound': 0.0}, 'speed_of_sound'),
    ({'firing_groups': 0}, 'firing_groups'), ({'cycle_rate': math.inf}, 'cycle_rate')])
def test_bad_terms_are_refused(changes, name):
    with pytest.raises(ValueError, match=name):
        SonarParams(**changes)


def test_preset_gives_the_terms_and_a_term_overrides_it():
    assert sonar_params({'preset': 'maxbotix_ez1'}) == SONAR_PRESETS['maxbotix_ez1']
    assert sonar_params({'critical_angle': 0.5}).critical_angle == 0.5
    with pytest.raises(ParameterError) as err:
        sonar_params({'min_range': 50.0})
    assert err.value.name == 'min_range'
