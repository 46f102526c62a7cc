"""
Tests of the fast route of robotica_kin.dynamics (issue 20): same results, same refusals.

One configuration of (n,) ndarrays with the default gravity skips the full checks (norm of each
vector, Pinocchio's own size check, results unchecked when the arm's torque_bound allows). Each
test compares it with the full route (the same values given as lists, or batches), with the
friction law written out from the table (book (5.84)-(5.86), HEMERO §A.3), or with the bounds
of robotica_kin.bounds.
"""
import math

import numpy as np
import pytest

from robotica_kin.dh import dh_model
from robotica_kin.dynamics import (coriolis, coriolis_matrix, fdyn, friction, gravity, inertia,
                                   rne)
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import puma560, two_link_arm


def _rpr_with_friction():
    """Return an R-P-R arm with masses, inertias, motors, viscous and Coulomb friction."""
    dyn = np.zeros((3, 20))
    dyn[:, :5] = [[0, 0, 0, 0.3, 0], [-math.pi / 2, 0.1, 0, 0, 1], [0, 0, 0, 0.2, 0]]
    dyn[:, 5] = [4.0, 2.5, 1.2]                       # m [kg]
    dyn[:, 6:9] = [[0.1, 0, 0.05], [0, 0, -0.2], [0, 0.02, 0.1]]   # centre of mass [m]
    dyn[:, 9:12] = [[0.05, 0.06, 0.04], [0.02, 0.02, 0.01], [0.01, 0.01, 0.005]]
    dyn[:, 15] = [2e-4, 1e-4, 5e-5]                   # J_m [kg m²]
    dyn[:, 16] = [50.0, -20.0, 30.0]                  # G
    dyn[:, 17] = [1e-3, 2e-3, 5e-4]                   # B [N m s/rad]
    dyn[:, 18] = [0.01, 0.02, 0.01]                   # Tc+ [N m]
    dyn[:, 19] = [-0.012, -0.01, -0.015]              # Tc- [N m]
    return dh_model(dyn[:, :5], name='rpr', qlim=[[-3, 3], [0, 1], [-3, 3]], dyn=dyn)


def _friction_by_hand(dyn, qd):
    """F = G² B q' + |G| Tc, Tc = Tc+ (q' > 0), Tc- (q' < 0), 0 (q' = 0), per joint."""
    gear, viscous, plus, minus = dyn[:, 16], dyn[:, 17], dyn[:, 18], dyn[:, 19]
    coulomb = [p if v > 0 else m if v < 0 else 0.0 for v, p, m in zip(qd, plus, minus)]
    return gear ** 2 * viscous * qd + np.abs(gear) * np.array(coulomb)


@pytest.mark.parametrize('robot', [puma560(), _rpr_with_friction()], ids=['puma560', 'rpr'])
def test_the_fast_route_gives_the_full_routes_results(robot):
    arm = pinocchio_arm(robot)
    data = arm.model.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1])
        qd, qdd = rng.normal(size=(2, robot.n))
        full = [list(x) for x in (q, qd, qdd)]          # lists take the full checks
        np.testing.assert_allclose(rne(arm, q, qd, qdd, data=data), rne(arm, *full),
                                   rtol=1e-14, atol=1e-12)
        np.testing.assert_allclose(inertia(arm, q, data=data), inertia(arm, full[0]), atol=1e-12)
        np.testing.assert_allclose(gravity(arm, q), gravity(arm, full[0]), atol=1e-12)
        np.testing.assert_allclose(coriolis(robot, q, qd), coriolis(arm, *full[:2]), atol=1e-12)
        np.testing.assert_allclose(coriolis_matrix(arm, q, qd),
                                   coriolis_matrix(arm, *full[:2]), atol=1e-12)
        np.testing.assert_allclose(friction(arm, qd), _friction_by_hand(robot.dyn, qd),
                                   atol=1e-14)
        # tau = M q'' + V + G + F (A.1), each term from its own function.
        np.testing.assert_allclose(
            rne(robot, q, qd, qdd),
            inertia(robot, q) @ qdd + coriolis(robot, q, qd) + gravity(robot, q)
            + _friction_by_hand(robot.dyn, qd), atol=1e-9)


