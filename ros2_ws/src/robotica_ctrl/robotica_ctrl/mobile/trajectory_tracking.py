"""
Trajectory (posture) tracking of Canudas de Wit et al. (1997), book §9.4.2, (9.59)-(9.82).

A reference robot moves as a unicycle with velocities (v_r, ω_r)(t) (9.59); the real robot
must follow its posture (x_r, y_r, θ_r)(t). The posture error expressed in the robot frame
(9.63) obeys (9.64)-(9.67)

    e1' =  ω e2 + u1,    e2' = -ω e1 + v_r sin e3,    e3' = u2,

with the auxiliary inputs u1 = -v + v_r cos e3, u2 = ω_r - ω (9.66), so the commands are
v = v_r cos e3 - u1 and ω = ω_r - u2. Three laws give u:

``'linear'`` (9.70)
    u1 = -k1 e1, u2 = -k2 sgn(v_r) e2 - k3 e3 with fixed gains. Linearised about e = 0 the
    characteristic polynomial is s (s + k1)(s + k3) + k2 |v_r| (s + k1) + ω_r² (s + k3) (9.72);
    :func:`design_linear_gains` places its roots at -2δb and -δb ± b sqrt(δ² - 1) for given
    constant (v_r, ω_r) (9.73)-(9.75).
``'scheduled'`` (9.76)-(9.77)
    The same law with b = sqrt(ω_r² + β v_r²), i.e. k1 = k3 = 2δ sqrt(ω_r² + β v_r²) and
    k2 = β |v_r|, recomputed from the current reference: the poles stay at the design
    values whatever the reference speed (the gains vanish when v_r = ω_r = 0).
``'nonlinear'`` (9.78)
    u1 = -k1 e1, u2 = -k2 v_r (sin e3 / e3) e2 - k3 e3 with k2 > 0 constant and
    k1 = k3 = 2δ sqrt(ω_r² + β v_r²) (9.82); V = k2 (e1² + e2²) / 2 + e3² / 2 (9.79) gives
    V' = -k1 k2 e1² - k3 e3² (9.81). Linearised: (s + k1)(s² + k1 s + k2 v_r² + ω_r²).

Conventions. The book measures the heading φ from the world y axis (x' = -v sin φ,
y' = v cos φ); here θ = φ + π/2 from the x axis (REP-103), the world axes being the same.
With cos θ = -sin φ and sin θ = cos φ, the book's (9.63)

    e1 = -sin φ (x_r - x) + cos φ (y_r - y),  e2 = -cos φ (x_r - x) - sin φ (y_r - y),
    e3 = φ_r - φ

reads e1 = cos θ Δx + sin θ Δy (along the heading), e2 = -sin θ Δx + cos θ Δy (lateral,
positive to the left) and e3 = θ_r - θ, so the errors and the laws keep the book's signs
unchanged. e3 is wrapped to (-π, π] (the book leaves it unwrapped); the commands are then
clipped to ``max_linear`` and ``max_angular`` (not in the book).

:func:`tracking_command` is the law at one instant, for a given reference sample.
:class:`TrajectoryTracker` drives it in time along a path: the reference is a
:class:`TimedPath`, the path's own timing when it has one (the stamps of a ``nav_msgs/Path``),
else the path driven at ``reference_speed`` from the first update on.
"""

from dataclasses import dataclass, fields
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.quintic_tracker import path_curvature, path_heading
from robotica_ctrl.mobile.tracker_base import (angle_error, check_pose, replace_gains,
                                               TrackerOutput)
from robotica_kin.finite import finite_real

__all__ = ['LAWS', 'PostureReference', 'TimedPath', 'TrackingCommand', 'TrajectoryTracker',
           'TrajectoryTrackingParams', 'design_linear_gains', 'posture_error',
           'tracking_command', 'tracking_gains']

LAWS = ('linear', 'scheduled', 'nonlinear')
"""Names of the control laws of :class:`TrajectoryTrackingParams`."""


def _pose(name: str, pose: ArrayLike) -> NDArray[np.float64]:
    """Return ``pose`` as a finite float64 (3,) array, or raise ValueError."""
    p = np.asarray(pose, dtype=np.float64)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise ValueError(f'{name} must be a finite (3,) vector (x, y, theta), got {pose!r}')
    return p


