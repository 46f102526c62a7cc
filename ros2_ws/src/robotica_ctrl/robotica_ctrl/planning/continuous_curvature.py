"""
Continuous-curvature paths through a polyline: clothoid turns at its corners (book §10.4).

Book §10.4 (seed catalogue Part 8.5): a path a vehicle can follow has continuous position,
heading and curvature, with |γ| <= γ_max (the minimum turning radius); lines joined by arcs
lack curvature continuity (a step of the steering, Nelson & Cox 1988), and clothoids, whose
curvature is linear in arc length (Fresnel integrals, Shin 1990), close that gap. The curve
geometry is that of §10.2: heading θ(s) with θ' = κ (10.80), signed curvature (10.81).

Each corner of a polyline (a planner's path, shortcut first) becomes the symmetric
continuous-curvature turn of Fraichard & Scheuer (2004, "From Reeds and Shepp's to
continuous-curvature paths", IEEE Trans. Robotics 20(6)): a clothoid of sharpness σ from
κ = 0 up to κ_max, an arc of curvature κ_max, and the mirror clothoid back to κ = 0; a
deflection |δ| < κ_max² / σ, too small to reach κ_max, is two clothoids meeting at the peak
κ = sqrt(σ |δ|). Choices made here (not in the book): every turn is the tightest the bounds
allow (σ = σ_max and κ_max, so it leaves the polyline as little as possible) and is symmetric
about the corner's bisector, tangent to both legs at the tangent length T from the vertex.
The path is then the polyline's straight parts joined by these turns: κ(s) is piecewise
linear and continuous, |κ| <= κ_max and |dκ/ds| <= σ_max everywhere. When the legs are too
short for their turns, or a leg turns back on itself, there is no such path and the result
says why; with a world, the path is also swept by the footprint and refused where it meets an
obstacle (a turn cuts inside its corner by :attr:`Turn.deviation`: shortcut the polyline
with at least that clearance).

For a steered vehicle (bicycle, tricycle, Ackermann, book (4.121)) κ_max = tan(α_max) / l
(:func:`robotica_kin.mobile.bicycle.curvature_from_steering`) and σ_max from the steering
rate (:func:`sharpness_bound`). A path is a list of *pieces* (m, 3) ``[κ0 [1/m], σ [1/m²],
length [m]]`` from a start posture, each of curvature κ0 + σ u along its own arc length u:
lines (0, 0), arcs (κ0, 0) and clothoids (σ ≠ 0), which :func:`sample_pieces` evaluates in
closed form (arcs exactly, clothoids with SciPy's Fresnel integrals).
"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.path_collision import check_path_points, pose_collision
from robotica_ctrl.planning.plan_result import PlanResult
from robotica_kin.angles import wrap_to_pi
from robotica_kin.world import World
from robotica_kin.world.queries import Footprint
from scipy.special import fresnel

__all__ = ['Turn', 'continuous_curvature_path', 'curve_result', 'cc_turn', 'sample_pieces',
           'sharpness_bound']

_CUSP = 1e-9          # [rad] a deflection within this of ±π turns back (a cusp)
_STRAIGHT = 1e-12     # [rad] a deflection below this is no corner
_LEG_TOLERANCE = 1e-9  # [m] slack of a leg's length against its turns' tangent lengths


def _positive(name: str, value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
            math.isfinite(value) and value > 0.0):
        raise ValueError(f'{name} must be finite and > 0, got {value!r}')
    return float(value)


def sharpness_bound(max_steering_rate: float, speed: float, wheelbase: float) -> float:
    """
    Return σ_max [1/m²]: the curvature rate dκ/ds a steered vehicle can follow at ``speed``.

    With κ = tan α / l (book (4.121)), dκ/dt = α' / (l cos² α) and dκ/ds = (dκ/dt) / v, so a
    path with |dκ/ds| <= σ asks the steering for |α'| = σ v l cos² α <= σ v l: the bound
    σ_max = α'_max / (v l) is sufficient at every steering angle.

    Parameters
    ----------
    max_steering_rate : float
        |α'|_max [rad/s] of the steering, > 0.
    speed : float
        The highest speed v [m/s] the path is driven at, > 0.
    wheelbase : float
        l [m], > 0.

    Examples
    --------
    >>> sharpness_bound(0.5, 2.0, 2.5)
    0.1

    """
    return (_positive('max_steering_rate', max_steering_rate)
            / (_positive('speed', speed) * _positive('wheelbase', wheelbase)))


def _check_pieces(pieces: ArrayLike) -> NDArray[np.float64]:
    arr = np.array(pieces, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3 or len(arr) == 0:
        raise ValueError(f'pieces must have shape (m, 3) [kappa0, sigma, length] with m >= 1, '
                         f'got shape {arr.shape}')
    if not np.isfinite(arr).all():
        raise ValueError('pieces must be finite (no NaN or inf)')
    if not (arr[:, 2] > 0.0).all():
        k = int(np.argmax(~(arr[:, 2] > 0.0)))
        raise ValueError(f'pieces[{k}]: length must be > 0 m, got {arr[k, 2]!r}')
    return arr


def _advance(start: NDArray[np.float64], kappa0: float, sigma: float,
             u: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the poses (k, 3) at arc lengths ``u`` (k,) along κ = κ0 + σ u from ``start``.

    θ = θ0 + κ0 u + σ u² / 2. Lines and arcs: the chord u sinc(κ0 u / 2) along the mean heading
    (exact, and stable as κ0 -> 0). Clothoids: completing the square, θ = φ + σ w² / 2 with
    w = u + κ0 / σ and φ = θ0 - κ0² / (2 σ), so x + i y = e^{iφ} ∫ e^{iσ w²/2} dw, which is
    sqrt(π/|σ|) (C + i S)(w sqrt(|σ|/π)) between the ends (conjugated for σ < 0).
    """
    x0, y0, theta0 = start.tolist()
    theta = theta0 + kappa0 * u + 0.5 * sigma * u * u
    if sigma == 0.0:
        half = 0.5 * kappa0 * u
        chord = u * np.sinc(half / math.pi)
        mean = theta0 + half
        return np.column_stack([x0 + chord * np.cos(mean), y0 + chord * np.sin(mean), theta])
    scale = math.sqrt(abs(sigma) / math.pi)
    w0 = kappa0 / sigma
    s_hi, c_hi = fresnel((u + w0) * scale)
    s_lo, c_lo = fresnel(w0 * scale)
    dx, dy = (c_hi - c_lo) / scale, (s_hi - s_lo) / scale
    if sigma < 0.0:
        dy = -dy
    phi = theta0 - kappa0 * kappa0 / (2.0 * sigma)
    c, s = math.cos(phi), math.sin(phi)
    return np.column_stack([x0 + c * dx - s * dy, y0 + s * dx + c * dy, theta])


