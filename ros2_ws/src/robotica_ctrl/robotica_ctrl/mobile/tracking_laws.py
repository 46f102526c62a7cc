"""
Every path- and trajectory-tracking law of book ch. 9 behind one interface, chosen by name.

The ``path_tracker`` node and the tracking benchmark drive the laws through this module:
:func:`make_law` builds the law named by one of :data:`LAWS` from a path and a flat mapping of
gains (the node's ``<law>.<gain>`` parameters, described with units and ranges in
:data:`LAW_PARAMETERS`), and every law answers :meth:`TrackingLaw.update` with the same
:class:`TrackerOutput`: the velocity command (v [m/s], ω [rad/s]) and the tracking errors.

========================= ============================================================ =======
law                       core                                                         book
========================= ============================================================ =======
``pure_pursuit``          :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`      §9.3.1
``adaptive_pure_pursuit`` :class:`~robotica_ctrl.mobile.adaptive_lookahead.AdaptivePurePursuit`
                          (L by speed, curvature or error)                             §9.3.1
``quintic``               :class:`~robotica_ctrl.mobile.quintic_tracker.QuinticTracker` §9.3.2
``trajectory_tracking``   :class:`~robotica_ctrl.mobile.trajectory_tracking.TrajectoryTracker`
                          (linear, scheduled or nonlinear, Canudas de Wit et al.)      §9.4.2
``frenet``                :class:`~robotica_ctrl.mobile.frenet_path_following.FrenetPathFollower`
                          (linear or nonlinear)                                        §9.4.3
``gpc``                   :class:`~robotica_ctrl.mobile.gpc.GpcPathTracker`            §9.5
========================= ============================================================ =======

Trajectory tracking needs a reference in time: the path's own timing when it has one (the
``times`` of :func:`make_law`, from the stamps of a ``nav_msgs/Path``), else the path driven at
``reference_speed`` from the first update on (:class:`TimedPath`). GPC runs once per its
``sample_time`` and holds its command in between, as the book's discrete controller does.
Frames are REP-103: x forward, y left, θ from the x axis, lateral errors > 0 left of the path.
"""

from abc import ABC, abstractmethod
from dataclasses import dataclass, fields, replace
import math
from typing import Any, Callable, Mapping, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.adaptive_lookahead import (AdaptivePurePursuit, LOOKAHEAD_RULES,
                                                     LookaheadRule)
from robotica_ctrl.mobile.frenet_path_following import (FRENET_LAWS, FrenetParams,
                                                        FrenetPathFollower)
from robotica_ctrl.mobile.gpc import GpcPathTracker, GpcTrackerParams
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.quintic_tracker import (path_curvature, path_heading, QuinticTracker,
                                                  QuinticTrackerParams)
from robotica_ctrl.mobile.tracker_base import check_pose
from robotica_ctrl.mobile.trajectory_tracking import (LAWS as TRAJECTORY_LAWS,
                                                      PostureReference, TrajectoryTracker,
                                                      TrajectoryTrackingParams)

__all__ = ['LAWS', 'LAW_PARAMETERS', 'LawParameter', 'TimedPath', 'TrackerOutput',
           'TrackingLaw', 'law_defaults', 'make_law', 'steering_angle']

LAWS = ('pure_pursuit', 'adaptive_pure_pursuit', 'quintic', 'trajectory_tracking', 'frenet',
        'gpc')


@dataclass(frozen=True)
class LawParameter:
    """
    One tunable of a law: default, description with unit and book symbol, range or choices.

    ``low``/``high`` bound a number (inclusive); ``choices`` list the values of a string.
    """

    default: float | int | str
    description: str
    low: float | None = None
    high: float | None = None
    choices: tuple[str, ...] = ()


