"""
The generalised Voronoi roadmap (book §12.6.2): every path point clears the robot's radius.

Clearances are computed here, independently of the world model's queries: the distance from
each point of the path (sampled every 5 mm, endpoints included) to every wall segment, circle
and occupied cell square of the test's world.
"""
import itertools
import math

import numpy as np
import pytest
from robotica_ctrl.planning import SearchBudget
from robotica_ctrl.planning.voronoi_roadmap import boundary_samples, voronoi_roadmap
from robotica_kin.world import World
from robotica_kin.world.rasterise import world_grid


def sample(path, step=0.005):
    out = [path[:1]]
    for a, b in zip(path[:-1], path[1:]):
        k = max(1, int(np.ceil(np.hypot(*(b - a)) / step)))
        out.append(a + (b - a) * (np.arange(1, k + 1) / k)[:, None])
    return np.vstack(out)


def wall_distance(points, walls):
    walls = np.asarray(walls, float)
    a, e = walls[:, :2], walls[:, 2:] - walls[:, :2]
    w = points[:, None, :] - a[None]
    t = np.clip((w * e).sum(-1) / (e * e).sum(-1), 0.0, 1.0)
    return np.hypot(*(w - t[..., None] * e).transpose(2, 0, 1)).min(axis=1)


def circle_distance(points, circles):
    circles = np.asarray(circles, float)
    return (np.hypot(points[:, None, 0] - circles[:, 0], points[:, None, 1] - circles[:, 1])
            - circles[:, 2]).min(axis=1)


def square_distance(points, grid):
    rows, cols = np.nonzero(grid.occupied)
    low = np.column_stack([grid.origin[0] + cols * grid.resolution,
                           grid.origin[1] + rows * grid.resolution])
    gap = np.maximum(np.maximum(low[None] - points[:, None], points[:, None] - low[None]
                                - grid.resolution), 0.0)
    return np.hypot(gap[..., 0], gap[..., 1]).min(axis=1)


def box(x0, y0, x1, y1):
    return [[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]]


# A room of two halves joined by a door 0.8 m wide (y from 1.6 to 2.4 in the wall x = 5).
ROOM = box(0, 0, 10, 4) + [[5, 0, 5, 1.6], [5, 2.4, 5, 4]]


def test_a_path_through_the_door_clears_the_radius():
    plan = voronoi_roadmap(World(walls=ROOM), [2.0, 1.0], [8.0, 1.0], robot_radius=0.3)
    assert plan.found, plan.reason
    points = sample(plan.path)
    assert wall_distance(points, ROOM).min() > 0.3
    crossing = points[np.argmin(np.abs(points[:, 0] - 5.0))]
    assert 1.9 < crossing[1] < 2.1                  # the roadmap runs through the door's middle
    assert plan.cost == pytest.approx(np.hypot(*np.diff(plan.path, axis=0).T).sum())
    assert plan.cost < 1.3 * (2 * math.hypot(3.0, 1.0))      # S, the door, G: 6.3 m
    assert len(plan.details['roadmap']) == len(plan.details['clearance']) > 0
    assert (plan.details['clearance'] > 0.3).all()


def test_a_door_narrower_than_the_robot_is_refused():
    plan = voronoi_roadmap(World(walls=ROOM), [2.0, 1.0], [8.0, 1.0], robot_radius=0.45)
    assert not plan.found
    assert plan.reason == ('the goal is unreachable: no roadmap path with a clearance above '
                           '0.45 m joins it to the start')
    assert plan.path is None and plan.expansions > 0


# A corridor 1.6 m wide that turns left, with a narrowing to 0.5 m (x = 3 to 3.5) on the way.
CORRIDOR = [[0, 0, 6, 0], [0, 1.6, 4.4, 1.6], [6, 0, 6, 6], [4.4, 1.6, 4.4, 6], [0, 0, 0, 1.6],
            [3, 0, 3, 0.55], [3.5, 0, 3.5, 0.55], [3, 0.55, 3.5, 0.55],
            [3, 1.6, 3, 1.05], [3.5, 1.6, 3.5, 1.05], [3, 1.05, 3.5, 1.05]]


