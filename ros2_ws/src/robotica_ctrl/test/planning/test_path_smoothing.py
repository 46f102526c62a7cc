"""
Tests of the line-of-sight shortcut and the clearance-keeping smoother (issue 21).

Inputs are the staircases a grid search returns: a shortest 8-neighbour path of networkx on the
free cell centres of a room, a cell being free when the robot's disc, grown by one cell, is clear
of every obstacle (so that diagonal moves are free too). Every path the code returns is checked
here by geometry written in this file, independent of robotica_kin.world: obstacles are convex
polygons (boxes and walls as two-vertex polygons); a disc swept along a segment is the capsule
(segment-to-polygon distance >= r); a polygon footprint translated along a segment sweeps the
convex hull of its two placements (scipy ConvexHull); rotated and translated, it is checked on
sub-steps of 1/4 of the step (hulls of consecutive sub-poses, less the sagitta of the
rotation); overlap is the separating axis theorem.
"""

import math

import networkx as nx
import numpy as np
import pytest
from robotica_ctrl.planning.continuous_curvature import cc_turn, continuous_curvature_path
from robotica_ctrl.planning.path_collision import polyline_collision, pose_collision
from robotica_ctrl.planning.path_shortcut import drop_collinear, shortcut_path
from robotica_ctrl.planning.path_smoothing import resample_polyline, smooth_path
from robotica_ctrl.planning.plan_result import SearchBudget
from robotica_kin.world import make_world
from scipy.spatial import ConvexHull

# ---------------------------------------------------------------- independent geometry

ROOM = (6.0, 4.0)
BOXES = [((2.0, 1.2), (0.8, 2.4)), ((4.0, 2.8), (0.8, 2.4)), ((3.0, 0.35), (0.5, 0.3))]
RECTANGLE = np.array([[-0.15, -0.1], [0.25, -0.1], [0.25, 0.1], [-0.15, 0.1]])


def box_corners(centre, size):
    (cx, cy), (w, h) = centre, size
    return np.array([[cx - w / 2, cy - h / 2], [cx + w / 2, cy - h / 2],
                     [cx + w / 2, cy + h / 2], [cx - w / 2, cy + h / 2]])


def room_walls():
    w, h = ROOM
    return [[0, 0, w, 0], [w, 0, w, h], [w, h, 0, h], [0, h, 0, 0]]


def obstacles():
    """Return the room's obstacles as convex polygons: the boxes, and each wall as a 2-gon."""
    walls = [np.array([[x1, y1], [x2, y2]], float) for x1, y1, x2, y2 in room_walls()]
    return [box_corners(c, s) for c, s in BOXES] + walls


def world():
    return make_world(walls=room_walls(), boxes=[(c, s, 0.0) for c, s in BOXES])


def point_segment(p, a, b):
    ab, ap = b - a, p - a
    t = np.clip(np.dot(ap, ab) / np.dot(ab, ab), 0.0, 1.0)
    return float(np.hypot(*(ap - t * ab)))


def edges(poly):
    return [(poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))] if len(poly) > 2 \
        else [(poly[0], poly[1])]


def overlap(p, q):
    """Separating axis theorem for two convex polygons (a 2-gon is a segment)."""
    for poly in (p, q):
        for a, b in edges(poly):
            axis = np.array([a[1] - b[1], b[0] - a[0]])
            pa, qa = p @ axis, q @ axis
            if pa.max() < qa.min() or qa.max() < pa.min():
                return False
    return True


def polygon_distance(p, q):
    """Distance between convex polygons: 0 if they overlap, else the least vertex-edge one."""
    if overlap(p, q):
        return 0.0
    return min(min(point_segment(v, a, b) for v in p for a, b in edges(q)),
               min(point_segment(v, a, b) for v in q for a, b in edges(p)))


def capsule_clearance(a, b, r):
    """Least distance of a disc of radius r swept from a to b to the obstacles."""
    segment = np.array([a, b]) if np.any(a != b) else np.array([a, a + 1e-12])
    return min(polygon_distance(segment, o) for o in obstacles()) - r


def placed(footprint, pose):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return footprint @ np.array([[c, s], [-s, c]]) + pose[:2]


