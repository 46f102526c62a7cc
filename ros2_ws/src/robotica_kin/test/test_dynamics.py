"""
Tests of robotica_kin.dynamics (catalog Part 3: §3.5, §3.8 Ej. 5.1-5.4; §12.4 dyn table).

References: the closed form (5.76)-(5.77) of Ej. 5.1 (``tests/reference_models.py``), the
values the catalog computed from it for Ej. 5.2, energy balances, and Pinocchio-style identities.
"""
import math

import numpy as np
import pinocchio as pin
import pytest

from reference_models import closed_form_2r
from robotica_kin.dh import dh_model
from robotica_kin.dynamics import (coriolis, coriolis_matrix, fdyn, friction, gravity, inertia,
                                   rne)
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import puma560, two_link_arm

G = 9.81


@pytest.mark.parametrize('seed', range(8))
def test_ejemplo_5_1_rne_equals_the_closed_form(seed):
    rng = np.random.default_rng(seed)
    m1, m2, l1, l2 = rng.uniform(0.5, 3.0, 4)
    q, qd, qdd = rng.uniform(-3, 3, (3, 2))
    _, dyn = two_link_arm(m1, m2, l1, l2)
    M, V, Gq, tau = closed_form_2r(m1, m2, l1, l2, q, qd, qdd)
    grav = [0.0, -G, 0.0]
    np.testing.assert_allclose(rne(dyn, q, qd, qdd, grav), tau, atol=1e-10)
    np.testing.assert_allclose(inertia(dyn, q), M, atol=1e-12)
    np.testing.assert_allclose(coriolis(dyn, q, qd), V, atol=1e-12)
    np.testing.assert_allclose(gravity(dyn, q, grav), Gq, atol=1e-12)


def test_ejemplo_5_2_forward_dynamics_matches_catalog_values():
    # m1 = 2, m2 = 1, l1 = 3, l2 = 1, tau = (30 + (1 + e^-t) 10 sin t, 10 + 10 cos t), g = 9.81;
    # catalog §3.8 values computed from (5.76): theta''(0) = [-6.0478, 34.3811];
    # t = 0.5: theta = [-0.3664, 3.1030], theta' = [-0.2057, 11.8385];
    # t = 1: theta = [-1.2169, 12.2009], theta' = [-4.4194, 29.0133].
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    grav = [0.0, -G, 0.0]

    def torque(t, q, qd):
        return [30.0 + (1.0 + math.exp(-t)) * 10.0 * math.sin(t), 10.0 + 10.0 * math.cos(t)]

    M, V, Gq, _ = closed_form_2r(2.0, 1.0, 3.0, 1.0, [0, 0], [0, 0], [0, 0])
    np.testing.assert_allclose(np.linalg.solve(M, np.array(torque(0, 0, 0)) - V - Gq),
                               [-6.0478, 34.3811], atol=5e-4)
    result = fdyn(dyn, 0.0, 1.0, torque, [0, 0], [0, 0], grav, t_eval=[0.5, 1.0])
    np.testing.assert_allclose(result.q[0], [-0.3664, 3.1030], atol=5e-4)
    np.testing.assert_allclose(result.qd[0], [-0.2057, 11.8385], atol=5e-4)
    np.testing.assert_allclose(result.q[1], [-1.2169, 12.2009], atol=5e-4)
    np.testing.assert_allclose(result.qd[1], [-4.4194, 29.0133], atol=5e-4)


def _ejemplo_5_3(viscous=0.0):
    # l1 = l2 = 0.8 m, m = 4.7, 2.6, 1.1 kg, link 3 inertia diag(0.05, 0.1, 0.1) kg m^2.
    dyn = np.array([
        [0, 0, 0, 0, 0, 4.7, 0.8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, viscous, 0, 0],
        [0, 0.8, 0, 0, 0, 2.6, 0.8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, viscous, 0, 0],
        [0, 0.8, 0, 0, 0, 1.1, 0, 0, 0, 0.05, 0.1, 0.1, 0, 0, 0, 0, 1, viscous, 0, 0]])
    return dyn, [0.0, -9.8, 0.0]


