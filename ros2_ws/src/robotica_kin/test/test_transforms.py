"""
Tests of robotica_kin.transforms: homogeneous transforms of chapter 3 (catalog 1, 12.1).

Reference values are the book's printed examples (Ejemplo 3.3, 3.4), the book's matrices
(3.26), (3.56), (3.69) written out entry by entry, the quaternion's defining formula of
fig. 3.20, or independent computations (np.linalg.inv); never the code under test.
"""

import math
import re

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.transforms import (
    angvec2tr, eul2tr, ishomog, q2tr, rotvec, rotx, roty, rotz, rpy2tr, tr2angvec, tr2eul,
    tr2q, tr2rpy, transl, trinv,
)
from scipy.spatial.transform import Rotation

ANGLES = st.floats(min_value=-10.0, max_value=10.0, allow_nan=False)
LENGTHS = st.floats(min_value=-100.0, max_value=100.0, allow_nan=False)
AXES = st.tuples(
    st.floats(min_value=-1.0, max_value=1.0, allow_nan=False),
    st.floats(min_value=-1.0, max_value=1.0, allow_nan=False),
    st.floats(min_value=-1.0, max_value=1.0, allow_nan=False),
).filter(lambda v: math.hypot(*v) > 1e-3)

# Ejemplo 3.3, (3.29)-(3.30): the point P1 = [0, 2, 0] in {A} and the robot's pose.
P1 = np.array([0.0, 2.0, 0.0, 1.0])
ROT_Z_20_PRINTED = np.array([
    [0.940, -0.342, 0.0, 0.0],
    [0.342, 0.940, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
])
T_A_B_PRINTED = np.array([  # (3.30)
    [0.940, -0.342, 0.0, 8.0],
    [0.342, 0.940, 0.0, 4.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
])
# Ejemplo 3.4, (3.36): the inverse of (3.30).
T_B_A_PRINTED = np.array([
    [0.940, 0.342, 0.0, -8.886],
    [-0.342, 0.940, 0.0, -1.023],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
])


def random_transform(axis, angle, p):
    """Return a transform built from an axis-angle rotation and a translation."""
    return transl(p) @ rotvec(axis, angle)


def with_rounding_noise(T):
    """
    Return T after a rotation there and back: the same T with ~1e-16 absolute noise.

    A matrix built directly from angles carries only relative rounding errors in its small
    entries, which hides ill-conditioned formulas; real transforms (products) do not.
    """
    axis = [0.3, -0.5, 0.8]
    return rotvec(axis, 1.0) @ rotvec(axis, -1.0) @ T


def rot_k_theta(k, theta):
    """Return Rot(K̂, θ) written out entry by entry (Craig's form of (3.25), v = 1 - cos θ)."""
    kx, ky, kz = np.asarray(k, dtype=float) / np.linalg.norm(k)
    c, s = math.cos(theta), math.sin(theta)
    v = 1.0 - c
    return np.array([
        [kx * kx * v + c, kx * ky * v - kz * s, kx * kz * v + ky * s],
        [kx * ky * v + kz * s, ky * ky * v + c, ky * kz * v - kx * s],
        [kx * kz * v - ky * s, ky * kz * v + kx * s, kz * kz * v + c],
    ])


# --- Book examples ---------------------------------------------------------------------------

def test_ejemplo_3_3_rotation_of_a_point_by_20_degrees_about_z():
    np.testing.assert_allclose(rotz(math.pi / 9) @ P1, [-0.684, 1.879, 0.0, 1.0], atol=5e-4)


def test_ejemplo_3_3_rotz_equals_the_printed_matrix():
    np.testing.assert_allclose(rotz(math.pi / 9), ROT_Z_20_PRINTED, atol=5e-4)


def test_ejemplo_3_3_robot_transform_equals_printed_3_30_and_moves_the_point():
    T_a_b = transl(8, 4, 0) @ rotz(math.pi / 9)
    np.testing.assert_allclose(T_a_b, T_A_B_PRINTED, atol=5e-4)
    # Not printed in the book: derived by hand, 8 - 2 sin 20° = 7.316, 4 + 2 cos 20° = 5.879.
    np.testing.assert_allclose(T_a_b @ P1, [7.316, 5.879, 0.0, 1.0], atol=5e-4)


def test_ejemplo_3_4_trinv_equals_printed_3_36():
    T_b_a = trinv(transl(8, 4, 0) @ rotz(math.pi / 9))
    np.testing.assert_allclose(T_b_a, T_B_A_PRINTED, atol=5e-4)


def test_ejemplo_3_4_trinv_equals_general_matrix_inverse():
    T_a_b = transl(8, 4, 0) @ rotz(math.pi / 9)
    np.testing.assert_allclose(trinv(T_a_b), np.linalg.inv(T_a_b), atol=1e-12)


# --- Elementary transforms -------------------------------------------------------------------

def test_transl_of_three_scalars_is_the_translation_operator_3_23():
    expected = np.array([
        [1.0, 0.0, 0.0, 1.5],
        [0.0, 1.0, 0.0, -2.0],
        [0.0, 0.0, 1.0, 3.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
    result = transl(1.5, -2, 3)
    assert result.dtype == np.float64
    np.testing.assert_array_equal(result, expected)
    np.testing.assert_array_equal(transl([1.5, -2, 3]), expected)
    np.testing.assert_array_equal(transl(np.array([1.5, -2.0, 3.0])), expected)


def test_transl_of_a_transform_returns_its_translation_vector():
    T = transl(1.0, 2.0, 3.0) @ rotx(0.7)
    p = transl(T)
    assert p.shape == (3,)
    assert p.dtype == np.float64
    np.testing.assert_array_equal(p, [1.0, 2.0, 3.0])
    p[0] = 99.0  # a copy, not a view into T
    assert T[0, 3] == 1.0


@pytest.mark.parametrize('theta', [-2.5, -0.3, 0.0, 0.4, math.pi / 9, 3.0])
def test_rotations_about_the_axes_match_the_written_out_matrices_3_26(theta):
    c, s = math.cos(theta), math.sin(theta)
    expected_x = [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]]
    expected_y = [[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]]
    expected_z = [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    np.testing.assert_allclose(rotx(theta), expected_x, atol=1e-15)
    np.testing.assert_allclose(roty(theta), expected_y, atol=1e-15)
    np.testing.assert_allclose(rotz(theta), expected_z, atol=1e-15)


def test_rotations_return_float64_4x4_for_integer_angles():
    for rotation in (rotx, roty, rotz):
        result = rotation(1)
        assert result.shape == (4, 4)
        assert result.dtype == np.float64


def test_rotvec_matches_the_written_out_axis_angle_matrix():
    rng = np.random.default_rng(20240531)
    for _ in range(50):
        k = rng.normal(size=3) * rng.uniform(0.01, 10.0)
        theta = rng.uniform(-10.0, 10.0)
        T = rotvec(k, theta)
        np.testing.assert_allclose(T[:3, :3], rot_k_theta(k, theta), atol=1e-14)
        np.testing.assert_array_equal(T[3], [0.0, 0.0, 0.0, 1.0])
        np.testing.assert_array_equal(T[:3, 3], [0.0, 0.0, 0.0])


@given(ANGLES)
def test_rotx_roty_rotz_equal_rotvec_about_the_unit_axes(theta):
    np.testing.assert_allclose(rotx(theta), rotvec([1, 0, 0], theta), atol=1e-15)
    np.testing.assert_allclose(roty(theta), rotvec([0, 1, 0], theta), atol=1e-15)
    np.testing.assert_allclose(rotz(theta), rotvec([0, 0, 1], theta), atol=1e-15)
    np.testing.assert_allclose(rotz(theta), rotvec([0, 0, 7.5], theta), atol=1e-15)


@given(AXES, ANGLES)
def test_angvec2tr_is_rotvec_with_the_arguments_swapped(axis, theta):
    np.testing.assert_array_equal(angvec2tr(theta, axis), rotvec(axis, theta))


# --- Inverse ---------------------------------------------------------------------------------

@given(AXES, ANGLES, st.tuples(LENGTHS, LENGTHS, LENGTHS))
def test_trinv_times_transform_is_identity(axis, angle, p):
    T = random_transform(axis, angle, p)
    np.testing.assert_allclose(trinv(T) @ T, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(T @ trinv(T), np.eye(4), atol=1e-12)


def test_trinv_rejects_a_wrong_last_row():
    T = transl(1, 2, 3)
    T[3] = [0.0, 0.0, 1.0, 1.0]
    with pytest.raises(ValueError, match=r'trinv: T is not a homogeneous transform'):
        trinv(T)


def test_trinv_rejects_a_rotation_block_that_is_not_orthonormal():
    with pytest.raises(ValueError, match=r'trinv: the rotation block of T is not orthonormal'):
        trinv(np.diag([2.0, 1.0, 1.0, 1.0]))
    # The book's matrix typed with 3 printed digits is not a rotation (0.940² + 0.342² ≠ 1).
    with pytest.raises(ValueError, match=r'not orthonormal'):
        trinv(T_A_B_PRINTED)


# --- RPY angles ------------------------------------------------------------------------------

def test_rpy2tr_matches_the_book_matrix_3_56_entry_by_entry():
    rng = np.random.default_rng(356)
    for _ in range(50):
        g, b, a = rng.uniform(-math.pi, math.pi, size=3)  # roll γ, pitch β, yaw α
        ca, sa = math.cos(a), math.sin(a)
        cb, sb = math.cos(b), math.sin(b)
        cg, sg = math.cos(g), math.sin(g)
        expected = np.array([
            [ca * cb, ca * sb * sg - sa * cg, ca * sb * cg + sa * sg, 0.0],
            [sa * cb, sa * sb * sg + ca * cg, sa * sb * cg - ca * sg, 0.0],
            [-sb, cb * sg, cb * cg, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
        np.testing.assert_allclose(rpy2tr(g, b, a), expected, atol=1e-15)
        np.testing.assert_allclose(rpy2tr([g, b, a]), expected, atol=1e-15)


@given(ANGLES, ANGLES, ANGLES)
def test_rpy2tr_agrees_with_scipy_extrinsic_xyz(roll, pitch, yaw):
    expected = Rotation.from_euler('xyz', [roll, pitch, yaw]).as_matrix()
    np.testing.assert_allclose(rpy2tr(roll, pitch, yaw)[:3, :3], expected, atol=1e-12)


@given(AXES, ANGLES)
def test_tr2rpy_round_trip_reproduces_the_rotation_and_pitch_is_in_range(axis, angle):
    T = rotvec(axis, angle)
    rpy = tr2rpy(T)
    assert rpy.shape == (3,)
    assert rpy.dtype == np.float64
    roll, pitch, yaw = rpy
    assert -math.pi / 2 <= pitch <= math.pi / 2
    assert -math.pi <= roll <= math.pi
    assert -math.pi <= yaw <= math.pi
    np.testing.assert_allclose(rpy2tr(roll, pitch, yaw), T, atol=1e-12)


@given(
    st.floats(min_value=-3.1, max_value=3.1),
    st.floats(min_value=-1.5, max_value=1.5),
    st.floats(min_value=-3.1, max_value=3.1),
)
def test_tr2rpy_returns_the_angles_inside_the_principal_range(roll, pitch, yaw):
    np.testing.assert_allclose(tr2rpy(rpy2tr(roll, pitch, yaw)), [roll, pitch, yaw],
                               atol=1e-12)


@pytest.mark.parametrize('pitch', [math.pi / 2, -math.pi / 2])
@pytest.mark.parametrize(('roll', 'yaw'), [(0.0, 0.0), (0.3, -1.2), (-2.0, 2.5), (3.0, 1.0)])
def test_tr2rpy_degenerate_pitch_returns_zero_yaw_and_reproduces_the_rotation(
        pitch, roll, yaw):
    T = rpy2tr(roll, pitch, yaw)
    r_roll, r_pitch, r_yaw = tr2rpy(T)
    assert r_yaw == 0.0
    assert r_pitch == pytest.approx(pitch, abs=1e-15)
    np.testing.assert_allclose(rpy2tr(r_roll, r_pitch, r_yaw), T, atol=1e-12)
    # (3.63)-(3.64) with α = 0: only γ - α (β = +90°) or γ + α (β = -90°) is defined.
    expected_roll = roll - yaw if pitch > 0.0 else roll + yaw
    assert math.cos(r_roll) == pytest.approx(math.cos(expected_roll), abs=1e-12)
    assert math.sin(r_roll) == pytest.approx(math.sin(expected_roll), abs=1e-12)


@pytest.mark.parametrize('offset', [1e-4, 1e-7, 1e-9, 2e-12, 1e-13, -1e-9, -1e-13])
def test_tr2rpy_round_trip_stays_accurate_next_to_pitch_90_degrees(offset):
    # With γ = atan2(r32, r33) evaluated literally the error grows like 1e-16 / cos β.
    for pitch in (math.pi / 2 - offset, -math.pi / 2 + offset):
        T = with_rounding_noise(rpy2tr(0.7, pitch, -1.9))
        np.testing.assert_allclose(rpy2tr(tr2rpy(T)), T, atol=1e-12)


# --- Z-Y-Z Euler angles ----------------------------------------------------------------------

def test_eul2tr_matches_the_book_matrix_3_69_entry_by_entry():
    rng = np.random.default_rng(369)
    for _ in range(50):
        a, b, g = rng.uniform(-math.pi, math.pi, size=3)
        ca, sa = math.cos(a), math.sin(a)
        cb, sb = math.cos(b), math.sin(b)
        cg, sg = math.cos(g), math.sin(g)
        expected = np.array([
            [ca * cb * cg - sa * sg, -ca * cb * sg - sa * cg, ca * sb, 0.0],
            [sa * cb * cg + ca * sg, -sa * cb * sg + ca * cg, sa * sb, 0.0],
            [-sb * cg, sb * sg, cb, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
        np.testing.assert_allclose(eul2tr(a, b, g), expected, atol=1e-15)
        np.testing.assert_allclose(eul2tr([a, b, g]), expected, atol=1e-15)


@given(ANGLES, ANGLES, ANGLES)
def test_eul2tr_agrees_with_scipy_intrinsic_zyz(alpha, beta, gamma):
    expected = Rotation.from_euler('ZYZ', [alpha, beta, gamma]).as_matrix()
    np.testing.assert_allclose(eul2tr(alpha, beta, gamma)[:3, :3], expected, atol=1e-12)


@given(AXES, ANGLES)
def test_tr2eul_round_trip_reproduces_the_rotation_and_beta_is_in_range(axis, angle):
    T = rotvec(axis, angle)
    eul = tr2eul(T)
    assert eul.shape == (3,)
    assert eul.dtype == np.float64
    alpha, beta, gamma = eul
    assert 0.0 <= beta <= math.pi
    assert -math.pi <= alpha <= math.pi
    assert -math.pi <= gamma <= math.pi
    np.testing.assert_allclose(eul2tr(alpha, beta, gamma), T, atol=1e-12)


@given(
    st.floats(min_value=-3.1, max_value=3.1),
    st.floats(min_value=0.05, max_value=3.1),
    st.floats(min_value=-3.1, max_value=3.1),
)
def test_tr2eul_returns_the_angles_inside_the_principal_range(alpha, beta, gamma):
    np.testing.assert_allclose(tr2eul(eul2tr(alpha, beta, gamma)), [alpha, beta, gamma],
                               atol=1e-12)


@pytest.mark.parametrize(('alpha', 'gamma'), [(0.0, 0.0), (0.3, -1.2), (-2.0, 2.5), (3.0, 1.0)])
def test_tr2eul_degenerate_beta_zero_returns_zero_alpha(alpha, gamma):
    T = eul2tr(alpha, 0.0, gamma)
    r_alpha, r_beta, r_gamma = tr2eul(T)
    assert r_alpha == 0.0
    assert r_beta == 0.0
    np.testing.assert_allclose(eul2tr(r_alpha, r_beta, r_gamma), T, atol=1e-12)
    # (3.71): Rz(α) Rz(γ) = Rz(α + γ).
    assert math.cos(r_gamma) == pytest.approx(math.cos(alpha + gamma), abs=1e-12)
    assert math.sin(r_gamma) == pytest.approx(math.sin(alpha + gamma), abs=1e-12)


@pytest.mark.parametrize(('alpha', 'gamma'), [(0.0, 0.0), (0.3, -1.2), (-2.0, 2.5), (3.0, 1.0)])
def test_tr2eul_degenerate_beta_180_returns_zero_alpha(alpha, gamma):
    T = eul2tr(alpha, math.pi, gamma)
    r_alpha, r_beta, r_gamma = tr2eul(T)
    assert r_alpha == 0.0
    assert r_beta == math.pi
    np.testing.assert_allclose(eul2tr(r_alpha, r_beta, r_gamma), T, atol=1e-12)
    # (3.72): Rz(α) Ry(π) Rz(γ) = Ry(π) Rz(γ - α).
    assert math.cos(r_gamma) == pytest.approx(math.cos(gamma - alpha), abs=1e-12)
    assert math.sin(r_gamma) == pytest.approx(math.sin(gamma - alpha), abs=1e-12)


@pytest.mark.parametrize('beta', [1e-7, 1e-9, 2e-12, 1e-13, math.pi - 1e-9, math.pi - 1e-13])
def test_tr2eul_round_trip_stays_accurate_next_to_the_degenerate_betas(beta):
    # With γ = atan2(r32, -r31) evaluated literally the error grows like 1e-16 / sin β.
    T = with_rounding_noise(eul2tr(0.7, beta, -1.9))
    np.testing.assert_allclose(eul2tr(tr2eul(T)), T, atol=1e-12)


# --- Quaternions and axis-angle --------------------------------------------------------------

def test_tr2q_matches_the_defining_formula_for_rotvec():
    rng = np.random.default_rng(320)
    for _ in range(50):
        k = rng.normal(size=3)
        k /= np.linalg.norm(k)
        theta = rng.uniform(0.0, math.pi)
        expected = np.concatenate([[math.cos(theta / 2)], k * math.sin(theta / 2)])
        q = tr2q(rotvec(k, theta))
        assert q.shape == (4,)
        assert q.dtype == np.float64
        np.testing.assert_allclose(q, expected, atol=1e-12)
        # θ and θ - 2π are the same rotation; the formula's w < 0 for θ - 2π, tr2q keeps w ≥ 0.
        np.testing.assert_allclose(tr2q(rotvec(k, theta - 2.0 * math.pi)), expected, atol=1e-12)


def test_q2tr_of_the_defining_formula_is_the_rotation_about_z():
    theta = 0.8
    q = [math.cos(theta / 2), 0.0, 0.0, math.sin(theta / 2)]
    c, s = math.cos(theta), math.sin(theta)
    expected = [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    np.testing.assert_allclose(q2tr(q), expected, atol=1e-15)
    np.testing.assert_allclose(q2tr(-3.0 * np.asarray(q)), expected, atol=1e-15)


@given(AXES, ANGLES)
def test_tr2q_is_unit_with_nonnegative_scalar_and_round_trips(axis, angle):
    T = rotvec(axis, angle)
    q = tr2q(T)
    assert q[0] >= 0.0
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(q2tr(q), T, atol=1e-12)


def test_tr2angvec_returns_the_angle_and_unit_axis_of_rotvec():
    rng = np.random.default_rng(3205)
    for _ in range(50):
        v = rng.normal(size=3) * rng.uniform(0.1, 10.0)
        theta = rng.uniform(1e-3, math.pi - 1e-3)
        result_theta, k = tr2angvec(rotvec(v, theta))
        assert isinstance(result_theta, float)
        assert k.shape == (3,)
        assert result_theta == pytest.approx(theta, abs=1e-12)
        np.testing.assert_allclose(k, v / np.linalg.norm(v), atol=1e-9)


def test_tr2angvec_of_the_identity_is_zero_about_z():
    theta, k = tr2angvec(np.eye(4))
    assert theta == 0.0
    np.testing.assert_array_equal(k, [0.0, 0.0, 1.0])


@given(AXES, ANGLES)
def test_tr2angvec_round_trips_with_angle_in_zero_to_pi(axis, angle):
    T = rotvec(axis, angle)
    theta, k = tr2angvec(T)
    assert 0.0 <= theta <= math.pi
    assert np.linalg.norm(k) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(angvec2tr(theta, k), T, atol=1e-12)


# --- Degrees ---------------------------------------------------------------------------------

def test_degrees_give_the_same_as_radians():
    d = 180.0 / math.pi
    for rotation in (rotx, roty, rotz):
        np.testing.assert_allclose(rotation(30.0, unit='deg'), rotation(math.pi / 6), atol=1e-15)
    np.testing.assert_allclose(rotvec([1, 2, 3], 45.0, 'deg'), rotvec([1, 2, 3], math.pi / 4),
                               atol=1e-15)
    np.testing.assert_allclose(angvec2tr(45.0, [1, 2, 3], 'deg'),
                               angvec2tr(math.pi / 4, [1, 2, 3]), atol=1e-15)
    np.testing.assert_allclose(rpy2tr(10.0, 20.0, 30.0, unit='deg'),
                               rpy2tr(10.0 / d, 20.0 / d, 30.0 / d), atol=1e-15)
    np.testing.assert_allclose(eul2tr([10.0, 20.0, 30.0], unit='deg'),
                               eul2tr(10.0 / d, 20.0 / d, 30.0 / d), atol=1e-15)
    T = rotvec([1, -2, 0.5], 1.1)
    np.testing.assert_allclose(tr2rpy(T, unit='deg'), tr2rpy(T) * d, atol=1e-12)
    np.testing.assert_allclose(tr2eul(T, unit='deg'), tr2eul(T) * d, atol=1e-12)
    theta, k = tr2angvec(T, unit='deg')
    assert theta == pytest.approx(1.1 * d, abs=1e-10)


@pytest.mark.parametrize(('function', 'args'), [
    (rotx, (1.0,)), (roty, (1.0,)), (rotz, (1.0,)), (rotvec, ([0, 0, 1], 1.0)),
    (angvec2tr, (1.0, [0, 0, 1])), (rpy2tr, (1.0, 2.0, 3.0)), (eul2tr, (1.0, 2.0, 3.0)),
    (tr2rpy, (np.eye(4),)), (tr2eul, (np.eye(4),)), (tr2angvec, (np.eye(4),)),
])
@pytest.mark.parametrize('unit', ['degrees', 'RAD', 'grad', ''])
def test_bad_unit_is_rejected(function, args, unit):
    with pytest.raises(ValueError, match=rf"{function.__name__}: unit must be 'rad' or 'deg'"):
        function(*args, unit=unit)


# --- Bad input -------------------------------------------------------------------------------

NAN_T = np.eye(4)
NAN_T[0, 1] = np.nan
INF_T = np.eye(4)
INF_T[1, 3] = np.inf


@pytest.mark.parametrize(('function', 'args', 'message'), [
    (tr2rpy, (np.eye(3),), 'tr2rpy: T must have shape (4, 4), got (3, 3)'),
    (tr2eul, (np.eye(3),), 'tr2eul: T must have shape (4, 4), got (3, 3)'),
    (tr2q, (np.ones((4, 4, 1)),), 'tr2q: T must have shape (4, 4), got (4, 4, 1)'),
    (tr2angvec, (np.eye(4)[:3],), 'tr2angvec: T must have shape (4, 4), got (3, 4)'),
    (trinv, (np.eye(3),), 'trinv: T must have shape (4, 4), got (3, 3)'),
    (tr2rpy, (NAN_T,), 'tr2rpy: T must be finite'),
    (tr2eul, (INF_T,), 'tr2eul: T must be finite'),
    (tr2q, (NAN_T,), 'tr2q: T must be finite'),
    (tr2angvec, (INF_T,), 'tr2angvec: T must be finite'),
    (trinv, (NAN_T,), 'trinv: T must be finite'),
    (transl, (NAN_T,), 'transl: T must be finite'),
    (tr2rpy, (np.full((4, 4), 'a'),), 'tr2rpy: T must be real numbers'),
    (transl, (np.eye(3),), 'transl: give x, y, z, a vector of shape (3,)'),
    (transl, ([1.0, 2.0],), 'transl: give x, y, z, a vector of shape (3,)'),
    (transl, (1.0, 2.0), 'transl: give x, y and z'),
    (transl, (np.nan, 0.0, 0.0), 'transl: x must be finite'),
    (transl, (0.0, [1.0, 2.0], 0.0), 'transl: y must be a scalar, got shape (2,)'),
    (transl, ([0.0, np.inf, 1.0],), 'transl: Q must be finite'),
    (transl, (np.diag([1.0, 1.0, 1.0, 2.0]),), 'transl: T is not a homogeneous transform'),
    (rotx, (np.nan,), 'rotx: theta must be finite'),
    (roty, (np.inf,), 'roty: theta must be finite'),
    (rotz, ([0.1, 0.2],), 'rotz: theta must be a scalar, got shape (2,)'),
    (rotz, ('0.5',), 'rotz: theta must be real numbers'),
    (rotvec, ([0.0, 0.0, 0.0], 1.0), 'rotvec: the rotation axis must be non-zero'),
    (rotvec, ([1.0, 0.0], 1.0), 'rotvec: the axis must have shape (3,), got (2,)'),
    (rotvec, ([1.0, np.nan, 0.0], 1.0), 'rotvec: the axis must be finite'),
    (rotvec, ([1.0, 0.0, 0.0], np.nan), 'rotvec: theta must be finite'),
    (angvec2tr, (1.0, [0.0, 0.0, 0.0]), 'angvec2tr: the rotation axis must be non-zero'),
    (angvec2tr, (np.inf, [0.0, 0.0, 1.0]), 'angvec2tr: theta must be finite'),
    (rpy2tr, (1.0, 2.0), 'rpy2tr: give three angles or one array of shape (3,), not two'),
    (rpy2tr, ([1.0, 2.0],), 'rpy2tr: [roll, pitch, yaw] must have shape (3,), got (2,)'),
    (rpy2tr, (0.0, np.nan, 0.0), 'rpy2tr: pitch must be finite'),
    (rpy2tr, ([0.0, 0.0, np.inf],), 'rpy2tr: [roll, pitch, yaw] must be finite'),
    (eul2tr, (1.0, None, 3.0), 'eul2tr: give three angles or one array of shape (3,), not two'),
    (eul2tr, (np.inf, 0.0, 0.0), 'eul2tr: alpha must be finite'),
    (q2tr, ([0.0, 0.0, 0.0, 0.0],), 'q2tr: the quaternion must be non-zero'),
    (q2tr, ([1.0, 0.0, 0.0],), 'q2tr: q must have shape (4,), got (3,)'),
    (q2tr, ([1.0, 0.0, np.nan, 0.0],), 'q2tr: q must be finite'),
])
def test_bad_input_raises_a_value_error_naming_the_function(function, args, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        function(*args)


# --- ishomog ---------------------------------------------------------------------------------

@pytest.mark.parametrize('T', [
    np.eye(4),
    np.eye(4, dtype=int),
    np.eye(4).tolist(),
    transl(8, 4, 0) @ rotz(math.pi / 9),
    transl(-1e3, 2.0, 3.0) @ rotvec([1, 2, 3], 2.5),
    rotx(0.3) + 1e-12,  # within the 1e-9 tolerance
])
def test_ishomog_accepts_homogeneous_transforms(T):
    assert ishomog(T) is True


BAD_LAST_ROW = np.eye(4)
BAD_LAST_ROW[3] = [1.0, 0.0, 0.0, 1.0]
NOT_ORTHONORMAL = rotx(0.3)
NOT_ORTHONORMAL[1, 1] += 1e-6


@pytest.mark.parametrize('T', [
    np.eye(3),
    np.eye(4)[:3],
    np.ones((4, 4, 1)),
    np.diag([1.0, 1.0, -1.0, 1.0]),  # a reflection: det R = -1
    np.diag([1.0, 1.0, 1.0, 2.0]),
    BAD_LAST_ROW,
    np.diag([2.0, 2.0, 2.0, 1.0]),
    NOT_ORTHONORMAL,
    T_A_B_PRINTED,  # 3 printed digits: not orthonormal to 1e-9
    NAN_T,
    INF_T,
    np.eye(4, dtype=complex),
    np.full((4, 4), 'a'),
    [[1.0, 0.0], [0.0]],
    None,
    'not a matrix',
])
def test_ishomog_rejects_everything_else_without_raising(T):
    assert ishomog(T) is False
