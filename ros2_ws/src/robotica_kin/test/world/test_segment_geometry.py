"""Tests of robotica_kin.world.segment_geometry against plain per-pair loops."""

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np

from robotica_kin.world.segment_geometry import (
    point_segment_distance, points_in_polygon, segment_segment_distance, segments_intersect)


def distance_loop(p, seg, samples=2001):
    """Return the distance of p to the segment by dense sampling (an upper bound, tight)."""
    s = np.linspace(0.0, 1.0, samples)
    x = seg[0] + s * (seg[2] - seg[0])
    y = seg[1] + s * (seg[3] - seg[1])
    return np.hypot(x - p[0], y - p[1]).min()


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_point_segment_distance_against_sampling(seed):
    rng = np.random.default_rng(seed)
    points, segments = rng.uniform(-5, 5, (6, 2)), rng.uniform(-5, 5, (4, 4))
    d = point_segment_distance(points, segments)
    for i, p in enumerate(points):
        for j, seg in enumerate(segments):
            sampled = distance_loop(p, seg)
            assert d[i, j] <= sampled + 1e-12
            assert sampled - d[i, j] < 1e-2


def test_intersections_by_hand():
    a = np.array([[0.0, 0.0, 2.0, 0.0]])
    b = np.array([[1.0, -1.0, 1.0, 1.0],     # crosses
                  [2.0, 0.0, 3.0, 1.0],      # touches at an endpoint
                  [1.0, 0.0, 3.0, 0.0],      # collinear overlap
                  [2.5, 0.0, 3.0, 0.0],      # collinear, apart
                  [0.0, 1.0, 2.0, 1.0]])     # parallel
    np.testing.assert_array_equal(segments_intersect(a, b), [[True, True, True, False, False]])
    np.testing.assert_allclose(segment_segment_distance(a, b), [[0.0, 0.0, 0.0, 0.5, 1.0]])


def test_point_in_concave_polygon():
    u_shape = np.array([[0, 0], [3, 0], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]], float)
    inside = points_in_polygon(np.array([[0.5, 2.0], [1.5, 2.0], [2.5, 0.5], [4.0, 1.0]]),
                               u_shape)
    np.testing.assert_array_equal(inside, [True, False, True, False])