def test_other_dtypes_and_strides_give_the_float64_results():
    arm = pinocchio_arm(puma560())
    q, qd, qdd = np.array([1, -1, 0, 2, 0, 1]), np.arange(6.0)[::-1] / 10, np.ones(6)
    expected = rne(arm, q.tolist(), qd.tolist(), qdd.tolist())
    strided = np.zeros((6, 2))
    strided[:, 0] = qd
    for args in ((q, qd, qdd), (q.astype(np.float32), qd, qdd), (q, strided[:, 0], qdd),
                 (q.astype(object), qd, qdd), (q.astype(np.float64), qd, qdd)):
        np.testing.assert_allclose(rne(arm, *args), expected, atol=1e-12)
    # A batch of one configuration keeps its batch shape.
    assert rne(arm, q[None, :], qd[None, :], qdd[None, :]).shape == (1, 6)


@pytest.mark.parametrize(('call', 'match'), [
    (lambda arm: rne(arm, np.zeros(6), np.zeros(6), np.zeros(5)), 'shape'),
    (lambda arm: rne(arm, np.zeros(7), np.zeros(7), np.zeros(7)), 'shape'),
    (lambda arm: inertia(arm, np.zeros(5)), 'shape'),
    (lambda arm: gravity(arm, np.zeros(6)[:5]), 'shape'),
    (lambda arm: friction(arm, np.zeros(5)), 'shape'),
    (lambda arm: rne(arm, np.full(6, np.nan), np.zeros(6), np.zeros(6)), 'q must be finite'),
    (lambda arm: rne(arm, np.zeros(6), np.array([0, 0, np.inf, 0, 0, 0]), np.zeros(6)), 'qd'),
    (lambda arm: rne(arm, np.zeros(6), np.zeros(6), np.array([0, 2e6, 0, 0, 0, 0.0])), 'qdd'),
    (lambda arm: coriolis(arm, np.zeros(6), np.full(6, 1e200)), 'qd must'),
    (lambda arm: coriolis_matrix(arm, np.full(6, -2e4), np.zeros(6)), 'q must'),
    (lambda arm: friction(arm, np.array([0, 0, 1001.0, 0, 0, 0])), r'1000\.0'),
    (lambda arm: inertia(arm, np.full(6, np.nan)), 'q must be finite'),
    (lambda arm: rne(arm, np.zeros(6), np.zeros(6), np.zeros(6),
                     data=pinocchio_arm(dh_model([[0, 0, 0, 0]])).model.createData()),
     'Data of the model'),
])
def test_the_fast_route_refuses_what_the_full_route_refuses(call, match):
    with pytest.raises(ValueError, match=match):
        call(pinocchio_arm(puma560()))


def test_values_within_the_bounds_but_beyond_the_norm_are_taken():
    # Each |q'_i| <= 1000 rad/s while the norm of q' is above it: the full checks accept it.
    arm = pinocchio_arm(puma560())
    q, qd, qdd = np.zeros(6), np.array([1e3, 1e3, 0, 0, 0, 0]), np.zeros(6)
    np.testing.assert_allclose(rne(arm, q, qd, qdd), rne(arm, [q], [qd], [qdd])[0], atol=1e-9)


def test_a_robot_of_absurd_mass_is_checked_on_every_route():
    # Ej. 5.1 with m1 = m2 = 1e308 kg, l1 = 3, l2 = 1 m: M11 = 25e308 kg m² overflows (5.77).
    _, dyn = two_link_arm(1e308, 1e308, 3.0, 1.0)
    arm = pinocchio_arm(dh_model(dyn[:, :5], dyn=dyn))
    assert not arm.torque_bound < 1e150
    with pytest.raises(ValueError, match='inertia is not finite'):
        inertia(arm, np.zeros(2))
    with pytest.raises(ValueError, match='rne is not finite'):
        rne(arm, np.zeros(2), np.zeros(2), np.array([1.0, 0.0]))
    # 1e100 kg is absurd too but finite: the results are checked, and given.
    _, heavy = two_link_arm(1e100, 1e100, 3.0, 1.0)
    M = inertia(heavy, np.zeros(2))
    np.testing.assert_allclose(M, [[25e100, 4e100], [4e100, 1e100]], rtol=1e-12)   # (5.77)


