"""
Tests of robotica_kin.analytic_ik: closed-form inverse kinematics (catalog 2.3, 2.6).

Reference values are the book's check values (Ej. 4.3), hand computations written out in the
test (Ej. 4.4 with the l1 = 4, l2 = 3 arm of Ej. H.3.1), the book's forward models (4.10) and
(4.23) written entry by entry, and the forward kinematics ``fkine`` (Pinocchio), an
independent route: every returned solution must reproduce the goal pose through it.
"""

import math

from hypothesis import assume, given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.analytic_ik import (
    choose_solution, ikine_planar_2r, ikine_planar_2r_geometric, ikine_planar_3r,
    ikine_puma560, ikine_rp, ikine_rpr,
)
from robotica_kin.dh import dh_model
from robotica_kin.forward_kinematics import fkine, link_frames
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560
from robotica_kin.transforms import rotvec, rotx, roty, transl

ANGLES = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)
LINKS = st.floats(min_value=0.2, max_value=5.0, allow_nan=False)


def angle_diff(a, b):
    """Return a - b modulo 2π in [-π, π], elementwise (independent of wrap_to_pi)."""
    return np.angle(np.exp(1j * (np.asarray(a, dtype=float) - np.asarray(b, dtype=float))))


def same_angles(a, b, tol):
    """Return whether two joint vectors of angles agree modulo 2π within tol."""
    return bool(np.all(np.abs(angle_diff(a, b)) <= tol))


def contains(rows, q, tol):
    """Return whether some row of ``rows`` equals q modulo 2π within tol."""
    return any(same_angles(row, q, tol) for row in rows)


def fk_4_10(l1, l2, q):
    """Return the planar 3R forward model (4.10), written out entry by entry."""
    t1, t2, t3 = q
    c1, s1 = math.cos(t1), math.sin(t1)
    c12, s12 = math.cos(t1 + t2), math.sin(t1 + t2)
    c123, s123 = math.cos(t1 + t2 + t3), math.sin(t1 + t2 + t3)
    return np.array([
        [c123, -s123, 0.0, l1 * c1 + l2 * c12],
        [s123, c123, 0.0, l1 * s1 + l2 * s12],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])


def fk_4_23(theta1, d2):
    """Return T_0_2 of the R-P-R robot, (4.23) written out entry by entry."""
    c1, s1 = math.cos(theta1), math.sin(theta1)
    return np.array([
        [c1, 0.0, s1, d2 * s1],
        [s1, 0.0, -c1, -d2 * c1],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])


def with_rounding_noise(T):
    """Return T after a rotation there and back (the same pose with ~1e-16 noise)."""
    axis = [0.3, -0.5, 0.8]
    return rotvec(axis, 1.0) @ rotvec(axis, -1.0) @ T


# ---------------------------------------------------------------- Ej. 4.3 (catalog 2.6)

def test_ejemplo_4_3():
    """Ej. 4.3 (4.24)-(4.25): the book's check values and the forward model (4.23)."""
    theta1, d2 = ikine_rp(0.0, -1.0)
    assert theta1 == pytest.approx(0.0, abs=1e-15) and d2 == pytest.approx(1.0)
    theta1, d2 = ikine_rp(1.0, 0.0)
    assert theta1 == pytest.approx(math.pi / 2) and d2 == pytest.approx(1.0)
    assert ikine_rp(0.0, 0.0) == (0.0, 0.0)
    # Behind the base: atan2(x, -y) = π exactly, inside (-π, π].
    assert ikine_rp(0.0, 2.0) == (pytest.approx(math.pi), pytest.approx(2.0))


