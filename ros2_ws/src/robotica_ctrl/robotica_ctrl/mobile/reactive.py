"""
Reactive control laws (book §9.6 and the reactive methods of §12.7).

Reactive control couples range readings directly to velocity commands (seed catalogue
Part 7.9, Part 10.6). All inputs are in ``base_link`` (REP-103: x forward, y left, angles
counter-clockwise from the x axis) and every law returns a :class:`VelocityCommand`
``(linear [m/s], angular [rad/s])``, which unpacks as the tuple ``(v, ω)``.

* :func:`wall_following` and :func:`corridor_centring`: the book implements the behaviours
  "wall following" and "corridor following" as path-following laws on a path derived online
  from the sensors (§9.6). The path is the straight line parallel to the wall at the set
  distance (or the corridor's centre line); the law is the linear path-following law (9.93)
  with zero path curvature, ω = u = −k1 v ξ − k2 |v| φ̃, with ξ the lateral error positive to
  the left of that line and φ̃ the heading relative to it. The book writes (9.93) with φ from
  the Y axis; the law is unchanged in REP-103 because only the differences ξ, φ̃ enter it
  (θ = φ + π/2). In travelled distance the loop is η'' + k2 η' + k1 η = 0 (9.97), so
  k1 = b², k2 = 2 δ b (9.98, corrected) gives damping δ independent of speed. The distance
  term with the angle term is a PD law on the distance, since ξ' = v sin φ̃.
* :func:`virtual_force_field`: Borenstein & Koren's VFF (12.9)-(12.15). Each obstacle point
  within the active window pushes with F_cr / d² away from it ((12.9) as printed points
  towards the cell: the repulsive sign is used here, Part 17); the goal pulls with constant
  magnitude F_ca; the robot steers along the resultant R (ω proportional to its bearing,
  saturated; the book's low-pass filter is left to the caller, this is stateless). Speed:
  the book's law v = V_max (1 − |cos θ|), θ the angle between the heading and the repulsive
  resultant F_r, stalls the robot as soon as a single point nearly ahead enters the window,
  however weak its push (v jumps to ≈ 0 while R still points at the goal). Here the slow-down
  is weighted by the push relative to the pull, v = V_max (1 − min(1, |F_r| / F_ca) |cos θ|),
  which is the book's law whenever |F_r| >= F_ca and V_max with no obstacle in the window
  (pure goal seeking).
* :func:`generalised_potential`: Krogh's generalised potential (12.3)-(12.8). An obstacle
  point approached at speed v_i > 0 has P_i = α v_i / (2 d_i α − v_i²) and pushes with
  −∇P_i = (2 P_i² / v_i) N̂_i, N̂_i the unit vector from the obstacle to the robot; the goal
  pulls with constant magnitude; steering and speed follow the resultant.
* :func:`speed_modulation`: the speed as a function of the nearest obstacle distance (§9.6),
  linear between a safety distance (stop) and a slow-down distance (full speed), as in the
  approach regulation of Nav2's Regulated Pure Pursuit.
"""

from dataclasses import dataclass, fields
import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real

__all__ = ['CorridorCentringParams', 'GeneralisedPotentialParams', 'SpeedModulationParams',
           'VelocityCommand', 'VirtualForceFieldParams', 'WallFollowingParams',
           'corridor_centring', 'generalised_potential', 'speed_modulation',
           'virtual_force_field', 'wall_following']


class VelocityCommand(NamedTuple):
    """Velocity command in ``base_link``: ``linear`` v [m/s], ``angular`` ω [rad/s] (CCW)."""

    linear: float
    angular: float


