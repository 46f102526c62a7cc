"""
Tests of robotica_kin.ik's compiled search (package robotica_native), beyond test_ik.py.

Solutions are checked through the forward kinematics computed as a NumPy product of Craig's
link transforms (4.5) (``tests/reference_models.py``), independent of Pinocchio and the solver.
"""
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from reference_models import fk_by_link_product
from robotica_kin.ik import ikine_solve
from robotica_kin.robots import planar_rrr, puma560


def _goals(robot, count, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(count, robot.n))
    return np.array([fk_by_link_product(robot, qi) for qi in q])


def test_random_restarts_are_deterministic_for_a_seed_and_depend_on_it():
    # One seed and a q0 far from the goal with a 1-iteration search: the solution comes from
    # the random restarts, which must repeat for a seed and differ between seeds.
    robot = puma560()
    goal = _goals(robot, 1, seed=21)[0]
    kwargs = {'q0': robot.qlim[:, 0] + 0.01, 'slimit': 1, 'seed_count': 1, 'ilimit': 5}
    first = ikine_solve(robot, goal, seed=1, **kwargs)
    again = ikine_solve(robot, goal, seed=1, **kwargs)
    other = ikine_solve(robot, goal, seed=2, **kwargs)
    np.testing.assert_array_equal(first.q, again.q)
    assert first.iterations == again.iterations == 5
    assert not np.array_equal(first.q, other.q)


def test_restarts_reach_poses_with_a_short_search_limit():
    # slimit = 8 and 4 seeds force restarts (seed table order, then random starts); every
    # solution must still be exact and within the limits.
    robot = puma560()
    iterations = []
    for goal in _goals(robot, 10, seed=22):
        result = ikine_solve(robot, goal, slimit=8, seed_count=4)
        assert result.success
        assert robot.within_limits(result.q)
        np.testing.assert_allclose(fk_by_link_product(robot, result.q), goal, atol=1e-6)
        iterations.append(result.iterations)
    # The 4 seeds take at most 4 * 8 iterations: beyond that, random restarts solved it.
    assert max(iterations) > 4 * 8


def test_threads_share_a_robot_and_get_the_sequential_answers():
    # The compiled solver releases the GIL; each concurrent call must use its own scratch data.
    robot = puma560()
    goals = _goals(robot, 40, seed=23)
    expected = [ikine_solve(robot, goal).q for goal in goals]
    with ThreadPoolExecutor(max_workers=4) as pool:
        got = list(pool.map(lambda goal: ikine_solve(robot, goal).q, goals))
    for q_expected, q_got in zip(expected, got):
        np.testing.assert_array_equal(q_got, q_expected)


def test_masked_planar_3r_trajectory_from_the_seed_table():
    # The masked path (error in {0}) without q0: position and orientation about z of a
    # planar 3R (Ej. 4.1 table, l3 > 0 adds a tool), checked by the closed form (4.10).
    robot = planar_rrr(4.0, 3.0, 1.0)
    goals = np.tile(np.eye(4), (3, 1, 1))
    phi = np.array([0.3, -0.2, 1.0])
    goals[:, 0, 0], goals[:, 0, 1] = np.cos(phi), -np.sin(phi)
    goals[:, 1, 0], goals[:, 1, 1] = np.sin(phi), np.cos(phi)
    goals[:, 0, 3], goals[:, 1, 3] = [5.0, 2.0, -1.0], [3.0, 4.0, 5.5]
    result = ikine_solve(robot, goals, mask=[1, 1, 0, 0, 0, 1])
    assert result.success.all()
    q = result.q
    px = 4.0 * np.cos(q[:, 0]) + 3.0 * np.cos(q[:, :2].sum(1)) + np.cos(q.sum(1))
    py = 4.0 * np.sin(q[:, 0]) + 3.0 * np.sin(q[:, :2].sum(1)) + np.sin(q.sum(1))
    np.testing.assert_allclose(px, goals[:, 0, 3], atol=1e-6)
    np.testing.assert_allclose(py, goals[:, 1, 3], atol=1e-6)
    np.testing.assert_allclose(np.cos(q.sum(1) - phi), 1.0, atol=1e-9)


def test_the_second_bad_pose_of_a_trajectory_is_named_and_nothing_is_solved():
    goals = np.tile(np.eye(4), (3, 1, 1))
    goals[1, 3, 3] = 2.0
    with pytest.raises(ValueError, match=r'T\[1\] is not a finite homogeneous'):
        ikine_solve(puma560(), goals)


@pytest.mark.parametrize('seed', [-1, 2 ** 64, 1.5, True])
def test_bad_seed_is_refused(seed):
    with pytest.raises(ValueError, match='seed'):
        ikine_solve(puma560(), np.eye(4), seed=seed)
