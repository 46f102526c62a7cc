"""
Tests of robotica_sim.sensors.force_torque (book §7.6, (7.8)-(7.11); catalogue Part 5.6).

References are written here, not taken from the code: the Maltese-cross H from the closed-form
spoke loads of the module docstring (t_k, z_k by hand, times G V K c / 4 of (7.8)-(7.9)); the
covariance of the recovered wrench as (HᵀH)⁻¹Hᵀ Σ_V H(HᵀH)⁻ᵀ with explicit inverses; the ADC
codes by hand. Means are checked with a chi-square bound on their Mahalanobis distance, the
covariance by whitening with the reference (each variance within chi-square bounds, each
correlation within normal bounds), all at a two-sided probability of about 1e-6, fixed seeds.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_kin.parameter_specs import check_parameters, ParameterError
from robotica_sim.sensors.force_torque import (bridge_gain, calibrate, FT_PRESETS,
                                               ft_sensor_params, ft_term_specs, FtSensorModel,
                                               FtSensorParams, maltese_cross_matrix,
                                               pseudo_inverse)
from scipy.stats import chi2

P = 1e-6       # chi-square tail probability
Z = 5.0        # normal bound (two-sided p ≈ 6e-7)
WRENCH = np.array([120.0, -80.0, 300.0, 4.0, -2.5, 1.5])   # [N, N m]


def assert_close(actual, expected, rtol=1e-9):
    """Elementwise within rtol of the largest |element| of ``expected`` (zeros compare too)."""
    np.testing.assert_allclose(actual, expected, rtol=0.0,
                               atol=rtol * np.abs(expected).max())


def reference_matrix(rho, scale):
    """H (8, 6) of the module docstring's closed form: rows t_k (2k) and z_k (2k + 1)."""
    rows = []
    for k in range(4):
        s, c = math.sin(k * math.pi / 2), math.cos(k * math.pi / 2)
        rows.append([-s / 2, c / 2, 0.0, 0.0, 0.0, 1 / (4 * rho)])           # t_k
        rows.append([0.0, 0.0, 1 / 4, s / (2 * rho), -c / (2 * rho), 0.0])   # z_k
    return scale * np.array(rows)


def reference_covariance(H, variance):
    """(HᵀH)⁻¹Hᵀ (variance I) H(HᵀH)⁻ᵀ with explicit inverses, book (7.11)."""
    hs = np.linalg.inv(H.T @ H) @ H.T
    return hs @ (variance * np.eye(H.shape[0])) @ hs.T


def assert_mean(samples, expected, covariance):
    """N (m - F)ᵀ Σ⁻¹ (m - F) ~ χ²(6): below its 1 - P quantile."""
    d = samples.mean(axis=0) - expected
    distance = samples.shape[0] * d @ np.linalg.solve(covariance, d)
    assert distance < chi2.ppf(1.0 - P, samples.shape[1]), distance


def assert_covariance(samples, covariance):
    """Whitened by the reference, the samples' covariance is I within chi-square bounds."""
    n = samples.shape[0]
    white = (samples - samples.mean(axis=0)) @ np.linalg.inv(np.linalg.cholesky(covariance)).T
    sample = white.T @ white / (n - 1)
    low, high = chi2.ppf(P, n - 1) / (n - 1), chi2.ppf(1.0 - P, n - 1) / (n - 1)
    assert np.all((low < np.diag(sample)) & (np.diag(sample) < high)), np.diag(sample)
    off = sample[~np.eye(sample.shape[0], dtype=bool)]
    assert np.abs(off).max() < Z / math.sqrt(n), np.abs(off).max()