def test_a_corridor_is_followed_where_it_is_wide_enough():
    plan = voronoi_roadmap(World(walls=CORRIDOR), [0.8, 0.8], [5.2, 5.0], robot_radius=0.2)
    assert plan.found, plan.reason
    assert wall_distance(sample(plan.path), CORRIDOR).min() > 0.2
    narrow = voronoi_roadmap(World(walls=CORRIDOR), [0.8, 0.8], [5.2, 5.0], robot_radius=0.3)
    assert not narrow.found and narrow.reason.startswith('the goal is unreachable')


@pytest.mark.parametrize('seed', range(4))
def test_paths_among_random_circles_clear_the_radius(seed):
    rng = np.random.default_rng(seed)
    circles = np.column_stack([rng.uniform(1, 9, (12, 2)), rng.uniform(0.3, 0.8, 12)])
    world = World(circles=circles, walls=box(-0.5, -0.5, 10.5, 10.5))
    start, goal = np.array([0.2, 0.2]), np.array([9.8, 9.8])
    plan = voronoi_roadmap(world, start, goal, robot_radius=0.15, spacing=0.15)
    if plan.found:
        points = sample(plan.path)
        assert np.minimum(circle_distance(points, circles),
                          wall_distance(points, box(-0.5, -0.5, 10.5, 10.5))).min() > 0.15
    else:
        assert plan.reason.startswith('the goal is unreachable')


def test_a_grid_world_is_planned_on_its_occupied_cells():
    grid = world_grid(World(walls=ROOM), 0.05, 0.2)
    world = World(grid=grid)
    plan = voronoi_roadmap(world, [2.0, 1.0], [8.0, 1.0], robot_radius=0.2, spacing=0.05)
    assert plan.found, plan.reason
    assert square_distance(sample(plan.path), grid).min() > 0.2
    assert len(boundary_samples(world, 0.05)) < int(grid.occupied.sum())   # the border only


def test_a_goal_in_sight_is_reached_straight():
    plan = voronoi_roadmap(World(walls=ROOM), [1.0, 1.0], [4.0, 3.0], robot_radius=0.3)
    assert plan.path.tolist() == [[1.0, 1.0], [4.0, 3.0]] and plan.cost == math.hypot(3, 2)


@pytest.mark.parametrize('start, goal, words', [
    ([5.0, 5.0], [8.0, 3.0], 'the start is in collision: (5, 5) m lies inside an obstacle'),
    ([2.0, 1.0], [9.9, 3.0], 'the goal is in an obstacle: (9.9, 3) m lies 0.1 m from an '
                             'obstacle, not more than the radius 0.3 m'),
])
def test_ends_too_close_to_an_obstacle_are_reported(start, goal, words):
    world = World(walls=ROOM, circles=[[5.0, 5.0, 0.5]])
    plan = voronoi_roadmap(world, start, goal, robot_radius=0.3)
    assert not plan.found and plan.reason == words


def test_the_budget_is_reported():
    plan = voronoi_roadmap(World(walls=ROOM), [2.0, 1.0], [8.0, 1.0],
                           budget=SearchBudget(max_expansions=10))
    assert plan.reason.startswith('the search budget was exhausted: ')
    assert plan.reason.endswith(' ridges to check, more than the 10 allowed')
    ticks = itertools.count()
    slow = voronoi_roadmap(World(walls=ROOM), [2.0, 1.0], [8.0, 1.0],
                           budget=SearchBudget(max_seconds=0.5),
                           clock=lambda: float(next(ticks)))
    assert slow.reason.startswith('the search budget was exhausted: 1 s, more than the 0.5 s')


@pytest.mark.parametrize('kwargs, words', [
    ({'robot_radius': -1.0}, 'robot_radius must be >= 0 m'),
    ({'spacing': 0.0}, 'spacing must be > 0 m'),
    ({'margin': math.nan}, 'margin must be > 0 m'),
    ({'connect': 0}, 'connect must be an integer >= 1'),
    ({'goal': [1.0]}, 'goal must be a finite point'),
])
def test_bad_input_is_refused(kwargs, words):
    call = {'world': World(walls=ROOM), 'start': [2.0, 1.0], 'goal': [8.0, 1.0], **kwargs}
    with pytest.raises(ValueError, match=words):
        voronoi_roadmap(**call)