_TRACKING = {   # the path-end and search tunables every path law shares
    'goal_tolerance': ('Distance to the path end at which the path is finished [m]',
                       1e-4, 100.0),
    'search_window': ('Half-width of the closest-point search around the progress [m]',
                      1e-3, 1000.0),
}
_PURE_PURSUIT = {
    'lookahead_distance': ('Look-ahead arc distance L [m], book (9.7)', 0.01, 100.0),
    'desired_linear_velocity': ('Cruise speed [m/s]', 1e-3, 100.0),
    'max_angular_velocity': ('Yaw-rate limit [rad/s]; the speed is lowered to keep the '
                             'curvature', 1e-3, 100.0),
    'approach_distance': ('Distance to the path end over which the speed ramps down [m]',
                          1e-3, 1000.0),
    'min_approach_velocity': ('Lowest speed while approaching the end [m/s]', 1e-4, 100.0),
    **_TRACKING,
}
_RULE = {
    'gain': ('Look-ahead gain: [s] for rule speed (L = gain v), dimensionless for curvature '
             '(L = gain / |c|) and error (L = min + gain |e|)', 0.0, 1000.0),
    'min_lookahead': ('Smallest look-ahead L [m]', 1e-3, 100.0),
    'max_lookahead': ('Largest look-ahead L [m]', 1e-3, 100.0),
    'curvature_spacing': ('Spacing of the three path points of the curvature estimate [m]',
                          1e-3, 10.0),
}
_QUINTIC = {
    'lookahead_distance': ('Arc distance from the closest point to the goal posture [m], '
                           'book (9.10)-(9.14)', 0.01, 100.0),
    'desired_linear_velocity': ('Cruise speed [m/s]', 1e-3, 100.0),
    'max_angular_velocity': ('Yaw-rate limit [rad/s]', 1e-3, 100.0),
    'actuator_delay': ('Steering lag compensated: the curvature is taken v tau ahead on the '
                       'quintic [s]', 1e-3, 10.0),
    'curvature_spacing': ('Spacing of the points of the path-curvature estimate [m]',
                          1e-3, 10.0),
    **_TRACKING,
}
_FRENET = {
    'k1': ('Lateral gain k1 [1/m^2], book (9.93)/(9.99)', 1e-6, 1e4),
    'k2': ('Heading gain k2 [1/m], book (9.93); k(v) = k2 |v| in (9.99)', 1e-6, 1e4),
    'desired_linear_velocity': ('Speed v [m/s], not controlled by the law', 1e-3, 100.0),
    'max_angular_velocity': ('Yaw-rate limit [rad/s]', 1e-3, 100.0),
    'curvature_window': ('Half-width of the arc over which the path curvature is averaged '
                         '[m]', 1e-3, 100.0),
    **_TRACKING,
}
_TRAJECTORY = {
    'k1': ('Along-track gain k1 [1/s] of the linear law (9.70)', 1e-6, 1e4),
    'k2': ('Lateral gain k2 [1/m]: fixed in (9.70), constant of (9.78)', 1e-6, 1e4),
    'k3': ('Heading gain k3 [1/s] of the linear law (9.70)', 1e-6, 1e4),
    'delta': ('Damping delta of (9.74), scheduled (9.77) and nonlinear (9.82) gains',
              1e-6, 100.0),
    'beta': ('Speed weight beta [rad^2/m^2] of b = sqrt(w_r^2 + beta v_r^2) (9.76)',
             1e-6, 1e4),
    'max_linear': ('|v| limit of the command [m/s]', 1e-3, 100.0),
    'max_angular': ('|w| limit of the command [rad/s]', 1e-3, 100.0),
    'reference_speed': ('Speed of the reference along a path without timing [m/s]',
                        1e-3, 100.0),
    'curvature_spacing': ('Spacing of the points of the reference heading and curvature '
                          'estimates [m]', 1e-3, 10.0),
    'goal_tolerance': ('Distance to the path end at which the trajectory is finished, once '
                       'the reference has reached it [m]', 1e-4, 100.0),
}
_GPC = {
    'linear_velocity': ('Commanded speed v [m/s] (> 0)', 1e-3, 100.0),
    'sample_time': ('Control period T [s] of the discrete law; the command is held in '
                    'between', 1e-3, 10.0),
    'steering_time_constant': ('First-order steering lag tau [s] of the model, (9.113); 0: '
                               'none', 0.0, 10.0),
    'n1': ('First predicted step N1, (9.121)', 1, 200),
    'n2': ('Last predicted step N2, (9.121)', 1, 200),
    'nu': ('Control horizon NU, (9.128)', 1, 200),
    'control_weight': ('Weight lambda [m^4] on the curvature increments, (9.121)', 0.0, 1e6),
    'softening': ('Reference softening alpha = exp(-tau_e) in [0, 1), (9.140)', 0.0, 0.999),
    'max_curvature': ('|curvature| limit of the vehicle [1/m]', 1e-3, 1e6),
    'model_speed_tolerance': ('Relative speed change that rebuilds the model (0: any)',
                              0.0, 10.0),
    **_TRACKING,
}


