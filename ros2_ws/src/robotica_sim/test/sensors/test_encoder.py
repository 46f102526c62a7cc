"""
Tests of robotica_sim.sensors.encoder: incremental-encoder counts (book §7.3.2, catalog §13.6).

Missed counts are checked against the binomial law of independent per-edge misses: the lost
count of n edges has mean n p and variance n p (1 - p), bounded at about 5 standard deviations
(normal) and by chi-square quantiles at p = 1e-6 for the spread across seeds.
"""
from fractions import Fraction
import math

from hypothesis import given, seed, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_sim.sensors.encoder import EncoderModel, EncoderParams, quantize_ticks
from scipy.stats import chi2

ANGLES = st.floats(min_value=-1e4, max_value=1e4, allow_nan=False, allow_infinity=False)
RESOLUTIONS = st.sampled_from([1, 2, 3, 4, 7, 360, 1000, 1024, 4096, 10000])
TWO_PI = Fraction('6.283185307179586476925286766559005768394')  # 2π to 40 digits


@pytest.mark.parametrize('angle, ticks_per_revolution, expected', [
    (0.0, 4096, 0),
    (math.pi / 2.0, 4096, 1024),         # a quarter turn: 4096 / 4
    (math.pi, 4096, 2048),               # half a turn
    (2.0 * math.pi, 4096, 4096),         # one full turn
    (6.0 * math.pi, 4096, 3 * 4096),     # three full turns
    (2.0 * math.pi, 1, 1),               # one count per revolution
    (math.pi / 2.0, 4, 1),               # x4 decoding of a 1-PPR disc
    (-math.pi / 2.0, 4096, -1024),       # backwards: exact edges are reached exactly
    (-2.0 * math.pi, 4096, -4096),
    (-1e-9, 4096, -1),                   # just behind zero: floor goes downwards, not to 0
    (-math.pi / 2.0 - 1e-9, 4096, -1025),
    (1e-9, 4096, 0),
    (0.75 * 2.0 * math.pi / 360, 360, 0),   # three quarters of a count: still 0
    (1.25 * 2.0 * math.pi / 360, 360, 1),
    (-0.25 * 2.0 * math.pi / 360, 360, -1),
])
def test_hand_computed_counts(angle, ticks_per_revolution, expected):
    ticks = quantize_ticks(angle, ticks_per_revolution)
    assert type(ticks) is int
    assert ticks == expected


@pytest.mark.parametrize('ticks_per_revolution', [1, 4, 360, 4096])
@pytest.mark.parametrize('k', [-5, -1, 0, 1, 3, 1000])
def test_one_count_below_and_above_an_edge(k, ticks_per_revolution):
    # The k-th edge sits at k 2 pi / N; 1e-9 rad is far above rounding and far below a count.
    edge = k * 2.0 * math.pi / ticks_per_revolution
    assert quantize_ticks(edge - 1e-9, ticks_per_revolution) == k - 1
    assert quantize_ticks(edge + 1e-9, ticks_per_revolution) == k
    # Halfway between two edges is unambiguous too.
    middle = (k + 0.5) * 2.0 * math.pi / ticks_per_revolution
    assert quantize_ticks(middle, ticks_per_revolution) == k


@seed(20240613)
@settings(max_examples=300, deadline=None)
@given(a=ANGLES, b=ANGLES, ticks_per_revolution=RESOLUTIONS)
def test_monotonic_in_the_angle(a, b, ticks_per_revolution):
    low, high = min(a, b), max(a, b)
    assert quantize_ticks(low, ticks_per_revolution) <= quantize_ticks(high, ticks_per_revolution)


@seed(7)
@settings(max_examples=300, deadline=None)
@given(angle=ANGLES, ticks_per_revolution=RESOLUTIONS)
def test_count_is_within_one_count_below_the_angle(angle, ticks_per_revolution):
    count = 2.0 * math.pi / ticks_per_revolution  # [rad] per tick
    residual = angle - quantize_ticks(angle, ticks_per_revolution) * count
    # 0 <= residual < one count, up to the rounding of angle * N / (2 pi) (a few ulps).
    rounding = 1e-12 * max(1.0, abs(angle))
    assert -rounding <= residual < count + rounding


@pytest.mark.parametrize('angle', [math.nan, math.inf, -math.inf])
def test_non_finite_angle_is_refused(angle):
    with pytest.raises(ValueError, match='finite'):
        quantize_ticks(angle, 4096)


@pytest.mark.parametrize('ticks_per_revolution', [0, -1, -4096])
def test_fewer_than_one_tick_per_revolution_is_refused(ticks_per_revolution):
    with pytest.raises(ValueError, match='ticks_per_revolution'):
        quantize_ticks(1.0, ticks_per_revolution)


@pytest.mark.parametrize('ppr, decoding, gear_ratio, expected', [
    (500, 4, 1.0, 2000),
    (500, 1, 1.0, 500),
    (500, 2, 1.0, 1000),
    (1000, 4, 1.5, 6000),
    (256, 4, 50.0, 51200),
    (3, 1, 1.0 / 3.0, 1),     # one count per wheel revolution, up to rounding of 1/3
])
def test_ticks_per_revolution_is_ppr_times_decoding_times_gear(ppr, decoding, gear_ratio,
                                                               expected):
    params = EncoderParams(ppr, decoding, gear_ratio)
    assert params.ticks_per_revolution == expected
    assert type(params.ticks_per_revolution) is int


