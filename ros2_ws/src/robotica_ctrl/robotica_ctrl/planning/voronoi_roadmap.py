"""
A roadmap on the generalised Voronoi diagram, searched by Dijkstra (book §12.6.2, free space).

The generalised Voronoi diagram is the set of points equidistant from two or more obstacle
boundaries: the paths on it keep as far from the obstacles as the free space allows. It is
approximated (as is usual) by the Voronoi diagram of points sampled along the boundaries
(``scipy.spatial.Voronoi``): the obstacles' walls, edges and circles every ``spacing`` [m],
and the centres of the occupied cells of a grid that border a free one. A frame of points
around everything, ``margin`` [m] beyond the obstacles, the start and the goal, bounds the
diagram so that the roadmap also goes round the outside of the obstacles; it is no obstacle.

A ridge (an edge of the diagram) becomes a roadmap edge only when its clearance, the distance
to the obstacles (:func:`robotica_kin.world.distance_to_obstacles`, exact; the world's
inflation counted), exceeds the robot's radius r along its whole length: it is checked at
points at most h = ``spacing`` / 2 apart, and kept when the least clearance found, less h / 2,
is above r (the clearance changes by at most the distance moved, so none between the checked
points can be lower). Ridges between two samples of one straight edge cross it and are
dropped by that test; those between samples of different boundaries form the diagram's
skeleton.

The start and the goal join the roadmap by straight segments on which a disc of radius r
touches nothing (:func:`robotica_kin.world.swept_collision`; a ray cast for r = 0), to each
of their ``connect`` nearest roadmap nodes in sight; then ``scipy.sparse.csgraph.dijkstra``
finds the shortest path on the graph. When the goal is in sight of the start that way, the
straight segment is the path (no roadmap is built). Work: the ridges whose
clearance is checked, counted as expansions against the :class:`~.plan_result.SearchBudget`.
"""

import math
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.roadmap_search import roadmap_path
from robotica_ctrl.planning.search_setup import (BudgetMeter, Clock, IN_OBSTACLE, planar_point,
                                                 robot_radius as radius_value)
from robotica_kin.world import cast_rays, distance_to_obstacles, swept_collision, World
from scipy.spatial import cKDTree, Voronoi

__all__ = ['boundary_samples', 'voronoi_roadmap']


def _positive(name: str, value: float) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
        raise ValueError(f'{name} must be > 0 m, got {value!r}')
    return float(value)


def _along(segments: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """Return points along each segment (n, 4), both ends included, at most spacing apart."""
    points = []
    for x1, y1, x2, y2 in segments:
        k = max(1, int(math.ceil(math.hypot(x2 - x1, y2 - y1) / spacing)))
        t = np.linspace(0.0, 1.0, k + 1)[:, None]
        points.append(np.column_stack([x1 + t[:, 0] * (x2 - x1), y1 + t[:, 0] * (y2 - y1)]))
    return np.vstack(points) if points else np.zeros((0, 2))


def boundary_samples(world: World, spacing: float) -> NDArray[np.float64]:
    """
    Return points (k, 2) [m] along the obstacles' boundaries, at most ``spacing`` [m] apart.

    Walls and polygon edges with both ends, circles round their circumference, and the
    centres of a grid's occupied cells that have a free (or unknown) 4-neighbour or lie on
    the grid's border; duplicates removed.

    >>> boundary_samples(World(walls=[[0, 0, 1, 0]]), 0.5).tolist()
    [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]]
    """
    spacing = _positive('spacing', spacing)
    parts = [_along(world.segments, spacing)]
    for cx, cy, rho in world.circles:
        k = max(8, int(math.ceil(2.0 * math.pi * rho / spacing)))
        angle = np.linspace(0.0, 2.0 * math.pi, k, endpoint=False)
        parts.append(np.column_stack([cx + rho * np.cos(angle), cy + rho * np.sin(angle)]))
    grid = world.grid
    if grid is not None:
        occupied = np.pad(grid.occupied, 1)
        inner = occupied[1:-1, 1:-1]
        edge = inner & ~(occupied[:-2, 1:-1] & occupied[2:, 1:-1]
                         & occupied[1:-1, :-2] & occupied[1:-1, 2:])
        rows, cols = np.nonzero(edge)
        parts.append(grid.cell_to_world(np.column_stack([cols, rows])))
    return np.unique(np.vstack(parts), axis=0)


def _frame(low: NDArray[np.float64], high: NDArray[np.float64],
           spacing: float) -> NDArray[np.float64]:
    (x0, y0), (x1, y1) = low, high
    sides = np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]])
    return _along(sides, spacing)


