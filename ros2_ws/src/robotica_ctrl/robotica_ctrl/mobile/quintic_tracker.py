"""
Quintic-polynomial geometric path tracking (book §9.3.2, (9.10)-(9.42); Shin 1990).

Each control period the tracker takes a goal posture on the path, a look-ahead arc length L
beyond the vehicle's closest point, and joins the vehicle to it with the quintic that matches
position, heading and curvature at both ends. The commanded curvature is the curvature of
that quintic where the vehicle will be once the steering has responded: a distance v τ ahead,
τ being the actuator delay (the book's look-ahead compensating first-order steering
dynamics). The curve is recomputed every period, which closes the loop.

Frame mapping. The book works in the vehicle frame with Y forward and X to the right and
writes the curve as x = f(y) with f' = -tan φ (9.15), f'' = -γ / cos³ φ (9.16)-(9.17). Here
the vehicle frame is REP-103 ``base_link`` (x forward, y left) and the curve is the lateral
offset to the left as a function of the forward distance, g(x) = -f(x), so that
g' = tan Δθ, g'' = γ / cos³ Δθ and the curvature is γ = g'' / (1 + g'²)^{3/2}. The goal of
(9.10)-(9.14) maps as y_f = forward, x_f = -lateral, φ_f = Δθ (θ = φ + π/2, so differences
of heading agree), γ unchanged (> 0 turns left in both), and the coefficients are
c_i = -a_i of (9.24), (9.27)-(9.29), (9.40)-(9.42).

The printed (9.40) has the denominator 2 y_f³; the correct one is 2 y_f⁵ (seed catalogue,
Part 17), used here.

The quintic exists for |φ_f| < π/2 and a goal ahead (y_f > 0). When the goal is behind the
vehicle or its relative heading exceeds ``MAX_GOAL_HEADING`` (where the book notes the
curve first goes backwards and then turns sharply, Martínez 1995), the tracker falls back on
the pure-pursuit arc to the goal point (9.5), with the book's larger value for a goal behind.
"""

from dataclasses import dataclass, fields
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.tracker_base import PathTrackerBase, TrackerOutput
from robotica_kin.angles import wrap_to_pi

__all__ = [
    'MAX_GOAL_HEADING', 'QuinticTracker', 'QuinticTrackerParams', 'path_curvature',
    'path_heading', 'quintic_coefficients', 'quintic_curvature',
]

MAX_GOAL_HEADING = 1.3  # [rad] beyond this relative goal heading the pure-pursuit arc is used
_MIN_FORWARD = 1e-6  # [m] a goal with a smaller forward distance is not ahead


