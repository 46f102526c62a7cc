"""
Tests of robotica_kin.world.quadtree: region and N-object quadtrees (book §12.4.2).

References: the root's area; independent point sampling (points drawn in each leaf must agree
with point_in_obstacle, points drawn on each obstacle must fall in non-free leaves that list
the object); block sums of the grid's cells by plain slicing; every pair of leaves compared
for a shared side; SciPy's Dijkstra on the free graph for connectivity.
"""

import math

import numpy as np
import pytest

from robotica_kin.world import grow, OccupancyGrid, World
from robotica_kin.world.quadtree import build_quadtree, FREE, MIXED, OCCUPIED
from robotica_kin.world.queries import point_in_obstacle
from robotica_kin.world.segment_geometry import points_in_polygon
from robotica_kin.world.shapes import box_polygon
from scipy.sparse.csgraph import dijkstra

# Five objects in the manner of fig. 12.2: two walls, a triangle, a turned box, a disc.
FIVE = World(walls=[[0.0, 0.0, 6.0, 0.3], [0.5, 5.5, 2.0, 3.5]],
             polygons=([[3.0, 3.0], [4.6, 3.4], [3.4, 4.7]],
                       box_polygon([1.6, 1.8], [1.0, 0.6], 0.5)),
             circles=[[4.8, 1.6, 0.5]])


def points_in_leaves(tree, rng, per_leaf=12):
    """Return points drawn in each leaf's closed square (corners included) and their leaves."""
    boxes = tree.boxes
    t = np.vstack([[[0, 0], [1, 0], [1, 1], [0, 1]], rng.random((per_leaf, 2))])
    local = boxes[:, None, 0:2] + t[None] * (boxes[:, None, 2:4] - boxes[:, None, 0:2])
    leaf = np.repeat(np.arange(len(boxes)), len(t))
    return tree.to_map(local.reshape(-1, 2)), leaf


def points_on_obstacles(world, rng, count=400):
    """Return points drawn on each object (walls, polygons, circles) and the object's number."""
    points, owner = [], []
    for k, wall in enumerate(world.walls):
        t = rng.random((count, 1))
        points.append(wall[:2] + t * (wall[2:] - wall[:2]))
        owner += [k] * count
    for k, polygon in enumerate(world.polygons):
        low, high = polygon.min(axis=0), polygon.max(axis=0)
        cand = rng.uniform(low, high, (20 * count, 2))
        inside = cand[points_in_polygon(cand, polygon)][:count]
        points.append(inside)
        owner += [len(world.walls) + k] * len(inside)
    for k, (cx, cy, r) in enumerate(world.circles):
        rho, phi = r * np.sqrt(rng.random(count)), rng.uniform(-math.pi, math.pi, count)
        points.append(np.column_stack([cx + rho * np.cos(phi), cy + rho * np.sin(phi)]))
        owner += [len(world.walls) + len(world.polygons) + k] * count
    return np.vstack(points), np.array(owner)