@settings(max_examples=40, deadline=None)
@given(theta1=ANGLES, d2=st.floats(min_value=0.01, max_value=2.0))
def test_ejemplo_4_3_round_trip(theta1, d2):
    """The origin of {2} from (4.23) and from the Ej. 4.2 table gives back θ1, d2."""
    x, y = fk_4_23(theta1, d2)[:2, 3]
    got_theta1, got_d2 = ikine_rp(x, y)
    assert got_d2 == pytest.approx(d2, abs=1e-12)
    assert abs(angle_diff(got_theta1, theta1)) < 1e-9
    T_0_2 = link_frames(cylindrical_rpr(), [theta1, d2, 0.3])[2]
    np.testing.assert_allclose(T_0_2, fk_4_23(got_theta1, got_d2), atol=1e-12)


def test_ikine_rp_rejects_nan():
    with pytest.raises(ValueError, match='finite'):
        ikine_rp(math.nan, 1.0)


# ---------------------------------------------------------------- Ej. 4.4 (catalog 2.6)

def test_ejemplo_4_4():
    """
    Ej. 4.4 on the Ej. H.3.1 arm (l1 = 4, l2 = 3), goal (3, 4, φ = 0), by hand.

    r = 5 so c2 = (25 - 16 - 9) / 24 = 0, θ2 = ±π/2. For θ2 = π/2 (4.35) gives
    θ1 = atan2(4, 3) - atan2(3, 4), whose sine is 0.8·0.8 - 0.6·0.6 = 7/25: θ1 = atan2(7, 24);
    for θ2 = -π/2, θ1 = atan2(4, 3) + atan2(3, 4) = π/2. θ3 = φ - θ1 - θ2 (4.39).
    """
    expected = np.array([
        [math.atan2(7, 24), math.pi / 2, -math.atan2(7, 24) - math.pi / 2],
        [math.pi / 2, -math.pi / 2, 0.0],
    ])
    np.testing.assert_allclose(ikine_planar_3r(4.0, 3.0, 3.0, 4.0, 0.0), expected, atol=1e-12)
    np.testing.assert_allclose(ikine_planar_2r(4.0, 3.0, 3.0, 4.0), expected[:, :2], atol=1e-12)
    np.testing.assert_allclose(
        ikine_planar_2r_geometric(4.0, 3.0, 3.0, 4.0), expected[:, :2], atol=1e-12)
    goal = transl(3.0, 4.0, 0.0)                            # (4.27) with φ = 0
    for q in expected:
        np.testing.assert_allclose(fkine(planar_rrr(4.0, 3.0), q), goal, atol=1e-12)
        np.testing.assert_allclose(fk_4_10(4.0, 3.0, q), goal, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(l1=LINKS, l2=LINKS, t1=ANGLES, t2=ANGLES, phi=ANGLES)
def test_ejemplo_4_4_round_trip(l1, l2, t1, t2, phi):
    """Both elbow solutions reproduce (x, y, φ) through fkine and (4.10); algebraic = geometric."""
    assume(abs(math.sin(t2)) > 1e-3)                       # away from the boundary circles
    goal = fk_4_10(l1, l2, [t1, t2, phi - t1 - t2])
    x, y = goal[:2, 3]
    solutions = ikine_planar_3r(l1, l2, x, y, phi)
    assert solutions.shape == (2, 3)
    assert solutions[0, 1] >= 0.0 > solutions[1, 1]        # documented order
    assert np.all(solutions > -math.pi) and np.all(solutions <= math.pi)
    assert contains(solutions, [t1, t2, phi - t1 - t2], 1e-8)
    for q in solutions:
        np.testing.assert_allclose(fkine(planar_rrr(l1, l2), q), goal, atol=1e-9)
        np.testing.assert_allclose(fk_4_10(l1, l2, q), goal, atol=1e-9)
    geometric = ikine_planar_2r_geometric(l1, l2, x, y)
    assert same_angles(geometric, solutions[:, :2], 1e-7)


@settings(max_examples=40, deadline=None)
@given(l1=LINKS, ratio=st.floats(min_value=0.02, max_value=0.98), angle=ANGLES)
def test_planar_2r_interior_points(l1, ratio, angle):
    """Any point strictly inside the annulus has two solutions reaching it (planar_rr tip)."""
    l2 = 0.7 * l1
    inner, outer = l1 - l2, l1 + l2
    r = inner + ratio * (outer - inner)
    x, y = r * math.cos(angle), r * math.sin(angle)
    solutions = ikine_planar_2r(l1, l2, x, y)
    assert solutions.shape == (2, 2)
    for q in solutions:
        np.testing.assert_allclose(fkine(planar_rr(l1, l2), q)[:2, 3], [x, y], atol=1e-9)
    np.testing.assert_allclose(
        angle_diff(ikine_planar_2r_geometric(l1, l2, x, y), solutions), 0.0, atol=1e-7)


def test_planar_2r_accurate_near_the_origin_with_equal_links():
    """With l1 = l2 the goal 1e-7 m from the origin is still reached to 1e-13 m."""
    x, y = 6e-8, -8e-8
    solutions = ikine_planar_2r(1.0, 1.0, x, y)
    assert solutions.shape == (2, 2)
    for q in solutions:
        np.testing.assert_allclose(fkine(planar_rr(1.0, 1.0), q)[:2, 3], [x, y], atol=1e-13)


# ---------------------------------------------------------------- reachability (catalog 2.3)

@pytest.mark.parametrize('x, y', [(7.5, 0.0), (0.0, -7.001), (0.5, 0.0), (0.0, 0.0),
                                  (0.6, -0.7)])
def test_outside_the_annulus_is_unreachable(x, y):
    """l1 = 4, l2 = 3: reachable iff 1 <= r <= 7 (book §4.4); the message says why."""
    with pytest.raises(ValueError, match=r'unreachable.*annulus 1 m <= r <= 7 m'):
        ikine_planar_2r(4.0, 3.0, x, y)
    with pytest.raises(ValueError, match='unreachable'):
        ikine_planar_2r_geometric(4.0, 3.0, x, y)
    with pytest.raises(ValueError, match='unreachable'):
        ikine_planar_3r(4.0, 3.0, x, y, 0.3)


@pytest.mark.parametrize('r', [7.0, 1.0])
@pytest.mark.parametrize('angle', [0.0, 0.4, -2.5, math.pi])
def test_boundary_has_one_solution(r, angle):
    """On the outer (stretched) and inner (folded) circle there is one solution."""
    x, y = r * math.cos(angle), r * math.sin(angle)
    for solve in (ikine_planar_2r, ikine_planar_2r_geometric):
        solutions = solve(4.0, 3.0, x, y)
        assert solutions.shape == (1, 2)
        assert abs(angle_diff(solutions[0, 1], 0.0 if r == 7.0 else math.pi)) < 1e-12
        np.testing.assert_allclose(fkine(planar_rr(4.0, 3.0), solutions[0])[:2, 3], [x, y],
                                   atol=1e-9)
    assert ikine_planar_3r(4.0, 3.0, x, y, 1.0).shape == (1, 3)


def test_dexterous_workspace_remark():
    """
    Book §4.4: with l1 = l2 only the origin is dexterous; otherwise no point is.

    At the origin every orientation θ1 + θ2 of link 2 is reached (θ2 = π, any θ1): the IK
    returns the documented θ1 = 0. At an interior point of an l1 != l2 arm only the two
    orientations of the two elbow solutions are reached.
    """
    for t in np.linspace(-3.0, 3.0, 7):
        np.testing.assert_allclose(fkine(planar_rr(1.0, 1.0), [t, math.pi])[:2, 3], 0.0,
                                   atol=1e-15)
    np.testing.assert_allclose(ikine_planar_2r(1.0, 1.0, 0.0, 0.0), [[0.0, math.pi]])
    np.testing.assert_allclose(ikine_planar_2r_geometric(1.0, 1.0, 0.0, 0.0), [[0.0, math.pi]])
    with pytest.raises(ValueError, match='unreachable'):
        ikine_planar_2r(1.0, 0.9, 0.0, 0.0)
    solutions = ikine_planar_2r(4.0, 3.0, 2.0, 3.0)
    orientations = solutions.sum(axis=1)
    assert abs(angle_diff(orientations[0], orientations[1])) > 0.1


def test_joint_2_limited_to_half_turn_leaves_one_solution():
    """Book §4.4: with θ2 in [0, π] the reachable set is the same, one solution per point."""
    qlim = [[-math.pi, math.pi], [0.0, math.pi]]
    for x, y in [(2.0, 3.0), (-5.0, 1.0), (0.5, -1.2)]:
        solutions = ikine_planar_2r(4.0, 3.0, x, y)
        inside = [q for q in solutions if 0.0 <= q[1] <= math.pi]
        assert len(inside) == 1
        chosen = choose_solution(solutions, [0.0, -1.0], qlim=qlim)
        np.testing.assert_allclose(chosen, inside[0])


@pytest.mark.parametrize('args', [(0.0, 1.0, 1.0, 0.0), (-1.0, 1.0, 1.0, 0.0),
                                  (1.0, math.nan, 1.0, 0.0), (1.0, 1.0, math.inf, 0.0),
                                  (1.0, 1.0, 1.0, 'a')])
def test_planar_bad_input(args):
    with pytest.raises(ValueError):
        ikine_planar_2r(*args)
    with pytest.raises(ValueError):
        ikine_planar_3r(*args, 0.0)


# ---------------------------------------------------------------- R-P-R (Ej. 4.2)

@settings(max_examples=50, deadline=None)
@given(theta1=ANGLES, d2=st.floats(min_value=0.0, max_value=1.0), theta3=ANGLES,
       l2=st.floats(min_value=0.05, max_value=1.0))
def test_ikine_rpr_round_trip(theta1, d2, theta3, l2):
    T = with_rounding_noise(fkine(cylindrical_rpr(l2), [theta1, d2, theta3]))
    q = ikine_rpr(T, l2)
    assert q[1] == pytest.approx(d2, abs=1e-9)
    assert same_angles(q[[0, 2]], [theta1, theta3], 1e-9)
    np.testing.assert_allclose(fkine(cylindrical_rpr(l2), q), T, atol=1e-9)


def test_ikine_rpr_unreachable():
    l2 = 0.2
    T = fkine(cylindrical_rpr(l2), [0.4, 0.5, -0.7])
    with pytest.raises(ValueError, match='unreachable.*z = 0'):
        ikine_rpr(transl(0.0, 0.0, 0.1) @ T, l2)
    with pytest.raises(ValueError, match='unreachable.*orientation'):
        ikine_rpr(T @ rotx(0.3), l2)
    with pytest.raises(ValueError, match='unreachable.*orientation'):
        ikine_rpr(T @ roty(1e-6), l2)
    # d2 = -0.1 < 0: the raw table lets fkine compute it; the robot cannot reach it.
    table = [[0, 0, 0, 0, 0], [math.pi / 2, 0, 0, 0, 1], [0, 0, 0, l2, 0]]
    with pytest.raises(ValueError, match=r'unreachable.*d2'):
        ikine_rpr(fkine(table, [0.4, -0.1, -0.7]), l2)
    with pytest.raises(ValueError, match='homogeneous'):
        ikine_rpr(np.eye(3), l2)
    with pytest.raises(ValueError):
        ikine_rpr(T, 0.0)


def test_ikine_rpr_tolerance():
    """A z error below tol is accepted, above it refused."""
    T = transl(0.0, 0.0, 1e-6) @ fkine(cylindrical_rpr(0.2), [0.4, 0.5, -0.7])
    np.testing.assert_allclose(ikine_rpr(T, 0.2, tol=1e-5), [0.4, 0.5, -0.7], atol=1e-9)
    with pytest.raises(ValueError, match='unreachable'):
        ikine_rpr(T, 0.2)


# ---------------------------------------------------------------- PUMA 560 (catalog 2.3, 12.4)

def flipped(q):
    """Return the wrist flip of q (book §4.4): θ4 + π, -θ5, θ6 + π."""
    return np.array([q[0], q[1], q[2], q[3] + math.pi, -q[4], q[5] + math.pi])


def check_puma_solutions(robot, q, T, expected_count):
    solutions = ikine_puma560(T, robot)
    assert solutions.shape == (expected_count, 6)
    assert np.all(solutions > -math.pi) and np.all(solutions <= math.pi)
    for row in solutions:
        np.testing.assert_allclose(fkine(robot, row), T, atol=1e-9)
    assert contains(solutions, q, 1e-7)
    return solutions


def test_puma560_random_round_trip():
    """200 random q within the limits: 8 distinct solutions, all reach T, one is q."""
    robot = puma560()
    rng = np.random.default_rng(560)
    for q in rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(200, 6)):
        T = with_rounding_noise(fkine(robot, q))
        solutions = check_puma_solutions(robot, q, T, 8)
        for i in range(8):
            for j in range(i):
                assert not same_angles(solutions[i], solutions[j], 1e-6)


