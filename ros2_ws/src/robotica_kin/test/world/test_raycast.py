"""
Tests of robotica_kin.world.raycast: hand-computed hits and brute force on random worlds.

The references are independent of the vectorised kernels: exact rational arithmetic per ray and
per segment (fractions), a per-ray, per-circle quadratic in plain Python, and, for the grid,
the same cells cast as square polygons by the segment method.
"""

from fractions import Fraction
import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world import cast_rays, OccupancyGrid, World
from robotica_kin.world.queries import grow
from robotica_kin.world.shapes import box_polygon


def brute_force_segments(segments, origin, angle, max_range):
    """Return the range to the nearest segment, by exact rationals on the float inputs."""
    ox, oy = Fraction(origin[0]), Fraction(origin[1])
    dx, dy = Fraction(math.cos(angle)), Fraction(math.sin(angle))
    best = math.inf
    for x1, y1, x2, y2 in segments:
        ax, ay = Fraction(x1), Fraction(y1)
        ex, ey = Fraction(x2) - ax, Fraction(y2) - ay
        denom = dx * ey - dy * ex
        if denom == 0:
            continue
        wx, wy = ax - ox, ay - oy
        t = (wx * ey - wy * ex) / denom
        s = (wx * dy - wy * dx) / denom
        if t >= 0 and 0 <= s <= 1:
            best = min(best, float(t))
    return best if best <= max_range else math.inf


def brute_force_circles(circles, origin, angle):
    best = math.inf
    dx, dy = math.cos(angle), math.sin(angle)
    for cx, cy, r in circles:
        fx, fy = origin[0] - cx, origin[1] - cy
        b = fx * dx + fy * dy
        c = fx * fx + fy * fy - r * r
        disc = b * b - c
        if disc < 0:
            continue
        for t in sorted((-b - math.sqrt(disc), -b + math.sqrt(disc))):
            if t >= 0:
                best = min(best, t)
                break
    return best


def test_ray_at_45_degrees_to_a_wall():
    world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    hits = cast_rays(world, [0.0, 0.0], [math.pi / 4])
    assert hits.ranges[0] == pytest.approx(2.0 * math.sqrt(2.0), rel=1e-12)
    assert hits.incidence[0] == pytest.approx(math.pi / 4, rel=1e-12)
    np.testing.assert_allclose(hits.points[0], [2.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(hits.normals[0], [-1.0, 0.0], atol=1e-12)
    assert hits.hit[0]


def test_normal_faces_the_origin_from_either_side():
    world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    hits = cast_rays(world, [[0.0, 0.0], [4.0, 0.0]], [0.0, math.pi])
    np.testing.assert_allclose(hits.normals, [[-1.0, 0.0], [1.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(hits.ranges, [2.0, 2.0])
    np.testing.assert_allclose(hits.incidence, [0.0, 0.0], atol=1e-7)


def test_circle_head_on_and_from_inside():
    world = World(circles=[[5.0, 0.0, 1.0]])
    hits = cast_rays(world, [[0.0, 0.0], [5.0, 0.0]], [0.0, math.pi / 2])
    np.testing.assert_allclose(hits.ranges, [4.0, 1.0])
    np.testing.assert_allclose(hits.normals[0], [-1.0, 0.0], atol=1e-12)
    # From inside the disc the ray meets its boundary; the normal still faces the origin.
    np.testing.assert_allclose(hits.normals[1], [0.0, -1.0], atol=1e-12)


def test_nothing_within_max_range():
    world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    hits = cast_rays(world, [0.0, 0.0], [0.0, math.pi], max_range=1.5)
    assert not hits.hit.any()
    assert np.isinf(hits.ranges).all()
    assert np.isnan(hits.points).all() and np.isnan(hits.incidence).all()


def test_sonar_ring_in_a_square_room():
    room = World(polygons=(box_polygon([0.0, 0.0], [4.0, 4.0]),))
    angles = np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False)
    origins = 0.2 * np.column_stack([np.cos(angles), np.sin(angles)])
    hits = cast_rays(room, origins, angles, max_range=10.0)
    expected = [brute_force_segments(room.segments, o, a, 10.0) for o, a in zip(origins, angles)]
    np.testing.assert_allclose(hits.ranges, expected, rtol=1e-12)
    assert hits.ranges[0] == pytest.approx(1.8)
    assert hits.ranges[1] == pytest.approx(2.0 * math.sqrt(2.0) - 0.2)


coordinate = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 30), multi=st.booleans())
def test_segments_against_exact_rationals(seed, n, multi):
    rng = np.random.default_rng(seed)
    segments = rng.uniform(-10.0, 10.0, (n, 4))
    angles = rng.uniform(-math.pi, math.pi, 40)
    origins = rng.uniform(-10.0, 10.0, (40, 2)) if multi else rng.uniform(-10.0, 10.0, 2)
    hits = cast_rays(World(walls=segments), origins, angles, max_range=15.0)
    per_ray = origins if multi else [origins] * len(angles)
    expected = [brute_force_segments(segments, o, a, 15.0) for o, a in zip(per_ray, angles)]
    np.testing.assert_allclose(hits.ranges, expected, rtol=1e-9, atol=1e-9)
    finite = np.isfinite(hits.ranges)
    np.testing.assert_allclose(np.linalg.norm(hits.normals[finite], axis=1), 1.0)
    assert ((hits.incidence[finite] >= 0.0) & (hits.incidence[finite] <= math.pi / 2)).all()


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), m=st.integers(1, 20))
def test_circles_against_a_plain_loop(seed, m):
    rng = np.random.default_rng(seed)
    circles = np.column_stack([rng.uniform(-10.0, 10.0, (m, 2)), rng.uniform(0.1, 3.0, m)])
    origin = rng.uniform(-10.0, 10.0, 2)
    angles = rng.uniform(-math.pi, math.pi, 50)
    hits = cast_rays(World(circles=circles), origin, angles)
    expected = [brute_force_circles(circles, origin, a) for a in angles]
    np.testing.assert_allclose(hits.ranges, expected, rtol=1e-9, atol=1e-9)
    # Each hit point lies on a circle.
    on = hits.points[hits.hit]
    gaps = np.abs(np.hypot(on[:, None, 0] - circles[:, 0], on[:, None, 1] - circles[:, 1])
                  - circles[:, 2]).min(axis=1)
    assert (gaps < 1e-9).all()


