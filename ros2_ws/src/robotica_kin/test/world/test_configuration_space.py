"""
Tests of robotica_kin.world.configuration_space (book §12.4.5, §12.6.3, figs. 12.5-12.15).

References: SciPy's ConvexHull of every difference b - a (the Minkowski sum by brute force);
a separating-axis overlap test of two convex polygons and a segment-polygon test written here;
the World's own footprint collision test (queries) for the rotating rectangle; SciPy's
connected-component labelling for the φ-slices' free space.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world import World
from robotica_kin.world.configuration_space import (
    arm_2r_cspace, convex_polygon, cspace_grid, cspace_obstacle, cspace_obstacles,
    minkowski_sum, phi_slice, swept_polygon)
from robotica_kin.world.queries import footprint_collides
from robotica_kin.world.shapes import box_polygon
from scipy.ndimage import label
from scipy.spatial import ConvexHull


def random_convex(rng, count, scale=1.0, centre=(0.0, 0.0)):
    """Return a convex polygon: the hull of ``count`` random points (CCW, from Qhull)."""
    cloud = rng.uniform(-scale, scale, (count, 2)) + centre
    return cloud[ConvexHull(cloud).vertices]


def canonical(v):
    """Return CCW vertices rolled to start at the lowest, then leftmost, one."""
    area = np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])
    v = v if area > 0 else v[::-1]
    k = np.lexsort((v[:, 0], v[:, 1]))[0]
    return np.roll(v, -k, axis=0)


def overlap(p, q):
    """Return whether two closed convex polygons meet: no separating edge normal."""
    for poly in (p, q):
        edges = np.roll(poly, -1, axis=0) - poly
        for n in np.column_stack([edges[:, 1], -edges[:, 0]]):
            if (p @ n).max() < (q @ n).min() or (q @ n).max() < (p @ n).min():
                return False
    return True


def inside_convex(v, points, tol=0.0):
    """Return whether points lie in the CCW convex polygon v (within tol)."""
    edges = np.roll(v, -1, axis=0) - v
    rel = points[:, None, :] - v[None]
    cross = edges[None, :, 0] * rel[..., 1] - edges[None, :, 1] * rel[..., 0]
    return (cross >= -tol * np.hypot(*edges.T)).all(axis=1)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_a=st.integers(3, 9), n_b=st.integers(3, 12))
def test_minkowski_c_obstacle_properties(seed, n_a, n_b):
    rng = np.random.default_rng(seed)
    robot = random_convex(rng, n_a, 0.8)
    obstacle = random_convex(rng, n_b, 1.5, (3.0, -1.0))
    c_obstacle = cspace_obstacle(obstacle, robot)
    a, b, ba = len(convex_polygon(robot)), len(convex_polygon(obstacle)), len(c_obstacle)
    assert b <= ba <= a + b                                 # the book's vertex-count bound
    differences = (obstacle[:, None, :] - robot[None, :, :]).reshape(-1, 2)
    hull = canonical(differences[ConvexHull(differences).vertices])
    assert len(hull) == ba
    np.testing.assert_allclose(canonical(c_obstacle), hull, atol=1e-9)
    edges = np.roll(c_obstacle, -1, axis=0) - c_obstacle
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    assert (turns > 0).all()                                # strictly convex, CCW
    if inside_convex(canonical(robot), np.zeros((1, 2)))[0]:   # r in A  =>  B in B_A
        assert inside_convex(c_obstacle, obstacle, 1e-9).all()
    # The robot placed at t meets the obstacle exactly when t lies in the C-obstacle.
    for t in rng.uniform(-2.0, 6.0, (40, 2)):
        in_c = inside_convex(c_obstacle, t[None])[0]
        assert overlap(robot + t, obstacle) == in_c


def test_book_shaped_example_and_parallel_edges():
    # A square B and a triangle A (r at a vertex): B_A has five vertices (fig. 12.6).
    c_obstacle = cspace_obstacle(box_polygon([2.5, 0.5], [1.0, 1.0]), [[0, 0], [1, 0], [0, 1]])
    assert len(c_obstacle) == 5
    # Two squares: every edge of A is parallel to one of B, so n_BA = n_B = 4.
    square = cspace_obstacle(box_polygon([0, 0], [2, 2]), box_polygon([0, 0], [1, 1]))
    np.testing.assert_allclose(canonical(square),
                               [[-1.5, -1.5], [1.5, -1.5], [1.5, 1.5], [-1.5, 1.5]])
    # A wall (a segment) and a square robot: a rectangle.
    wall = cspace_obstacle([[0, 0], [4, 0]], box_polygon([0, 0], [1, 1]))
    np.testing.assert_allclose(canonical(wall), [[-0.5, -0.5], [4.5, -0.5], [4.5, 0.5],
                                                 [-0.5, 0.5]])
    # The robot turned by theta: the C-obstacle of the turned polygon.
    turned = cspace_obstacle(box_polygon([0, 0], [2, 2]), [[0, 0], [1, 0], [0, 1]], math.pi)
    np.testing.assert_allclose(canonical(turned), canonical(minkowski_sum(
        box_polygon([0, 0], [2, 2]), [[0, 0], [1, 0], [0, 1]])), atol=1e-12)


def test_non_convex_robot_is_the_union_of_its_parts():
    rng = np.random.default_rng(11)
    parts = [box_polygon([0.5, 0.0], [1.0, 0.2]), box_polygon([0.0, 0.5], [0.2, 1.0])]  # an L
    obstacles = [random_convex(rng, 6, 0.7, (2.0, 2.0)), [[3.0, -1.0], [3.5, 1.0]]]
    c_obstacles = cspace_obstacles(obstacles, parts)
    assert len(c_obstacles) == 4
    for t in rng.uniform(-1.0, 5.0, (300, 2)):
        in_c = any(inside_convex(c, t[None])[0] for c in c_obstacles)
        hits = any(overlap(part + t, np.asarray(b, dtype=float)) for part in parts
                   for b in obstacles)
        assert hits == in_c


ROBOT = box_polygon([0.0, 0.0], [2.0, 0.6])          # 2.0 m long (its x axis), 0.6 m wide
ROOM = [box_polygon([5.0, -0.1], [10.4, 0.2]), box_polygon([5.0, 10.1], [10.4, 0.2]),
        box_polygon([-0.1, 5.0], [0.2, 10.4]), box_polygon([10.1, 5.0], [0.2, 10.4]),
        box_polygon([2.2, 5.0], [4.4, 0.4]), box_polygon([7.8, 5.0], [4.4, 0.4])]
START, GOAL = (2.0, 2.0), (8.0, 8.0)                 # below and above a gap 1.2 m wide


def connected(grid, a, b):
    """Return whether cells of points a and b lie in one 4-connected free component."""
    components, _ = label(~grid.occupied)
    (ca, ra), (cb, rb) = grid.world_to_cell([a, b])
    return components[ra, ca] != 0 and components[ra, ca] == components[rb, cb]


def test_rotating_rectangle_passes_the_gap_only_across():
    world = World(polygons=tuple(ROOM))
    at_zero = cspace_grid(phi_slice(ROOM, ROBOT, 0.0, 0.0), [0, 0, 10, 10], 0.05)
    across = cspace_grid(phi_slice(ROOM, ROBOT, 0.5 * math.pi, 0.5 * math.pi),
                         [0, 0, 10, 10], 0.05)
    assert not connected(at_zero, START, GOAL)        # fig. 12.13: no solution at φ = 0
    assert connected(across, START, GOAL)             # fig. 12.15: a solution at φ = π/2
    # Independently, by the World's footprint test: at φ = 0 the robot collides wherever its
    # reference point crosses the dividing wall's line; at φ = π/2 the straight route through
    # the gap is free.
    assert all(footprint_collides(world, ROBOT, [x, 5.0, 0.0]) for x in np.arange(0, 10, 0.01))
    route = ([(x, 2.0) for x in np.arange(2.0, 5.0, 0.02)]
             + [(5.0, y) for y in np.arange(2.0, 8.0, 0.02)]
             + [(x, 8.0) for x in np.arange(5.0, 8.0, 0.02)])
    assert not any(footprint_collides(world, ROBOT, [x, y, 0.5 * math.pi]) for x, y in route)
    # A slice of width 20° about π/2 still passes (conservative sweep), one about 0 does not.
    wide = cspace_grid(phi_slice(ROOM, ROBOT, math.radians(80), math.radians(100)),
                       [0, 0, 10, 10], 0.05)
    assert connected(wide, START, GOAL)
    assert not connected(cspace_grid(phi_slice(ROOM, ROBOT, -0.2, 0.2), [0, 0, 10, 10], 0.05),
                         START, GOAL)
    # Every free cell of a slice is free for the robot at its centre (grid soundness).
    rng = np.random.default_rng(2)
    free = np.argwhere(~across.occupied)
    for row, col in free[rng.choice(len(free), 300, replace=False)]:
        centre = across.cell_to_world([[col, row]])[0]
        assert not footprint_collides(world, ROBOT, [*centre, 0.5 * math.pi])


def test_swept_polygon_encloses_every_turn():
    rng = np.random.default_rng(4)
    for _ in range(10):
        robot = random_convex(rng, 7, 1.0)
        low = rng.uniform(-math.pi, math.pi)
        span = rng.uniform(0.0, 0.9 * math.pi)
        swept = swept_polygon(robot, low, low + span)
        for phi in np.linspace(low, low + span, 60):
            c, s = math.cos(phi), math.sin(phi)
            turned = robot @ np.array([[c, s], [-s, c]])
            assert inside_convex(swept, turned, 1e-9).all()
    with pytest.raises(ValueError, match='phi_high - phi_low'):
        swept_polygon(ROBOT, 0.0, math.pi)


def segment_meets_polygon(a, b, polygon):
    """Return whether segment a-b meets a simple polygon: an edge crossing or a point inside."""
    def orient(p, q, r):
        return np.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    def on(p, q, r):
        return min(p[0], q[0]) <= r[0] <= max(p[0], q[0]) and min(p[1], q[1]) <= r[1] <= max(
            p[1], q[1])

    n = len(polygon)
    for k in range(n):
        c, d = polygon[k], polygon[(k + 1) % n]
        o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
        if o1 != o2 and o3 != o4:
            return True
        if (o1 == 0 and on(a, b, c)) or (o2 == 0 and on(a, b, d)) or (
                o3 == 0 and on(c, d, a)) or (o4 == 0 and on(c, d, b)):
            return True
    x, y = a
    crossings = 0
    for k in range(n):
        (x1, y1), (x2, y2) = polygon[k], polygon[(k + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            crossings += 1
    return crossings % 2 == 1


ARM_OBSTACLES = [box_polygon([1.5, 0.0], [0.2, 0.2]),
                 [[-1.2, 0.8], [-0.4, 1.0], [-0.6, 1.6], [-1.0, 1.3]],
                 [[0.2, -1.6], [0.9, -1.2], [0.3, -0.9]]]


def arm_collides(theta1, theta2, lengths=(1.0, 0.8)):
    elbow = np.array([lengths[0] * math.cos(theta1), lengths[0] * math.sin(theta1)])
    tip = elbow + lengths[1] * np.array([math.cos(theta1 + theta2), math.sin(theta1 + theta2)])
    return any(segment_meets_polygon(np.zeros(2), elbow, np.asarray(p, float))
               or segment_meets_polygon(elbow, tip, np.asarray(p, float)) for p in ARM_OBSTACLES)


def test_arm_2r_grid_against_a_scalar_check():
    space = arm_2r_cspace([1.0, 0.8], ARM_OBSTACLES, cells=(72, 60))
    assert space.collision.shape == (72, 60)
    np.testing.assert_allclose(np.diff(space.theta1), 2 * math.pi / 72)
    assert space.theta1[0] == pytest.approx(-math.pi + math.pi / 72)
    expected = [[arm_collides(t1, t2) for t2 in space.theta2] for t1 in space.theta1]
    np.testing.assert_array_equal(space.collision, expected)
    assert 0.05 < space.collision.mean() < 0.6
    # Known cells: stretched along +x the arm's tip reaches the post at 1.5 m; folded, not.
    stretched = arm_2r_cspace([1.0, 0.8], ARM_OBSTACLES, cells=(3, 3))
    assert stretched.collision[1, 1] and not arm_collides(0.0, 2.0)


def test_arm_2r_conservative_cells_are_free_throughout():
    exact = arm_2r_cspace([1.0, 0.8], ARM_OBSTACLES, cells=(48, 48))
    safe = arm_2r_cspace([1.0, 0.8], ARM_OBSTACLES, cells=(48, 48), conservative=True)
    assert (safe.collision >= exact.collision).all()
    assert safe.collision.sum() > exact.collision.sum()
    rng = np.random.default_rng(8)
    step = 2 * math.pi / 48
    free = np.argwhere(~safe.collision)
    for i, j in free[rng.choice(len(free), 200, replace=False)]:
        for _ in range(5):
            t1 = safe.theta1[i] + rng.uniform(-0.5, 0.5) * step
            t2 = safe.theta2[j] + rng.uniform(-0.5, 0.5) * step
            assert not arm_collides(t1, t2)


def test_bad_input():
    with pytest.raises(ValueError, match='not convex'):
        convex_polygon([[0, 0], [2, 0], [1, 0.5], [2, 2], [0, 2]])
    with pytest.raises(ValueError, match='robot'):
        cspace_obstacle(box_polygon([0, 0], [1, 1]), [[0, 0], [1, 0]])
    with pytest.raises(ValueError, match='segment'):
        minkowski_sum([[0, 0], [0, 0]], box_polygon([0, 0], [1, 1]))
    with pytest.raises(ValueError, match='bounds'):
        cspace_grid([], [0, 0, 0, 1], 0.1)
    with pytest.raises(ValueError, match='more than'):
        cspace_grid([], [0, 0, 1000, 1000], 0.01)
    with pytest.raises(ValueError, match='link_lengths'):
        arm_2r_cspace([1.0, -1.0], [])
    with pytest.raises(ValueError, match='cells'):
        arm_2r_cspace([1.0, 1.0], [], cells=(0, 10))
    assert not arm_2r_cspace([1.0, 1.0], [], cells=(4, 4)).collision.any()