def test_puma560_wrist_flip_pairs():
    """Each solution's wrist flip (θ4 + π, -θ5, θ6 + π) is also a solution (book §4.4)."""
    robot = puma560()
    rng = np.random.default_rng(4)
    for q in rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(20, 6)):
        solutions = ikine_puma560(fkine(robot, q))
        for row in solutions:
            assert contains(solutions, flipped(row), 1e-9)
        # Flip pairs share the arm joints: four distinct (θ1, θ2, θ3), two rows each.
        arms = {tuple(np.round(row[:3], 6)) for row in solutions}
        assert len(arms) == 4


def test_puma560_default_robot_and_tool():
    """robot=None is puma560(); a tool is removed first (T @ inv(tool))."""
    q = np.array([0.3, -0.8, 1.1, -0.4, 0.9, 2.0])
    T = fkine(puma560(), q)
    np.testing.assert_allclose(ikine_puma560(T), ikine_puma560(T, puma560()))
    tool = transl(0.01, -0.02, 0.1) @ rotx(0.2)
    robot = dh_model(puma560().table, name='puma_tool', qlim=puma560().qlim, tool=tool)
    T_tool = fkine(robot, q)
    np.testing.assert_allclose(T_tool, T @ tool, atol=1e-12)
    check_puma_solutions(robot, q, T_tool, 8)