def posture_error(pose: ArrayLike, reference_pose: ArrayLike) -> NDArray[np.float64]:
    """
    Return the posture error (e1, e2, e3) of ``pose`` to ``reference_pose`` in the robot frame.

    Book (9.63) in REP-103 form: with (Δx, Δy) = (x_r - x, y_r - y),
    e1 = cos θ Δx + sin θ Δy [m] (along the robot's heading), e2 = -sin θ Δx + cos θ Δy [m]
    (lateral, positive when the reference is to the robot's left) and
    e3 = θ_r - θ [rad] wrapped to (-π, π].

    Parameters
    ----------
    pose : array_like, shape (3,)
        Robot pose (x [m], y [m], θ [rad]) in the world frame, θ from the x axis.
    reference_pose : array_like, shape (3,)
        Reference pose (x_r, y_r, θ_r) in the same frame.

    Returns
    -------
    ndarray, shape (3,)
        (e1 [m], e2 [m], e3 [rad]), float64.

    Raises
    ------
    ValueError
        If either pose is not a finite (3,) vector.

    Examples
    --------
    >>> posture_error([0.0, 0.0, math.pi / 2], [0.0, 1.0, math.pi / 2])  # 1 m ahead
    array([1., 0., 0.])
    >>> posture_error([1.0, 1.0, 0.0], [1.0, 3.0, 0.5])  # 2 m to the left
    array([0. , 2. , 0.5])

    """
    p = _pose('pose', pose)
    r = _pose('reference_pose', reference_pose)
    return np.array(_error(*p.tolist(), *r.tolist()))


def _error(x: float, y: float, theta: float, x_r: float, y_r: float,
           theta_r: float) -> tuple[float, float, float]:
    """Return (9.63) in REP-103 form for finite scalars, e3 wrapped to (-π, π]."""
    dx, dy = x_r - x, y_r - y
    c, s = math.cos(theta), math.sin(theta)
    e3 = math.remainder(theta_r - theta, 2.0 * math.pi)  # in [-π, π]
    return c * dx + s * dy, -s * dx + c * dy, (math.pi if e3 == -math.pi else e3)


def design_linear_gains(
    delta: float, b: float, v_ref: float, omega_ref: float
) -> tuple[float, float, float]:
    """
    Return the gains (k1, k2, k3) of the linear law placing its poles for a constant reference.

    Book (9.73)-(9.75): identifying (9.72) with k3 = k1 with (s + 2δb)(s² + 2δbs + b²)
    (9.74) gives k1 = k3 = 2δb and k2 = (b² - ω_r²) / |v_r|; the poles are -2δb and
    -δb ± b sqrt(δ² - 1).

    Parameters
    ----------
    delta : float
        Damping δ of the complex pair, > 0.
    b : float
        Natural frequency b [rad/s], > |ω_r| so that k2 > 0.
    v_ref : float
        Constant reference speed v_r [m/s], non-zero.
    omega_ref : float
        Constant reference yaw rate ω_r [rad/s].

    Returns
    -------
    tuple of float
        (k1 [1/s], k2 [1/m], k3 [1/s]) for :class:`TrajectoryTrackingParams` with
        ``law='linear'``.

    Raises
    ------
    ValueError
        If an input is not finite, δ <= 0, v_r = 0 or b <= |ω_r|.

    Examples
    --------
    >>> design_linear_gains(0.5, 2.0, 0.5, 1.0)
    (2.0, 6.0, 2.0)

    """
    delta = finite_real('delta', delta)
    b = finite_real('b', b)
    v_ref = finite_real('v_ref', v_ref)
    omega_ref = finite_real('omega_ref', omega_ref)
    if not delta > 0.0:
        raise ValueError(f'delta must be > 0, got {delta!r}')
    if v_ref == 0.0:
        raise ValueError('v_ref must be non-zero: k2 = (b² - ω_r²) / |v_r| (9.75)')
    if not b > abs(omega_ref):
        raise ValueError(f'b ({b!r} rad/s) must exceed |omega_ref| ({abs(omega_ref)!r} rad/s) '
                         'so that k2 > 0')
    k1 = 2.0 * delta * b
    return k1, (b * b - omega_ref * omega_ref) / abs(v_ref), k1