def _clear(world: World, a: NDArray[np.float64], b: NDArray[np.float64], radius: float) -> bool:
    """Return whether a disc of ``radius`` (a point if 0) moves from a to b touching nothing."""
    if radius > 0.0:
        return swept_collision(world, radius, [a[0], a[1], 0.0], [b[0], b[1], 0.0]) is None
    length = float(np.hypot(*(b - a)))
    if length == 0.0:
        return True
    hits = cast_rays(world, a, [math.atan2(b[1] - a[1], b[0] - a[0])], length)
    return not bool(hits.hit[0])


def _ridge_clearance(world: World, vertices: NDArray[np.float64],
                     ridges: NDArray[np.intp], step: float) -> NDArray[np.float64]:
    """Return the least clearance [m] each ridge (e, 2) can have: the least checked - step/2."""
    a, b = vertices[ridges[:, 0]], vertices[ridges[:, 1]]
    counts = np.maximum(1, np.ceil(np.hypot(*(b - a).T) / step).astype(np.int64))
    owner = np.repeat(np.arange(len(ridges)), counts + 1)
    first = np.concatenate([[0], np.cumsum(counts + 1)[:-1]])
    t = (np.arange(len(owner)) - first[owner]) / counts[owner]
    points = a[owner] + t[:, None] * (b - a)[owner]
    clearance = distance_to_obstacles(world, points)
    least = np.full(len(ridges), np.inf)
    np.minimum.at(least, owner, clearance)
    spacing = np.hypot(*(b - a).T) / counts
    return least - 0.5 * spacing


