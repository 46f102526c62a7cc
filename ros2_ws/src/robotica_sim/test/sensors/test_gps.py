"""
Tests of robotica_sim.sensors.gps (book §7.7.5; seed catalog §5.7 and Part 15).

References: the Rayleigh distribution of a circular normal horizontal error (scipy.stats) for
the CEP and 2DRMS conversions; the book's and the SPS specification's figures for the presets;
chi-square bounds (scipy.stats.chi2) on variances of independent samples; the exact AR(1) form
of a first-order Gauss–Markov process (its normalised innovations are i.i.d. N(0, 1) for any
sampling interval) and the least-squares AR(1) coefficient for the correlation time; the
stationary law of a two-state Markov chain and geometric outage lengths for the dropouts.
All runs use fixed seeds; bounds are about 5σ, so a wrong variance, correlation time or
outage law fails them.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import ParameterError
from robotica_sim.sensors.gps import (
                                      gps_params,
                                      gps_preset,
                                      GPS_PRESETS,
                                      GPS_STATUSES,
                                      gps_term_specs,
                                      GPS_TERMS,
                                      GpsFix,
                                      GpsModel,
                                      GpsParams,
                                      NAVSAT_STATUS,
                                      stddev_from_2drms,
                                      stddev_from_cep,
                                      )
from scipy.stats import chi2, rayleigh

ALPHA = 1e-6  # two-sided level of the chi-square bounds


def chi2_bounds(dof):
    return chi2.ppf(0.5 * ALPHA, dof), chi2.ppf(1.0 - 0.5 * ALPHA, dof)


def quiet(**changes):
    """Return parameters without dropouts, with the given changes."""
    return dataclasses.replace(GpsParams(dropout_probability=0.0), **changes)


def errors_at(model, times, seed=99):
    """Return the stamps and errors (fix - truth) of the fixes at ``times``, truth random."""
    truth = np.random.default_rng(seed).uniform(-1e3, 1e3, (len(times), 3))
    stamps, errors = [], []
    for t, position in zip(times, truth):
        fix = model.measure(t, position)
        if fix is not None:
            stamps.append(fix.stamp)
            errors.append(fix.enu - position)
    return np.array(stamps), np.array(errors)


# Conversions and presets ------------------------------------------------------------------

def test_cep_is_the_rayleigh_median():
    sigma = stddev_from_cep(2.5)
    assert rayleigh.median(scale=sigma) == pytest.approx(2.5, rel=1e-12)


def test_2drms_is_twice_the_rms_radius():
    sigma = stddev_from_2drms(100.0)
    assert 2.0 * math.sqrt(rayleigh.moment(2, scale=sigma)) == pytest.approx(100.0, rel=1e-12)


def test_presets_are_ordered_from_sa_to_rtk():
    names = list(GPS_PRESETS)
    assert names == ['sa_standalone', 'standalone', 'dgps', 'rtk']
    for field in ('horizontal_stddev', 'vertical_stddev'):
        values = [getattr(GPS_PRESETS[name], field) for name in names]
        assert all(a > b for a, b in zip(values, values[1:])), (field, values)
    assert [GPS_PRESETS[name].status for name in names] == ['fix', 'fix', 'dgps', 'rtk']


def test_preset_figures():
    """Book §7.7.5 / SPS 1995: SA 100 m 2DRMS, 156 m 2σ vertical; DGPS 1 m; RTK 2 cm."""
    sa = gps_preset('sa_standalone')
    assert 2.0 * math.sqrt(2.0) * sa.horizontal_stddev == pytest.approx(100.0)
    assert 2.0 * sa.vertical_stddev == pytest.approx(156.0)
    assert 2.0 * math.sqrt(2.0) * gps_preset('dgps').horizontal_stddev == pytest.approx(1.0)
    assert 2.0 * math.sqrt(2.0) * gps_preset('rtk').horizontal_stddev == pytest.approx(0.02)
    standalone = gps_preset('standalone')
    assert rayleigh.median(scale=standalone.horizontal_stddev) == pytest.approx(2.5)
    assert standalone == GpsParams()


@pytest.mark.parametrize('name', list(GPS_PRESETS))
def test_gps_preset_returns_the_preset(name):
    assert gps_preset(name) is GPS_PRESETS[name]


def test_gps_preset_unknown_name_lists_the_names():
    with pytest.raises(ValueError) as info:
        gps_preset('glonass')
    for name in GPS_PRESETS:
        assert name in str(info.value)
    with pytest.raises(ValueError, match='unknown'):
        gps_preset(None)  # type: ignore[arg-type]


def test_presets_cannot_be_changed():
    with pytest.raises(TypeError):
        GPS_PRESETS['rtk'] = GpsParams()  # type: ignore[index]
    with pytest.raises(dataclasses.FrozenInstanceError):
        GPS_PRESETS['rtk'].latency = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(('changes', 'match'), [
    ({'horizontal_stddev': 0.0}, 'horizontal_stddev'),
    ({'vertical_stddev': -1.0}, 'vertical_stddev'),
    ({'vertical_stddev': math.nan}, 'vertical_stddev'),
    ({'correlation_time': 0.0}, 'correlation_time'),
    ({'correlation_time': math.inf}, 'correlation_time'),
    ({'white_stddev': -0.1}, 'white_stddev'),
    ({'horizontal_stddev': 1.0, 'white_stddev': 1.5}, 'white_stddev'),
    ({'update_rate': 0.0}, 'update_rate'),
    ({'latency': -0.01}, 'latency'),
    ({'dropout_probability': 1.0}, 'dropout_probability'),
    ({'dropout_probability': -0.1}, 'dropout_probability'),
    ({'dropout_mean_duration': 0.0}, 'dropout_mean_duration'),
    ({'update_rate': 1.0, 'dropout_mean_duration': 0.5}, 'dropout_mean_duration'),
    ({'status': 'rtk_float'}, 'status'),
    ({'latency': '0.1'}, 'latency'),
    ({'update_rate': True}, 'update_rate'),
])
def test_params_reject_bad_values(changes, match):
    with pytest.raises(ValueError, match=match):
        dataclasses.replace(GpsParams(), **changes)


def test_short_outages_allowed_without_dropouts():
    params = GpsParams(update_rate=1.0, dropout_probability=0.0, dropout_mean_duration=0.1)
    assert params.dropout_mean_duration == 0.1


def test_covariance_and_correlated_part():
    params = GpsParams(horizontal_stddev=2.0, vertical_stddev=3.0, white_stddev=1.0)
    np.testing.assert_array_equal(params.covariance, np.diag([4.0, 4.0, 9.0]))
    np.testing.assert_allclose(params.correlated_stddev ** 2, [3.0, 3.0, 8.0])


def test_navsat_status_values():
    assert dict(NAVSAT_STATUS) == {'fix': 0, 'dgps': 1, 'rtk': 2}
    assert set(NAVSAT_STATUS) == set(GPS_STATUSES)


def test_navsat_status_matches_sensor_msgs():
    from sensor_msgs.msg import NavSatStatus   # a dependency of robotica_sim: never skipped
    assert NAVSAT_STATUS['fix'] == NavSatStatus.STATUS_FIX
    assert NAVSAT_STATUS['dgps'] == NavSatStatus.STATUS_SBAS_FIX
    assert NAVSAT_STATUS['rtk'] == NavSatStatus.STATUS_GBAS_FIX


# Schedule and latency ---------------------------------------------------------------------

@pytest.mark.parametrize('rate', [1.0, 5.0, 10.0, 20.0])
def test_fix_rate_equals_update_rate(rate):
    model = GpsModel(quiet(update_rate=rate), seed=1)
    times = np.arange(3001) * 0.01  # 100 Hz calls for 30 s
    stamps, _ = errors_at(model, times)
    assert len(stamps) == int(round(30.0 * rate)) + 1
    np.testing.assert_allclose(np.diff(stamps), 1.0 / rate, atol=1e-9)


def test_fix_schedule_with_incommensurate_calls():
    """Calls every 13 ms, fixes at 10 Hz: one fix per 0.1 s slot, stamped at the first call."""
    model = GpsModel(quiet(update_rate=10.0), seed=2)
    times = 5.0 + np.arange(2000) * 0.013
    stamps, _ = errors_at(model, times)
    slots = np.floor((stamps - 5.0) * 10.0 + 1e-6)
    np.testing.assert_array_equal(slots, np.arange(len(stamps)))
    assert len(stamps) == math.floor((times[-1] - 5.0) * 10.0) + 1
    lag = stamps - (5.0 + slots * 0.1)
    assert np.all(lag >= -1e-9) and np.all(lag < 0.013)
    assert np.all(np.isin(stamps, times))


def test_none_between_fixes_and_slots_skipped_by_slow_calls():
    model = GpsModel(quiet(update_rate=2.0), seed=3)
    results = [model.measure(t, [0.0, 0.0, 0.0]) for t in (0.0, 0.1, 0.49, 0.5, 0.99)]
    assert [r is not None for r in results] == [True, False, False, True, False]
    # a call after several missed slots gives one fix, and the grid stays anchored at t0
    assert model.measure(2.7, [0.0, 0.0, 0.0]) is not None
    assert model.measure(2.9, [0.0, 0.0, 0.0]) is None
    assert model.measure(3.0, [0.0, 0.0, 0.0]) is not None


@pytest.mark.parametrize('name', list(GPS_PRESETS))
def test_latency_and_fix_contents(name):
    params = dataclasses.replace(gps_preset(name), dropout_probability=0.0)
    model = GpsModel(params, seed=4)
    fix = model.measure(12.5, [1.0, 2.0, 3.0])
    assert isinstance(fix, GpsFix)
    assert fix.stamp == 12.5
    assert fix.available_at == pytest.approx(12.5 + params.latency, abs=1e-12)
    assert fix.status == params.status
    assert fix.navsat_status == NAVSAT_STATUS[params.status]
    np.testing.assert_array_equal(fix.covariance, params.covariance)
    assert fix.enu.shape == (3,)
    with pytest.raises(ValueError):
        fix.enu[0] = 0.0  # read-only


# Error statistics -------------------------------------------------------------------------

def test_error_mean_and_variance_of_independent_fixes():
    """Fixes 1 s apart with τ = 0.05 s are independent: Σ e²/σ² ~ χ²(N) per axis."""
    params = quiet(horizontal_stddev=2.0, vertical_stddev=3.0, white_stddev=1.0,
                   correlation_time=0.05, update_rate=1.0)
    n = 4000
    _, errors = errors_at(GpsModel(params, seed=5), np.arange(n, dtype=float))
    assert errors.shape == (n, 3)
    sigma = np.array([2.0, 2.0, 3.0])
    low, high = chi2_bounds(n)
    for axis in range(3):
        assert abs(errors[:, axis].mean()) < 5.0 * sigma[axis] / math.sqrt(n)
        assert low < np.sum((errors[:, axis] / sigma[axis]) ** 2) < high, axis
    correlation = np.corrcoef(errors.T)
    assert np.all(np.abs(correlation[np.triu_indices(3, 1)]) < 5.0 / math.sqrt(n))


def test_gauss_markov_innovations_for_irregular_intervals():
    """
    Check the exact discretisation of the Gauss–Markov part over random intervals.

    With no white part, ν_k = (x_k - φ_k x_(k-1)) / (σ sqrt(1 - φ_k²)), φ_k = exp(-Δt_k/τ), are
    i.i.d. N(0, 1) for any intervals Δt_k iff the discretisation is exact.
    """
    tau = 2.0
    params = quiet(horizontal_stddev=2.0, vertical_stddev=3.0, white_stddev=0.0,
                   correlation_time=tau, update_rate=1000.0)
    intervals = np.random.default_rng(6).uniform(0.002, 3.0, 5000)
    times = np.concatenate([[0.0], np.cumsum(intervals)])
    stamps, errors = errors_at(GpsModel(params, seed=7), times)
    assert len(stamps) == len(times)
    phi = np.exp(-np.diff(stamps) / tau)[:, None]
    sigma = np.array([2.0, 2.0, 3.0])
    nu = (errors[1:] - phi * errors[:-1]) / (sigma * np.sqrt(1.0 - phi**2))
    n = len(nu)
    low, high = chi2_bounds(n)
    for axis in range(3):
        assert abs(nu[:, axis].mean()) < 5.0 / math.sqrt(n)
        assert low < np.sum(nu[:, axis] ** 2) < high, axis
        lag1 = np.sum(nu[1:, axis] * nu[:-1, axis]) / np.sum(nu[:, axis] ** 2)
        assert abs(lag1) < 5.0 / math.sqrt(n)
    # the first sample is drawn from the stationary law (not zero)
    assert np.any(errors[0] != 0.0)


def test_autocorrelation_time_equals_correlation_time():
    """Least-squares AR(1) coefficient ρ̂ of 10 Hz samples gives τ̂ = -Δt / ln ρ̂ ≈ τ (±15 %)."""
    tau, dt = 1.0, 0.1
    params = quiet(horizontal_stddev=1.0, vertical_stddev=1.0, white_stddev=0.0,
                   correlation_time=tau, update_rate=1.0 / dt)
    _, errors = errors_at(GpsModel(params, seed=8), np.arange(10000) * dt)
    rho = np.sum(errors[1:] * errors[:-1]) / np.sum(errors[:-1] ** 2)
    # σ(ρ̂) = sqrt((1 - ρ²) / 3N), so σ(τ̂)/τ = σ(ρ̂) / (ρ |ln ρ|) ≈ 2.7 %
    assert -dt / math.log(rho) == pytest.approx(tau, rel=0.15)


def test_white_part_is_uncorrelated_between_fixes():
    """Lag-1 autocorrelation = (σ_GM² / σ²) exp(-Δt/τ) = 0.75 · e^-0.1 (Bartlett σ ≈ 0.007)."""
    tau, dt = 1.0, 0.1
    params = quiet(horizontal_stddev=1.0, vertical_stddev=1.0, white_stddev=0.5,
                   correlation_time=tau, update_rate=1.0 / dt)
    _, errors = errors_at(GpsModel(params, seed=9), np.arange(10000) * dt)
    errors = errors - errors.mean(axis=0)
    lag1 = np.sum(errors[1:] * errors[:-1]) / np.sum(errors**2)
    assert lag1 == pytest.approx(0.75 * math.exp(-dt / tau), abs=0.035)


# Dropouts ---------------------------------------------------------------------------------

def runs_of_false(flags):
    """Return the lengths of the runs of False in ``flags`` that end before its end."""
    lengths, current = [], 0
    for flag in flags:
        if not flag:
            current += 1
        elif current:
            lengths.append(current)
            current = 0
    return np.array(lengths)


def test_dropout_fraction_probability_and_mean_duration():
    """
    Check the lost fraction, the loss probability per fix and the mean outage.

    Per-fix loss p = 0.05, mean outage D = 0.5 s at 10 Hz: q = 0.2 per fix, lost fraction
    p / (p + q) = 0.2, outages geometric with mean 1/q = 5 fixes = D.
    """
    rate, p, duration = 10.0, 0.05, 0.5
    params = dataclasses.replace(GpsParams(), update_rate=rate, dropout_probability=p,
                                 dropout_mean_duration=duration)
    model = GpsModel(params, seed=10)
    n = 20000
    on = np.array([model.measure(k / rate, [0.0, 0.0, 0.0]) is not None for k in range(n)])
    q = 1.0 / (rate * duration)
    fraction, lam = p / (p + q), 1.0 - p - q
    sd_fraction = math.sqrt(fraction * (1.0 - fraction) / n * (1.0 + lam) / (1.0 - lam))
    assert abs((~on).mean() - fraction) < 5.0 * sd_fraction
    losses = np.sum(on[:-1] & ~on[1:])
    trials = np.sum(on[:-1])
    assert abs(losses / trials - p) < 5.0 * math.sqrt(p * (1.0 - p) / trials)
    lengths = runs_of_false(on)
    sd_mean = math.sqrt(1.0 - q) / q / math.sqrt(len(lengths))
    assert abs(lengths.mean() - 1.0 / q) < 5.0 * sd_mean
    assert lengths.mean() / rate == pytest.approx(duration, rel=0.25)


def test_dropout_chain_steps_over_skipped_slots():
    """
    Check that the on/off chain takes one step per fix slot, also for skipped slots.

    Calls every 3rd slot: the chain moves 3 steps per call, so an outage ends at a call with
    probability q (1 - λ³) / (p + q), λ = 1 - p - q, not q (mean ≈ 2.2 calls instead of 5).
    """
    rate, p, duration = 10.0, 0.05, 0.5
    params = dataclasses.replace(GpsParams(), update_rate=rate, dropout_probability=p,
                                 dropout_mean_duration=duration)
    model = GpsModel(params, seed=11)
    on = np.array([model.measure(3 * k / rate, [0.0, 0.0, 0.0]) is not None
                   for k in range(10000)])
    q = 1.0 / (rate * duration)
    recover = q * (1.0 - (1.0 - p - q) ** 3) / (p + q)
    lengths = runs_of_false(on)
    sd_mean = math.sqrt(1.0 - recover) / recover / math.sqrt(len(lengths))
    assert abs(lengths.mean() - 1.0 / recover) < 5.0 * sd_mean


def test_no_dropouts_when_probability_is_zero():
    model = GpsModel(quiet(update_rate=10.0), seed=12)
    assert all(model.measure(k / 10.0, [0.0, 0.0, 0.0]) is not None for k in range(2000))


# Reproducibility, reset and input checks --------------------------------------------------

def test_same_seed_same_fixes_and_generator_accepted():
    params = gps_preset('dgps')
    times = np.arange(500) * 0.05
    _, first = errors_at(GpsModel(params, seed=13), times)
    _, second = errors_at(GpsModel(params, seed=13), times)
    _, third = errors_at(GpsModel(params, seed=np.random.default_rng(13)), times)
    _, other = errors_at(GpsModel(params, seed=14), times)
    np.testing.assert_array_equal(first, second)
    np.testing.assert_array_equal(first, third)
    assert first.shape != other.shape or not np.array_equal(first, other)


def test_reset_restarts_the_schedule():
    model = GpsModel(quiet(update_rate=1.0), seed=15)
    assert model.measure(0.0, [0.0, 0.0, 0.0]) is not None
    assert model.measure(0.5, [0.0, 0.0, 0.0]) is None
    model.reset()
    assert model.measure(0.6, [0.0, 0.0, 0.0]) is not None  # new grid anchored at 0.6 s
    assert model.measure(1.5, [0.0, 0.0, 0.0]) is None
    assert model.measure(1.6, [0.0, 0.0, 0.0]) is not None


def test_reset_allows_earlier_time():
    model = GpsModel(quiet(update_rate=1.0), seed=16)
    model.measure(10.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match='backwards'):
        model.measure(9.0, [0.0, 0.0, 0.0])
    model.reset()
    assert model.measure(9.0, [0.0, 0.0, 0.0]) is not None


@pytest.mark.parametrize(('t', 'position', 'match'), [
    (math.nan, [0.0, 0.0, 0.0], 't'),
    (math.inf, [0.0, 0.0, 0.0], 't'),
    (1.0, [0.0, 0.0], 'true_enu'),
    (1.0, [0.0, math.nan, 0.0], 'true_enu'),
    (1.0, [[0.0, 0.0, 0.0]], 'true_enu'),
    (0.5, [0.0, 0.0, 0.0], 'backwards'),
])
def test_measure_rejects_bad_input_and_keeps_state(t, position, match):
    model = GpsModel(quiet(update_rate=1.0), seed=17)
    model.measure(1.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=match):
        model.measure(t, position)
    assert model.measure(1.5, [0.0, 0.0, 0.0]) is None
    assert model.measure(2.0, [0.0, 0.0, 0.0]) is not None


@pytest.mark.parametrize('seed', [None, -1, 1.5, True, 'seed'])
def test_model_rejects_bad_seed(seed):
    with pytest.raises(ValueError, match='seed'):
        GpsModel(GpsParams(), seed=seed)


def test_model_rejects_bad_params():
    with pytest.raises(ValueError, match='GpsParams'):
        GpsModel({'update_rate': 1.0}, seed=0)  # type: ignore[arg-type]


# -- the emulator's parameters: every term, the preset as starting values ----------------------
@pytest.mark.parametrize('name', sorted(GPS_PRESETS))
def test_parameters_without_terms_are_the_preset(name):
    assert gps_params({'preset': name}) == GPS_PRESETS[name]
    fields = {f.name for f in dataclasses.fields(GpsParams)}
    assert {term.replace('.', '_') for term in GPS_TERMS} == fields
    for term, spec in gps_term_specs(name).items():   # preset values within their ranges
        spec.check(term, spec.default)


def test_a_term_given_overrides_the_preset_and_only_it():
    params = gps_params({'preset': 'rtk', 'update_rate': 2.0, 'dropout.probability': 0.0})
    assert params == dataclasses.replace(GPS_PRESETS['rtk'], update_rate=2.0,
                                         dropout_probability=0.0)
    model = GpsModel(params, 0)
    stamps = [fix.stamp for k in range(101)
              if (fix := model.measure(0.01 * k, [0.0, 0.0, 0.0])) is not None]
    assert stamps == pytest.approx([0.0, 0.5, 1.0])   # 2 Hz, never dropped


@pytest.mark.parametrize('values, name', [
    ({'horizontal_stddev': 0.0}, 'horizontal_stddev'),
    ({'white_stddev': 1.0}, 'white_stddev'),                 # > σ_h of dgps: GpsParams refuses
    ({'dropout.mean_duration': 0.05}, 'dropout.mean_duration'),   # < one period at 5 Hz
    ({'dropout.probability': 1.0}, 'dropout.probability'),
    ({'status': 'ppp'}, 'status'),
])
def test_a_bad_term_is_refused_by_name(values, name):
    with pytest.raises(ParameterError) as info:
        gps_params({'preset': 'dgps', **values})
    assert info.value.name == name


def test_a_new_rate_restarts_the_schedule_and_keeps_the_error():
    model = GpsModel(dataclasses.replace(gps_preset('dgps'), dropout_probability=0.0), 1)
    assert model.measure(0.0, [0.0, 0.0, 0.0]) is not None
    assert model.measure(0.1, [0.0, 0.0, 0.0]) is None      # next due at 0.2 s
    model.params = dataclasses.replace(model.params, update_rate=1.0, white_stddev=0.0)
    fix = model.measure(0.1, [0.0, 0.0, 0.0])               # due at once, then 1 Hz
    assert fix is not None and model.measure(0.5, [0.0, 0.0, 0.0]) is None
    assert fix.covariance[0, 0] == pytest.approx(gps_preset('dgps').horizontal_stddev ** 2)
