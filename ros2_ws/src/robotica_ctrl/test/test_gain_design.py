"""
Tests of robotica_ctrl.joint_control.gain_design: Ej. 8.6 and the error it designs against.

Reference values: the book's (8.74), K_p > 0.98 / arccos(1 - 0.005) = 9.796 (seed catalogue
Part 6, Ej. 8.6), and an independent integration of the error equation (8.60) at rest with
scipy: its steady state is the closed form (8.61).
"""
import math

import pytest
from robotica_ctrl.joint_control.gain_design import (chord_error, max_steady_state_error,
                                                     proportional_gain_for_chord,
                                                     steady_state_error)
from scipy.integrate import solve_ivp


def test_ejemplo_8_6():
    # m̂ = 1 kg, m = 1.1 kg, l = 1 m, g = 9.8 m/s², largest chord 0.1 m.
    kp = proportional_gain_for_chord(1.1 - 1.0, 1.0, 1.0, 0.1)
    assert kp == pytest.approx(9.796, abs=5e-4)
    # With that gain, the largest error's chord is the design's 0.1 m.
    assert chord_error(1.0, max_steady_state_error(0.1, 1.0, 1.0, kp)) == pytest.approx(0.1)
    assert chord_error(1.0, max_steady_state_error(0.1, 1.0, 1.0, 2 * kp)) < 0.1


@pytest.mark.parametrize('theta', [0.0, 0.7, math.pi])
def test_steady_state_of_the_error_equation(theta):
    mu, m_hat, length, kp, kv, g = 0.2, 1.5, 0.8, 16.0, 8.0, 9.8
    forcing = mu / (m_hat * length) * g * math.cos(theta)   # (8.60) at rest: θ'' = 0
    solution = solve_ivp(lambda t, y: [y[1], forcing - kv * y[1] - kp * y[0]], (0.0, 30.0),
                         [0.0, 0.0], rtol=1e-10, atol=1e-12)
    assert steady_state_error(mu, m_hat, length, kp, theta, g) == pytest.approx(
        solution.y[0, -1], abs=1e-9)


def test_bad_values_are_refused():
    with pytest.raises(ValueError, match='kp must be > 0'):
        steady_state_error(0.1, 1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match='max_chord must be at most 2 l'):
        proportional_gain_for_chord(0.1, 1.0, 1.0, 2.5)
    with pytest.raises(ValueError, match='model_mass must be > 0'):
        proportional_gain_for_chord(0.1, -1.0, 1.0, 0.1)
    with pytest.raises(ValueError):
        chord_error(1.0, math.nan)