def quintic_coefficients(forward: float, lateral: float, heading: float,
                         curvature_start: float = 0.0,
                         curvature_goal: float = 0.0) -> NDArray[np.float64]:
    """
    Return the coefficients c0..c5 of the quintic joining the vehicle to a goal posture.

    The curve is y = Σ c_i x^i in ``base_link`` (x forward, y lateral to the left) [m], with
    y(0) = 0, y'(0) = 0, y''(0) = γ_in and y(x_f) = y_f, y'(x_f) = tan φ_f,
    y''(x_f) = γ_f / cos³ φ_f: the boundary conditions (9.18)-(9.23). In the book's symbols
    (x_f = -lateral, y_f = forward, φ_f = heading, k = -γ_f / cos³ φ_f) the coefficients are
    a0 = a1 = 0, a2 = -γ_in/2 (9.27)-(9.29), and

    a3 = (20 x_f + k y_f² + 3 γ_in y_f² + 8 y_f tan φ_f) / (2 y_f³)      (9.42)
    a4 = -(2 k y_f² + 14 y_f tan φ_f + 3 γ_in y_f² + 30 x_f) / (2 y_f⁴)  (9.41)
    a5 = (6 y_f tan φ_f + 12 x_f + (k + γ_in) y_f²) / (2 y_f⁵)           (9.40, corrected)

    and c_i = -a_i.

    Parameters
    ----------
    forward : float
        Forward distance of the goal point in ``base_link`` [m], the book's y_f; > 0.
    lateral : float
        Lateral offset of the goal point in ``base_link`` [m], > 0 to the left (= -x_f).
    heading : float
        Goal heading relative to the vehicle [rad], φ_f, in (-π/2, π/2).
    curvature_start : float
        Vehicle curvature γ_in [1/m] (the book's γ_act), > 0 turning left.
    curvature_goal : float
        Path curvature γ_f at the goal [1/m], > 0 turning left.

    Returns
    -------
    ndarray, shape (6,)
        c0..c5 in increasing powers (units m^(1-i)); ``numpy.polynomial.polynomial``
        order, the reverse of ``numpy.polyval``'s.

    Raises
    ------
    ValueError
        If a value is not finite, ``forward <= 0`` or ``|heading| >= π/2``.

    Examples
    --------
    >>> quintic_coefficients(2.0, 0.0, 0.0)  # straight ahead: all zero
    array([0., 0., 0., 0., 0., 0.])
    >>> c = quintic_coefficients(1.0, 1.0, 0.0)  # 10 x³ - 15 x⁴ + 6 x⁵
    >>> c.tolist()
    [0.0, 0.0, 0.0, 10.0, -15.0, 6.0]

    """
    values = (forward, lateral, heading, curvature_start, curvature_goal)
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f'quintic_coefficients needs finite values, got {values!r}')
    if forward <= 0.0:
        raise ValueError(f'the goal must be ahead (forward > 0 m), got {forward!r}')
    if abs(heading) >= 0.5 * math.pi:
        raise ValueError(f'the relative goal heading must be in (-pi/2, pi/2), got {heading!r}')
    # Book symbols, §9.3.2.
    y_f = float(forward)
    x_f = -float(lateral)
    tan_f = math.tan(heading)
    gamma_in = float(curvature_start)
    k = -float(curvature_goal) / math.cos(heading) ** 3
    a2 = -0.5 * gamma_in  # (9.29)
    a3 = (20.0 * x_f + k * y_f**2 + 3.0 * gamma_in * y_f**2 + 8.0 * y_f * tan_f) / (
        2.0 * y_f**3)  # (9.42)
    a4 = -(2.0 * k * y_f**2 + 14.0 * y_f * tan_f + 3.0 * gamma_in * y_f**2 + 30.0 * x_f) / (
        2.0 * y_f**4)  # (9.41)
    a5 = (6.0 * y_f * tan_f + 12.0 * x_f + (k + gamma_in) * y_f**2) / (
        2.0 * y_f**5)  # (9.40), denominator 2 y_f⁵ (printed 2 y_f³)
    return -np.array([0.0, 0.0, a2, a3, a4, a5]) + 0.0  # + 0.0 turns -0.0 into 0.0


def quintic_curvature(coefficients: ArrayLike, x: float) -> float:
    """
    Return the signed curvature [1/m] of y = Σ c_i x^i at forward distance ``x`` [m].

    γ = y'' / (1 + y'²)^{3/2}, the REP-103 form of the book's γ = -f'' / (1 + f'²)^{3/2}
    (§9.3.2); > 0 turns left.

    Raises
    ------
    ValueError
        If ``coefficients`` is not a finite (6,) vector or ``x`` is not finite.

    >>> quintic_curvature([0.0, 0.0, 0.5, 0.0, 0.0, 0.0], 0.0)  # y = x²/2
    1.0

    """
    c = np.asarray(coefficients, dtype=np.float64)
    if c.shape != (6,) or not np.all(np.isfinite(c)) or not math.isfinite(x):
        raise ValueError(f'need finite coefficients (6,) and x, got {coefficients!r}, {x!r}')
    d1 = float(np.polynomial.polynomial.polyval(x, np.polynomial.polynomial.polyder(c)))
    d2 = float(np.polynomial.polynomial.polyval(x, np.polynomial.polynomial.polyder(c, 2)))
    return d2 / (1.0 + d1 * d1) ** 1.5


