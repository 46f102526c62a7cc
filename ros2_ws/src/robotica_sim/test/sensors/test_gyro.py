"""
Tests of robotica_sim.sensors.gyro (book §7.7.3; catalogue §5.7, §13.6 and Part 15).

References are the defining statistics of each noise process, not the code: white noise of
density N has variance N²/dt per sample and no correlation; a first-order Gauss-Markov process
has variance σ² and autocorrelation exp(-|lag|/T) (so it falls to 1/e at lag T and its lag-1
coefficient is exp(-dt/T)); a random walk K has independent increments of variance K² dt.
Variances are checked against chi-square bounds (with the effective degrees of freedom
N (1 - φ²)/(1 + φ²) of an AR(1) sequence for the Gauss-Markov bias), means against normal
bounds, all at a two-sided probability of about 1e-6 with fixed seeds.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import ParameterError
from robotica_sim.sensors.allan import allan_deviation
from robotica_sim.sensors.gyro import (gyro_params, GYRO_PRESETS, gyro_term_specs, GyroModel,
                                       GyroParams)
from scipy.stats import chi2

DT = 0.01      # [s]
Z = 5.0        # normal bound (two-sided p ≈ 6e-7)
P = 1e-6       # chi-square tail probability


def assert_variance(samples, expected, dof=None):
    samples = np.asarray(samples)
    dof = samples.size - 1 if dof is None else dof
    ratio = samples.var(ddof=1) / expected
    low, high = chi2.ppf(P, dof) / dof, chi2.ppf(1.0 - P, dof) / dof
    assert low < ratio < high, (ratio, low, high)


def assert_mean(samples, expected, stddev):
    samples = np.asarray(samples)
    assert abs(samples.mean() - expected) < Z * stddev / math.sqrt(samples.size)


def test_ideal_gyro_reads_the_true_rate():
    gyro = GyroModel(GyroParams(), seed=0)
    rates = np.linspace(-3.0, 3.0, 13)
    assert [gyro.measure(r, DT) for r in rates] == list(rates)
    np.testing.assert_array_equal(gyro.measure_many(rates, DT), rates)
    assert gyro.bias == 0.0


@pytest.mark.parametrize('rate', [-2.0, 0.0, 0.7])
def test_scale_factor_and_turn_on_bias(rate):
    gyro = GyroModel(GyroParams(initial_bias=0.01, scale_factor_error=-0.03), seed=0)
    assert gyro.measure(rate, DT) == pytest.approx(0.97 * rate + 0.01, abs=1e-15)
    np.testing.assert_allclose(gyro.measure_many([rate] * 3, DT), 0.97 * rate + 0.01,
                               atol=1e-15)


@pytest.mark.parametrize('dt', [0.001, 0.01, 0.1])
def test_white_noise_mean_variance_and_whiteness(dt):
    density = 2e-3  # N [rad/s/√Hz]
    n = 100_000
    gyro = GyroModel(GyroParams(noise_density=density), seed=11)
    y = gyro.measure_many(np.full(n, 0.5), dt)
    sigma = density / math.sqrt(dt)
    assert gyro.variance(dt) == pytest.approx(sigma ** 2, rel=1e-12)
    assert_mean(y, 0.5, sigma)
    assert_variance(y, sigma ** 2)
    e = y - 0.5
    lag1 = np.dot(e[:-1], e[1:]) / np.dot(e, e)
    assert abs(lag1) < Z / math.sqrt(n)


def test_white_noise_variance_bound_rejects_a_wrong_density():
    y = GyroModel(GyroParams(noise_density=2.2e-3), seed=11).measure_many(np.zeros(100_000), DT)
    with pytest.raises(AssertionError):
        assert_variance(y, (2e-3) ** 2 / DT)


def test_allan_deviation_of_white_noise():
    """Angle random walk: slope -1/2 at short τ, level N/√τ (IEEE Std 952)."""
    density = 1e-3
    y = GyroModel(GyroParams(noise_density=density), seed=3).measure_many(np.zeros(2 ** 16), DT)
    sizes = np.array([1, 2, 4, 8, 16, 32, 64])
    taus, adev = allan_deviation(y, DT, taus=sizes * DT)
    assert np.polyfit(np.log(taus), np.log(adev), 1)[0] == pytest.approx(-0.5, abs=0.03)
    np.testing.assert_allclose(adev * np.sqrt(taus), density, rtol=0.05)


def autocorrelation(x, max_lag):
    """Sample autocorrelation at lags 1..max_lag - 1 (FFT of the zero-padded, centred x)."""
    e = np.asarray(x) - np.mean(x)
    spectrum = np.fft.rfft(e, 2 * e.size)
    acov = np.fft.irfft(spectrum * np.conj(spectrum))[:max_lag]
    return acov[1:] / acov[0]


def gauss_markov_run(sigma, correlation_time, n, seed):
    params = GyroParams(bias_instability=sigma, bias_correlation_time=correlation_time)
    return GyroModel(params, seed=seed).measure_many(np.zeros(n), DT)


def test_gauss_markov_bias_variance_and_correlation_time():
    sigma, correlation_time = 2e-3, 0.5  # σ_b [rad/s], T [s]
    n = 200_000  # 4000 T
    b = gauss_markov_run(sigma, correlation_time, n, seed=5)
    phi = math.exp(-DT / correlation_time)
    dof = n * (1.0 - phi ** 2) / (1.0 + phi ** 2)
    assert_variance(b, sigma ** 2, dof)
    assert abs(b.mean()) < Z * sigma * math.sqrt((1.0 + phi) / (1.0 - phi) / n)
    # Autocorrelation: where it falls to 1/e is the correlation time.
    lags = np.arange(1, int(3 * correlation_time / DT))
    acf = autocorrelation(b, lags.size + 1)
    crossing = lags[np.argmax(acf < math.exp(-1.0))] * DT
    assert crossing == pytest.approx(correlation_time, rel=0.1)
    # The lag-1 coefficient is φ = exp(-dt/T) (standard error √((1 - φ²)/n)).
    assert acf[0] == pytest.approx(phi, abs=Z * math.sqrt((1.0 - phi ** 2) / n))


def test_gauss_markov_correlation_time_check_rejects_a_wrong_one():
    """The 1/e crossing of a bias with T = 0.75 s is not within 10 % of 0.5 s."""
    b = gauss_markov_run(2e-3, 0.75, 200_000, seed=5)
    lags = np.arange(1, 150)
    acf = autocorrelation(b, lags.size + 1)
    assert lags[np.argmax(acf < math.exp(-1.0))] * DT > 0.55


def test_gauss_markov_is_stationary_with_a_varying_period():
    """The exact discretisation keeps variance σ² for any dt, and starts stationary."""
    sigma, correlation_time = 1e-3, 0.2
    gyro = GyroModel(GyroParams(bias_instability=sigma, bias_correlation_time=correlation_time),
                     seed=8)
    periods = np.random.default_rng(1).uniform(0.001, 0.05, 20_000)
    b = np.array([gyro.measure(0.0, dt) for dt in periods])
    phi = math.exp(-periods.mean() / correlation_time)
    assert_variance(b, sigma ** 2, 20_000 * (1.0 - phi ** 2) / (1.0 + phi ** 2))
    # At power-on the bias is already N(0, σ²): across many gyros.
    starts = [GyroModel(GyroParams(bias_instability=sigma), seed=s).bias for s in range(2000)]
    assert_mean(starts, 0.0, sigma)
    assert_variance(starts, sigma ** 2)


def test_rate_random_walk_increments():
    k = 1e-3  # K [rad/s^1.5]
    n = 100_000
    y = GyroModel(GyroParams(random_walk=k), seed=21).measure_many(np.zeros(n), DT)
    increments = np.diff(y)
    assert_mean(increments, 0.0, k * math.sqrt(DT))
    assert_variance(increments, k ** 2 * DT)
    lag1 = np.dot(increments[:-1], increments[1:]) / np.dot(increments, increments)
    assert abs(lag1) < Z / math.sqrt(n)
    # The walk starts at 0: the first reading is one increment.
    firsts = [GyroModel(GyroParams(random_walk=k), seed=s).measure(0.0, DT) for s in range(2000)]
    assert_variance(firsts, k ** 2 * DT)


def test_turn_on_bias_spread():
    params = GyroParams(initial_bias=0.1, initial_bias_stddev=0.01)
    biases = [GyroModel(params, seed=s).measure(0.0, DT) for s in range(2000)]
    assert_mean(biases, 0.1, 0.01)
    assert_variance(biases, 0.01 ** 2)
    gyro = GyroModel(params, seed=4)
    first = gyro.bias
    assert gyro.measure_many(np.zeros(5), DT) == pytest.approx(first)  # constant until reset
    gyro.reset()
    assert gyro.bias != first


def test_saturation_and_quantisation():
    gyro = GyroModel(GyroParams(saturation=1.0, resolution=0.01), seed=0)
    rates = [-5.0, -1.004, -0.0049, 0.0149, 0.0151, 0.999, 2.0]
    expected = [-1.0, -1.0, 0.0, 0.01, 0.02, 1.0, 1.0]
    np.testing.assert_allclose(gyro.measure_many(rates, DT), expected, atol=1e-15)
    np.testing.assert_allclose([gyro.measure(r, DT) for r in rates], expected, atol=1e-15)


def test_quantisation_noise_enters_the_reported_variance():
    """With σ ≫ LSB/2 the quantised variance is σ² + LSB²/12 (Sheppard's correction)."""
    params = GyroParams(noise_density=1e-3, resolution=0.01)   # σ = 0.01 rad/s = 1 LSB
    gyro = GyroModel(params, seed=13)
    y = gyro.measure_many(np.full(200_000, 0.123), DT)
    np.testing.assert_allclose(y / 0.01, np.rint(y / 0.01), atol=1e-9)
    assert gyro.variance(DT) == pytest.approx(1e-4 + 1e-4 / 12.0)
    assert_variance(y, gyro.variance(DT))
    assert_mean(y, 0.123, 0.01)


@pytest.mark.parametrize('name', sorted(GYRO_PRESETS))
def test_measure_and_measure_many_agree(name):
    params = GYRO_PRESETS[name]
    rates = np.sin(np.linspace(0.0, 20.0, 500))
    one = GyroModel(params, seed=99)
    many = GyroModel(params, seed=99)
    looped = np.array([one.measure(r, DT) for r in rates])
    vectorised = many.measure_many(rates, DT)
    tolerance = max(params.resolution, 1e-15)
    np.testing.assert_allclose(vectorised, looped, rtol=0.0, atol=tolerance)
    assert many.bias == pytest.approx(one.bias, rel=1e-9, abs=1e-15)
    # Interleaving the two keeps the same stream.
    assert many.measure(0.3, DT) == pytest.approx(one.measure_many([0.3], DT)[0], abs=tolerance)


def test_same_seed_same_readings_and_generator_accepted():
    params = GYRO_PRESETS['mems_consumer']
    a = GyroModel(params, seed=5).measure_many(np.zeros(100), DT)
    b = GyroModel(params, seed=np.random.default_rng(5)).measure_many(np.zeros(100), DT)
    c = GyroModel(params, seed=6).measure_many(np.zeros(100), DT)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_presets():
    assert set(GYRO_PRESETS) == {'mems_consumer', 'mems_tactical', 'fog'}
    consumer = GYRO_PRESETS['mems_consumer']
    assert consumer.saturation == pytest.approx(math.radians(100.0))     # book §7.7.3
    assert consumer.noise_density == pytest.approx(math.radians(0.005))  # MPU-6050
    grades = [GYRO_PRESETS[name] for name in ('mems_consumer', 'mems_tactical', 'fog')]
    for better, worse in zip(grades[1:], grades[:-1]):
        assert better.noise_density < worse.noise_density
        assert better.bias_instability < worse.bias_instability
        assert better.random_walk < worse.random_walk


def test_measure_many_of_nothing():
    assert GyroModel(GyroParams(), seed=0).measure_many([], DT).shape == (0,)


@pytest.mark.parametrize('kwargs, match', [
    ({'noise_density': -1e-3}, 'noise_density'),
    ({'noise_density': math.nan}, 'noise_density'),
    ({'bias_instability': -1.0}, 'bias_instability'),
    ({'random_walk': math.inf}, 'random_walk'),
    ({'initial_bias_stddev': -0.1}, 'initial_bias_stddev'),
    ({'resolution': -0.1}, 'resolution'),
    ({'bias_correlation_time': 0.0}, 'bias_correlation_time'),
    ({'bias_correlation_time': math.inf}, 'bias_correlation_time'),
    ({'initial_bias': math.nan}, 'initial_bias'),
    ({'scale_factor_error': -1.0}, 'scale_factor_error'),
    ({'saturation': 0.0}, 'saturation'),
    ({'saturation': math.nan}, 'saturation'),
])
def test_bad_params_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        GyroParams(**kwargs)


def test_bad_measurements_are_refused():
    gyro = GyroModel(GyroParams(), seed=0)
    with pytest.raises(ValueError, match='true_rate'):
        gyro.measure(math.nan, DT)
    for dt in (0.0, -0.01, math.nan):
        with pytest.raises(ValueError, match='dt'):
            gyro.measure(0.0, dt)
        with pytest.raises(ValueError, match='dt'):
            gyro.measure_many([0.0], dt)
        with pytest.raises(ValueError, match='dt'):
            gyro.variance(dt)
    with pytest.raises(ValueError, match='finite'):
        gyro.measure_many([0.0, math.inf], DT)
    with pytest.raises(ValueError, match='shape'):
        gyro.measure_many([[0.0]], DT)
    with pytest.raises(ValueError, match='GyroParams'):
        GyroModel({'noise_density': 0.0}, seed=0)


# -- the emulator's parameters: every term, the preset as starting values ----------------------
@pytest.mark.parametrize('name', sorted(GYRO_PRESETS))
def test_parameters_without_terms_are_the_preset(name):
    assert gyro_params({'preset': name}) == GYRO_PRESETS[name]
    specs = gyro_term_specs(name)
    assert set(specs) == {f.name for f in dataclasses.fields(GyroParams)}
    for term, spec in specs.items():   # each preset value lies within its declared range
        spec.check(term, spec.default)
        assert spec.default == getattr(GYRO_PRESETS[name], term)


def test_a_term_given_overrides_the_preset_and_only_it():
    params = gyro_params({'preset': 'fog', 'noise_density': 1e-3, 'saturation': 2.0})
    assert dataclasses.replace(GYRO_PRESETS['fog'], noise_density=1e-3, saturation=2.0) \
        == params
    # The overridden density is what the model draws: variance N²/dt within chi-square bounds.
    gyro = GyroModel(dataclasses.replace(params, initial_bias_stddev=0.0, bias_instability=0.0,
                                         random_walk=0.0), seed=3)
    assert_variance(gyro.measure_many(np.zeros(20_000), DT), 1e-3 ** 2 / DT)


@pytest.mark.parametrize('values, name', [
    ({'noise_density': -1e-3}, 'noise_density'),
    ({'bias_correlation_time': 0.0}, 'bias_correlation_time'),
    ({'scale_factor_error': 0.7}, 'scale_factor_error'),
    ({'saturation': 0.0}, 'saturation'),
    ({'preset': 'ring_laser'}, 'preset'),
])
def test_a_bad_term_is_refused_by_name(values, name):
    with pytest.raises(ParameterError) as info:
        gyro_params({'preset': 'mems_consumer', **values})
    assert info.value.name == name


def test_terms_may_change_while_the_biases_go_on():
    gyro = GyroModel(GYRO_PRESETS['mems_consumer'], seed=4)
    gyro.measure_many(np.zeros(100), DT)
    bias = gyro.bias
    gyro.params = dataclasses.replace(gyro.params, scale_factor_error=0.2)
    assert gyro.bias == bias and gyro.params.scale_factor_error == 0.2
    with pytest.raises(ValueError, match='GyroParams'):
        gyro.params = {'scale_factor_error': 0.2}
