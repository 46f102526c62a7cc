"""
Tests of robotica_kin.ik: HEMERO's ikine on a damped least-squares solver (catalog §2.3, §12.2).

Every solution is checked through the forward kinematics, computed independently as a
NumPy product of Craig's link transforms (4.5), never through the solver's own error measure.
"""
import math

import numpy as np
import pytest

from reference_models import fk_by_link_product
from robotica_kin.dh import dh_model
from robotica_kin.ik import IKError, ikine, ikine_solve
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560

PLANAR_MASK = [1, 1, 0, 0, 0, 1]


def _pose_error(T, goal):
    """Norm of [p_d - p; rotation angle of R_d R^T] [m, rad]."""
    rot = goal[:3, :3] @ T[:3, :3].T
    angle = math.acos(max(-1.0, min(1.0, (np.trace(rot) - 1.0) / 2.0)))
    return math.hypot(np.linalg.norm(goal[:3, 3] - T[:3, 3]), angle)


def _random_goals(robot, count, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(count, robot.n))
    return q, np.array([fk_by_link_product(robot, qi) for qi in q])


def test_puma560_random_reachable_poses_success_rate_and_accuracy():
    # Issue target: >= 99.5 % of random reachable poses (fkine of random q within limits).
    robot = puma560()
    _, goals = _random_goals(robot, 400, seed=7)
    solved = 0
    for goal in goals:
        result = ikine_solve(robot, goal)
        if result.success:
            solved += 1
            assert robot.within_limits(result.q)
            assert _pose_error(fk_by_link_product(robot, result.q), goal) < 1e-6
            assert result.residual < 1e-6
    assert solved / len(goals) >= 0.995


def test_puma560_home_pose_from_its_own_pose():
    robot = puma560()
    goal = fk_by_link_product(robot, np.zeros(6))
    # Home pose (catalog §12.4, dhp560): wrist centre at (a2 + a3, d2 + d3, -d4)... checked
    # through the independent product of link transforms rather than by a stored number.
    q = ikine(robot, goal, q0=np.zeros(6))
    np.testing.assert_allclose(q, np.zeros(6), atol=1e-9)


def test_ejemplo_h_3_1_arc_converges_when_warm_started():
    # Catalog §12.6: planar 3R, l1 = 4 m, l2 = 3 m, arc of radius 5 m, x = 0:0.05:5,
    # y = sqrt(25 - x^2), phi = 0, q0 = [0 0 0], M = [1 1 0 0 0 1]: every point converges.
    dh = [[0, 0, 0, 0, 0], [0, 4, 0, 0, 0], [0, 3, 0, 0, 0]]
    x = np.arange(0.0, 5.0 + 1e-9, 0.05)
    y = np.sqrt(np.maximum(25.0 - x ** 2, 0.0))
    TG = np.tile(np.eye(4), (x.size, 1, 1))
    TG[:, 0, 3], TG[:, 1, 3] = x, y
    q = ikine(dh, TG, 1e-6, 1000, [0, 0, 0], PLANAR_MASK)
    assert q.shape == (x.size, 3)
    l1, l2 = 4.0, 3.0
    # Closed form (4.10) of the Ej. 4.1 table, independent of the solver.
    px = l1 * np.cos(q[:, 0]) + l2 * np.cos(q[:, 0] + q[:, 1])
    py = l1 * np.sin(q[:, 0]) + l2 * np.sin(q[:, 0] + q[:, 1])
    np.testing.assert_allclose(px, x, atol=1e-6)
    np.testing.assert_allclose(py, y, atol=1e-6)
    np.testing.assert_allclose(np.cos(q.sum(axis=1)), 1.0, atol=1e-9)


def _appendix_line():
    """Return the appendix's straight line (catalog §12.6, fig. A.1) as 51 poses of {6} in {0}."""
    x = np.arange(0.40, 0.45 + 1e-9, 0.001)            # x = 0.40:0.001:0.45 m
    TG = np.tile(np.eye(4), (x.size, 1, 1))           # identity orientation
    TG[:, 0, 3], TG[:, 1, 3], TG[:, 2, 3] = x, 0.1, 0.1
    return TG


def test_appendix_puma_line_reaches_stol_with_hemeros_dhp560():
    # Catalog §12.6: q = ikine(dhp560, stol, ilimit, TG) on x = 0.40:0.001:0.45 m, y = z = 0.1 m.
    # The book uses stol = 0.1; HEMERO's dhp560 has no joint limits, and every point is reached
    # at stol = 1e-6 (issue 20 measured 7.7e-7 at worst).
    TG = _appendix_line()
    assert TG.shape == (51, 4, 4)
    robot = puma560()
    stol = 1e-6
    q = ikine(robot, TG, stol, 1000)
    assert q.shape == (51, 6)
    for qi, goal in zip(q, TG):
        assert _pose_error(fk_by_link_product(robot, qi), goal) < stol


def test_appendix_puma_line_leaves_craigs_joint_ranges():
    # With Craig's ranges (joint 2 stops at 45°, joint 5 at ±100°) no point of the line has a
    # solution: why puma560() follows HEMERO and leaves them out by default.
    result = ikine_solve(puma560(joint_limits=True), _appendix_line(), 1e-6, 1000)
    assert not result.success.any()


def test_trajectory_rows_of_16_are_matlab_column_major():
    robot = puma560()
    q_true, goals = _random_goals(robot, 3, seed=3)
    rows = np.array([goal.flatten(order='F') for goal in goals])
    from_rows = ikine_solve(robot, rows)
    from_stack = ikine_solve(robot, goals)
    np.testing.assert_array_equal(from_rows.q, from_stack.q)
    assert from_rows.success.tolist() == [True, True, True]


