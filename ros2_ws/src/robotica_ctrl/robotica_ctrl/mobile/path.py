"""
Geometry of a reference path given as a polyline (book §9.2, §9.3.1).

Chapter 9 of Ollero (2001) gives a path as a sequence of points or postures, e.g. recorded
with DGPS or produced by a planner (§9.2). The pure-pursuit tracker (§9.3.1, fig. 9.4) needs,
each control period, the path point closest to the vehicle and the point a given arc length
further on. :class:`PolylinePath` provides both: the arc-length parametrisation with
:meth:`PolylinePath.point_at`, and the closest-point search :meth:`PolylinePath.project`,
over the whole path or in a window of arc length around a hint (what keeps a tracker on the
right lap of a closed path and bounds the work per period).

Frames are REP-103: headings from the x axis, counter-clockwise; lateral offsets are positive
to the left of the direction of travel.
"""

from bisect import bisect_left, bisect_right
from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['PathProjection', 'PolylinePath']

_CLOSED_TOLERANCE = 1e-9  # [m] a path whose first and last points are this close is closed
_DUPLICATE_TOLERANCE = 1e-12  # [m] a point this close to its predecessor is a duplicate
_TIE_TOLERANCE = 1e-12  # [m] distances this close are a tie, resolved towards the smaller s


@dataclass(frozen=True)
class PathProjection:
    """
    Closest point of a path to a query point, and the query point's offsets from it.

    Attributes
    ----------
    s : float
        Arc length of the closest point from the start of the path [m].
    point : ndarray, shape (2,)
        Closest point (x, y) [m] in the path frame; stored as a read-only float64 copy.
    segment : int
        Index i of the segment, from vertex i to vertex i + 1, that holds the closest point.
    tangent_heading : float
        Heading of that segment [rad], from the x axis, counter-clockwise.
    cross_track : float
        Signed lateral offset of the query point [m], > 0 when it is left of the path.
        Beside the path ``|cross_track| == distance`` (at a vertex the side is that of the
        bisector of its two segments; straight beyond a cusp, where the path reverses, it
        counts as left); beyond an end of an open path it is the offset from the end
        segment's line.
    along_track : float
        Offset of the query point along the end segment beyond an end of an open path [m]:
        < 0 before the start, > 0 after the end, 0 beside the path (always 0 when closed).
    distance : float
        Euclidean distance from the query point to the closest point [m], so that
        ``distance**2 == cross_track**2 + along_track**2``, except where a windowed search
        (:meth:`PolylinePath.project`) stops at an end of its window: there ``cross_track``
        is the lateral component of the offset only.

    Raises
    ------
    ValueError
        If ``point`` is not of shape (2,), a value is not finite, ``segment < 0`` or
        ``distance < 0``.

    Examples
    --------
    >>> p = PathProjection(1.0, [1.0, 0.0], 0, 0.0, 0.5, 0.0, 0.5)
    >>> p.point, p.cross_track
    (array([1., 0.]), 0.5)

    """

    s: float
    point: NDArray[np.float64]
    segment: int
    tangent_heading: float
    cross_track: float
    along_track: float
    distance: float

    def __post_init__(self) -> None:
        point = np.array(self.point, dtype=np.float64)
        if point.shape != (2,):
            raise ValueError(f'point must have shape (2,), got {point.shape}')
        scalars = (self.s, self.tangent_heading, self.cross_track, self.along_track,
                   self.distance)
        if not (np.all(np.isfinite(point)) and np.all(np.isfinite(scalars))):
            raise ValueError(f'projection values must be finite, got {point!r}, {scalars!r}')
        if self.segment < 0:
            raise ValueError(f'segment must be >= 0, got {self.segment!r}')
        if self.distance < 0.0:
            raise ValueError(f'distance must be >= 0 m, got {self.distance!r}')
        point.flags.writeable = False
        object.__setattr__(self, 'point', point)

    @classmethod
    def _from_checked(cls, s: float, x: float, y: float, segment: int, tangent_heading: float,
                      cross_track: float, along_track: float,
                      distance: float) -> 'PathProjection':
        """Build a projection from finite values already checked by the caller (no checks)."""
        point = np.array([x, y])
        point.flags.writeable = False
        projection = cls.__new__(cls)
        projection.__dict__.update(s=s, point=point, segment=segment,
                                   tangent_heading=tangent_heading, cross_track=cross_track,
                                   along_track=along_track, distance=distance)
        return projection


