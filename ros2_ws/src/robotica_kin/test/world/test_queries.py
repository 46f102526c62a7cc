"""
Tests of robotica_kin.world.queries: clearance, growing (book §12.4.4) and footprint contact.

References: plain loops over every obstacle and every occupied cell, hand-computed contacts,
and the no-tunnelling case (10 m in one step through a 1 cm wall).
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world import OccupancyGrid, World
from robotica_kin.world.queries import (
    distance_to_obstacles, footprint_collides, footprint_distance, grow, point_in_obstacle,
    swept_collision)
from robotica_kin.world.shapes import box_polygon

SQUARE = [[-0.3, -0.2], [0.3, -0.2], [0.3, 0.2], [-0.3, 0.2]]
THIN_WALL = World(polygons=(box_polygon([5.0, 0.0], [0.01, 4.0]),))


def square_distance_loop(grid, point):
    """Return the distance to the nearest occupied square, one cell at a time."""
    best = math.inf
    (u, v), = grid.world_to_grid([point])
    for row in range(grid.height):
        for col in range(grid.width):
            if grid.occupied[row, col]:
                du = max(col - u, 0.0, u - col - 1.0)
                dv = max(row - v, 0.0, v - row - 1.0)
                best = min(best, math.hypot(du, dv) * grid.resolution)
    return best


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), yaw=st.floats(-math.pi, math.pi))
def test_grid_distance_against_every_cell(seed, yaw):
    rng = np.random.default_rng(seed)
    data = np.where(rng.random((10, 12)) < 0.08, 100, 0).astype(np.int8)
    grid = OccupancyGrid(data, 0.3, (0.5, -0.5, yaw))
    points = rng.uniform(-4.0, 4.0, (15, 2))
    expected = [square_distance_loop(grid, p) for p in points]
    np.testing.assert_allclose(distance_to_obstacles(World(grid=grid), points), expected,
                               rtol=1e-9, atol=1e-12)


def test_distance_inside_and_outside_polygons_and_circles():
    world = World(polygons=(box_polygon([0.0, 0.0], [2.0, 2.0]),), circles=[[5.0, 0.0, 1.0]])
    d = distance_to_obstacles(world, [[0.0, 0.0], [3.0, 0.0], [0.0, 4.0], [5.0, 0.5]])
    np.testing.assert_allclose(d, [0.0, 1.0, 3.0, 0.0])
    np.testing.assert_array_equal(point_in_obstacle(world, [[0.5, 0.5], [2.5, 0.0]]),
                                  [True, False])


def test_grow_is_a_robot_radius():
    world = World(walls=[[0.0, -1.0, 0.0, 1.0]])
    grown = grow(world, 0.4)
    np.testing.assert_array_equal(point_in_obstacle(grown, [[0.39, 0.0], [0.41, 0.0],
                                                            [0.0, 1.39], [0.3, 1.3]]),
                                  [True, False, True, False])
    np.testing.assert_allclose(distance_to_obstacles(grown, [[1.0, 0.0]]), [0.6])
    assert grow(grown, 0.1).inflation == pytest.approx(0.5)


def test_grown_grid_is_conservative():
    data = np.zeros((21, 21), np.int8)
    data[10, 10] = 100
    grid = OccupancyGrid(data, 0.1)
    grown = grow(World(grid=grid), 0.25).grid
    # Every point within 0.25 m of the occupied square is in an occupied cell of the grown grid.
    rng = np.random.default_rng(3)
    points = rng.uniform(0.0, 2.1, (2000, 2))
    near = distance_to_obstacles(World(grid=grid), points) <= 0.25
    assert point_in_obstacle(World(grid=grown), points[near]).all()
    # And no cell is marked farther than one cell diagonal beyond the growth.
    far = distance_to_obstacles(World(grid=grid), points) > 0.25 + 0.1 * math.sqrt(2.0)
    assert not point_in_obstacle(World(grid=grown), points[far]).any()


@pytest.mark.parametrize('footprint', [0.25, SQUARE])
def test_no_tunnelling_through_a_thin_wall(footprint):
    fraction = swept_collision(THIN_WALL, footprint, [0.0, 0.0, 0.0], [10.0, 0.0, 0.0])
    assert fraction is not None
    contact_x = 10.0 * fraction
    assert contact_x == pytest.approx(4.995 - (0.25 if footprint == 0.25 else 0.3), abs=1e-3)
    assert not footprint_collides(THIN_WALL, footprint, [contact_x - 2e-3, 0.0, 0.0])
    assert footprint_collides(THIN_WALL, footprint, [contact_x + 2e-3, 0.0, 0.0])


def test_no_tunnelling_through_a_thin_grid_wall():
    data = np.zeros((40, 200), np.int8)
    data[:, 100] = 100                  # one 5 cm column at x = 5.00..5.05
    world = World(grid=OccupancyGrid(data, 0.05, (0.0, -1.0, 0.0)))
    for footprint in (0.25, SQUARE):
        fraction = swept_collision(world, footprint, [0.0, 0.0, 0.0], [10.0, 0.0, 0.0])
        reach = 0.25 if footprint == 0.25 else 0.3
        assert fraction == pytest.approx((5.0 - reach) / 10.0, abs=2e-4)


def test_free_step_and_contact_at_start():
    assert swept_collision(THIN_WALL, 0.25, [0.0, 0.0, 0.0], [4.0, 0.0, 0.0]) is None
    assert swept_collision(THIN_WALL, SQUARE, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]) is None
    assert swept_collision(THIN_WALL, 0.25, [4.9, 0.0, 0.0], [0.0, 0.0, 0.0]) == 0.0


def test_rotation_in_place_touches_a_wall():
    # A 0.6 x 0.4 box whose corner reaches sqrt(0.3² + 0.2²) = 0.3606 m when turned.
    wall = World(walls=[[0.34, -1.0, 0.34, 1.0]])
    fraction = swept_collision(wall, SQUARE, [0.0, 0.0, -math.pi / 2], [0.0, 0.0, 0.0])
    assert fraction is not None
    theta = -math.pi / 2 + fraction * math.pi / 2
    assert footprint_distance(wall, SQUARE, [0.0, 0.0, theta]) <= 1e-4
    assert not footprint_collides(wall, SQUARE, [0.0, 0.0, theta - 1e-3])


def test_footprint_distance_by_hand():
    wall = World(walls=[[2.0, -1.0, 2.0, 1.0]], circles=[[0.0, 3.0, 0.5]])
    assert footprint_distance(wall, SQUARE, [0.0, 0.0, 0.0]) == pytest.approx(1.7)
    assert footprint_distance(wall, SQUARE, [0.0, 2.0, 0.0]) == pytest.approx(0.3)
    # A wall entirely inside the footprint collides though no edge crosses it.
    inside = World(walls=[[0.0, 0.0, 0.1, 0.0]])
    assert footprint_collides(inside, SQUARE, [0.0, 0.0, 0.0])


@pytest.mark.parametrize(('call', 'message'), [
    (lambda: swept_collision(World(), -1.0, [0, 0, 0], [1, 0, 0]), 'radius must be > 0'),
    (lambda: swept_collision(World(), [[0, 0], [1, 0]], [0, 0, 0], [1, 0, 0]),
     'footprint: a polygon needs at least 3 vertices'),
    (lambda: swept_collision(World(), 0.1, [0, 0], [1, 0, 0]), 'pose_from must be'),
    (lambda: distance_to_obstacles(World(), [0.0, 1.0]), 'shape \\(k, 2\\)'),
    (lambda: grow(World(), -0.1), 'radius must be >= 0'),
])
def test_bad_input(call, message):
    with pytest.raises(ValueError, match=message):
        call()
