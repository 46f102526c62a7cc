"""
Tests of robotica_kin.velocity_propagation: velprop (catalog 2.4, 2.6, 12.2).

References: the book's velocity vectors (4.65)-(4.70), (4.78) and (4.79) written out with
sines and cosines (catalog 2.6; (4.79)'s fifth entry is c3 θ1', catalog Part 17), central
differences of ``fkine`` composed with a moving base integrated by scipy's matrix exponential,
and the rigid-body velocity formula (4.51); never the code under test.
"""

import math

import numpy as np
import pytest
from robotica_kin.dh import dh_model
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacobn
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560
from robotica_kin.transforms import rotvec, transl
from robotica_kin.velocity_propagation import velprop
from scipy.linalg import expm

H = 1e-6          # central-difference step [s]
FD_TOL = 1e-8     # its truncation (~H²) and round-off (~1e-16 / H) error, with margin


def vex(S):
    """Return the vector of the skew-symmetric part of a 3×3 matrix."""
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


def random_robot(rng):
    """Return a random DH model: random n, sigma, geometry and tool."""
    n = int(rng.integers(1, 8))
    table = np.column_stack([
        rng.uniform(-math.pi, math.pi, n), rng.uniform(-1, 1, n),
        rng.uniform(-math.pi, math.pi, n), rng.uniform(-1, 1, n), rng.integers(0, 2, n)])
    tool = transl(rng.uniform(-0.5, 0.5, 3)) @ rotvec(rng.normal(size=3), rng.uniform(-3, 3))
    return dh_model(table, name='random', tool=tool)


def tool_velocity_by_finite_differences(robot, q, qd, v0, w0):
    """
    Return [v; ω] of the tool in its own axes by differentiating its world pose numerically.

    The base moves as ``T_w_0(t) = expm(t [[S(w0), v0], [0, 0]])`` (frame {0} at the world
    frame at t = 0, v0 the velocity of its origin), the joints as ``q + t qd``; the tool pose
    is ``T_w_0(t) fkine(q + t qd)``.
    """
    wx, wy, wz = w0
    xi = np.array([[0.0, -wz, wy, v0[0]], [wz, 0.0, -wx, v0[1]], [-wy, wx, 0.0, v0[2]],
                   [0.0, 0.0, 0.0, 0.0]])
    plus = expm(H * xi) @ fkine(robot, q + H * qd)
    minus = expm(-H * xi) @ fkine(robot, q - H * qd)
    R = fkine(robot, q)[:3, :3]
    v = R.T @ (plus[:3, 3] - minus[:3, 3]) / (2 * H)
    w = R.T @ vex((plus[:3, :3] - minus[:3, :3]) @ R.T / (2 * H))
    return np.concatenate([v, w])


def test_ejemplo_4_5():
    """
    Ej. 4.5 (catalog 2.6): planar 3R, velprop equals (4.78); with θ3 = 0 it is (4.68)-(4.70).

    Checked on ``planar_rrr(l1, l2)`` and on the raw table of Ej. 4.1.
    """
    rng = np.random.default_rng(45)
    for _ in range(20):
        l1, l2 = rng.uniform(0.2, 5.0, 2)
        q = rng.uniform(-math.pi, math.pi, 3)
        qd = rng.uniform(-2, 2, 3)
        s3, c3 = math.sin(q[2]), math.cos(q[2])
        s23, c23 = math.sin(q[1] + q[2]), math.cos(q[1] + q[2])
        expected = np.array([                                               # (4.78)
            (l1 * s23 + l2 * s3) * qd[0] + l2 * s3 * qd[1],
            (l1 * c23 + l2 * c3) * qd[0] + l2 * c3 * qd[1],
            0.0, 0.0, 0.0,
            qd[0] + qd[1] + qd[2]])
        table = [[0, 0, 0, 0, 0], [0, l1, 0, 0, 0], [0, l2, 0, 0, 0]]
        for robot in (planar_rrr(l1, l2), table):
            np.testing.assert_allclose(velprop(robot, q, qd, [0, 0, 0], [0, 0, 0]), expected,
                                       rtol=0, atol=1e-12)
        s2, c2 = math.sin(q[1]), math.cos(q[1])
        expected_4_70 = [l1 * s2 * qd[0], l1 * c2 * qd[0] + l2 * (qd[0] + qd[1]), 0.0,
                         0.0, 0.0, qd[0] + qd[1]]                           # (4.68)-(4.70)
        np.testing.assert_allclose(velprop(table, [q[0], q[1], 0.0], [qd[0], qd[1], 0.0]),
                                   expected_4_70, rtol=0, atol=1e-12)


def test_ejemplo_4_6():
    """Ej. 4.6 (catalog 2.6): R-P-R robot, velprop equals (4.79) with c3 θ1' as 5th entry."""
    rng = np.random.default_rng(46)
    for _ in range(20):
        l2 = rng.uniform(0.05, 2.0)
        t1, d2, t3 = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 1.0), rng.uniform(-3, 3)
        t1d, d2d, t3d = rng.uniform(-2, 2, 3)
        s3, c3 = math.sin(t3), math.cos(t3)
        expected = [c3 * (l2 + d2) * t1d, -s3 * (l2 + d2) * t1d, d2d, s3 * t1d, c3 * t1d, t3d]
        table = [[0, 0, 0, 0, 0], [math.pi / 2, 0, 0, 0, 1], [0, 0, 0, l2, 0]]
        for robot in (table, cylindrical_rpr(l2)):
            np.testing.assert_allclose(velprop(robot, [t1, d2, t3], [t1d, d2d, t3d]), expected,
                                       rtol=0, atol=1e-12)