@dataclass(frozen=True)
class TrajectoryTrackingParams:
    """
    Tunables of :func:`tracking_command` and :class:`TrajectoryTracker`.

    The defaults are Ejemplo 9.4 (nonlinear law, δ = 0.9, β = 13.75, k2 = 19); Ejemplo 9.3
    is ``law='linear', k2=2.0`` (k1 = 1, k3 = 4) for (a) and ``law='scheduled'`` for (b).
    Which gains each law reads: ``'linear'`` k1, k2, k3; ``'scheduled'`` δ, β;
    ``'nonlinear'`` k2, δ, β. The last three tunables are the tracker's reference and end
    (:class:`TrajectoryTracker`).

    Raises
    ------
    ValueError
        If ``law`` is not one of :data:`LAWS`, or a number is not positive and finite.

    Examples
    --------
    >>> TrajectoryTrackingParams().law
    'nonlinear'
    >>> TrajectoryTrackingParams(law='linear', k2=2.0).k2
    2.0

    """

    law: str = 'nonlinear'  # 'linear' (9.70), 'scheduled' (9.77) or 'nonlinear' (9.78)
    k1: float = 1.0  # [1/s] along-track gain of the linear law (9.70), Ejemplo 9.3(a)
    k2: float = 19.0  # [1/m] lateral gain: (9.70) fixed, (9.78) constant; Ejemplo 9.4
    k3: float = 4.0  # [1/s] heading gain of the linear law (9.70), Ejemplo 9.3(a)
    delta: float = 0.9  # δ, damping of (9.74), scheduled (9.77) and nonlinear (9.82)
    beta: float = 13.75  # β [rad²/m²], speed weight of b = sqrt(ω_r² + β v_r²) (9.76)
    max_linear: float = 1.0  # [m/s] |v| limit applied to the command (not in the book)
    max_angular: float = 1.5  # [rad/s] |ω| limit applied to the command (not in the book)
    reference_speed: float = 0.5  # [m/s] of the reference along a path without timing
    curvature_spacing: float = 0.1  # [m] of the reference heading and curvature estimates
    goal_tolerance: float = 0.05  # [m] from the path end, once the reference is there: done

    def __post_init__(self) -> None:
        if self.law not in LAWS:
            raise ValueError(f'law must be one of {LAWS}, got {self.law!r}')
        for field in fields(self):
            if field.name == 'law':
                continue
            value = getattr(self, field.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f'{field.name} must be positive and finite, got {value!r}')


@dataclass(frozen=True)
class PostureReference:
    """
    One sample of the reference trajectory (9.59): posture and velocities at the same time.

    Attributes
    ----------
    x, y : float
        Reference position [m] in the world frame.
    theta : float
        Reference heading θ_r [rad] from the x axis (REP-103; the book's φ_r + π/2).
    v : float
        Reference speed v_r [m/s]; negative drives backwards.
    omega : float
        Reference yaw rate ω_r [rad/s], > 0 counter-clockwise.

    Raises
    ------
    ValueError
        If a value is not finite.

    Examples
    --------
    >>> PostureReference(1.0, 2.0, 0.0, 0.5, 0.1).pose
    array([1., 2., 0.])

    """

    x: float
    y: float
    theta: float
    v: float
    omega: float

    def __post_init__(self) -> None:
        for field in fields(self):
            value = finite_real(field.name, getattr(self, field.name))
            object.__setattr__(self, field.name, value)

    @property
    def pose(self) -> NDArray[np.float64]:
        """Return the reference posture (x_r [m], y_r [m], θ_r [rad]) as a (3,) array."""
        return np.array([self.x, self.y, self.theta])