def grid_as_boxes(grid):
    """Return the occupied cells of an axis-aligned grid as square polygons."""
    rows, cols = np.nonzero(grid.occupied)
    centres = grid.cell_to_world(np.column_stack([cols, rows]))
    return World(polygons=tuple(box_polygon(c, [grid.resolution] * 2) for c in centres))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), density=st.floats(0.02, 0.3))
def test_grid_against_its_cells_as_polygons(seed, density):
    rng = np.random.default_rng(seed)
    data = np.where(rng.random((12, 15)) < density, 100, 0).astype(np.int8)
    grid = OccupancyGrid(data, 0.25, (-1.0, 0.5, 0.0))
    origin = rng.uniform([-2.0, -0.5], [3.5, 4.5])
    angles = rng.uniform(-math.pi, math.pi, 60)
    hits = cast_rays(World(grid=grid), origin, angles, max_range=6.0)
    reference = cast_rays(grid_as_boxes(grid), origin, angles, max_range=6.0)
    start = grid.world_to_cell([origin])[0]
    if grid.inside([start])[0] and grid.occupied[start[1], start[0]]:
        np.testing.assert_array_equal(hits.ranges, 0.0)
    else:
        np.testing.assert_allclose(hits.ranges, reference.ranges, rtol=1e-9, atol=1e-9)
        h = hits.hit
        np.testing.assert_allclose(np.abs(hits.normals[h]), np.abs(reference.normals[h]),
                                   atol=1e-9)


def test_rotated_grid_matches_a_rotated_wall():
    # One column of occupied cells in a grid turned by 30°: its face is the line u = 4 cells.
    yaw = math.pi / 6
    data = np.zeros((40, 10), np.int8)
    data[:, 4] = 100
    grid = OccupancyGrid(data, 0.1, (0.0, 0.0, yaw))
    face = np.array([[0.4, 0.0], [0.4, 4.0]]) @ np.array(
        [[math.cos(yaw), math.sin(yaw)], [-math.sin(yaw), math.cos(yaw)]])
    wall = World(walls=[face.ravel()])
    origin = grid.cell_to_world([[1, 20]])[0]
    angles = yaw + np.linspace(-1.0, 1.0, 21)
    np.testing.assert_allclose(cast_rays(World(grid=grid), origin, angles).ranges,
                               cast_rays(wall, origin, angles).ranges, rtol=1e-9)


def test_grid_start_in_an_occupied_cell_has_range_zero():
    grid = OccupancyGrid(np.full((3, 3), 100, np.int8), 1.0)
    hits = cast_rays(World(grid=grid), [1.5, 1.5], [0.0, 1.0])
    np.testing.assert_array_equal(hits.ranges, [0.0, 0.0])


def test_unknown_and_outside_cells_are_free():
    grid = OccupancyGrid(np.full((3, 3), -1, np.int8), 1.0)
    hits = cast_rays(World(grid=grid), [-5.0, 1.5], [0.0], max_range=20.0)
    assert not hits.hit[0]


def test_grown_world_is_cast_against_capsules():
    world = grow(World(walls=[[2.0, -1.0, 2.0, 1.0]], circles=[[0.0, 5.0, 1.0]]), 0.5)
    hits = cast_rays(world, [0.0, 0.0], [0.0, math.pi / 2])
    np.testing.assert_allclose(hits.ranges, [1.5, 3.5])
    # Past the wall's end, the ray meets the end cap: x = 2 - sqrt(0.5² - 0.3²) = 1.6.
    cap = cast_rays(world, [0.0, 1.3], [0.0])
    assert cap.ranges[0] == pytest.approx(1.6)
    np.testing.assert_allclose(cap.normals[0], [-0.8, 0.6], atol=1e-12)


@pytest.mark.parametrize(('origin', 'angles', 'max_range', 'message'), [
    ([0.0, 0.0, 0.0], [0.0], 1.0, 'origin must have shape'),
    ([[0.0, 0.0]] * 3, [0.0, 1.0], 1.0, 'origin must have shape'),
    ([0.0, 0.0], [[0.0]], 1.0, 'angles must have shape'),
    ([0.0, math.nan], [0.0], 1.0, 'must be finite'),
    ([0.0, 0.0], [0.0], 0.0, 'max_range must be > 0'),
])
def test_bad_input_raises(origin, angles, max_range, message):
    with pytest.raises(ValueError, match=message):
        cast_rays(World(), origin, angles, max_range)


def test_unbounded_range_reports_misses():
    hits = cast_rays(World(walls=[[2.0, -1.0, 2.0, 1.0]]), [0.0, 0.0], [0.0, math.pi])
    np.testing.assert_array_equal(hits.hit, [True, False])
