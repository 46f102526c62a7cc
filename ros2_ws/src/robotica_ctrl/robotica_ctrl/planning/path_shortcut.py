"""
Shortcutting a planned polyline by line of sight, against the world model (book §12.6).

A grid search (A*, §12.6.2) returns a staircase of cell centres, and a roadmap a path through
its nodes; both are longer than they need be and turn more often than a vehicle should. The
greedy line-of-sight shortcut (the post-processing of grid paths, cf. Theta*, Nash et al.
2007, which does it during the search) keeps, from each kept vertex, the farthest later vertex
that the robot's footprint reaches in a straight line without meeting an obstacle: the
visibility test of the visibility graph (§12.6.2), made with the footprint swept along the
segment (:func:`~robotica_ctrl.planning.path_collision.polyline_collision`).

* Collinear vertices are dropped first (no check needed: the path does not change).
* A shortcut must keep ``clearance`` [m] from every obstacle (it is tested in the world grown
  by it, §12.4.4); where no shortcut does, the path keeps its own segment. So when the input
  is collision-free the output is too, never longer, and every new segment keeps the margin:
  a margin the later rounding of corners
  (:mod:`~robotica_ctrl.planning.continuous_curvature`) can cut into.
* A path that already collides is refused with where; the work is one swept test per
  candidate, at most (N² - N)/2 for N vertices, bounded by a :class:`SearchBudget` (the path
  shortcut so far is returned, with ``details['budget_hit']``).
"""

import math
from typing import Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.path_collision import (check_clearance, check_path_points,
                                                   polyline_collision)
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_kin.world import grow, swept_collision, World
from robotica_kin.world.queries import Footprint

__all__ = ['drop_collinear', 'path_length', 'shortcut_path']

_COLLINEAR = 1e-12   # |cross| / (|a| |b|) below which two segments are collinear


def path_length(points: NDArray[np.float64]) -> float:
    """
    Return the length [m] of a polyline (N, 2) [m].

    >>> path_length(np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]))
    6.0
    """
    steps = np.diff(points, axis=0)
    return float(np.hypot(steps[:, 0], steps[:, 1]).sum())


def drop_collinear(points: ArrayLike) -> NDArray[np.float64]:
    """
    Return the polyline without repeated points and without vertices inside a straight run.

    A vertex is dropped when the segments before and after it point the same way (cross
    product below 1e-12 of their lengths' product, dot product > 0); a vertex where the path
    turns back is kept.

    >>> drop_collinear([[0, 0], [1, 0], [1, 0], [2, 0], [2, 1], [2, 2]]).tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]
    """
    p = check_path_points(points)
    p = p[np.r_[True, np.any(np.diff(p, axis=0) != 0.0, axis=1)]]
    if len(p) < 3:
        return p
    a, b = p[1:-1] - p[:-2], p[2:] - p[1:-1]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = (a * b).sum(axis=1)
    scale = np.hypot(a[:, 0], a[:, 1]) * np.hypot(b[:, 0], b[:, 1])
    straight = (np.abs(cross) <= _COLLINEAR * scale) & (dot > 0.0)
    return p[np.r_[True, ~straight, True]]


def shortcut_path(world: World, points: ArrayLike, footprint: Footprint,
                  clearance: float = 0.0, budget: SearchBudget = SearchBudget(),
                  clock: Optional[Callable[[], float]] = None) -> PlanResult:
    """
    Return the polyline shortcut by line of sight for ``footprint`` in ``world``.

    From the first point, keep the farthest later vertex whose straight segment the footprint
    drives (heading along it) at least ``clearance`` from every obstacle, else the next
    vertex; repeat from it until the last.

    Parameters
    ----------
    world : World
        The obstacles (map frame).
    points : array_like, shape (N, 2)
        The planned path [m], N >= 2.
    footprint : float or array_like (v, 2)
        The robot: a radius [m] or a polygon [m] in ``base_link``.
    clearance : float
        The margin [m] >= 0 every new segment keeps from the obstacles.
    budget : SearchBudget
        ``max_expansions`` bounds the swept tests, ``max_seconds`` their time by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only the tests count.

    Returns
    -------
    PlanResult
        ``path`` (M, 2) with M <= N, ``cost`` its length [m], ``expansions`` the swept tests;
        ``details``: ``kept`` (M,) the indices of the kept vertices in the collinear-free
        input, ``budget_hit``. No path when the input collides (``collision``: (segment,
        fraction) in the input).

    Raises
    ------
    ValueError
        For points not (N, 2) finite, a negative clearance or a bad footprint.

    Examples
    --------
    A staircase in an empty room becomes its diagonal:

    >>> room = World(walls=[[-1, -1, 5, -1], [5, -1, 5, 5], [5, 5, -1, 5], [-1, 5, -1, -1]])
    >>> stairs = [[0, 0], [1, 0], [1, 1], [2, 1], [2, 2], [3, 2], [3, 3]]
    >>> shortcut_path(room, stairs, 0.3).path.tolist()
    [[0.0, 0.0], [3.0, 3.0]]

    """
    margin = check_clearance(clearance)
    p = drop_collinear(points)
    hit = polyline_collision(world, footprint, p)
    if hit is not None:
        return PlanResult.none(
            f'the path collides: segment {hit[0]} from {p[hit[0]].tolist()} to '
            f'{p[hit[0] + 1].tolist()} meets an obstacle at {hit[1]:.3f} of its length',
            collision=hit)
    grown = grow(world, margin) if margin > 0.0 else world
    began = clock() if clock is not None else 0.0
    kept, tests, exhausted = [0], 0, False
    i = 0
    while i < len(p) - 1:
        j = i + 1
        for candidate in range(len(p) - 1, i + 1, -1):
            if tests >= budget.max_expansions or (
                    clock is not None and clock() - began > budget.max_seconds):
                exhausted = True
                break
            tests += 1
            dx, dy = (p[candidate] - p[i]).tolist()
            heading = math.atan2(dy, dx)
            if swept_collision(grown, footprint, [*p[i], heading],
                               [*p[candidate], heading]) is None:
                j = candidate
                break
        if exhausted:
            kept.extend(range(i + 1, len(p)))
            break
        kept.append(j)
        i = j
    path = p[kept]
    return PlanResult(path=path, cost=path_length(path), expansions=tests,
                      details={'kept': np.array(kept), 'budget_hit': exhausted})