def test_puma_of_craigs_textbook_table():
    """
    The same structure with Craig's textbook twists (Ej. 4.7's table, catalog 2.6).

    α = [0, -π/2, 0, -π/2, π/2, -π/2], a2 = 0.4318, a3 = 0.0203, d3 = 0.15005, d4 = 0.4318;
    the lengths are read from the model, so the solver must work unchanged.
    """
    table = [[0, 0, 0, 0], [-math.pi / 2, 0, 0, 0], [0, 0.4318, 0, 0.15005],
             [-math.pi / 2, 0.0203, 0, 0.4318], [math.pi / 2, 0, 0, 0], [-math.pi / 2, 0, 0, 0]]
    robot = dh_model(table, name='craig_puma')
    rng = np.random.default_rng(7)
    for q in rng.uniform(-math.pi, math.pi, size=(30, 6)):
        check_puma_solutions(robot, q, fkine(robot, q), 8)


def test_puma560_wrist_singularity():
    """
    θ5 = 0: axes 4 and 6 align; that arm solution gets one row, with θ4 as asked.

    In dhp560 α4 + α5 = 0, so with θ5 = 0 the wrist rotation is Rz(θ4) Rz(θ6): only
    θ4 + θ6 is determined. The other three arm solutions have other R_0_3, so a regular
    wrist and two rows each: 1 + 3 * 2 = 7 rows.
    """
    robot = puma560()
    q = np.array([0.5, -1.0, 0.8, 0.6, 0.0, -0.4])
    T = fkine(robot, q)
    for theta4 in (0.0, 0.7):
        solutions = ikine_puma560(T, theta4_singular=theta4)
        assert solutions.shape == (7, 6)
        for row in solutions:
            np.testing.assert_allclose(fkine(robot, row), T, atol=1e-9)
        same_arm = [row for row in solutions if same_angles(row[:3], q[:3], 1e-9)]
        assert len(same_arm) == 1
        assert same_arm[0][3] == pytest.approx(theta4)
        assert abs(angle_diff(same_arm[0][4], 0.0)) < 1e-9
        assert abs(angle_diff(same_arm[0][3] + same_arm[0][5], q[3] + q[5])) < 1e-9
        others = [row for row in solutions if not same_angles(row[:3], q[:3], 1e-9)]
        for row in others:
            assert contains(others, flipped(row), 1e-9)


