"""Tests of HEMERO's mobile-robot blocks in robotica_kin.hemero ([H] (3.28)-(3.35), §12.3)."""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin import hemero
from robotica_kin.angles import heading_from_book, wrap_to_pi
from robotica_kin.hemero import (
    modelo_directo_bicicleta,
    modelo_directo_diferencial,
    modelo_directo_sincrona,
    modelo_directo_triciclo,
    modelo_inverso_bicicleta,
    modelo_inverso_diferencial,
    modelo_inverso_sincrona,
    modelo_inverso_triciclo,
)
from scipy.integrate import solve_ivp

BLOCKS = ['modelo_directo_bicicleta', 'modelo_directo_diferencial', 'modelo_directo_sincrona',
          'modelo_directo_triciclo', 'modelo_inverso_bicicleta', 'modelo_inverso_diferencial',
          'modelo_inverso_sincrona', 'modelo_inverso_triciclo']
ANGLE = st.floats(-math.pi, math.pi)
SPEED = st.floats(-10.0, 10.0)
DIMENSION = st.floats(0.05, 3.0)


def unit_circle(t):
    """Ejemplo 4.8's path x = cos t, y = sin t: velocity, acceleration, jerk."""
    c, s = math.cos(t), math.sin(t)
    return [-s, c], [-c, -s], [s, -c]


def lissajous(t):
    """Path x = 3 sin(0.5 t) + t, y = cos t: position and three derivatives (never standing)."""
    return ([3.0 * math.sin(0.5 * t) + t, math.cos(t)],
            [1.5 * math.cos(0.5 * t) + 1.0, -math.sin(t)],
            [-0.75 * math.sin(0.5 * t), -math.cos(t)],
            [-0.375 * math.cos(0.5 * t), math.sin(t)])


def test_blocks_are_exported_and_old_names_kept():
    for name in BLOCKS:
        assert name in hemero.__all__
        assert callable(getattr(hemero, name))
    for name in ('fkine', 'ikine', 'jacob0', 'rotx', 'velprop', 'rne', 'puma560'):
        assert name in hemero.__all__
    assert len(set(hemero.__all__)) == len(hemero.__all__)


@given(ANGLE, st.floats(-1.5, 1.5), SPEED, st.floats(-2.0, 2.0), DIMENSION, DIMENSION)
def test_directo_triciclo_and_bicicleta_are_3_28_3_29(phi, alpha, w_t, w_alpha, c, length):
    """[H] (3.28) = (3.29), written out in the book convention (φ from y)."""
    expected = np.array([[-c * math.sin(phi) * math.cos(alpha), 0.0],
                         [c * math.cos(phi) * math.cos(alpha), 0.0],
                         [c * math.sin(alpha) / length, 0.0],
                         [0.0, 1.0]]) @ np.array([w_t, w_alpha])
    state = [0.5, -0.5, phi, alpha]
    for block in (modelo_directo_triciclo, modelo_directo_bicicleta):
        book = block(0.0, state, [w_t, w_alpha], c, length, 'book')
        np.testing.assert_allclose(book, expected, atol=1e-9)
        rep = block(0.0, [0.5, -0.5, heading_from_book(phi), alpha], [w_t, w_alpha], c,
                    length)
        np.testing.assert_allclose(rep, expected, atol=1e-9)


@given(ANGLE, SPEED, SPEED, DIMENSION, DIMENSION)
def test_directo_diferencial_is_3_30(phi, w_i, w_d, c, b):
    expected = np.array([[-c * math.sin(phi) / 2, -c * math.sin(phi) / 2],
                         [c * math.cos(phi) / 2, c * math.cos(phi) / 2],
                         [-c / b, c / b]]) @ np.array([w_i, w_d])
    book = modelo_directo_diferencial(0.0, [1.0, 2.0, phi], [w_i, w_d], c, b, 'book')
    np.testing.assert_allclose(book, expected, atol=1e-9)
    rep = modelo_directo_diferencial(0.0, [1.0, 2.0, heading_from_book(phi)], [w_i, w_d], c, b)
    np.testing.assert_allclose(rep, expected, atol=1e-9)


@given(ANGLE, SPEED, SPEED)
def test_directo_sincrona_is_3_31(phi, v, omega):
    expected = [-math.sin(phi) * v, math.cos(phi) * v, omega]
    np.testing.assert_allclose(
        modelo_directo_sincrona(0.0, [0.0, 0.0, phi], [v, omega], 'book'), expected, atol=1e-12)
    np.testing.assert_allclose(
        modelo_directo_sincrona(0.0, [0.0, 0.0, heading_from_book(phi)], [v, omega]), expected,
        atol=1e-12)


@pytest.mark.parametrize('block', [modelo_inverso_triciclo, modelo_inverso_bicicleta])
@pytest.mark.parametrize('t', np.linspace(0.0, 0.5 * math.pi, 4))
def test_ejemplo_4_8(block, t):
    """Ejemplo 4.8: l = 1.5 m, unit circle -> α = 56.31°, ω_α = 0, v_t = 1.8028 m/s, φ = t."""
    v_t, w_alpha, alpha, phi = block(*unit_circle(t), 1.5, 'book')
    assert math.degrees(alpha) == pytest.approx(56.31, abs=5e-3)
    assert w_alpha == pytest.approx(0.0, abs=1e-12)
    assert v_t == pytest.approx(1.8028, abs=5e-5)
    assert wrap_to_pi(phi - t) == pytest.approx(0.0, abs=1e-12)
    v_t_rep, _, alpha_rep, theta = block(*unit_circle(t), 1.5)
    assert (v_t_rep, alpha_rep) == pytest.approx((v_t, alpha))
    assert wrap_to_pi(theta - heading_from_book(phi)) == pytest.approx(0.0, abs=1e-12)


