"""
Tests of robotica_sim.sensors.compass (book §7.7.2, (7.13); catalogue §5.7 and Part 15).

Independent references. Level sensor, yaw ψ (REP-103), declination 0: the horizontal field is
H (sin ψ, cos ψ) in base_link. A horizontal deviation m_h = M H (sin ψ, cos ψ) + (h_x, h_y)
read as z = m_y + i m_x gives the compass deviation δ = arg z - ψ. With M = I and c =
(h_y + i h_x)/H, z = H e^{iψ} (1 + c e^{-iψ}), so

    δ = Σ_{n>=1} (-1)^{n+1} |c|^n sin(n (arg c - ψ)) / n          (hard iron, one-cycle first)

and with h = 0, z = H (α e^{iψ} + β e^{-iψ}), α = ((m11 + m22) + i (m12 - m21))/2,
β = ((m22 - m11) + i (m12 + m21))/2, so with k = β/α

    δ = arg α + Σ_{n>=1} (-1)^{n+1} |k|^n sin(n (arg k - 2ψ)) / n   (soft iron: two-cycle)

(the power series of log(1 + w), |w| < 1). Tilt: the rotations about x and y written out by
hand. Noise: normal and chi-square bounds at a two-sided probability of about 1e-6.
"""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.angles import wrap_to_pi
from robotica_sim.sensors.compass import (
                                          CompassModel,
                                          CompassParams,
                                          earth_field,
                                          heading_error_curve,
                                          heading_noise_stddev,
                                          )
from scipy.stats import chi2

F = 45e-6                  # [T]
INCLINATION = math.radians(54.0)
H = F * math.cos(INCLINATION)
Z = F * math.sin(INCLINATION)  # downwards
YAWS = np.linspace(-math.pi, math.pi, 360, endpoint=False)
SITE = {'declination': 0.0, 'inclination': INCLINATION, 'field_strength': F}


def fourier_fit(yaws, values, harmonics=4):
    """Least-squares A0 + Σ (a_n cos nψ + b_n sin nψ); returns A0, a (n,), b (n,)."""
    columns = [np.ones_like(yaws)]
    for n in range(1, harmonics + 1):
        columns += [np.cos(n * yaws), np.sin(n * yaws)]
    coefficients = np.linalg.lstsq(np.stack(columns, axis=1), values, rcond=None)[0]
    return coefficients[0], coefficients[1::2], coefficients[2::2]


def log_series(constant, w_abs, w_arg, multiple, yaws, terms=60):
    """Return constant + Σ (-1)^{n+1} |w|^n sin(n (arg w - multiple ψ)) / n."""
    total = np.full_like(yaws, constant)
    for n in range(1, terms + 1):
        total += (-1) ** (n + 1) * w_abs ** n * np.sin(n * (w_arg - multiple * yaws)) / n
    return total


@given(st.floats(-10.0, 10.0), st.floats(-math.pi, math.pi), st.floats(-1.4, 1.4))
def test_ideal_compass_reads_the_true_yaw(yaw, declination, inclination):
    params = CompassParams(declination=declination, inclination=inclination, field_strength=F)
    field, heading = CompassModel(params, seed=0).measure(yaw)
    assert abs(wrap_to_pi(heading - yaw)) < 1e-12
    assert -math.pi < heading <= math.pi
    assert np.linalg.norm(field) == pytest.approx(F, rel=1e-12)
    # Raw magnetic heading (7.13), atan2(m_x, m_y), is ψ + D before the correction.
    assert abs(wrap_to_pi(math.atan2(field[0], field[1]) - yaw - declination)) < 1e-12


@pytest.mark.parametrize('yaw, expected', [
    (0.0, (0.0, H, -Z)),               # facing east: north is to the left (+y)
    (math.pi / 2.0, (H, 0.0, -Z)),     # facing north: field ahead
    (math.pi, (0.0, -H, -Z)),          # facing west: north to the right
    (-math.pi / 2.0, (-H, 0.0, -Z)),   # facing south: field behind
])
def test_field_in_base_link_rep103(yaw, expected):
    field, heading = CompassModel(CompassParams(**SITE), seed=0).measure(yaw)
    np.testing.assert_allclose(field, expected, atol=1e-18)
    assert abs(wrap_to_pi(heading - yaw)) < 1e-12


def test_earth_field_components_with_declination():
    d = math.radians(10.0)
    params = CompassParams(declination=d, inclination=INCLINATION, field_strength=F)
    east, north, up = earth_field(params)
    assert math.atan2(east, north) == pytest.approx(d)   # east of true north
    assert math.hypot(east, north) == pytest.approx(H)
    assert up == pytest.approx(-Z)