def hull_clearance(footprint, pose_a, pose_b, substeps=1):
    """
    Least distance of a polygon moved from pose_a to pose_b to the obstacles, less a bound.

    Each sub-step sweeps the hull of its two placements, but for the rotation: a body point at
    ρ from the centre strays from its chord by at most the sagitta ρ (1 - cos(Δθ/2)), which is
    subtracted (zero for a translation).
    """
    delta = pose_b - pose_a
    delta[2] = (delta[2] + math.pi) % (2 * math.pi) - math.pi      # the short way, as the code
    poses = [pose_a + t * delta for t in np.linspace(0.0, 1.0, substeps + 1)]
    least = math.inf
    for u, v in zip(poses[:-1], poses[1:]):
        corners = np.vstack([placed(footprint, u), placed(footprint, v)])
        hull = corners[ConvexHull(corners).vertices]
        least = min(least, min(polygon_distance(hull, o) for o in obstacles()))
    turn = abs(delta[2]) / substeps
    return least - np.hypot(*footprint.T).max() * (1.0 - math.cos(turn / 2))


def disc_clearances(points, r):
    return np.array([capsule_clearance(a, b, r) for a, b in zip(points[:-1], points[1:])])


def cell_clearance(points):
    """Distance [m] of points (k, 2) to the axis-aligned boxes and the room's walls."""
    w, h = ROOM
    d = np.minimum.reduce([points[:, 0], w - points[:, 0], points[:, 1], h - points[:, 1]])
    for (cx, cy), (bw, bh) in BOXES:
        gap = np.maximum(np.abs(points - [cx, cy]) - [bw / 2, bh / 2], 0.0)
        d = np.minimum(d, np.hypot(gap[:, 0], gap[:, 1]))
    return d


def grid_path(start, goal, r, resolution=0.1):
    """Return a shortest 8-neighbour path of free cell centres (networkx) from start to goal."""
    w, h = ROOM
    xs, ys = np.arange(resolution / 2, w, resolution), np.arange(resolution / 2, h, resolution)
    centres = np.stack(np.meshgrid(xs, ys, indexing='ij'), axis=-1)
    free = (cell_clearance(centres.reshape(-1, 2)) > r + resolution).reshape(centres.shape[:2])
    graph = nx.Graph()
    for i, j in zip(*np.nonzero(free)):
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
            if 0 <= i + di < len(xs) and 0 <= j + dj < len(ys) and free[i + di, j + dj]:
                graph.add_edge((i, j), (i + di, j + dj), weight=math.hypot(di, dj))
    cell = [tuple(int(v) for v in np.floor(np.asarray(q) / resolution)) for q in (start, goal)]
    nodes = nx.shortest_path(graph, cell[0], cell[1], weight='weight')
    return np.array([[xs[i], ys[j]] for i, j in nodes])