class PolylinePath:
    """
    A planar path through points (N, 2) [m], parametrised by arc length s [m].

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Vertices (x, y) [m] in the path frame (e.g. ``odom``), in the order of travel;
        N >= 2, finite. Consecutive duplicates (a point within 1e-12 m of its predecessor)
        are dropped.

    Raises
    ------
    ValueError
        If ``points`` is not (N, 2), holds a non-finite value, or fewer than 2 distinct
        points remain.

    Notes
    -----
    Segment i runs from vertex i to vertex i + 1 and holds ``s[i] <= s <= s[i + 1]``. The path
    is closed when its first and last points coincide within 1e-9 m. All arrays it exposes are
    read-only.

    Examples
    --------
    >>> path = PolylinePath([[0.0, 0.0], [3.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    >>> path.s, path.length, path.closed
    (array([0., 3., 7.]), 7.0, False)

    """

    def __init__(self, points: ArrayLike) -> None:
        p = np.array(points, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2:
            raise ValueError(f'points must have shape (N, 2), got {p.shape}')
        if not np.all(np.isfinite(p)):
            raise ValueError('points must be finite')
        keep = np.ones(len(p), dtype=bool)
        keep[1:] = np.hypot(*np.diff(p, axis=0).T) > _DUPLICATE_TOLERANCE
        p = p[keep]
        if len(p) < 2:
            raise ValueError(f'a path needs at least 2 distinct points, got {len(p)}')
        delta = np.diff(p, axis=0)
        seg_len = np.hypot(delta[:, 0], delta[:, 1])
        self._points = _read_only(p)
        self._seg_len = _read_only(seg_len)
        self._s = _read_only(np.concatenate(([0.0], np.cumsum(seg_len))))
        self._tangents = _read_only(delta / seg_len[:, np.newaxis])
        self._headings = _read_only(np.arctan2(delta[:, 1], delta[:, 0]))
        self._closed = bool(np.hypot(*(p[-1] - p[0])) <= _CLOSED_TOLERANCE)
        # Per-call work reads these: contiguous coordinate columns for the vectorised search,
        # and Python floats for the scalar steps (bisect, one segment), equal to the arrays.
        self._x = np.ascontiguousarray(p[:, 0])
        self._y = np.ascontiguousarray(p[:, 1])
        self._tx = np.ascontiguousarray(self._tangents[:, 0])
        self._ty = np.ascontiguousarray(self._tangents[:, 1])
        self._s_list: list[float] = self._s.tolist()
        self._seg_len_list: list[float] = seg_len.tolist()
        self._points_list: list[list[float]] = p.tolist()
        self._tangents_list: list[list[float]] = self._tangents.tolist()
        self._headings_list: list[float] = self._headings.tolist()
        self._length = self._s_list[-1]

    @property
    def points(self) -> NDArray[np.float64]:
        """Vertices (N, 2) [m], consecutive duplicates dropped."""
        return self._points

    @property
    def s(self) -> NDArray[np.float64]:
        """Cumulative arc length (N,) [m] at each vertex; ``s[0] == 0``."""
        return self._s

    @property
    def length(self) -> float:
        """Total arc length [m]."""
        return self._length

    @property
    def tangents(self) -> NDArray[np.float64]:
        """Return the unit tangent (N - 1, 2) of each segment, in the direction of travel."""
        return self._tangents

    @property
    def headings(self) -> NDArray[np.float64]:
        """Heading (N - 1,) [rad] of each segment, from the x axis, in (-π, π]."""
        return self._headings

    @property
    def closed(self) -> bool:
        """Whether the first and last points coincide (within 1e-9 m)."""
        return self._closed

    def point_at(self, s: float) -> NDArray[np.float64]:
        """
        Return the point (x, y) [m], shape (2,), at arc length ``s`` [m].

        ``s`` is clamped to [0, length]; vertices are returned exactly.

        Raises
        ------
        ValueError
            If ``s`` is not finite.

        >>> PolylinePath([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]]).point_at(5.0)
        array([3., 2.])

        """
        i, u = self._locate(s)
        f = u / self._seg_len_list[i]
        (xa, ya), (xb, yb) = self._points_list[i], self._points_list[i + 1]
        return np.array([(1.0 - f) * xa + f * xb, (1.0 - f) * ya + f * yb])

    def heading_at(self, s: float) -> float:
        """
        Return the path heading [rad] at arc length ``s`` [m] (clamped to [0, length]).

        At a vertex the heading of the segment leaving it is returned (of the last segment
        at the end of the path).

        Raises
        ------
        ValueError
            If ``s`` is not finite.

        >>> PolylinePath([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]]).heading_at(3.0)
        1.5707963267948966

        """
        return self._headings_list[self._locate(s)[0]]

    def project(self, point: ArrayLike, s_hint: float | None = None,
                window: float | None = None) -> PathProjection:
        """
        Project ``point`` onto the path: closest point and offsets (book fig. 9.4, step 1).

        Parameters
        ----------
        point : array_like, shape (2,)
            Query point (x, y) [m] in the path frame.
        s_hint : float, optional
            Arc length [m] near which to search, e.g. the tracker's last progress; clamped
            to [0, length]. Give it together with ``window``.
        window : float, optional
            Half-width [m] of the search: only the part of the path with s in
            [s_hint - window, s_hint + window] is searched (the segments overlapping it, cut
            at its ends), which picks the right lap of a closed path and costs O(window)
            instead of O(N). Without ``s_hint`` and ``window`` the whole path is searched.

        Returns
        -------
        PathProjection
            The closest point among the searched segments; on a tie, the one with the
            smaller s. See :class:`PathProjection` for the signs of the offsets.

        Raises
        ------
        ValueError
            If ``point`` is not a finite (2,) vector, only one of ``s_hint`` and ``window``
            is given, or they are not finite, or ``window < 0``.

        >>> path = PolylinePath([[0.0, 0.0], [4.0, 0.0]])
        >>> path.project([1.0, 0.5]).cross_track
        0.5
        >>> path.project([5.0, -1.0]).along_track
        1.0

        """
        q = np.asarray(point, dtype=np.float64)
        if q.shape != (2,):
            raise ValueError(f'point must be a finite (2,) vector, got {point!r}')
        qx, qy = q.tolist()
        if not (math.isfinite(qx) and math.isfinite(qy)):
            raise ValueError(f'point must be a finite (2,) vector, got {point!r}')
        lo, hi = self._search_interval(s_hint, window)
        # Segment i overlaps [lo, hi] when s[i + 1] >= lo and s[i] <= hi.
        first = max(bisect_left(self._s_list, lo) - 1, 0)
        stop = min(bisect_right(self._s_list, hi), len(self._seg_len_list))
        # Parameter t in [0, 1] of each segment's closest point, cut at the window's ends.
        ax, ay = self._x[first:stop], self._y[first:stop]
        t = qx - ax
        t *= self._tx[first:stop]
        dy = qy - ay
        dy *= self._ty[first:stop]
        t += dy
        t /= self._seg_len[first:stop]
        s_list, seg_len = self._s_list, self._seg_len_list
        if lo > -math.inf:
            # Only the first segment starts before lo (s[first] < lo <= s[first + 1]).
            t_lo = (lo - s_list[first]) / seg_len[first]
            if t[0] < t_lo:
                t[0] = t_lo
        if hi < math.inf:
            # Only segments with s[i + 1] >= hi can be cut: s[i + 1] < hi, s[i + 1] being
            # s[i] + seg_len[i] rounded to nearest, gives hi - s[i] >= seg_len[i] exactly.
            for i in range(max(bisect_left(s_list, hi) - 1, first), stop):
                t_hi = (hi - s_list[i]) / seg_len[i]
                if t[i - first] > t_hi:
                    t[i - first] = t_hi
        np.maximum(t, 0.0, out=t)  # also turns a -0.0 into 0.0
        np.minimum(t, 1.0, out=t)
        # Distance to each closest point (1 - t) a + t b; the first within the tie wins.
        u = 1.0 - t
        cx = u * ax
        cx += t * self._x[first + 1:stop + 1]
        cy = u * ay
        cy += t * self._y[first + 1:stop + 1]
        np.subtract(qx, cx, out=cx)
        np.subtract(qy, cy, out=cy)
        dist = np.hypot(cx, cy)
        d_min = float(dist[dist.argmin()])  # NaN if a distance is (argmin stops at a NaN)
        k = int((dist <= d_min + _TIE_TOLERANCE).argmax())
        i = first + k
        t_k, distance = float(t[k]), float(dist[k])
        (xa, ya), (xb, yb) = self._points_list[i], self._points_list[i + 1]
        px, py = (1.0 - t_k) * xa + t_k * xb, (1.0 - t_k) * ya + t_k * yb
        cross_track, along_track = self._offsets(qx - px, qy - py, i, t_k, distance)
        s = s_list[i] + t_k * seg_len[i]
        values = (s, px, py, cross_track, along_track, d_min)
        if not all(map(math.isfinite, values)):  # only if coordinates overflow
            raise ValueError(f'projection values must be finite, got {values!r}')
        return PathProjection._from_checked(s, px, py, i, self._headings_list[i], cross_track,
                                            along_track, distance)

    def _locate(self, s: float) -> tuple[int, float]:
        """Return the segment holding arc length ``s`` and the distance [m] along it."""
        if not math.isfinite(s):
            raise ValueError(f's must be finite, got {s!r}')
        s = min(max(float(s), 0.0), self._length)
        i = min(bisect_right(self._s_list, s) - 1, len(self._seg_len_list) - 1)
        return i, s - self._s_list[i]

    def _search_interval(self, s_hint: float | None,
                         window: float | None) -> tuple[float, float]:
        """Return the arc-length interval [lo, hi] [m] to search, infinite past the ends."""
        if s_hint is None and window is None:
            return -math.inf, math.inf
        if s_hint is None or window is None:
            raise ValueError('give s_hint and window together, or neither')
        if not (math.isfinite(s_hint) and math.isfinite(window) and window >= 0.0):
            raise ValueError(f'need finite s_hint and window >= 0 m, got {s_hint!r}, {window!r}')
        hint = min(max(float(s_hint), 0.0), self._length)
        # Past an end the interval is left open, so that the end vertex is reached exactly.
        lo = hint - window if hint - window > 0.0 else -math.inf
        hi = hint + window if hint + window < self._length else math.inf
        return lo, hi

    def _offsets(self, dx: float, dy: float, i: int, t: float,
                 distance: float) -> tuple[float, float]:
        """Return (cross_track, along_track) [m] of offset (dx, dy) from point t of segment i."""
        tx, ty = self._tangents_list[i]
        cross = tx * dy - ty * dx
        along = tx * dx + ty * dy + 0.0  # + 0.0: a zero offset gives 0.0, not -0.0
        last = len(self._seg_len_list) - 1
        neighbour = i - 1 if t == 0.0 else i + 1 if t == 1.0 else None
        if neighbour is None:
            return cross, 0.0
        if self._closed:
            neighbour %= last + 1
        elif neighbour < 0:
            return cross, min(along, 0.0)
        elif neighbour > last:
            return cross, max(along, 0.0)
        # At a vertex the side is that of the bisector of the two tangents; at a cusp, where
        # the bisector vanishes, that of the segment; straight beyond a cusp, left.
        nx, ny = self._tangents_list[neighbour]
        side = (tx + nx) * dy - (ty + ny) * dx
        if side == 0.0:
            side = cross if cross != 0.0 else 1.0
        return math.copysign(distance, side), 0.0


def _read_only(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``a`` marked read-only."""
    a.flags.writeable = False
    return a
