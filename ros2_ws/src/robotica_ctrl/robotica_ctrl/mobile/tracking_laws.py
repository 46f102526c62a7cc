"""
Every tracking law of the book behind one interface, chosen by name: the registry.

The ``path_tracker`` node and the tracking benchmark drive the laws through this module:
:func:`make_law` builds the law named by a key of :data:`LAW_PARAMETERS` from a path and a
flat mapping of gains (the node's ``<law>.<gain>`` parameters, described there with units and
ranges), and every law answers
:meth:`~robotica_ctrl.mobile.tracker_base.TrackingLaw.update` with the same
:class:`~robotica_ctrl.mobile.tracker_base.TrackerOutput`: the velocity command
(v [m/s], ω [rad/s]), the tracking errors and the law's own telemetry.

========================== ============================================================ =======
law                        class                                                        book
========================== ============================================================ =======
``pure_pursuit``           :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`      §9.3.1
``adaptive_pure_pursuit``  :class:`~robotica_ctrl.mobile.adaptive_lookahead.AdaptivePurePursuit`
                           (L by speed, curvature or error)                             §9.3.1
``reversing_pure_pursuit`` :class:`~.reversing_pure_pursuit.ReversingPurePursuit`      §9.3.1
                           (path of postures cut at its cusps, reverse pieces backwards)
``quintic``                :class:`~robotica_ctrl.mobile.quintic_tracker.QuinticTracker` §9.3.2
``trajectory_tracking``    :class:`~robotica_ctrl.mobile.trajectory_tracking.TrajectoryTracker`
                           (linear, scheduled or nonlinear, Canudas de Wit et al.)      §9.4.2
``frenet``                 :class:`~robotica_ctrl.mobile.frenet_path_following.FrenetPathFollower`
                           (linear or nonlinear)                                        §9.4.3
``gpc``                    :class:`~robotica_ctrl.mobile.gpc_tracker.GpcPathTracker`    §9.5
``open_loop``              :class:`~robotica_ctrl.mobile.open_loop.OpenLoop`            §4.7
                           (a profile of (v, ω) against time, no feedback)
========================== ============================================================ =======

:data:`LAWS` lists the six the tracking benchmark compares (reversing pure pursuit, on its
paths without cusps, is pure pursuit). Trajectory tracking needs a reference in time: the
path's own timing when it has one (the ``times`` of :func:`make_law`, from the stamps of a
``nav_msgs/Path``), else the path driven at ``reference_speed`` from the first update on. GPC
runs once per its ``sample_time`` and holds its command in between, as the book's discrete
controller does. The open-loop profile reads neither the pose nor the path. Reversing pure
pursuit follows the path's postures (x, y, θ): the ``postures`` of :func:`make_law`, the
points with the ``headings`` of :func:`law_for_path` (the yaws of a ``nav_msgs/Path``'s
orientations). A step against the heading is driven in reverse (v < 0), with a stop at each
cusp; without headings the postures face along the path and the law is pure pursuit. Frames
are REP-103: x forward, y left, θ from the x axis, lateral errors > 0 left of the path.
"""

from dataclasses import replace
import math
from typing import Any, Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.mobile.adaptive_lookahead import (adaptive_params, AdaptivePurePursuit,
                                                     LOOKAHEAD_RULES, LookaheadRule)
from robotica_ctrl.mobile.frenet_path_following import (FRENET_LAWS, FrenetParams,
                                                        FrenetPathFollower)
from robotica_ctrl.mobile.gpc_tracker import GpcPathTracker, GpcTrackerParams
from robotica_ctrl.mobile.open_loop import OpenLoop, OpenLoopProfile
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.quintic_tracker import QuinticTracker, QuinticTrackerParams
from robotica_ctrl.mobile.reversing_pure_pursuit import ReversingPurePursuit
from robotica_ctrl.mobile.tracker_base import replace_gains, TrackingLaw
from robotica_ctrl.mobile.trajectory_tracking import (LAWS as TRAJECTORY_LAWS,
                                                      TrajectoryTracker,
                                                      TrajectoryTrackingParams)
