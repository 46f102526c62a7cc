"""
Tests of robotica_kin.forward_kinematics (catalog §2.2, §2.6 Ej. 4.1 and 4.2, §12.2 fkine).

References: the book's closed forms (4.10) and (4.15)-(4.17) written out here, and a NumPy
product of (4.4) link matrices built in the test.
"""
import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.dh import dh_model
from robotica_kin.forward_kinematics import fkine, link_frames
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560

ANGLE = st.floats(-math.pi, math.pi)
LENGTH = st.floats(0.1, 5.0)


@settings(max_examples=40, deadline=None)
@given(t1=ANGLE, t2=ANGLE, t3=ANGLE, l1=LENGTH, l2=LENGTH)
def test_ejemplo_4_1_equals_closed_form_4_10(t1, t2, t3, l1, l2):
    c1, s1 = math.cos(t1), math.sin(t1)
    c12, s12 = math.cos(t1 + t2), math.sin(t1 + t2)
    c123, s123 = math.cos(t1 + t2 + t3), math.sin(t1 + t2 + t3)
    expected = np.array([[c123, -s123, 0, l1 * c1 + l2 * c12],
                         [s123, c123, 0, l1 * s1 + l2 * s12], [0, 0, 1, 0], [0, 0, 0, 1]])
    # HEMERO's table (Table 4.2) with placeholders in the theta column: ignored (§12.2).
    dh = [[0, 0, 376, 0, 0], [0, l1, 212, 0, 0], [0, l2, 789, 0, 0]]
    np.testing.assert_allclose(fkine(dh, [t1, t2, t3]), expected, atol=1e-12)
    np.testing.assert_allclose(fkine(planar_rrr(l1, l2), [t1, t2, t3]), expected, atol=1e-12)


def test_ejemplo_4_2_chain_of_4_15_to_4_17():
    t1, d2, t3, l2 = 0.3, 0.6, -1.1, 0.2
    c1, s1, c3, s3 = math.cos(t1), math.sin(t1), math.cos(t3), math.sin(t3)
    T01 = np.array([[c1, -s1, 0, 0], [s1, c1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    T12 = np.array([[1, 0, 0, 0], [0, 0, -1, -d2], [0, 1, 0, 0], [0, 0, 0, 1]])
    T23 = np.array([[c3, -s3, 0, 0], [s3, c3, 0, 0], [0, 0, 1, l2], [0, 0, 0, 1]])
    np.testing.assert_allclose(fkine(cylindrical_rpr(l2), [t1, d2, t3]), T01 @ T12 @ T23,
                               atol=1e-14)
    # (4.23): the first two joints alone put frame {2} at (d2 s1, -d2 c1, 0).
    frames = link_frames(cylindrical_rpr(l2), [t1, d2, t3])
    np.testing.assert_allclose(frames[2][:3, 3], [d2 * s1, -d2 * c1, 0.0], atol=1e-14)


def test_planar_rr_tool_is_the_tip():
    q = [0.4, -1.2]
    tip = fkine(planar_rr(4.0, 3.0), q)[:3, 3]
    np.testing.assert_allclose(tip, [4 * math.cos(0.4) + 3 * math.cos(-0.8),
                                     4 * math.sin(0.4) + 3 * math.sin(-0.8), 0.0], atol=1e-14)


def _product(robot, q):
    T = np.eye(4)
    for i in range(robot.n):
        theta = robot.theta[i] if robot.prismatic[i] else q[i]
        d = q[i] if robot.prismatic[i] else robot.d[i]
        ca, sa = math.cos(robot.alpha[i]), math.sin(robot.alpha[i])
        ct, st_ = math.cos(theta), math.sin(theta)
        T = T @ np.array([[ct, -st_, 0, robot.a[i]], [st_ * ca, ct * ca, -sa, -sa * d],
                          [st_ * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])
    return T @ robot.tool


@pytest.mark.parametrize('seed', range(5))
def test_pinocchio_and_numpy_routes_agree_on_random_tables(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 8))
    table = np.column_stack([rng.uniform(-3, 3, (n, 4)), rng.integers(0, 2, n)])
    tool = np.eye(4)
    tool[:3, 3] = rng.normal(size=3)
    robot = dh_model(table, tool=tool)
    q = rng.uniform(-3, 3, (50, n))
    arm = pinocchio_arm(robot)
    data = arm.model.createData()
    batch = fkine(robot, q)                       # vectorised NumPy route
    single = np.array([fkine(arm, qi, data=data) for qi in q])    # Pinocchio route
    expected = np.array([_product(robot, qi) for qi in q])
    np.testing.assert_allclose(single, batch, atol=1e-12)
    np.testing.assert_allclose(single, expected, atol=1e-12)
    np.testing.assert_allclose(fkine(robot, q[0]), expected[0], atol=1e-12)   # NumPy, one q
    np.testing.assert_allclose(fkine(arm, q), batch, atol=0)     # an arm's batch: NumPy too
    np.testing.assert_allclose(fkine(arm, q[0]), expected[0], atol=1e-12)   # its own data


def test_data_needs_the_arm_of_its_model():
    robot = puma560()
    arm = pinocchio_arm(robot)
    with pytest.raises(ValueError, match='pass the arm'):
        fkine(robot, np.zeros(6), data=arm.model.createData())
    with pytest.raises(ValueError, match='Data of the model'):
        fkine(arm, np.zeros(6), data=pinocchio_arm(planar_rr(1.0, 1.0)).model.createData())


def test_shapes_of_batches_and_frames():
    robot = puma560()
    q = np.zeros((7, 6))
    assert fkine(robot, q).shape == (7, 4, 4)
    frames = link_frames(robot, q)
    assert frames.shape == (7, 7, 4, 4)
    np.testing.assert_array_equal(frames[:, 0], np.broadcast_to(np.eye(4), (7, 4, 4)))


def test_puma560_home_pose():
    # dhp560 at q = 0 (catalog §12.4): every Rot(Z) is the identity, so the chain is the product
    # of Rot(X, alpha_{i-1}) Tras(X, a_{i-1}) Tras(Z, d_i). By hand: Tras(Z, 0.2435) after
    # Rot(X, -90°) moves along +Y_0; row 3 adds 0.4318 along X_0 and -0.0934 along Y_0; row 4
    # adds -0.0203 along X_0 and, after Rot(X, -90°) Rot(X, 90°) = I, 0.4331 along Z_0.
    T = np.eye(4)
    for alpha, a, d in [(0, 0, 0), (-math.pi / 2, 0, 0.2435), (0, 0.4318, -0.0934),
                        (math.pi / 2, -0.0203, 0.4331), (-math.pi / 2, 0, 0), (math.pi / 2, 0, 0)]:
        ca, sa = math.cos(alpha), math.sin(alpha)
        T = T @ np.array([[1, 0, 0, a], [0, ca, -sa, -sa * d], [0, sa, ca, ca * d], [0, 0, 0, 1]])
    np.testing.assert_allclose(fkine(puma560(), np.zeros(6)), T, atol=1e-14)
    np.testing.assert_allclose(T[:3, 3], [0.4318 - 0.0203, 0.2435 - 0.0934, 0.4331], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-15)


def test_bad_q_is_refused():
    with pytest.raises(ValueError, match='shape'):
        fkine(puma560(), np.zeros(5))
    with pytest.raises(ValueError, match='finite'):
        fkine(puma560(), [0, 0, math.nan, 0, 0, 0])