def _check_positive(params: object) -> None:
    for field in fields(params):  # type: ignore[arg-type]
        value = getattr(params, field.name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise ValueError(f'{field.name} must be positive and finite, got {value!r}')


def _saturate(omega: float, limit: float) -> float:
    return max(-limit, min(limit, omega))


@dataclass(frozen=True)
class WallFollowingParams:
    """
    Tunables of :func:`wall_following`; all must be positive and finite.

    Examples
    --------
    >>> WallFollowingParams(desired_distance=0.5).k_distance
    4.0

    """

    desired_distance: float = 0.5  # set distance to the wall [m]
    linear_velocity: float = 0.3  # v [m/s]
    k_distance: float = 4.0  # k1 of (9.93) [1/m²]; b² with b = 2 1/m
    k_angle: float = 4.0  # k2 of (9.93) [1/m]; 2 δ b with δ = 1
    max_angular_velocity: float = 1.5  # |ω| limit [rad/s]

    def __post_init__(self) -> None:
        _check_positive(self)


@dataclass(frozen=True)
class CorridorCentringParams:
    """
    Tunables of :func:`corridor_centring`; all must be positive and finite.

    Examples
    --------
    >>> CorridorCentringParams().linear_velocity
    0.3

    """

    linear_velocity: float = 0.3  # v [m/s]
    k_distance: float = 4.0  # k1 of (9.93) [1/m²]
    k_angle: float = 4.0  # k2 of (9.93) [1/m]
    max_angular_velocity: float = 1.5  # |ω| limit [rad/s]

    def __post_init__(self) -> None:
        _check_positive(self)


def _line_following(xi: float, heading_error: float, v: float, k1: float, k2: float,
                    limit: float) -> VelocityCommand:
    """Law (9.93) on a straight line (γ_c = 0): ω = −k1 v ξ − k2 |v| φ̃, saturated."""
    return VelocityCommand(v, _saturate(-k1 * v * xi - k2 * abs(v) * heading_error, limit))


def _check_angle(angle: float, name: str) -> float:
    a = finite_real(name, angle)
    if abs(a) >= 0.5 * math.pi:
        raise ValueError(
            f'{name} must lie in (-pi/2, pi/2) (the forward direction), got {angle!r}')
    return a


def wall_following(distance_to_wall: float, wall_angle: float, side: str,
                   params: WallFollowingParams) -> VelocityCommand:
    """
    Return the command that keeps ``params.desired_distance`` to a straight wall (§9.6).

    The reference path is the line parallel to the wall at the set distance; law (9.93) with
    ξ = d_ref − d for a wall on the left, ξ = d − d_ref on the right (positive to the left of
    the reference line), and φ̃ = −``wall_angle`` (the heading relative to the wall):
    ω = −k1 v ξ − k2 v φ̃, saturated at ``max_angular_velocity``; v = ``linear_velocity``.

    Parameters
    ----------
    distance_to_wall : float
        Perpendicular distance d [m] from the ``base_link`` origin to the wall, > 0.
    wall_angle : float
        Direction of the wall line in ``base_link`` [rad], the one pointing forward, in
        (−π/2, π/2); positive when the wall runs to the left of the heading.
    side : {'left', 'right'}
        Side of the robot on which the wall is.
    params : WallFollowingParams
        Set distance, speed and gains.

    Returns
    -------
    VelocityCommand
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If the distance is not positive and finite, the angle is not finite or outside
        (−π/2, π/2), or ``side`` is unknown.

    >>> p = WallFollowingParams(desired_distance=0.5, linear_velocity=0.5)
    >>> round(wall_following(0.6, 0.0, 'left', p).angular, 9)  # ω = −4 · 0.5 · (0.5 − 0.6)
    0.2

    """
    d = finite_real('distance_to_wall', distance_to_wall)
    if d <= 0.0:
        raise ValueError(f'distance_to_wall must be positive, got {distance_to_wall!r}')
    angle = _check_angle(wall_angle, 'wall_angle')
    if side == 'left':
        xi = params.desired_distance - d
    elif side == 'right':
        xi = d - params.desired_distance
    else:
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    return _line_following(xi, -angle, params.linear_velocity, params.k_distance,
                           params.k_angle, params.max_angular_velocity)


def corridor_centring(left_distance: float, right_distance: float, corridor_angle: float,
                      params: CorridorCentringParams) -> VelocityCommand:
    """
    Return the command that keeps the robot on the centre line of a straight corridor (§9.6).

    Law (9.93) on the centre line: ξ = (d_r − d_l) / 2 (positive when the robot is left of
    the centre), φ̃ = −``corridor_angle``; ω = −k1 v ξ − k2 v φ̃, saturated.

    Parameters
    ----------
    left_distance, right_distance : float
        Perpendicular distances d_l, d_r [m] to the left and right walls, > 0.
    corridor_angle : float
        Direction of the corridor axis in ``base_link`` [rad], in (−π/2, π/2).
    params : CorridorCentringParams
        Speed and gains.

    Returns
    -------
    VelocityCommand
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If a distance is not positive and finite or the angle is not in (−π/2, π/2).

    >>> corridor_centring(1.0, 1.0, 0.0, CorridorCentringParams())
    VelocityCommand(linear=0.3, angular=0.0)

    """
    dl = finite_real('left_distance', left_distance)
    dr = finite_real('right_distance', right_distance)
    if dl <= 0.0 or dr <= 0.0:
        raise ValueError(f'distances must be positive, got {left_distance!r}, {right_distance!r}')
    angle = _check_angle(corridor_angle, 'corridor_angle')
    return _line_following(0.5 * (dr - dl), -angle, params.linear_velocity, params.k_distance,
                           params.k_angle, params.max_angular_velocity)


@dataclass(frozen=True)
class VirtualForceFieldParams:
    """
    Tunables of :func:`virtual_force_field`; all must be positive and finite.

    Examples
    --------
    >>> VirtualForceFieldParams().window_radius
    2.0

    """

    repulsive_gain: float = 1.0  # F_cr of (12.9) [N·m²] (force units are arbitrary)
    attractive_gain: float = 1.0  # F_ca of (12.13) [N]
    window_radius: float = 2.0  # obstacles farther than this are ignored [m]
    max_linear_velocity: float = 0.5  # V_max [m/s]
    k_heading: float = 2.0  # ω = k_heading · bearing of R [1/s]
    max_angular_velocity: float = 1.5  # [rad/s]
    goal_tolerance: float = 0.05  # stop within this distance of the goal [m]

    def __post_init__(self) -> None:
        _check_positive(self)


@dataclass(frozen=True)
class GeneralisedPotentialParams:
    """
    Tunables of :func:`generalised_potential`; all must be positive and finite.

    Examples
    --------
    >>> GeneralisedPotentialParams().max_deceleration
    1.0

    """

    max_deceleration: float = 1.0  # α of (12.3) [m/s²]
    repulsive_gain: float = 1.0  # scale of −∇P_i [N·m/s]
    attractive_gain: float = 1.0  # constant goal pull [N]
    max_linear_velocity: float = 0.5  # [m/s]
    k_heading: float = 2.0  # [1/s]
    max_angular_velocity: float = 1.5  # [rad/s]
    goal_tolerance: float = 0.05  # [m]

    def __post_init__(self) -> None:
        _check_positive(self)


def _points(obstacles_xy: ArrayLike) -> NDArray[np.float64]:
    pts = np.asarray(obstacles_xy, dtype=np.float64)
    if pts.size == 0:
        return np.zeros((0, 2))
    if pts.ndim != 2 or pts.shape[1] != 2 or not np.all(np.isfinite(pts)):
        raise ValueError(f'obstacles_xy must be a finite (N, 2) array, got shape {pts.shape}')
    if np.any(np.hypot(pts[:, 0], pts[:, 1]) == 0.0):
        raise ValueError('an obstacle point lies at the robot origin (d = 0)')
    return pts


def _goal(goal_xy: ArrayLike) -> NDArray[np.float64]:
    g = np.asarray(goal_xy, dtype=np.float64)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise ValueError(f'goal_xy must be a finite (2,) vector, got {goal_xy!r}')
    return g


def _steer(resultant: NDArray[np.float64], k: float, limit: float) -> float:
    return _saturate(k * math.atan2(float(resultant[1]), float(resultant[0])), limit)


def virtual_force_field(obstacles_xy: ArrayLike, goal_xy: ArrayLike,
                        params: VirtualForceFieldParams) -> VelocityCommand:
    """
    Return the VFF command (Borenstein & Koren 1989; book (12.9)-(12.15)).

    F_r = Σ F_cr (−p_i) / |p_i|³ over the points with |p_i| <= ``window_radius`` (repulsion
    F_cr / d² away from each point), F_a = F_ca g / |g|, R = F_a + F_r;
    ω = k_heading atan2(R_y, R_x) saturated; v = V_max if F_r = 0, else
    v = V_max (1 − min(1, |F_r| / F_ca) |cos θ|) with cos θ = F_rx / |F_r| (the robot moves
    along x): the book's (12.15) when |F_r| >= F_ca, see the module notes. Within
    ``goal_tolerance`` of the goal the command is zero.

    Parameters
    ----------
    obstacles_xy : array_like, shape (N, 2)
        Obstacle points (x, y) [m] in ``base_link`` (occupied cells, range returns); N may be 0.
    goal_xy : array_like, shape (2,)
        Goal (x, y) [m] in ``base_link``.
    params : VirtualForceFieldParams
        Gains, window and limits.

    Returns
    -------
    VelocityCommand
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If the arrays have the wrong shape or non-finite values, or a point is at the origin.

    >>> virtual_force_field([], [2.0, 0.0], VirtualForceFieldParams())
    VelocityCommand(linear=0.5, angular=0.0)

    """
    pts = _points(obstacles_xy)
    goal = _goal(goal_xy)
    goal_distance = float(np.hypot(goal[0], goal[1]))
    if goal_distance <= params.goal_tolerance:
        return VelocityCommand(0.0, 0.0)
    d = np.hypot(pts[:, 0], pts[:, 1])
    near = d <= params.window_radius
    repulsive = -params.repulsive_gain * np.sum(pts[near] / d[near, None] ** 3, axis=0)
    resultant = params.attractive_gain * goal / goal_distance + repulsive
    magnitude = float(np.hypot(repulsive[0], repulsive[1]))
    v = params.max_linear_velocity
    if magnitude > 0.0:
        strength = min(1.0, magnitude / params.attractive_gain)
        v *= 1.0 - strength * abs(float(repulsive[0])) / magnitude
    return VelocityCommand(v, _steer(resultant, params.k_heading, params.max_angular_velocity))


def generalised_potential(obstacles_xy: ArrayLike, goal_xy: ArrayLike, speed: float,
                          params: GeneralisedPotentialParams) -> VelocityCommand:
    """
    Return the command of Krogh's generalised potential field (1984; book (12.3)-(12.8)).

    The robot moves along its x axis at ``speed`` v >= 0. For the obstacle point p_i at
    distance d_i, N̂_i = −p_i / d_i and the approach speed is v_i = v p_ix / d_i; with α the
    maximum deceleration, t_min = v_i / α, t_max = 2 d_i / v_i and
    P_i = 1 / (t_max − t_min) = α v_i / (2 d_i α − v_i²) (12.6) if v_i > 0, else 0; the force
    is −∇P_i = (2 P_i² / v_i) N̂_i (12.8), scaled by ``repulsive_gain``. The goal pulls with
    constant magnitude ``attractive_gain`` (the book gives no form; as in VFF). Then
    ω = k_heading β saturated, β = atan2(R_y, R_x), and v = V_max max(cos β, 0). If some
    t_max <= t_min (the obstacle can no longer be avoided by braking) the command is a full
    stop (0, 0). Within ``goal_tolerance`` of the goal the command is zero.

    Parameters
    ----------
    obstacles_xy : array_like, shape (N, 2)
        Closest obstacle points (x, y) [m] in ``base_link``; N may be 0.
    goal_xy : array_like, shape (2,)
        Goal (x, y) [m] in ``base_link``.
    speed : float
        Current forward speed v [m/s], >= 0.
    params : GeneralisedPotentialParams
        Deceleration, gains and limits.

    Returns
    -------
    VelocityCommand
        (v [m/s], ω [rad/s]).

    Raises
    ------
    ValueError
        If the arrays are malformed, a point is at the origin, or ``speed`` is negative or
        not finite.

    >>> generalised_potential([[0.0, 1.0]], [2.0, 0.0], 0.5, GeneralisedPotentialParams())
    VelocityCommand(linear=0.5, angular=0.0)

    """
    pts = _points(obstacles_xy)
    goal = _goal(goal_xy)
    v = finite_real('speed', speed)
    if v < 0.0:
        raise ValueError(f'speed must be >= 0, got {speed!r}')
    goal_distance = float(np.hypot(goal[0], goal[1]))
    if goal_distance <= params.goal_tolerance:
        return VelocityCommand(0.0, 0.0)
    alpha = params.max_deceleration
    resultant = params.attractive_gain * goal / goal_distance
    for x, y in pts:
        d = math.hypot(x, y)
        v_i = v * x / d
        if v_i <= 0.0:
            continue
        margin = 2.0 * d * alpha - v_i * v_i
        if margin <= 0.0:
            return VelocityCommand(0.0, 0.0)
        potential = alpha * v_i / margin
        resultant = resultant + params.repulsive_gain * (2.0 * potential ** 2 / v_i) * np.array(
            [-x / d, -y / d])
    bearing = math.atan2(float(resultant[1]), float(resultant[0]))
    linear = params.max_linear_velocity * max(math.cos(bearing), 0.0)
    return VelocityCommand(linear, _saturate(params.k_heading * bearing,
                                             params.max_angular_velocity))


@dataclass(frozen=True)
class SpeedModulationParams:
    """
    Tunables of :func:`speed_modulation`; positive, ``safety_distance < slowdown_distance``.

    Raises
    ------
    ValueError
        If a value is not positive and finite or the distances are not ordered.

    Examples
    --------
    >>> SpeedModulationParams(safety_distance=0.3, slowdown_distance=1.0).safety_distance
    0.3

    """

    safety_distance: float = 0.3  # stop at or below this obstacle distance [m]
    slowdown_distance: float = 1.0  # full speed at or beyond this distance [m]

    def __post_init__(self) -> None:
        _check_positive(self)
        if self.safety_distance >= self.slowdown_distance:
            raise ValueError(
                f'safety_distance ({self.safety_distance!r} m) must be below '
                f'slowdown_distance ({self.slowdown_distance!r} m)')


def speed_modulation(v_desired: float, nearest_obstacle_distance: float,
                     params: SpeedModulationParams) -> float:
    """
    Return the speed [m/s] scaled down near obstacles (§9.6).

    v = 0 for d <= d_s, v = v_d (d − d_s) / (d_f − d_s) for d_s < d < d_f, v = v_d for
    d >= d_f (d_s = ``safety_distance``, d_f = ``slowdown_distance``). The sign of v_d is
    kept, so |v| is non-decreasing in d.

    Parameters
    ----------
    v_desired : float
        Desired speed v_d [m/s].
    nearest_obstacle_distance : float
        Distance d [m] to the nearest obstacle, >= 0; ``math.inf`` when none is seen.
    params : SpeedModulationParams
        Distances.

    Returns
    -------
    float
        Modulated speed [m/s].

    Raises
    ------
    ValueError
        If ``v_desired`` is not finite, or the distance is NaN or negative.

    >>> speed_modulation(1.0, 0.65, SpeedModulationParams(0.3, 1.0))
    0.5

    """
    vd = finite_real('v_desired', v_desired)
    d = float(nearest_obstacle_distance)
    if math.isnan(d) or d < 0.0:
        raise ValueError(
            f'nearest_obstacle_distance must be >= 0, got {nearest_obstacle_distance!r}')
    if d <= params.safety_distance:
        return 0.0
    if d >= params.slowdown_distance:
        return vd
    return vd * (d - params.safety_distance) / (
        params.slowdown_distance - params.safety_distance)