@dataclass(frozen=True)
class TrackingCommand:
    """
    Output of one :meth:`TrajectoryTracker.update`.

    Attributes
    ----------
    linear : float
        Forward velocity v = v_r cos e3 + k1 e1 [m/s] in ``base_link``, clipped.
    angular : float
        Yaw rate ω = ω_r - u2 [rad/s], > 0 counter-clockwise, clipped.
    error : ndarray, shape (3,)
        Posture error (e1 [m], e2 [m], e3 [rad]) of (9.63); a read-only float64 copy.
    gains : tuple of float
        The gains (k1, k2, k3) the law used at this step ((9.77) and (9.82) depend on the
        reference); for ``'nonlinear'`` k2 is the constant of (9.78).
    saturated : bool
        Whether ``max_linear`` or ``max_angular`` clipped the command.

    Examples
    --------
    >>> TrackingCommand(0.5, 0.0, np.zeros(3), (1.0, 2.0, 3.0), False).error
    array([0., 0., 0.])

    """

    linear: float
    angular: float
    error: NDArray[np.float64]
    gains: tuple[float, float, float]
    saturated: bool

    def __post_init__(self) -> None:
        error = np.array(self.error, dtype=np.float64)
        if error.shape != (3,):
            raise ValueError(f'error must have shape (3,), got {error.shape}')
        error.flags.writeable = False
        object.__setattr__(self, 'error', error)


def tracking_gains(params: TrajectoryTrackingParams, v_ref: float,
                   omega_ref: float) -> tuple[float, float, float]:
    """
    Return (k1, k2, k3) of the law of ``params`` for the reference velocities (v_r, ω_r).

    ``'linear'``: the fixed k1, k2, k3 (9.70). ``'scheduled'``: k1 = k3 =
    2δ sqrt(ω_r² + β v_r²), k2 = β |v_r| (9.77). ``'nonlinear'``: k1 = k3 as in
    ``'scheduled'`` (9.82), k2 the constant of (9.78).

    >>> tracking_gains(TrajectoryTrackingParams(law='scheduled', beta=3.0), 1.0, 1.0)
    (3.6, 3.0, 3.6)

    """
    p = params
    if p.law == 'linear':
        return p.k1, p.k2, p.k3
    k13 = 2.0 * p.delta * math.sqrt(omega_ref * omega_ref + p.beta * v_ref * v_ref)
    if p.law == 'scheduled':
        return k13, p.beta * abs(v_ref), k13
    return k13, p.k2, k13


def tracking_command(pose: ArrayLike, reference: PostureReference,
                     params: TrajectoryTrackingParams) -> TrackingCommand:
    """
    Return the velocity command for robot pose ``pose`` tracking ``reference``.

    The law has no memory: the command depends only on the pose and the reference sample.
    Error (9.63) by :func:`posture_error`; u1 = -k1 e1 for every law; u2 =
    -k2 sgn(v_r) e2 - k3 e3 for ``'linear'`` (9.70) and ``'scheduled'`` (9.77), and
    u2 = -k2 v_r (sin e3 / e3) e2 - k3 e3 for ``'nonlinear'`` (9.78); then
    v = v_r cos e3 - u1 and ω = ω_r - u2 (9.66), each clipped to its limit.

    Parameters
    ----------
    pose : array_like, shape (3,)
        Robot pose (x [m], y [m], θ [rad]) in the reference's frame, θ from the x axis.
    reference : PostureReference
        Reference posture and velocities at the same time.
    params : TrajectoryTrackingParams
        Law and gains (:func:`tracking_gains`) and the limits.

    Returns
    -------
    TrackingCommand
        Velocities, error and gains.

    Raises
    ------
    ValueError
        If ``pose`` is not a finite (3,) vector.

    Examples
    --------
    >>> params = TrajectoryTrackingParams(law='linear')
    >>> cmd = tracking_command([0.0, 0.0, 0.0], PostureReference(0.1, 0.0, 0.0, 0.5, 0.0),
    ...                        params)
    >>> round(cmd.linear, 12), cmd.angular  # 0.5 + k1 0.1
    (0.6, 0.0)
    >>> cmd = tracking_command([0.0, 0.0, 0.0], PostureReference(0.0, 0.05, 0.0, 0.5, 0.2),
    ...                        params)
    >>> cmd.linear, round(cmd.angular, 12)  # ω = 0.2 + k2 0.05 (k2 = 19)
    (0.5, 1.15)

    """
    v_ref, omega_ref = reference.v, reference.omega
    x, y, theta = _pose('pose', pose).tolist()
    e1, e2, e3 = _error(x, y, theta, reference.x, reference.y, reference.theta)
    k1, k2, k3 = tracking_gains(params, v_ref, omega_ref)
    u1 = -k1 * e1
    if params.law == 'nonlinear':
        sinc = math.sin(e3) / e3 if e3 != 0.0 else 1.0
        u2 = -k2 * v_ref * sinc * e2 - k3 * e3
    else:
        sign = (v_ref > 0.0) - (v_ref < 0.0)
        u2 = -k2 * sign * e2 - k3 * e3
    v = v_ref * math.cos(e3) - u1
    omega = omega_ref - u2
    v_clipped = min(max(v, -params.max_linear), params.max_linear)
    omega_clipped = min(max(omega, -params.max_angular), params.max_angular)
    saturated = v_clipped != v or omega_clipped != omega
    return TrackingCommand(v_clipped, omega_clipped, np.array([e1, e2, e3]), (k1, k2, k3),
                           saturated)


