"""
Potential-field planners (book §12.7): the goal reached in the open, the U-shaped trap reported.

The trap is the geometry of scenarios/potential_trap.yaml (robotica_sim): a U of walls that
opens towards the robot between it and the goal. Clearances are computed here from the test's
own obstacles (walls as points 1 mm apart in a k-d tree).
"""
import itertools
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.reactive import GeneralisedPotentialParams, VirtualForceFieldParams
from robotica_ctrl.planning import SearchBudget
from robotica_ctrl.planning.potential_planner import potential_planner, PotentialPlannerParams
from robotica_kin.world import OccupancyGrid, World
from scipy.spatial import cKDTree

U_WALLS = [[3.0, -1.0, 3.0, 1.0], [3.0, 1.0, 1.8, 1.0], [3.0, -1.0, 1.8, -1.0]]
KROGH = GeneralisedPotentialParams()
VFF = VirtualForceFieldParams(repulsive_gain=0.02, window_radius=1.0)   # points every 0.1 m
LAWS = pytest.mark.parametrize('law', [KROGH, VFF], ids=['potential', 'vff'])


def wall_distance(points, walls, step=1e-3):
    """Return the distance to walls sampled every ``step``: within step / 2 of the exact one."""
    dense = np.vstack([np.linspace(w[:2], w[2:], int(np.hypot(w[2] - w[0], w[3] - w[1]) / step)
                                   + 2) for w in np.asarray(walls, float)])
    return cKDTree(dense).query(points)[0] - 0.5 * step


@LAWS
def test_an_open_world_is_crossed_straight_to_the_goal(law):
    plan = potential_planner(World(), [0.0, 0.0], [6.0, 0.0], law)
    assert plan.found, plan.reason
    assert plan.path[-1].tolist() == [6.0, 0.0]
    assert plan.cost == pytest.approx(6.0, abs=1e-9)
    assert np.abs(plan.path[:, 1]).max() == 0.0
    # 0.5 m/s for 0.1 s a step, until the first pose within the goal tolerance.
    poses = plan.details['poses']
    assert np.allclose(np.diff(poses[:, 0]), 0.05)
    d = 6.0 - poses[:, 0]
    assert d[-2] > law.goal_tolerance >= d[-1]
    assert plan.details['trap'] is None and len(poses) == plan.expansions + 1


@LAWS
def test_an_obstacle_beside_the_way_is_avoided_with_clearance(law):
    circles = np.array([[3.0, 0.3, 0.5], [4.5, -0.6, 0.3]])
    params = PotentialPlannerParams(robot_radius=0.2)
    plan = potential_planner(World(circles=circles), [0.0, 0.0, 0.0], [6.0, 0.0], law, params)
    assert plan.found, plan.reason
    assert np.hypot(*(plan.path[-1] - [6.0, 0.0])) == 0.0
    poses = plan.details['poses']
    gaps = np.hypot(poses[:, None, 0] - circles[:, 0], poses[:, None, 1] - circles[:, 1])
    assert (gaps - circles[:, 2]).min() > 0.2
    assert plan.cost > 6.0


@LAWS
def test_the_u_shaped_trap_is_reported_with_its_position(law):
    plan = potential_planner(World(walls=U_WALLS), [0.0, 0.0, 0.0], [6.0, 0.0], law)
    assert not plan.found and plan.path is None
    assert plan.reason.startswith('local minimum of the ')
    x, y = plan.details['trap']
    assert 1.8 < x < 3.0 - 0.2 and abs(y) < 1.0 - 0.2          # inside the U
    assert f'trapped at ({x:.3f}, {y:.3f}) m' in plan.reason
    assert f'{math.hypot(6.0 - x, y):.3f} m from the goal' in plan.reason
    poses = plan.details['poses']
    assert wall_distance(poses[:, :2], U_WALLS).min() > 0.2     # no contact on the way
    assert plan.expansions == len(poses) - 1 < 1000


def test_the_progress_window_catches_a_dithering_robot():
    params = PotentialPlannerParams(stall_steps=20, min_progress=0.05)
    plan = potential_planner(World(walls=U_WALLS), [0.0, 0.0, 0.0], [6.0, 0.0], KROGH, params)
    assert 'the goal came ' in plan.reason and 'in the last 20 steps, less than 0.05 m' in \
        plan.reason
    d = np.hypot(*(plan.details['poses'][:, :2] - [6.0, 0.0]).T)
    assert d[-21] - d[-1] < 0.05 and (d[:-21] - d[20:-1] >= 0.05).all()


