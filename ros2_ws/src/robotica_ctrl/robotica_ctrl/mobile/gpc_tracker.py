"""
The GPC path tracker of book §9.5 (fig. 9.28; Ollero & Amidi 1991).

The generalised predictive controller of :mod:`robotica_ctrl.mobile.gpc` steers a vehicle
along a path (§9.5 with the bicycle model of §9.4.4): the output is the lateral distance
to the path and the input the commanded curvature γ (fig. 9.28). The book linearises
(9.109)-(9.110) ``ξ' = -v φ``, ``φ' = γ v`` with the steering lag ``γ' = (u - γ)/τ``; in
REP-103, with the lateral offset e positive to the left of the path and the heading error
θ̃ = θ - θ_path (θ = φ + π/2, both measured in the same path-attached frame), the same model
reads ``e' = v θ̃``, ``θ̃' = v γ``, i.e. ``e = v²/(s² (τ s + 1)) u``. It is sampled with a
zero-order hold at the control period T (:func:`lateral_carima_model`) and rebuilt whenever the
speed changes (the procedure after (9.139)).

Each period the tracker attaches a frame to the path point closest to the vehicle, tangent to
the path there (the book's local coordinates (9.122)-(9.123), θ_path standing for φ_d(0)), and
works in the small-angle geometry of the model: a point at arc length σ along the path from
there and offset e to its left has the lateral coordinate ``e + Y(σ)``, with the unrolled path
``Y(σ) = ∫₀^σ (θ_path(σ') - θ_path(0)) dσ'`` (the sine of (9.122)-(9.123) replaced by its
angle, the distance along the tangent by the arc length). The output y(k) is the cross-track
error, the past outputs are ``e(k-i) + Y(s(k-i) - s(k))`` from the stored cross-track errors and
progress, and the desired outputs are ``y_d(k+j) = Y(v T j)``: the path the vehicle should
follow, previewed over the horizon, which makes a longer horizon anticipate curves (figs
9.29-9.31). On a circle the model is then exact, so γ settles on the path's curvature with
no steady-state error (the book: the steering command stays close to the path curvature).

The law is discrete: :class:`GpcPathTracker` runs once per ``sample_time`` and holds its
command in between (zero-order hold), whatever the rate of its updates.
"""

from collections import deque
from dataclasses import dataclass
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.gpc import check_horizons, GpcController
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_ctrl.mobile.tracker_base import check_pose, PathTrackerBase, TrackerOutput
from robotica_kin.angles import wrap_to_pi

__all__ = ['GpcPathTracker', 'GpcTrackerParams', 'lateral_carima_model']


def lateral_carima_model(speed: float, sample_time: float, steering_time_constant: float = 0.0
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return A(q⁻¹), B(q⁻¹) of the linearised lateral bicycle model at ``speed``, sampled with ZOH.

    Continuous model (9.109)-(9.113) in REP-103 form: ``e' = v θ̃``, ``θ̃' = v γ`` and, when
    τ > 0, ``γ' = (u - γ)/τ``; output e (lateral offset [m], > 0 left), input u (commanded
    curvature [1/m]), so e = v² / (s² (τ s + 1)) u. With a zero-order hold at T this is
    ``A(q⁻¹) e(k) = B(q⁻¹) u(k-1)``; τ = 0 gives the double integrator
    A = 1 - 2 q⁻¹ + q⁻², B = (v T)²/2 (1 + q⁻¹); τ > 0 gives
    A = (1 - q⁻¹)² (1 - p q⁻¹), p = exp(-T/τ), and three B coefficients.

    Parameters
    ----------
    speed : float
        Forward speed v > 0 [m/s].
    sample_time : float
        Sampling period T > 0 [s].
    steering_time_constant : float
        Steering lag τ >= 0 [s] (0: the curvature follows the command at once).

    Returns
    -------
    a : ndarray, shape (3,) or (4,)
    b : ndarray, shape (2,) or (3,)

    Raises
    ------
    ValueError
        If v or T is not positive and finite, or τ is negative or not finite.

    Examples
    --------
    >>> lateral_carima_model(1.0, 0.1)
    (array([ 1., -2.,  1.]), array([0.005, 0.005]))

    """
    for name, value in (('speed', speed), ('sample_time', sample_time)):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f'{name} must be positive and finite, got {value!r}')
    tau = steering_time_constant
    if not (math.isfinite(tau) and tau >= 0.0):
        raise ValueError(f'steering_time_constant must be finite and >= 0 s, got {tau!r}')
    v, t = float(speed), float(sample_time)
    if tau == 0.0:
        phi = [[1.0, v * t], [0.0, 1.0]]
        gamma = [0.5 * (v * t) ** 2, v * t]
    else:
        # Exact ZOH solution of the states (e, θ̃, γ) over one period (derived by integrating
        # γ(t) = p(t) γ0 + (1 - p(t)) u twice), p = exp(-T/τ).
        p = math.exp(-t / tau)
        lag = tau * (1.0 - p)
        phi = [[1.0, v * t, v * v * tau * (t - lag)],
               [0.0, 1.0, v * lag],
               [0.0, 0.0, p]]
        gamma = [v * v * (0.5 * t * t - tau * t + tau * lag), v * (t - lag), 1.0 - p]
    return _transfer_function(phi, gamma)


def _transfer_function(
    phi: list[list[float]], gamma: list[float]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return A, B of ``e(z)/u(z) = C (zI - Φ)⁻¹ Γ`` with C = [1, 0, …] (Faddeev–LeVerrier).

    det(zI - Φ) = z^n + c_1 z^(n-1) + … + c_n and adj(zI - Φ) = Σ_k M_k z^(n-k) with
    M_1 = I, M_k = Φ M_(k-1) + c_(k-1) I, c_k = -tr(Φ M_k)/k; dividing by z^n gives A in q⁻¹
    and, the numerator being of degree n - 1, a one-step delay times B = [C M_k Γ].
    """
    n = len(phi)
    a = [1.0] + [0.0] * n
    b = [0.0] * n
    m = [[float(i == j) for j in range(n)] for i in range(n)]
    for k in range(1, n + 1):
        if k > 1:
            m = [[sum(phi[i][r] * m[r][j] for r in range(n)) + a[k - 1] * (i == j)
                  for j in range(n)] for i in range(n)]
        a[k] = -sum(phi[i][r] * m[r][i] for i in range(n) for r in range(n)) / k
        b[k - 1] = sum(m[0][r] * gamma[r] for r in range(n))
    return np.array(a), np.array(b)