def turning(points):
    """Heading change [rad] at each interior point of a polyline."""
    d = np.diff(points, axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    return np.abs((np.diff(heading) + math.pi) % (2 * math.pi) - math.pi)


def length(points):
    return float(np.hypot(*np.diff(points, axis=0).T).sum())


@pytest.fixture(scope='module')
def staircase():
    """Return the grid path from the lower left to the upper right, between the long boxes."""
    return grid_path((0.5, 0.5), (5.5, 3.5), 0.2)


# ---------------------------------------------------------------- the checker itself

def test_independent_checker_sees_the_boxes():
    assert capsule_clearance(np.array([0.5, 2.0]), np.array([3.5, 2.0]), 0.2) < 0.0
    assert capsule_clearance(np.array([1.0, 3.0]), np.array([3.0, 3.0]), 0.2) == pytest.approx(
        0.6 - 0.2)   # above the first box (top y = 2.4), 0.6 m left of the second, wall 1 m
    assert hull_clearance(RECTANGLE, np.array([1.0, 3.0, 0.0]),
                          np.array([2.5, 3.0, 0.0])) == pytest.approx(0.5)


# ---------------------------------------------------------------- shortcut


def test_shortcut_of_a_grid_path_is_free_shorter_and_keeps_its_ends(staircase):
    assert disc_clearances(staircase, 0.2).min() > 0.0
    result = shortcut_path(world(), staircase, 0.2)
    path = result.path
    assert result.found and result.reason == ''
    assert path[0].tolist() == staircase[0].tolist()
    assert path[-1].tolist() == staircase[-1].tolist()
    assert len(path) <= 8 < len(staircase)        # measured: 6 vertices of 83
    assert result.cost == pytest.approx(length(path))
    assert result.cost < length(staircase) - 0.4  # measured: 8.78 m against 9.36 m
    assert disc_clearances(path, 0.2).min() > -1e-6   # touches at most (tolerance 1e-4)
    assert all(any(np.array_equal(v, s) for s in staircase) for v in path)


def test_shortcut_keeps_the_clearance_on_its_new_segments(staircase):
    result = shortcut_path(world(), staircase, 0.2, clearance=0.15)
    path = result.path
    old = {tuple(a) + tuple(b) for a, b in zip(staircase[:-1], staircase[1:])}
    new = [(a, b) for a, b in zip(path[:-1], path[1:]) if tuple(a) + tuple(b) not in old]
    assert new, 'the shortcut should make new segments'
    assert min(capsule_clearance(a, b, 0.2) for a, b in new) >= 0.15 - 1e-3
    assert result.cost <= length(staircase)
    assert result.cost >= shortcut_path(world(), staircase, 0.2).cost - 1e-9


def test_shortcut_of_a_rectangle_footprint_is_free():
    path = grid_path((0.5, 3.5), (5.5, 0.5), 0.3)
    result = shortcut_path(world(), path, RECTANGLE)
    out = result.path
    assert result.found and len(out) < len(path)
    headings = np.arctan2(*np.diff(out, axis=0).T[::-1])
    for a, b, th in zip(out[:-1], out[1:], headings):
        assert hull_clearance(RECTANGLE, np.array([*a, th]), np.array([*b, th])) > -1e-6


def test_a_colliding_path_is_refused_with_where():
    result = shortcut_path(world(), [[0.5, 2.0], [3.5, 2.0]], 0.2)
    assert not result.found and result.path is None
    assert 'collides' in result.reason and 'segment 0' in result.reason
    assert result.details['collision'][0] == 0


def test_the_budget_stops_the_shortcut_with_a_valid_path(staircase):
    result = shortcut_path(world(), staircase, 0.2, budget=SearchBudget(max_expansions=3))
    assert result.found and result.details['budget_hit'] and result.expansions == 3
    assert result.path[-1].tolist() == staircase[-1].tolist()
    assert disc_clearances(result.path, 0.2).min() > -1e-6
    ticks = iter(range(100))
    timed = shortcut_path(world(), staircase, 0.2, clock=lambda: float(next(ticks)),
                          budget=SearchBudget(max_seconds=2.0))
    assert timed.details['budget_hit'] and timed.expansions <= 3


def test_collinear_vertices_go_first():
    assert drop_collinear([[0, 0], [0.1, 0.1], [0.2, 0.2], [0.2, 0.3], [0.2, 0.2]]).tolist() \
        == [[0, 0], [0.2, 0.2], [0.2, 0.3], [0.2, 0.2]]   # the turn back is kept


@pytest.mark.parametrize('points, clearance, match', [
    ([[0, 0]], 0.0, 'shape'), ([[0, 0], [1, math.nan]], 0.0, 'finite'),
    ([[0, 0], [1, 1]], -0.1, 'clearance'), ([[0, 0], [1, 1]], math.inf, 'clearance')])
def test_shortcut_refuses_bad_input(points, clearance, match):
    with pytest.raises(ValueError, match=match):
        shortcut_path(world(), points, 0.2, clearance=clearance)
    if match == 'clearance':
        with pytest.raises(ValueError, match=match):
            polyline_collision(world(), 0.2, points, clearance=clearance)
        with pytest.raises(ValueError, match=match):
            pose_collision(world(), 0.2, [[0.5, 0.5, 0.0]], clearance=clearance)


# ---------------------------------------------------------------- smoothing


def test_smoothing_rounds_the_staircase_and_keeps_it_free(staircase):
    result = smooth_path(world(), staircase, 0.2, clearance=0.1, spacing=0.1)
    path = result.path
    dense = resample_polyline(staircase, 0.1)
    assert result.found and path.shape == dense.shape
    assert path[0].tolist() == staircase[0].tolist()
    assert path[-1].tolist() == staircase[-1].tolist()
    assert disc_clearances(path, 0.2).min() > 0.0
    # the 45-degree steps of the grid become turns of a few degrees per 0.1 m
    assert turning(staircase).max() == pytest.approx(math.pi / 4)
    assert turning(path).max() < math.radians(16.0)       # measured: 13.2 deg
    assert (turning(path) ** 2).sum() < 0.2 * (turning(staircase) ** 2).sum()   # 0.91 / 8.64
    assert result.cost < length(staircase)                 # measured: 8.92 m against 9.36 m
    assert result.details['converged']


def test_smoothing_never_brings_a_pose_nearer_than_asked(staircase):
    clearance = 0.25
    dense = resample_polyline(staircase, 0.1)
    before = np.array([capsule_clearance(p, p, 0.2) for p in dense])
    result = smooth_path(world(), staircase, 0.2, clearance=clearance, spacing=0.1,
                         weight_data=0.02)
    after = np.array([capsule_clearance(p, p, 0.2) for p in result.path])
    assert (after >= np.minimum(clearance, before) - 1e-9).all()
    assert np.allclose(after, result.details['clearance'])


@pytest.mark.parametrize('clearance', [0.1, 0.3])
def test_pure_smoothing_pulls_the_path_taut_at_the_clearance(clearance):
    """
    Without the data term the path shrinks until it rests at the margin around the box.

    Box [1, 2] x [0, 1], disc r = 0.2, from (0, 0) over the box to (3, 0): the limit is the
    shortest path at distance ρ = r + clearance from the box, by hand: two tangents from the
    ends to circles of radius ρ on the top corners, two arcs, and the 1 m top.
    """
    box_world = make_world(boxes=[([1.5, 0.5], [1.0, 1.0], 0.0)])
    result = smooth_path(box_world, [[0, 0], [0, 2], [3, 2], [3, 0]], 0.2, clearance=clearance,
                         spacing=0.15, weight_data=0.0, max_sweeps=1000)
    rho = 0.2 + clearance
    corner = math.sqrt(2.0)
    taut = 2.0 * (math.sqrt(corner ** 2 - rho ** 2)
                  + rho * (math.pi / 4 + math.asin(rho / corner))) + 1.0
    assert result.details['converged']
    assert result.cost == pytest.approx(taut, abs=0.01)    # measured: 1.7e-3, 1.4e-3 short
    box = box_corners((1.5, 0.5), (1.0, 1.0))
    gaps = np.array([polygon_distance(np.array([p, p + 1e-12]), box) - 0.2
                     for p in result.path])
    assert gaps.min() == pytest.approx(clearance, abs=1e-5)


def test_smoothing_a_rectangle_footprint_checks_its_headings():
    path = shortcut_path(world(), grid_path((0.5, 3.5), (5.5, 0.5), 0.3), RECTANGLE).path
    result = smooth_path(world(), path, RECTANGLE, spacing=0.15, max_sweeps=40)
    out, headings = result.path, result.details['headings']
    poses = np.column_stack([out, headings])
    chord = np.vstack([out[1] - out[0], out[2:] - out[:-2], out[-1] - out[-2]])
    assert np.allclose(headings, np.arctan2(chord[:, 1], chord[:, 0]))
    steps = zip(poses[:-1], poses[1:])
    assert min(hull_clearance(RECTANGLE, a, b, substeps=4) for a, b in steps) > -1e-6
    assert turning(out).max() < turning(path).max()


def test_smoothing_refuses_a_colliding_path_and_stops_at_its_budget(staircase):
    refused = smooth_path(world(), [[0.5, 2.0], [3.5, 2.0]], 0.2)
    assert not refused.found and 'collides' in refused.reason
    cut = smooth_path(world(), staircase, 0.2, budget=SearchBudget(max_expansions=10))
    assert cut.found and cut.details['budget_hit'] and cut.expansions == 10
    assert not cut.details['converged']


@pytest.mark.parametrize('kwargs, match', [
    ({'weight_data': 0.5, 'weight_smooth': 0.4}, 'convex'), ({'weight_smooth': 0.0}, 'smooth'),
    ({'weight_data': -0.1}, 'weight_data'), ({'spacing': 0.0}, 'spacing'),
    ({'tolerance': -1.0}, 'tolerance'), ({'max_sweeps': 0}, 'max_sweeps'),
    ({'clearance': -1.0}, 'clearance')])
def test_smoothing_refuses_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        smooth_path(world(), [[0.5, 0.5], [1.0, 0.5]], 0.2, **kwargs)


# ---------------------------------------------------------------- grid path to vehicle path


def test_a_grid_path_becomes_a_free_continuous_curvature_path():
    """
    Plan with the margin a turn cuts, shortcut keeping it, round the corners: still free.

    A right-angle turn at κ_max = 2 1/m, σ_max = 8 1/m² leaves its corner by 0.214 m; the
    grid path is planned for a disc of r + that margin, the shortcut keeps the margin, and the
    rounded path (turns of 67-74 degrees) stays clear of every obstacle for the disc r.
    """
    kappa, sigma = 2.0, 8.0
    margin = cc_turn(math.pi / 2, kappa, sigma).deviation
    staircase = grid_path((0.6, 0.7), (5.4, 3.3), 0.2 + margin)
    short = shortcut_path(world(), staircase, 0.2, clearance=margin)
    assert turning(short.path).max() < math.pi / 2
    result = continuous_curvature_path(short.path, kappa, sigma, ds=0.02, world=world(),
                                       footprint=0.2)
    assert result.found, result.reason
    assert np.abs(result.details['curvature']).max() <= kappa + 1e-12
    assert disc_clearances(result.path[:, :2], 0.2).min() > 0.0     # measured: 0.224 m
