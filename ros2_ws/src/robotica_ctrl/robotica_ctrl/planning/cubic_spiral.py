"""
Posture-to-posture connection by a cubic spiral: curvature cubic in arc length (book §10.4).

Book §10.4 (seed catalogue Part 8.5) asks of a vehicle's path that it join an initial and a
final posture (position, heading and curvature fixed at both ends, fig. 10.7) with continuous
curvature and |γ| <= γ_max, and names clothoids (curvature linear in arc length). One degree
more gives the *cubic spiral* of Kelly & Nagy (2003, "Reactive nonholonomic trajectory
generation via parametric optimal control", Int. J. Robotics Research 22(7-8), 583-601;
Nagy & Kelly 2001), which meets all four end conditions with one polynomial:

    κ(s) = a + b s + c s² + d s³,   θ(s) = θ0 + a s + b s²/2 + c s³/3 + d s⁴/4   (10.80)
    x(s) = x0 + ∫ cos θ,   y(s) = y0 + ∫ sin θ   (0 <= s <= s_f)

Method (the choices are ours where the paper leaves them open): the curve is written in the
start's frame and parameterised, as in McNaughton (2011, CMU thesis), by its curvatures at
s = 0, s_f/3, 2 s_f/3, s_f: the two end ones are the postures' κ, which leaves (κ1, κ2, s_f)
for the three equations x(s_f), y(s_f), θ(s_f) = goal. θ is closed form, x and y come from
32-point Gauss-Legendre quadrature, and SciPy's trust-region least squares (``least_squares``,
method 'trf', s_f > 0) solves the system, i.e. Newton's method with a trust region as the paper
does. Starts: the quadratic curvature that turns by the heading change Δθ (wrapped to (-π, π])
over s_f0 = d (1 + Δθ²/5) + 2 |Δθ|/5 (d the chord), Nagy & Kelly's initial length, and then
0.75, 1.5 and 2.5 times it. Of the converged spirals the shortest within κ_max is kept; the
peak |κ| is exact (at the ends or at a root of κ'). When none converges, or each turns
harder than κ_max, the result says so.
"""

from functools import lru_cache
import math
from typing import Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.continuous_curvature import curve_result
from robotica_ctrl.planning.path_collision import pose_collision
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_kin.angles import wrap_to_pi
from robotica_kin.world import World
from robotica_kin.world.queries import Footprint
from scipy.optimize import least_squares

__all__ = ['cubic_spiral', 'spiral_coefficients']

_NODES = 32                      # Gauss-Legendre nodes of the end-point quadrature
_SAMPLE_NODES = 8                # nodes per sample interval
_STARTS = (1.0, 0.75, 1.5, 2.5)  # initial lengths, times the heuristic s_f0
_MAX_EVALUATIONS = 200           # residual evaluations of one start
_TOLERANCE = 1e-9                # [m] and [rad] at the goal for a converged spiral
_SAME_POINT = 1e-12              # [m] postures this close are at one point
# κ(u) = A + B u + C u² + D u³ on u = s / s_f from κ at u = 0, 1/3, 2/3, 1 (Lagrange).
_KNOTS_TO_POWERS = np.array([[1.0, 0.0, 0.0, 0.0],
                             [-5.5, 9.0, -4.5, 1.0],
                             [9.0, -22.5, 18.0, -4.5],
                             [-4.5, 13.5, -13.5, 4.5]])


