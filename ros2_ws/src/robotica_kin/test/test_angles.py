"""Tests of robotica_kin.angles: wrapping and the book's heading convention (catalog §2.7)."""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.angles import heading_from_book, heading_to_book, wrap_to_pi

ANGLES = st.floats(min_value=-1.0e3, max_value=1.0e3, allow_nan=False)


@pytest.mark.parametrize(('angle', 'expected'), [
    (0.0, 0.0),
    (1.0, 1.0),
    (math.pi, math.pi),
    (-math.pi, math.pi),
    (3.0 * math.pi, math.pi),
    (2.0 * math.pi, 0.0),
    (-1.5 * math.pi, 0.5 * math.pi),
    (1.5 * math.pi, -0.5 * math.pi),
    (7.0, 7.0 - 2.0 * math.pi),
    (-100.0, -100.0 + 32.0 * math.pi),
])
def test_wrap_to_pi_known_values(angle, expected):
    result = wrap_to_pi(angle)
    assert isinstance(result, float)
    assert result == pytest.approx(expected, abs=1e-12)
    assert -math.pi < result <= math.pi


@pytest.mark.parametrize(('angle', 'cosine'), [
    (np.nextafter(math.pi, 4.0), -1.0),
    (np.nextafter(-math.pi, -4.0), -1.0),
    (np.nextafter(2.0 * math.pi, 0.0), 1.0),
    (np.nextafter(-3.0 * math.pi, -10.0), -1.0),
])
def test_wrap_to_pi_stays_in_half_open_interval_next_to_the_cut(angle, cosine):
    result = wrap_to_pi(float(angle))
    assert -math.pi < result <= math.pi
    assert math.cos(result) == pytest.approx(cosine)


def test_wrap_to_pi_keeps_array_shape():
    angles = np.array([[0.0, 4.0], [-4.0, 10.0 * math.pi]])
    result = wrap_to_pi(angles)
    assert isinstance(result, np.ndarray)
    assert result.dtype == np.float64
    assert result.shape == (2, 2)
    expected = np.array([[0.0, 4.0 - 2.0 * math.pi], [2.0 * math.pi - 4.0, 0.0]])
    np.testing.assert_allclose(result, expected, atol=1e-12)


def test_wrap_to_pi_accepts_a_list():
    np.testing.assert_allclose(wrap_to_pi([-math.pi, 3.5]), [math.pi, 3.5 - 2.0 * math.pi])


@given(ANGLES)
def test_wrap_to_pi_is_in_range_and_equal_modulo_two_pi(angle):
    result = wrap_to_pi(angle)
    assert -math.pi < result <= math.pi
    turns = (angle - result) / (2.0 * math.pi)
    assert turns == pytest.approx(round(turns), abs=1e-9)


@pytest.mark.parametrize(('phi', 'theta'), [
    (0.0, 0.5 * math.pi),             # book: facing +y
    (-0.25 * math.pi, 0.25 * math.pi),  # Ejemplo 4.9's φ0
    (-0.5 * math.pi, 0.0),            # facing +x
    (0.5 * math.pi, math.pi),         # facing -x
    (math.pi, -0.5 * math.pi),        # facing -y
])
def test_heading_from_and_to_book_known_values(phi, theta):
    assert heading_from_book(phi) == pytest.approx(theta, abs=1e-12)
    assert heading_to_book(theta) == pytest.approx(wrap_to_pi(phi), abs=1e-12)


@given(ANGLES)
def test_book_and_rep103_give_the_same_direction_of_motion(phi):
    """Book (4.97)-(4.98): (x', y') / v = (-sin φ, cos φ) must equal (cos θ, sin θ)."""
    theta = heading_from_book(phi)
    assert math.cos(theta) == pytest.approx(-math.sin(phi), abs=1e-9)
    assert math.sin(theta) == pytest.approx(math.cos(phi), abs=1e-9)
    assert -math.pi < theta <= math.pi


@given(ANGLES)
def test_heading_to_book_inverts_heading_from_book(phi):
    back = heading_to_book(heading_from_book(phi))
    assert wrap_to_pi(back - phi) == pytest.approx(0.0, abs=1e-9)


def test_heading_conversions_accept_arrays():
    phi = np.array([0.0, -0.25 * math.pi])
    theta = heading_from_book(phi)
    np.testing.assert_allclose(theta, [0.5 * math.pi, 0.25 * math.pi])
    np.testing.assert_allclose(heading_to_book(theta), phi, atol=1e-15)
