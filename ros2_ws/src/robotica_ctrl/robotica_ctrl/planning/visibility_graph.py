"""
The visibility graph and Dijkstra's shortest path (book §12.6.2, fig. 12.11; §12.6.3, fig. 12.12).

The nodes are the start S, the goal G and the obstacles' vertices; an edge joins two nodes
when the segment between them crosses no obstacle (it may run along an edge or touch a
vertex); its weight is its length. For a point among polygons the shortest path is a chain of
such segments, so Dijkstra's search of the graph (``scipy.sparse.csgraph.dijkstra``) gives the
optimal path: optimal in 2-D for a point among convex polygons, as the book says, and here
among simple (non-convex) polygons and walls too, whose segment test is exact for them.

A circular robot of radius r is a point among the obstacles grown by r (§12.4.4, §12.6.3: the
C-obstacles of a disc). The growth is the Minkowski sum with a disc, whose boundary is curved;
here the disc is replaced by the regular polygon of ``sides`` sides circumscribed about it, so
each grown obstacle is a polygon that contains the exact one (conservative: the path keeps at
least r from the obstacles, and at most r (1 / cos(π / sides) - 1) more than needed near a
vertex: 2 % of r with 16 sides). A convex polygon grows into the convex hull of its vertices
plus the disc polygon's (``scipy.spatial.ConvexHull``); a non-convex one into the union of
itself and of each edge's grown capsule (a point of P ⊕ D lies in P, or within D of the
boundary point where its segment leaves P); a wall into its capsule; a circle of radius ρ
into the regular polygon circumscribed about the circle of radius ρ + r. The world's own
``inflation`` (:func:`robotica_kin.world.grow`) adds to r. Circles are polygons of ``sides``
sides even with r = 0. Without growth, walls stay zero-thickness segments that a path may not
cross.

The test of a segment: it must not properly cross an obstacle's edge (the two segments cross
at a point interior to both); where it passes through an obstacle vertex, it must not pass
between the edges that meet there (into a polygon through its vertex, through the joint of
two walls, or through a T-joint: an edge is cut at every vertex that lies on it); and each of
its pieces between those vertices must have its midpoint outside every grown obstacle's
interior. Vertices inside another obstacle are no nodes. At a vertex the edges that meet
there cut the plane into sectors, and the vertex is one node per sector (a path may not pass
from one to another there); a segment along an edge is a lane on each side.

Only the segments tangent to the obstacles at their vertex ends are tested (the reduced
visibility graph: a shortest path bends round a vertex only with the obstacle inside the bend,
so at each of its vertices both edges lie on one side of the segment). Work: the segments
tested, at most n (n - 1) / 2 for n points (S, G and the vertices), are counted as expansions
against the :class:`~.plan_result.SearchBudget`.
"""

import math
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.roadmap_search import roadmap_path
from robotica_ctrl.planning.search_setup import (BudgetMeter, Clock, IN_OBSTACLE, planar_point,
                                                 robot_radius as radius_value)
from robotica_kin.world import World
from robotica_kin.world.segment_geometry import point_segment_distance, points_in_polygon
from robotica_kin.world.shapes import polygon_edges
from scipy.spatial import ConvexHull

__all__ = ['disc_polygon', 'grown_obstacles', 'visibility_graph']

_CHUNK = 4096               # segments tested against all edges at once (memory: chunk x edges)
_ANGLE_TOLERANCE = 1e-9     # [rad] a segment this close to a ray's direction runs along it


def disc_polygon(radius: float, sides: int = 16) -> NDArray[np.float64]:
    """
    Return the regular polygon (sides, 2) [m] circumscribed about the disc of ``radius``.

    Its vertices lie at radius / cos(π / sides) from the origin, counter-clockwise; the disc
    touches the middle of each edge. ValueError for radius <= 0 or fewer than 3 sides.

    >>> disc_polygon(1.0, 4).round(4).tolist()
    [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]]
    """
    if not (math.isfinite(radius) and radius > 0.0):
        raise ValueError(f'radius must be > 0 m, got {radius!r}')
    if not (isinstance(sides, int) and sides >= 3):
        raise ValueError(f'sides must be an integer >= 3, got {sides!r}')
    angles = (np.arange(sides) + 0.5) * (2.0 * math.pi / sides)
    reach = radius / math.cos(math.pi / sides)
    return np.column_stack([reach * np.cos(angles), reach * np.sin(angles)])