_FIELD = {'variant': 'law'}   # gain name -> params field, where they differ ('law' is the node's)


def _specs(defaults: Any, numbers: dict[str, tuple[str, float, float]],
           strings: dict[str, tuple[str, tuple[str, ...]]] | None = None,
           overrides: dict[str, float | int | str] | None = None) -> dict[str, LawParameter]:
    """Return the parameter specs of a law, defaults from its params dataclass ``defaults``."""
    overrides = overrides or {}

    def default(name: str) -> Any:
        return overrides[name] if name in overrides else getattr(defaults,
                                                                 _FIELD.get(name, name))

    specs = {name: LawParameter(default(name), description, choices=choices)
             for name, (description, choices) in (strings or {}).items()}
    for name, (description, low, high) in numbers.items():
        specs[name] = LawParameter(default(name), description, low, high)
    return specs


LAW_PARAMETERS: dict[str, dict[str, LawParameter]] = {
    'pure_pursuit': _specs(PurePursuitParams(), _PURE_PURSUIT),
    'adaptive_pure_pursuit': _specs(
        PurePursuitParams(), {k: v for k, v in _PURE_PURSUIT.items()
                              if k != 'lookahead_distance'} | _RULE,
        {'rule': ('Input of the look-ahead rule', LOOKAHEAD_RULES)},
        {'rule': LookaheadRule().kind, 'gain': LookaheadRule().gain,
         'min_lookahead': LookaheadRule().minimum, 'max_lookahead': LookaheadRule().maximum,
         'curvature_spacing': LookaheadRule().curvature_spacing}),
    'quintic': _specs(QuinticTrackerParams(), _QUINTIC),
    'trajectory_tracking': _specs(
        TrajectoryTrackingParams(), _TRAJECTORY,
        {'variant': ('Canudas de Wit law: linear (9.70), scheduled (9.77) or nonlinear (9.78)',
                     TRAJECTORY_LAWS)},
        {'reference_speed': 0.5, 'curvature_spacing': 0.1, 'goal_tolerance': 0.05}),
    'frenet': _specs(FrenetParams(), _FRENET,
                     {'variant': ('Frenet law: linear (9.93) or nonlinear (9.99)',
                                  FRENET_LAWS)}),
    # A finite curvature limit by default: unlimited, GPC's curvature steps at a sharp corner
    # reached 48 rad/s at 0.5 m/s in the tracking benchmark.
    'gpc': _specs(GpcTrackerParams(), _GPC, overrides={'max_curvature': 2.0,
                                                       'model_speed_tolerance': 0.1}),
}


def law_defaults(law: str) -> dict[str, float | int | str]:
    """
    Return the default gains of ``law`` (a name of :data:`LAWS`) as a flat mapping.

    >>> law_defaults('pure_pursuit')['lookahead_distance']
    0.5
    """
    return {name: spec.default for name, spec in _law_specs(law).items()}