def test_default_site_is_seville():
    params = CompassParams()
    assert params.field_strength == pytest.approx(43.6e-6)
    assert math.degrees(params.inclination) == pytest.approx(51.1)
    assert math.degrees(params.declination) == pytest.approx(-0.2)
    np.testing.assert_array_equal(params.hard_iron, np.zeros(3))
    assert not params.hard_iron.flags.writeable


@pytest.mark.parametrize('hard_iron', [(4e-6, 0.0, 0.0), (0.0, -6e-6, 3e-6), (5e-6, 5e-6, -1e-5)])
def test_hard_iron_is_a_one_cycle_deviation(hard_iron):
    params = CompassParams(hard_iron=hard_iron, **SITE)
    curve = heading_error_curve(params, YAWS)
    c = complex(hard_iron[1], hard_iron[0]) / H
    np.testing.assert_allclose(curve, log_series(0.0, abs(c), np.angle(c), 1, YAWS), atol=1e-12)
    a0, a, b = fourier_fit(YAWS, curve)
    # One-cycle: δ ≈ (h_x/H) cos ψ - (h_y/H) sin ψ; higher harmonics are O(|c|²).
    assert abs(a0) < 1e-12
    assert a[0] == pytest.approx(hard_iron[0] / H, abs=abs(c) ** 3)
    assert b[0] == pytest.approx(-hard_iron[1] / H, abs=abs(c) ** 3)
    assert np.hypot(a[1], b[1]) == pytest.approx(abs(c) ** 2 / 2.0, abs=1e-12)
    assert np.hypot(a[0], b[0]) > 5.0 * np.hypot(a[1:], b[1:]).max()


@pytest.mark.parametrize('horizontal', [
    ((1.1, 0.0), (0.0, 0.95)),      # different gains: sin 2ψ
    ((1.0, 0.08), (0.08, 1.0)),     # symmetric cross-coupling: cos 2ψ
    ((1.0, 0.05), (-0.05, 1.0)),    # antisymmetric: a constant (misalignment)
    ((1.05, 0.1), (0.02, 0.9)),
])
def test_soft_iron_is_a_two_cycle_deviation(horizontal):
    m = np.array(horizontal)
    soft_iron = np.eye(3)
    soft_iron[:2, :2] = m
    curve = heading_error_curve(CompassParams(soft_iron=soft_iron, **SITE), YAWS)
    alpha = complex(m[0, 0] + m[1, 1], m[0, 1] - m[1, 0]) / 2.0
    beta = complex(m[1, 1] - m[0, 0], m[0, 1] + m[1, 0]) / 2.0
    k = beta / alpha
    expected = log_series(np.angle(alpha), abs(k), np.angle(k), 2, YAWS)
    np.testing.assert_allclose(curve, expected, atol=1e-12)
    a0, a, b = fourier_fit(YAWS, curve)
    # Odd harmonics vanish: m(ψ + π) = -m(ψ), so δ has period π.
    np.testing.assert_allclose([a[0], b[0], a[2], b[2]], 0.0, atol=1e-12)
    assert a0 == pytest.approx(np.angle(alpha), abs=1e-12)
    assert np.hypot(a[1], b[1]) == pytest.approx(abs(k), abs=1e-12)


@pytest.mark.parametrize('tilt', [math.radians(3.0), math.radians(-8.0)])
def test_roll_tilt_error(tilt):
    """Tilt ε about base_link x: m_x = H sin ψ, m_y = H cos ψ cos ε - Z sin ε."""
    params = CompassParams(tilt_error=tilt, tilt_axis=0.0, **SITE)
    curve = heading_error_curve(params, YAWS)
    heading = np.arctan2(H * np.sin(YAWS), H * np.cos(YAWS) * math.cos(tilt) - Z * math.sin(tilt))
    np.testing.assert_allclose(curve, wrap_to_pi(heading - YAWS), atol=1e-12)
    # One-cycle to first order: δ ≈ ε tan I sin ψ.
    a0, a, b = fourier_fit(YAWS, curve)
    assert b[0] == pytest.approx(tilt * math.tan(INCLINATION), rel=0.1)


def test_pitch_tilt_error():
    """Tilt ε about base_link y: m_x = H sin ψ cos ε + Z sin ε, m_y = H cos ψ."""
    tilt = math.radians(5.0)
    params = CompassParams(tilt_error=tilt, tilt_axis=math.pi / 2.0, **SITE)
    field, _ = CompassModel(params, seed=0).measure(0.4)
    expected = [H * math.sin(0.4) * math.cos(tilt) + Z * math.sin(tilt), H * math.cos(0.4),
                H * math.sin(0.4) * math.sin(tilt) - Z * math.cos(tilt)]
    np.testing.assert_allclose(field, expected, atol=1e-18)
    curve = heading_error_curve(params, YAWS)
    heading = np.arctan2(H * np.sin(YAWS) * math.cos(tilt) + Z * math.sin(tilt), H * np.cos(YAWS))
    np.testing.assert_allclose(curve, wrap_to_pi(heading - YAWS), atol=1e-12)