@dataclass(frozen=True)
class GpcTrackerParams:
    """
    Tunables of :class:`GpcPathTracker`.

    The defaults follow the NavLab experiment of §9.5 where the book gives numbers (18 path
    points, NU = 1, N1 = 1); the other values are ours.

    Raises
    ------
    ValueError
        If a float is not positive and finite (``steering_time_constant`` and ``softening``
        may be 0, ``control_weight`` too when the problem stays well posed, ``max_curvature``
        may be infinite), a horizon is not an integer with 1 <= n1 <= n2 and 1 <= nu <= n2,
        or ``softening`` is not in [0, 1).

    Examples
    --------
    >>> GpcTrackerParams(n2=25).n2
    25

    """

    linear_velocity: float = 1.0  # v [m/s], commanded forward speed (> 0)
    sample_time: float = 0.1  # T [s], control period; the command is held in between
    steering_time_constant: float = 0.0  # τ [s], first-order steering lag (0: none), (9.113)
    n1: int = 1  # N1, first predicted step (9.121)
    n2: int = 18  # N2, last predicted step (9.121); NavLab: 18 points
    nu: int = 1  # NU, control horizon (9.128); NavLab: 1
    control_weight: float = 0.1  # λ [m⁴] on Δγ² (9.121): output in m, input in 1/m
    softening: float = 0.0  # α = exp(-τ_e) in [0, 1), reference softening (9.140)
    max_curvature: float = math.inf  # [1/m], |γ| limit of the vehicle
    model_speed_tolerance: float = 0.0  # relative speed change that rebuilds the model (0: any)
    goal_tolerance: float = 0.05  # [m]
    search_window: float = 2.0  # [m], closest-point search around the progress

    def __post_init__(self) -> None:
        check_horizons(self.n1, self.n2, self.nu)
        for name in ('linear_velocity', 'sample_time', 'goal_tolerance', 'search_window'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        for name in ('steering_time_constant', 'control_weight', 'model_speed_tolerance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (self.max_curvature > 0.0):
            raise ValueError(f'max_curvature must be > 0 1/m, got {self.max_curvature!r}')
        if not (math.isfinite(self.softening) and 0.0 <= self.softening < 1.0):
            raise ValueError(f'softening must be in [0, 1), got {self.softening!r}')


class GpcPathTracker(PathTrackerBase[GpcTrackerParams]):
    """
    GPC path tracker of a :class:`PolylinePath` (book §9.5, fig. 9.28; Ollero & Amidi 1991).

    Each period: project the position on the path (in a window around the progress, as
    :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`); take the frame tangent to the
    path at the closest point; express the current and past positions and the path an arc
    length v T j ahead (j = 1 … N2) as lateral offsets in it (module docstring); compute
    Δγ(k) by (9.129) and apply γ(k) = γ(k-1) + Δγ(k), limited to ``max_curvature`` (the
    applied increment is the one remembered). The model (9.118) comes from
    :func:`lateral_carima_model` at the current speed and is rebuilt when that speed changes
    by more than ``model_speed_tolerance``. Between periods the command is held.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses (e.g. ``odom``).
    params : GpcTrackerParams
        Tunables; replace them with :meth:`set_params`.

    Raises
    ------
    ValueError
        If ``params`` make the GPC problem singular (λ = 0 with too few rows).

    Notes
    -----
    The law runs at the first :meth:`update` and then at the first one at least
    ``sample_time`` later; the stored cross-track errors and progress of those periods give
    the model's past outputs. The updates in between hold the command (zero-order hold) and
    report the errors of their own pose. After construction or :meth:`reset` the vehicle is
    assumed to have driven straight along its current heading with γ = 0 (the model at rest).
    Beyond the end of the path the reference continues along the last segment. As
    :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`, it stops (zero command) once
    within ``goal_tolerance`` of the end, until :meth:`reset`.

    Examples
    --------
    >>> from robotica_ctrl.mobile.path import PolylinePath
    >>> tracker = GpcPathTracker(PolylinePath([[0.0, 0.0], [20.0, 0.0]]), GpcTrackerParams())
    >>> out = tracker.update([0.0, 0.0, 0.0], 0.0)
    >>> out.linear, out.extras['curvature'], out.cross_track
    (1.0, 0.0, 0.0)

    """

    def __init__(self, path: PolylinePath, params: GpcTrackerParams) -> None:
        super().__init__(path, params)
        self._model_speed = params.linear_velocity
        self._controller = _build_controller(params, self._model_speed)
        self.reset()

    @property
    def controller(self) -> GpcController:
        """Return the GPC core built for the current model."""
        return self._controller

    def set_params(self, params: GpcTrackerParams) -> None:
        """
        Use ``params`` from now on; the model is rebuilt, the progress and history kept.

        Raises
        ------
        ValueError
            If the new GPC problem is singular (the old params are then kept).

        """
        self._controller = _build_controller(params, params.linear_velocity)
        self._params = params
        self._model_speed = params.linear_velocity

    def reset(self, curvature: float = 0.0) -> None:
        """
        Restart from the beginning of the path, with γ(k-1) = ``curvature`` [1/m].

        Raises
        ------
        ValueError
            If ``curvature`` is not finite.

        """
        if not math.isfinite(curvature):
            raise ValueError(f'curvature must be finite, got {curvature!r}')
        super().reset()
        self._history: deque[tuple[float, float]] = deque(maxlen=_MAX_HISTORY)
        self._du_past: deque[float] = deque(maxlen=_MAX_HISTORY)
        self._u = float(curvature)
        self._next_time = -math.inf
        self._held: tuple[float, float, Mapping[str, Any]] = (0.0, 0.0, {'curvature': 0.0})

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Return the command for the vehicle pose ``pose`` at ``time`` (fig. 9.28).

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        time : float
            Time of the pose [s]: the law runs once per ``sample_time`` (class notes).
        speed : float, optional
            Measured forward speed [m/s]: the model is built at it (book: the model at the
            current speed) once it exceeds a fifth of ``params.linear_velocity``, at
            ``params.linear_velocity`` before (and when it is None or not finite). The
            commanded speed is always ``params.linear_velocity``.

        Returns
        -------
        TrackerOutput
            Velocities, errors from the projection and the closest point as
            ``target_point``; ``extras``: ``curvature`` γ = u(k) [1/m], ``reference``
            (N2 - N1 + 1,), the softened desired lateral offsets w(k+N1) … w(k+N2) [m] in the
            local, unrolled path frame (module notes), the path previewed over the horizon,
            and ``prediction`` (N2 - N1 + 1,), the predicted offsets ŷ(k+N1) … ŷ(k+N2) [m]
            with the planned increments (read-only; those of the last period while held).

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector.

        Examples
        --------
        1 m left of a straight path, heading along it: turn right (γ < 0).

        >>> from robotica_ctrl.mobile.path import PolylinePath
        >>> path = PolylinePath([[0.0, 0.0], [20.0, 0.0]])
        >>> out = GpcPathTracker(path, GpcTrackerParams()).update([0.0, 1.0, 0.0], 0.0)
        >>> out.cross_track, out.extras['curvature'] < 0.0
        (1.0, True)

        """
        x = check_pose(pose)
        params = self._params
        if time >= self._next_time - 1e-9 or self._finished:
            v = params.linear_velocity   # the model at the measured speed once moving (§9.5)
            if speed is not None and math.isfinite(speed) and speed > 0.2 * v:
                v = speed
            output = self._period(x, v)
            self._held = (output.linear, output.angular, output.extras)
            self._next_time = time + self._params.sample_time
            return output
        projection = self._path.project(x[:2], s_hint=self._progress,
                                        window=params.search_window)
        linear, angular, extras = self._held
        return self._output(linear, angular, float(x[2]), projection, projection.point, False,
                            extras)

    def _period(self, pose: NDArray[np.float64], v: float) -> TrackerOutput:
        """Run one period of the law for ``pose`` with the model at speed ``v`` [m/s] > 0."""
        params = self._params
        x, projection = self._locate(pose)
        if abs(v - self._model_speed) > params.model_speed_tolerance * self._model_speed:
            self._controller = _build_controller(params, v)
            self._model_speed = v
        ctrl = self._controller
        path = self._path
        e = projection.cross_track
        theta = float(x[2])
        if self._finished:
            zeros = np.zeros(params.n2 - params.n1 + 1)
            zeros.flags.writeable = False
            return self._output(0.0, 0.0, theta, projection, projection.point, True,
                                {'curvature': 0.0, 'reference': zeros, 'prediction': zeros})
        heading_error = float(wrap_to_pi(theta - projection.tangent_heading))
        na = ctrl.a.size - 1
        nb = ctrl.b.size - 1
        step = v * params.sample_time
        past = list(self._history)[:na]
        ahead = projection.s + step * np.arange(1.0, params.n2 + 1.0)
        offsets = _unrolled_offsets(path, projection,
                                    np.concatenate(([s for _, s in past], ahead)))
        y_past = np.empty(na + 1)
        y_past[0] = e
        for i, (e_i, _) in enumerate(past, start=1):
            y_past[i] = e_i + offsets[i - 1]
        # Missing past outputs (after a reset): driven straight at the current heading, γ = 0.
        for i in range(len(past) + 1, na + 1):
            y_past[i] = y_past[i - 1] - step * heading_error
        du_past = np.zeros(nb)
        recent = list(self._du_past)[:nb]
        du_past[:len(recent)] = recent
        increments, reference = ctrl.plan(y_past, du_past, offsets[len(past):])
        u = min(max(self._u + float(increments[0]), -params.max_curvature),
                params.max_curvature)
        self._du_past.appendleft(u - self._u)
        self._u = u
        self._history.appendleft((e, projection.s))
        linear = params.linear_velocity
        prediction = np.array(ctrl.prediction)
        reference.flags.writeable = prediction.flags.writeable = False
        return self._output(linear, linear * u, theta, projection, projection.point, False,
                            {'curvature': u, 'reference': reference, 'prediction': prediction})


_MAX_HISTORY = 4  # past outputs and increments kept: na + 1 <= 4, nb <= 2


def _unrolled_offsets(path: PolylinePath, projection: PathProjection,
                      s: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the path's unrolled lateral offsets Y(s) [m] from its point at ``projection.s``.

    Y(σ) = ∫ (θ_path(σ') - θ_path(s0)) dσ' from s0 = ``projection.s`` to σ, the lateral offset
    of the path in the frame tangent to it at s0 with the small-angle geometry of the model
    (sin replaced by its angle, arc length for the longitudinal coordinate). Headings are
    unwrapped along the path; before its start and after its end the path continues straight.
    """
    s0 = projection.s
    lo, hi = min(float(s.min()), s0), max(float(s.max()), s0)
    last = len(path.headings) - 1
    i_lo = min(max(int(np.searchsorted(path.s, lo, side='right')) - 1, 0), projection.segment)
    i_hi = max(min(int(np.searchsorted(path.s, hi, side='right')) - 1, last),
               projection.segment)
    headings = np.unwrap(path.headings[i_lo:i_hi + 1])
    relative = headings - headings[projection.segment - i_lo]
    breaks = np.concatenate(([lo], path.s[i_lo + 1:i_hi + 1], [hi]))
    integral = np.concatenate(([0.0], np.cumsum(np.diff(breaks) * relative)))
    offsets: NDArray[np.float64] = np.interp(s, breaks, integral) - np.interp(s0, breaks,
                                                                              integral)
    return offsets


def _build_controller(params: GpcTrackerParams, speed: float) -> GpcController:
    """Return the GPC core of the lateral model at ``speed`` [m/s] (procedure after (9.139))."""
    a, b = lateral_carima_model(speed, params.sample_time, params.steering_time_constant)
    return GpcController(a, b, params.n1, params.n2, params.nu, params.control_weight,
                         params.softening)
