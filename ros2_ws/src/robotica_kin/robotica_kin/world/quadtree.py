"""
Quadtrees of the world model (book §12.4.2): region quadtrees and N-object quadtrees.

A quadtree subdivides a square containing the workspace into four quadrants, recursively, until
a decomposition rule holds (Samet 1989). The book gives two rules (for octrees; fig. 12.1 and
12.2), both built here by :func:`build_quadtree`:

* **region quadtree**: a node is split until it lies entirely in an obstacle (*occupied*) or
  entirely outside every obstacle (*free*); nodes still *mixed* at the finest size (the
  ``resolution``) stay mixed leaves;
* **N-object quadtree** (``max_objects`` = N): each node stores the list of objects that touch
  it, and is split until no leaf holds more than N objects (or the finest size is reached).
  Only objects that share a leaf can collide imminently (:meth:`Quadtree.candidate_pairs`).

Every leaf is also classified free / occupied / mixed, so that the free leaves form a graph for
planning (:meth:`Quadtree.free_graph`): nodes are free leaves, edges join leaves that share a
piece of side of positive length, through the middle of that piece (a "portal"), so that the
path centre - portal - centre stays inside the two leaves.

**From a World** (walls, polygons, circles, honouring its ``inflation``): the root is the
square on the obstacles' bounding box grown by ``margin`` (or on ``bounds``), axis-aligned in
the map frame. A node is *free* when no obstacle touches its closed square (exact: segment
clipping and segment-to-square distances, circle-to-square distances, the square's centre in a
polygon when no edge reaches it). It is *occupied* when it lies in one obstacle: in a circle
(its corners within the radius), in a polygon (its centre inside and no edge entering its
interior) or, with inflation r, in the capsule of one segment (its corners within r). A square
covered only by a union of obstacles is mixed: "occupied" is never claimed when not sure.
The objects are numbered walls first, then polygons, then circles.

**From an OccupancyGrid** (its binary :attr:`~OccupancyGrid.occupied` view; unknown cells are
free, as there): the tree lives in the grid's frame (its ``origin``), the finest leaf is a
block of 2^k cells, and the root a power-of-two square of cells padded beyond the map; the
padding counts as occupied (a plan must not leave the map). Counts of occupied cells per node
come from a summed-area table, so the classification is exact.

Leaves are stored in Morton (Z) order of their lower-left corner at the finest level (the
linear quadtree of Gargantini 1982): locating a point is a binary search, and neighbours are
found by a sort of the leaves' sides along each grid line (no scan of every pair).
"""

from dataclasses import dataclass, field
from functools import cached_property
import math
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.segment_geometry import points_in_polygon, segment_segment_distance
from robotica_kin.world.shapes import World

__all__ = ['FREE', 'MAX_DEPTH', 'MIXED', 'OCCUPIED', 'Quadtree', 'QuadtreeGraph',
           'build_quadtree']

FREE, OCCUPIED, MIXED = 0, 1, 2      # leaf states
MAX_DEPTH = 12                       # finest level: 4096 x 4096 finest squares
_BLOCK = 1 << 19                     # squares x segments per classification block


def _spread_bits(v: NDArray[np.int64]) -> NDArray[np.int64]:
    """Return v (< 2^16) with a zero bit inserted above each bit (Morton interleaving)."""
    out = np.zeros_like(v)
    for bit in range(16):
        out |= ((v >> bit) & 1) << (2 * bit)
    return out


def _morton(col: NDArray[np.int64], row: NDArray[np.int64]) -> NDArray[np.int64]:
    return _spread_bits(col) | (_spread_bits(row) << 1)


