"""
Tests of robotica_kin.differential_motion: tr2diff, diff2tr, tr2jac (catalog 12.2, [H] §3).

References are the matrix (3.5) written out entry by entry (with the skew-symmetric ``-δx``
where [H] (3.6)/(3.24) misprint ``+δx``, catalog Part 17), exact constructions of small and
finite motions from rotvec/transl, and rigid-body motions integrated with scipy's matrix
exponential and differentiated numerically; never the code under test.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.differential_motion import diff2tr, tr2diff, tr2jac
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.robots import cylindrical_rpr, puma560
from robotica_kin.transforms import rotvec, transl, trinv
from scipy.linalg import expm

FINITE = st.floats(min_value=-2.0, max_value=2.0, allow_nan=False)
VECTOR3 = st.tuples(FINITE, FINITE, FINITE)
AXIS = VECTOR3.filter(lambda v: math.hypot(*v) > 1e-2)


def random_pose(rng):
    """Return a random homogeneous transform (axis-angle rotation, translation in [-2, 2] m)."""
    rotation = rotvec(rng.normal(size=3), rng.uniform(-math.pi, math.pi))
    return transl(rng.uniform(-2, 2, 3)) @ rotation


def twist_matrix(v, w):
    """Return the 4×4 matrix [[S(w), v], [0, 0]] of a rigid-body velocity (v at the origin)."""
    wx, wy, wz = w
    return np.array([[0.0, -wz, wy, v[0]], [wz, 0.0, -wx, v[1]], [-wy, wx, 0.0, v[2]],
                     [0.0, 0.0, 0.0, 0.0]])


def vex(S):
    """Return the vector of the skew-symmetric part of a 3×3 matrix."""
    return 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])


@given(VECTOR3, VECTOR3)
@settings(max_examples=30, deadline=None)
def test_diff2tr_is_matrix_3_5(d, delta):
    """diff2tr gives (3.5) entry by entry, skew-symmetric (-δx at row 2, column 3)."""
    dx, dy, dz = d
    ddx, ddy, ddz = delta
    expected = np.array([
        [0.0, -ddz, ddy, dx],
        [ddz, 0.0, -ddx, dy],
        [-ddy, ddx, 0.0, dz],
        [0.0, 0.0, 0.0, 0.0]])
    Delta = diff2tr([dx, dy, dz, ddx, ddy, ddz])
    np.testing.assert_array_equal(Delta, expected)
    np.testing.assert_array_equal(Delta[:3, :3], -Delta[:3, :3].T)


@given(VECTOR3, VECTOR3)
@settings(max_examples=30, deadline=None)
def test_round_trip(d, delta):
    """tr2diff(diff2tr(D)) = D, and diff2tr(tr2diff(Δ)) = Δ for a matrix of the form (3.5)."""
    D = np.array(d + delta)
    np.testing.assert_allclose(tr2diff(diff2tr(D)), D, rtol=0, atol=1e-15)
    Delta = diff2tr(D)
    np.testing.assert_allclose(diff2tr(tr2diff(Delta)), Delta, rtol=0, atol=1e-15)


def test_tr2diff_one_argument_takes_the_mean_of_the_two_entries():
    """Each δ is the mean of its two entries of a matrix that is only roughly skew ([H] §3)."""
    M = np.zeros((4, 4))
    M[:3, 3] = [0.1, -0.2, 0.3]
    M[2, 1], M[1, 2] = 0.30, -0.10      # δx = (0.30 + 0.10) / 2
    M[0, 2], M[2, 0] = 0.05, -0.15      # δy = (0.05 + 0.15) / 2
    M[1, 0], M[0, 1] = -0.40, 0.20      # δz = (-0.40 - 0.20) / 2
    M[0, 0] = M[1, 1] = 1e-3            # diagonal terms of a finite difference are ignored
    np.testing.assert_allclose(tr2diff(M), [0.1, -0.2, 0.3, 0.2, 0.1, -0.3], rtol=0, atol=1e-15)


def test_tr2diff_two_arguments_exact_motion_about_the_origin_of_t1():
    """
    (3.25)-(3.26): T2 = T1 turned by ε about k through the origin of T1, then shifted by d.

    Built as ``T2 = transl(p1 + d) rotvec(k, ε) transl(-p1) T1``, so that p2 = p1 + d and
    R2 = Rot(k, ε) R1 (k and d in the reference frame). Then ``½ Σ r1 × r2 = sin(ε) k`` for
    every ε, so tr2diff gives ``[d; sin(ε) k]`` exactly, not only to first order.
    """
    rng = np.random.default_rng(3)
    for _ in range(50):
        T1 = random_pose(rng)
        p1 = T1[:3, 3]
        d = rng.uniform(-1, 1, 3)
        k = rng.normal(size=3)
        k /= np.linalg.norm(k)
        eps = rng.uniform(-3.0, 3.0)
        T2 = transl(p1 + d) @ rotvec(k, eps) @ transl(-p1) @ T1
        np.testing.assert_allclose(tr2diff(T1, T2), np.concatenate([d, math.sin(eps) * k]),
                                   rtol=0, atol=1e-12)


def test_tr2diff_two_arguments_motion_about_the_reference_origin():
    """
    T2 = transl(d) rotvec(k, ε) T1 turns T1 about the reference frame's origin, not its own.

    Its origin then moves by ``d + (Rot(k, ε) - I) p1``, which is what tr2diff reports as the
    translation (the displacement of the origin of T1); the rotation is still sin(ε) k.
    """
    rng = np.random.default_rng(4)
    for _ in range(20):
        T1 = random_pose(rng)
        d = rng.uniform(-1, 1, 3)
        k = rng.normal(size=3)
        k /= np.linalg.norm(k)
        eps = rng.uniform(-0.5, 0.5)
        Rk = rotvec(k, eps)
        T2 = transl(d) @ Rk @ T1
        expected = np.concatenate([d + (Rk[:3, :3] - np.eye(3)) @ T1[:3, 3], math.sin(eps) * k])
        np.testing.assert_allclose(tr2diff(T1, T2), expected, rtol=0, atol=1e-12)


def test_one_and_two_argument_forms_to_first_order():
    """
    For a small motion, tr2diff((T2 - T1) T1^-1) is Paul's Δ (dT = Δ T, (3.1)).

    Its translation is the motion of the point at the reference origin, ``(p2 - p1) - δ × p1``,
    and its rotation the two-argument form's δ, both to O(ε²).
    """
    rng = np.random.default_rng(5)
    for _ in range(20):
        T1 = random_pose(rng)
        D = 1e-6 * rng.uniform(-1, 1, 6)
        p1 = T1[:3, 3]
        T2 = transl(p1 + D[:3]) @ rotvec(D[3:], np.linalg.norm(D[3:])) @ transl(-p1) @ T1
        two = tr2diff(T1, T2)
        one = tr2diff((T2 - T1) @ trinv(T1))
        np.testing.assert_allclose(two, D, rtol=0, atol=1e-15)
        np.testing.assert_allclose(one[3:], two[3:], rtol=0, atol=1e-11)
        np.testing.assert_allclose(one[:3], two[:3] - np.cross(two[3:], T1[:3, 3]), rtol=0,
                                   atol=1e-11)


@pytest.mark.parametrize('robot', [puma560(), cylindrical_rpr()], ids=lambda r: r.name)
def test_tr2diff_matches_jacob0(robot):
    """tr2diff between fkine at q and at q + h dq is jacob0 dq h to O(h²): the ikine error."""
    rng = np.random.default_rng(6)
    h = 1e-6
    for _ in range(10):
        q = rng.uniform(0.1, 1.0, robot.n)
        dq = rng.uniform(-1, 1, robot.n)
        D = tr2diff(fkine(robot, q - h * dq), fkine(robot, q + h * dq)) / (2 * h)
        np.testing.assert_allclose(D, jacob0(robot, q) @ dq, rtol=0, atol=1e-8)


def test_tr2jac_against_a_rigid_body_moving_by_hand():
    """
    tr2jac(T_A_B) turns a body's velocity at the origin of {A} into the one at the origin of {B}.

    The body moves as ``T_A_B(t) = expm(t ξ) T_A_B`` (scipy), ξ = [[S(ω), v], [0, 0]] the
    twist in {A}; central differences of the origin of {B} and of its rotation give its
    velocity, which is then expressed in the axes of {B} at t = 0.
    """
    rng = np.random.default_rng(7)
    h = 1e-6
    for _ in range(20):
        T = random_pose(rng)
        v, w = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
        xi = twist_matrix(v, w)
        plus, minus = expm(h * xi) @ T, expm(-h * xi) @ T
        R = T[:3, :3]
        v_b = R.T @ (plus[:3, 3] - minus[:3, 3]) / (2 * h)
        w_b = R.T @ vex((plus[:3, :3] - minus[:3, :3]) @ R.T / (2 * h))
        np.testing.assert_allclose(tr2jac(T) @ np.concatenate([v, w]),
                                   np.concatenate([v_b, w_b]), rtol=0, atol=1e-8)


def test_tr2jac_transforms_differential_matrices():
    """Paul's change of frame of a differential motion: diff2tr(J D) = T^-1 diff2tr(D) T."""
    rng = np.random.default_rng(8)
    for _ in range(20):
        T = random_pose(rng)
        D = rng.uniform(-1, 1, 6)
        np.testing.assert_allclose(diff2tr(tr2jac(T) @ D), trinv(T) @ diff2tr(D) @ T, rtol=0,
                                   atol=1e-12)


