"""
The world model of the plane (book §12.4): walls, polygons, circles and an occupancy grid.

A :class:`World` is plain data validated once when built (the model of Pinocchio's
model/data split): the algorithms on it are free functions (:mod:`~robotica_kin.world.raycast`,
:mod:`~robotica_kin.world.queries`). Everything is in the ``map`` frame [m]:

* ``walls`` (n, 4): segments ``[x1, y1, x2, y2]`` of zero thickness;
* ``polygons``: simple polygons (v, 2), v >= 3, not self-intersecting (solid obstacles:
  point-in-obstacle counts their inside); boxes (centre, size, yaw) are polygons;
* ``circles`` (m, 3): ``[cx, cy, r]``, r > 0 (solid discs, the book's cylinders in the plane);
* ``grid``: an optional :class:`~robotica_kin.world.occupancy_grid.OccupancyGrid`;
* ``inflation`` [m]: the radius the geometric obstacles have been grown by (§12.4.4,
  :func:`~robotica_kin.world.queries.grow`): every query and the ray casting treat a wall as
  the capsule of that radius around it, a polygon as its Minkowski sum with the disc, a circle
  of radius r as one of radius r + inflation. Grown grids are dilated instead (their cells).

``segments`` (derived, (n + Σv, 4)) is every wall and every polygon edge: what rays meet.
"""

from dataclasses import dataclass, field
import math
from typing import Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world.errors import WorldError
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.segment_geometry import segments_intersect

__all__ = ['World', 'box_polygon', 'make_world', 'polygon_edges', 'validate_polygon']


def _frozen(array: NDArray[np.float64]) -> NDArray[np.float64]:
    array.flags.writeable = False
    return array


def _float_table(where: str, value: ArrayLike, columns: int) -> NDArray[np.float64]:
    try:
        table = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise WorldError(f'{where}: must be numbers, got {value!r}') from err
    if table.size == 0:
        table = table.reshape(0, columns)
    if table.ndim != 2 or table.shape[1] != columns:
        raise WorldError(f'{where}: must have shape (n, {columns}), got {table.shape}')
    if not np.isfinite(table).all():
        raise WorldError(f'{where}: must be finite, got {value!r}')
    return table


def validate_polygon(vertices: ArrayLike, where: str = 'polygon') -> NDArray[np.float64]:
    """
    Return a polygon's vertices (v, 2) [m] as float64, or raise WorldError naming ``where``.

    A closing vertex equal to the first is dropped. The polygon must have at least three
    vertices, finite coordinates, no repeated consecutive vertex and no two edges that meet
    except adjacent edges at their shared vertex (simple: not self-intersecting).

    >>> validate_polygon([[0, 0], [1, 0], [0, 1], [0, 0]]).shape
    (3, 2)
    >>> validate_polygon([[0, 0], [1, 1], [1, 0], [0, 1]])
    Traceback (most recent call last):
    ...
    robotica_kin.world.errors.WorldError: polygon: self-intersecting (edges 0 and 2 cross)
    """
    v = _float_table(where, vertices, 2)
    if len(v) >= 2 and np.array_equal(v[0], v[-1]):
        v = v[:-1]
    if len(v) < 3:
        raise WorldError(f'{where}: a polygon needs at least 3 vertices, got {len(v)}')
    edges = polygon_edges(v)
    if np.any((edges[:, 0] == edges[:, 2]) & (edges[:, 1] == edges[:, 3])):
        raise WorldError(f'{where}: repeated consecutive vertex (an edge of zero length)')
    n = len(v)
    meets = segments_intersect(edges, edges)
    i, j = np.triu_indices(n, 1)
    adjacent = (j == i + 1) | ((i == 0) & (j == n - 1))
    bad = meets[i, j] & ~adjacent
    # Adjacent edges share one vertex; they must not fold back over each other.
    e = edges[:, 2:4] - edges[:, 0:2]
    e_next = np.roll(e, -1, axis=0)
    folds = ((e[:, 0] * e_next[:, 1] - e[:, 1] * e_next[:, 0]) == 0.0) & (
        (e * e_next).sum(axis=1) < 0.0)
    if bad.any():
        k = int(np.argmax(bad))
        raise WorldError(f'{where}: self-intersecting (edges {i[k]} and {j[k]} cross)')
    if folds.any():
        k = int(np.argmax(folds))
        raise WorldError(f'{where}: self-intersecting (edges {k} and {(k + 1) % n} overlap)')
    return _frozen(v)