@dataclass(frozen=True, eq=False)
class QuadtreeGraph:
    """
    The free leaves of a quadtree as a weighted graph for planning.

    ``leaves`` (n,): the leaf index of each node; ``centres`` (n, 2) [m, map frame];
    ``matrix``: a symmetric scipy.sparse CSR (n, n) of edge lengths [m] (centre to portal to
    centre), for scipy.sparse.csgraph; ``edges`` (E, 2) node pairs (a < b) and ``portals``
    (E, 2) [m, map frame] the middle of the side they share.
    """

    leaves: NDArray[np.int64]
    centres: NDArray[np.float64]
    matrix: Any
    edges: NDArray[np.int64]
    portals: NDArray[np.float64]
    _portal_of: dict[tuple[int, int], int] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        lookup = {(int(a), int(b)): k for k, (a, b) in enumerate(self.edges.tolist())}
        object.__setattr__(self, '_portal_of', lookup)

    def node_of(self, leaf: int) -> int:
        """Return the node of a free leaf; ValueError if the leaf is not free."""
        k = int(np.searchsorted(self.leaves, leaf))
        if k >= len(self.leaves) or self.leaves[k] != leaf:
            raise ValueError(f'leaf {leaf} is not a free leaf')
        return k

    def path_points(self, nodes: ArrayLike) -> NDArray[np.float64]:
        """
        Return the polyline (m, 2) [m, map frame] of a node path: centre, portal, centre, ...

        Each piece lies in one free leaf (a convex square), so the polyline is free.
        ValueError if two consecutive nodes are not joined by an edge.
        """
        path = [int(n) for n in np.asarray(nodes).ravel()]
        points = [self.centres[path[0]]] if path else []
        for a, b in zip(path, path[1:]):
            k = self._portal_of.get((min(a, b), max(a, b)))
            if k is None:
                raise ValueError(f'nodes {a} and {b} are not neighbours')
            points += [self.portals[k], self.centres[b]]
        return np.array(points, dtype=np.float64).reshape(-1, 2)


