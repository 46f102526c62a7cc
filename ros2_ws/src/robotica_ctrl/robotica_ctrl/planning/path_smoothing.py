"""
Smoothing a planned polyline without losing clearance: constrained Laplacian smoothing.

A planner's path (A*, the visibility graph or a Voronoi roadmap of book §12.6, shortcut by
:mod:`~robotica_ctrl.planning.path_shortcut` or not) has sharp corners, which a vehicle
cannot follow (§10.4: heading and curvature must be continuous). The classic smoother
(e.g. Thrun's, as in PythonRobotics' path smoothing) resamples the path every ``spacing`` and
moves each interior point y_i, ends fixed, by gradient steps on
Σ α |x_i - y_i|² + β |y_{i-1} - 2 y_i + y_{i+1}|²:

    y_i <- y_i + α (x_i - y_i) + β (y_{i-1} + y_{i+1} - 2 y_i)

(x the resampled input; α + 2β <= 1 makes each step a convex combination of x_i and the
three points, so the path stays in their hull). Unconstrained it pulls every bend tight around
its obstacle. The constraint added here (our choice; Gauss-Seidel order, one point at a time,
so the path is valid after every move): a move is kept only if

* the footprint at the new pose keeps a clearance >= min(``clearance``, the clearance that
  pose had in the resampled input), by :func:`robotica_kin.world.footprint_distance`; by
  induction no pose ever ends nearer an obstacle than that, and
* every step of the path it changes stays collision-free: a step from pose a to pose b whose
  clearances c_a, c_b satisfy c_a + c_b > |Δp| + ρ |Δθ| is free (clearance is 1-Lipschitz in
  the moving body, which moves at most |Δp| + ρ |Δθ|, ρ its farthest vertex), else it is swept
  (:func:`robotica_kin.world.swept_collision`).

So a collision-free input gives a collision-free output (a colliding input is refused).
Poses: points with the tangent heading (the chord from the previous point to the next,
:func:`~robotica_ctrl.planning.path_collision.path_headings`), which matters for a polygon
footprint only; moving a point changes the headings of its neighbours, so their clearances and
the four steps around it are checked too. Frames: map, [m], [rad].
"""

import math
from typing import Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.path_collision import (check_clearance, check_path_points,
                                                   path_headings, pose_collision)
from robotica_ctrl.planning.path_shortcut import path_length
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_kin.angles import wrap_to_pi
from robotica_kin.world import footprint_distance, swept_collision, validate_polygon, World
from robotica_kin.world.queries import Footprint

__all__ = ['resample_polyline', 'smooth_path']

_HALVINGS = 4   # a refused move is retried at 1/2, 1/4 and 1/8 of its length


def resample_polyline(points: ArrayLike, spacing: float) -> NDArray[np.float64]:
    """
    Return the polyline with points added so that none is more than ``spacing`` [m] apart.

    Every input vertex is kept (the path is the same); each segment of length ℓ is cut into
    ceil(ℓ / spacing) equal parts. Repeated consecutive points are dropped.

    >>> resample_polyline([[0, 0], [1, 0], [1, 0.5]], 0.4).round(4).tolist()
    [[0.0, 0.0], [0.3333, 0.0], [0.6667, 0.0], [1.0, 0.0], [1.0, 0.25], [1.0, 0.5]]
    """
    p = check_path_points(points)
    if not (isinstance(spacing, (int, float)) and math.isfinite(spacing) and spacing > 0.0):
        raise ValueError(f'spacing must be finite and > 0 m, got {spacing!r}')
    p = p[np.r_[True, np.any(np.diff(p, axis=0) != 0.0, axis=1)]]
    parts = [p[:1]]
    for a, b in zip(p[:-1], p[1:]):
        n = max(1, math.ceil(math.hypot(*(b - a)) / spacing - 1e-9))
        t = np.arange(1, n + 1)[:, None] / n
        parts.append(a + t * (b - a))
    return np.vstack(parts)