def _energy(dyn, grav, q, qd):
    """Kinetic (5.81) plus potential energy of the Ej. 5.3 arm, from its geometry."""
    c1, s1 = math.cos(q[0]), math.sin(q[0])
    s12 = math.sin(q[0] + q[1])
    kinetic = 0.5 * qd @ inertia(dyn, q) @ qd
    heights = [0.8 * s1, 0.8 * s1 + 0.8 * s12, 0.8 * s1 + 0.8 * s12]   # y of each mass
    del c1
    return kinetic + 9.8 * float(np.dot([4.7, 2.6, 1.1], heights))


def test_ejemplo_5_4_a_hanging_arm_stays_at_rest():
    dyn, grav = _ejemplo_5_3()
    q0 = [-math.pi / 2, 0.0, 0.0]
    np.testing.assert_allclose(gravity(dyn, q0, grav), 0.0, atol=1e-12)
    result = fdyn(dyn, 0.0, 2.0, None, q0, [0, 0, 0], grav, max_step=0.01)
    np.testing.assert_allclose(result.q[-1], q0, atol=1e-9)


def test_ejemplo_5_4_b_free_motion_conserves_energy():
    dyn, grav = _ejemplo_5_3()
    q0 = np.array([math.pi / 6, math.pi / 6, math.pi / 18])
    result = fdyn(dyn, 0.0, 3.0, None, q0, [0, 0, 0], grav, max_step=0.01)
    energies = [_energy(dyn, grav, q, qd) for q, qd in zip(result.q, result.qd)]
    assert np.ptp(energies) < 1e-5 * abs(energies[0])
    assert np.abs(result.qd).max() > 1.0      # it does fall and keep moving


def test_ejemplo_5_4_c_viscous_friction_brings_it_to_rest_hanging():
    dyn, grav = _ejemplo_5_3(viscous=5.0)
    q0 = np.array([math.pi / 6, math.pi / 6, math.pi / 18])
    result = fdyn(dyn, 0.0, 40.0, None, q0, [0, 0, 0], grav, max_step=0.05)
    energies = np.array([_energy(dyn, grav, q, qd) for q, qd in zip(result.q, result.qd)])
    assert np.all(np.diff(energies) <= 1e-6)
    final = result.q[-1]
    assert math.cos(final[0] + math.pi / 2) == pytest.approx(1.0, abs=1e-3)
    # theta2 -> 0. The catalog also says theta3 -> 0, but link 3's centre of mass is on joint
    # 3's axis (5.92), so gravity exerts no torque on joint 3: any theta3 is an equilibrium and
    # the test only asks that joint 3 stops.
    assert math.sin(final[1]) == pytest.approx(0.0, abs=1e-3)
    np.testing.assert_allclose(result.qd[-1], 0.0, atol=1e-2)


def test_an_arm_and_the_callers_data_give_the_robots_results():
    """The kept arm with one scratch Data reused by every call, against fresh ones per call."""
    robot = puma560()
    arm = pinocchio_arm(robot)
    data = arm.model.createData()
    rng = np.random.default_rng(3)
    q, qd, qdd = rng.normal(size=(3, 6))
    grav = [0.0, -9.81, 0.0]
    for _ in range(2):     # the second pass starts from the scratch the first one left
        np.testing.assert_array_equal(rne(arm, q, qd, qdd, grav, data=data),
                                      rne(robot, q, qd, qdd, grav))
        np.testing.assert_array_equal(inertia(arm, q, data=data), inertia(robot, q))
        np.testing.assert_array_equal(gravity(arm, q, data=data), gravity(robot, q))
        np.testing.assert_array_equal(coriolis(arm, q, qd, data=data), coriolis(robot, q, qd))
        np.testing.assert_array_equal(coriolis_matrix(arm, q, qd, data=data),
                                      coriolis_matrix(robot, q, qd))
    by_arm = fdyn(arm, 0.0, 0.05, None, q, qd)
    np.testing.assert_array_equal(by_arm.q, fdyn(robot, 0.0, 0.05, None, q, qd).q)
    _, other = two_link_arm(2.0, 1.0, 3.0, 1.0)
    with pytest.raises(ValueError, match='Data of the model'):
        rne(arm, q, qd, qdd, data=pinocchio_arm(dh_model(other[:, :5], dyn=other))
            .model.createData())