@dataclass(frozen=True, eq=False)
class Quadtree:
    """
    A quadtree's leaves, in Morton order (see the module docstring).

    Attributes
    ----------
    origin : (x, y, yaw)
        The pose [m, rad] of the tree's frame in the map frame; the root is [0, size]² there.
    size : float
        The root square's side [m].
    max_depth : int
        The finest level D: the finest leaf's side is size / 2^D.
    depth : ndarray (L,) int
        Each leaf's level (0: the root).
    index : ndarray (L, 2) int
        Each leaf's (col, row) among the 2^depth x 2^depth squares of its level.
    state : ndarray (L,) int8
        FREE, OCCUPIED or MIXED.
    objects : tuple of tuples
        The objects touching each leaf (N-object trees; () for trees of grids).

    """

    origin: tuple[float, float, float]
    size: float
    max_depth: int
    depth: NDArray[np.int64]
    index: NDArray[np.int64]
    state: NDArray[np.int8]
    objects: tuple[tuple[int, ...], ...] = ()

    @cached_property
    def _finest(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Return each leaf's lower-left corner (L, 2) and side (L,) in finest squares."""
        side = np.left_shift(1, self.max_depth - self.depth)
        return self.index * side[:, None], side

    @cached_property
    def codes(self) -> NDArray[np.int64]:
        """Return each leaf's Morton code at the finest level (ascending)."""
        corner, _ = self._finest
        return _morton(corner[:, 0], corner[:, 1])

    @cached_property
    def boxes(self) -> NDArray[np.float64]:
        """Return each leaf's square [x0, y0, x1, y1] (L, 4) [m] in the tree's frame."""
        corner, side = self._finest
        unit = self.size / (1 << self.max_depth)
        return np.column_stack([corner, corner + side[:, None]]).astype(np.float64) * unit

    @property
    def areas(self) -> NDArray[np.float64]:
        """Return each leaf's area (L,) [m²]."""
        b = self.boxes
        return np.asarray((b[:, 2] - b[:, 0]) * (b[:, 3] - b[:, 1]))

    def to_map(self, points: ArrayLike) -> NDArray[np.float64]:
        """Return points (k, 2) of the tree's frame [m] in the map frame."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        return np.column_stack([x0 + c * p[:, 0] - s * p[:, 1], y0 + s * p[:, 0] + c * p[:, 1]])

    @cached_property
    def centres(self) -> NDArray[np.float64]:
        """Return each leaf's centre (L, 2) [m] in the map frame."""
        b = self.boxes
        return self.to_map(0.5 * (b[:, 0:2] + b[:, 2:4]))

    def corners(self) -> NDArray[np.float64]:
        """Return the four corners of every leaf, (L, 4, 2) [m] in the map frame, CCW."""
        b = self.boxes
        c = np.stack([b[:, [0, 1]], b[:, [2, 1]], b[:, [2, 3]], b[:, [0, 3]]], axis=1)
        return self.to_map(c.reshape(-1, 2)).reshape(-1, 4, 2)

    def locate(self, points: ArrayLike) -> NDArray[np.int64]:
        """
        Return the leaf holding each point (k, 2) [m, map frame]; -1 outside the root.

        A point on a side between leaves goes to the leaf above / to the right of it.
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        rx, ry = p[:, 0] - x0, p[:, 1] - y0
        n = 1 << self.max_depth
        unit = self.size / n
        u = np.floor((c * rx + s * ry) / unit)
        v = np.floor((-s * rx + c * ry) / unit)
        inside = (u >= 0) & (u < n) & (v >= 0) & (v < n) & np.isfinite(u) & np.isfinite(v)
        code = _morton(np.where(inside, u, 0).astype(np.int64),
                       np.where(inside, v, 0).astype(np.int64))
        leaf = np.searchsorted(self.codes, code, side='right') - 1
        return np.where(inside, leaf, -1).astype(np.int64)

    @cached_property
    def neighbours(self) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        """
        Return the pairs (E, 2) of leaves sharing a piece of side and that piece (E, 4) [m].

        Pairs are (a, b) with a < b; a piece is [x0, y0, x1, y1] in the tree's frame. Leaves
        that touch at a corner only are not neighbours (a passage of zero width).
        """
        corner, side = self._finest
        lo, hi = corner, corner + side[:, None]
        m = (1 << self.max_depth) + 1
        pairs, pieces = [], []
        for axis in (0, 1):          # 0: sides along x = const (east-west), 1: y = const
            other = 1 - axis
            # Each leaf B by its low side (line lo[axis], interval [lo, hi) along the other
            # axis): on one line these intervals are disjoint, so both keys sort alike.
            key0 = lo[:, axis] * m + lo[:, other]
            order = np.argsort(key0, kind='stable')
            key0, key1 = key0[order], (lo[:, axis] * m + hi[:, other])[order]
            line = hi[:, axis] * m
            first = np.searchsorted(key1, line + lo[:, other], side='right')
            last = np.searchsorted(key0, line + hi[:, other], side='left')
            count = np.maximum(last - first, 0)
            a = np.repeat(np.arange(len(side)), count)
            offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
            b = order[np.repeat(first, count) + offset]
            start = np.maximum(lo[a, other], lo[b, other])
            end = np.minimum(hi[a, other], hi[b, other])
            at = hi[a, axis]
            piece = (np.column_stack([at, start, at, end]) if axis == 0
                     else np.column_stack([start, at, end, at]))
            pairs.append(np.column_stack([a, b]))
            pieces.append(piece)
        p = np.vstack(pairs)
        unit = self.size / (1 << self.max_depth)
        swap = p[:, 0] > p[:, 1]
        p[swap] = p[swap][:, ::-1]
        return p.astype(np.int64), np.vstack(pieces).astype(np.float64) * unit

    def free_graph(self) -> QuadtreeGraph:
        """Return the free leaves as a graph (module docstring); see :class:`QuadtreeGraph`."""
        from scipy.sparse import csr_matrix
        leaves = np.nonzero(self.state == FREE)[0].astype(np.int64)
        node = np.full(len(self.state), -1, np.int64)
        node[leaves] = np.arange(len(leaves))
        pairs, pieces = self.neighbours
        both = (node[pairs[:, 0]] >= 0) & (node[pairs[:, 1]] >= 0)
        edges = node[pairs[both]]
        portals = self.to_map(0.5 * (pieces[both, 0:2] + pieces[both, 2:4]))
        centres = self.centres[leaves]
        a, b = edges[:, 0], edges[:, 1]
        length = (np.hypot(*(centres[a] - portals).T) + np.hypot(*(centres[b] - portals).T))
        n = len(leaves)
        matrix = csr_matrix((np.concatenate([length, length]),
                             (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(n, n))
        return QuadtreeGraph(leaves, centres, matrix, edges, portals)

    def candidate_pairs(self) -> set[tuple[int, int]]:
        """Return the pairs of objects (i < j) that share a leaf: the only ones that may meet."""
        found: set[tuple[int, int]] = set()
        for objs in self.objects:
            found.update((a, b) for k, a in enumerate(objs) for b in objs[k + 1:])
        return found


class _WorldClassifier:
    """Which objects of a World touch, and which contain, axis-aligned squares of the map."""

    def __init__(self, world: World) -> None:
        self.world = world
        self.inflation = world.inflation
        n_walls = len(world.walls)
        sizes = [1] * n_walls + [len(p) for p in world.polygons]
        self.segment_object = np.repeat(np.arange(len(sizes)), sizes)
        self.segment_start = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.n_segment_objects = len(sizes)
        self.n_objects = len(sizes) + len(world.circles)

    def classify(self, boxes: NDArray[np.float64]
                 ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """Return (touch, contained) (K, objects): the object meets / holds the square."""
        k = len(boxes)
        touch = np.zeros((k, self.n_objects), dtype=bool)
        contained = np.zeros((k, self.n_objects), dtype=bool)
        segments = self.world.segments
        block = max(1, _BLOCK // max(len(segments), 1))
        for start in range(0, k, block):
            rows = slice(start, start + block)
            if len(segments):
                t, c = self._segments(boxes[rows], segments)
                touch[rows, :self.n_segment_objects] = t
                contained[rows, :self.n_segment_objects] = c
            if len(self.world.circles):
                t, c = self._circles(boxes[rows])
                touch[rows, self.n_segment_objects:] = t
                contained[rows, self.n_segment_objects:] = c
        return touch, contained

    def _segments(self, boxes: NDArray[np.float64], seg: NDArray[np.float64]
                  ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        x0, y0 = boxes[:, None, 0], boxes[:, None, 1]
        x1, y1 = boxes[:, None, 2], boxes[:, None, 3]
        ax, ay = seg[None, :, 0], seg[None, :, 1]
        ex, ey = seg[None, :, 2] - ax, seg[None, :, 3] - ay
        lo = np.zeros((len(boxes), len(seg)))
        hi = np.ones((len(boxes), len(seg)))
        with np.errstate(divide='ignore', invalid='ignore'):
            for p, e, low, high in ((ax, ex, x0, x1), (ay, ey, y0, y1)):
                ta, tb = (low - p) / e, (high - p) / e
                flat = e == 0.0
                inside = (p >= low) & (p <= high)
                lo = np.maximum(lo, np.where(flat, np.where(inside, 0.0, 2.0),
                                             np.minimum(ta, tb)))
                hi = np.minimum(hi, np.where(flat, np.where(inside, 1.0, -1.0),
                                             np.maximum(ta, tb)))
        meets = lo <= hi
        mid = 0.5 * (lo + hi)
        mx, my = ax + mid * ex, ay + mid * ey
        enters = meets & (mx > x0) & (mx < x1) & (my > y0) & (my < y1)
        touch_seg = meets
        corners = np.stack([boxes[:, [0, 1]], boxes[:, [2, 1]], boxes[:, [2, 3]],
                            boxes[:, [0, 3]]], axis=1)
        capsule = np.zeros_like(meets)
        if self.inflation > 0.0:
            edges = np.concatenate([corners, np.roll(corners, -1, axis=1)], axis=2)
            gap = segment_segment_distance(edges.reshape(-1, 4), seg)
            touch_seg = meets | (gap.reshape(len(boxes), 4, -1).min(axis=1) <= self.inflation)
            # The capsule of a segment is convex: it holds the square if it holds its corners.
            far = np.zeros_like(gap[:len(boxes)])
            for j in range(4):
                cx, cy = corners[:, j, 0:1], corners[:, j, 1:2]
                with np.errstate(divide='ignore', invalid='ignore'):
                    s = np.clip(((cx - ax) * ex + (cy - ay) * ey) / (ex * ex + ey * ey), 0, 1)
                far = np.maximum(far, np.hypot(cx - ax - s * ex, cy - ay - s * ey))
            capsule = far <= self.inflation
        starts = self.segment_start
        touch = np.logical_or.reduceat(touch_seg, starts, axis=1)
        contained = np.logical_or.reduceat(capsule, starts, axis=1)
        entered = np.logical_or.reduceat(enters, starts, axis=1)
        n_walls = len(self.world.walls)
        centres = 0.5 * (boxes[:, 0:2] + boxes[:, 2:4])
        for k, polygon in enumerate(self.world.polygons):
            inside = points_in_polygon(centres, polygon)
            touch[:, n_walls + k] |= inside
            contained[:, n_walls + k] |= inside & ~entered[:, n_walls + k]
        return touch, contained

    def _circles(self, boxes: NDArray[np.float64]
                 ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        c = self.world.circles
        radius = c[None, :, 2] + self.inflation
        cx, cy = c[None, :, 0], c[None, :, 1]
        x0, y0 = boxes[:, None, 0], boxes[:, None, 1]
        x1, y1 = boxes[:, None, 2], boxes[:, None, 3]
        near = np.hypot(np.maximum(np.maximum(x0 - cx, cx - x1), 0.0),
                        np.maximum(np.maximum(y0 - cy, cy - y1), 0.0))
        far = np.hypot(np.maximum(cx - x0, x1 - cx), np.maximum(cy - y0, y1 - cy))
        return near <= radius, far <= radius


def _check_resolution(resolution: float) -> None:
    if not (isinstance(resolution, (int, float)) and math.isfinite(resolution)
            and resolution > 0.0):
        raise ValueError(f'resolution must be > 0 m, got {resolution!r}')


def _depth_for(ratio: float) -> int:
    depth = max(0, int(math.ceil(math.log2(ratio) - 1e-12)))
    if depth > MAX_DEPTH:
        raise ValueError(f'a quadtree {depth} levels deep is more than MAX_DEPTH = {MAX_DEPTH}:'
                         ' coarsen the resolution')
    return depth


def _subdivide(max_depth: int, classify: Any, max_objects: Optional[int]
               ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int8],
                          list[NDArray[np.bool_]]]:
    """Split from the root level by level; return the leaves' depth, index, state, objects."""
    depth_out, index_out, state_out, touch_out = [], [], [], []
    index = np.zeros((1, 2), np.int64)
    children = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.int64)
    for depth in range(max_depth + 1):
        touch, contained, state = classify(depth, index)
        if max_objects is None:
            split = state == MIXED
        else:
            split = touch.sum(axis=1) > max_objects
        if depth == max_depth:
            split[:] = False
        keep = ~split
        depth_out.append(np.full(int(keep.sum()), depth, np.int64))
        index_out.append(index[keep])
        state_out.append(state[keep])
        if touch is not None:
            touch_out.extend(touch[keep])
        index = (2 * index[split][:, None, :] + children).reshape(-1, 2)
        if len(index) == 0:
            break
    return (np.concatenate(depth_out), np.vstack(index_out), np.concatenate(state_out),
            touch_out)