def _hull(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the convex hull's vertices (h, 2), counter-clockwise."""
    return np.asarray(points[ConvexHull(points).vertices])


def _is_convex(polygon: NDArray[np.float64]) -> bool:
    e = np.roll(polygon, -1, axis=0) - polygon
    turn = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
    return bool((turn >= 0.0).all() or (turn <= 0.0).all())


def grown_obstacles(world: World, robot_radius: float = 0.0, sides: int = 16
                    ) -> tuple[list[NDArray[np.float64]], NDArray[np.float64]]:
    """
    Return the obstacles of ``world`` grown by r as polygons, and the walls left ungrown.

    r = ``world.inflation`` + ``robot_radius`` [m]; the growth is the Minkowski sum with
    :func:`disc_polygon` (r, ``sides``), see the module's docstring. Returns the polygons
    (each (v, 2) [m], map frame; they may overlap) and, when r = 0, the walls (w, 4) [m]
    (zero thickness); with r > 0 every wall is a polygon and the walls' table is empty.

    Examples
    --------
    >>> pieces, walls = grown_obstacles(World(walls=[[0, 0, 2, 0]]), 0.5, 4)
    >>> len(pieces), walls.shape, pieces[0].round(2).tolist()
    (1, (0, 4), [[-0.5, 0.5], [-0.5, -0.5], [2.5, -0.5], [2.5, 0.5]])

    """
    if world.grid is not None:
        raise ValueError('the visibility graph plans among walls, polygons and circles; a '
                         'world with an occupancy grid needs a grid planner (grid_astar)')
    r = world.inflation + radius_value(robot_radius)
    disc = disc_polygon(r, sides) if r > 0.0 else None
    pieces: list[NDArray[np.float64]] = []
    for polygon in world.polygons:
        if disc is None:
            pieces.append(np.asarray(polygon))
        elif _is_convex(polygon):
            pieces.append(_hull((polygon[:, None, :] + disc[None, :, :]).reshape(-1, 2)))
        else:
            pieces.append(np.asarray(polygon))
            pieces.extend(_capsule(edge, disc) for edge in polygon_edges(polygon))
    for cx, cy, rho in world.circles:
        pieces.append(disc_polygon(float(rho) + r, sides) + [cx, cy])
    if disc is None:
        return pieces, np.asarray(world.walls)
    pieces.extend(_capsule(wall, disc) for wall in world.walls)
    return pieces, np.zeros((0, 4))


def _capsule(segment: NDArray[np.float64], disc: NDArray[np.float64]) -> NDArray[np.float64]:
    ends = np.vstack([disc + segment[0:2], disc + segment[2:4]])
    return _hull(ends)


def _orientation(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64],
                 tolerance: float) -> NDArray[np.float64]:
    """Return the sign (-1, 0, 1) of the turn a -> b -> c, broadcast; 0 within tolerance."""
    turn = ((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))
    return np.where(np.abs(turn) <= tolerance, 0.0, np.sign(turn))


def _crosses(a: NDArray[np.float64], b: NDArray[np.float64], edges: NDArray[np.float64],
             tolerance: float) -> NDArray[np.bool_]:
    """Return whether each segment a-b (m,) properly crosses some edge (e, 4)."""
    if len(edges) == 0:
        return np.zeros(len(a), dtype=bool)
    c, d = edges[None, :, 0:2], edges[None, :, 2:4]
    a, b = a[:, None, :], b[:, None, :]
    proper = ((_orientation(a, b, c, tolerance) * _orientation(a, b, d, tolerance) < 0.0)
              & (_orientation(c, d, a, tolerance) * _orientation(c, d, b, tolerance) < 0.0))
    return np.asarray(proper.any(axis=1))


def _strictly_inside(points: NDArray[np.float64], pieces: list[NDArray[np.float64]],
                     tolerance: float) -> NDArray[np.bool_]:
    """Return whether each point lies inside some piece, farther than tolerance from its edge."""
    inside = np.zeros(len(points), dtype=bool)
    for piece in pieces:
        low, high = piece.min(axis=0), piece.max(axis=0)
        near = np.flatnonzero(~inside & (points > low).all(axis=1) & (points < high).all(axis=1))
        if len(near) == 0:
            continue
        p = points[near]
        hit = points_in_polygon(p, piece)
        if hit.any():
            clear = point_segment_distance(p[hit], polygon_edges(piece)).min(axis=1) > tolerance
            hit[hit] = clear
        inside[near[hit]] = True
    return inside