class TimedPath:
    """
    A reference trajectory along a path: the arc length s(t) [m] and the posture there.

    With ``times`` (one per path point [s], strictly increasing; ``stations`` are the points'
    arc lengths [m], ``path.s`` by default) the path carries its own timing; without, it is
    driven at ``speed`` [m/s] from ``start`` [s]. The reference posture at t is the path
    point at s(t), the heading of the chord of the points ``spacing`` either side,
    v_r = ds/dt and ω_r = v_r c(s) with c the three-point curvature; a timed path takes its
    heading from its own points instead (central differences, exact on an evenly sampled
    arc) and ω_r = dθ/dt. Past the end the reference stops there (v_r = ω_r = 0).

    >>> line = PolylinePath([[0.0, 0.0], [2.0, 0.0]])
    >>> ref = TimedPath(line, speed=0.5).reference(1.0)
    >>> ref.x, ref.v, ref.omega
    (0.5, 0.5, 0.0)
    """

    def __init__(self, path: PolylinePath, times: ArrayLike | None = None, speed: float = 0.5,
                 start: float = 0.0, spacing: float = 0.1,
                 stations: ArrayLike | None = None) -> None:
        self.path = path
        self.spacing = float(spacing)
        if times is None:
            if not (math.isfinite(speed) and speed > 0.0):
                raise ValueError(f'speed must be positive and finite, got {speed!r}')
            self._times = np.array([start, start + path.length / speed])
            self._s = np.array([0.0, path.length])
            self._theta = None
            return
        t = np.asarray(times, dtype=np.float64)
        s = np.asarray(path.s if stations is None else stations, dtype=np.float64)
        if t.ndim != 1 or t.shape != s.shape or t.size < 2:
            raise ValueError(f'times must have one value per path point ({s.size}), got '
                             f'shape {t.shape}')
        if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0.0)):
            raise ValueError('times must be finite and increase strictly')
        if not (np.all(np.isfinite(s)) and np.all(np.diff(s) >= 0.0)):
            raise ValueError('stations must be finite and non-decreasing arc lengths [m]')
        self._times, self._s = t, s
        # A trajectory's heading and yaw rate come from its own points (central differences,
        # exact on an arc sampled evenly), not from the chords of ``spacing``.
        points = np.array([path.point_at(float(si)) for si in s])
        chords = np.empty_like(points)
        chords[1:-1] = points[2:] - points[:-2]
        chords[0], chords[-1] = points[1] - points[0], points[-1] - points[-2]
        self._theta = np.unwrap(np.arctan2(chords[:, 1], chords[:, 0]))

    @property
    def end_time(self) -> float:
        """Return the time [s] at which the reference reaches the end of the path."""
        return float(self._times[-1])

    def reference(self, t: float) -> PostureReference:
        """Return the reference posture and velocities at time ``t`` [s]."""
        times, s_points = self._times, self._s
        s = float(np.interp(t, times, s_points))
        i = min(max(int(np.searchsorted(times, t, side='right')) - 1, 0), len(times) - 2)
        moving = bool(times[0] <= t < times[-1])
        dt = float(times[i + 1] - times[i])
        v = float(s_points[i + 1] - s_points[i]) / dt if moving else 0.0
        point = self.path.point_at(s)
        if self._theta is not None:
            theta = float(np.interp(t, times, self._theta))
            omega = float(self._theta[i + 1] - self._theta[i]) / dt if moving else 0.0
            return PostureReference(float(point[0]), float(point[1]), theta, v, omega)
        theta = path_heading(self.path, s, self.spacing)
        omega = v * path_curvature(self.path, s, self.spacing) if v != 0.0 else 0.0
        return PostureReference(float(point[0]), float(point[1]), theta, v, omega)


