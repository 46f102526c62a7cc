"""
Tests of robotica_kin.world.rasterise: a world drawn as an occupancy grid.

Independent checks: every cell that a point sampled along a wall falls in is occupied (the
wall never falls between cells), and every cell whose centre is farther from all walls than
half its diagonal (computed here by a plain point-segment loop) is free.
"""
import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from robotica_kin.world import World, WorldError
from robotica_kin.world.rasterise import world_grid


def point_segment(p, a, b):
    ab, ap = b - a, p - a
    t = min(1.0, max(0.0, float(ap @ ab) / float(ab @ ab)))
    return float(np.hypot(*(ap - t * ab)))


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(*[st.floats(-3.0, 3.0)] * 4), min_size=1, max_size=4),
       st.sampled_from([0.1, 0.25, 0.5]))
def test_walls_drawn_without_gaps(walls, resolution):
    walls = [w for w in walls if math.hypot(w[2] - w[0], w[3] - w[1]) > 1e-3]
    if not walls:
        return
    grid = world_grid(World(walls=walls), resolution, 0.5)
    x0, y0, _ = grid.origin
    for x1, y1, x2, y2 in walls:
        for s in np.linspace(0.0, 1.0, 200):
            x, y = x1 + s * (x2 - x1), y1 + s * (y2 - y1)
            j, i = int((x - x0) // resolution), int((y - y0) // resolution)
            assert grid.data[i, j] == 100
    half_diagonal = resolution * math.sqrt(2.0) / 2.0
    for i in range(grid.height):
        for j in range(grid.width):
            centre = np.array([x0 + (j + 0.5) * resolution, y0 + (i + 0.5) * resolution])
            d = min(point_segment(centre, np.array(w[:2]), np.array(w[2:])) for w in walls)
            if d > half_diagonal + 1e-9:
                assert grid.data[i, j] == 0


def test_a_circle_and_the_limits():
    grid = world_grid(World(circles=[[1.0, 1.0, 0.5]]), 0.1, 0.2)
    assert grid.origin[:2] == pytest.approx((0.3, 0.3))
    centre_cell = grid.data[7, 7]     # the cell holding (1.05, 1.05), inside the disc
    assert centre_cell == 100
    assert grid.data[0, 0] == 0
    with pytest.raises(WorldError, match='no obstacle to draw'):
        world_grid(World(), 0.1)
    with pytest.raises(WorldError, match='resolution must be > 0'):
        world_grid(World(walls=[[0, 0, 1, 0]]), 0.0)
    with pytest.raises(WorldError, match='raise the resolution'):
        world_grid(World(walls=[[0, 0, 1000, 1000]]), 0.01)
