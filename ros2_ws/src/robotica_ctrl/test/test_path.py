"""Tests of robotica_ctrl.mobile.path: polyline geometry for the trackers of book §9.3.1."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

from robotica_ctrl.mobile.path import PathProjection, PolylinePath

# An L-shaped path: 4 m along +x, then a left turn and 3 m along +y (length 7 m).
L_SHAPE = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]]


def unit_circle_points(n):
    """Return n + 1 vertices of a closed counter-clockwise unit circle starting at (1, 0)."""
    angles = np.linspace(0.0, 2.0 * math.pi, n + 1)
    points = np.column_stack((np.cos(angles), np.sin(angles)))
    points[-1] = points[0]
    return points


def test_arc_length_tangents_and_headings():
    path = PolylinePath(L_SHAPE)
    np.testing.assert_array_equal(path.s, [0.0, 4.0, 7.0])
    assert path.length == 7.0
    np.testing.assert_allclose(path.tangents, [[1.0, 0.0], [0.0, 1.0]], atol=1e-15)
    np.testing.assert_allclose(path.headings, [0.0, 0.5 * math.pi])
    assert not path.closed


def test_consecutive_duplicates_are_dropped():
    path = PolylinePath([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [1.0, 1e-13], [1.0, 2.0]])
    np.testing.assert_array_equal(path.points, [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]])
    assert path.length == 3.0


@pytest.mark.parametrize('points', [
    [[1.0, 1.0], [1.0, 1.0]],            # fewer than 2 distinct points
    [[0.0, 0.0]],                         # a single point
    [],                                   # nothing
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],   # 3-D points
    [0.0, 1.0],                           # a vector, not (N, 2)
    [[0.0, 0.0], [math.nan, 1.0]],        # not finite
    [[0.0, 0.0], [math.inf, 1.0]],
])
def test_invalid_points_are_rejected(points):
    with pytest.raises(ValueError):
        PolylinePath(points)


def test_arrays_are_read_only():
    path = PolylinePath(L_SHAPE)
    for array in (path.points, path.s, path.tangents, path.headings):
        with pytest.raises(ValueError):
            array[0] = 1.0


def test_closed_when_first_and_last_points_coincide():
    assert PolylinePath(unit_circle_points(8)).closed
    assert PolylinePath([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 5e-10]]).closed
    assert not PolylinePath([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 1e-6]]).closed


@pytest.mark.parametrize(('s', 'point', 'heading'), [
    (-1.0, [0.0, 0.0], 0.0),              # clamped to the start
    (0.0, [0.0, 0.0], 0.0),
    (2.5, [2.5, 0.0], 0.0),
    (4.0, [4.0, 0.0], 0.5 * math.pi),     # a vertex: heading of the segment leaving it
    (5.5, [4.0, 1.5], 0.5 * math.pi),
    (7.0, [4.0, 3.0], 0.5 * math.pi),
    (100.0, [4.0, 3.0], 0.5 * math.pi),   # clamped to the end
])
def test_point_and_heading_at_arc_length(s, point, heading):
    path = PolylinePath(L_SHAPE)
    np.testing.assert_array_equal(path.point_at(s), point)
    assert path.heading_at(s) == pytest.approx(heading)


def test_point_at_rejects_non_finite_arc_length():
    path = PolylinePath(L_SHAPE)
    with pytest.raises(ValueError):
        path.point_at(math.nan)
    with pytest.raises(ValueError):
        path.heading_at(math.inf)


# Hand-computed projections onto L_SHAPE: (query, s, point, segment, heading, cross, along).
# The path turns left at (4, 0), so the outside of the corner is on the right (cross < 0).
L_SHAPE_CASES = [
    ((1.0, 0.5), 1.0, (1.0, 0.0), 0, 0.0, 0.5, 0.0),              # left of the 1st segment
    ((2.0, -1.0), 2.0, (2.0, 0.0), 0, 0.0, -1.0, 0.0),            # right of it
    ((3.0, 2.0), 6.0, (4.0, 2.0), 1, 0.5 * math.pi, 1.0, 0.0),    # left of the 2nd segment
    ((5.0, 1.0), 5.0, (4.0, 1.0), 1, 0.5 * math.pi, -1.0, 0.0),   # right of it
    ((5.0, -1.0), 4.0, (4.0, 0.0), 0, 0.0, -math.sqrt(2.0), 0.0),  # outside the corner
    ((4.0, -2.0), 4.0, (4.0, 0.0), 0, 0.0, -2.0, 0.0),            # outside, along the 2nd
    ((-3.0, 4.0), 0.0, (0.0, 0.0), 0, 0.0, 4.0, -3.0),            # before the start
    ((-2.0, 0.0), 0.0, (0.0, 0.0), 0, 0.0, 0.0, -2.0),            # straight behind the start
    ((5.0, 5.0), 7.0, (4.0, 3.0), 1, 0.5 * math.pi, -1.0, 2.0),   # after the end, right
    ((3.5, 3.5), 7.0, (4.0, 3.0), 1, 0.5 * math.pi, 0.5, 0.5),    # after the end, left
    ((4.0, 0.0), 4.0, (4.0, 0.0), 0, 0.0, 0.0, 0.0),              # on the corner
]


@pytest.mark.parametrize(('query', 's', 'point', 'segment', 'heading', 'cross', 'along'),
                         L_SHAPE_CASES)
def test_projection_hand_computed(query, s, point, segment, heading, cross, along):
    projection = PolylinePath(L_SHAPE).project(query)
    assert projection.s == pytest.approx(s, abs=1e-12)
    np.testing.assert_allclose(projection.point, point, atol=1e-12)
    assert projection.segment == segment
    assert projection.tangent_heading == pytest.approx(heading)
    assert projection.cross_track == pytest.approx(cross, abs=1e-12)
    assert projection.along_track == pytest.approx(along, abs=1e-12)
    expected_distance = math.dist(query, point)
    assert projection.distance == pytest.approx(expected_distance, abs=1e-12)
    # The invariant behind the two offsets: distance² = cross² + along².
    assert math.hypot(projection.cross_track, projection.along_track) == pytest.approx(
        projection.distance, abs=1e-12)


def test_clockwise_path_has_left_on_the_inside():
    # Clockwise square: travelling along it, its interior is on the right.
    square = [[0.0, 0.0], [0.0, 2.0], [2.0, 2.0], [2.0, 0.0], [0.0, 0.0]]
    assert PolylinePath(square).project([1.0, 0.5]).cross_track == pytest.approx(-0.5)
    assert PolylinePath(square[::-1]).project([1.0, 0.5]).cross_track == pytest.approx(0.5)


def test_cusp_side():
    # The path runs to (1, 0) heading -x, then reverses and heads +x.
    path = PolylinePath([[2.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
    beyond = path.project([0.0, 0.0])  # straight beyond the cusp: counts as left
    assert (beyond.s, beyond.cross_track, beyond.along_track, beyond.distance) == (
        1.0, 1.0, 0.0, 1.0)
    # Above the cusp: right of the first segment (heading -x), 1 m beyond it.
    above = path.project([0.0, 1.0])
    assert above.s == 1.0
    assert above.cross_track == pytest.approx(-math.sqrt(2.0))


def test_tie_prefers_smaller_arc_length():
    # A U: (1, 1) is 1 m from both the first leg (s = 1) and the last leg (s = 9).
    path = PolylinePath([[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]])
    projection = path.project([1.0, 1.0])
    assert projection.s == 1.0
    assert projection.segment == 0
    assert projection.cross_track == 1.0


def test_closed_path_has_no_ends():
    # Just outside the seam of a closed circle: no along-track offset, 0.5 m to the right.
    projection = PolylinePath(unit_circle_points(64)).project([1.5, 0.0])
    assert projection.s == 0.0
    assert projection.along_track == 0.0
    assert projection.cross_track == pytest.approx(-0.5)


def test_window_picks_the_right_lap_of_a_closed_circle():
    path = PolylinePath(unit_circle_points(360))
    seam = [1.0, 0.0]  # the start and the end of the path
    assert path.project(seam).s == 0.0  # global search: tie, smaller s
    assert path.project(seam, s_hint=path.length - 0.1, window=0.5).s == pytest.approx(
        path.length, abs=1e-12)
    assert path.project(seam, s_hint=0.1, window=0.5).s == 0.0
    # A point just past the seam belongs to the start of the lap only without a hint
    # that places the tracker at the end of the previous lap.
    after_seam = [math.cos(0.05), math.sin(0.05)]
    assert path.project(after_seam).s == pytest.approx(0.05, abs=1e-4)
    assert path.project(after_seam, s_hint=path.length - 0.1,
                        window=0.5).s == pytest.approx(path.length, abs=1e-12)


def test_window_restricts_the_search():
    # 1 m segments along x: only the part of the path with s in [s_hint ± window] counts.
    path = PolylinePath([[x, 0.0] for x in range(11)])
    assert path.project([8.0, 0.5]).s == 8.0
    assert path.project([8.0, 0.5], s_hint=2.0, window=1.0).s == 3.0
    assert path.project([8.0, 0.5], s_hint=20.0, window=1.0).s == 9.0  # hint clamped to 10
    assert path.project([8.0, 0.5], s_hint=-5.0, window=0.0).s == 0.0  # hint clamped to 0


@pytest.mark.parametrize(('point', 's_hint', 'window'), [
    ([1.0, 1.0], 1.0, None),
    ([1.0, 1.0], None, 1.0),
    ([1.0, 1.0], 1.0, -0.1),
    ([1.0, 1.0], math.nan, 1.0),
    ([1.0, 1.0], 1.0, math.inf),
    ([1.0, math.nan], None, None),
    ([1.0, 1.0, 0.0], None, None),
])
def test_invalid_projection_queries_are_rejected(point, s_hint, window):
    with pytest.raises(ValueError):
        PolylinePath(L_SHAPE).project(point, s_hint=s_hint, window=window)


def test_projection_validates_and_freezes():
    projection = PathProjection(1.0, [1.0, 0.0], 0, 0.0, 0.5, 0.0, 0.5)
    with pytest.raises(ValueError):
        projection.point[0] = 2.0
    with pytest.raises(AttributeError):
        projection.s = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        PathProjection(1.0, [1.0, 0.0, 0.0], 0, 0.0, 0.5, 0.0, 0.5)
    with pytest.raises(ValueError):
        PathProjection(1.0, [1.0, 0.0], 0, 0.0, 0.5, 0.0, -0.5)
    with pytest.raises(ValueError):
        PathProjection(math.nan, [1.0, 0.0], 0, 0.0, 0.5, 0.0, 0.5)


# Any floats, and small integers, which make ties, collinear runs and cusps likely.
coordinates = st.one_of(st.floats(min_value=-10.0, max_value=10.0, allow_nan=False),
                        st.integers(min_value=-3, max_value=3).map(float))
planar_points = st.tuples(coordinates, coordinates)


def distance_to_segment(q, a, b):
    """Return the distance from q to segment ab (textbook clamped projection)."""
    q, a, b = (np.asarray(v, dtype=float) for v in (q, a, b))
    ab = b - a
    t = min(max(float(np.dot(q - a, ab) / np.dot(ab, ab)), 0.0), 1.0)
    return float(np.linalg.norm(q - (a + t * ab)))


@settings(max_examples=300, deadline=None)
@given(st.lists(planar_points, min_size=2, max_size=8), planar_points)
def test_projection_lies_on_path_and_is_closest(vertices, query):
    try:
        path = PolylinePath(vertices)
    except ValueError:
        # Only a path whose points all lie within 1e-12 m of their predecessors is refused.
        assert max(math.dist(a, b) for a, b in zip(vertices, vertices[1:])) <= 1e-12
        return
    projection = path.project(query)
    segments = list(zip(path.points[:-1], path.points[1:]))
    # The projected point lies on the path, at its arc length, on its segment ...
    a, b = segments[projection.segment]
    assert distance_to_segment(projection.point, a, b) <= 1e-9
    np.testing.assert_allclose(path.point_at(projection.s), projection.point, atol=1e-9)
    # ... at the reported distance, no farther than any vertex or any segment.
    assert projection.distance == pytest.approx(math.dist(query, projection.point), abs=1e-9)
    assert projection.distance <= min(math.dist(query, v) for v in vertices) + 1e-9
    assert projection.distance <= min(distance_to_segment(query, a, b)
                                      for a, b in segments) + 1e-9
    assert math.hypot(projection.cross_track, projection.along_track) == pytest.approx(
        projection.distance, abs=1e-9)


def distance_to_piece(q, a, b):
    """Return the distance from q to segment ab, which may be a point (no division by 0)."""
    ab = (b[0] - a[0], b[1] - a[1])
    ab_sq = ab[0] ** 2 + ab[1] ** 2
    if ab_sq == 0.0:
        return math.dist(q, a)
    t = min(max(((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1]) / ab_sq, 0.0), 1.0)
    return math.dist(q, (a[0] + t * ab[0], a[1] + t * ab[1]))


def brute_force_window_distance(vertices, query, lo, hi):
    """
    Return the distance from ``query`` to the part of the polyline with s in [lo, hi].

    Written independently of PolylinePath: arc lengths summed with math.dist, every segment
    cut to the window by linear interpolation and measured with distance_to_segment.
    """
    best = math.inf
    s = 0.0
    for a, b in zip(vertices, vertices[1:]):
        length = math.dist(a, b)
        start, end = max(lo, s), min(hi, s + length)
        if length > 0.0 and start <= end + 1e-12:
            f0 = min(max((start - s) / length, 0.0), 1.0)
            f1 = min(max((end - s) / length, f0), 1.0)
            cut_a = [a[0] + f0 * (b[0] - a[0]), a[1] + f0 * (b[1] - a[1])]
            cut_b = [a[0] + f1 * (b[0] - a[0]), a[1] + f1 * (b[1] - a[1])]
            best = min(best, distance_to_piece(query, cut_a, cut_b))
        s += length
    return best


def check_windowed_projection(path, vertices, query, s_hint, window):
    """Assert that the windowed projection matches the brute force over every segment."""
    length = sum(math.dist(a, b) for a, b in zip(vertices, vertices[1:]))
    hint = min(max(s_hint, 0.0), length)
    lo, hi = max(hint - window, 0.0), min(hint + window, length)
    projection = path.project(query, s_hint=s_hint, window=window)
    assert projection.distance == pytest.approx(
        brute_force_window_distance(vertices, query, lo, hi), abs=1e-9)
    assert lo - 1e-9 <= projection.s <= hi + 1e-9
    assert math.dist(query, projection.point) == pytest.approx(projection.distance, abs=1e-9)
    # The point lies on the segment it names, at its arc length.
    a, b = path.points[projection.segment], path.points[projection.segment + 1]
    assert distance_to_segment(projection.point, a, b) <= 1e-9
    s_on_segment = sum(math.dist(p, r) for p, r in zip(path.points[:projection.segment],
                                                       path.points[1:projection.segment + 1]))
    assert projection.s == pytest.approx(
        s_on_segment + math.dist(a, projection.point), abs=1e-9)
    # Frozen and read-only like a projection built by the public constructor.
    with pytest.raises(ValueError):
        projection.point[0] = 0.0
    with pytest.raises(AttributeError):
        projection.s = 0.0  # type: ignore[misc]
    return projection


@settings(max_examples=300, deadline=None)
@given(st.lists(planar_points, min_size=2, max_size=8), planar_points,
       st.floats(min_value=-5.0, max_value=150.0), st.floats(min_value=0.0, max_value=60.0))
def test_windowed_projection_matches_brute_force(vertices, query, s_hint, window):
    try:
        path = PolylinePath(vertices)
    except ValueError:
        return  # all points within 1e-12 m of their predecessors (see the test above)
    # Use the vertices the path kept, so that both sides measure the same polyline.
    check_windowed_projection(path, path.points.tolist(), query, s_hint, window)


def test_windowed_projection_on_a_dense_closed_path_matches_brute_force():
    # The trackers' case: about 500 vertices 5 cm apart, a 2 m window around the progress,
    # queries near the path, windows whose ends fall on vertices, mid-segment or past the
    # seam of the closed path.
    rng = np.random.default_rng(20240606)
    angles = np.linspace(0.0, 2.0 * math.pi, 503)
    vertices = np.column_stack((2.0 * np.sin(angles), 2.0 * np.sin(angles) * np.cos(angles)))
    vertices[-1] = vertices[0]
    path = PolylinePath(vertices)
    assert path.closed
    s_vertices = path.s
    for _ in range(300):
        s_hint = float(rng.uniform(-1.0, path.length + 1.0))
        if rng.random() < 0.3:
            s_hint = float(s_vertices[rng.integers(len(s_vertices))])
        window = float(rng.choice([2.0, 0.0, float(rng.uniform(0.0, 4.0)),
                                   float(s_vertices[rng.integers(1, 20)])]))
        near = np.array([2.0 * math.sin(rng.uniform(0.0, 2.0 * math.pi)), 0.0])
        near[1] = near[0] * math.sqrt(max(1.0 - (near[0] / 2.0) ** 2, 0.0))
        query = near + rng.normal(scale=0.3, size=2)
        if rng.random() < 0.2:
            query = path.points[rng.integers(len(path.points))]  # exactly on a vertex
        check_windowed_projection(path, path.points.tolist(), query, s_hint, window)
