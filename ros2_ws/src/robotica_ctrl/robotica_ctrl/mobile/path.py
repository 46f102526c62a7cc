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
        return float(self._s[-1])

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
        f = u / float(self._seg_len[i])
        point: NDArray[np.float64] = (1.0 - f) * self._points[i] + f * self._points[i + 1]
        return point

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
        return float(self._headings[self._locate(s)[0]])

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
        if q.shape != (2,) or not np.all(np.isfinite(q)):
            raise ValueError(f'point must be a finite (2,) vector, got {point!r}')
        lo, hi = self._search_interval(s_hint, window)
        # Segment i overlaps [lo, hi] when s[i + 1] >= lo and s[i] <= hi.
        first = max(int(np.searchsorted(self._s, lo, side='left')) - 1, 0)
        stop = min(int(np.searchsorted(self._s, hi, side='right')), len(self._seg_len))
        a = self._points[first:stop]
        b = self._points[first + 1:stop + 1]
        s0 = self._s[first:stop]
        seg_len = self._seg_len[first:stop]
        t = np.einsum('ij,ij->i', q - a, self._tangents[first:stop]) / seg_len
        t = np.clip(np.clip(t, (lo - s0) / seg_len, (hi - s0) / seg_len), 0.0, 1.0)
        closest = (1.0 - t)[:, np.newaxis] * a + t[:, np.newaxis] * b
        dist = np.hypot(q[0] - closest[:, 0], q[1] - closest[:, 1])
        k = int(np.flatnonzero(dist <= dist.min() + _TIE_TOLERANCE)[0])
        i = first + k
        cross_track, along_track = self._offsets(q - closest[k], i, float(t[k]),
                                                 float(dist[k]))
        return PathProjection(
            s=float(self._s[i] + t[k] * self._seg_len[i]), point=closest[k], segment=i,
            tangent_heading=float(self._headings[i]), cross_track=cross_track,
            along_track=along_track, distance=float(dist[k]))

    def _locate(self, s: float) -> tuple[int, float]:
        """Return the segment holding arc length ``s`` and the distance [m] along it."""
        if not math.isfinite(s):
            raise ValueError(f's must be finite, got {s!r}')
        s = min(max(float(s), 0.0), self.length)
        i = min(int(np.searchsorted(self._s, s, side='right')) - 1, len(self._seg_len) - 1)
        return i, s - float(self._s[i])

    def _search_interval(self, s_hint: float | None,
                         window: float | None) -> tuple[float, float]:
        """Return the arc-length interval [lo, hi] [m] to search, infinite past the ends."""
        if s_hint is None and window is None:
            return -math.inf, math.inf
        if s_hint is None or window is None:
            raise ValueError('give s_hint and window together, or neither')
        if not (math.isfinite(s_hint) and math.isfinite(window) and window >= 0.0):
            raise ValueError(f'need finite s_hint and window >= 0 m, got {s_hint!r}, {window!r}')
        hint = min(max(float(s_hint), 0.0), self.length)
        # Past an end the interval is left open, so that the end vertex is reached exactly.
        lo = hint - window if hint - window > 0.0 else -math.inf
        hi = hint + window if hint + window < self.length else math.inf
        return lo, hi

    def _offsets(self, delta: NDArray[np.float64], i: int, t: float,
                 distance: float) -> tuple[float, float]:
        """Return (cross_track, along_track) [m] of offset ``delta`` from point t of segment i."""
        tangent = self._tangents[i]
        cross = float(tangent[0] * delta[1] - tangent[1] * delta[0])
        along = float(tangent @ delta)
        last = len(self._seg_len) - 1
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
        bisector = tangent + self._tangents[neighbour]
        side = float(bisector[0] * delta[1] - bisector[1] * delta[0])
        if side == 0.0:
            side = cross if cross != 0.0 else 1.0
        return math.copysign(distance, side), 0.0


def _read_only(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``a`` marked read-only."""
    a.flags.writeable = False
    return a
