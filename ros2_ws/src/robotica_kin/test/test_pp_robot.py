"""
Tests of robotica_kin.robots.pp_robot: the planar PP robot of Ej. 8.10-8.11 (catalog §6.8).

Reference: the book's model (8.182)-(8.183) in its joint order [d1, d2],
M = diag(m1, m1 + m2) and G = [0; (m1 + m2) g]; the chain's order is [d2, d1].
"""
import math

import numpy as np
import pytest
from robotica_kin.dynamics import gravity, inertia
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.robots import pp_robot, robot_by_name

G = 9.81
PLANE = [0.0, -G, 0.0]          # the robot moves in the XY plane, Y up
BOOK_ORDER = [1, 0]             # chain q = [d2, d1] -> book [d1, d2]


@pytest.mark.parametrize(('m1', 'm2'), [(2.0, 0.35), (1.5, 4.0), (3.0, 0.0)])
@pytest.mark.parametrize('q', [[0.0, 0.0], [math.sqrt(2.0), 3.0 * math.sqrt(2.0)], [-2.5, 7.0]])
def test_mass_matrix_and_gravity_are_the_books_8_183(m1, m2, q):
    robot = pp_robot(m1, m2)
    M = inertia(robot, q)[np.ix_(BOOK_ORDER, BOOK_ORDER)]
    np.testing.assert_allclose(M, [[m1, 0.0], [0.0, m1 + m2]], atol=1e-12)
    np.testing.assert_allclose(gravity(robot, q, grav=PLANE)[BOOK_ORDER], [0.0, (m1 + m2) * G],
                               atol=1e-12)


def test_end_effector_is_d1_along_x_and_d2_along_y():
    robot = pp_robot()
    d2, d1 = 1.25, -0.75
    T = fkine(robot, [d2, d1])
    np.testing.assert_allclose(T[:3, 3], [d1, d2, 0.0], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-12)   # tool parallel to {0}
    J = jacob0(robot, [d2, d1])
    np.testing.assert_allclose(J[:3][:, BOOK_ORDER], np.eye(3)[:, :2], atol=1e-12)
    np.testing.assert_allclose(J[3:], 0.0, atol=1e-12)


def test_joints_name_the_book_variables_and_the_defaults_are_ej_8_10():
    robot = robot_by_name('pp_robot')
    assert robot.joint_names == ('d2_vertical', 'd1_horizontal')
    assert robot.prismatic.tolist() == [True, True]
    np.testing.assert_allclose(np.diag(inertia(robot, [0.0, 0.0])), [2.35, 2.0], atol=1e-12)
    # Ej. 8.10 starts at d1 = 3√2, d2 = √2 m: inside the limits.
    assert robot.within_limits([math.sqrt(2.0), 3.0 * math.sqrt(2.0)])


@pytest.mark.parametrize(('m1', 'm2', 'match'), [(0.0, 0.35, 'm1'), (math.nan, 0.35, 'm1'),
                                                 (2.0, -0.1, 'm2'), (2.0, math.inf, 'm2')])
def test_bad_masses_are_refused(m1, m2, match):
    with pytest.raises(ValueError, match=match):
        pp_robot(m1, m2)