from robotica_kin.mobile.vehicles import GEOMETRY_PARAMETERS
from robotica_kin.parameter_specs import check_parameters, ParameterSpec

__all__ = ['COMMAND_TYPES', 'LAWS', 'LAW_PARAMETERS', 'POSE_SOURCES', 'TRACKER_PARAMETERS',
           'check_gains', 'law_defaults', 'law_for_path', 'make_law', 'steering_angle']

LAWS = ('pure_pursuit', 'adaptive_pure_pursuit', 'quintic', 'trajectory_tracking', 'frenet',
        'gpc')
"""
The laws the tracking benchmark compares; :data:`LAW_PARAMETERS` also holds
``reversing_pure_pursuit`` (pure pursuit on a path without cusps) and ``open_loop``.
"""


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
_OPEN_LOOP = {
    'times': 'Times t_k [s] of the profile rows, strictly increasing; the last row is held '
             'after them, book Ej. 4.8, 4.9',
    'linear': 'Forward speed v_k [m/s] of each row, linear in between',
    'angular': 'Yaw rate w_k [rad/s] of each row, linear in between',
}


def _specs(defaults: Any, numbers: dict[str, tuple[str, float, float]],
           strings: dict[str, tuple[str, tuple[str, ...]]] | None = None,
           overrides: dict[str, float | int | str] | None = None) -> dict[str, ParameterSpec]:
    """Return the parameter specs of a law, defaults from its params dataclass ``defaults``."""
    overrides = overrides or {}

    def default(name: str) -> Any:
        return overrides[name] if name in overrides else getattr(defaults, name)

    specs = {name: ParameterSpec(default(name), description, choices=choices)
             for name, (description, choices) in (strings or {}).items()}
    for name, (description, low, high) in numbers.items():
        specs[name] = ParameterSpec(default(name), description, low, high)
    return specs


LAW_PARAMETERS: dict[str, dict[str, ParameterSpec]] = {
    'pure_pursuit': _specs(PurePursuitParams(), _PURE_PURSUIT),
    'reversing_pure_pursuit': _specs(PurePursuitParams(), _PURE_PURSUIT),
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
        {'variant': TrajectoryTrackingParams().law}),
    'frenet': _specs(FrenetParams(), _FRENET,
                     {'variant': ('Frenet law: linear (9.93) or nonlinear (9.99)',
                                  FRENET_LAWS)},
                     {'variant': FrenetParams().law}),
    # A finite curvature limit by default: unlimited, GPC's curvature steps at a sharp corner
    # reached 48 rad/s at 0.5 m/s in the tracking benchmark.
    'gpc': _specs(GpcTrackerParams(), _GPC, overrides={'max_curvature': 2.0,
                                                       'model_speed_tolerance': 0.1}),
    'open_loop': {name: ParameterSpec((0.0,), description)   # standing still
                  for name, description in _OPEN_LOOP.items()},
}
"""Every law :func:`make_law` builds (:data:`LAWS`, ``reversing_pure_pursuit``, ``open_loop``)."""

POSE_SOURCES = ('odom', 'ground_truth')
COMMAND_TYPES = ('twist', 'steering')
TRACKER_PARAMETERS: dict[str, ParameterSpec] = {
    'law': ParameterSpec('pure_pursuit', 'Tracking law', choices=tuple(LAW_PARAMETERS)),
    'command_type': ParameterSpec('twist', 'Command: cmd_vel Twist, or vehicle_command '
                                  'VehicleCommand for steered vehicles', choices=COMMAND_TYPES),
    'wheelbase': replace(GEOMETRY_PARAMETERS['wheelbase'], description=(
        'Wheelbase l [m] of a steered vehicle (command_type steering)')),
    'pose_source': ParameterSpec('odom', 'Pose the law reads (odom: the estimate; '
                                 'ground_truth: the truth of the simulator, ground_truth/odom)',
                                 choices=POSE_SOURCES),
    'max_cross_track': ParameterSpec(5.0, 'Farther than this from the path [m] the robot is '
                                     'lost: stop', 1e-3, 1e6),
    'control_rate': ParameterSpec(0.0, 'Control rate [Hz]; 0: once per pose message',
                                  0.0, 1000.0),
    'pose_timeout': ParameterSpec(0.5, 'With control_rate > 0, a pose older than this [s] '
                                  'stops the robot', 1e-3, 60.0),
}
"""The path tracker's own parameters (not a law's gains): ranges and choices."""