@pytest.mark.parametrize('law', [GeneralisedPotentialParams(repulsive_gain=1e-4),
                                 VirtualForceFieldParams(repulsive_gain=1e-6)],
                         ids=['potential', 'vff'])
def test_a_law_too_weak_to_avoid_a_wall_ends_in_a_reported_collision(law):
    walls = [[3.0, -2.0, 3.0, 2.0]]
    plan = potential_planner(World(walls=walls), [0.0, 0.0, 0.0], [6.0, 0.0], law)
    assert not plan.found and plan.reason.startswith('collision: the ')
    assert 'drives a disc of 0.2 m into an obstacle at (2.800, ' in plan.reason
    # The run stops before the contact: its last pose at most touches (x = 2.8 m).
    assert wall_distance(plan.details['poses'][:, :2], walls).min() > 0.2 - 1e-3


def test_a_grid_world_is_sensed_by_its_occupied_cells():
    data = np.zeros((40, 80), np.int8)
    data[15:25, 30:34] = 100                          # a block 0.4 x 1 m ahead
    world = World(grid=OccupancyGrid(data, 0.1, (-1.0, -2.0, 0.0)))
    for law in (KROGH, VFF):
        plan = potential_planner(world, [0.0, 0.3, 0.0], [6.0, 0.0], law)
        assert plan.found, plan.reason
        cells = plan.details['poses'][:, :2]
        u, v = (cells[:, 0] + 1.0) / 0.1, (cells[:, 1] + 2.0) / 0.1
        gap = np.hypot(np.maximum.reduce([30 - u, u - 34, 0 * u]),
                       np.maximum.reduce([15 - v, v - 25, 0 * v])) * 0.1
        assert gap.min() > 0.2


@pytest.mark.parametrize('start, goal, words', [
    ([1.9, 0.0], [6.0, 0.0], 'the start is in collision: a disc of 0.2 m at (1.9, 0) m'),
    ([0.0, 0.0], [3.1, 0.0], 'the goal is in an obstacle: a disc of 0.2 m at (3.1, 0) m'),
])
def test_ends_in_obstacles_are_reported(start, goal, words):
    world = World(walls=[[2.0, -1.0, 2.0, 1.0]], circles=[[3.0, 0.0, 0.05]])
    plan = potential_planner(world, start, goal)
    assert not plan.found and plan.reason.startswith(words)


def test_the_budget_is_reported():
    plan = potential_planner(World(), [0.0, 0.0], [6.0, 0.0],
                             budget=SearchBudget(max_expansions=10))
    assert plan.reason == 'the search budget was exhausted: 10 expansions, the most allowed'
    assert len(plan.details['poses']) == 11
    ticks = itertools.count()
    slow = potential_planner(World(), [0.0, 0.0], [60.0, 0.0],
                             budget=SearchBudget(max_seconds=10.0),
                             clock=lambda: float(next(ticks)))
    assert slow.reason.startswith('the search budget was exhausted: 11 s, more than the 10 s')


def test_the_field_points_at_the_goal_in_the_open():
    params = PotentialPlannerParams(field_step=1.0)
    plan = potential_planner(World(circles=[[20.0, 20.0, 0.5]]), [0.0, 0.0], [4.0, 0.0],
                             KROGH, params)
    field = plan.details['field']
    assert field.shape[1] == 3 and len(field) > 20
    bearing = np.arctan2(0.0 - field[:, 1], 4.0 - field[:, 0])
    away = np.hypot(field[:, 0] - 4.0, field[:, 1]) > 0.1
    assert np.allclose(np.angle(np.exp(1j * (field[away, 2] - bearing[away]))), 0.0)


@pytest.mark.parametrize('kwargs, words', [
    ({'law': 'vff'}, 'law must be GeneralisedPotentialParams or VirtualForceFieldParams'),
    ({'params': {}}, 'params must be PotentialPlannerParams'),
    ({'start': [0.0, math.nan]}, 'start must be a finite point'),
    ({'goal': [0.0]}, 'goal must be a finite point'),
])
def test_bad_input_is_refused(kwargs, words):
    call = {'world': World(), 'start': [0.0, 0.0], 'goal': [1.0, 1.0], **kwargs}
    with pytest.raises(ValueError, match=words):
        potential_planner(**call)


@pytest.mark.parametrize('field, value', [('step', 0.0), ('stall_steps', 1),
                                          ('field_step', -1.0), ('robot_radius', math.inf)])
def test_bad_tunables_are_refused(field, value):
    with pytest.raises(ValueError, match=field):
        PotentialPlannerParams(**{field: value})
