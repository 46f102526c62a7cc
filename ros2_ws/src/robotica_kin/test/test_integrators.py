"""Tests of robotica_kin.integrators.rk4_step against closed-form solutions."""

import math

import numpy as np
import pytest

from robotica_kin.integrators import rk4_step


def decay(t, x):
    return -x


def integrate(f, x0, t_end, h, *args):
    x = np.asarray(x0, dtype=np.float64)
    steps = round(t_end / h)
    for k in range(steps):
        x = rk4_step(f, k * h, x, h, *args)
    return x


def test_exponential_decay_matches_exp():
    x = integrate(decay, [1.0], 1.0, 0.1)
    assert x[0] == pytest.approx(math.exp(-1.0), abs=1e-6)


def test_fourth_order_convergence():
    """Halving h divides the global error by about 2**4 = 16."""
    errors = [abs(integrate(decay, [1.0], 2.0, h)[0] - math.exp(-2.0)) for h in (0.2, 0.1, 0.05)]
    for coarse, fine in zip(errors, errors[1:]):
        assert 14.0 < coarse / fine < 18.0


def test_exact_for_a_cubic_in_time():
    """For x' = t**3, RK4 is Simpson's rule, exact for cubics: x(t0+h) - x(t0) = Δ(t**4)/4."""
    t0, h = 1.0, 0.5
    x = rk4_step(lambda t, x: [t**3], t0, [2.0], h)
    assert x[0] == pytest.approx(2.0 + ((t0 + h) ** 4 - t0**4) / 4.0, abs=1e-14)


def test_harmonic_oscillator_with_extra_argument():
    """Harmonic oscillator x'' = -k x from (1, 0): x = cos(√k t), x' = -√k sin(√k t)."""
    def oscillator(t, state, stiffness):
        return np.array([state[1], -stiffness * state[0]])

    stiffness, t_end = 4.0, 3.0
    state = integrate(oscillator, [1.0, 0.0], t_end, 0.001, stiffness)
    w = math.sqrt(stiffness)
    np.testing.assert_allclose(state, [math.cos(w * t_end), -w * math.sin(w * t_end)],
                               atol=1e-9)


def test_returns_float64_and_leaves_the_input_alone():
    x0 = np.array([1, 2])
    x1 = rk4_step(lambda t, x: np.array([1, 1]), 0.0, x0, 0.5)
    assert x1.dtype == np.float64
    assert x1.shape == (2,)
    np.testing.assert_array_equal(x1, [1.5, 2.5])
    np.testing.assert_array_equal(x0, [1, 2])


def test_time_reaches_the_slopes():
    times = []

    def record(t, x):
        times.append(t)
        return np.zeros(1)

    rk4_step(record, 2.0, [0.0], 0.5)
    assert times == [2.0, 2.25, 2.25, 2.5]


@pytest.mark.parametrize('h', [0.0, -0.1, math.nan, math.inf])
def test_rejects_bad_step(h):
    with pytest.raises(ValueError, match='step h'):
        rk4_step(decay, 0.0, [1.0], h)


def test_rejects_non_finite_time():
    with pytest.raises(ValueError, match='time t'):
        rk4_step(decay, math.nan, [1.0], 0.1)


@pytest.mark.parametrize('x0', [1.0, [[1.0], [2.0]]])
def test_rejects_non_vector_state(x0):
    with pytest.raises(ValueError, match=r'shape \(n,\)'):
        rk4_step(decay, 0.0, x0, 0.1)


def test_rejects_slope_of_wrong_shape():
    with pytest.raises(ValueError, match='f returned shape'):
        rk4_step(lambda t, x: np.zeros(3), 0.0, [1.0, 2.0], 0.1)
