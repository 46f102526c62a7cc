"""
plan_path: every method by name on one world, the options checked, the failures said.

The room is walls round 4 x 4 m and a wall from (2, 0) to (2, 3): from (1, 1) to (3, 1) every
path goes round the wall's free end (y = 3). Its clearance is measured here with plain geometry
(the distance from each sample to each wall segment), not with the world model's queries.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.planning.planners import plan_path, PLANNER_METHODS, planner_options
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.world.shapes import make_world

WALLS = np.array([[0, 0, 4, 0], [4, 0, 4, 4], [4, 4, 0, 4], [0, 4, 0, 0], [2, 0, 2, 3]], float)
ROOM = make_world(walls=WALLS)


def _clearance(path: np.ndarray) -> float:
    """Return the least distance [m] from the path (sampled every 1 cm) to the walls."""
    samples = [a + (b - a) * t for a, b in zip(path[:-1], path[1:])
               for t in np.linspace(0.0, 1.0, max(2, int(np.hypot(*(b - a)) / 0.01) + 1))]
    points = np.array(samples)
    best = math.inf
    for x0, y0, x1, y1 in WALLS:
        d = np.array([x1 - x0, y1 - y0])
        t = np.clip(((points - [x0, y0]) @ d) / (d @ d), 0.0, 1.0)
        best = min(best, float(np.min(np.hypot(*(points - ([x0, y0] + t[:, None] * d)).T))))
    return best


@pytest.mark.parametrize('method', ['astar', 'visibility_graph', 'voronoi'])
def test_the_complete_planners_go_round_the_wall(method):
    result = plan_path(ROOM, [1.0, 1.0], [3.0, 1.0], {'method': method, 'robot_radius': 0.2})
    assert result.found, result.reason
    path = result.path[:, :2]
    assert path[0] == pytest.approx([1.0, 1.0], abs=0.1)
    assert path[-1] == pytest.approx([3.0, 1.0], abs=0.05)
    assert path[:, 1].max() > 3.0
    # Round the wall's end: at least the two tangents from the ends to (2, 3.2).
    assert result.cost >= 2.0 * math.hypot(1.0, 2.2) - 1e-9
    assert _clearance(path) >= 0.2 - 0.01   # the robot's radius (a disc grown into a 16-gon)


@pytest.mark.parametrize('method', ['potential', 'vff'])
def test_the_potential_fields_are_trapped_behind_the_wall_and_say_so(method):
    # The goal is behind the wall from the start: the attraction pulls into the wall, the
    # book's local minimum (§12.7). The planner reports it; it never returns a colliding path.
    result = plan_path(ROOM, [1.0, 1.0], [3.0, 1.0], {'method': method, 'robot_radius': 0.2})
    assert not result.found
    assert 'local minimum' in result.reason or 'collision' in result.reason


def test_every_method_is_offered():
    assert set(PLANNER_METHODS) == {'astar', 'visibility_graph', 'voronoi', 'potential', 'vff'}


def test_a_grid_world_refuses_the_geometric_planners():
    from robotica_kin.world.occupancy_grid import OccupancyGrid
    from robotica_kin.world.shapes import World
    grid = World(grid=OccupancyGrid(np.zeros((10, 10), np.int8), 0.5))
    for method in ('visibility_graph', 'voronoi'):
        result = plan_path(grid, [1.0, 1.0], [4.0, 4.0], {'method': method})
        assert not result.found and 'this world is a grid' in result.reason
    assert plan_path(grid, [1.0, 1.0], [4.0, 4.0], {'method': 'astar'}).found


@pytest.mark.parametrize('options, name', [
    ({'method': 'rrt'}, 'method'), ({'neighbours': 12}, 'neighbours'),
    ({'robot_radius': -1.0}, 'robot_radius'), ({'max_seconds': 0.0}, 'max_seconds'),
])
def test_bad_options_are_named(options, name):
    with pytest.raises(ParameterError) as info:
        planner_options(options)
    assert info.value.name == name