def test_puma560_stretched_elbow_has_four_solutions():
    """
    θ3 = atan2(d4, a3) stretches the forearm along the upper arm (wrist centre at a2 + R).

    In frame {2} the wrist centre is (a2 + a3 c3 + d4 s3, a3 s3 - d4 c3, d3) (link transforms
    (4.5) with α3 = π/2): its distance from axis 2 is largest, a2 + sqrt(a3^2 + d4^2), there.
    """
    robot = puma560()
    a2, a3, d4 = 0.4318, -0.0203, 0.4331
    q = np.array([0.2, -0.6, math.atan2(d4, a3), 0.3, 0.8, 0.1])
    frames = link_frames(robot, q)
    wrist_in_2 = np.linalg.solve(frames[2], frames[4][:, 3])[:2]
    assert np.linalg.norm(wrist_in_2) == pytest.approx(a2 + math.hypot(a3, d4), abs=1e-12)
    check_puma_solutions(robot, q, fkine(robot, q), 4)


@pytest.mark.parametrize('position, why', [
    ((2.0, 0.0, 0.0), 'annulus'),
    ((0.0, 0.0, 0.3), 'shoulder offset'),
    ((0.05, 0.05, -0.2), 'shoulder offset'),
])
def test_puma560_unreachable(position, why):
    with pytest.raises(ValueError, match=f'unreachable.*{why}'):
        ikine_puma560(transl(position))