ROBOTS = [puma560(), planar_rr(0.7, 0.4), planar_rrr(1.0, 0.8, 0.3), cylindrical_rpr(0.3)]


@pytest.mark.parametrize('robot', ROBOTS, ids=lambda r: r.name)
def test_velprop_equals_jacobn_times_qd(robot):
    """(4.77): for a fixed base, velprop(q, qd) = jacobn(q) qd."""
    rng = np.random.default_rng(21)
    for _ in range(10):
        q = rng.uniform(-math.pi, math.pi, robot.n)
        qd = rng.uniform(-2, 2, robot.n)
        np.testing.assert_allclose(velprop(robot, q, qd), jacobn(robot, q) @ qd, rtol=0,
                                   atol=1e-12)


def test_moving_base_against_the_rigid_body_formula():
    """
    With base velocities v0, w0 (in {0}), velprop adds the base's rigid motion (4.51).

    The tool origin at p moves at ``v0 + w0 × p`` from the base alone; in tool axes:
    ``[R^T (v0 + w0 × p); R^T w0] + jacobn qd``, with R, p from fkine.
    """
    rng = np.random.default_rng(22)
    for robot in ROBOTS:
        for _ in range(5):
            q = rng.uniform(-math.pi, math.pi, robot.n)
            qd = rng.uniform(-2, 2, robot.n)
            v0, w0 = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
            T = fkine(robot, q)
            R, p = T[:3, :3], T[:3, 3]
            expected = np.concatenate([R.T @ (v0 + np.cross(w0, p)), R.T @ w0])
            expected += jacobn(robot, q) @ qd
            np.testing.assert_allclose(velprop(robot, q, qd, v0, w0), expected, rtol=0,
                                       atol=1e-12)


def test_moving_base_against_finite_differences():
    """With v0, w0, velprop equals the numerical derivative of the tool's world pose."""
    rng = np.random.default_rng(23)
    robots = ROBOTS + [random_robot(rng) for _ in range(10)]
    for robot in robots:
        q = rng.uniform(-math.pi, math.pi, robot.n)
        qd = rng.uniform(-2, 2, robot.n)
        v0, w0 = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
        np.testing.assert_allclose(
            velprop(robot, q, qd, v0, w0),
            tool_velocity_by_finite_differences(robot, q, qd, v0, w0), rtol=0, atol=FD_TOL)
        fixed_base = tool_velocity_by_finite_differences(robot, q, qd, np.zeros(3), np.zeros(3))
        np.testing.assert_allclose(velprop(robot, q, qd), fixed_base, rtol=0, atol=FD_TOL)


@pytest.mark.parametrize('robot', ROBOTS, ids=lambda r: r.name)
def test_batch_equals_loop(robot):
    """(m, n) q and qd give (m, 6), equal to m single calls."""
    rng = np.random.default_rng(24)
    Q = rng.uniform(-math.pi, math.pi, (6, robot.n))
    QD = rng.uniform(-2, 2, (6, robot.n))
    v0, w0 = [0.1, -0.2, 0.3], [0.3, 0.2, -0.1]
    batch = velprop(robot, Q, QD, v0, w0)
    assert batch.shape == (6, 6)
    np.testing.assert_allclose(batch, [velprop(robot, q, qd, v0, w0) for q, qd in zip(Q, QD)],
                               rtol=0, atol=1e-15)
    assert velprop(robot, Q[0], QD[0]).shape == (6,)


@pytest.mark.parametrize('call', [
    lambda: velprop(puma560(), np.zeros(5), np.zeros(5)),
    lambda: velprop(puma560(), np.zeros(6), np.zeros(5)),
    lambda: velprop(puma560(), np.zeros(6), np.zeros((2, 6))),
    lambda: velprop(puma560(), np.zeros((2, 6)), np.zeros(6)),
    lambda: velprop(puma560(), [0, 0, 0, math.nan, 0, 0], np.zeros(6)),
    lambda: velprop(puma560(), np.zeros(6), [0, 0, 0, 0, 0, math.inf]),
    lambda: velprop(puma560(), np.zeros(6), np.zeros(6), v0=[0, 0]),
    lambda: velprop(puma560(), np.zeros(6), np.zeros(6), w0=[0, 0, math.nan]),
    lambda: velprop(puma560(), np.zeros(6), np.zeros(6), v0=np.zeros((2, 3))),
    lambda: velprop(puma560(), np.zeros(6), np.zeros(6), w0='abc'),
    lambda: velprop([[0, 0, 0]], [0.0], [0.0]),
])
def test_bad_input_raises(call):
    """Wrong sizes of q, qd, v0, w0 and NaN or inf anywhere are refused with ValueError."""
    with pytest.raises(ValueError):
        call()