def _footprint_reach(footprint: Footprint) -> float:
    """Return ρ [m], the farthest vertex of a polygon footprint; 0 for a circle (any heading)."""
    if isinstance(footprint, (int, float)) and not isinstance(footprint, bool):
        if not (math.isfinite(footprint) and footprint > 0.0):
            raise ValueError(f'footprint radius must be > 0 m, got {footprint!r}')
        return 0.0
    polygon = validate_polygon(footprint, 'footprint')
    return float(np.hypot(polygon[:, 0], polygon[:, 1]).max())


def _heading(y: NDArray[np.float64], j: int) -> float:
    """Return the tangent heading [rad] at point j (as :func:`path_headings`)."""
    a, b = y[max(j - 1, 0)], y[min(j + 1, len(y) - 1)]
    return math.atan2(b[1] - a[1], b[0] - a[0])


def _check_weights(weight_data: float, weight_smooth: float, tolerance: float,
                   max_sweeps: int) -> None:
    if not (math.isfinite(weight_data) and 0.0 <= weight_data < 1.0):
        raise ValueError(f'weight_data must be in [0, 1), got {weight_data!r}')
    if not (math.isfinite(weight_smooth) and 0.0 < weight_smooth <= 0.5):
        raise ValueError(f'weight_smooth must be in (0, 0.5], got {weight_smooth!r}')
    if weight_data + 2.0 * weight_smooth > 1.0:
        raise ValueError(f'weight_data + 2 weight_smooth must be <= 1 (a convex step), got '
                         f'{weight_data!r} + 2 * {weight_smooth!r}')
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise ValueError(f'tolerance must be finite and > 0 m, got {tolerance!r}')
    if isinstance(max_sweeps, bool) or not isinstance(max_sweeps, int) or max_sweeps < 1:
        raise ValueError(f'max_sweeps must be an integer >= 1, got {max_sweeps!r}')


class _Smoother:
    """The path being smoothed: points, headings, clearances and the acceptance test."""

    def __init__(self, world: World, footprint: Footprint, y: NDArray[np.float64],
                 reach: float) -> None:
        self.world, self.footprint, self.reach = world, footprint, reach
        self.y = y
        self.theta = path_headings(y) if reach > 0.0 else np.zeros(len(y))
        self.clear = np.array([self.clearance(j) for j in range(len(y))])

    def pose(self, j: int) -> list[float]:
        return [float(self.y[j, 0]), float(self.y[j, 1]), float(self.theta[j])]

    def clearance(self, j: int) -> float:
        return footprint_distance(self.world, self.footprint, self.pose(j))

    def step_free(self, j: int) -> bool:
        """Return whether the step from pose j to pose j + 1 is collision-free."""
        moved = math.hypot(*(self.y[j + 1] - self.y[j]).tolist())
        turned = abs(wrap_to_pi(float(self.theta[j + 1] - self.theta[j])))
        if self.clear[j] + self.clear[j + 1] > moved + self.reach * turned:
            return True
        return swept_collision(self.world, self.footprint, self.pose(j),
                               self.pose(j + 1)) is None

    def try_move(self, i: int, target: NDArray[np.float64], required: NDArray[np.float64]
                 ) -> bool:
        """Move point i to ``target`` if the constraints hold; return whether it moved."""
        last = len(self.y) - 1
        poses = range(max(i - 1, 0), min(i + 1, last) + 1) if self.reach > 0.0 else range(i, i + 1)
        old = self.y[i].copy(), self.theta[poses].copy(), self.clear[poses].copy()
        self.y[i] = target
        for j in poses:
            if self.reach > 0.0:
                self.theta[j] = _heading(self.y, j)
            self.clear[j] = self.clearance(j)
        steps = range(max(poses[0] - 1, 0), min(poses[-1], last - 1) + 1)
        if (self.clear[poses] >= required[poses]).all() and all(
                self.step_free(j) for j in steps):
            return True
        self.y[i], self.theta[poses], self.clear[poses] = old
        return False


