"""
Tests of robotica_sim.sensors.allan: overlapping Allan deviation (IEEE 952-1997, Part 15).

References are the textbook results for the noise processes themselves, not the gyro model:
white rate noise of density N has σ²(τ) = N²/τ; a discrete rate random walk
r_k = r_{k-1} + K √dt w_k has, exactly, σ²(m dt) = K² dt (2m² + 1)/(6m) (the triangular
weights of the increments in the second difference, Σ c² = (2m³ + m)/3), which tends to the
continuous K² τ/3; a linear ramp R t has σ(τ) = R τ/√2. Confidence bounds: chi-square with
the equivalent degrees of freedom of Riley, NIST SP 1065 (2008), table 5, taken at 3/4 (those
approximations are within about 25 % of a Monte-Carlo check).
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_sim.sensors.allan import allan_deviation, default_cluster_sizes
from scipy.stats import chi2

DT = 0.01  # [s]
N_SAMPLES = 2 ** 16


def edf_white(n_samples, m):
    """NIST SP 1065 table 5, white FM, overlapping ADEV; N = n + 1 phase points."""
    n = n_samples + 1
    return (3.0 * (n - 1) / (2.0 * m) - 2.0 * (n - 2) / n) * 4.0 * m ** 2 / (4.0 * m ** 2 + 5.0)


def edf_random_walk(n_samples, m):
    """NIST SP 1065 table 5, random-walk FM, overlapping ADEV; N = n + 1 phase points."""
    n = n_samples + 1
    return (n - 2) / m * ((n - 1) ** 2 - 3 * m * (n - 1) + 4 * m ** 2) / (n - 3) ** 2


def assert_variance_within_chi2(estimate, expected, edf, p=1e-6):
    edf = 0.75 * np.asarray(edf)  # conservative: wider bounds
    low = chi2.ppf(p, edf) / edf
    high = chi2.ppf(1.0 - p, edf) / edf
    ratio = np.asarray(estimate) / np.asarray(expected)
    assert np.all(ratio > low), (ratio, low)
    assert np.all(ratio < high), (ratio, high)


def loglog_slope(taus, adev):
    return np.polyfit(np.log(taus), np.log(adev), 1)[0]


def brute_force_avar(y, m):
    """Overlapping Allan variance from the definition: differences of adjacent m-averages."""
    means = np.array([y[k:k + m].mean() for k in range(len(y) - m + 1)])
    diffs = means[m:] - means[:-m]
    return 0.5 * np.mean(diffs ** 2)


def test_linear_ramp_is_r_tau_over_root_two():
    rate_slope = 0.3  # R [rad/s²]
    y = rate_slope * DT * np.arange(1000)
    taus, adev = allan_deviation(y, DT)
    np.testing.assert_allclose(adev, rate_slope * taus / math.sqrt(2.0), rtol=1e-9)


def test_constant_rate_has_zero_deviation():
    taus, adev = allan_deviation(np.full(1000, 123.456), DT)
    assert np.all(adev < 1e-12)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-10.0, 10.0), min_size=4, max_size=40), st.data())
def test_matches_the_definition_with_averages(values, data):
    y = np.array(values)
    m = data.draw(st.integers(1, len(y) // 2))
    taus, adev = allan_deviation(y, DT, taus=[m * DT])
    assert taus[0] == pytest.approx(m * DT)
    assert adev[0] ** 2 == pytest.approx(brute_force_avar(y, m), rel=1e-9, abs=1e-12)


def test_white_noise_level_and_slope():
    density = 1e-3  # N [rad/s/√Hz]
    y = density / math.sqrt(DT) * np.random.default_rng(42).standard_normal(N_SAMPLES)
    sizes = np.array([1, 2, 4, 8, 16, 32, 64, 128, 256])
    taus, adev = allan_deviation(y, DT, taus=sizes * DT)
    np.testing.assert_allclose(taus, sizes * DT)
    assert_variance_within_chi2(adev ** 2, density ** 2 / taus, edf_white(N_SAMPLES, sizes))
    assert loglog_slope(taus, adev) == pytest.approx(-0.5, abs=0.03)


def test_random_walk_level_and_slope():
    k = 1e-4  # K [rad/s^1.5]
    y = k * math.sqrt(DT) * np.cumsum(np.random.default_rng(7).standard_normal(N_SAMPLES))
    sizes = np.array([1, 2, 4, 8, 16, 32, 64, 128, 256, 512])
    taus, adev = allan_deviation(y, DT, taus=sizes * DT)
    exact = k ** 2 * DT * (2.0 * sizes ** 2 + 1.0) / (6.0 * sizes)
    assert_variance_within_chi2(adev ** 2, exact, edf_random_walk(N_SAMPLES, sizes))
    # The continuous-time K² τ/3 differs from the exact one by 1/(2m²): the slope is +1/2.
    long = sizes >= 8
    np.testing.assert_allclose(exact[long], k ** 2 * taus[long] / 3.0, rtol=0.01)
    assert loglog_slope(taus[long], adev[long]) == pytest.approx(0.5, abs=0.05)


def test_white_noise_bound_rejects_a_wrong_density():
    """The chi-square bound of the white-noise test fails for a 10 % larger density."""
    density = 1e-3
    y = 1.1 * density / math.sqrt(DT) * np.random.default_rng(42).standard_normal(N_SAMPLES)
    taus, adev = allan_deviation(y, DT, taus=[DT])
    with pytest.raises(AssertionError):
        assert_variance_within_chi2(adev ** 2, density ** 2 / taus, edf_white(N_SAMPLES, 1))


def test_default_taus_are_log_spaced_multiples_of_dt():
    taus, adev = allan_deviation(np.random.default_rng(0).standard_normal(1000), DT)
    sizes = taus / DT
    np.testing.assert_allclose(sizes, np.rint(sizes), atol=1e-9)
    assert sizes[0] == 1 and sizes[-1] == 500
    assert np.all(np.diff(sizes) > 0)
    assert taus.shape == adev.shape
    ratios = sizes[1:] / sizes[:-1]
    assert ratios[sizes[:-1] >= 10].max() < 1.35  # about ten per decade: 10^0.1 = 1.26


def test_default_cluster_sizes_for_two_samples():
    np.testing.assert_array_equal(default_cluster_sizes(2), [1])


@pytest.mark.parametrize('samples, dt, taus, match', [
    ([1.0], DT, None, 'at least 2'),
    ([[1.0, 2.0], [3.0, 4.0]], DT, None, 'shape'),
    ([1.0, math.nan, 2.0], DT, None, 'finite'),
    ([1.0, 2.0, 3.0], 0.0, None, 'dt'),
    ([1.0, 2.0, 3.0], math.inf, None, 'dt'),
    (np.zeros(10), DT, [0.015], 'multiple'),
    (np.zeros(10), DT, [0.06], r'\[dt, 5 dt\]'),
    (np.zeros(10), DT, [0.0], r'\[dt, 5 dt\]'),
    (np.zeros(10), DT, [], 'non-empty'),
    (np.zeros(10), DT, [math.nan], 'non-empty'),
])
def test_bad_input_is_refused(samples, dt, taus, match):
    with pytest.raises(ValueError, match=match):
        allan_deviation(samples, dt, taus)