_Builder = Callable[[PolylinePath, Mapping[str, Any], ArrayLike | None, ArrayLike | None,
                     ArrayLike | None], TrackingLaw]
"""A law from (path, gains, times, stations, postures), the arguments of :func:`make_law`."""


def _reversing(path: PolylinePath, gains: Mapping[str, Any],
               postures: ArrayLike | None) -> ReversingPurePursuit:
    """Return reversing pure pursuit of ``postures`` (default: ``path`` at its tangents)."""
    if postures is None:
        headings = path.headings
        postures = np.column_stack([path.points, np.append(headings, headings[-1])])
    return ReversingPurePursuit(postures, replace_gains(PurePursuitParams(), gains))


_BUILDERS: dict[str, _Builder] = {
    'pure_pursuit': lambda path, gains, times, stations, postures: PurePursuit(
        path, replace_gains(PurePursuitParams(), gains)),
    'reversing_pure_pursuit': lambda path, gains, times, stations, postures: _reversing(
        path, gains, postures),
    'adaptive_pure_pursuit': lambda path, gains, times, stations, postures: AdaptivePurePursuit(
        path, *adaptive_params(gains)),
    'quintic': lambda path, gains, times, stations, postures: QuinticTracker(
        path, replace_gains(QuinticTrackerParams(), gains)),
    'trajectory_tracking': lambda path, gains, times, stations, postures: TrajectoryTracker(
        path, replace_gains(TrajectoryTrackingParams(), gains), times, stations),
    'frenet': lambda path, gains, times, stations, postures: FrenetPathFollower(
        path, replace_gains(FrenetParams(), gains)),
    'gpc': lambda path, gains, times, stations, postures: GpcPathTracker(
        path, replace_gains(GpcTrackerParams(), gains)),
    'open_loop': lambda path, gains, times, stations, postures: OpenLoop(
        OpenLoopProfile(**gains)),
}


def law_defaults(law: str) -> dict[str, float | int | str | tuple[float, ...]]:
    """
    Return the default gains of ``law`` (a key of :data:`LAW_PARAMETERS`) as a flat mapping.

    >>> law_defaults('pure_pursuit')['lookahead_distance']
    0.5
    """
    return {name: spec.default for name, spec in _law_specs(law).items()}


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


def _law_specs(law: str) -> dict[str, ParameterSpec]:
    if law not in LAW_PARAMETERS:
        raise ValueError(f'law must be one of {tuple(LAW_PARAMETERS)}, got {law!r}')
    return LAW_PARAMETERS[law]


