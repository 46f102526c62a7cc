"""
The visibility graph (book §12.6.2): optimal for a point among convex polygons, by brute force.

The reference is written here: a segment is free when, for every convex obstacle, some axis
(an edge normal of the polygon or the segment's normal) separates their projections or lets
them only touch (the separating-axis theorem); the shortest path is the least of all simple
paths from S to G through the free segments between S, G and the vertices (depth-first
enumeration), or Floyd-Warshall's distances on slightly larger worlds.
"""
import itertools
import math

import numpy as np
import pytest
from robotica_ctrl.planning import SearchBudget
from robotica_ctrl.planning.visibility_graph import (disc_polygon, grown_obstacles,
                                                     visibility_graph)
from robotica_kin.world import box_polygon, OccupancyGrid, World
from scipy.spatial import ConvexHull

EPS = 1e-9


def meets_interior(a, b, polygon):
    """
    Return whether the open segment a-b meets the interior of a convex polygon (SAT).

    They are disjoint when, along some axis (an edge normal of the polygon or the segment's
    normal), the open interval of the polygon's projection misses the segment's projection
    (an interval, or a point along the segment's own normal).
    """
    segment = np.array([a, b], dtype=float)
    edges = np.roll(polygon, -1, axis=0) - polygon
    d = segment[1] - segment[0]
    for axis in [np.array([-e[1], e[0]]) for e in edges] + [np.array([-d[1], d[0]])]:
        if np.hypot(*axis) == 0.0:
            continue
        axis = axis / np.hypot(*axis)
        p, s = polygon @ axis, segment @ axis
        if s.max() - s.min() <= EPS:                      # the segment projects to a point
            if not p.min() + EPS < s.mean() < p.max() - EPS:
                return False
        elif min(p.max(), s.max()) - max(p.min(), s.min()) <= EPS:
            return False
    return True


def strictly_inside(point, polygon):
    """Return whether a point lies inside a convex polygon, off its boundary."""
    e = np.roll(polygon, -1, axis=0) - polygon
    w = point - polygon
    turn = e[:, 0] * w[:, 1] - e[:, 1] * w[:, 0]
    return bool((turn > EPS).all() or (turn < -EPS).all())


def reference_graph(nodes, polygons):
    n = len(nodes)
    length = np.full((n, n), np.inf)
    for i, j in itertools.combinations(range(n), 2):
        if not any(meets_interior(nodes[i], nodes[j], p) for p in polygons):
            length[i, j] = length[j, i] = np.hypot(*(nodes[j] - nodes[i]))
    return length


def shortest_by_enumeration(length):
    """Return the least length of all simple paths from node 0 to node 1."""
    best = math.inf
    stack = [(0, 0.0, {0})]
    while stack:
        node, so_far, seen = stack.pop()
        if node == 1:
            best = min(best, so_far)
            continue
        for nxt in np.flatnonzero(np.isfinite(length[node])):
            if nxt not in seen:
                stack.append((nxt, so_far + length[node, nxt], seen | {nxt}))
    return best


def floyd_warshall(length):
    d = np.where(np.isfinite(length), length, np.inf)
    np.fill_diagonal(d, 0.0)
    for k in range(len(d)):
        d = np.minimum(d, d[:, k, None] + d[None, k, :])
    return d[0, 1]


def random_world(rng, count, vertices):
    """Return convex polygons between x = 1.5 and 4.5, a start left of them, a goal right."""
    polygons = []
    for _ in range(count):
        centre = rng.uniform([2.5, 1.5], [3.5, 4.5])
        cloud = centre + rng.uniform(-1.2, 1.2, (vertices + 3, 2))
        hull = cloud[ConvexHull(cloud).vertices][:vertices]
        polygons.append(hull[ConvexHull(hull).vertices])
    s = rng.uniform([0.0, 0.5], [1.0, 5.5])
    g = rng.uniform([5.0, 0.5], [6.0, 5.5])
    return polygons, s, g


def nodes_of(polygons, s, g):
    corners = [v for p in polygons for v in p
               if not any(strictly_inside(v, q) for q in polygons)]
    return np.vstack([s, g] + corners)


@pytest.mark.parametrize('count, vertices, trials, reference', [
    (1, 4, 30, shortest_by_enumeration),
    (2, 3, 30, shortest_by_enumeration),
    (2, 4, 20, shortest_by_enumeration),
    (3, 4, 20, floyd_warshall),
])
def test_the_path_is_the_shortest_among_convex_polygons(count, vertices, trials, reference):
    rng = np.random.default_rng(1212 + 10 * count + vertices)
    detours = 0
    for _ in range(trials):
        polygons, s, g = random_world(rng, count, vertices)
        optimum = reference(reference_graph(nodes_of(polygons, s, g), polygons))
        plan = visibility_graph(World(polygons=tuple(polygons)), s, g)
        if math.isinf(optimum):
            assert not plan.found and 'unreachable' in plan.reason
            continue
        assert plan.found, plan.reason
        assert plan.cost == pytest.approx(optimum, rel=1e-9, abs=1e-9)
        detours += len(plan.path) > 2
        for a, b in zip(plan.path[:-1], plan.path[1:]):
            assert not any(meets_interior(a, b, p) for p in polygons)
    assert detours >= trials // 4      # the obstacles were in the way often enough


