"""
Tests of robotica_kin.jacobian: jacobn, jacob0, manipulability (catalog 2.5, 2.6, 12.2).

References: the book's symbolic Jacobians (4.73)-(4.76) and (4.80) written out with sines and
cosines (catalog 2.6), velocity propagation for Ej. 4.7, and central differences of ``fkine``
(independent of both Jacobian routes); the single-configuration route (Pinocchio) and the batch
route (Paul's method in NumPy) are also checked against each other.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from reference_models import link_transform
from robotica_kin.dh import as_dh_model, dh_model
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import _paul_jacobians, jacob0, jacobn, manipulability
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560
from robotica_kin.transforms import rotvec, transl
from robotica_kin.velocity_propagation import velprop

H = 1e-6          # central-difference step [rad or m]
FD_TOL = 1e-8     # its truncation (~H²) and round-off (~1e-16 / H) error, with margin


def random_robot(rng, n=None, tool=True):
    """Return a random DH model: random n, sigma, geometry and (optionally) tool."""
    n = int(rng.integers(1, 8)) if n is None else n
    table = np.column_stack([
        rng.uniform(-math.pi, math.pi, n), rng.uniform(-1, 1, n),
        rng.uniform(-math.pi, math.pi, n), rng.uniform(-1, 1, n), rng.integers(0, 2, n)])
    pose = (transl(rng.uniform(-0.5, 0.5, 3)) @ rotvec(rng.normal(size=3), rng.uniform(-3, 3))
            if tool else None)
    return dh_model(table, name='random', tool=pose)


def blkdiag(R):
    """Return the 6×6 matrix diag(R, R)."""
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = R
    return out


def vex(S):
    """Return the vector of the skew-symmetric part of a 3×3 matrix."""
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


def jacob0_by_finite_differences(robot, q):
    """
    Return the base-frame Jacobian from central differences of fkine (independent reference).

    Linear rows: d p / d q_i; angular rows: the skew part of ``(R(q + h e_i) - R(q - h e_i))
    R^T / 2h``, i.e. ω with ``R' = S(ω) R``.
    """
    T = fkine(robot, q)
    J = np.zeros((6, robot.n))
    for i in range(robot.n):
        e = np.zeros(robot.n)
        e[i] = H
        plus, minus = fkine(robot, q + e), fkine(robot, q - e)
        J[:3, i] = (plus[:3, 3] - minus[:3, 3]) / (2 * H)
        J[3:, i] = vex((plus[:3, :3] - minus[:3, :3]) @ T[:3, :3].T / (2 * H))
    return J


def planar_rrr_table(l1, l2):
    """Return the raw HEMERO table of Ej. 4.1 (Table 4.2)."""
    return [[0, 0, 0, 0, 0], [0, l1, 0, 0, 0], [0, l2, 0, 0, 0]]


def test_ejemplo_4_5():
    """
    Ej. 4.5 (catalog 2.6): planar 3R, jacobn (4.75), jacob0 (4.76), the 2R ⁰J (4.73) and (4.74).

    Frame {3} sits at the end of link 2 and turns with θ3. (4.73) is the Jacobian of that
    point, frame {3}'s origin, for joints 1 and 2: rows x, y and columns 1, 2 of jacob0.
    """
    rng = np.random.default_rng(45)
    for _ in range(20):
        l1, l2 = rng.uniform(0.2, 5.0, 2)
        q = rng.uniform(-math.pi, math.pi, 3)
        s1, c1 = math.sin(q[0]), math.cos(q[0])
        s2 = math.sin(q[1])
        s3, c3 = math.sin(q[2]), math.cos(q[2])
        s12, c12 = math.sin(q[0] + q[1]), math.cos(q[0] + q[1])
        s23, c23 = math.sin(q[1] + q[2]), math.cos(q[1] + q[2])
        J3 = np.array([                                                     # (4.75)
            [l1 * s23 + l2 * s3, l2 * s3, 0.0],
            [l1 * c23 + l2 * c3, l2 * c3, 0.0],
            [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0]])
        J0 = np.array([                                                     # (4.76)
            [-(l1 * s1 + l2 * s12), -l2 * s12, 0.0],
            [l1 * c1 + l2 * c12, l2 * c12, 0.0],
            [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0]])
        J0_inv_2r = np.array([                                              # (4.74)
            [l2 * c12, l2 * s12],
            [-(l1 * c1 + l2 * c12), -(l1 * s1 + l2 * s12)]]) / (l1 * l2 * s2)
        for robot in (planar_rrr(l1, l2), planar_rrr_table(l1, l2)):
            np.testing.assert_allclose(jacobn(robot, q), J3, rtol=0, atol=1e-12)
            np.testing.assert_allclose(jacob0(robot, q), J0, rtol=0, atol=1e-12)
            J_2r = jacob0(robot, q)[:2, :2]                                 # (4.73)
            np.testing.assert_allclose(J_2r, J0[:2, :2], rtol=0, atol=1e-12)
            np.testing.assert_allclose(np.linalg.inv(J_2r), J0_inv_2r, rtol=1e-9, atol=1e-9)


def test_ejemplo_4_5_singular_at_stretched_and_folded():
    """Ej. 4.5: the 2R ⁰J is singular at θ2 = 0 (stretched) and θ2 = 180° (folded)."""
    for theta2 in (0.0, math.pi):
        J = jacob0(planar_rrr(4.0, 3.0), [0.7, theta2, -0.2])[:2, :2]
        assert abs(np.linalg.det(J)) < 1e-12
    assert abs(np.linalg.det(jacob0(planar_rrr(4.0, 3.0), [0.7, 1.0, -0.2])[:2, :2])) > 1.0


def test_ejemplo_4_6():
    """Ej. 4.6 (catalog 2.6): jacobn of the R-P-R robot equals (4.80)."""
    rng = np.random.default_rng(46)
    for _ in range(20):
        l2 = rng.uniform(0.05, 2.0)
        t1, d2, t3 = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 1.0), rng.uniform(-3, 3)
        s3, c3 = math.sin(t3), math.cos(t3)
        expected = np.array([
            [c3 * (l2 + d2), 0.0, 0.0],
            [-s3 * (l2 + d2), 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [s3, 0.0, 0.0],
            [c3, 0.0, 0.0],
            [0.0, 0.0, 1.0]])
        table = [[0, 0, 0, 0, 0], [math.pi / 2, 0, 0, 0, 1], [0, 0, 0, l2, 0]]
        for robot in (table, cylindrical_rpr(l2)):
            np.testing.assert_allclose(jacobn(robot, [t1, d2, t3]), expected, rtol=0, atol=1e-12)


# Ej. 4.7: the symbolic PUMA table of the book, with Craig's PUMA 560 dimensions [m] for
# a2, a3, d3, d4 (the book prints no numbers).
A2, A3, D3, D4 = 0.4318, 0.0203, 0.15005, 0.4318
PUMA_EJ_4_7 = [
    [0, 0, 0, 0, 0],
    [-math.pi / 2, 0, 0, 0, 0],
    [0, A2, 0, D3, 0],
    [-math.pi / 2, A3, 0, D4, 0],
    [math.pi / 2, 0, 0, 0, 0],
    [-math.pi / 2, 0, 0, 0, 0],
]


def geometric_jacobians(table, q):
    """
    Return ``(⁰J, ⁶J)`` of an all-revolute table, built here from its link frames (reference).

    Frames {1} … {n} by the product of Craig's link transforms (4.5) (``reference_models``);
    column i of ⁰J is ``[z_i × (p_n - p_i); z_i]`` (joint i turns about Z_i of frame {i}), and
    ⁶J is ⁰J with both halves in frame {n}: no robotica code is involved.
    """
    T = np.eye(4)
    frames = []
    for (alpha, a, _, d, _), theta in zip(table, q):
        T = T @ link_transform(alpha, a, theta, d)
        frames.append(T)
    p_n, R_n = frames[-1][:3, 3], frames[-1][:3, :3]
    J_0 = np.array([np.concatenate([np.cross(F[:3, 2], p_n - F[:3, 3]), F[:3, 2]])
                    for F in frames]).T
    return J_0, blkdiag(R_n.T) @ J_0


@pytest.mark.parametrize('robot', [puma560(), PUMA_EJ_4_7], ids=['dhp560', 'ej_4_7'])
def test_ejemplo_4_7(robot):
    """
    Ej. 4.7 (catalog 2.6): the PUMA 560's Jacobian by velprop and jacobn, and jacob0.

    The book computes it both ways and prints no numbers; the reference is the geometric
    Jacobian of the table's own link frames, computed in this test. Column i of the tool-frame
    Jacobian is velprop with ``qd = e_i`` (4.77).
    """
    table = as_dh_model(robot).table
    rng = np.random.default_rng(47)
    for _ in range(10):
        q = rng.uniform(-math.pi, math.pi, 6)
        J_0, J_n = geometric_jacobians(table, q)
        by_velprop = np.column_stack([velprop(robot, q, e) for e in np.eye(6)])
        np.testing.assert_allclose(by_velprop, J_n, rtol=0, atol=1e-12)
        np.testing.assert_allclose(jacobn(robot, q), J_n, rtol=0, atol=1e-12)
        np.testing.assert_allclose(jacob0(robot, q), J_0, rtol=0, atol=1e-12)


ROBOTS = [puma560(), planar_rr(0.7, 0.4), planar_rrr(1.0, 0.8, 0.3), cylindrical_rpr(0.3)]


@pytest.mark.parametrize('robot', ROBOTS, ids=lambda r: r.name)
def test_jacobians_match_finite_differences(robot):
    """jacob0 vs central differences of fkine; jacobn vs the same rotated into the tool frame."""
    rng = np.random.default_rng(11)
    Q = rng.uniform(0.05, 1.0, (8, robot.n))
    for q in Q:
        J_fd = jacob0_by_finite_differences(robot, q)
        R = fkine(robot, q)[:3, :3]
        np.testing.assert_allclose(jacob0(robot, q), J_fd, rtol=0, atol=FD_TOL)
        np.testing.assert_allclose(jacobn(robot, q), blkdiag(R.T) @ J_fd, rtol=0, atol=FD_TOL)
    np.testing.assert_allclose(
        jacob0(robot, Q), np.stack([jacob0_by_finite_differences(robot, q) for q in Q]),
        rtol=0, atol=FD_TOL)


def test_random_robots_match_finite_differences():
    """Random DH tables (random σ, geometry, tool): both routes agree with fkine's differences."""
    rng = np.random.default_rng(12)
    for _ in range(25):
        robot = random_robot(rng)
        Q = rng.uniform(-math.pi, math.pi, (3, robot.n))
        J_0 = jacob0(robot, Q)
        J_n = jacobn(robot, Q)
        for k, q in enumerate(Q):
            J_fd = jacob0_by_finite_differences(robot, q)
            R = fkine(robot, q)[:3, :3]
            np.testing.assert_allclose(jacob0(robot, q), J_fd, rtol=0, atol=FD_TOL)
            np.testing.assert_allclose(J_0[k], J_fd, rtol=0, atol=FD_TOL)
            np.testing.assert_allclose(J_n[k], blkdiag(R.T) @ J_fd, rtol=0, atol=FD_TOL)


