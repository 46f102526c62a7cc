"""Tests of robotica_sim.encoder_model: incremental-encoder counts (book §7.3.2, catalog §13.6)."""
import math

from hypothesis import given, seed, settings
import hypothesis.strategies as st
import pytest

from robotica_sim.encoder_model import quantize_ticks

ANGLES = st.floats(min_value=-1e4, max_value=1e4, allow_nan=False, allow_infinity=False)
RESOLUTIONS = st.sampled_from([1, 2, 3, 4, 7, 360, 1000, 1024, 4096, 10000])


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