def path_curvature(path: PolylinePath, s: float, spacing: float) -> float:
    """
    Estimate the path curvature [1/m] at arc length ``s`` [m] from three path points.

    The points at s - spacing, s, s + spacing (clamped to the path) define a circle whose
    signed curvature 4 A / (|ab| |bc| |ca|), A the signed area of the triangle, is returned
    (> 0 turning left); exact for points on a circle, 0 on a straight stretch or when the
    points coincide at an end of the path. A polyline has no curvature of its own, so this
    stands for the γ of the path postures (x, y, φ, γ) of §9.2.

    Raises
    ------
    ValueError
        If ``s`` is not finite or ``spacing`` is not positive and finite.

    >>> square = PolylinePath([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    >>> round(path_curvature(square, 1.0, 1.0), 6)  # circle through three corners
    1.414214

    """
    if not (math.isfinite(spacing) and spacing > 0.0):
        raise ValueError(f'spacing must be positive and finite, got {spacing!r}')
    a, b, c = (path.point_at(s - spacing), path.point_at(s), path.point_at(s + spacing))
    ab, bc, ca = b - a, c - b, a - c
    cross = float(ab[0] * bc[1] - ab[1] * bc[0])  # twice the signed area
    lengths = math.hypot(*ab) * math.hypot(*bc) * math.hypot(*ca)
    if lengths == 0.0:
        return 0.0
    return 2.0 * cross / lengths


@dataclass(frozen=True)
class QuinticTrackerParams:
    """
    Tunables of :class:`QuinticTracker`; all must be positive and finite.

    ``actuator_delay`` must be positive: the quintic starts with the vehicle's own curvature
    (9.29), so its curvature at x = 0 is γ_in and a tracker fed back its last command would
    never change it. The book's look-ahead x = v τ is what makes the law act; take τ as the
    steering time constant (0.5 s in Ejemplo 9.1) plus about one control period.

    Raises
    ------
    ValueError
        If a value is not positive and finite.

    Examples
    --------
    >>> QuinticTrackerParams(lookahead_distance=1.5).lookahead_distance
    1.5

    """

    lookahead_distance: float = 1.0  # [m] arc length from the closest point to the goal
    desired_linear_velocity: float = 0.5  # [m/s]
    max_angular_velocity: float = 1.5  # [rad/s] v is reduced so that |v γ| stays below
    actuator_delay: float = 0.5  # τ [s]: curvature taken v τ ahead on the quintic
    goal_tolerance: float = 0.05  # [m]
    search_window: float = 2.0  # [m] window of the closest-point search around the progress
    curvature_spacing: float = 0.2  # [m] spacing of the points of the path-curvature estimate

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{field.name} must be positive and finite, got {value!r}')