def test_inverso_diferencial_is_3_34_on_ejemplo_4_9_geometry():
    """
    Ejemplo 4.9's c = 0.25 m, b = 1 m on a circle of radius 5.5 m at 1.1 m/s (ω = 0.2 rad/s).

    (3.34): ω_i = (v - (b/2) ω)/c = 4.0, ω_d = (v + (b/2) ω)/c = 4.8 rad/s.
    """
    t = 0.7
    radius, rate = 5.5, 0.2
    velocity = [-radius * rate * math.sin(rate * t), radius * rate * math.cos(rate * t)]
    acceleration = [-radius * rate**2 * math.cos(rate * t), -radius * rate**2 * math.sin(rate * t)]
    w_i, w_d, phi = modelo_inverso_diferencial(velocity, acceleration, 0.25, 1.0, 'book')
    assert (w_i, w_d) == pytest.approx((4.0, 4.8))
    assert phi == pytest.approx(rate * t)
    # the matrix of (3.34), written out
    phi_dot = rate
    row = -math.sin(phi) * velocity[0] + math.cos(phi) * velocity[1]
    assert w_i == pytest.approx((row - 0.5 * phi_dot) / 0.25)
    assert w_d == pytest.approx((row + 0.5 * phi_dot) / 0.25)


def test_inverso_sincrona_is_3_35():
    _, velocity, acceleration, _ = lissajous(1.3)
    v, omega, phi = modelo_inverso_sincrona(velocity, acceleration, 'book')
    assert phi == pytest.approx(math.atan2(-velocity[0], velocity[1]))
    assert v == pytest.approx(-math.sin(phi) * velocity[0] + math.cos(phi) * velocity[1])
    assert v == pytest.approx(math.hypot(*velocity))
    assert omega == pytest.approx((velocity[0] * acceleration[1] - acceleration[0] * velocity[1])
                                  / (velocity[0]**2 + velocity[1]**2))


@pytest.mark.parametrize('convention', ['rep103', 'book'])
def test_inverse_then_direct_blocks_retrace_the_path(convention):
    """
    Inverse block -> controls -> direct block retraces the path (HEMERO's usual pairing).

    For the synchronous, differential and tricycle blocks; integrated with solve_ivp.
    """
    c, b, length = 0.2, 0.6, 1.2

    def synchronous(t, state):
        v, omega, _ = modelo_inverso_sincrona(*lissajous(t)[1:3], convention)
        return modelo_directo_sincrona(t, state, [v, omega], convention)

    def differential(t, state):
        w_i, w_d, _ = modelo_inverso_diferencial(*lissajous(t)[1:3], c, b, convention)
        return modelo_directo_diferencial(t, state, [w_i, w_d], c, b, convention)

    def tricycle(t, state):
        v_t, w_alpha, _, _ = modelo_inverso_triciclo(*lissajous(t)[1:], length, convention)
        return modelo_directo_triciclo(t, state, [v_t / c, w_alpha], c, length, convention)

    _, _, alpha0, heading0 = modelo_inverso_triciclo(*lissajous(0.0)[1:], length, convention)
    start = lissajous(0.0)[0]
    for f, state0 in ((synchronous, [*start, heading0]), (differential, [*start, heading0]),
                      (tricycle, [*start, heading0, alpha0])):
        sol = solve_ivp(f, (0.0, 6.0), state0, rtol=1e-10, atol=1e-12)
        end = sol.y[:, -1]
        assert end[:2] == pytest.approx(lissajous(6.0)[0], abs=1e-6)
        heading_end = modelo_inverso_sincrona(*lissajous(6.0)[1:3], convention)[2]
        assert wrap_to_pi(end[2] - heading_end) == pytest.approx(0.0, abs=1e-6)


def test_blocks_reject_bad_input():
    with pytest.raises(ValueError, match='wheel_radius'):
        modelo_directo_triciclo(0.0, [0.0, 0.0, 0.0, 0.0], [1.0, 0.0], 0.0, 1.0)
    with pytest.raises(ValueError, match='wheel_separation'):
        modelo_directo_diferencial(0.0, [0.0, 0.0, 0.0], [1.0, 1.0], 0.1, -1.0)
    with pytest.raises(ValueError, match='u'):
        modelo_directo_diferencial(0.0, [0.0, 0.0, 0.0], [1.0], 0.1, 1.0)
    with pytest.raises(ValueError, match='convention'):
        modelo_directo_sincrona(0.0, [0.0, 0.0, 0.0], [1.0, 0.0], 'ned')
    with pytest.raises(ValueError, match='velocity'):
        modelo_inverso_sincrona([0.0, 0.0], [1.0, 0.0])
    with pytest.raises(ValueError, match='wheelbase'):
        modelo_inverso_triciclo([1.0, 0.0], [0.0, 0.0], [0.0, 0.0], 0.0)