def _states(free: NDArray[np.bool_], occupied: NDArray[np.bool_]) -> NDArray[np.int8]:
    return np.where(free, FREE, np.where(occupied, OCCUPIED, MIXED)).astype(np.int8)


def _sorted(origin: tuple[float, float, float], size: float, max_depth: int,
            depth: NDArray[np.int64], index: NDArray[np.int64], state: NDArray[np.int8],
            objects: tuple[tuple[int, ...], ...]) -> Quadtree:
    side = np.left_shift(1, max_depth - depth)
    order = np.argsort(_morton(index[:, 0] * side, index[:, 1] * side))
    return Quadtree(origin, size, max_depth, depth[order], index[order], state[order],
                    tuple(objects[k] for k in order) if objects else ())


def _from_world(world: World, resolution: float, max_objects: Optional[int],
                bounds: Optional[ArrayLike], margin: float) -> Quadtree:
    if bounds is None:
        r = world.inflation
        c = world.circles
        points = np.vstack([world.segments[:, 0:2] - r, world.segments[:, 2:4] + r,
                            world.segments[:, 0:2] + r, world.segments[:, 2:4] - r,
                            c[:, 0:2] - (c[:, 2:3] + r), c[:, 0:2] + (c[:, 2:3] + r)])
        if len(points) == 0:
            raise ValueError('the world has no obstacle: give the bounds of the quadtree')
        low, high = points.min(axis=0) - margin, points.max(axis=0) + margin
    else:
        b = np.asarray(bounds, dtype=np.float64)
        if b.shape != (4,) or not np.isfinite(b).all() or not (b[2:] > b[:2]).all():
            raise ValueError(f'bounds must be finite [xmin, ymin, xmax, ymax], got {bounds!r}')
        low, high = b[:2], b[2:]
    size = float((high - low).max())
    max_depth = _depth_for(size / resolution)
    classifier = _WorldClassifier(world)

    def classify(depth: int, index: NDArray[np.int64]) -> Any:
        side = size / (1 << depth)
        boxes = np.hstack([low + index * side, low + (index + 1) * side])
        touch, contained = classifier.classify(boxes)
        free, inside = np.asarray(~touch.any(axis=1)), np.asarray(contained.any(axis=1))
        return touch, contained, _states(free, inside)

    depth, index, state, touch = _subdivide(max_depth, classify, max_objects)
    objects = tuple(tuple(int(i) for i in np.nonzero(t)[0]) for t in touch)
    return _sorted((float(low[0]), float(low[1]), 0.0), size, max_depth, depth, index, state,
                   objects)