@pytest.mark.parametrize('robot', [puma560(), _rpr_with_friction(),
                                   dh_model(two_link_arm(2.0, 1.0, 3.0, 1.0)[1][:, :5],
                                            dyn=two_link_arm(2.0, 1.0, 3.0, 1.0)[1])],
                         ids=['puma560', 'rpr', 'ej_5_1'])
def test_torque_bound_bounds_every_result_within_the_joint_bounds(robot):
    # The extreme joint values of robotica_kin.bounds: |q| <= 1e4, |q'| <= 1e3, |q''| <= 1e6.
    arm = pinocchio_arm(robot)
    rng = np.random.default_rng(11)
    n = robot.n
    q = rng.uniform(-1e4, 1e4, size=(20, n))
    qd = 1e3 * rng.choice([-1.0, 1.0], size=(20, n))
    qdd = 1e6 * rng.choice([-1.0, 1.0], size=(20, n))
    largest = max(np.abs(rne(arm, q, qd, qdd)).max(), np.abs(inertia(arm, q)).max(),
                  np.abs(coriolis(arm, q, qd)).max(), np.abs(gravity(arm, q)).max(),
                  np.abs(friction(arm, qd)).max())
    assert 0.0 < largest <= arm.torque_bound < 1e150


def test_fdyn_follows_the_model_with_friction():
    # fdyn's q' changes as M q'' = tau - V - G - F says (5.88), with V, G and M from their own
    # Pinocchio algorithms and F written out from the table; q'' by central differences.
    robot = _rpr_with_friction()
    torque = np.array([3.0, 8.0, -2.0])   # beyond each Coulomb torque: q' keeps its sign
    step = 1e-3
    result = fdyn(robot, 0.0, 0.2, lambda t, q, qd: torque, [0.1, 0.3, -0.2], [0.5, 0.2, -0.3],
                  grav=[0, 0, -9.81], t_eval=np.arange(201) * step, rtol=1e-11, atol=1e-12)
    for k in (50, 100, 150):
        q, qd = result.q[k], result.qd[k]
        assert np.all(np.sign(result.qd[k - 1]) == np.sign(result.qd[k + 1]))   # no sgn jump
        expected = np.linalg.solve(inertia(robot, q), torque - coriolis(robot, q, qd)
                                   - gravity(robot, q, [0, 0, -9.81])
                                   - _friction_by_hand(robot.dyn, qd))
        differences = (result.qd[k + 1] - result.qd[k - 1]) / (2 * step)
        np.testing.assert_allclose(differences, expected, rtol=1e-4, atol=1e-4)


@pytest.mark.parametrize('call', [
    lambda arm: rne(arm, np.zeros(2), np.zeros(2), np.zeros(2)),
    lambda arm: rne(arm, np.zeros(2), np.zeros(2), np.zeros(2), grav=[0, -9.81, 0]),
    lambda arm: inertia(arm, np.zeros(2)),
    lambda arm: gravity(arm, np.zeros(2)),
    lambda arm: gravity(arm, np.zeros(2), grav=[0, -9.81, 0]),
    lambda arm: coriolis(arm, np.zeros(2), np.zeros(2)),
    lambda arm: coriolis_matrix(arm, np.zeros(2), np.zeros(2)),
    lambda arm: friction(arm, np.zeros(2)),
    lambda arm: fdyn(arm, 0.0, 0.1, None, np.zeros(2), np.zeros(2)),
])
def test_an_arm_without_dynamics_is_refused_on_every_route(call):
    with pytest.raises(ValueError, match='no dyn table'):
        call(pinocchio_arm(dh_model([[0, 0, 0, 0], [0, 1.0, 0, 0]])))