def test_a_wall_is_passed_by_its_end():
    plan = visibility_graph(World(walls=[[1.0, -1.0, 1.0, 2.0]]), [0.0, 0.0], [2.0, 0.0])
    assert plan.path.tolist() == [[0.0, 0.0], [1.0, -1.0], [2.0, 0.0]]
    assert plan.cost == pytest.approx(2 * math.sqrt(2))


def test_no_path_through_the_joint_of_two_walls():
    # A V of walls with its apex at the origin, opening towards +x: the straight line from
    # inside the V to behind it passes exactly through the joint.
    world = World(walls=[[0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, -1.0]])
    plan = visibility_graph(world, [0.5, 0.0], [-1.0, 0.0])
    assert plan.found and len(plan.path) == 3
    assert plan.cost == pytest.approx(math.hypot(0.5, 1.0) + math.hypot(2.0, 1.0))


def test_a_closed_triangle_of_walls_holds_its_inside():
    triangle = [[0.0, 0.0, 2.0, 0.0], [2.0, 0.0, 1.0, 2.0], [1.0, 2.0, 0.0, 0.0]]
    plan = visibility_graph(World(walls=triangle), [1.0, 0.5], [3.0, 3.0])
    assert not plan.found and 'unreachable' in plan.reason
    # Sliding along a wall on either side is allowed: from a corner of it, outside.
    along = visibility_graph(World(walls=triangle), [-1.0, 0.0], [3.0, 0.0])
    assert along.cost == pytest.approx(4.0)


def test_no_path_through_a_t_joint_of_walls():
    # The end of the wall x = 1 touches the wall y = 0 in its middle: no way through there.
    plan = visibility_graph(World(walls=[[0, 0, 2, 0], [1, 0, 1, 1]]), [0.5, 0.5], [1.5, -0.5])
    assert plan.path.tolist() == [[0.5, 0.5], [0.0, 0.0], [1.5, -0.5]]
    assert plan.cost == pytest.approx(math.hypot(0.5, 0.5) + math.hypot(1.5, 0.5))


def test_no_path_between_two_squares_that_touch_at_a_corner():
    squares = (box_polygon([0.5, 0.5], [1.0, 1.0]), box_polygon([1.5, 1.5], [1.0, 1.0]))
    plan = visibility_graph(World(polygons=squares), [0.0, 2.0], [2.0, 0.0])
    assert plan.found and len(plan.path) > 2
    assert plan.cost == pytest.approx(4.0)      # around either square, by (0, 0) or (2, 2)


def test_a_non_convex_polygon_is_planned_around_exactly():
    u_shape = [[0, 0], [3, 0], [3, 3], [0, 3], [0, 2], [2, 2], [2, 1], [0, 1]]   # opens to -x
    plan = visibility_graph(World(polygons=(u_shape,)), [1.0, 1.5], [4.0, 1.5])
    parts = [np.array(p, float) for p in ([[0, 0], [3, 0], [3, 1], [0, 1]],
                                          [[2, 1], [3, 1], [3, 2], [2, 2]],
                                          [[0, 2], [3, 2], [3, 3], [0, 3]])]
    s, g = np.array([1.0, 1.5]), np.array([4.0, 1.5])
    corners = np.array(u_shape, float)
    optimum = shortest_by_enumeration(reference_graph(np.vstack([s, g, corners]), parts))
    assert plan.cost == pytest.approx(optimum)
    assert plan.path[1].tolist() in ([0.0, 1.0], [0.0, 2.0])    # out of the U's mouth first


def distance_to_polygon(points, polygon):
    a, b = polygon, np.roll(polygon, -1, axis=0)
    e = b - a
    w = points[:, None, :] - a[None]
    t = np.clip((w * e).sum(-1) / (e * e).sum(-1), 0.0, 1.0)
    return np.hypot(*(w - t[..., None] * e).transpose(2, 0, 1)).min(axis=1)


def sample(path, step=0.01):
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:]):
        k = max(1, int(np.ceil(np.hypot(*(b - a)) / step)))
        out.extend(a + (b - a) * (np.arange(1, k + 1) / k)[:, None])
    return np.array(out)