@pytest.mark.parametrize('inflation', [0.0, 0.15])
def test_region_quadtree_of_a_world(inflation):
    world = grow(FIVE, inflation)
    tree = build_quadtree(world, 0.1)
    assert tree.areas.sum() == pytest.approx(tree.size ** 2, rel=1e-12)
    assert tree.size == pytest.approx(6.0 + 2 * inflation + 1.0)      # the walls' x span + 2 x 0.5
    rng = np.random.default_rng(1)
    # Leaves partition the root: each random point lies in exactly one half-open square.
    probe = tree.to_map(rng.random((3000, 2)) * tree.size)
    local = probe - np.array(tree.origin[:2])
    b = tree.boxes
    holds = ((local[:, None, 0] >= b[:, 0]) & (local[:, None, 0] < b[:, 2])
             & (local[:, None, 1] >= b[:, 1]) & (local[:, None, 1] < b[:, 3]))
    assert (holds.sum(axis=1) == 1).all()
    np.testing.assert_array_equal(tree.locate(probe), holds.argmax(axis=1))
    # Free leaves hold no obstacle point, occupied ones only obstacle points.
    points, leaf = points_in_leaves(tree, rng)
    taken = point_in_obstacle(world, points)
    assert not taken[tree.state[leaf] == FREE].any()
    assert taken[tree.state[leaf] == OCCUPIED].all()
    # Every point of every obstacle (grown) lies in a leaf that is not free.
    on, _ = points_on_obstacles(world, rng)
    if inflation:
        turn = rng.uniform(-math.pi, math.pi, len(on))
        on = on + 0.999 * inflation * np.column_stack([np.cos(turn), np.sin(turn)])
        assert point_in_obstacle(world, on).all()
    assert (tree.state[tree.locate(on)] != FREE).all()
    assert (tree.depth[tree.state == MIXED] == tree.max_depth).all()
    assert (tree.state == OCCUPIED).sum() > 0


@pytest.mark.parametrize('yaw', [0.0, 0.4])
def test_region_quadtree_of_a_grid(yaw):
    rng = np.random.default_rng(7)
    data = np.zeros((37, 50), np.int8)
    data[10:25, 5:20] = 100
    data[rng.random(data.shape) < 0.03] = 100
    data[30:, 30:] = -1                                  # unknown: free, as in the grid
    grid = OccupancyGrid(data, 0.1, (1.0, -2.0, yaw))
    tree = build_quadtree(grid, 0.1)
    assert tree.size == pytest.approx(6.4) and tree.max_depth == 6
    assert tree.areas.sum() == pytest.approx(tree.size ** 2, rel=1e-12)
    padded = np.ones((64, 64), dtype=bool)
    padded[:37, :50] = grid.occupied
    for k in range(len(tree.state)):
        side = 64 >> int(tree.depth[k])
        col, row = tree.index[k] * side
        cells = padded[row:row + side, col:col + side]
        expected = FREE if not cells.any() else OCCUPIED if cells.all() else MIXED
        assert tree.state[k] == expected
    centres = grid.cell_to_world(np.column_stack([np.tile(np.arange(50), 37),
                                                  np.repeat(np.arange(37), 50)]))
    np.testing.assert_array_equal(tree.state[tree.locate(centres)] == FREE,
                                  ~grid.occupied.ravel())
    coarse = build_quadtree(grid, 0.45)                  # blocks of 4 cells
    assert coarse.max_depth == 4 and coarse.size == pytest.approx(6.4)
    np.testing.assert_allclose(coarse.areas[coarse.state == MIXED], 0.16)


def test_neighbours_against_every_pair():
    tree = build_quadtree(FIVE, 0.2)
    pairs, pieces = tree.neighbours
    b = tree.boxes
    expected = {}
    for i in range(len(b)):
        for j in range(i + 1, len(b)):
            for axis in (0, 1):
                other = 1 - axis
                touching = b[i, 2 + axis] == b[j, axis] or b[j, 2 + axis] == b[i, axis]
                lo = max(b[i, other], b[j, other])
                hi = min(b[i, 2 + other], b[j, 2 + other])
                if touching and hi > lo:
                    expected[(i, j)] = (lo, hi)
    assert len(expected) > 100
    found = {tuple(p): piece for p, piece in zip(pairs.tolist(), pieces.tolist())}
    assert set(found) == set(expected)
    for key, (lo, hi) in expected.items():
        piece = found[key]
        span = sorted([piece[0], piece[2]]) if piece[1] == piece[3] else [piece[1], piece[3]]
        assert span == pytest.approx([lo, hi])


