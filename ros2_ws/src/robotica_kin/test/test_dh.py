"""Tests of robotica_kin.dh: HEMERO DH tables and Craig's link transform (catalog §2.2, §12.2)."""
import dataclasses
import math

import numpy as np
import pytest

from robotica_kin.dh import as_dh_model, as_dyn_model, dh_model, DHModel, linktrans


def _rot_x(alpha):
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _rot_z(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _tras(x=0.0, z=0.0):
    T = np.eye(4)
    T[0, 3], T[2, 3] = x, z
    return T


@pytest.mark.parametrize('seed', range(10))
def test_linktrans_is_the_product_of_the_four_elementary_motions(seed):
    # (4.4): Rot(X, alpha) Tras(X, a) Rot(Z, theta) Tras(Z, d), multiplied out here.
    alpha, a, theta, d = np.random.default_rng(seed).uniform(-3, 3, 4)
    expected = _rot_x(alpha) @ _tras(x=a) @ _rot_z(theta) @ _tras(z=d)
    np.testing.assert_allclose(linktrans(alpha, a, theta, d), expected, atol=1e-14)


def test_ejemplo_4_2_link_transforms_4_15_to_4_17():
    # HEMERO calls of Ej. 4.2: linktrans([0 0 125 0 0], t1), linktrans([pi/2 0 0 426 1], d2),
    # linktrans([0 0 876 l2 0], t3); the 125/426/876 placeholders are ignored.
    t1, d2, t3, l2 = 0.4, 0.7, -0.9, 0.25
    c1, s1, c3, s3 = math.cos(t1), math.sin(t1), math.cos(t3), math.sin(t3)
    np.testing.assert_allclose(linktrans([0, 0, 125, 0, 0], t1),
                               [[c1, -s1, 0, 0], [s1, c1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
                               atol=1e-15)
    np.testing.assert_allclose(linktrans([math.pi / 2, 0, 0, 426, 1], d2),
                               [[1, 0, 0, 0], [0, 0, -1, -d2], [0, 1, 0, 0], [0, 0, 0, 1]],
                               atol=1e-15)
    np.testing.assert_allclose(linktrans([0, 0, 876, l2, 0], t3),
                               [[c3, -s3, 0, 0], [s3, c3, 0, 0], [0, 0, 1, l2], [0, 0, 0, 1]],
                               atol=1e-15)


def test_four_column_row_is_revolute():
    np.testing.assert_array_equal(linktrans([0.3, 1.0, 99.0, 0.2], 0.5),
                                  linktrans(0.3, 1.0, 0.5, 0.2))


def test_dh_model_reads_sigma_and_defaults():
    robot = dh_model([[0, 0, 0, 0, 0], [math.pi / 2, 0, 0, 0, 1], [0, 0, 0, 0.3, 0]])
    assert robot.prismatic.tolist() == [False, True, False]
    assert robot.joint_names == ('joint_1', 'joint_2', 'joint_3')
    np.testing.assert_array_equal(robot.qlim[0], [-math.pi, math.pi])
    np.testing.assert_array_equal(robot.qlim[1], [-1.0, 1.0])
    np.testing.assert_array_equal(robot.tool, np.eye(4))
    np.testing.assert_array_equal(robot.table[:, 4], [0, 1, 0])
    with pytest.raises(ValueError):
        robot.alpha[0] = 1.0     # read-only arrays


def test_as_dh_model_returns_a_model_unchanged_and_validates_a_table():
    table = [[0, 0, 0, 0], [0, 1.5, 0, 0]]
    robot = as_dh_model(table)
    np.testing.assert_array_equal(robot.table, np.column_stack([table, [0, 0]]))
    assert as_dh_model(robot) is robot
    with pytest.raises(ValueError, match='shape'):
        as_dh_model([[0, 0, 0]])


def test_as_dyn_model_needs_the_dynamic_table():
    dyn = np.zeros((2, 20))
    dyn[1, 1] = 1.5
    dyn[:, 5] = 1.0
    robot = as_dyn_model(dyn)
    np.testing.assert_array_equal(robot.dyn, dyn)
    assert as_dyn_model(robot) is robot
    with pytest.raises(ValueError, match='no dyn table'):
        as_dyn_model(dh_model(dyn[:, :5]))
    with pytest.raises(ValueError, match=r'\(n, 20\)'):
        as_dyn_model(dyn[:, :5])


def test_dh_model_is_plain_data():
    """The model holds its table and nothing else: no Pinocchio model, no scratch (issue 15)."""
    assert [f.name for f in dataclasses.fields(DHModel)] == [
        'alpha', 'a', 'theta', 'd', 'prismatic', 'qlim', 'name', 'joint_names', 'dyn', 'tool']
    robot = dh_model([[0, 0, 0, 0]])
    with pytest.raises(dataclasses.FrozenInstanceError):
        robot.name = 'other'


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'dh': [[0, 0, 0]]}, 'shape'),
    ({'dh': []}, 'shape'),
    ({'dh': [[0, 0, math.nan, 0]]}, 'finite'),
    ({'dh': [[0, 0, 0, 0]], 'qlim': [[1.0, -1.0]]}, 'lower <= upper'),
    ({'dh': [[0, 0, 0, 0]], 'qlim': [[0, 1], [0, 1]]}, 'qlim'),
    ({'dh': [[0, 0, 0, 0]] * 2, 'joint_names': ['a', 'a']}, 'distinct'),
    ({'dh': [[0, 0, 0, 0]], 'dyn': np.zeros((1, 19))}, 'dyn'),
    ({'dh': [[0, 0, 0, 0]], 'dyn': np.ones((1, 20))}, 'equal the DH table'),
    ({'dh': [[0, 0, 0, 0]], 'tool': np.diag([1.0, 1.0, 2.0, 1.0])}, 'tool'),
])
def test_bad_tables_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dh_model(**kwargs)


def test_check_q_refuses_wrong_sizes_and_nan():
    robot = dh_model([[0, 0, 0, 0], [0, 1, 0, 0]], name='rr')
    with pytest.raises(ValueError, match=r"shape \(2,\) or \(m, 2\).*'rr'"):
        robot.check_q([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match='finite'):
        robot.check_q([0.0, math.inf])
    assert robot.check_q([[0, 1], [2, 3]]).shape == (2, 2)


def test_linktrans_refuses_bad_arguments():
    with pytest.raises(ValueError, match='4 or 5'):
        linktrans([0, 0, 0], 1.0)
    with pytest.raises(ValueError, match='finite'):
        linktrans(0.0, 0.0, math.nan, 0.0)
    with pytest.raises(ValueError, match='takes'):
        linktrans(0.0, 0.0, 0.0)