@given(st.integers(min_value=0, max_value=2**32 - 1))
@settings(max_examples=30, deadline=None)
def test_pinocchio_and_paul_routes_agree(seed):
    """An arm's route (Pinocchio LOCAL / LOCAL_WORLD_ALIGNED) equals Paul's method to 1e-12."""
    rng = np.random.default_rng(seed)
    robot = random_robot(rng, tool=bool(rng.integers(0, 2)))
    arm = pinocchio_arm(robot)
    data = arm.model.createData()
    q = rng.uniform(-math.pi, math.pi, robot.n)
    J_n, R = _paul_jacobians(robot, q[np.newaxis])
    np.testing.assert_allclose(jacobn(arm, q, data=data), J_n[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(jacob0(arm, q, data=data), blkdiag(R[0]) @ J_n[0], rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(jacobn(robot, q), J_n[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(R[0], fkine(robot, q)[:3, :3], rtol=0, atol=1e-12)


@pytest.mark.parametrize('robot', ROBOTS, ids=lambda r: r.name)
def test_batch_equals_loop(robot):
    """(m, n) in gives (m, 6, n) out, equal to m single calls of an arm (the two routes)."""
    Q = np.random.default_rng(13).uniform(-math.pi, math.pi, (7, robot.n))
    arm = pinocchio_arm(robot)
    for fn in (jacobn, jacob0):
        batch = fn(robot, Q)
        assert batch.shape == (7, 6, robot.n)
        np.testing.assert_allclose(batch, np.stack([fn(arm, q) for q in Q]), rtol=0,
                                   atol=1e-12)
        np.testing.assert_allclose(fn(arm, Q), batch, rtol=0, atol=0)
        assert fn(robot, Q[:1]).shape == (1, 6, robot.n)
        assert fn(robot, Q[0]).shape == (6, robot.n)


def test_prismatic_and_tool_columns():
    """Closed forms: a prismatic joint moves along its Z; a tool offset adds ω × p (4.51)."""
    t1 = 0.4    # (4.23): the origin of {2} is (d2 s1, -d2 c1, 0), so d p / d d2 = (s1, -c1, 0)
    J = jacob0(cylindrical_rpr(0.2), [t1, 0.5, 0.0])
    np.testing.assert_allclose(J[:, 1], [math.sin(t1), -math.cos(t1), 0, 0, 0, 0], atol=1e-15)
    # planar 2R with tool at l2: the tip's velocity for joint 2 is l2 along the link normal.
    J = jacob0(planar_rr(4.0, 3.0), [0.0, math.pi / 2])
    np.testing.assert_allclose(J[:, 1], [-3, 0, 0, 0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(J[:, 0], [-3, 4, 0, 0, 0, 1], atol=1e-12)


def test_manipulability():
    """Yoshikawa's w: l1 l2 |s2| for planar arms (det of (4.73)); sqrt(det(J Jᵀ)) for the PUMA."""
    rng = np.random.default_rng(14)
    for _ in range(10):
        l1, l2 = rng.uniform(0.2, 3.0, 2)
        q = rng.uniform(-math.pi, math.pi, 3)
        expected = l1 * l2 * abs(math.sin(q[1]))
        assert manipulability(planar_rr(l1, l2), q[:2], mask=[1, 1, 0, 0, 0, 0]) == \
            pytest.approx(expected, abs=1e-12)
        assert manipulability(planar_rrr(l1, l2), q, mask=[1, 1, 0, 0, 0, 1]) == \
            pytest.approx(expected, abs=1e-12)
    robot = puma560()
    Q = rng.uniform(-math.pi, math.pi, (5, 6))
    w = manipulability(robot, Q)
    assert w.shape == (5,)
    yoshikawa = [math.sqrt(np.linalg.det(J @ J.T)) for J in (jacob0(robot, q) for q in Q)]
    np.testing.assert_allclose(w, yoshikawa, rtol=1e-9, atol=0)
    wrist_flat = Q[0].copy()
    wrist_flat[4] = 0.0      # θ5 = 0: axes 4 and 6 aligned (book §4.6)
    assert manipulability(robot, wrist_flat) < 1e-12 < manipulability(robot, Q[0])
    assert manipulability(pinocchio_arm(robot), Q[0]) == pytest.approx(w[0], rel=1e-9)


@pytest.mark.parametrize('call', [
    lambda: jacobn(puma560(), np.zeros(5)),
    lambda: jacob0(puma560(), np.zeros(7)),
    lambda: jacobn(puma560(), np.zeros((2, 5))),
    lambda: jacob0(puma560(), np.zeros((2, 2, 6))),
    lambda: jacobn(puma560(), [0, 0, math.nan, 0, 0, 0]),
    lambda: jacob0(puma560(), [[0, 0, 0, 0, 0, math.inf]]),
    lambda: jacobn([[0, 0, 0]], [0.0]),
    lambda: jacob0([[0, 0, 0, math.nan]], [0.0]),
    lambda: manipulability(planar_rr(), [0.1, 0.2]),              # 6 rows, 2 joints
    lambda: manipulability(planar_rr(), [0.1, 0.2], mask=[1, 1, 1, 0, 0, 0]),
    lambda: manipulability(puma560(), np.zeros(6), mask=[0] * 6),
    lambda: manipulability(puma560(), np.zeros(6), mask=[2, 1, 1, 1, 1, 1]),
    lambda: manipulability(puma560(), np.zeros(6), mask=[1, 1, 1]),
    lambda: manipulability(puma560(), [math.nan] * 6),
])
def test_bad_input_raises(call):
    """Wrong q sizes, NaN or inf, bad tables and bad masks are refused with ValueError."""
    with pytest.raises(ValueError):
        call()