@pytest.mark.parametrize('seed', range(5))
def test_puma560_identities(seed):
    robot = puma560()
    rng = np.random.default_rng(seed)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1])
    qd, qdd = rng.normal(size=(2, 6))
    M = inertia(robot, q)
    np.testing.assert_allclose(M, M.T, atol=1e-14)
    assert np.linalg.eigvalsh(M).min() > 0.0
    # M includes the reflected motor inertia J_m G^2 (fig. A.7): more than the links alone.
    assert M[0, 0] > 291e-6 * 62.6111**2
    tau = rne(robot, q, qd, qdd)
    # ABA (an independent Pinocchio algorithm) inverts RNE: aba(rnea(a)) = a.
    model = pinocchio_arm(robot).model
    np.testing.assert_allclose(pin.aba(model, model.createData(), q, qd, tau), qdd, atol=1e-9)
    np.testing.assert_allclose(tau, M @ qdd + coriolis(robot, q, qd) + gravity(robot, q),
                               atol=1e-9)
    np.testing.assert_allclose(gravity(robot, q), rne(robot, q, np.zeros(6), np.zeros(6)),
                               atol=1e-12)
    # M' - 2 V_m is skew-symmetric (5.83); M' by central differences along qd.
    h = 1e-6
    M_dot = (inertia(robot, q + h * qd) - inertia(robot, q - h * qd)) / (2 * h)
    N = M_dot - 2.0 * coriolis_matrix(robot, q, qd)
    np.testing.assert_allclose(N, -N.T, atol=1e-6)


def test_friction_is_per_joint_and_referred_to_the_motor():
    dyn = np.zeros((2, 20))
    dyn[:, 5] = 1.0
    dyn[1, 1] = 1.0
    dyn[:, 16] = [10.0, -5.0]         # gear ratios
    dyn[:, 17] = [0.01, 0.02]         # B
    dyn[:, 18] = [0.3, 0.2]           # Tc+
    dyn[:, 19] = [-0.4, -0.1]         # Tc-
    np.testing.assert_allclose(friction(dyn, [2.0, -1.0]),
                               [100 * 0.01 * 2 + 10 * 0.3, 25 * 0.02 * -1 + 5 * -0.1])
    np.testing.assert_allclose(friction(dyn, [0.0, 0.0]), 0.0)
    tau0 = rne(dyn, [0.1, 0.2], [2.0, -1.0], [0, 0], [0, 0, 0])
    np.testing.assert_allclose(tau0 - coriolis(dyn, [0.1, 0.2], [2.0, -1.0]),
                               friction(dyn, [2.0, -1.0]), atol=1e-12)


