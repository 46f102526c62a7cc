"""Tests of robotica_kin.world.shapes: building and validating worlds (book §12.4.3)."""

import math

import numpy as np
import pytest

from robotica_kin.world import box_polygon, make_world, validate_polygon, World, WorldError


def test_box_turned_by_a_quarter_turn():
    box = box_polygon([1.0, 2.0], [2.0, 1.0], math.pi / 2)
    np.testing.assert_allclose(box, [[1.5, 1.0], [1.5, 3.0], [0.5, 3.0], [0.5, 1.0]],
                               atol=1e-12)


def test_segments_are_walls_then_polygon_edges():
    world = make_world(walls=[[0, 0, 1, 0]], polygons=[[[2, 0], [3, 0], [3, 1]]],
                       boxes=[([0, 5], [1, 1], 0.0)], circles=[[9, 9, 1]])
    assert world.segments.shape == (8, 4)
    np.testing.assert_array_equal(world.segments[0], [0, 0, 1, 0])
    np.testing.assert_array_equal(world.segments[3], [3, 1, 2, 0])
    assert len(world.polygons) == 2
    with pytest.raises(ValueError):
        world.segments[0, 0] = 5.0       # plain data, read-only once built


def test_closing_vertex_is_dropped():
    assert validate_polygon([[0, 0], [1, 0], [1, 1], [0, 0]]).shape == (3, 2)


@pytest.mark.parametrize(('vertices', 'message'), [
    ([[0, 0], [1, 0]], 'at least 3 vertices, got 2'),
    ([[0, 0], [2, 2], [2, 0], [0, 2]], r'self-intersecting \(edges 0 and 2 cross\)'),
    ([[0, 0], [2, 0], [1, 0]], 'self-intersecting'),
    ([[0, 0], [1, 0], [1, 0], [0, 1]], 'zero length'),
    ([[0, 0], [1, math.nan], [0, 1]], 'must be finite'),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], r'shape \(n, 2\)'),
    ([['a', 0], [1, 0], [0, 1]], 'must be numbers'),
])
def test_bad_polygon(vertices, message):
    with pytest.raises(WorldError, match=message) as info:
        World(polygons=(vertices,))
    assert str(info.value).startswith('polygons[0]: ')


@pytest.mark.parametrize(('kwargs', 'message'), [
    ({'walls': [[0, 0, 1, 0], [1, 1, 1, 1]]}, r'walls\[1\]: a wall of zero length'),
    ({'walls': [[0, 0, 1]]}, r'walls: must have shape \(n, 4\)'),
    ({'circles': [[0, 0, 1], [0, 0, -1]]}, r'circles\[1\]: radius must be > 0 m, got -1.0'),
    ({'circles': [[0, 0, math.inf]]}, 'circles: must be finite'),
    ({'inflation': -0.1}, 'inflation must be >= 0 m'),
    ({'grid': np.zeros((2, 2))}, 'grid must be an OccupancyGrid'),
])
def test_bad_world(kwargs, message):
    with pytest.raises(WorldError, match=message):
        World(**kwargs)


@pytest.mark.parametrize(('box', 'message'), [
    (([0, 0], [0, 1], 0.0), r'boxes\[0\].size: width and height must be > 0 m'),
    (([0, 0, 0], [1, 1], 0.0), r'boxes\[0\].center: must have shape'),
    (([0, 0], [1, 1], math.nan), r'boxes\[0\].yaw: must be a finite angle'),
])
def test_bad_box(box, message):
    with pytest.raises(WorldError, match=message):
        make_world(boxes=[box])


def test_world_error_is_a_value_error():
    assert issubclass(WorldError, ValueError)