def smooth_path(world: World, points: ArrayLike, footprint: Footprint, clearance: float = 0.0,
                spacing: float = 0.1, weight_data: float = 0.1, weight_smooth: float = 0.4,
                tolerance: float = 1e-4, max_sweeps: int = 100,
                budget: SearchBudget = SearchBudget(),
                clock: Optional[Callable[[], float]] = None) -> PlanResult:
    """
    Return the path resampled every ``spacing`` and smoothed, keeping clearance.

    Parameters
    ----------
    world : World
        The obstacles (map frame).
    points : array_like, shape (N, 2)
        The planned path [m], N >= 2, collision-free for ``footprint``.
    footprint : float or array_like (v, 2)
        The robot: a radius [m] or a polygon [m] in ``base_link`` (heading: the path's tangent).
    clearance : float
        [m] >= 0: no pose ends nearer an obstacle than min(clearance, its input clearance).
    spacing : float
        Largest distance [m] between the resampled points, > 0.
    weight_data, weight_smooth : float
        α in [0, 1) (pull to the input) and β in (0, 0.5] (smoothing), α + 2β <= 1.
    tolerance : float
        [m] > 0: stop when no point moves more than this in a sweep.
    max_sweeps : int
        Sweeps over the points at most.
    budget : SearchBudget
        ``max_expansions`` bounds the tried moves, ``max_seconds`` their time by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only the moves count.

    Returns
    -------
    PlanResult
        ``path`` (M, 2) with the input's ends, ``cost`` its length [m], ``expansions`` the
        tried moves; ``details``: ``headings`` (M,) [rad], ``clearance`` (M,) [m] per pose,
        ``sweeps``, ``converged`` (the last sweep moved less than ``tolerance``),
        ``budget_hit``. No path when the input collides (``collision``: (step, fraction)).

    Raises
    ------
    ValueError
        For points not (N, 2) finite, a bad footprint, clearance, spacing, weights,
        tolerance or max_sweeps.

    Examples
    --------
    A right-angle bend in an empty world is rounded, its ends kept:

    >>> result = smooth_path(World(walls=[[5, 5, 6, 5]]), [[0, 0], [2, 0], [2, 2]], 0.2,
    ...                      spacing=0.25)
    >>> result.found, result.path[[0, -1]].tolist(), result.cost < 4.0
    (True, [[0.0, 0.0], [2.0, 2.0]], True)

    """
    margin = check_clearance(clearance)
    reach = _footprint_reach(footprint)
    _check_weights(weight_data, weight_smooth, tolerance, max_sweeps)
    x = resample_polyline(points, spacing)
    if len(x) < 2:
        raise ValueError('points must hold at least two distinct points')
    smoother = _Smoother(world, footprint, x.copy(), reach)
    poses = np.column_stack([x, smoother.theta])
    hit = pose_collision(world, footprint, poses)
    if hit is not None:
        return PlanResult.none(f'the path collides: the step from {poses[hit[0]].tolist()} '
                               f'meets an obstacle at {hit[1]:.3f} of its length',
                               collision=hit)
    required = np.minimum(margin, smoother.clear)
    began = clock() if clock is not None else 0.0
    tried, sweeps, converged, exhausted = 0, 0, False, False
    y = smoother.y
    while sweeps < max_sweeps and not converged and not exhausted:
        sweeps += 1
        largest = 0.0
        for i in range(1, len(y) - 1):
            if tried >= budget.max_expansions or (
                    clock is not None and clock() - began > budget.max_seconds):
                exhausted = True
                break
            tried += 1
            target = (y[i] + weight_data * (x[i] - y[i])
                      + weight_smooth * (y[i - 1] + y[i + 1] - 2.0 * y[i]))
            step = target - y[i]
            for _ in range(_HALVINGS):
                move = math.hypot(*step.tolist())
                if move <= 0.0 or smoother.try_move(i, y[i] + step, required):
                    largest = max(largest, move)
                    break
                step = 0.5 * step
        converged = not exhausted and largest < tolerance
    return PlanResult(path=y.copy(), cost=path_length(y), expansions=tried,
                      details={'headings': smoother.theta.copy(),
                               'clearance': smoother.clear.copy(), 'sweeps': sweeps,
                               'converged': converged, 'budget_hit': exhausted})