@lru_cache(maxsize=4)
def _gauss(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    nodes, weights = np.polynomial.legendre.leggauss(n)
    return nodes, weights


def spiral_coefficients(knots: ArrayLike, length: float) -> NDArray[np.float64]:
    """
    Return (a, b, c, d) of κ(s) = a + b s + c s² + d s³ from κ at s = 0, L/3, 2L/3, L.

    Units: [1/m], [1/m²], [1/m³], [1/m⁴]; ``knots`` (4,) [1/m], ``length`` L [m] > 0.

    >>> spiral_coefficients([0.0, 1.0, 2.0, 3.0], 3.0).tolist()   # κ = s
    [0.0, 1.0, 0.0, 0.0]
    """
    k = np.asarray(knots, dtype=np.float64)
    if k.shape != (4,) or not np.isfinite(k).all():
        raise ValueError(f'knots must be 4 finite curvatures [1/m], got {knots!r}')
    if not (math.isfinite(length) and length > 0.0):
        raise ValueError(f'length must be finite and > 0 m, got {length!r}')
    return np.asarray(_KNOTS_TO_POWERS @ k / length ** np.arange(4))


def _heading(coefficients: NDArray[np.float64], s: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return θ(s) - θ0 [rad] = a s + b s²/2 + c s³/3 + d s⁴/4."""
    a, b, c, d = coefficients.tolist()
    return np.asarray(s * (a + s * (b / 2.0 + s * (c / 3.0 + s * d / 4.0))))


def _end(coefficients: NDArray[np.float64], length: float) -> NDArray[np.float64]:
    """Return (x, y, θ) at s = length in the start's frame (Gauss-Legendre quadrature)."""
    nodes, weights = _gauss(_NODES)
    theta = _heading(coefficients, 0.5 * length * (nodes + 1.0))
    half = 0.5 * length
    return np.array([half * weights @ np.cos(theta), half * weights @ np.sin(theta),
                     float(_heading(coefficients, np.array([length]))[0])])


def _peak(coefficients: NDArray[np.float64], length: float) -> float:
    """Return max |κ(s)| [1/m] on [0, length]: at the ends or where κ'(s) = 0."""
    a, b, c, d = coefficients.tolist()
    candidates = [0.0, length]
    if any((b, c, d)):
        roots = np.roots([3.0 * d, 2.0 * c, b]) if (c or d) else np.zeros(0)
        candidates += [float(r.real) for r in roots if abs(r.imag) < 1e-12
                       and 0.0 < r.real < length]
    s = np.array(candidates)
    return float(np.abs(a + s * (b + s * (c + s * d))).max())


def _sample(coefficients: NDArray[np.float64], length: float, ds: float
            ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Return (s, poses in the start's frame, κ) every <= ds, positions by quadrature."""
    s = np.linspace(0.0, length, max(1, math.ceil(length / ds - 1e-9)) + 1)
    nodes, weights = _gauss(_SAMPLE_NODES)
    h = np.diff(s)
    inner = s[:-1, None] + 0.5 * h[:, None] * (nodes + 1.0)
    theta_inner = _heading(coefficients, inner)
    steps = 0.5 * h[:, None] * np.stack([np.cos(theta_inner) @ weights,
                                         np.sin(theta_inner) @ weights], axis=1)
    xy = np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    a, b, c, d = coefficients.tolist()
    kappa = a + s * (b + s * (c + s * d))
    return s, np.column_stack([xy, _heading(coefficients, s)]), np.asarray(kappa)


def _posture(value: ArrayLike, name: str) -> NDArray[np.float64]:
    q = np.asarray(value, dtype=np.float64)
    if q.shape != (4,) or not np.isfinite(q).all():
        raise ValueError(f'{name} must be a finite posture (x, y, theta, kappa), got {value!r}')
    return q


def cubic_spiral(start: ArrayLike, goal: ArrayLike, max_curvature: float = math.inf,
                 ds: float = 0.05, budget: SearchBudget = SearchBudget(),
                 clock: Optional[Callable[[], float]] = None, world: Optional[World] = None,
                 footprint: Optional[Footprint] = None) -> PlanResult:
    """
    Return the cubic spiral from posture ``start`` to ``goal``, sampled every ``ds``.

    Parameters
    ----------
    start, goal : array_like, shape (4,)
        Postures (x [m], y [m], θ [rad], κ [1/m]), map frame, θ from the x axis, κ > 0
        turning left. The spiral turns by goal θ - start θ wrapped to (-π, π].
    max_curvature : float
        κ_max [1/m] > 0 (inf: no bound), e.g. tan(α_max) / l of a steered vehicle.
    ds : float
        Largest spacing of the samples [m], > 0.
    budget : SearchBudget
        ``max_expansions`` bounds the residual evaluations of all starts together,
        ``max_seconds`` their time by ``clock`` (checked between starts).
    clock : callable, optional
        Returns the time [s] (e.g. ``time.monotonic``); without it only evaluations count.
    world, footprint : World and a radius [m] or polygon (v, 2) [m], optional
        When given, the sampled spiral is swept with the footprint and refused where it meets
        an obstacle.

    Returns
    -------
    PlanResult
        ``path`` (n, 3) poses, ``cost`` the length s_f [m], ``expansions`` the residual
        evaluations; details as :func:`~.continuous_curvature.curve_result` plus
        ``coefficients`` (a, b, c, d) (in the start's frame, s from the start), ``knots``
        κ at s = 0, s_f/3, 2 s_f/3, s_f and ``residual`` (x, y, θ) at the goal; or no path
        with the reason (a posture beyond κ_max, no convergence, every spiral beyond κ_max,
        the budget, the two postures at one point, a collision).

    Raises
    ------
    ValueError
        For a posture that is not 4 finite numbers, ds or κ_max not > 0, or a world without
        a footprint.

    Examples
    --------
    A lane change of 1 m over 4 m, straight at both ends:

    >>> result = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], ds=0.1)
    >>> result.found, round(result.cost, 4), round(result.details['max_curvature'], 4)
    (True, 4.1766, 0.3385)
    >>> result.path[-1].round(9).tolist()
    [4.0, 1.0, 0.0]
    >>> cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], max_curvature=0.3).reason[:40]
    'the cubic spiral that joins the postures'

    """
    p0, p1 = _posture(start, 'start'), _posture(goal, 'goal')
    if not (isinstance(max_curvature, (int, float)) and max_curvature > 0.0):
        raise ValueError(f'max_curvature must be > 0 1/m (inf: none), got {max_curvature!r}')
    if not (isinstance(ds, (int, float)) and math.isfinite(ds) and ds > 0.0):
        raise ValueError(f'ds must be finite and > 0 m, got {ds!r}')
    if world is not None and footprint is None:
        raise ValueError('a world needs a footprint (a radius [m] or a polygon) to check')
    for name, posture in (('start', p0), ('goal', p1)):
        if abs(posture[3]) > max_curvature:
            return PlanResult.none(f'the {name} curvature {posture[3]:g} 1/m exceeds '
                                   f'max_curvature {max_curvature:g} 1/m')
    c0, s0 = math.cos(p0[2]), math.sin(p0[2])
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    target = np.array([c0 * dx + s0 * dy, -s0 * dx + c0 * dy, wrap_to_pi(p1[2] - p0[2])])
    chord = math.hypot(dx, dy)
    if chord < _SAME_POINT:
        if abs(target[2]) < _TOLERANCE and p0[3] == p1[3]:
            return curve_result(np.zeros(1), p0[None, :3].copy(), p0[3:4].copy(), abs(p0[3]))
        return PlanResult.none('the postures are at one point with another heading or '
                               'curvature: no spiral joins a point to itself')
    return _solve(p0, p1, target, chord, float(max_curvature), float(ds), budget, clock,
                  world, footprint)


def _solve(p0: NDArray[np.float64], p1: NDArray[np.float64], target: NDArray[np.float64],
           chord: float, max_curvature: float, ds: float, budget: SearchBudget,
           clock: Optional[Callable[[], float]], world: Optional[World],
           footprint: Optional[Footprint]) -> PlanResult:
    """Run the least-squares starts and build the result (see :func:`cubic_spiral`)."""
    k0, kf, turn = float(p0[3]), float(p1[3]), float(target[2])
    first = chord * (1.0 + turn * turn / 5.0) + 0.4 * abs(turn)
    began = clock() if clock is not None else 0.0

    def residual(q: NDArray[np.float64]) -> NDArray[np.float64]:
        return _end(spiral_coefficients([k0, q[0], q[1], kf], float(q[2])), float(q[2])) - target

    evaluations, solutions, best_residual = 0, [], math.inf
    for factor in _STARTS:
        left = budget.max_expansions - evaluations
        timed_out = clock is not None and clock() - began > budget.max_seconds
        if left <= 0 or timed_out:
            break
        length = first * factor
        mean = turn / length   # quadratic κ(u) with these ends and mean: C = 3 (κ0 + κf) - 6 m
        c2 = 3.0 * (k0 + kf) - 6.0 * mean
        b1 = kf - k0 - c2
        guess = [k0 + b1 / 3.0 + c2 / 9.0, k0 + 2.0 * b1 / 3.0 + 4.0 * c2 / 9.0, length]
        fit = least_squares(residual, guess, method='trf', x_scale='jac',
                            bounds=([-np.inf, -np.inf, 1e-9 * chord], np.inf),
                            ftol=1e-15, xtol=1e-15, gtol=1e-15,
                            max_nfev=min(_MAX_EVALUATIONS, left))
        evaluations += int(fit.nfev)
        error = float(np.abs(fit.fun).max())
        best_residual = min(best_residual, error)
        if error <= _TOLERANCE:
            coefficients = spiral_coefficients([k0, fit.x[0], fit.x[1], kf], float(fit.x[2]))
            solutions.append((float(fit.x[2]), _peak(coefficients, float(fit.x[2])),
                              coefficients, fit))
    feasible = [sol for sol in solutions if sol[1] <= max_curvature * (1.0 + 1e-12)]
    if not feasible:
        if solutions:
            peak = min(sol[1] for sol in solutions)
            return PlanResult.none(
                f'the cubic spiral that joins the postures turns with |kappa| up to {peak:.4g} '
                f'1/m > max_curvature {max_curvature:g} 1/m: the goal is too close for that '
                'change of heading and curvature', evaluations, peak_curvature=peak)
        why = (f'the budget of {budget.max_expansions} evaluations or {budget.max_seconds:g} s '
               'ran out' if evaluations >= budget.max_expansions or (
                   clock is not None and clock() - began > budget.max_seconds)
               else f'the least squares left a residual of {best_residual:.3g}')
        return PlanResult.none(f'no cubic spiral found from {len(_STARTS)} starts: {why}',
                               evaluations)
    length, peak, coefficients, fit = min(feasible, key=lambda sol: sol[0])
    s, local, kappa = _sample(coefficients, length, ds)
    c, s_ = math.cos(p0[2]), math.sin(p0[2])
    poses = np.column_stack([p0[0] + c * local[:, 0] - s_ * local[:, 1],
                             p0[1] + s_ * local[:, 0] + c * local[:, 1], p0[2] + local[:, 2]])
    if world is not None and footprint is not None:
        hit = pose_collision(world, footprint, poses)
        if hit is not None:
            return PlanResult.none(f'the footprint meets an obstacle at s = {s[hit[0]]:.3f} m '
                                   f'of the spiral {poses[hit[0], :2].round(3).tolist()}',
                                   evaluations, collision=hit)
    result = curve_result(s, poses, kappa, peak, coefficients=coefficients,
                          knots=np.array([k0, fit.x[0], fit.x[1], kf]), residual=fit.fun)
    return PlanResult(path=result.path, cost=result.cost, expansions=evaluations,
                      details=result.details)