def test_batches_equal_loops():
    robot = puma560()
    rng = np.random.default_rng(4)
    q, qd, qdd = rng.normal(size=(3, 5, 6))
    batch = rne(robot, q, qd, qdd)
    assert batch.shape == (5, 6)
    np.testing.assert_allclose(batch[2], rne(robot, q[2], qd[2], qdd[2]))
    assert inertia(robot, q).shape == (5, 6, 6)


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: rne(puma560(), np.zeros(6), np.zeros(6), np.zeros(5)), 'shape'),
    (lambda: rne(puma560(), np.full(6, np.nan), np.zeros(6), np.zeros(6)), 'finite'),
    (lambda: gravity(puma560(), np.zeros(6), grav=[0, 0]), 'grav'),
    (lambda: inertia(np.zeros((2, 19)), [0, 0]), '20'),
    (lambda: inertia([[0, 0, 0, 0]], [0]), '20'),
    (lambda: fdyn(puma560(), 1.0, 0.0, None, np.zeros(6), np.zeros(6)), 't0 < tf'),
    (lambda: fdyn(puma560(), 0.0, 1.0, lambda t, q, qd: [0.0], np.zeros(6), np.zeros(6)),
     'torquefun'),
])
def test_bad_input_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(('call', 'match'), [
    # Issue 16: q' = 1e200 gave NaN torques silently. Bounds of robotica_kin.bounds: |q| <= 1e4,
    # |q'| <= 1e3, |q''| <= 1e6.
    (lambda: rne(puma560(), np.zeros(6), np.full(6, 1e200), np.zeros(6)), 'qd must be finite'),
    (lambda: rne(puma560(), np.zeros(6), [0, 0, 1001.0, 0, 0, 0], np.zeros(6)), r'1000\.0'),
    (lambda: rne(puma560(), [0, 0, 0, 0, 0, -2e4], np.zeros(6), np.zeros(6)), 'q must'),
    (lambda: rne(puma560(), np.zeros(6), np.zeros(6), [0, 2e6, 0, 0, 0, 0]), 'qdd must'),
    (lambda: rne(puma560(), np.zeros((2, 6)), [[0.0] * 6, [1e200] * 6], np.zeros((2, 6))),
     'qd must'),
    (lambda: coriolis(puma560(), np.zeros(6), np.full(6, 1e200)), 'qd must'),
    (lambda: coriolis_matrix(puma560(), np.zeros(6), np.full(6, -1e10)), 'qd must'),
    (lambda: friction(puma560(), np.full(6, 1e306)), 'qd must'),
    (lambda: gravity(puma560(), np.full(6, 1e300)), 'q must'),
    (lambda: inertia(puma560(), np.full(6, 1e300)), 'q must'),
    (lambda: fdyn(puma560(), 0.0, 1.0, None, np.zeros(6), np.full(6, 1e200)), 'qd0 must'),
])
def test_absurd_joint_values_are_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_a_result_that_overflows_is_refused():
    # Ej. 5.1 with m1 = m2 = 1e308 kg, l1 = 3, l2 = 1 m: (5.77) M11 = l2² m2 + 2 l1 l2 m2
    # + l1² (m1 + m2) = 25e308 kg m², beyond the largest float (1.8e308).
    _, dyn = two_link_arm(1e308, 1e308, 3.0, 1.0)
    with pytest.raises(ValueError, match='inertia is not finite'):
        inertia(dyn, [0.0, 0.0])
    with pytest.raises(ValueError, match='rne is not finite'):
        rne(dyn, [0.0, 0.0], [0.0, 0.0], [1.0, 0.0])


def test_values_at_the_bounds_are_taken():
    # Ej. 5.1 (m1 = 2, m2 = 1 kg, l1 = 3, l2 = 1 m), horizontal plane (no gravity), stretched,
    # joint 1 at q1' = 1000 rad/s (the bound), q2' = 0, q'' = 0: (5.77) V = (0, m2 l1 l2 s2 q1'²)
    # = 0 at q2 = 0, and the centripetal force does no torque: tau = 0.
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    tau = rne(dyn, [1e4, 0.0], [1e3, 0.0], [0.0, 0.0], grav=[0, 0, 0])
    np.testing.assert_allclose(tau, [0.0, 0.0], atol=1e-6)
    # q2 = pi/2: V2 = m2 l1 l2 q1'² = 3e6 N m; plus M21 q1'' with q1'' = 1e6 (the bound):
    # M21 = l2² m2 + l1 l2 m2 cos q2 = 1 kg m², tau2 = 3e6 + 1e6.
    tau = rne(dyn, [0.0, math.pi / 2], [1e3, 0.0], [1e6, 0.0], grav=[0, 0, 0])
    assert tau[1] == pytest.approx(4e6, rel=1e-9)


def test_robot_without_dyn_is_refused():
    from robotica_kin.robots import planar_rrr
    with pytest.raises(ValueError, match='no dyn table'):
        inertia(planar_rrr(), [0, 0, 0])