class QuinticTracker(PathTrackerBase[QuinticTrackerParams]):
    """
    Quintic-polynomial tracker of a :class:`PolylinePath` (book §9.3.2).

    The state is the progress s [m] along the path (windowed closest-point search, as in
    :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`) and the last commanded
    curvature, used as the vehicle's γ_act when none is measured.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses given to :meth:`update` (e.g. ``odom``).
    params : QuinticTrackerParams
        Tunables; replace them at run time with :meth:`set_params`.

    Examples
    --------
    >>> tracker = QuinticTracker(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), QuinticTrackerParams())
    >>> out = tracker.update([0.0, 0.0, 0.0], 0.0)
    >>> out.linear, out.extras['curvature'], out.target_point
    (0.5, 0.0, array([1., 0.]))

    """

    def __init__(self, path: PolylinePath, params: QuinticTrackerParams) -> None:
        super().__init__(path, params)
        self._curvature = 0.0

    def reset(self) -> None:
        """Restart from the beginning of the path: progress 0, curvature 0, not finished."""
        super().reset()
        self._curvature = 0.0

    def update(self, pose: ArrayLike, time: float, speed: float | None = None, *,
               current_curvature: float | None = None) -> TrackerOutput:
        """
        Return the command for vehicle pose ``pose`` (one period of §9.3.2).

        Steps: (1) project the position onto the path within the search window around the
        progress; (2) goal point at arc length s + ``lookahead_distance`` (clamped at the
        end), with the path heading there (chord of the points ``curvature_spacing`` either
        side) and curvature (:func:`path_curvature`); (3) goal posture in ``base_link``,
        (9.10)-(9.14); (4) quintic (:func:`quintic_coefficients`) with γ_in the measured
        curvature, or the last command; (5) γ = its curvature at x = min(v τ, x_f), v the
        desired speed; (6) v = desired, reduced so that |v γ| <= ``max_angular_velocity``;
        ω = v γ. A goal behind the vehicle or at a relative heading beyond
        ``MAX_GOAL_HEADING`` uses the pure-pursuit arc instead (see the module notes). Once
        the remaining arc length and the distance to the last point are both within
        ``goal_tolerance`` the command is zero and stays so until :meth:`reset`.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        time : float
            Time of the pose [s]; not used.
        speed : float, optional
            Measured speed [m/s]; not used (the quintic is read v τ ahead at the desired
            speed).
        current_curvature : float, optional
            Measured vehicle curvature γ_act [1/m]; the last command when omitted.

        Returns
        -------
        TrackerOutput
            Velocities, errors from the projection and the goal point as ``target_point``;
            ``extras``: ``curvature`` γ [1/m] and ``coefficients``, the quintic c0..c5 in
            ``base_link`` (:func:`quintic_coefficients`, read-only), or None when the
            pure-pursuit fallback (or the stop) produced the command.

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector, ``current_curvature`` is not finite, or
            the goal point coincides with the vehicle.

        """
        if current_curvature is not None and not math.isfinite(current_curvature):
            raise ValueError(f'current_curvature must be finite, got {current_curvature!r}')
        x, projection = self._locate(pose)
        gamma_in = self._curvature if current_curvature is None else float(current_curvature)
        params = self._params
        path = self._path
        s_goal = min(projection.s + params.lookahead_distance, path.length)
        goal = path.point_at(s_goal)
        theta = float(x[2])
        if self._finished:
            self._curvature = 0.0
            return self._output(0.0, 0.0, theta, projection, goal, True,
                                {'curvature': 0.0, 'coefficients': None})
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        dx, dy = float(goal[0] - x[0]), float(goal[1] - x[1])
        forward = cos_t * dx + sin_t * dy  # (9.11), REP-103
        lateral = -sin_t * dx + cos_t * dy  # -(9.10)
        if forward == 0.0 and lateral == 0.0:
            raise ValueError('the goal point is at the vehicle: curvature undefined')
        heading = float(wrap_to_pi(path_heading(path, s_goal, params.curvature_spacing)
                                   - theta))  # (9.12)
        v = params.desired_linear_velocity
        coefficients = None
        if forward > _MIN_FORWARD and abs(heading) <= MAX_GOAL_HEADING:
            gamma_f = path_curvature(path, s_goal, params.curvature_spacing)  # (9.13)
            coefficients = quintic_coefficients(forward, lateral, heading, gamma_in, gamma_f)
            coefficients.flags.writeable = False
            gamma = quintic_curvature(coefficients, min(v * params.actuator_delay, forward))
        else:
            gamma = _pure_pursuit_curvature(forward, lateral)
        if abs(v * gamma) > params.max_angular_velocity:
            v = params.max_angular_velocity / abs(gamma)
        self._curvature = gamma
        return self._output(v, v * gamma, theta, projection, goal, False,
                            {'curvature': gamma, 'coefficients': coefficients})


def path_heading(path: PolylinePath, s: float, spacing: float) -> float:
    """
    Return the heading [rad] of the chord through the path points at s ± ``spacing`` [m].

    The segment's own heading where both points coincide (a path shorter than the chord).
    """
    a, b = path.point_at(s - spacing), path.point_at(s + spacing)
    if np.hypot(*(b - a)) == 0.0:
        return path.heading_at(s)
    return math.atan2(float(b[1] - a[1]), float(b[0] - a[0]))


def _pure_pursuit_curvature(forward: float, lateral: float) -> float:
    """Return the pure-pursuit γ (9.5) to a goal (forward, lateral) [m], larger if behind."""
    distance_sq = forward * forward + lateral * lateral
    if forward > 0.0:
        return 2.0 * lateral / distance_sq
    larger = 2.0 / math.sqrt(distance_sq)
    return larger if lateral >= 0.0 else -larger