def sample_pieces(start: ArrayLike, pieces: ArrayLike, ds: float
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """
    Return (s, poses, κ): a path of linear-curvature pieces sampled at most ``ds`` apart.

    Parameters
    ----------
    start : array_like, shape (3,)
        The start posture (x [m], y [m], θ [rad]), map frame.
    pieces : array_like, shape (m, 3)
        ``[κ0 [1/m], σ [1/m²], length [m] > 0]`` per piece: curvature κ0 + σ u along it.
    ds : float
        The largest spacing [m] of the samples, > 0: the total length L is cut in
        ceil(L / ds) equal steps, so both ends are samples.

    Returns
    -------
    s : ndarray (n,)
        Arc length [m] of each sample from the start.
    poses : ndarray (n, 3)
        (x [m], y [m], θ [rad]) of each sample; θ is continuous (not wrapped).
    kappa : ndarray (n,)
        Curvature κ [1/m] of each sample, > 0 turning left.

    Raises
    ------
    ValueError
        For a start that is not a finite (3,), pieces not (m, 3) finite with lengths > 0, or
        ds <= 0.

    Examples
    --------
    A quarter circle of radius 1 m:

    >>> s, poses, kappa = sample_pieces([0, 0, 0], [[1.0, 0.0, math.pi / 2]], 0.1)
    >>> poses[-1].round(12).tolist(), len(s)
    ([1.0, 1.0, 1.570796326795], 17)

    """
    origin = np.asarray(start, dtype=np.float64)
    if origin.shape != (3,) or not np.isfinite(origin).all():
        raise ValueError(f'start must be a finite (x, y, theta), got {start!r}')
    table = _check_pieces(pieces)
    step = _positive('ds', ds)
    ends = np.cumsum(table[:, 2])
    total = float(ends[-1])
    s = np.linspace(0.0, total, max(1, math.ceil(total / step - 1e-9)) + 1)
    starts = ends - table[:, 2]
    which = np.clip(np.searchsorted(starts, s, side='right') - 1, 0, len(table) - 1)
    poses = np.empty((len(s), 3))
    pose = origin
    for k, (kappa0, sigma, length) in enumerate(table.tolist()):
        mine = which == k
        poses[mine] = _advance(pose, kappa0, sigma, s[mine] - starts[k])
        pose = _advance(pose, kappa0, sigma, np.array([length]))[0]
    poses[-1] = pose
    kappa = table[which, 0] + table[which, 1] * (s - starts[which])
    kappa[-1] = table[-1, 0] + table[-1, 1] * table[-1, 2]
    return s, poses, kappa


@dataclass(frozen=True)
class Turn:
    """
    A symmetric continuous-curvature turn of deflection δ (:func:`cc_turn`).

    Attributes
    ----------
    pieces : ndarray (m, 3)
        ``[κ0, σ, length]`` from the turn's start, heading along the incoming leg (m = 0 for
        δ = 0).
    tangent_length : float
        T [m]: the turn starts T before the vertex on the incoming leg and ends T after it on
        the outgoing one.
    deviation : float
        [m] how far the turn's middle lies from the vertex, inside the corner: the most the
        path leaves the polyline there.
    peak_curvature : float
        max |κ| [1/m] along the turn.

    """

    pieces: NDArray[np.float64]
    tangent_length: float
    deviation: float
    peak_curvature: float


def cc_turn(deflection: float, max_curvature: float, max_sharpness: float) -> Turn:
    """
    Return the tightest symmetric continuous-curvature turn of ``deflection`` δ [rad].

    Clothoid (σ_max, κ from 0 to κ_max), arc (κ_max, turning |δ| - κ_max²/σ_max), clothoid
    back to 0 when |δ| >= κ_max² / σ_max; else two clothoids of length sqrt(|δ| / σ_max)
    each, peak sqrt(σ_max |δ|) (Fraichard & Scheuer 2004). δ > 0 turns left; |δ| < π.

    Parameters
    ----------
    deflection : float
        δ [rad], the change of heading from the incoming to the outgoing leg, in (-π, π).
    max_curvature : float
        κ_max [1/m], > 0.
    max_sharpness : float
        σ_max [1/m²], > 0: the largest |dκ/ds|.

    Raises
    ------
    ValueError
        For |δ| >= π (a cusp) or a bound that is not finite and > 0.

    Examples
    --------
    A right angle with κ_max = 1 1/m and σ_max = 2 1/m²: 0.5 m of clothoid each side of an
    arc turning π/2 - 0.5 rad.

    >>> turn = cc_turn(math.pi / 2, 1.0, 2.0)
    >>> turn.pieces.round(4).tolist()
    [[0.0, 2.0, 0.5], [1.0, 0.0, 1.0708], [1.0, -2.0, 0.5]]
    >>> round(turn.tangent_length, 4), round(turn.deviation, 4), turn.peak_curvature
    (1.2599, 0.4289, 1.0)

    """
    kappa_max = _positive('max_curvature', max_curvature)
    sigma = _positive('max_sharpness', max_sharpness)
    delta = float(deflection)
    if not (math.isfinite(delta) and abs(delta) < math.pi):
        raise ValueError(f'deflection must be in (-pi, pi) rad, got {deflection!r}')
    size, sign = abs(delta), math.copysign(1.0, delta)
    if size < _STRAIGHT:
        return Turn(np.zeros((0, 3)), 0.0, 0.0, 0.0)
    if size >= kappa_max * kappa_max / sigma:
        ramp = kappa_max / sigma
        arc = (size - kappa_max * ramp) / kappa_max
        table = [[0.0, sigma, ramp], [kappa_max, 0.0, arc], [kappa_max, -sigma, ramp]]
        table = [row for row in table if row[2] > 0.0]
        peak = kappa_max
    else:
        ramp = math.sqrt(size / sigma)
        peak = sigma * ramp
        table = [[0.0, sigma, ramp], [peak, -sigma, ramp]]
    pieces = np.array(table) * [sign, sign, 1.0]
    half = 0.5 * float(pieces[:, 2].sum())
    _, poses, _ = sample_pieces([0.0, 0.0, 0.0], pieces, half)   # start, middle, end
    tangent = float(poses[-1, 1] / math.sin(delta))
    deviation = math.hypot(poses[1, 0] - tangent, poses[1, 1])
    return Turn(pieces, tangent, deviation, peak)


def curve_result(s: NDArray[np.float64], poses: NDArray[np.float64],
                 kappa: NDArray[np.float64], peak: float, **details: object) -> PlanResult:
    """
    Return the :class:`PlanResult` of a sampled curve: path (n, 3) poses, cost its length.

    ``details``: ``s`` (n,) [m], ``curvature`` (n,) [1/m], ``max_curvature`` (the exact
    max |κ| of the curve, not only of its samples) [1/m], ``samples`` (n, 4) (x, y, θ, κ),
    and the caller's own.
    """
    return PlanResult(path=poses, cost=float(s[-1]), details={
        's': s, 'curvature': kappa, 'max_curvature': float(peak),
        'samples': np.column_stack([poses, kappa]), **details})


def continuous_curvature_path(points: ArrayLike, max_curvature: float, max_sharpness: float,
                              ds: float = 0.05, world: Optional[World] = None,
                              footprint: Optional[Footprint] = None) -> PlanResult:
    """
    Return the polyline with clothoid turns at its corners, sampled every ``ds`` (book §10.4).

    The path starts at the first point with the first leg's heading and κ = 0 and ends at
    the last with the last leg's heading and κ = 0; each interior vertex becomes
    :func:`cc_turn` of its deflection, between straight stretches of the legs. Consecutive
    repeated points are dropped; a collinear vertex is no corner.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        The polyline [m], map frame, N >= 2 (at least two distinct points).
    max_curvature : float
        κ_max [1/m] > 0: tan(α_max) / l for a steered vehicle.
    max_sharpness : float
        σ_max [1/m²] > 0, the largest |dκ/ds| (:func:`sharpness_bound`).
    ds : float
        Largest spacing of the samples [m], > 0.
    world, footprint : World and a radius [m] or polygon (v, 2) [m], optional
        When given, the sampled path is swept with the footprint
        (:func:`~robotica_ctrl.planning.path_collision.pose_collision`) and refused where it
        meets an obstacle.

    Returns
    -------
    PlanResult
        ``path`` (n, 3) poses (x, y, θ), ``cost`` its length [m], details as
        :func:`curve_result` plus ``pieces`` (m, 3), ``turns`` (the :class:`Turn` of each
        interior vertex); or no path with the reason: a leg turns back (cusp), a leg too
        short for its turns (naming it and both lengths), or a collision (``collision``:
        (step, fraction)).

    Raises
    ------
    ValueError
        For points not (N, 2) finite with two distinct points, a bound or ds not > 0, or a
        world without a footprint.

    Examples
    --------
    >>> result = continuous_curvature_path([[0, 0], [4, 0], [4, 4]], 1.0, 2.0, ds=0.1)
    >>> result.found, round(result.details['max_curvature'], 6)
    (True, 1.0)
    >>> result.path[-1].round(9).tolist()
    [4.0, 4.0, 1.570796327]
    >>> continuous_curvature_path([[0, 0], [1, 0], [1, 1]], 1.0, 2.0).reason[:38]
    'leg 0 (vertex 0 to 1) is 1.000 m long,'

    """
    p = check_path_points(points)
    kappa_max = _positive('max_curvature', max_curvature)
    sigma = _positive('max_sharpness', max_sharpness)
    step = _positive('ds', ds)
    if world is not None and footprint is None:
        raise ValueError('a world needs a footprint (a radius [m] or a polygon) to check')
    p = p[np.r_[True, np.any(np.diff(p, axis=0) != 0.0, axis=1)]]
    if len(p) < 2:
        raise ValueError('points must hold at least two distinct points')
    legs = np.diff(p, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    deflections = np.atleast_1d(wrap_to_pi(np.diff(headings)))
    cusps = np.flatnonzero(np.abs(deflections) > math.pi - _CUSP)
    if len(cusps):
        k = int(cusps[0]) + 1
        return PlanResult.none(f'the path turns back at vertex {k} {p[k].tolist()}: a cusp '
                               'needs a reversal, which a forward path cannot make')
    turns = [cc_turn(float(d), kappa_max, sigma) for d in deflections]
    tangent = np.array([0.0, *(t.tangent_length for t in turns), 0.0])
    need = tangent[:-1] + tangent[1:]
    short = np.flatnonzero(need > lengths + _LEG_TOLERANCE)
    if len(short):
        j = int(short[0])
        return PlanResult.none(
            f'leg {j} (vertex {j} to {j + 1}) is {lengths[j]:.3f} m long, its turns need '
            f'{need[j]:.3f} m ({tangent[j]:.3f} + {tangent[j + 1]:.3f}) for |kappa| <= '
            f'{kappa_max:g} 1/m and |dkappa/ds| <= {sigma:g} 1/m^2: shortcut the path or '
            'allow sharper turns', leg=j)
    table: list[NDArray[np.float64]] = []
    for j in range(len(lengths)):
        straight = lengths[j] - need[j]
        if straight > _LEG_TOLERANCE:
            table.append(np.array([[0.0, 0.0, straight]]))
        if j < len(turns) and len(turns[j].pieces):
            table.append(turns[j].pieces)
    pieces = np.vstack(table)
    s, poses, kappa = sample_pieces([*p[0], headings[0]], pieces, step)
    peak = max((t.peak_curvature for t in turns), default=0.0)
    if world is not None and footprint is not None:
        hit = pose_collision(world, footprint, poses)
        if hit is not None:
            return PlanResult.none(
                f'the footprint meets an obstacle at s = {s[hit[0]]:.3f} m of the path '
                f'{poses[hit[0], :2].round(3).tolist()}: a turn cuts its corner by up to '
                f'{max(t.deviation for t in turns) if turns else 0.0:.3f} m; keep that '
                'clearance when shortcutting', collision=hit)
    return curve_result(s, poses, kappa, peak, pieces=pieces, turns=turns)