class TrajectoryTracker:
    """
    Posture tracker of Canudas de Wit et al. (book §9.4.2) along a path in time.

    Each :meth:`update` takes the reference posture of the :class:`TimedPath` at its time
    (built at the first update: an untimed path starts where and when the robot starts) and
    applies :func:`tracking_command`. Once the reference has reached the end of the path and
    the robot is within ``goal_tolerance`` of it, the command is zero until :meth:`reset`.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses (e.g. ``odom``).
    params : TrajectoryTrackingParams
        Law, gains, limits and reference; replace them with :meth:`set_params`.
    times : array_like, optional
        Time [s] of each path point (see :class:`TimedPath`); without, the reference moves
        at ``params.reference_speed``.
    stations : array_like, optional
        Arc length [m] of each point ``times`` refers to (default ``path.s``; give them when
        the points had duplicates that :class:`PolylinePath` dropped).

    Examples
    --------
    >>> tracker = TrajectoryTracker(PolylinePath([[0.0, 0.0], [4.0, 0.0]]),
    ...                             TrajectoryTrackingParams())
    >>> tracker.update([0.0, 0.0, 0.0], 10.0).linear   # on the reference at its start
    0.5

    """

    def __init__(self, path: PolylinePath, params: TrajectoryTrackingParams,
                 times: ArrayLike | None = None, stations: ArrayLike | None = None) -> None:
        self._path = path
        self._params = params
        self._times, self._stations = times, stations
        self._reference: TimedPath | None = None
        self._finished = False

    @property
    def params(self) -> TrajectoryTrackingParams:
        """Return the current tunables."""
        return self._params

    def set_params(self, params: TrajectoryTrackingParams) -> None:
        """Use ``params`` from the next update on (the reference's from the next reset)."""
        self._params = params

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace some tunables by name (``variant`` is ``law``); ValueError keeps the old."""
        self.set_params(replace_gains(self._params, gains))

    def reset(self) -> None:
        """Restart the reference at the next update; not finished."""
        self._reference = None
        self._finished = False

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Return the command for ``pose`` at ``time`` [s] and its errors to the reference.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Robot pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        time : float
            Time of the pose [s].
        speed : float, optional
            Measured speed [m/s]; not used.

        Returns
        -------
        TrackerOutput
            Velocities; ``cross_track``, ``heading_error`` and ``along_track`` (> 0 when the
            robot lags) in the frame of the reference posture, whose position is the
            ``target_point``; ``extras``: ``error`` (e1, e2, e3) of (9.63), ``gains``
            (k1, k2, k3) and ``saturated`` of :func:`tracking_command` (absent once finished).

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector or ``time`` is not finite.

        """
        x = check_pose(pose)
        if not math.isfinite(time):
            raise ValueError(f'time must be finite, got {time!r}')
        params = self._params
        if self._reference is None:   # an untimed path starts where the robot starts
            self._reference = TimedPath(self._path, self._times, float(params.reference_speed),
                                        time, float(params.curvature_spacing), self._stations)
        reference = self._reference.reference(time)
        error_x, error_y = x[0] - reference.x, x[1] - reference.y
        c, s = math.cos(reference.theta), math.sin(reference.theta)
        cross = -s * error_x + c * error_y
        behind = -(c * error_x + s * error_y)
        heading = angle_error(float(x[2]), reference.theta)
        target = np.array([reference.x, reference.y])
        target.flags.writeable = False
        if time >= self._reference.end_time and \
                math.hypot(error_x, error_y) <= float(params.goal_tolerance):
            self._finished = True
        if self._finished:
            return TrackerOutput(0.0, 0.0, cross, heading, behind, target, True)
        command = tracking_command(x, reference, params)
        return TrackerOutput(command.linear, command.angular, cross, heading, behind, target,
                             False, {'error': command.error, 'gains': command.gains,
                                     'saturated': command.saturated})
