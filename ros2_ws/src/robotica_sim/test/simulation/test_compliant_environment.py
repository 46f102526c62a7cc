"""
Tests of robotica_sim.simulation.compliant_environment: the compliant plane of book (8.164).

References: ψ = K_e (x - x_e) along the normal in contact and zero out of it (8.164), Ej. 8.10's
surface (K_e = 1200 N/m, x_e1 = 2 m along the normal (1, -1, 0)/√2), and the Coulomb law
written out in the tests.
"""
import math

import numpy as np
import pytest
from robotica_sim.simulation.compliant_environment import CompliantPlane

S = 1.0 / math.sqrt(2.0)
NORMAL = np.array([S, -S, 0.0])          # Ej. 8.10's x1 axis, into the surface
TANGENT = np.array([S, S, 0.0])          # x2, along the surface


def _ej_8_10(**kwargs):
    return CompliantPlane(2.0 * NORMAL, [1.0, -1.0, 0.0], 1200.0, **kwargs)


@pytest.mark.parametrize('x1', [1.0, 1.999, 2.0])
def test_no_force_out_of_contact(x1):
    plane = _ej_8_10(damping=50.0, friction=0.5)
    point = x1 * NORMAL + 3.0 * TANGENT
    assert plane.penetration(point) == pytest.approx(x1 - 2.0, abs=1e-12)
    np.testing.assert_array_equal(plane.force(point, 0.7 * TANGENT - 2.0 * NORMAL), 0.0)


@pytest.mark.parametrize('depth', [1e-4, 2.5e-3, 0.1])
def test_force_in_contact_is_stiffness_times_penetration_along_the_normal(depth):
    plane = _ej_8_10()
    point = (2.0 + depth) * NORMAL - 1.5 * TANGENT + [0.0, 0.0, 0.3]
    psi = plane.force(point, 0.4 * TANGENT)           # frictionless: the slide adds nothing
    np.testing.assert_allclose(psi, 1200.0 * depth * NORMAL, rtol=1e-9, atol=1e-12)


def test_normal_damping_adds_but_never_pulls():
    plane = _ej_8_10(damping=100.0)
    point = 2.01 * NORMAL
    np.testing.assert_allclose(plane.force(point, 0.05 * NORMAL), (12.0 + 5.0) * NORMAL,
                               rtol=1e-12)
    np.testing.assert_allclose(plane.force(point, -0.1 * NORMAL), 2.0 * NORMAL, rtol=1e-9)
    # Leaving fast: K_e δ + B_e δ' = 12 - 20 < 0, no adhesion.
    np.testing.assert_array_equal(plane.force(point, -0.2 * NORMAL), 0.0)


def test_coulomb_friction_drags_the_surface_along_the_sliding_velocity():
    plane = _ej_8_10(friction=0.3)
    point = 2.01 * NORMAL
    psi = plane.force(point, 0.5 * TANGENT + 0.01 * NORMAL)
    np.testing.assert_allclose(psi, 12.0 * NORMAL + 0.3 * 12.0 * TANGENT, rtol=1e-12)
    # Below v_mu = 1e-3 m/s the friction is proportional to the speed (regularised).
    slow = plane.force(point, 2e-4 * TANGENT)
    np.testing.assert_allclose(slow, 12.0 * NORMAL + 0.3 * 12.0 * 0.2 * TANGENT, rtol=1e-9)


def test_normal_is_normalised_and_natural_frequency():
    plane = CompliantPlane([0.0, 0.0, 0.0], [0.0, 0.0, -3.0], 1200.0)
    np.testing.assert_array_equal(plane.normal, [0.0, 0.0, -1.0])
    assert plane.natural_frequency(2.35) == pytest.approx(math.sqrt(1200.0 / 2.35))


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: CompliantPlane([0, 0], [0, 0, 1], 1.0), 'point'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 0], 1.0), 'normal'),
    (lambda: CompliantPlane([0, 0, 0], [0, math.nan, 1], 1.0), 'normal'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 1], 0.0), 'stiffness'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 1], math.inf), 'stiffness'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 1], 1.0, damping=-1.0), 'damping'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 1], 1.0, friction=-0.1), 'friction'),
    (lambda: CompliantPlane([0, 0, 0], [0, 0, 1], 1.0, friction_velocity=0.0),
     'friction_velocity'),
    (lambda: _ej_8_10().force([0.0, math.nan, 0.0], np.zeros(3)), 'position'),
    (lambda: _ej_8_10().force(3.0 * NORMAL, [0.0, 0.0]), 'velocity'),
    (lambda: _ej_8_10().natural_frequency(0.0), 'mass'),
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
