"""
Vectorised primitives of planar segments: intersection, distances, point in polygon.

Segments are rows ``[x1, y1, x2, y2]`` [m] of one frame; every function broadcasts over all
pairs (no Python loop over segments or points), so that (k, n) tables come out in one call.
The world model (§12.4 of the book) builds its queries and its validation on them.
"""

import numpy as np
from numpy.typing import NDArray

__all__ = ['point_segment_distance', 'points_in_polygon', 'segment_segment_distance',
           'segments_intersect']


def _cross(ax: NDArray[np.float64], ay: NDArray[np.float64],
           bx: NDArray[np.float64], by: NDArray[np.float64]) -> NDArray[np.float64]:
    return ax * by - ay * bx


def segments_intersect(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
    """
    Return whether each closed segment of ``a`` (n, 4) meets each of ``b`` (m, 4): (n, m).

    Touching (an endpoint on the other segment) and collinear overlap count as meeting. The
    test is the sign test of the parametric intersection, exact up to floating rounding.

    >>> segments_intersect(np.array([[0., 0., 2., 2.]]), np.array([[0., 2., 2., 0.],
    ...                                                            [3., 0., 3., 1.]]))
    array([[ True, False]])
    """
    px, py = a[:, None, 0], a[:, None, 1]
    rx, ry = a[:, None, 2] - px, a[:, None, 3] - py
    qx, qy = b[None, :, 0], b[None, :, 1]
    sx, sy = b[None, :, 2] - qx, b[None, :, 3] - qy
    wx, wy = qx - px, qy - py
    denom = _cross(rx, ry, sx, sy)
    t_num = _cross(wx, wy, sx, sy)
    u_num = _cross(wx, wy, rx, ry)
    with np.errstate(divide='ignore', invalid='ignore'):
        t = t_num / denom
        u = u_num / denom
        proper = (denom != 0.0) & (t >= 0.0) & (t <= 1.0) & (u >= 0.0) & (u <= 1.0)
        rr = rx * rx + ry * ry
        t0 = (wx * rx + wy * ry) / rr
        t1 = t0 + (sx * rx + sy * ry) / rr
        overlap = (np.maximum(np.minimum(t0, t1), 0.0) <= np.minimum(np.maximum(t0, t1), 1.0))
    collinear = (denom == 0.0) & (u_num == 0.0) & overlap
    return np.asarray(proper | collinear)


def point_segment_distance(points: NDArray[np.float64],
                           segments: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the distance [m] of each point (k, 2) to each closed segment (n, 4): (k, n).

    >>> point_segment_distance(np.array([[1., 1.], [3., 0.]]), np.array([[0., 0., 2., 0.]]))
    array([[1.],
           [1.]])
    """
    ax, ay = segments[None, :, 0], segments[None, :, 1]
    ex, ey = segments[None, :, 2] - ax, segments[None, :, 3] - ay
    wx, wy = points[:, None, 0] - ax, points[:, None, 1] - ay
    ee = ex * ex + ey * ey
    with np.errstate(divide='ignore', invalid='ignore'):
        s = np.where(ee > 0.0, (wx * ex + wy * ey) / ee, 0.0)
    s = np.clip(s, 0.0, 1.0)
    return np.asarray(np.hypot(wx - s * ex, wy - s * ey))


def segment_segment_distance(a: NDArray[np.float64],
                             b: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the distance [m] between each segment of ``a`` (n, 4) and of ``b`` (m, 4): (n, m).

    Zero where they meet, else the least of the four endpoint-to-segment distances.

    >>> segment_segment_distance(np.array([[0., 0., 1., 0.]]), np.array([[2., -1., 2., 1.],
    ...                                                                  [0., -1., 1., 1.]]))
    array([[1., 0.]])
    """
    d = np.minimum(point_segment_distance(a[:, 0:2], b), point_segment_distance(a[:, 2:4], b))
    d = np.minimum(d, point_segment_distance(b[:, 0:2], a).T)
    d = np.minimum(d, point_segment_distance(b[:, 2:4], a).T)
    return np.where(segments_intersect(a, b), 0.0, d)


def points_in_polygon(points: NDArray[np.float64],
                      polygon: NDArray[np.float64]) -> NDArray[np.bool_]:
    """
    Return whether each point (k, 2) lies inside the simple polygon (v, 2): (k,) bool.

    The even-odd crossing rule; a point on the boundary may fall either way (callers that need
    the boundary test the distance to the edges).

    >>> square = np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]])
    >>> points_in_polygon(np.array([[0.5, 0.5], [1.5, 0.5]]), square)
    array([ True, False])
    """
    x, y = points[:, None, 0], points[:, None, 1]
    x1, y1 = polygon[None, :, 0], polygon[None, :, 1]
    x2, y2 = np.roll(polygon[:, 0], -1)[None, :], np.roll(polygon[:, 1], -1)[None, :]
    straddles = (y1 > y) != (y2 > y)
    with np.errstate(divide='ignore', invalid='ignore'):
        x_cross = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
    crossings = np.count_nonzero(straddles & (x < x_cross), axis=1)
    return np.asarray(crossings % 2 == 1)