def _split_at(edges: NDArray[np.float64], corners: NDArray[np.float64],
              tolerance: float) -> NDArray[np.float64]:
    """Return the edges cut at every corner that lies inside one (a T-joint becomes a corner)."""
    pieces = []
    for first in range(0, len(edges), _CHUNK // 8 or 1):
        block = edges[first:first + _CHUNK // 8]
        a, e = block[:, None, 0:2], block[:, None, 2:4] - block[:, None, 0:2]
        w = corners[None, :, :] - a
        length2 = (e * e).sum(axis=2)
        t = (w * e).sum(axis=2) / np.maximum(length2, tolerance ** 2)
        off = np.abs(w[..., 0] * e[..., 1] - w[..., 1] * e[..., 0])
        inside = (off <= tolerance * np.sqrt(length2)) & (t > 1e-12) & (t < 1.0 - 1e-12)
        for k, edge in enumerate(block):
            cuts = np.concatenate([[0.0], np.sort(t[k, inside[k]]), [1.0]])
            points = edge[0:2] + cuts[:, None] * (edge[2:4] - edge[0:2])
            pieces.append(np.hstack([points[:-1], points[1:]]))
    return np.vstack(pieces) if pieces else np.zeros((0, 4))


class _Obstacles:
    """
    The grown obstacles as the segment test needs them: edges, corners and their sectors.

    At a corner, the edges that leave it (its rays, sorted by angle in [0, 2π)) cut the plane
    round it into sectors, sector k from ray k to ray k + 1 counter-clockwise. A path may not
    pass from one sector to another at the corner: that would go between obstacles that meet
    there (into a polygon through its vertex, through the joint of two walls). So a corner
    is one graph node per sector, and a segment that runs along a ray is two lanes, one on
    each side of it (a zero-thickness wall has a free side each way).
    """

    def __init__(self, pieces: list[NDArray[np.float64]], walls: NDArray[np.float64],
                 tolerance: float) -> None:
        self.pieces = pieces
        self.tolerance = tolerance
        edges = np.vstack([walls, *(polygon_edges(p) for p in pieces)])
        corners = np.unique(np.vstack([edges[:, 0:2], edges[:, 2:4]]), axis=0)
        self.edges = _split_at(edges, corners, tolerance)
        ends = np.vstack([self.edges[:, 0:2], self.edges[:, 2:4]])
        self.corners, where = np.unique(ends, axis=0, return_inverse=True)
        where = where.ravel()
        d = self.edges[:, 2:4] - self.edges[:, 0:2]
        angles = np.mod(np.concatenate([np.arctan2(d[:, 1], d[:, 0]),
                                        np.arctan2(-d[:, 1], -d[:, 0])]), 2.0 * math.pi)
        counts = np.bincount(where, minlength=len(self.corners))
        self.rays = np.full((len(self.corners), max(1, int(counts.max(initial=1)))), np.inf)
        order = np.lexsort((angles, where))
        rank = np.arange(len(order)) - np.searchsorted(where[order], where[order])
        self.rays[where[order], rank] = angles[order]
        self.sectors = np.where(counts >= 2, counts, 1)

    def sector(self, corner: NDArray[np.intp], angle: NDArray[np.float64],
               lane: int) -> NDArray[np.intp]:
        """Return the sector of each corner that a direction enters (lane ±1 on a ray)."""
        rays = self.rays[corner]
        real = np.isfinite(rays)                  # rows are padded with inf
        a = np.mod(angle, 2.0 * math.pi)[:, None]
        gap = np.abs(np.mod(np.where(real, rays, 0.0) - a + math.pi, 2.0 * math.pi) - math.pi)
        on = real & (gap <= _ANGLE_TOLERANCE)
        count = self.sectors[corner]
        below = (real & (rays < a) & ~on).sum(axis=1)
        sector = np.mod(below - 1, count)
        k = np.argmax(on, axis=1)
        sector = np.where(on.any(axis=1), np.mod(k - (lane < 0), count), sector)
        return np.asarray(np.where(count >= 2, sector, 0))

    def tangent(self, corner: NDArray[np.intp], angle: NDArray[np.float64]
                ) -> NDArray[np.bool_]:
        """
        Return whether a segment leaving each corner along ``angle`` [rad] is tangent there.

        At a corner of two edges (a polygon's vertex, two walls' joint), both edges must lie
        on one side of the segment's line (or on it); a shortest path only bends round an
        obstacle that lies inside the bend, so it never uses another segment from there. A
        corner of one edge or of three and more, or no corner (-1: S, G), passes.
        """
        result = np.ones(len(corner), dtype=bool)
        two = np.flatnonzero(corner >= 0)
        two = two[self.sectors[corner[two]] == 2]
        if len(two) == 0:
            return result
        rays = self.rays[corner[two], :2]
        sides = np.sin(rays - angle[two, None])
        result[two] = sides[:, 0] * sides[:, 1] >= -_ANGLE_TOLERANCE
        return result

    def visible(self, a: NDArray[np.float64], b: NDArray[np.float64]
                ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """Return whether each segment a-b (m,) is free on its left and on its right lane."""
        tolerance = self.tolerance
        free = ~_crosses(a, b, self.edges, tolerance ** 2)
        lanes = (free.copy(), free.copy())
        rows = np.flatnonzero(free)
        if len(rows) == 0 or len(self.corners) == 0:
            return lanes
        ab = b[rows] - a[rows]
        length = np.sqrt((ab * ab).sum(axis=1))
        # The corners on a segment, strictly between its ends, cut it into pieces.
        w = self.corners[None, :, :] - a[rows, None, :]
        t = (w * ab[:, None, :]).sum(axis=2) / np.maximum(length, tolerance)[:, None] ** 2
        off = np.abs(w[..., 0] * ab[:, None, 1] - w[..., 1] * ab[:, None, 0])
        on = (off <= tolerance * length[:, None]) & (t > 1e-12) & (t < 1.0 - 1e-12)
        points = [0.5 * (a[rows] + b[rows])]
        owners = [np.arange(len(rows))]
        for k in np.flatnonzero(on.any(axis=1)):
            corners = np.flatnonzero(on[k])
            forward = np.full(len(corners), math.atan2(ab[k, 1], ab[k, 0]))
            for lane, result in zip((1, -1), lanes):
                # Passing a corner: in from behind (lane mirrored), out ahead, one sector.
                if (self.sector(corners, forward + math.pi, -lane)
                        != self.sector(corners, forward, lane)).any():
                    result[rows[k]] = False
            cuts = np.concatenate([[0.0], np.sort(t[k, corners]), [1.0]])
            mids = 0.5 * (cuts[:-1] + cuts[1:])
            points.append(a[rows[k]] + mids[:, None] * ab[k])
            owners.append(np.full(len(mids), k))
        inside = _strictly_inside(np.vstack(points), self.pieces, tolerance)
        blocked = rows[np.unique(np.concatenate(owners)[inside])]
        for result in lanes:
            result[blocked] = False
        return lanes


def _lane_edges(obstacles: _Obstacles, points: NDArray[np.float64], corner: NDArray[np.intp],
                first: NDArray[np.intp], i: NDArray[np.intp], j: NDArray[np.intp],
                lanes: tuple[NDArray[np.bool_], NDArray[np.bool_]]
                ) -> NDArray[np.intp]:
    """Return the graph edges (e, 2) of the free lanes between points i and j (node copies)."""
    forward = np.arctan2(points[j, 1] - points[i, 1], points[j, 0] - points[i, 0])
    edges = []
    for lane, free in zip((1, -1), lanes):
        ends = []
        for at, angle, side in ((i, forward, lane), (j, forward + math.pi, -lane)):
            copy = first[at].copy()
            is_corner = corner[at] >= 0
            copy[is_corner] += obstacles.sector(corner[at][is_corner], angle[is_corner], side)
            ends.append(copy)
        edges.append(np.column_stack(ends)[free])
    return np.unique(np.vstack(edges), axis=0)


def visibility_graph(world: World, start: ArrayLike, goal: ArrayLike,
                     robot_radius: float = 0.0, sides: int = 16,
                     budget: SearchBudget = SearchBudget(), clock: Optional[Clock] = None
                     ) -> PlanResult:
    """
    Return the shortest path from start to goal by the visibility graph (book §12.6.2).

    Parameters
    ----------
    world : World
        Walls, polygons and circles (no grid), map frame.
    start, goal : array_like, shape (2,)
        Points (x, y) [m], map frame.
    robot_radius : float
        r [m] >= 0 of a circular robot: the obstacles are grown by it (:func:`grown_obstacles`).
    sides : int
        Sides of the polygon that stands for a disc (growth, circles), >= 3.
    budget : SearchBudget
        At most ``max_expansions`` segments tested, ``max_seconds`` by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only the segments are bounded.

    Returns
    -------
    PlanResult
        ``path`` (k, 2) [m] S, obstacle vertices, G; ``cost`` its length [m] (optimal among the
        grown obstacles). None with the reason: the start or the goal in a grown obstacle, the
        goal unreachable, the budget exhausted. ``details``: ``nodes`` (n, 2) [m] (S and G
        first), ``graph`` (g, 4) [m] the visible segments, ``obstacles`` the grown polygons,
        ``walls`` (w, 4) the ungrown walls.

    Raises
    ------
    ValueError
        For a world with a grid, a non-finite start or goal, r < 0, sides < 3.

    Examples
    --------
    Around a wall from (1, -1) to (1, 1), by its upper end:

    >>> plan = visibility_graph(World(walls=[[1, -1, 1, 1]]), [0, 0], [2, 0])
    >>> plan.path.tolist(), round(plan.cost, 6) == round(2 * math.sqrt(2), 6)
    ([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], True)

    """
    s, g = planar_point('start', start), planar_point('goal', goal)
    pieces, walls = grown_obstacles(world, robot_radius, sides)
    meter = BudgetMeter(budget, clock)
    scale = max([1.0, float(np.abs(np.vstack([s, g])).max())]
                + [float(np.abs(p).max()) for p in pieces] + [float(np.abs(walls).max(initial=0))])
    obstacles = _Obstacles(pieces, walls, 1e-9 * scale)
    details: dict[str, Any] = {'obstacles': pieces, 'walls': walls}
    ends_inside = _strictly_inside(np.vstack([s, g]), pieces, obstacles.tolerance)
    for inside, role, point in zip(ends_inside, ('start', 'goal'), (s, g)):
        if inside:
            return PlanResult.none(f'{IN_OBSTACLE[role]}: ({point[0]:g}, {point[1]:g}) m lies in '
                                   f'an obstacle grown by {world.inflation + robot_radius:g} m',
                                   **details)
    corners = np.flatnonzero(~_strictly_inside(obstacles.corners, pieces,
                                               obstacles.tolerance))
    points = np.vstack([s, g, obstacles.corners[corners]])
    corner = np.concatenate([[-1, -1], corners])          # the corner of each point, or -1
    copies = np.concatenate([[1, 1], obstacles.sectors[corners]])
    first = np.concatenate([[0], np.cumsum(copies)[:-1]])  # its first node (one per sector)
    nodes = np.repeat(points, copies, axis=0)
    details['nodes'] = nodes
    n = len(points)
    i, j = np.triu_indices(n, 1)
    forward = np.arctan2(points[j, 1] - points[i, 1], points[j, 0] - points[i, 0])
    tangent = obstacles.tangent(corner[i], forward) & obstacles.tangent(corner[j],
                                                                        forward + math.pi)
    i, j = i[tangent], j[tangent]
    if len(i) > budget.max_expansions:
        return PlanResult.none(f'the search budget was exhausted: {len(i)} segments to test '
                               f'between {n} points, more than the {budget.max_expansions} '
                               'allowed', **details)
    left, right = np.zeros(len(i), dtype=bool), np.zeros(len(i), dtype=bool)
    for start_row in range(0, len(i), _CHUNK):
        rows = slice(start_row, start_row + _CHUNK)
        left[rows], right[rows] = obstacles.visible(points[i[rows]], points[j[rows]])
        tested = min(start_row + _CHUNK, len(i))
        reason = meter.overtime(f' (after {tested} of {len(i)} segments)')
        if reason:
            return PlanResult.none(reason, tested, **details)
    edges = _lane_edges(obstacles, points, corner, first, i, j, (left, right))
    details['graph'] = np.hstack([nodes[edges[:, 0]], nodes[edges[:, 1]]])
    if np.array_equal(s, g):
        return PlanResult(s[None, :], 0.0, expansions=len(i), details=details)
    return roadmap_path(nodes, edges, len(i), details, 'the goal is unreachable: no chain of '
                        'visible segments joins it to the start')
