"""
Tests of robotica_ctrl.joint_control.regressor (seed catalogue Part 6, §6.4, Ej. 8.7-8.8).

References, none computed by the code under test: the closed form (5.76)-(5.77) of Ej. 5.1
(``tests/reference_models.py``), ``robotica_kin.dynamics`` (rne, inertia, gravity) on the
PUMA 560, and the Christoffel matrix built here from finite differences of M(q).
"""

import math

import numpy as np
import pytest
from reference_models import closed_form_2r
from robotica_ctrl.joint_control.regressor import (LinkMassRegressor,
                                                   two_link_computed_torque_regressor,
                                                   two_link_slotine_li_regressor,
                                                   TwoLinkRegressor)
from robotica_kin.dynamics import gravity, inertia, rne
from robotica_kin.robots import puma560, two_link_arm

L1, L2, G = 1.0, 1.5, 9.8
MASSES = np.array([0.8, 2.3])
PLANAR_GRAVITY = [0.0, -G, 0.0]    # the book's planar convention, gravity along -y


def random_states(count: int, n: int, seed: int) -> np.ndarray:
    """Return ``count`` random (q, q', q'', v) of n joints each, shape (count, 4, n)."""
    return np.random.default_rng(seed).uniform(-2.0, 2.0, size=(count, 4, n))