@pytest.mark.parametrize('kwargs, match', [
    ({'pulses_per_revolution': 0}, 'pulses_per_revolution'),
    ({'pulses_per_revolution': 500.0}, 'pulses_per_revolution'),
    ({'pulses_per_revolution': True}, 'pulses_per_revolution'),
    ({'decoding': 3}, 'decoding'),
    ({'decoding': 0}, 'decoding'),
    ({'gear_ratio': 0.0}, 'gear_ratio'),
    ({'gear_ratio': -2.0}, 'gear_ratio'),
    ({'gear_ratio': math.nan}, 'gear_ratio'),
    ({'gear_ratio': 1.0001}, 'integer'),          # 2000.2 counts per revolution
    ({'pulses_per_revolution': 1, 'decoding': 1, 'gear_ratio': 0.5}, 'integer'),
    ({'missed_count_probability': -0.1}, 'missed_count_probability'),
    ({'missed_count_probability': 1.5}, 'missed_count_probability'),
    ({'missed_count_probability': math.nan}, 'missed_count_probability'),
])
def test_bad_encoder_params_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        EncoderParams(**kwargs)


@pytest.mark.parametrize('ppr, decoding, gear_ratio', [(500, 4, 1.0), (360, 2, 1.5), (64, 1, 3.0)])
def test_without_misses_the_count_is_the_floor_of_the_angle(ppr, decoding, gear_ratio):
    n = ppr * decoding * Fraction(gear_ratio)
    encoder = EncoderModel(EncoderParams(ppr, decoding, gear_ratio), seed=0)
    angles = np.concatenate([np.linspace(0.0, 40.0, 301), np.linspace(40.0, -25.0, 211)])
    for angle in angles:
        # Reference: floor(angle N / 2π) in exact rational arithmetic on the float angle and a
        # 40-digit rational 2π (the angles avoid edges by far more than its error).
        expected = math.floor(Fraction(float(angle)) * n / TWO_PI)
        assert encoder.ticks(float(angle)) == expected
    assert encoder.missed == 0


def test_quarter_turn_of_a_500_ppr_x4_encoder():
    encoder = EncoderModel(EncoderParams(500, 4), seed=0)
    assert encoder.ticks(math.pi / 2.0 + 1e-9) == 500   # 360° / (4 PPR) per count
    assert encoder.ticks(2.0 * math.pi + 1e-9) == 2000
    assert encoder.ticks(-1e-9) == -1


def test_missed_counts_fraction_matches_p():
    p = 0.01
    params = EncoderParams(500, 4, missed_count_probability=p)
    encoder = EncoderModel(params, seed=2024)
    angles = np.linspace(0.0, 2000.0 * math.pi, 20_001)   # 1000 revolutions forward
    readings = [encoder.ticks(float(a)) for a in angles]
    edges = quantize_ticks(float(angles[-1]), params.ticks_per_revolution)
    lost = edges - readings[-1]
    assert lost == encoder.missed
    assert abs(lost - edges * p) < 5.0 * math.sqrt(edges * p * (1.0 - p))
    assert np.all(np.diff(readings) >= 0)          # forward motion never counts backwards
    ideal = [quantize_ticks(float(a), params.ticks_per_revolution) for a in angles]
    assert np.all(np.diff(np.subtract(ideal, readings)) >= 0)   # lost counts stay lost


def test_missed_counts_spread_is_binomial():
    p, edges_per_run = 0.05, 2000
    params = EncoderParams(500, 4, missed_count_probability=p)
    steps = np.linspace(0.0, 2.0 * math.pi + 1e-9, 41)   # one revolution in 40 calls
    lost = []
    for run_seed in range(400):
        encoder = EncoderModel(params, seed=run_seed)
        for angle in steps:
            reading = encoder.ticks(float(angle))
        lost.append(edges_per_run - reading)
    lost = np.array(lost)
    variance = edges_per_run * p * (1.0 - p)
    assert abs(lost.mean() - edges_per_run * p) < 5.0 * math.sqrt(variance / lost.size)
    dof = lost.size - 1
    ratio = lost.var(ddof=1) / variance
    assert chi2.ppf(1e-6, dof) / dof < ratio < chi2.ppf(1.0 - 1e-6, dof) / dof


def test_backwards_the_counter_lags_from_above():
    params = EncoderParams(500, 4, missed_count_probability=0.2)
    encoder = EncoderModel(params, seed=3)
    angles = np.linspace(0.0, -20.0 * math.pi, 2001)
    readings = [encoder.ticks(float(a)) for a in angles]
    assert readings[-1] > quantize_ticks(float(angles[-1]), params.ticks_per_revolution)
    assert encoder.missed < 0
    assert np.all(np.diff(readings) <= 0)


def test_all_edges_missed_and_reset():
    encoder = EncoderModel(EncoderParams(500, 4, missed_count_probability=1.0), seed=0)
    assert encoder.ticks(10.0) == 0
    assert encoder.missed == quantize_ticks(10.0, 2000)
    encoder.reset()
    assert encoder.missed == 0
    assert encoder.ticks(0.0) == 0


def test_same_seed_same_counts_and_generator_accepted():
    params = EncoderParams(500, 4, missed_count_probability=0.1)
    angles = np.linspace(0.0, 300.0, 200)

    def counts(seed_or_generator):
        encoder = EncoderModel(params, seed=seed_or_generator)
        return [encoder.ticks(float(x)) for x in angles]

    assert counts(9) == counts(9) == counts(np.random.default_rng(9))
    assert counts(9) != counts(10)


def test_bad_model_input_is_refused():
    encoder = EncoderModel(EncoderParams(), seed=0)
    with pytest.raises(ValueError, match='finite'):
        encoder.ticks(math.nan)
    with pytest.raises(ValueError, match='EncoderParams'):
        EncoderModel(2000, seed=0)