def test_tr2jac_pure_translation_and_rotation():
    """Closed cases: a translation only moves the point (ω × p); a rotation only re-expresses."""
    J = tr2jac(transl(1, 2, 3))
    np.testing.assert_array_equal(J[:3, :3], np.eye(3))
    np.testing.assert_allclose(J @ [0, 0, 0, 1, 0, 0], [0, -3, 2, 1, 0, 0], atol=1e-15)
    J = tr2jac(rotvec([0, 0, 1], math.pi / 2))
    np.testing.assert_allclose(J @ [1, 0, 0, 0, 0, 1], [0, -1, 0, 0, 0, 1], atol=1e-15)


@pytest.mark.parametrize('call', [
    lambda: diff2tr([0.0] * 5),
    lambda: diff2tr([0.0, 0.0, 0.0, 0.0, 0.0, math.nan]),
    lambda: diff2tr('abcdef'),
    lambda: tr2diff(np.eye(3)),
    lambda: tr2diff(np.eye(4)),                                   # a pose, not Δ
    lambda: tr2diff(np.full((4, 4), math.nan)),
    lambda: tr2diff(np.eye(4), np.diag([1.0, 1.0, 1.0, 2.0])),   # last row
    lambda: tr2diff(np.diag([2.0, 1.0, 1.0, 1.0]), np.eye(4)),   # not orthonormal
    lambda: tr2diff(np.eye(4), np.eye(3)),
    lambda: tr2diff(np.eye(4), np.full((4, 4), math.inf)),
    lambda: tr2jac(np.diag([1.0, 1.0, 3.0, 1.0])),
    lambda: tr2jac(np.zeros((4, 4))),
    lambda: tr2jac(np.eye(6)),
])
def test_bad_input_raises(call):
    """Wrong shapes, NaN or inf, non-homogeneous poses and a pose given as Δ are refused."""
    with pytest.raises(ValueError):
        call()