def polygon_edges(vertices: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the closed polygon's edges (v, 4) ``[x1, y1, x2, y2]``, vertex i to vertex i + 1.

    >>> polygon_edges(np.array([[0., 0.], [1., 0.], [0., 1.]]))[2]
    array([0., 1., 0., 0.])
    """
    return np.hstack([vertices, np.roll(vertices, -1, axis=0)])


def box_polygon(center: ArrayLike, size: ArrayLike, yaw: float = 0.0,
                where: str = 'box') -> NDArray[np.float64]:
    """
    Return the box of centre (x, y) [m], size (width along its x, height along its y) [m].

    ``yaw`` [rad] turns it about its centre, counter-clockwise from the map's x axis. The four
    vertices (4, 2) come counter-clockwise. WorldError names ``where`` for a bad input.

    >>> box_polygon([1.0, 1.0], [2.0, 1.0])
    array([[0. , 0.5],
           [2. , 0.5],
           [2. , 1.5],
           [0. , 1.5]])
    """
    c = _float_table(f'{where}.center', np.array([center], dtype=object), 2)[0]
    s = _float_table(f'{where}.size', np.array([size], dtype=object), 2)[0]
    if not (s > 0.0).all():
        raise WorldError(f'{where}.size: width and height must be > 0 m, got {s.tolist()}')
    if not (isinstance(yaw, (int, float)) and not isinstance(yaw, bool) and math.isfinite(yaw)):
        raise WorldError(f'{where}.yaw: must be a finite angle [rad], got {yaw!r}')
    half = 0.5 * s
    corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * half
    cy, sy = math.cos(yaw), math.sin(yaw)
    rotation = np.array([[cy, -sy], [sy, cy]])
    return _frozen(corners @ rotation.T + c)


@dataclass(frozen=True, eq=False)
class World:
    """
    A planar world (map frame, [m]): walls, polygons, circles, an optional grid, inflation.

    Built with :func:`make_world` (walls, boxes, polygons, circles) or directly; validated in
    ``__post_init__`` (WorldError): finite tables of the right shape, walls of non-zero length,
    valid polygons, radii > 0, inflation >= 0.

    >>> world = World(walls=[[0, 0, 1, 0]], polygons=([[2, 0], [3, 0], [3, 1]],))
    >>> world.segments.shape, world.circles.shape
    ((4, 4), (0, 3))
    """

    walls: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 4)))
    circles: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))
    polygons: tuple[NDArray[np.float64], ...] = ()
    grid: Optional[OccupancyGrid] = None
    inflation: float = 0.0          # [m] radius the geometric obstacles are grown by
    segments: NDArray[np.float64] = field(init=False, repr=False)
    _surfaces: dict[float, tuple[NDArray[np.float64], NDArray[np.float64]]] = field(
        init=False, repr=False, default_factory=dict)

    def __post_init__(self) -> None:
        walls = _float_table('walls', self.walls, 4)
        zero = (walls[:, 0] == walls[:, 2]) & (walls[:, 1] == walls[:, 3])
        if zero.any():
            raise WorldError(f'walls[{int(np.argmax(zero))}]: a wall of zero length')
        circles = _float_table('circles', self.circles, 3)
        if not (circles[:, 2] > 0.0).all():
            k = int(np.argmax(~(circles[:, 2] > 0.0)))
            raise WorldError(f'circles[{k}]: radius must be > 0 m, got {float(circles[k, 2])}')
        polygons = tuple(validate_polygon(p, f'polygons[{k}]')
                         for k, p in enumerate(self.polygons))
        if self.grid is not None and not isinstance(self.grid, OccupancyGrid):
            raise WorldError(f'grid must be an OccupancyGrid, got {type(self.grid).__name__}')
        if not (isinstance(self.inflation, (int, float)) and math.isfinite(self.inflation)
                and self.inflation >= 0.0):
            raise WorldError(f'inflation must be >= 0 m, got {self.inflation!r}')
        segments = np.vstack([walls, *(polygon_edges(p) for p in polygons)])
        object.__setattr__(self, 'walls', _frozen(walls))
        object.__setattr__(self, 'circles', _frozen(circles))
        object.__setattr__(self, 'polygons', polygons)
        object.__setattr__(self, 'inflation', float(self.inflation))
        object.__setattr__(self, 'segments', _frozen(segments))

    def surfaces(self, extra: float = 0.0
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """
        Return the segments (s, 4) and circles (c, 3) bounding the obstacles grown by r.

        r = ``inflation`` + ``extra`` [m] (extra: a circular robot's radius). With r = 0 they
        are :attr:`segments` and :attr:`circles`. Grown by r, each segment becomes its capsule:
        the two segments offset by ± r along its normal and a circle of radius r on each
        distinct endpoint; each circle's radius grows by r. A ray from outside meets the union
        of these surfaces first where it meets the grown obstacle. Cached per r.
        """
        r = self.inflation + extra
        cached = self._surfaces.get(r)
        if cached is not None:
            return cached
        if r == 0.0:
            result = (self.segments, self.circles)
        else:
            seg = self.segments
            e = seg[:, 2:4] - seg[:, 0:2]
            n = np.column_stack([-e[:, 1], e[:, 0]]) / np.hypot(e[:, 0], e[:, 1])[:, None]
            offset = np.hstack([n, n]) * r
            ends = np.unique(np.vstack([seg[:, 0:2], seg[:, 2:4]]), axis=0)
            circles = np.vstack([self.circles + [0.0, 0.0, r],
                                 np.column_stack([ends, np.full(len(ends), r)])])
            result = (_frozen(np.vstack([seg + offset, seg - offset])), _frozen(circles))
        if len(self._surfaces) < 16:
            self._surfaces[r] = result
        return result


def make_world(walls: ArrayLike = (), boxes: Sequence[tuple[ArrayLike, ArrayLike, float]] = (),
               polygons: Sequence[ArrayLike] = (), circles: ArrayLike = (),
               grid: Optional[OccupancyGrid] = None) -> World:
    """
    Return a World from walls (n, 4), boxes (centre, size, yaw), polygons and circles (m, 3).

    All in the map frame [m], yaw [rad]; boxes become polygons (:func:`box_polygon`) placed
    after the given polygons. WorldError names the first bad item.

    >>> world = make_world(walls=[[0, 0, 4, 0]], boxes=[([2, 2], [1, 1], 0.0)],
    ...                    circles=[[5, 5, 0.5]])
    >>> len(world.polygons), world.segments.shape
    (1, (5, 4))
    """
    boxed = [box_polygon(c, s, y, f'boxes[{k}]') for k, (c, s, y) in enumerate(boxes)]
    return World(walls=_float_table('walls', walls, 4),
                 circles=_float_table('circles', circles, 3),
                 polygons=tuple(validate_polygon(p, f'polygons[{k}]')
                                for k, p in enumerate(polygons)) + tuple(boxed), grid=grid)