class TrackerOutput(NamedTuple):
    """
    One step of any law: the command and the errors the node reports as ``TrackingError``.

    Attributes
    ----------
    linear : float
        Forward velocity v [m/s] in ``base_link``.
    angular : float
        Yaw rate ω [rad/s], > 0 counter-clockwise.
    cross_track : float
        Lateral offset from the path (or the reference) [m], > 0 left of it.
    heading_error : float
        θ - θ_path (or θ - θ_ref) [rad], wrapped to (-π, π].
    along_track : float
        Offset along the path beyond its ends (path laws), or behind the reference
        (trajectory tracking, > 0 when the robot lags) [m].
    target_point : ndarray, shape (2,)
        The point the law steers to: goal point, or reference position [m].
    finished : bool
        Whether the end of the path (or trajectory) was reached; the command is then zero.

    """

    linear: float
    angular: float
    cross_track: float
    heading_error: float
    along_track: float
    target_point: NDArray[np.float64]
    finished: bool


class TrackingLaw(ABC):
    """A tracking law with its state, driven once per control period by :meth:`update`."""

    def __init__(self, path: PolylinePath) -> None:
        self.path = path

    @abstractmethod
    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        """
        Return the command and errors for ``pose`` (x [m], y [m], θ [rad]) at ``time`` [s].

        ``speed`` is the measured forward speed [m/s] when known (adaptive look-ahead, GPC
        model). Raises ValueError for a pose that is not a finite (3,) vector.
        """

    @abstractmethod
    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace some gains (names of :data:`LAW_PARAMETERS`); ValueError keeps the old."""

    @abstractmethod
    def reset(self) -> None:
        """Restart from the beginning of the path (and of the trajectory)."""


def _heading_error(theta: float, reference: float) -> float:
    """Return θ - θ_ref [rad] wrapped to (-π, π] (scalar, cheaper than wrap_to_pi)."""
    error = math.remainder(theta - reference, math.tau)
    return math.pi if error == -math.pi else error


def _output(linear: float, angular: float, pose: NDArray[np.float64],
            projection: PathProjection, target: NDArray[np.float64],
            finished: bool) -> TrackerOutput:
    """Return the output of a path law whose core has accepted ``pose`` (x, y, θ)."""
    return TrackerOutput(float(linear), float(angular), projection.cross_track,
                         _heading_error(float(pose[2]), projection.tangent_heading),
                         projection.along_track, target, finished)


class _Wrapped(TrackingLaw):
    """A path law whose core takes a params dataclass; gains map onto its fields."""

    def __init__(self, path: PolylinePath, core: Any, params_type: type) -> None:
        super().__init__(path)
        self._core = core
        self._fields = {field.name for field in fields(params_type)}

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        changes = {_FIELD.get(name, name): value for name, value in gains.items()
                   if _FIELD.get(name, name) in self._fields}
        self._core.set_params(replace(self._core.params, **changes))

    def reset(self) -> None:
        self._core.reset()


class _PurePursuitLaw(_Wrapped):
    def __init__(self, path: PolylinePath, gains: Mapping[str, Any]) -> None:
        super().__init__(path, PurePursuit(path, _params(PurePursuitParams, gains)),
                         PurePursuitParams)

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        x = np.asarray(pose, dtype=np.float64)   # the core checks it
        command = self._core.update(x)
        return _output(command.linear, command.angular, x, command.projection,
                       command.goal_point, command.finished)


class _AdaptiveLaw(TrackingLaw):
    def __init__(self, path: PolylinePath, gains: Mapping[str, Any]) -> None:
        super().__init__(path)
        self._gains = dict(gains)
        self._core = AdaptivePurePursuit(path, *self._build(self._gains))

    @staticmethod
    def _build(gains: Mapping[str, Any]) -> tuple[PurePursuitParams, LookaheadRule]:
        rule = LookaheadRule(str(gains['rule']), float(gains['gain']),
                             float(gains['min_lookahead']), float(gains['max_lookahead']),
                             float(gains['curvature_spacing']))
        params = _params(PurePursuitParams, {**gains, 'lookahead_distance': rule.minimum})
        return params, rule

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        x = np.asarray(pose, dtype=np.float64)   # the core checks it
        command = self._core.update(x, speed)
        return _output(command.linear, command.angular, x, command.projection,
                       command.goal_point, command.finished)

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        merged = {**self._gains, **gains}
        self._core.set_params(*self._build(merged))
        self._gains = merged

    def reset(self) -> None:
        self._core.reset()


class _QuinticLaw(_Wrapped):
    def __init__(self, path: PolylinePath, gains: Mapping[str, Any]) -> None:
        super().__init__(path, QuinticTracker(path, _params(QuinticTrackerParams, gains)),
                         QuinticTrackerParams)

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        x = check_pose(pose)
        command = self._core.update(x)
        return _output(command.linear, command.angular, x, self._core.last_projection,
                       command.goal_point, command.finished)


class _FrenetLaw(_Wrapped):
    def __init__(self, path: PolylinePath, gains: Mapping[str, Any]) -> None:
        super().__init__(path, FrenetPathFollower(path, _params(FrenetParams, gains)),
                         FrenetParams)

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        command = self._core.update(pose)
        projection = command.projection
        return TrackerOutput(command.linear, command.angular, command.lateral_error,
                             command.heading_error, projection.along_track, projection.point,
                             command.finished)


class _GpcLaw(_Wrapped):
    """
    GPC once per ``sample_time``; the command is held in between (zero-order hold).

    The model is that of the measured speed once it exceeds a fifth of the commanded one
    (rebuilt when it changes by ``model_speed_tolerance``), of the commanded speed before.
    """

    def __init__(self, path: PolylinePath, gains: Mapping[str, Any]) -> None:
        super().__init__(path, GpcPathTracker(path, _params(GpcTrackerParams, gains)),
                         GpcTrackerParams)
        self._next_time = -math.inf
        self._held = (0.0, 0.0)

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        x = check_pose(pose)
        if time >= self._next_time - 1e-9 or self._core.finished:
            params = self._core.params   # the model at the measured speed, once moving (§9.5)
            moving = speed is not None and math.isfinite(speed) and \
                speed > 0.2 * params.linear_velocity
            command = self._core.update(x, speed if moving else None)
            self._held = (command.linear, command.angular)
            self._next_time = time + self._core.params.sample_time
            return _output(command.linear, command.angular, x, command.projection,
                           command.projection.point, command.finished)
        projection = self.path.project(x[:2], s_hint=self._core.progress,
                                       window=self._core.params.search_window)
        return _output(*self._held, x, projection, projection.point, False)

    def reset(self) -> None:
        super().reset()
        self._next_time = -math.inf
        self._held = (0.0, 0.0)


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


class _TrajectoryLaw(TrackingLaw):
    """Canudas de Wit's posture tracking against a :class:`TimedPath` reference."""

    def __init__(self, path: PolylinePath, gains: Mapping[str, Any],
                 times: ArrayLike | None, stations: ArrayLike | None) -> None:
        super().__init__(path)
        self._times, self._stations = times, stations
        self._gains = dict(gains)
        self._core = TrajectoryTracker(_params(TrajectoryTrackingParams, gains))
        self._reference: TimedPath | None = None
        self._finished = False

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        x = check_pose(pose)
        if not math.isfinite(time):
            raise ValueError(f'time must be finite, got {time!r}')
        if self._reference is None:   # an untimed path starts where the robot starts
            self._reference = TimedPath(self.path, self._times,
                                        float(self._gains['reference_speed']), time,
                                        float(self._gains['curvature_spacing']), self._stations)
        reference = self._reference.reference(time)
        error_x, error_y = x[0] - reference.x, x[1] - reference.y
        c, s = math.cos(reference.theta), math.sin(reference.theta)
        cross = -s * error_x + c * error_y
        behind = -(c * error_x + s * error_y)
        heading = _heading_error(float(x[2]), reference.theta)
        target = np.array([reference.x, reference.y])
        if time >= self._reference.end_time and \
                math.hypot(error_x, error_y) <= float(self._gains['goal_tolerance']):
            self._finished = True
        if self._finished:
            return TrackerOutput(0.0, 0.0, cross, heading, behind, target, True)
        command = self._core.update(x, reference)
        return TrackerOutput(command.linear, command.angular, cross, heading, behind, target,
                             False)

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        merged = {**self._gains, **gains}
        self._core.set_params(_params(TrajectoryTrackingParams, merged))
        self._gains = merged

    def reset(self) -> None:
        self._reference = None
        self._finished = False