def test_a_disc_robot_keeps_its_radius_from_the_obstacles():
    box = box_polygon([2.0, 0.0], [1.0, 2.0], 0.3)
    world = World(polygons=(box,), walls=[[0.0, 2.0, 4.0, 2.0]], circles=[[2.0, -2.0, 0.4]])
    point = visibility_graph(world, [0.0, 0.0], [4.0, 0.0])
    disc = visibility_graph(world, [0.0, 0.0], [4.0, 0.0], robot_radius=0.3)
    assert point.found and disc.found
    points = sample(disc.path)
    clearance = np.minimum.reduce([
        distance_to_polygon(points, box),
        distance_to_polygon(points, np.array([[0.0, 2.0], [4.0, 2.0]])),
        np.hypot(*(points - [2.0, -2.0]).T) - 0.4])
    assert clearance.min() >= 0.3 - 1e-9
    assert disc.cost > point.cost
    # The grown obstacles hold the exact ones grown by r: the polygon of the disc contains it.
    assert np.hypot(*disc_polygon(0.3, 16).T).min() == pytest.approx(0.3 / math.cos(
        math.pi / 16))


def test_a_gap_narrower_than_the_robot_is_refused():
    walls = [[0.0, 1.0, 2.0, 1.0], [0.0, -1.0, 2.0, -1.0], [2.0, 1.0, 2.0, 0.2],
             [2.0, -1.0, 2.0, -0.2], [0.0, 1.0, 0.0, -1.0]]     # a box with a 0.4 m door
    world = World(walls=walls)
    assert visibility_graph(world, [1.0, 0.0], [3.0, 0.0], robot_radius=0.15).found
    plan = visibility_graph(world, [1.0, 0.0], [3.0, 0.0], robot_radius=0.25)
    assert not plan.found
    assert plan.reason == ('the goal is unreachable: no chain of visible segments joins it to '
                           'the start')


@pytest.mark.parametrize('start, goal, words', [
    ([0.0, 0.0], [2.0, 0.0], 'the goal is in an obstacle: (2, 0) m lies in an obstacle grown'),
    ([2.0, 0.3], [4.0, 0.0], 'the start is in collision: (2, 0.3) m'),
])
def test_ends_in_obstacles_are_reported(start, goal, words):
    plan = visibility_graph(World(polygons=(box_polygon([2, 0], [1, 1]),)), start, goal)
    assert not plan.found and plan.reason.startswith(words)


def test_the_budget_is_reported():
    world = World(polygons=(box_polygon([2, 0], [1, 1]),))
    plan = visibility_graph(world, [0, 0], [4, 0], budget=SearchBudget(max_expansions=5))
    # S-G, S and G to the two near corners each, the box's 4 sides: the other segments are
    # no tangents (the box's diagonals, S or G to a far corner).
    assert plan.reason == ('the search budget was exhausted: 9 segments to test between 6 '
                           'points, more than the 5 allowed')
    ticks = itertools.count()
    slow = visibility_graph(world, [0, 0], [4, 0], budget=SearchBudget(max_seconds=0.5),
                            clock=lambda: float(next(ticks)))
    assert slow.reason == ('the search budget was exhausted: 1 s, more than the 0.5 s allowed '
                           '(after 9 of 9 segments)')


def test_details_hold_the_graph_and_the_grown_obstacles():
    world = World(polygons=(box_polygon([2, 0], [1, 1]),), circles=[[5.0, 3.0, 0.5]])
    plan = visibility_graph(world, [0, 0], [4, 0], robot_radius=0.1, sides=8)
    pieces, walls = grown_obstacles(world, 0.1, 8)
    assert len(plan.details['obstacles']) == len(pieces) == 2
    assert np.allclose(plan.details['nodes'][:2], [[0, 0], [4, 0]])
    n = 2 + sum(len(p) for p in pieces)                # S, G and the vertices
    assert len(plan.details['graph']) > 0 and 0 < plan.expansions < n * (n - 1) // 2
    for a in plan.details['graph']:
        assert not any(meets_interior(a[:2], a[2:], p) for p in pieces)


def test_start_equal_to_goal_and_an_empty_world():
    assert visibility_graph(World(), [1, 1], [1, 1]).path.tolist() == [[1.0, 1.0]]
    plan = visibility_graph(World(), [0, 0], [3, 4])
    assert plan.cost == 5.0 and len(plan.path) == 2


@pytest.mark.parametrize('kwargs, words', [
    ({'world': World(grid=OccupancyGrid(np.zeros((2, 2), np.int8), 1.0))}, 'grid planner'),
    ({'robot_radius': -0.1}, 'robot_radius must be >= 0 m'),
    ({'sides': 2, 'robot_radius': 0.1}, 'sides must be an integer >= 3'),
    ({'start': [math.inf, 0.0]}, 'start must be a finite point'),
])
def test_bad_input_is_refused(kwargs, words):
    call = {'world': World(), 'start': [0.0, 0.0], 'goal': [1.0, 1.0], **kwargs}
    with pytest.raises(ValueError, match=words):
        visibility_graph(**call)