def test_free_graph_connects_through_a_gap_only():
    room = [[0, 0, 8, 0], [8, 0, 8, 4], [8, 4, 0, 4], [0, 4, 0, 0]]
    start, goal = [1.0, 2.0], [7.0, 2.0]
    for gap, reachable in ((0.6, True), (0.0, False)):
        divider = [[4.0, 0.0, 4.0, 2.0 - gap / 2]] + ([[4.0, 2.0 + gap / 2, 4.0, 4.0]] if gap
                                                      else [[4.0, 2.0, 4.0, 4.0]])
        world = grow(World(walls=room + divider), 0.2)
        tree = build_quadtree(world, 0.05, margin=0.0)
        graph = tree.free_graph()
        a, b = (graph.node_of(int(tree.locate([p])[0])) for p in (start, goal))
        dist, previous = dijkstra(graph.matrix, indices=a, return_predecessors=True)
        assert np.isfinite(dist[b]) == reachable
        if reachable:
            nodes = [b]
            while nodes[-1] != a:
                nodes.append(previous[nodes[-1]])
            points = graph.path_points(nodes[::-1])
            assert dist[b] == pytest.approx(np.hypot(*np.diff(points, axis=0).T).sum())
            assert dist[b] >= np.hypot(*(graph.centres[b] - graph.centres[a]))
            t = np.linspace(0.0, 1.0, 50)[:, None]
            dense = np.vstack([p + t * (q - p) for p, q in zip(points, points[1:])])
            assert not point_in_obstacle(world, dense).any()
            assert np.abs(dense[:, 1] - 2.0).max() < 2.0 - 0.2


def test_n_object_quadtree():
    rng = np.random.default_rng(3)
    for n in (0, 1, 2):
        tree = build_quadtree(FIVE, 0.05, max_objects=n)
        counts = np.array([len(o) for o in tree.objects])
        assert (counts[tree.depth < tree.max_depth] <= n).all()
        assert tree.areas.sum() == pytest.approx(tree.size ** 2, rel=1e-12)
        on, owner = points_on_obstacles(FIVE, rng)
        leaves = tree.locate(on)
        assert all(o in tree.objects[k] for o, k in zip(owner.tolist(), leaves.tolist()))
        assert (counts[tree.state == FREE] == 0).all()
        # Objects far apart never share a leaf: the wall at the bottom and the triangle.
        assert (0, 2) not in tree.candidate_pairs()
    # Two discs that overlap share a leaf whatever N: they may collide.
    tree = build_quadtree(World(circles=[[0, 0, 1], [1.5, 0, 1], [5, 5, 1]]), 0.05,
                          max_objects=1)
    assert tree.candidate_pairs() == {(0, 1)}


def test_bad_input():
    with pytest.raises(ValueError, match='resolution'):
        build_quadtree(FIVE, 0.0)
    with pytest.raises(ValueError, match='MAX_DEPTH'):
        build_quadtree(FIVE, 1e-4)
    with pytest.raises(ValueError, match='bounds'):
        build_quadtree(World(), 0.1)
    with pytest.raises(ValueError, match='max_objects'):
        build_quadtree(FIVE, 0.1, max_objects=-1)
    grid = OccupancyGrid(np.zeros((4, 4), np.int8), 0.5)
    with pytest.raises(ValueError, match='both'):
        build_quadtree(World(walls=[[0, 0, 1, 0]], grid=grid), 0.5)
    with pytest.raises(ValueError, match='max_objects'):
        build_quadtree(grid, 0.5, max_objects=2)
    tree = build_quadtree(World(grid=grid), 0.5)
    assert tree.state.tolist() == [FREE]
    empty = build_quadtree(World(), 0.5, bounds=[0, 0, 2, 1])
    assert empty.state.tolist() == [FREE] and empty.size == 2.0
    assert empty.locate([[3.0, 0.0], [1.0, 0.5]]).tolist() == [-1, 0]
    with pytest.raises(ValueError, match='not a free leaf'):
        build_quadtree(World(circles=[[0, 0, 1]]), 0.5).free_graph().node_of(10**6)