def _from_grid(grid: OccupancyGrid, resolution: float) -> Quadtree:
    block = 1 << max(0, int(math.floor(math.log2(resolution / grid.resolution) + 1e-12)))
    max_depth = _depth_for(max(grid.width, grid.height) / block)
    n = block << max_depth
    occupied = np.ones((n, n), dtype=bool)             # the padding beyond the map: occupied
    occupied[:grid.height, :grid.width] = grid.occupied
    table = np.zeros((n + 1, n + 1), np.int64)
    table[1:, 1:] = occupied.cumsum(axis=0).cumsum(axis=1)

    def classify(depth: int, index: NDArray[np.int64]) -> Any:
        side = n >> depth
        u0, v0 = index[:, 0] * side, index[:, 1] * side
        u1, v1 = u0 + side, v0 + side
        count = table[v1, u1] - table[v0, u1] - table[v1, u0] + table[v0, u0]
        return None, None, _states(np.asarray(count == 0), np.asarray(count == side * side))

    depth, index, state, _ = _subdivide(max_depth, classify, None)
    return _sorted(grid.origin, n * grid.resolution, max_depth, depth, index, state, ())


def build_quadtree(source: Union[World, OccupancyGrid], resolution: float,
                   max_objects: Optional[int] = None, bounds: Optional[ArrayLike] = None,
                   margin: float = 0.5) -> Quadtree:
    """
    Return the region quadtree (or, with ``max_objects`` = N, the N-object quadtree) of a world.

    Parameters
    ----------
    source : World or OccupancyGrid
        Walls, polygons and circles (grown by the world's inflation), or a grid's occupied
        cells. A World holding only a grid is its grid; one with both is refused.
    resolution : float
        The finest leaf's side [m] (at most; a grid's is a power-of-two block of cells).
    max_objects : int, optional
        N of an N-object quadtree (World only): split while a node holds more than N objects.
    bounds : array_like, optional
        [xmin, ymin, xmax, ymax] [m] the root must cover (World only); default: the obstacles'
        bounding box grown by ``margin`` [m].
    margin : float
        [m] >= 0, around the obstacles when no ``bounds`` are given (World only).

    Raises
    ------
    ValueError
        A bad resolution or bounds, an empty world without bounds, more than MAX_DEPTH levels,
        max_objects < 0 or with a grid, a World with both geometry and a grid.

    Examples
    --------
    A disc of radius 1 in a 4 m square: the leaves fill the square, none free touches the disc:

    >>> tree = build_quadtree(World(circles=[[0.0, 0.0, 1.0]]), 0.25, margin=1.0)
    >>> tree.size, tree.max_depth, float(tree.areas.sum())
    (4.0, 4, 16.0)
    >>> [int((tree.state == s).sum()) for s in (FREE, OCCUPIED, MIXED)]
    [56, 20, 36]

    """
    _check_resolution(resolution)
    if max_objects is not None and not (isinstance(max_objects, int) and max_objects >= 0):
        raise ValueError(f'max_objects must be an integer >= 0, got {max_objects!r}')
    if isinstance(source, World) and source.grid is not None:
        if len(source.segments) or len(source.circles):
            raise ValueError('a World with both a grid and geometry: build the quadtree of '
                             'its grid or of its geometry')
        source = source.grid
    if isinstance(source, OccupancyGrid):
        if max_objects is not None or bounds is not None:
            raise ValueError('an occupancy grid gives a region quadtree on its own extent: no '
                             'max_objects, no bounds')
        return _from_grid(source, resolution)
    if not isinstance(source, World):
        raise ValueError(f'source must be a World or an OccupancyGrid, got '
                         f'{type(source).__name__}')
    if not (math.isfinite(margin) and margin >= 0.0):
        raise ValueError(f'margin must be >= 0 m, got {margin!r}')
    return _from_world(source, resolution, max_objects, bounds, margin)