def christoffel(robot, q: np.ndarray, qd: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Return C(q, q') (n, n) of the Christoffel symbols of M, by central differences of M."""
    n = q.size
    dm = np.empty((n, n, n))      # dm[i, j, k] = ∂M_ij/∂q_k
    for k in range(n):
        step = np.zeros(n)
        step[k] = h
        dm[:, :, k] = (inertia(robot, q + step) - inertia(robot, q - step)) / (2.0 * h)
    # c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j - ∂M_jk/∂q_i), C_ij = Σ_k c_ijk q'_k
    symbols = 0.5 * (dm + np.einsum('ikj->ijk', dm) - np.einsum('jki->ijk', dm))
    return np.einsum('ijk,k->ij', symbols, qd)


def test_christoffel_helper_on_the_2r():
    """The test's own C(q, q') gives V of (5.77), V = C q', and V_m of (8.133) (+ in (2, 1))."""
    _, dyn = two_link_arm(*MASSES, L1, L2)
    q, qd = np.array([0.3, 0.9]), np.array([-0.7, 1.1])
    m2, s2 = MASSES[1], math.sin(q[1])
    book = np.array([[-m2 * L1 * L2 * s2 * qd[1], -m2 * L1 * L2 * s2 * (qd[0] + qd[1])],
                     [m2 * L1 * L2 * s2 * qd[0], 0.0]])
    np.testing.assert_allclose(christoffel(dyn, q, qd), book, atol=1e-7)
    _, v, _, _ = closed_form_2r(*MASSES, L1, L2, q, qd, [0.0, 0.0], G)
    np.testing.assert_allclose(book @ qd, v, atol=1e-12)


@pytest.mark.parametrize('state', random_states(5, 2, seed=1))
def test_generic_regressor_equals_the_closed_forms_on_the_2r(state):
    """The generic regressor on two_link_arm: W of (8.100) and Y of (8.134), φ = [m1, m2]."""
    q, qd, qdd, v = state
    generic = LinkMassRegressor(two_link_arm(*MASSES, L1, L2)[1], PLANAR_GRAVITY)
    assert generic.parameter_names == ('link_1.mass', 'link_2.mass')
    np.testing.assert_array_equal(generic.masses, MASSES)
    w, known = generic.computed_torque_terms(q, qd, qdd)
    np.testing.assert_allclose(w, two_link_computed_torque_regressor(q, qd, qdd, L1, L2, G),
                               atol=1e-12)
    np.testing.assert_array_equal(known, [0.0, 0.0])   # no motor inertia, no friction
    np.testing.assert_allclose(generic.slotine_li(q, qd, v, qdd),
                               two_link_slotine_li_regressor(q, qd, v, qdd, L1, L2, G),
                               atol=1e-12)
    np.testing.assert_allclose(generic.inertia(q, [0.3, -1.0]),
                               TwoLinkRegressor(L1, L2, G).inertia(q, [0.3, -1.0]), atol=1e-12)


@pytest.mark.parametrize('state', random_states(5, 2, seed=2))
def test_closed_forms_against_the_2r_dynamics(state):
    """W φ = M q'' + V + G of (5.76); Y φ = M a + V_m v + G with V_m of (8.133); M(φ) of (5.77)."""
    q, qd, qdd, v = state
    mass, coriolis, grav, tau = closed_form_2r(*MASSES, L1, L2, q, qd, qdd, G)
    np.testing.assert_allclose(two_link_computed_torque_regressor(q, qd, qdd, L1, L2, G) @ MASSES,
                               tau, atol=1e-12)
    m2, s2 = MASSES[1], math.sin(q[1])
    v_m = np.array([[-m2 * L1 * L2 * s2 * qd[1], -m2 * L1 * L2 * s2 * (qd[0] + qd[1])],
                    [m2 * L1 * L2 * s2 * qd[0], 0.0]])
    np.testing.assert_allclose(two_link_slotine_li_regressor(q, qd, v, qdd, L1, L2, G) @ MASSES,
                               mass @ qdd + v_m @ v + grav, atol=1e-12)
    np.testing.assert_allclose(TwoLinkRegressor(L1, L2, G).inertia(q, MASSES), mass, atol=1e-12)
    np.testing.assert_allclose(v_m @ qd, coriolis, atol=1e-12)


@pytest.mark.parametrize('state', random_states(4, 6, seed=3))
def test_puma_regressors_reproduce_rne(state):
    """PUMA 560, masses of its table: W φ + known = rne = Y φ + known (v = q', a = q'')."""
    robot = puma560()
    regressor = LinkMassRegressor(robot)
    q, qd, qdd, _ = state
    expected = rne(robot, q, qd, qdd)    # gravity [0, 0, -9.81], motor inertia J_m G²
    w, known = regressor.computed_torque_terms(q, qd, qdd)
    np.testing.assert_allclose(w @ regressor.masses + known, expected, rtol=1e-12, atol=1e-10)
    y, known = regressor.slotine_li_terms(q, qd, qd, qdd)
    np.testing.assert_allclose(y @ regressor.masses + known, expected, rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(regressor.inertia(q, regressor.masses), inertia(robot, q),
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize('state', random_states(3, 6, seed=4))
def test_puma_slotine_li_regressor_uses_the_christoffel_matrix(state):
    """Y φ + known = M a + C(q, q') v + G, C from finite differences of M (independent)."""
    robot = puma560()
    regressor = LinkMassRegressor(robot)
    q, qd, a, v = state
    y, known = regressor.slotine_li_terms(q, qd, v, a)
    expected = inertia(robot, q) @ a + christoffel(robot, q, qd) @ v + gravity(robot, q)
    np.testing.assert_allclose(y @ regressor.masses + known, expected, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize('state', random_states(3, 6, seed=5))
def test_puma_skew_symmetry(state):
    """M' - 2 C is skew-symmetric, C read off the regressor: C e_j = (Y(v = e_j) - Y(v = 0)) φ."""
    robot = puma560()
    regressor = LinkMassRegressor(robot)
    q, qd, _, _ = state
    zero = np.zeros(6)

    def torque(v):
        y, known = regressor.slotine_li_terms(q, qd, v, zero)
        return y @ regressor.masses + known

    c = np.column_stack([torque(unit) - torque(zero) for unit in np.eye(6)])
    h = 1e-6
    m_dot = (inertia(robot, q + h * qd) - inertia(robot, q - h * qd)) / (2.0 * h)
    n = m_dot - 2.0 * c
    np.testing.assert_allclose(n + n.T, np.zeros((6, 6)), atol=1e-6)
    assert np.abs(n).max() > 1e-2     # not trivially zero
    np.testing.assert_allclose(c, christoffel(robot, q, qd), atol=1e-6)


def test_zero_mass_link_is_left_out_and_known():
    """PUMA link 1 has 0 kg (I_zz = 0.35 kg m²): not in φ; its inertia is in the known torque."""
    robot = puma560()
    regressor = LinkMassRegressor(robot)
    assert regressor.links == (2, 3, 4, 5, 6)
    assert regressor.parameter_names == tuple(f'link_{i}.mass' for i in range(2, 7))
    np.testing.assert_array_equal(regressor.masses, robot.dyn[1:, 5])
    q, zero = np.zeros(6), np.zeros(6)
    qdd = np.array([1.0, 0, 0, 0, 0, 0])
    w, known = regressor.computed_torque_terms(q, zero, qdd)
    inertia_1 = robot.dyn[0, 14] + robot.dyn[0, 15] * robot.dyn[0, 16] ** 2   # I_zz + J_m G²
    assert known[0] == pytest.approx(inertia_1, rel=1e-12)
    np.testing.assert_allclose(w @ regressor.masses + known, rne(robot, q, zero, qdd), atol=1e-12)


def test_masses_change_the_dynamics_linearly():
    """Doubling m2 of the 2R doubles its share: the generic W is the same for any table masses."""
    q, qd, qdd = np.array([0.2, -0.4]), np.array([0.5, 0.1]), np.array([1.0, -2.0])
    light = LinkMassRegressor(two_link_arm(0.8, 2.3, L1, L2)[1], PLANAR_GRAVITY)
    heavy = LinkMassRegressor(two_link_arm(5.0, 0.1, L1, L2)[1], PLANAR_GRAVITY)
    np.testing.assert_allclose(light.computed_torque(q, qd, qdd),
                               heavy.computed_torque(q, qd, qdd), atol=1e-12)


@pytest.mark.parametrize('bad', [
    lambda: two_link_computed_torque_regressor([0, 0, 0], [0, 0, 0], [0, 0, 0], L1, L2, G),
    lambda: two_link_computed_torque_regressor([0, np.nan], [0, 0], [0, 0], L1, L2, G),
    lambda: two_link_computed_torque_regressor([0, 0], [0, 0], [0, 0], 0.0, L2, G),
    lambda: two_link_slotine_li_regressor([0, 0], [0, 0], [0, 0], [0, 0], L1, -1.0, G),
    lambda: two_link_slotine_li_regressor([0, 0], [0, 0], [0, 0], [0], L1, L2, G),
    lambda: two_link_slotine_li_regressor([0, 0], [0, 0], [0, 0], [0, 0], L1, L2, math.inf),
    lambda: TwoLinkRegressor(L1, L2, G).inertia([0, 0], [1.0]),
    lambda: LinkMassRegressor(np.zeros((2, 5))),
    lambda: LinkMassRegressor(two_link_arm(0.0, 0.0, L1, L2)[1]),
    lambda: LinkMassRegressor(puma560(), grav=[0.0, np.nan, 0.0]),
    lambda: LinkMassRegressor(puma560()).computed_torque(np.zeros(5), np.zeros(5), np.zeros(5)),
    lambda: LinkMassRegressor(puma560()).slotine_li(np.zeros(6), np.zeros(6), np.zeros(6),
                                                    [0, 0, 0, 0, 0, np.inf]),
    lambda: LinkMassRegressor(puma560()).inertia(np.zeros(6), np.ones(6)),
])
def test_bad_input_raises(bad):
    with pytest.raises(ValueError):
        bad()