def test_puma560_refuses_other_structures_and_bad_poses():
    with pytest.raises(ValueError, match='6 revolute'):
        ikine_puma560(np.eye(4), planar_rrr())
    table = puma560().table.copy()
    table[4, 1] = 0.1                                       # a_4 != 0: no common wrist centre
    with pytest.raises(ValueError, match='a_4 must be 0'):
        ikine_puma560(np.eye(4), table)
    table = puma560().table.copy()
    table[4, 0] = 0.3                                       # α4 not a right angle
    with pytest.raises(ValueError, match='alpha_4'):
        ikine_puma560(np.eye(4), table)
    T = fkine(puma560(), np.zeros(6))
    bad = T.copy()
    bad[0, 3] = math.nan
    with pytest.raises(ValueError, match='homogeneous'):
        ikine_puma560(bad)
    with pytest.raises(ValueError, match='homogeneous'):
        ikine_puma560(T[:3])


# ---------------------------------------------------------------- choose_solution (catalog 2.3)

def test_choose_solution_picks_the_nearest_puma_solution():
    robot = puma560()
    rng = np.random.default_rng(11)
    for q in rng.uniform(robot.qlim[:, 0] + 0.1, robot.qlim[:, 1] - 0.1, size=(20, 6)):
        solutions = ikine_puma560(fkine(robot, q))
        current = q + rng.uniform(-0.05, 0.05, size=6)
        chosen = choose_solution(solutions, current, qlim=robot.qlim)
        np.testing.assert_allclose(chosen, q, atol=1e-8)