def make_law(law: str, path: PolylinePath, gains: Mapping[str, Any] | None = None,
             times: ArrayLike | None = None, stations: ArrayLike | None = None,
             postures: ArrayLike | None = None) -> TrackingLaw:
    """
    Return the tracking law named ``law`` (a key of :data:`LAW_PARAMETERS`) for ``path``.

    Parameters
    ----------
    law : str
        Name of the law.
    path : PolylinePath
        Reference path in the frame of the poses (the open-loop profile ignores it).
    gains : mapping, optional
        Gains by the names of ``LAW_PARAMETERS[law]``; missing ones take their defaults.
    times : array_like, optional
        Time [s] of each path point, strictly increasing (trajectory tracking only; without
        it the reference moves at ``reference_speed``).
    stations : array_like, optional
        Arc length [m] of each point ``times`` refers to (default ``path.s``; give them when
        the points had duplicates that :class:`PolylinePath` dropped).
    postures : array_like, shape (N, 3), optional
        The path as postures (x [m], y [m], θ [rad]) in the order of travel, duplicates kept
        (a cusp may repeat a point): reversing pure pursuit only, which drives a step against
        θ in reverse (default: ``path``'s points at their tangent headings, all forward).

    Raises
    ------
    ValueError
        For an unknown law or gain name, a gain the law refuses, or postures that are not
        finite (N, 3) (reversing pure pursuit).

    >>> law = make_law('pure_pursuit', PolylinePath([[0.0, 0.0], [5.0, 0.0]]))
    >>> law.update([0.0, 0.0, 0.0], 0.0).linear
    0.5

    """
    specs = _law_specs(law)
    unknown = set(gains or {}) - set(specs)
    if unknown:
        raise ValueError(f'{law} has no gain {sorted(unknown)}; its gains: {sorted(specs)}')
    merged = {**law_defaults(law), **(gains or {})}
    return _BUILDERS[law](path, merged, times, stations, postures)


def check_gains(law: str, gains: Mapping[str, Any]) -> None:
    """
    Check the gains of ``law`` as the path tracker does at start-up and on every change.

    Each gain against its range or choices (:data:`LAW_PARAMETERS`), then together by the law
    itself (:func:`make_law` on a straight path: e.g. ``min_lookahead <= max_lookahead``).

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For a gain out of its range or choices (``name`` is the gain's).
    ValueError
        For an unknown law or gain, or gains the law refuses together.

    Examples
    --------
    >>> check_gains('pure_pursuit', {'lookahead_distance': 1.0})

    """
    check_parameters(_law_specs(law), gains)
    make_law(law, PolylinePath([[0.0, 0.0], [1.0, 0.0]]), gains)


def law_for_path(law: str, points: ArrayLike, gains: Mapping[str, Any] | None = None,
                 times: ArrayLike | None = None, headings: ArrayLike | None = None
                 ) -> tuple[TrackingLaw, PolylinePath, bool]:
    """
    Return the law ``law`` for the path through ``points`` (N, 2) [m], the path, and if timed.

    What the path tracker does with each path it receives: ``times`` (N,) [s], the stamps of
    the path's poses, make it a trajectory when they increase strictly (trajectory tracking
    follows them at the arc length of each point, duplicates included); otherwise they are
    ignored. ``headings`` (N,) [rad], the yaw of each pose's orientation, are the vehicle's
    heading at each point for reversing pure pursuit (a step against the heading is driven
    in reverse; the points with them are the law's postures, duplicates kept); the other laws
    ignore them.

    Raises
    ------
    ValueError
        For a path of fewer than two distinct points, headings that are not one per point,
        or as :func:`make_law`.

    Examples
    --------
    >>> law, path, timed = law_for_path('pure_pursuit', [[0.0, 0.0], [5.0, 0.0]],
    ...                                 times=[0.0, 0.0])
    >>> path.length, timed
    (5.0, False)
    >>> law, _, _ = law_for_path('reversing_pure_pursuit', [[0, 0], [1, 0], [0, 0]],
    ...                          headings=[0, 0, 0])   # 1 m forward, then 1 m back
    >>> [law.update([1.0, 0.0, 0.0], 0.0).linear for _ in range(2)]   # at the cusp: stop, back
    [0.0, -0.5]

    """
    xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    postures = None
    if headings is not None:
        yaw = np.asarray(headings, dtype=np.float64)
        if yaw.shape != (len(xy),):
            raise ValueError(f'headings must be one per point ({len(xy)}), got shape '
                             f'{yaw.shape}')
        postures = np.column_stack([xy, yaw])
    stamps = np.asarray(times if times is not None else [], dtype=np.float64)
    timed = stamps.size == len(xy) >= 2 and bool(np.all(np.diff(stamps) > 0.0))
    path = PolylinePath(xy)
    stations = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))))
    return make_law(law, path, gains, stamps if timed else None,
                    stations if timed else None, postures), path, timed