def test_measure_agrees_with_the_deviation_curve():
    params = CompassParams(declination=0.3, hard_iron=(3e-6, -2e-6, 5e-6),
                           soft_iron=((1.05, 0.02, 0.01), (0.03, 0.97, -0.02), (0.0, 0.01, 1.0)),
                           tilt_error=0.04, tilt_axis=0.7, inclination=INCLINATION,
                           field_strength=F)
    compass = CompassModel(params, seed=0)
    measured = np.array([compass.measure(float(yaw))[1] for yaw in YAWS])
    np.testing.assert_allclose(wrap_to_pi(measured - YAWS), heading_error_curve(params, YAWS),
                               atol=1e-12)


def test_declination_cancels_in_the_deviation_curve_of_an_ideal_sensor():
    params = CompassParams(declination=math.radians(-12.0), inclination=INCLINATION,
                           field_strength=F)
    np.testing.assert_allclose(heading_error_curve(params, YAWS), 0.0, atol=1e-12)


def test_noise_statistics():
    sigma = 2e-7  # [T]: heading σ ≈ σ/H ≈ 0.0075 rad
    params = CompassParams(noise_stddev=sigma, **SITE)
    compass = CompassModel(params, seed=17)
    yaw, n = 0.8, 20_000
    readings = [compass.measure(yaw) for _ in range(n)]
    fields = np.array([r[0] for r in readings])
    headings = np.array([r[1] for r in readings])
    ideal, _ = CompassModel(CompassParams(**SITE), seed=0).measure(yaw)
    dof = n - 1
    low, high = chi2.ppf(1e-6, dof) / dof, chi2.ppf(1.0 - 1e-6, dof) / dof
    for axis in range(3):
        assert abs(fields[:, axis].mean() - ideal[axis]) < 5.0 * sigma / math.sqrt(n)
        assert low < fields[:, axis].var(ddof=1) / sigma ** 2 < high
    heading_sigma = heading_noise_stddev(params)
    assert heading_sigma == pytest.approx(sigma / H)
    assert abs(headings.mean() - yaw) < 5.0 * heading_sigma / math.sqrt(n)
    # First-order heading variance; its relative error, O(σ²/H²) ≈ 1e-4, is far inside the bound.
    assert low < headings.var(ddof=1) / heading_sigma ** 2 < high


def test_same_seed_same_readings():
    params = CompassParams(noise_stddev=1e-7)
    a = [CompassModel(params, seed=3).measure(0.1)[1] for _ in range(2)]
    generator = np.random.default_rng(3)
    b = CompassModel(params, seed=generator).measure(0.1)[1]
    assert a[0] == a[1] == b
    c = CompassModel(params, seed=4).measure(0.1)[1]
    assert c != a[0]


@pytest.mark.parametrize('kwargs, match', [
    ({'field_strength': 0.0}, 'field_strength'),
    ({'field_strength': math.nan}, 'field_strength'),
    ({'inclination': 1.6}, 'inclination'),
    ({'declination': 4.0}, 'declination'),
    ({'tilt_error': math.pi / 2.0}, 'tilt_error'),
    ({'tilt_axis': math.inf}, 'tilt_axis'),
    ({'noise_stddev': -1e-7}, 'noise_stddev'),
    ({'hard_iron': (0.0, 0.0)}, 'hard_iron'),
    ({'hard_iron': (0.0, math.nan, 0.0)}, 'hard_iron'),
    ({'hard_iron': 'iron'}, 'hard_iron'),
    ({'soft_iron': np.eye(2)}, 'soft_iron'),
    ({'soft_iron': np.zeros((3, 3))}, 'invertible'),
    ({'soft_iron': np.full((3, 3), math.inf)}, 'soft_iron'),
])
def test_bad_params_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        CompassParams(**kwargs)


def test_bad_input_is_refused():
    compass = CompassModel(CompassParams(), seed=0)
    with pytest.raises(ValueError, match='true_yaw'):
        compass.measure(math.nan)
    with pytest.raises(ValueError, match='yaws'):
        heading_error_curve(CompassParams(), [0.0, math.inf])
    with pytest.raises(ValueError, match='yaws'):
        heading_error_curve(CompassParams(), np.zeros((2, 2)))
    with pytest.raises(ValueError, match='CompassParams'):
        CompassModel(None, seed=0)