def test_trajectory_is_warm_started_from_the_previous_point():
    # A smooth joint path: each point starts from the previous solution, so the solver
    # follows the same branch and needs few iterations.
    robot = puma560()
    t = np.linspace(0.0, 1.0, 25)
    q_path = np.column_stack([0.3 * t, -0.8 + 0.2 * t, 0.9 - 0.1 * t, 0.2 + 0 * t, 0.7 * t + 0.3,
                              0.1 * t])
    goals = np.array([fk_by_link_product(robot, qi) for qi in q_path])
    result = ikine_solve(robot, goals, q0=q_path[0])
    assert result.success.all()
    np.testing.assert_allclose(result.q, q_path, atol=1e-6)
    assert result.iterations[1:].max() <= 6


def test_unreachable_pose_reports_instead_of_raising_and_ikine_raises_ikerror():
    robot = puma560()
    far = np.eye(4)
    far[0, 3] = 10.0     # 10 m: far beyond the PUMA's reach of about 0.9 m
    result = ikine_solve(robot, far, ilimit=200)
    assert result.success is False
    assert result.iterations == 200
    assert result.residual > 8.0
    with pytest.raises(IKError, match='did not converge') as info:
        ikine(robot, far, ilimit=200)
    assert info.value.index is None
    assert info.value.residual > 8.0


def test_ikerror_names_the_failing_point_of_a_trajectory():
    robot = planar_rrr(4.0, 3.0)
    goals = np.tile(np.eye(4), (3, 1, 1))
    goals[:, 0, 3] = [5.0, 6.0, 9.0]     # the last point is beyond l1 + l2 = 7 m
    with pytest.raises(IKError) as info:
        ikine(robot, goals, mask=PLANAR_MASK, ilimit=100)
    assert info.value.index == 2


def test_points_outside_the_annulus_never_converge_h_3_1_map():
    # Catalog §12.6 (a): with q0 = 0, unreachable points (r < 1 or r > 7) never converge.
    dh = [[0, 0, 0, 0], [0, 4, 0, 0], [0, 3, 0, 0]]
    for x, y in [(0.3, 0.4), (5.0, 5.0), (7.0, 0.5)]:
        T = np.eye(4)
        T[0, 3], T[1, 3] = x, y
        # Position only: the orientation of a reachable point could always be matched.
        result = ikine_solve(dh, T, q0=[0, 0, 0], mask=[1, 1, 0, 0, 0, 0], ilimit=300)
        assert not result.success


def test_tool_frame_and_position_mask_on_planar_rr():
    robot = planar_rr(4.0, 3.0)
    T = np.eye(4)
    T[0, 3], T[1, 3] = 2.0, 5.0
    q = ikine(robot, T, mask=[1, 1, 0, 0, 0, 0])
    tip = fk_by_link_product(robot, q)[:3, 3]
    np.testing.assert_allclose(tip, [2.0, 5.0, 0.0], atol=1e-6)


def test_six_dof_robot_with_a_tool():
    base = puma560()
    tool = np.eye(4)
    tool[:3, 3] = [0.0, 0.05, 0.12]
    robot = dh_model(base.table, qlim=base.qlim, tool=tool)
    _, goals = _random_goals(robot, 20, seed=11)
    for goal in goals:
        result = ikine_solve(robot, goal)
        assert result.success
        assert _pose_error(fk_by_link_product(robot, result.q), goal) < 1e-6


def test_prismatic_joint_within_its_limits():
    robot = cylindrical_rpr(0.3, d2_max=1.0)
    q_true = np.array([0.7, 0.45, -0.2])
    goal = fk_by_link_product(robot, q_true)
    result = ikine_solve(robot, goal, mask=[1, 1, 1, 0, 0, 0])
    assert result.success
    assert 0.0 <= result.q[1] <= 1.0
    np.testing.assert_allclose(fk_by_link_product(robot, result.q)[:3, 3], goal[:3, 3], atol=1e-6)


def test_results_are_deterministic():
    robot = puma560()
    _, goals = _random_goals(robot, 5, seed=5)
    first = ikine_solve(robot, goals)
    second = ikine_solve(robot, goals)
    np.testing.assert_array_equal(first.q, second.q)


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'T': np.full((4, 4), np.nan)}, 'not a finite homogeneous'),
    ({'T': np.eye(3)}, 'shape'),
    ({'T': np.diag([1.0, 1.0, -1.0, 1.0])}, 'homogeneous'),
    ({'mask': [1, 1, 0.5, 0, 0, 1]}, 'mask'),
    ({'mask': [0, 0, 0, 0, 0, 0]}, 'at least one'),
    ({'mask': [1, 1, 1]}, 'mask'),
    ({'q0': [0.0, 0.0]}, 'q0'),
    ({'q0': [0.0, math.nan, 0.0, 0.0, 0.0, 0.0]}, 'finite'),
    ({'stol': 0.0}, 'stol'),
    ({'stol': math.nan}, 'stol'),
    ({'ilimit': 0}, 'ilimit'),
    ({'ilimit': 2.5}, 'ilimit'),
])
def test_bad_input_is_refused(kwargs, match):
    args = {'dh': puma560(), 'T': np.eye(4)} | kwargs
    with pytest.raises(ValueError, match=match):
        ikine_solve(**args)


def test_bad_dh_table_is_refused():
    with pytest.raises(ValueError, match='DH table'):
        ikine([[0, 0, 0]], np.eye(4))