def voronoi_roadmap(world: World, start: ArrayLike, goal: ArrayLike, robot_radius: float = 0.0,
                    spacing: float = 0.1, margin: Optional[float] = None, connect: int = 8,
                    budget: SearchBudget = SearchBudget(), clock: Optional[Clock] = None
                    ) -> PlanResult:
    """
    Return a path on the generalised Voronoi roadmap from start to goal (book §12.6.2).

    Parameters
    ----------
    world : World
        Walls, polygons, circles and/or an occupancy grid, map frame.
    start, goal : array_like, shape (2,)
        Points (x, y) [m], map frame.
    robot_radius : float
        r [m] >= 0: every point of the path keeps a clearance above r.
    spacing : float
        Boundary sampling step [m] > 0 (finer: closer to the true diagram, more work).
    margin : float, optional
        Distance [m] of the bounding frame beyond everything; default 1 m + 2 r.
    connect : int
        How many of the nearest roadmap nodes the start and the goal try to reach (>= 1).
    budget : SearchBudget
        At most ``max_expansions`` ridges checked and ``max_seconds`` by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only the ridges are bounded.

    Returns
    -------
    PlanResult
        ``path`` (k, 2) [m] S, roadmap vertices, G; ``cost`` its length [m]. None with the
        reason: the start or the goal in an obstacle or within r of one, no roadmap node in
        sight of either, the goal unreachable on the roadmap, the budget exhausted.
        ``details``: ``roadmap`` (e, 4) [m] the kept ridges, ``samples`` (k, 2) [m] the
        boundary points, ``clearance`` (e,) [m] the kept ridges' least clearance bound.

    Raises
    ------
    ValueError
        For a non-finite start or goal, r < 0, spacing or margin not > 0, connect < 1.

    Examples
    --------
    Round a wall, keeping more than 0.3 m from it:

    >>> plan = voronoi_roadmap(World(walls=[[3, -1, 3, 1]]), [2, 0], [4, 0], robot_radius=0.3)
    >>> plan.found, bool(plan.details['clearance'].min() > 0.3), len(plan.path) > 2
    (True, True, True)

    """
    s, g = planar_point('start', start), planar_point('goal', goal)
    r = radius_value(robot_radius)
    spacing = _positive('spacing', spacing)
    margin = _positive('margin', margin) if margin is not None else 1.0 + 2.0 * r
    if not (isinstance(connect, int) and connect >= 1):
        raise ValueError(f'connect must be an integer >= 1, got {connect!r}')
    meter = BudgetMeter(budget, clock)
    ends = distance_to_obstacles(world, np.vstack([s, g]))
    for clearance, role, p in zip(ends, ('start', 'goal'), (s, g)):
        if clearance <= r:
            where = 'inside an obstacle' if clearance == 0.0 else \
                f'{clearance:.3g} m from an obstacle, not more than the radius {r:g} m'
            return PlanResult.none(f'{IN_OBSTACLE[role]}: ({p[0]:g}, {p[1]:g}) m lies {where}')
    samples = boundary_samples(world, spacing)
    details: dict[str, Any] = {'samples': samples}
    if np.array_equal(s, g):
        return PlanResult(s[None, :], 0.0, details=details)
    if _clear(world, s, g, r):       # in sight: the straight segment is the shortest path
        return PlanResult(np.vstack([s, g]), float(np.hypot(*(g - s))),
                          details={**details, 'roadmap': np.zeros((0, 4))})
    everything = np.vstack([samples, s, g])
    low, high = everything.min(axis=0) - margin, everything.max(axis=0) + margin
    diagram = Voronoi(np.vstack([samples, _frame(low, high, max(spacing, margin / 4.0))]))
    ridges = np.array([v for v in diagram.ridge_vertices if min(v) >= 0], dtype=np.intp)
    ridges = ridges.reshape(-1, 2)
    if len(ridges) > budget.max_expansions:
        return PlanResult.none(f'the search budget was exhausted: {len(ridges)} ridges to '
                               f'check, more than the {budget.max_expansions} allowed',
                               **details)
    vertices = diagram.vertices
    inside = ((vertices >= low) & (vertices <= high)).all(axis=1)
    ridges = ridges[inside[ridges].all(axis=1)]
    bound = _ridge_clearance(world, vertices, ridges, 0.5 * spacing)
    keep = bound > r
    ridges, bound = ridges[keep], bound[keep]
    details['roadmap'] = np.hstack([vertices[ridges[:, 0]], vertices[ridges[:, 1]]])
    details['clearance'] = bound
    reason = meter.overtime(f' (after checking {len(keep)} ridges)')
    if reason:
        return PlanResult.none(reason, len(keep), **details)
    return _search(world, s, g, r, vertices, ridges, connect, len(keep), details)


def _search(world: World, s: NDArray[np.float64], g: NDArray[np.float64], r: float,
            vertices: NDArray[np.float64], ridges: NDArray[np.intp], connect: int,
            work: int, details: dict[str, Any]) -> PlanResult:
    """Join S and G to the roadmap and return Dijkstra's shortest path on it."""
    used = np.unique(ridges)
    nodes = np.vstack([s, g, vertices[used]])
    index = np.full(len(vertices), -1)
    index[used] = np.arange(len(used)) + 2
    edges = [index[ridges]]
    tree = cKDTree(nodes[2:]) if len(used) else None
    for k, (role, p) in enumerate((('start', s), ('goal', g))):
        linked = []
        if tree is not None:
            _, near = tree.query(p, k=min(connect, len(used)))
            for m in np.atleast_1d(near):
                if _clear(world, p, nodes[m + 2], r):
                    linked.append([k, m + 2])
        if not linked:
            return PlanResult.none(f'the {role} cannot reach the roadmap: none of its '
                                   f'{connect} nearest nodes is in sight with a clearance '
                                   f'above {r:g} m', work, **details)
        edges.append(np.array(linked))
    return roadmap_path(nodes, np.vstack(edges), work, details, 'the goal is unreachable: no '
                        f'roadmap path with a clearance above {r:g} m joins it to the start')