# -- the calibration matrix of the geometry, (7.8)-(7.10) ------------------------------------
@pytest.mark.parametrize('name', sorted(FT_PRESETS))
def test_geometry_matrix_is_the_closed_form(name):
    p = FT_PRESETS[name]
    scale = p.amplifier_gain * p.bridge_voltage * p.gauge_factor / 4.0 * p.strain_per_newton
    H = reference_matrix(p.spoke_radius, scale)
    np.testing.assert_allclose(maltese_cross_matrix(p), H, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(FtSensorModel(p, seed=0).calibration_matrix, H, rtol=1e-12,
                               atol=1e-15)


def test_bridge_gain_is_book_7_9_linearised():
    # K = 2.5 (chromium, book (7.8)), V = 10 V, G = 1: ΔV = V K ε / 4 = 6.25 V per unit strain,
    # which the exact one-arm bridge V x / (4 + 2x), x = K ε, approaches as ε -> 0.
    p = FtSensorParams(gauge_factor=2.5, bridge_voltage=10.0)
    assert bridge_gain(p) == 6.25
    eps = 1e-6
    x = 2.5 * eps
    assert bridge_gain(p) * eps == pytest.approx(10.0 * x / (4.0 + 2.0 * x), rel=1e-5)


def test_spoke_loads_balance_the_wrench():
    """The gauges' shares, put back on the spokes, give the wrench again (equilibrium)."""
    p = FtSensorParams(strain_per_newton=1.0, bridge_voltage=4.0, gauge_factor=1.0)
    loads = maltese_cross_matrix(p) @ WRENCH          # t_0, z_0, t_1, z_1, ... [N]
    rho, f, m = p.spoke_radius, np.zeros(3), np.zeros(3)
    for k in range(4):
        r = np.array([math.cos(k * math.pi / 2), math.sin(k * math.pi / 2), 0.0])
        force = loads[2 * k] * np.cross([0.0, 0.0, 1.0], r) + loads[2 * k + 1] * np.eye(3)[2]
        f += force
        m += np.cross(rho * r, force)
    np.testing.assert_allclose(np.concatenate([f, m]), WRENCH, rtol=1e-12)


def test_ideal_sensor_recovers_the_wrench_exactly():
    ft = FtSensorModel(FtSensorParams(), seed=0)
    reading = ft.measure(WRENCH)
    np.testing.assert_allclose(reading.volts, maltese_cross_matrix(FtSensorParams()) @ WRENCH,
                               rtol=1e-14)
    np.testing.assert_allclose(reading.wrench, WRENCH, rtol=1e-12)
    assert not reading.saturated.any()


def test_pseudo_inverse_is_book_7_11():
    H = maltese_cross_matrix(FT_PRESETS['metal_foil'])
    assert_close(pseudo_inverse(H), np.linalg.inv(H.T @ H) @ H.T)
    np.testing.assert_allclose(pseudo_inverse(H) @ H, np.eye(6), atol=1e-12)


# -- noise: mean and covariance of F̂ = H^S V ---------------------------------------------------
@pytest.mark.parametrize('name', sorted(FT_PRESETS))
def test_recovered_wrench_mean_and_covariance(name):
    params = dataclasses.replace(FT_PRESETS[name], adc_bits=0)   # noise only
    n = 20_000
    ft = FtSensorModel(params, seed=21)
    readings = ft.measure_many(np.tile(WRENCH, (n, 1)))
    H = reference_matrix(params.spoke_radius, bridge_gain(params) * params.strain_per_newton)
    covariance = reference_covariance(H, params.noise_stddev ** 2)
    assert_close(ft.wrench_covariance(), covariance)
    assert not readings.saturated.any()
    assert_mean(readings.wrench, WRENCH, covariance)
    assert_covariance(readings.wrench, covariance)


def test_covariance_check_rejects_a_wrong_noise():
    params = dataclasses.replace(FT_PRESETS['metal_foil'], adc_bits=0, noise_stddev=1.1e-3)
    readings = FtSensorModel(params, seed=21).measure_many(np.tile(WRENCH, (20_000, 1)))
    H = reference_matrix(params.spoke_radius, bridge_gain(params) * params.strain_per_newton)
    with pytest.raises(AssertionError):
        assert_covariance(readings.wrench, reference_covariance(H, 1e-6))


def test_quantisation_noise_enters_the_covariance():
    """σ = 1 LSB: the quantised gauges have variance σ² + q²/12 (Sheppard)."""
    params = dataclasses.replace(FT_PRESETS['metal_foil'], noise_stddev=20.0 / 2 ** 12,
                                 adc_bits=12)
    ft = FtSensorModel(params, seed=8)
    readings = ft.measure_many(np.tile(WRENCH, (20_000, 1)))
    q = 20.0 / 2 ** 12
    np.testing.assert_allclose(readings.volts / q, np.rint(readings.volts / q), atol=1e-9)
    H = reference_matrix(params.spoke_radius, bridge_gain(params) * params.strain_per_newton)
    covariance = reference_covariance(H, q ** 2 + q ** 2 / 12.0)
    assert_close(ft.wrench_covariance(), covariance)
    assert_mean(readings.wrench, WRENCH, covariance)
    assert_covariance(readings.wrench, covariance)


def test_measure_and_measure_many_agree_and_seeds_repeat():
    params = FT_PRESETS['metal_foil']
    wrenches = np.outer(np.linspace(-1.0, 1.0, 7), WRENCH)
    one = FtSensorModel(params, seed=3)
    looped = np.array([one.measure(w).volts for w in wrenches])
    many = FtSensorModel(params, seed=np.random.default_rng(3)).measure_many(wrenches)
    np.testing.assert_array_equal(looped, many.volts)
    other = FtSensorModel(params, seed=4).measure_many(wrenches)
    assert not np.array_equal(other.volts, many.volts)


# -- the ADC: quantisation and saturation -------------------------------------------------------
def test_adc_codes_and_saturation_by_hand():
    # H = I (six gauges, one a wrench axis), 4 bits over ±8 V: q = 1 V, codes -8..7.
    ft = FtSensorModel(FtSensorParams(adc_bits=4, adc_range=8.0), seed=0,
                       calibration_matrix=np.eye(6))
    reading = ft.measure([0.4, 0.6, -2.6, 7.4, -9.0, 100.0])
    assert reading.volts.tolist() == [0.0, 1.0, -3.0, 7.0, -8.0, 7.0]
    assert reading.saturated.tolist() == [False, False, False, False, True, True]
    np.testing.assert_array_equal(reading.wrench, reading.volts)


def test_saturation_without_quantisation_and_its_wrong_wrench():
    params = dataclasses.replace(FT_PRESETS['metal_foil'], noise_stddev=0.0, adc_bits=0)
    ft = FtSensorModel(params, seed=0)
    H = ft.calibration_matrix
    rated = ft.measure(WRENCH)
    assert not rated.saturated.any() and np.abs(rated.volts).max() < 10.0
    overload = 20.0 * WRENCH
    reading = ft.measure(overload)
    ideal = H @ overload
    expected = np.clip(ideal, -10.0, 10.0)
    np.testing.assert_allclose(reading.volts, expected, rtol=1e-14)
    assert reading.saturated.tolist() == (np.abs(ideal) > 10.0).tolist()
    assert reading.saturated.any()
    assert np.abs(reading.wrench - overload).max() > 1.0   # clipped gauges: a wrong wrench


# -- calibration with known wrenches --------------------------------------------------------
def known_wrenches(m, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(-1.0, 1.0, (m, 6)) * [400.0, 400.0, 800.0, 8.0, 8.0, 8.0]


@pytest.mark.parametrize('m', [6, 30])
def test_calibration_without_noise_is_exact(m):
    params = dataclasses.replace(FT_PRESETS['metal_foil'], noise_stddev=0.0, adc_bits=0)
    ft = FtSensorModel(params, seed=0)
    w = known_wrenches(m)
    estimate = calibrate(w, ft.measure_many(w).volts)
    np.testing.assert_allclose(estimate, ft.calibration_matrix, rtol=1e-9, atol=1e-15)


def test_calibration_with_noise_is_within_its_bounds():
    """
    Each gauge's row ĥ_i has covariance σ² (WᵀW)⁻¹ (W the known wrenches, m x 6).

    So Σ_i (ĥ_i - h_i)ᵀ WᵀW (ĥ_i - h_i) / σ² ~ χ²(6 n).
    """
    params = dataclasses.replace(FT_PRESETS['metal_foil'], adc_bits=0)
    ft = FtSensorModel(params, seed=5)
    w = known_wrenches(200, seed=1)
    estimate = calibrate(w, ft.measure_many(w).volts)
    error = estimate - ft.calibration_matrix
    statistic = np.einsum('ij,jk,ik->', error, w.T @ w, error) / params.noise_stddev ** 2
    dof = error.size
    assert chi2.ppf(P, dof) < statistic < chi2.ppf(1.0 - P, dof), statistic
    # and the recovered wrench with the estimated H is close to the truth
    hs = pseudo_inverse(estimate)
    assert np.abs(hs @ (ft.calibration_matrix @ WRENCH) - WRENCH).max() < 1.0


def test_a_given_calibration_matrix_replaces_the_geometry():
    H = np.vstack([np.eye(6), np.ones((2, 6))]) * 1e-3
    ft = FtSensorModel(FT_PRESETS['metal_foil'], seed=0, calibration_matrix=H)
    assert ft.gauges == 8
    np.testing.assert_array_equal(ft.calibration_matrix, H)
    ft.params = dataclasses.replace(ft.params, gauge_factor=4.8)   # a term: H stays given
    np.testing.assert_array_equal(ft.calibration_matrix, H)
    geometric = FtSensorModel(FtSensorParams(), seed=0)
    geometric.params = FtSensorParams(gauge_factor=4.0)   # the geometry's H doubles
    np.testing.assert_allclose(geometric.calibration_matrix,
                               2.0 * maltese_cross_matrix(FtSensorParams()), rtol=1e-14)


# -- bad input: one clear ValueError naming the value ---------------------------------------
@pytest.mark.parametrize('kwargs, match', [
    ({'spoke_radius': 0.0}, 'spoke_radius'),
    ({'strain_per_newton': -1e-6}, 'strain_per_newton'),
    ({'gauge_factor': 0.0}, 'gauge_factor'),
    ({'gauge_factor': math.nan}, 'gauge_factor'),
    ({'bridge_voltage': math.inf}, 'bridge_voltage'),
    ({'amplifier_gain': 0.0}, 'amplifier_gain'),
    ({'noise_stddev': -1e-3}, 'noise_stddev'),
    ({'adc_bits': 33}, 'adc_bits'),
    ({'adc_bits': 12.0}, 'adc_bits'),
    ({'adc_range': 0.0}, 'adc_range'),
    ({'adc_range': math.nan}, 'adc_range'),
])
def test_bad_params_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        FtSensorParams(**kwargs)


@pytest.mark.parametrize('matrix, match', [
    (np.eye(6)[:5], 'n >= 6'),
    (np.ones((8, 5)), r'shape \(n, 6\)'),
    (np.ones((8, 6)), 'rank 6'),
    (np.full((6, 6), np.nan), 'finite'),
    ('H', 'numbers'),
])
def test_bad_calibration_matrices_are_refused(matrix, match):
    with pytest.raises(ValueError, match=match):
        FtSensorModel(FtSensorParams(), seed=0, calibration_matrix=matrix)
    with pytest.raises(ValueError, match='calibration_matrix'):
        pseudo_inverse(matrix)


def test_bad_measurements_and_calibrations_are_refused():
    ft = FtSensorModel(FtSensorParams(), seed=0)
    with pytest.raises(ValueError, match='wrench must have shape'):
        ft.measure(WRENCH[:3])
    with pytest.raises(ValueError, match='wrenches must be finite'):
        ft.measure([math.nan] + [0.0] * 5)
    with pytest.raises(ValueError, match='wrenches must have shape'):
        ft.measure_many(WRENCH)
    with pytest.raises(ValueError, match='FtSensorParams'):
        FtSensorModel({'gauge_factor': 2.0}, seed=0)
    with pytest.raises(ValueError, match='FtSensorParams'):
        ft.params = {'gauge_factor': 2.0}
    w = known_wrenches(10)
    volts = ft.measure_many(w).volts
    with pytest.raises(ValueError, match='rank 6'):
        calibrate(w[:5], volts[:5])
    with pytest.raises(ValueError, match='rank 6'):
        calibrate(np.tile(w[:1], (10, 1)), volts)
    with pytest.raises(ValueError, match='readings must have shape'):
        calibrate(w, volts[:9])
    with pytest.raises(ValueError, match='finite'):
        calibrate(w, np.full_like(volts, np.inf))


# -- the emulator's parameters: every term, the preset as starting values -------------------
@pytest.mark.parametrize('name', sorted(FT_PRESETS))
def test_the_preset_gives_every_term_within_its_range(name):
    specs = ft_term_specs(name)
    defaults = {term: spec.default for term, spec in specs.items()}
    check_parameters(specs, defaults)
    assert FtSensorParams(**defaults) == FT_PRESETS[name] == ft_sensor_params({'preset': name})


def test_a_term_given_overrides_the_preset_and_only_it():
    params = ft_sensor_params({'preset': 'semiconductor', 'noise_stddev': 0.01, 'adc_bits': 12})
    assert params == dataclasses.replace(FT_PRESETS['semiconductor'], noise_stddev=0.01,
                                         adc_bits=12)


@pytest.mark.parametrize('values, name', [
    ({'gauge_factor': 0.0}, 'gauge_factor'),       # in range, refused by the model
    ({'adc_bits': 40}, 'adc_bits'),
    ({'spoke_radius': 0.0}, 'spoke_radius'),
    ({'preset': 'capacitive'}, 'preset'),
])
def test_a_bad_term_is_refused_by_name(values, name):
    with pytest.raises(ParameterError) as info:
        ft_sensor_params({'preset': 'metal_foil', **values})
    assert info.value.name == name
    assert '\n' not in str(info.value)