def _params(params_type: Any, gains: Mapping[str, Any]) -> Any:
    """Return ``params_type`` built from the entries of ``gains`` that are its fields."""
    names = {field.name for field in fields(params_type)}
    return params_type(**{_FIELD.get(name, name): value for name, value in gains.items()
                          if _FIELD.get(name, name) in names})


def steering_angle(linear: float, angular: float, wheelbase: float) -> float:
    """
    Return the steering angle α = atan(l ω / v) [rad] of a law's (v, ω) for a steered vehicle.

    Book (4.119), (4.121), l = ``wheelbase`` [m]. Stopped (v = 0) the wheel keeps straight:
    unlike :func:`robotica_kin.mobile.bicycle.bicycle_inverse`, which refuses a turn on the
    spot, a controller's command must never fail.

    >>> round(math.degrees(steering_angle(1.0, 1.0, 1.5)), 2)   # Ej. 4.8
    56.31
    """
    return math.atan(wheelbase * angular / linear) if linear != 0.0 else 0.0


def _law_specs(law: str) -> dict[str, LawParameter]:
    if law not in LAW_PARAMETERS:
        raise ValueError(f'law must be one of {LAWS}, got {law!r}')
    return LAW_PARAMETERS[law]


def make_law(law: str, path: PolylinePath, gains: Mapping[str, Any] | None = None,
             times: ArrayLike | None = None, stations: ArrayLike | None = None) -> TrackingLaw:
    """
    Return the tracking law named ``law`` (one of :data:`LAWS`) for ``path``.

    Parameters
    ----------
    law : str
        Name of the law.
    path : PolylinePath
        Reference path in the frame of the poses.
    gains : mapping, optional
        Gains by the names of ``LAW_PARAMETERS[law]``; missing ones take their defaults.
    times : array_like, optional
        Time [s] of each path point, strictly increasing (trajectory tracking only; without
        it the reference moves at ``reference_speed``).
    stations : array_like, optional
        Arc length [m] of each point ``times`` refers to (default ``path.s``; give them when
        the points had duplicates that :class:`PolylinePath` dropped).

    Raises
    ------
    ValueError
        For an unknown law or gain name, or a gain the law refuses.

    >>> law = make_law('pure_pursuit', PolylinePath([[0.0, 0.0], [5.0, 0.0]]))
    >>> law.update([0.0, 0.0, 0.0], 0.0).linear
    0.5

    """
    specs = _law_specs(law)
    unknown = set(gains or {}) - set(specs)
    if unknown:
        raise ValueError(f'{law} has no gain {sorted(unknown)}; its gains: {sorted(specs)}')
    merged = {**law_defaults(law), **(gains or {})}
    if law == 'trajectory_tracking':
        return _TrajectoryLaw(path, merged, times, stations)
    builders: dict[str, Callable[[PolylinePath, Mapping[str, Any]], TrackingLaw]] = {
        'pure_pursuit': _PurePursuitLaw, 'adaptive_pure_pursuit': _AdaptiveLaw,
        'quintic': _QuinticLaw, 'frenet': _FrenetLaw, 'gpc': _GpcLaw}
    return builders[law](path, merged)