def test_choose_solution_compares_angles_modulo_two_pi():
    # -3.1 is 2π - 6.2 = 0.083 rad from 3.1; 2.0 is 1.1 rad away.
    chosen = choose_solution([[-3.1], [2.0]], [3.1])
    np.testing.assert_allclose(chosen, [-3.1 + 2.0 * math.pi])
    # With limits ±3 no equivalent of -3.1 fits: 2.0 is the only admissible solution.
    np.testing.assert_allclose(choose_solution([[-3.1], [2.0]], [3.1], qlim=[[-3.0, 3.0]]),
                               [2.0])


def test_choose_solution_uses_the_whole_joint_range():
    """PUMA joint 6 spans ±266° (Craig's ranges): θ6 = 4 rad is reached as 4, not as 4 - 2π."""
    robot = puma560(joint_limits=True)
    q = np.array([0.1, -0.5, 0.4, 0.3, 0.6, 4.0])
    solutions = ikine_puma560(fkine(robot, q))
    chosen = choose_solution(solutions, q, qlim=robot.qlim)
    np.testing.assert_allclose(chosen, q, atol=1e-9)


def test_choose_solution_limits_travel_through_the_gap():
    """Limits [-3, 3]: from 2.9 to -2.9 the joint travels 5.8 rad, not 0.48 through ±π."""
    chosen = choose_solution([[-2.9, 0.0], [1.0, 1.0]], [2.9, 0.0], qlim=[[-3, 3], [-3, 3]])
    np.testing.assert_allclose(chosen, [1.0, 1.0])
    chosen = choose_solution([[-2.9, 0.0], [1.0, 1.0]], [2.9, 0.0])
    np.testing.assert_allclose(chosen, [2.0 * math.pi - 2.9, 0.0])


def test_choose_solution_weights_and_prismatic_joints():
    solutions = [[1.0, 0.0], [0.0, 1.5]]
    np.testing.assert_allclose(choose_solution(solutions, [0.0, 0.0]), [1.0, 0.0])
    np.testing.assert_allclose(choose_solution(solutions, [0.0, 0.0], weights=[10.0, 1.0]),
                               [0.0, 1.5])
    # A prismatic value 2π away is 2π m away, not the same position.
    solutions = [[0.0, 0.5 + 2.0 * math.pi], [0.0, 2.0]]
    np.testing.assert_allclose(choose_solution(solutions, [0.0, 0.5]), [0.0, 0.5])
    np.testing.assert_allclose(
        choose_solution(solutions, [0.0, 0.5], prismatic=[False, True]), [0.0, 2.0])
    # cylindrical_rpr: d2 within [0, 1] m.
    robot = cylindrical_rpr()
    with pytest.raises(ValueError, match='joint limits'):
        choose_solution([[0.0, 1.5, 0.0]], [0.0, 0.0, 0.0], qlim=robot.qlim,
                        prismatic=robot.prismatic)


def test_choose_solution_raises_when_none_fit():
    with pytest.raises(ValueError, match='joint limits'):
        choose_solution([[2.0, 0.0], [0.0, 2.0]], [0.0, 0.0], qlim=[[-1, 1], [-1, 1]])


@pytest.mark.parametrize('kwargs', [
    {'solutions': np.zeros((0, 2)), 'q_current': [0.0, 0.0]},
    {'solutions': [[0.0, 0.0]], 'q_current': [0.0]},
    {'solutions': [[0.0, math.nan]], 'q_current': [0.0, 0.0]},
    {'solutions': [[0.0, 0.0]], 'q_current': [0.0, 0.0], 'weights': [1.0, -1.0]},
    {'solutions': [[0.0, 0.0]], 'q_current': [0.0, 0.0], 'qlim': [[1.0, -1.0], [0.0, 1.0]]},
    {'solutions': [[0.0, 0.0]], 'q_current': [0.0, 0.0], 'prismatic': [True]},
])
def test_choose_solution_bad_input(kwargs):
    with pytest.raises(ValueError):
        choose_solution(**kwargs)
