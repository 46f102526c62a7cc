"""
Metrics of a recorded run, computed from its :class:`~robotica_sim.grading.series.RunSeries`.

Three groups, each computed when the bag holds its topics (:data:`METRICS` lists every metric
with its unit, topics and definition; docs/grading.md explains them):

- **mobile** (path tracking, book ch. 9): cross-track and heading errors of the ground truth
  against the reference ``/path`` (the closest point is searched within a window around the
  progress, as the trackers do, so that a closed or self-crossing path is followed lap by
  lap; a path whose orientations are the vehicle's headings, as a parking plan that reverses
  sends it, is measured against those headings: :func:`segment_directions`), completion,
  time, path length, control effort, collisions and time in contact (from the simulator's
  ``/bumper``, recorded when the run has a world); the final pose error
  against the last pose of the last ``/path`` (a parking plan's parked goal, issue 21) and the
  number of manoeuvres (:func:`travel_stretches` of the truth's speed);
- **estimation** (book ch. 7): the error of the ``/odom`` estimate against the ground truth,
  interpolated at the estimate's stamps, and the fraction of samples within 3 sigma;
- **arm** (book ch. 8): joint errors ``e = q_d - q`` (8.30) of the joint controller, settling
  time, overshoot, peak torque, mechanical energy, and the tool's Cartesian error by forward
  kinematics (4.6) of the scenario's arm.

A metric whose topic the bag lacks is *absent* (in :attr:`RunMetrics.absent`, with the
reason), never zero (a run without a world has no ``/bumper``: its collisions are absent); a
metric that exists but cannot be defined for this run (no step reference for overshoot) is
None with a note.

For the sensor figures of ``robotica report``: :func:`reading_error` (a reading minus the truth
at its stamp) and :func:`normal_fit` (mean, standard deviation of an error).
"""
from dataclasses import dataclass, field
import math
from typing import Any, Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_kin.angles import wrap_to_pi
from robotica_sim.grading.series import RunSeries, Series, TOPICS

__all__ = ['METRICS', 'MetricInfo', 'MetricParams', 'MetricValue', 'RunMetrics',
           'compute_metrics', 'contact_events', 'energy', 'max_abs', 'normal_fit', 'overshoot',
           'path_errors', 'pose_errors', 'reading_error', 'rms', 'segment_directions',
           'truth_path_errors',
           'settling_time', 'total_variation', 'travel_stretches', 'travelled_length']

MetricValue = float | bool | list[float | None] | None
"""A metric's value: a number, a flag, one number per joint (None: n/a for that joint)."""


@dataclass(frozen=True)
class MetricParams:
    """Tunables of the metrics (a rubric's ``parameters`` section overrides them)."""

    goal_tolerance: float = 0.1   # [m] the end is reached within this (arc length, distance)
    search_window: float = 2.0    # [m] half-width of the closest-point search around progress
    settling_band: float = 0.02   # [-] settling band, fraction of the joint's reference span
    sigma_bound: float = 3.0      # [-] consistency bound of the estimate, in std deviations
    stop_speed: float = 0.01      # [m/s] |v| up to this is a stop, for manoeuvres
    orientation_tolerance: float = 0.05   # [rad] /path orientation vs tangent, in (0, pi/4]

    def __post_init__(self) -> None:
        for name in ('goal_tolerance', 'search_window', 'settling_band', 'sigma_bound',
                     'stop_speed', 'orientation_tolerance'):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
                    math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be a finite number > 0, got {value!r}')
        if self.settling_band >= 1.0:
            raise ValueError(f'settling_band must be < 1, got {self.settling_band!r}')
        if self.orientation_tolerance > math.pi / 4.0:
            raise ValueError(f'orientation_tolerance must be <= pi/4 rad, got '
                             f'{self.orientation_tolerance!r}')


@dataclass(frozen=True)
class MetricInfo:
    """What a metric means: unit, group, the topics it needs and its definition."""

    unit: str
    group: str                   # 'run', 'mobile', 'estimation' or 'arm'
    topics: tuple[str, ...]      # all needed (alternatives are described in ``definition``)
    definition: str
    per_joint: bool = False


_TRUTH, _PATH, _ODOM = TOPICS['truth'], TOPICS['path'], TOPICS['odom']
_CONTROLLER, _TORQUES = TOPICS['controller'], TOPICS['torques']
_JOINTS, _REFERENCE = TOPICS['joint_states'], TOPICS['trajectory']
_JOINT_ERROR = (_JOINTS, _REFERENCE)   # or the controller's report, _CONTROLLER

METRICS: dict[str, MetricInfo] = {
    'rms_cross_track': MetricInfo(
        'm', 'mobile', (_TRUTH, _PATH),
        'RMS over the ground-truth samples of the signed distance to the path (> 0 left of '
        'the travel direction; on a reverse segment of a path whose orientations are the '
        'vehicle headings, > 0 left of the heading, as the reversing tracker measures it); '
        'from /path_tracker/tracking_error when the bag lacks the truth or the path'),
    'max_cross_track': MetricInfo(
        'm', 'mobile', (_TRUTH, _PATH), 'largest |cross-track error|, as rms_cross_track'),
    'rms_heading_error': MetricInfo(
        'rad', 'mobile', (_TRUTH, _PATH),
        'RMS of the truth heading minus the reference heading at the closest point, wrapped '
        'to (-pi, pi]: the heading the /path orientations give when each segment is within '
        'orientation_tolerance of its first pose orientation or of its opposite (the tangent, '
        '+ pi on a reverse segment), else the path tangent; from the tracking error topic as '
        'rms_cross_track'),
    'max_heading_error': MetricInfo(
        'rad', 'mobile', (_TRUTH, _PATH), 'largest |heading error|, as rms_heading_error'),
    'completion': MetricInfo(
        '-', 'mobile', (_TRUTH, _PATH),
        'arc length of the closest path point to the last truth pose / path length, in [0, 1]'),
    'finished': MetricInfo(
        'bool', 'mobile', (_TRUTH, _PATH),
        'true once both the remaining arc length and the distance to the last path point '
        'were within goal_tolerance (as the trackers decide it); 1 in a rubric'),
    'time': MetricInfo('s', 'run', (TOPICS['clock'],), 'duration of the run: the last /clock'),
    'path_length': MetricInfo('m', 'mobile', (_TRUTH,),
                              'length of the travelled ground-truth polyline'),
    'rms_angular_command': MetricInfo(
        'rad/s', 'mobile', (TOPICS['cmd_vel'],), 'RMS of the angular velocity command w'),
    'angular_command_variation': MetricInfo(
        'rad/s', 'mobile', (TOPICS['cmd_vel'],),
        'total variation sum |w[k+1] - w[k]| of the angular velocity command, the integral '
        'of |dw/dt| dt: large when the command chatters'),
    'rms_steering': MetricInfo(
        'rad', 'mobile', (TOPICS['vehicle_command'],), 'RMS of the steering angle command'),
    'steering_variation': MetricInfo(
        'rad', 'mobile', (TOPICS['vehicle_command'],),
        'total variation sum |a[k+1] - a[k]| of the steering angle command'),
    'rms_trajectory_error': MetricInfo(
        'm', 'mobile', (_TRUTH, _PATH),
        'RMS distance from the truth to the timed reference point at the same time (only for '
        'a /path whose pose stamps increase: a trajectory)'),
    'max_trajectory_error': MetricInfo(
        'm', 'mobile', (_TRUTH, _PATH), 'largest distance, as rms_trajectory_error'),
    'final_position_error': MetricInfo(
        'm', 'mobile', (_TRUTH, _PATH),
        "distance from the truth's last position to the last pose of the last /path (a "
        "parking plan's parked goal; a tracked path's end)"),
    'final_heading_error': MetricInfo(
        'rad', 'mobile', (_TRUTH, _PATH),
        "|truth's last heading minus the yaw of the last /path pose's orientation|, wrapped "
        'to [0, pi] (the orientation is the vehicle heading, also on a reverse segment)'),
    'manoeuvres': MetricInfo(
        '-', 'mobile', (_TRUTH,),
        "stretches of travel in one direction of the truth's longitudinal speed v: samples "
        'with |v| <= stop_speed are stops and skipped; 1 + the sign changes among the moving '
        'samples (a stop between two arcs of one direction is no new one), 0 if it never moves'),
    'collisions': MetricInfo(
        'count', 'mobile', (TOPICS['bumper'],),
        "contacts with the obstacles of the scenario's world: a contact starts when the "
        'robot touches after being free (the simulator stops it there)'),
    'time_in_contact': MetricInfo(
        's', 'mobile', (TOPICS['bumper'],),
        'simulated time the robot spent touching the world: the steps that began in contact'),
    'rms_position_error': MetricInfo(
        'm', 'estimation', (_ODOM, _TRUTH),
        'RMS of the /odom position error against the truth interpolated at the odom stamps'),
    'max_position_error': MetricInfo(
        'm', 'estimation', (_ODOM, _TRUTH), 'largest /odom position error'),
    'rms_odom_heading_error': MetricInfo(
        'rad', 'estimation', (_ODOM, _TRUTH),
        'RMS of the /odom heading error, wrapped to (-pi, pi]'),
    'max_odom_heading_error': MetricInfo(
        'rad', 'estimation', (_ODOM, _TRUTH), 'largest |/odom heading error|'),
    'within_3_sigma': MetricInfo(
        '-', 'estimation', (_ODOM, _TRUTH),
        'fraction of /odom samples whose x, y and heading errors are all within sigma_bound '
        '(3) standard deviations of the odom covariance diagonal; n/a without covariance'),
    'rms_joint_error': MetricInfo(
        'rad|m', 'arm', _JOINT_ERROR, 'per joint, RMS of e = q_d - q (8.30): q of /joint_states, '
        'q_d the recorded joint trajectory at its times (without them, the controller_state)',
        per_joint=True),
    'max_joint_error': MetricInfo(
        'rad|m', 'arm', _JOINT_ERROR, 'per joint, largest |e|', per_joint=True),
    'settling_time': MetricInfo(
        's', 'arm', _JOINT_ERROR,
        'per joint, time from the first sample after which |e| stays within the band '
        'settling_band * max(reference span, |e(0)|); n/a when the last sample is outside',
        per_joint=True),
    'overshoot': MetricInfo(
        '%', 'arm', _JOINT_ERROR,
        'per joint, 100 * (largest travel of q beyond the final reference) / |final reference '
        '- q(0)|, for a set-point reference (held over the last quarter of the run)',
        per_joint=True),
    'peak_torque': MetricInfo(
        'N m|N', 'arm', (_TORQUES,), 'per joint, largest |tau| of /joint_torques',
        per_joint=True),
    'energy': MetricInfo(
        'J', 'arm', (_TORQUES, _JOINTS),
        'integral of sum_j |tau_j qdot_j| dt (trapezoid), tau from /joint_torques, qdot from '
        '/joint_states interpolated at the torque times'),
    'rms_cartesian_error': MetricInfo(
        'm', 'arm', _JOINT_ERROR,
        'RMS distance between the tool positions of q_d and q = q_d - e, by forward '
        "kinematics (4.6) of the scenario's arm (two_link_arm: tip at l2 along x2; puma560)"),
    'max_cartesian_error': MetricInfo(
        'm', 'arm', _JOINT_ERROR, 'largest tool position error, as rms_cartesian_error'),
}
"""Every metric :func:`compute_metrics` knows, by name."""


@dataclass(frozen=True)
class RunMetrics:
    """The metrics of one run."""

    values: dict[str, MetricValue]   # computed metrics; None: n/a (see notes)
    notes: dict[str, str] = field(default_factory=dict)   # why n/a, or the data source
    absent: dict[str, str] = field(default_factory=dict)  # metric -> why the bag cannot give it
    joint_names: tuple[str, ...] = ()


def rms(values: ArrayLike) -> float:
    """
    Return the root mean square of ``values`` (any shape, over every element; same unit).

    The one RMS of the project: grading, the run summary, the report and the benchmarks use
    it. An empty input gives NaN (there is no mean to take); a NaN in the input gives NaN.

    >>> rms([3.0, -3.0, 3.0, -3.0])
    3.0
    >>> rms([])
    nan
    """
    a = np.asarray(values, dtype=np.float64)
    return math.sqrt(float(np.mean(a * a))) if a.size else math.nan


def total_variation(u: ArrayLike) -> float:
    """
    Return ``sum |u[k+1] - u[k]|``, the integral of ``|du/dt| dt`` of a sampled signal.

    >>> total_variation([0.0, 1.0, -1.0])
    3.0
    """
    return float(np.sum(np.abs(np.diff(np.asarray(u, dtype=np.float64)))))


def travelled_length(x: ArrayLike, y: ArrayLike) -> float:
    """
    Return the length [m] of the polyline through the points (x, y) [m].

    >>> travelled_length([0.0, 3.0, 3.0], [0.0, 4.0, 5.0])
    6.0
    """
    return float(np.sum(np.hypot(np.diff(np.asarray(x, dtype=np.float64)),
                                 np.diff(np.asarray(y, dtype=np.float64)))))


def travel_stretches(v: ArrayLike, stop_speed: float) -> int:
    """
    Return the number of manoeuvres: stretches of travel in one direction of a speed signal.

    Samples with ``|v| <= stop_speed`` are stops and are skipped; a stretch is a maximal run of
    moving samples of one sign, and two stretches of the same sign separated only by a stop
    are one (the stop between the two arcs of a reverse manoeuvre, where the wheels are
    re-oriented, starts no new manoeuvre). So the count is 1 + the number of sign changes
    among the moving samples, and 0 when nothing moves.

    Parameters
    ----------
    v : array_like, shape (n,)
        Longitudinal speed [m/s] (> 0 forward), in time order.
    stop_speed : float
        [m/s] the largest ``|v|`` that is a stop (>= 0).

    Returns
    -------
    int

    Examples
    --------
    Forward, stop, reverse, stop, reverse, forward: three manoeuvres.

    >>> travel_stretches([0.5, 0.0, -0.4, 0.005, -0.3, 0.2], 0.01)
    3
    >>> travel_stretches([0.0, 0.004, -0.003], 0.01)
    0

    """
    speeds = np.asarray(v, dtype=np.float64).ravel()
    moving = np.sign(speeds[np.abs(speeds) > stop_speed])
    return int(moving.size and 1 + np.count_nonzero(np.diff(moving)))


_DUPLICATE = 1e-12
"""[m] A path point this close to its predecessor is dropped (as
:class:`~robotica_ctrl.mobile.path.PolylinePath` drops it): its step is no segment."""


def segment_directions(points: ArrayLike, headings: ArrayLike | None,
                       tolerance: float = 0.05) -> NDArray[np.int8] | None:
    """
    Return each segment's direction of travel if a path's orientations are vehicle headings.

    A ``nav_msgs/Path`` gives each pose an orientation. A planner that drives forward gives
    it the tangent (or leaves it the identity, yaw 0, as some external planners do); a plan
    that also reverses (the parking planner of issue 21) gives it the vehicle's heading,
    which on a reverse segment points against the travel. Each segment of non-zero length
    (those of ``PolylinePath(points)``: a point within 1e-12 m of its predecessor is dropped)
    is compared with the orientation ψ of the pose it leaves from (the last pose before the
    next distinct point): forward (+1) when its tangent is within ``tolerance`` of ψ, reverse
    (-1) when within ``tolerance`` of ψ + π. When every segment is one or the other, the
    orientations are the vehicle's headings and their directions are returned; otherwise
    (an orientation across a segment, an orientation that is not finite, no headings) None:
    the orientations say nothing of the heading, and the tangent is the reference.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        The path's positions [m].
    headings : array_like, shape (N,), or None
        The yaw [rad] of each pose's orientation.
    tolerance : float
        [rad] the largest angle between a segment and its pose's orientation (or its
        opposite), in (0, π/4].

    Returns
    -------
    ndarray of int8, shape (M,), or None
        +1 or -1 for each of the M segments of ``PolylinePath(points)``.

    Raises
    ------
    ValueError
        If ``points`` is not (N, 2), ``headings`` not (N,), or ``tolerance`` out of range.

    Examples
    --------
    Two metres out and one back with the heading 0 throughout; then a path along y whose
    orientations are the identity (not its tangent, π/2).

    >>> segment_directions([[0, 0], [1, 0], [2, 0], [2, 0], [1, 0]], [0, 0, 0, 0, 0]).tolist()
    [1, 1, -1]
    >>> segment_directions([[0, 0], [0, 1]], [0.0, 0.0]) is None
    True

    """
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f'points must have shape (N, 2), got {p.shape}')
    if not (isinstance(tolerance, (int, float)) and 0.0 < tolerance <= math.pi / 4.0):
        raise ValueError(f'tolerance must be in (0, pi/4] rad, got {tolerance!r}')
    if headings is None:
        return None
    psi = np.asarray(headings, dtype=np.float64)
    if psi.shape != (len(p),):
        raise ValueError(f'headings must have shape ({len(p)},), one per point, got '
                         f'{psi.shape}')
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(psi))):
        return None
    leaving = np.flatnonzero(np.hypot(*np.diff(p, axis=0).T) > _DUPLICATE)   # step k: k, k+1
    if leaving.size == 0:
        return None
    vertices = p[np.concatenate(([0], leaving + 1))]   # PolylinePath's points
    step = np.diff(vertices, axis=0)
    deviation = np.abs(wrap_to_pi(np.arctan2(step[:, 1], step[:, 0]) - psi[leaving]))
    forward, reverse = deviation <= tolerance, deviation >= math.pi - tolerance
    if not np.all(forward | reverse):
        return None
    return np.where(forward, 1, -1).astype(np.int8)


def truth_path_errors(run: RunSeries, params: MetricParams | None = None
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                 NDArray[np.float64], NDArray[np.int8] | None]:
    """
    Return :func:`path_errors` of the run's truth against its last ``/path``, and the directions.

    The directions are :func:`segment_directions` of the path's orientations (None: the
    tangent is the reference); ``params`` give the search window and the orientation tolerance.
    The one place where grading, the summary line and the report's figure measure the truth.
    """
    chosen = params or MetricParams()
    truth = run.truth
    if truth is None or run.path is None or len(run.path) < 2:
        raise ValueError('the run needs the truth and a /path of two points or more')
    directions = segment_directions(run.path, run.path_headings, chosen.orientation_tolerance)
    s, cross, heading = path_errors(PolylinePath(run.path), truth['x'], truth['y'],
                                    truth['theta'], chosen.search_window, directions)
    return s, cross, heading, directions


def path_errors(path: PolylinePath, x: ArrayLike, y: ArrayLike, theta: ArrayLike,
                window: float, directions: ArrayLike | None = None
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """
    Project poses onto a path in order, following the progress (book fig. 9.4, step 1).

    The one path projection of the project: ``robotica grade``, the summary line of
    ``robotica run``, ``robotica report`` and the tracking benchmark all use it.

    Each pose after the first is projected within ``window`` [m] of arc length around the
    previous projection, as the trackers do
    (:class:`~robotica_ctrl.mobile.tracker_base.PathTrackerBase`), so that a pose near a
    crossing is measured against the branch being driven. On a closed path the search goes on
    past the end into the next lap. The start is chosen among the local closest points of the
    first position (one per stretch of ``window`` of the path, so every branch that passes near
    it is a candidate): from each, the poses are followed until the trajectory has moved
    ``2 window`` [m] from its start (or ends), and the candidate with the smallest sum of
    squared cross-track errors over that stretch wins (the first in s on a tie). A run that
    starts at the beginning of the path starts there; one that starts 1 mm behind the crossing
    of a figure eight is measured on the lobe it drives, not on the other one; one that starts
    on the far lobe is measured from there.

    With ``directions`` (:func:`segment_directions`: the path's orientations are the vehicle's
    headings) a reverse segment (-1) is measured as the reversing tracker
    (:class:`~robotica_ctrl.mobile.reversing_pure_pursuit.ReversingPurePursuit`) measures it:
    against the heading the vehicle should have there, its tangent + π (within the tolerance
    of :func:`segment_directions`, the orientation of its pose: the tangent is used so that a
    vehicle on the segment is measured as on a forward one, whatever the sampling of an arc),
    and the cross-track error is > 0 left of that heading (right of the travel). A path
    whose orientations are all along its tangents (+1 everywhere) is measured exactly as
    without them. On a path with a cusp, where the way back may run over the way out, a
    closest point ahead of the progress (within ``window``) that is as close as the one
    found around it is taken, so that the progress goes on past the cusp instead of back.

    Parameters
    ----------
    path : PolylinePath
        The reference, in the frame of the poses.
    x, y, theta : array_like, shape (n,)
        Poses [m, m, rad], REP-103; n >= 1.
    window : float
        Half-width [m] of the search around the progress (> 0).
    directions : array_like, shape (M,), optional
        +1 (forward) or -1 (reverse) for each of the path's M segments; None: all forward.

    Returns
    -------
    progress, cross_track, heading_error : ndarray, shape (n,)
        Progress [m]: the arc length of the closest point, plus the path length for each lap
        completed on a closed path (a start within ``window`` behind the end of a closed path
        is just behind its start: negative); signed lateral offset [m] (> 0 left of the
        travel; of the heading on a reverse segment); heading minus the reference heading
        (the tangent heading; + π on a reverse segment) [rad], wrapped to (-pi, pi].

    Raises
    ------
    ValueError
        If the inputs differ in length, are empty or not finite, ``window`` is not > 0, or
        ``directions`` is not one +1 or -1 per segment.

    Examples
    --------
    >>> s, e, h = path_errors(PolylinePath([[0, 0], [4, 0]]), [1.0], [0.5], [0.1], 2.0)
    >>> s.tolist(), e.tolist(), h.round(6).tolist()
    ([1.0], [0.5], [0.1])

    Backing along the same line, heading 0: 0.5 m left of the vehicle, heading error 0.1.

    >>> s, e, h = path_errors(PolylinePath([[4, 0], [0, 0]]), [3.0], [0.5], [0.1], 2.0, [-1])
    >>> s.tolist(), e.tolist(), h.round(6).tolist()
    ([1.0], [0.5], [0.1])

    """
    xs, ys = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    thetas = np.asarray(theta, dtype=np.float64)
    if not (xs.ndim == 1 and xs.shape == ys.shape == thetas.shape and xs.size):
        raise ValueError(f'x, y and theta must be (n,) arrays of one length n >= 1, got '
                         f'{xs.shape}, {ys.shape}, {thetas.shape}')
    if not (math.isfinite(window) and window > 0.0):
        raise ValueError(f'window must be a finite number > 0 m, got {window!r}')
    points = np.column_stack([xs, ys])
    if not (np.all(np.isfinite(points)) and np.all(np.isfinite(thetas))):
        raise ValueError('poses must be finite')
    signs = np.ones(len(path.points) - 1)
    if directions is not None:
        given = np.asarray(directions)
        if given.shape != signs.shape or not np.all(np.abs(given) == 1):
            raise ValueError(f'directions must be +1 or -1 for each of the {len(signs)} '
                             f'segments of the path, got {given!r}')
        signs = given.astype(np.float64)
    cusps = bool(np.any(signs < 0.0) and np.any(signs > 0.0))
    n = len(points)
    progress, cross, reference = np.empty(n), np.empty(n), np.empty(n)
    steps = _follow(path, points, _start_progress(path, points, window, cusps), window, cusps)
    for k, (s, projection) in enumerate(steps):
        sign = signs[projection.segment]
        progress[k], cross[k] = s, sign * projection.cross_track
        reference[k] = projection.tangent_heading + (math.pi if sign < 0.0 else 0.0)
    return progress, cross, wrap_to_pi(thetas - reference)


def _follow(path: PolylinePath, points: NDArray[np.float64], start: float,
            window: float, ahead: bool = False) -> Iterator[tuple[float, PathProjection]]:
    """
    Yield the progress [m] and projection of each point, from progress ``start`` [m].

    ``ahead``: a closest point in [progress, progress + window] as close (1e-9 m) as the one
    around the progress is taken (a path with cusps, whose way back may retrace its way out).
    """
    length = path.length
    laps = math.floor(start / length)
    hint = start - laps * length
    for point in points:
        projection = path.project(point, s_hint=hint, window=window)
        end = min(hint + window, length)
        if ahead and end > hint:
            forward = path.project(point, s_hint=0.5 * (hint + end), window=0.5 * (end - hint))
            if forward.distance <= projection.distance + 1e-9:
                projection = forward
        if path.closed and hint + window > length:
            # Past the end of a closed path the search goes on from its start (next lap).
            wrapped = path.project(point, s_hint=0.0, window=hint + window - length)
            if wrapped.distance < projection.distance:
                projection, laps = wrapped, laps + 1
        hint = projection.s
        yield laps * length + hint, projection


def _start_progress(path: PolylinePath, points: NDArray[np.float64], window: float,
                    ahead: bool = False) -> float:
    """Return the progress [m] at which :func:`path_errors` starts following ``points``."""
    first, length = points[0], path.length
    candidates = set()
    for hint in np.append(np.arange(0.0, length, window), length).tolist():
        s = path.project(first, s_hint=hint, window=window).s
        # A closest point cut at an inner end of its search interval is no local minimum:
        # the neighbouring intervals (they overlap by half) find the minimum beyond it.
        if not any(abs(s - end) <= 1e-9 and 0.0 < end < length
                   for end in (hint - window, hint + window)):
            candidates.add(s - length if path.closed and s > length - window else s)
    if len(candidates) == 1:
        return candidates.pop()
    moved = np.hypot(points[:, 0] - first[0], points[:, 1] - first[1])
    beyond = np.flatnonzero(moved >= 2.0 * window)
    stretch = points[:beyond[0] + 1] if beyond.size else points
    scores = [(sum(p.cross_track ** 2 for _, p in _follow(path, stretch, start, window, ahead)),
               start) for start in sorted(candidates)]
    best = min(score for score, _ in scores)
    return next(start for score, start in scores if score <= best * (1.0 + 1e-9) + 1e-12)


def pose_errors(truth: Series, estimate: Series) -> tuple[NDArray[np.float64], ...]:
    """
    Return the errors of ``estimate`` against ``truth`` interpolated at the estimate's stamps.

    Both series have columns ``x``, ``y`` [m] and ``theta`` [rad] in the same frame; the
    truth's heading is unwrapped before the linear interpolation. Estimate samples outside
    the truth's time span are left out.

    Returns
    -------
    t, ex, ey, etheta : ndarray, shape (m,)
        Stamps [s] and errors estimate - truth [m, m, rad (wrapped to (-pi, pi])].

    """
    inside = (estimate.t >= truth.t[0]) & (estimate.t <= truth.t[-1])
    t = estimate.t[inside]
    return (t, *(reading_error(t, estimate[name][inside], truth.t, truth[name],
                               angle=name == 'theta') for name in ('x', 'y', 'theta')))


def settling_time(t: ArrayLike, error: ArrayLike, band: float) -> float | None:
    """
    Return the time [s] from ``t[0]`` after which ``|error|`` stays within ``band``.

    None when the last sample is outside the band (the error never settles).

    >>> settling_time([0.0, 1.0, 2.0, 3.0], [1.0, 0.01, 0.5, 0.01], 0.02)
    3.0
    >>> settling_time([0.0, 1.0], [0.0, 1.0], 0.02) is None
    True
    """
    times = np.asarray(t, dtype=np.float64)
    outside = np.flatnonzero(np.abs(np.asarray(error, dtype=np.float64)) > band)
    if len(outside) == 0:
        return 0.0
    if outside[-1] == len(times) - 1:
        return None
    return float(times[outside[-1] + 1] - times[0])


def overshoot(q: ArrayLike, q_final: float) -> float | None:
    """
    Return the overshoot [%] of a joint moving from ``q[0]`` to the set point ``q_final``.

    ``100 * max(0, max_t sign(d) (q(t) - q_final)) / |d|`` with ``d = q_final - q[0]``;
    None when ``d`` is 0 (no move to overshoot).

    >>> overshoot([0.0, 0.8, 1.25, 1.0], 1.0)
    25.0
    """
    qs = np.asarray(q, dtype=np.float64)
    move = q_final - float(qs[0])
    if abs(move) <= 1e-12 * max(1.0, abs(q_final)):
        return None
    beyond = float(np.max(math.copysign(1.0, move) * (qs - q_final)))
    return 100.0 * max(0.0, beyond) / abs(move)


def energy(t: ArrayLike, tau: ArrayLike, qdot: ArrayLike) -> float:
    """
    Return the mechanical energy [J] ``integral sum_j |tau_j qdot_j| dt`` (trapezoid rule).

    ``t`` [s] (n,); ``tau`` [N m | N] and ``qdot`` [rad/s | m/s] (n, joints) at those times.

    >>> energy([0.0, 1.0, 2.0], [[2.0], [2.0], [2.0]], [[1.0], [-1.0], [1.0]])
    4.0
    """
    power = np.sum(np.abs(np.asarray(tau, dtype=np.float64) * np.asarray(qdot, dtype=float)),
                   axis=1)
    times = np.asarray(t, dtype=np.float64)
    return float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(times)))


def contact_events(t: ArrayLike, in_contact: ArrayLike) -> tuple[int, float]:
    """
    Return the contacts and the time in contact [s] of a bumper's samples.

    ``t`` (n,) [s] in increasing order, ``in_contact`` (n,) true where the robot touches. A
    contact starts at a sample in contact whose predecessor is free (or the first sample);
    the time in contact is the sum of t[k + 1] - t[k] over the samples k in contact (the
    steps that began in contact: the simulator's own count).

    >>> contact_events([0.0, 0.1, 0.2, 0.3, 0.4], [0, 1, 1, 0, 1])
    (2, 0.2)
    """
    times = np.asarray(t, dtype=np.float64)
    touching = np.asarray(in_contact, dtype=bool)
    starts = touching & ~np.concatenate([[False], touching[:-1]])
    time = float(np.sum(np.diff(times)[touching[:-1]]))
    return int(np.count_nonzero(starts)), round(time, 12)


def _lacks(run: RunSeries, topics: tuple[str, ...]) -> str:
    """Return why the run cannot give a metric that needs ``topics``."""
    missing = [topic for topic in topics if not run.counts.get(topic)]
    wrong = [f'{topic}: {run.ignored[topic]}' for topic in topics if topic in run.ignored]
    reasons = []
    if missing:
        names = ' and '.join(missing)
        reasons.append(f'needs topic{"s" if len(missing) > 1 else ""} {names}, which the bag '
                       'lacks')
    if wrong:
        reasons.append(f'cannot use {"; ".join(wrong)}')
    return '; '.join(reasons) or 'needs data the bag lacks'


_TRACKING_FALLBACK = ('rms_cross_track', 'max_cross_track', 'rms_heading_error',
                      'max_heading_error')


def _mobile(run: RunSeries, params: MetricParams, out: RunMetrics) -> None:
    values, notes = out.values, out.notes
    truth = run.truth
    if truth is not None:
        values['path_length'] = travelled_length(truth['x'], truth['y'])
    if run.bumper is not None:
        values['collisions'], values['time_in_contact'] = contact_events(
            run.bumper.t, run.bumper['in_contact'])
    if truth is not None and len(truth):
        values['manoeuvres'] = travel_stretches(truth['v'], params.stop_speed)
        _final_pose(run, truth, out)
    if truth is not None and run.path is not None and len(run.path) >= 2:
        path = PolylinePath(run.path)
        s, cross, heading, directions = truth_path_errors(run, params)
        if directions is not None and np.any(directions < 0):
            reverse = f'{np.count_nonzero(directions < 0)} of {len(directions)} segments'
            for name in ('rms_heading_error', 'max_heading_error'):
                notes[name] = f'against the /path orientations ({reverse} reverse)'
            for name in ('rms_cross_track', 'max_cross_track'):
                notes[name] = f'> 0 left of the heading ({reverse} reverse)'
        values['rms_cross_track'], values['max_cross_track'] = rms(cross), max_abs(cross)
        values['rms_heading_error'], values['max_heading_error'] = (rms(heading),
                                                                    max_abs(heading))
        values['completion'] = float(np.clip(s[-1] / path.length, 0.0, 1.0))
        end_distance = np.hypot(truth['x'] - path.points[-1, 0], truth['y'] - path.points[-1, 1])
        values['finished'] = bool(np.any(np.maximum(path.length - s, end_distance)
                                         <= params.goal_tolerance))
        if run.path_times is not None:
            distance = np.hypot(truth['x'] - np.interp(truth.t, run.path_times, run.path[:, 0]),
                                truth['y'] - np.interp(truth.t, run.path_times, run.path[:, 1]))
            values['rms_trajectory_error'] = rms(distance)
            values['max_trajectory_error'] = max_abs(distance)
        else:
            out.absent['rms_trajectory_error'] = out.absent['max_trajectory_error'] = (
                'needs a timed /path (pose stamps increasing: a trajectory), which the bag '
                'lacks')
    elif run.tracking_error is not None:
        cross, heading = run.tracking_error['cross_track'], run.tracking_error['heading']
        values['rms_cross_track'], values['max_cross_track'] = rms(cross), max_abs(cross)
        values['rms_heading_error'], values['max_heading_error'] = (rms(heading),
                                                                    max_abs(heading))
        for name in _TRACKING_FALLBACK:
            notes[name] = f'from {TOPICS["tracking_error"]} (the bag lacks the truth or path)'
    cmd = run.cmd
    if cmd is not None and 'w' in cmd.columns:
        values['rms_angular_command'] = rms(cmd['w'])
        values['angular_command_variation'] = total_variation(cmd['w'])
    if cmd is not None and 'steering' in cmd.columns:
        values['rms_steering'] = rms(cmd['steering'])
        values['steering_variation'] = total_variation(cmd['steering'])


def _final_pose(run: RunSeries, truth: Series, out: RunMetrics) -> None:
    """Set the final position and heading errors against the last /path's last pose."""
    if run.path is None:
        return   # absent: compute_metrics says which topic the bag lacks
    if len(run.path) == 0:
        out.absent['final_position_error'] = out.absent['final_heading_error'] = (
            'needs a /path with poses; the last /path has none')
        return
    goal = run.path[-1]
    out.values['final_position_error'] = float(math.hypot(truth['x'][-1] - goal[0],
                                                          truth['y'][-1] - goal[1]))
    if run.path_end_heading is None:
        out.absent['final_heading_error'] = ("needs a finite orientation of the last /path's "
                                             'last pose, which the bag lacks')
    else:
        out.values['final_heading_error'] = abs(float(wrap_to_pi(
            truth['theta'][-1] - run.path_end_heading)))


def _estimation(run: RunSeries, params: MetricParams, out: RunMetrics) -> None:
    if run.truth is None or run.odom is None:
        return
    t, ex, ey, eth = pose_errors(run.truth, run.odom)
    if len(t) == 0:
        for name, info in METRICS.items():
            if info.group == 'estimation':
                out.absent[name] = 'needs /odom stamps within the time span of the truth'
        return
    position = np.hypot(ex, ey)
    values = out.values
    values['rms_position_error'], values['max_position_error'] = rms(position), float(
        np.max(position))
    values['rms_odom_heading_error'] = rms(eth)
    values['max_odom_heading_error'] = max_abs(eth)
    inside = (run.odom.t >= run.truth.t[0]) & (run.odom.t <= run.truth.t[-1])
    variances = [run.odom[name][inside] for name in ('var_x', 'var_y', 'var_theta')]
    if not any(np.any(v > 0.0) for v in variances):
        values['within_3_sigma'] = None
        out.notes['within_3_sigma'] = '/odom reports no covariance'
        return
    bound = params.sigma_bound
    within = np.ones(len(t), dtype=bool)
    for error, variance in zip((ex, ey, eth), variances):
        within &= np.abs(error) <= bound * np.sqrt(np.maximum(variance, 0.0))
    values['within_3_sigma'] = float(np.mean(within))


def _joint_errors(run: RunSeries) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                           NDArray[np.float64]] | None:
    """
    Return the times [s], the reference q_d and the error e = q_d - q (8.30), each (n, joints).

    From the simulator's joint states against the recorded reference when the bag has both:
    the truth, whoever controlled the arm (a user's controller's own report is not graded);
    else from the controller's ``controller_state``; None without either.
    """
    if run.reference is not None and run.joint_states is not None \
            and run.joint_states['position'].shape == run.reference['position'].shape:
        q_d = run.reference['position']
        return run.reference.t, q_d, q_d - run.joint_states['position']
    controller = run.controller
    if controller is not None and len(controller) > 0:
        return controller.t, controller['reference_position'], controller['position_error']
    return None


def _arm(run: RunSeries, params: MetricParams, out: RunMetrics) -> None:
    values, notes = out.values, out.notes
    errors = _joint_errors(run)
    if errors is not None and len(errors[0]) > 0:
        t, q_d, e = errors
        q = q_d - e
        values['rms_joint_error'] = [rms(column) for column in e.T]
        values['max_joint_error'] = np.max(np.abs(e), axis=0).tolist()
        span = np.maximum(np.ptp(q_d, axis=0), np.abs(e[0]))
        settling = [settling_time(t, e[:, j], params.settling_band * span[j])
                    for j in range(e.shape[1])]
        values['settling_time'] = settling
        if None in settling:
            notes['settling_time'] = 'n/a for a joint whose error ends outside the band'
        late = t >= t[0] + 0.75 * (t[-1] - t[0])
        held = np.all(np.abs(q_d[late] - q_d[-1]) <= 1e-9 * np.maximum(1.0, np.abs(q_d[-1])),
                      axis=0)
        overshoots = [overshoot(q[:, j], float(q_d[-1, j])) if held[j] else None
                      for j in range(e.shape[1])]
        values['overshoot'] = overshoots
        if None in overshoots:
            notes['overshoot'] = ('n/a for a joint without a set-point reference (held over '
                                  'the last quarter) or without a move')
        cartesian = _tool_errors(run.scenario, q_d, q)
        if isinstance(cartesian, str):
            out.absent['rms_cartesian_error'] = out.absent['max_cartesian_error'] = cartesian
        else:
            values['rms_cartesian_error'] = rms(cartesian)
            values['max_cartesian_error'] = float(np.max(cartesian))
    torques = run.torques
    if torques is not None and len(torques) > 0:
        values['peak_torque'] = np.max(np.abs(torques['effort']), axis=0).tolist()
        joints = run.joint_states
        if joints is not None and joints['velocity'].shape[1] == torques['effort'].shape[1]:
            qdot = np.column_stack([np.interp(torques.t, joints.t, joints['velocity'][:, j])
                                    for j in range(joints['velocity'].shape[1])])
            values['energy'] = energy(torques.t, torques['effort'], qdot)
        elif joints is not None:
            out.absent['energy'] = (f'needs as many /joint_states velocities '
                                    f'({joints["velocity"].shape[1]}) as torques '
                                    f'({torques["effort"].shape[1]})')


def _tool_errors(scenario: dict | None, q_d: NDArray[np.float64],
                 q: NDArray[np.float64]) -> NDArray[np.float64] | str:
    """Return |p(q_d) - p(q)| [m] per sample by FK of the scenario's arm, or why it cannot."""
    arm: Any = (scenario or {}).get('arm')
    if not isinstance(arm, dict):
        return "needs the scenario's arm (model) in the bag's metadata, which the bag lacks"
    # Lazy: robotica_kin's kinematics loads Pinocchio, which only arm runs need.
    from robotica_kin.dh import dh_model
    from robotica_kin.forward_kinematics import fkine
    from robotica_kin.robots import puma560, two_link_arm
    from robotica_kin.transforms import transl
    model = arm.get('model', 'puma560')
    try:
        if model == 'two_link_arm':
            lengths = [float(v) for v in arm['lengths']]
            dh = two_link_arm(1.0, 1.0, *lengths)[0]
            robot = dh_model(dh, tool=transl(lengths[1], 0.0, 0.0))
        elif model == 'puma560':
            robot = puma560()
        else:
            return f'needs a known arm model (two_link_arm, puma560), the scenario has {model!r}'
        if robot.n != q.shape[1]:
            return f'needs {robot.n} joints for {model}, the controller has {q.shape[1]}'
        p_d = fkine(robot, q_d)[:, :3, 3]
        p = fkine(robot, q)[:, :3, 3]
    except (KeyError, TypeError, ValueError) as err:
        return f'needs a valid arm in the scenario: {err}'
    return np.linalg.norm(p_d - p, axis=1)


def max_abs(values: ArrayLike) -> float:
    """
    Return the largest magnitude of ``values`` (any shape, non-empty; same unit).

    >>> max_abs([0.5, -2.0, 1.0])
    2.0
    """
    return float(np.max(np.abs(np.asarray(values, dtype=np.float64))))


def compute_metrics(run: RunSeries, params: MetricParams | None = None) -> RunMetrics:
    """
    Compute every metric the run's topics allow.

    Parameters
    ----------
    run : RunSeries
        The run, from :func:`robotica_sim.grading.series.load_run`.
    params : MetricParams, optional
        Goal tolerance, search window, settling band, sigma bound, stop speed; defaults if
        None.

    Returns
    -------
    RunMetrics
        ``values`` of the computed metrics (None: n/a, explained in ``notes``), and for every
        other metric of :data:`METRICS` the reason in ``absent`` ("needs topic Y, which the
        bag lacks").

    """
    joints = run.controller if run.controller is not None else run.joint_states
    out = RunMetrics(values={}, joint_names=joints.names if joints is not None else ())
    chosen = params or MetricParams()
    if run.counts.get(TOPICS['clock']):
        out.values['time'] = run.duration
    _mobile(run, chosen, out)
    _estimation(run, chosen, out)
    _arm(run, chosen, out)
    for name, info in METRICS.items():
        if name in out.values or name in out.absent:
            continue
        reason = _lacks(run, info.topics)
        if name in _TRACKING_FALLBACK:
            reason += f' (or {TOPICS["tracking_error"]})'
        elif info.topics == _JOINT_ERROR:
            reason += f' (or {_CONTROLLER})'
        elif name in ('collisions', 'time_in_contact'):
            reason += ' (the simulator publishes it when the run has a world)'
        out.absent[name] = reason
    return out


def reading_error(t_reading: ArrayLike, reading: ArrayLike, t_truth: ArrayLike,
                  truth: ArrayLike, angle: bool = False) -> NDArray[np.float64]:
    """
    Return a sensor's error: each reading minus the truth interpolated at its stamp.

    The truth is interpolated linearly between its samples; readings stamped outside the
    truth's time span get NaN.

    Parameters
    ----------
    t_reading, reading : array_like, shape (n,)
        Stamps [s] and values of the readings.
    t_truth, truth : array_like, shape (m,)
        Stamps [s], increasing, and values of the ground truth, in the readings' unit.
    angle : bool
        Values are angles [rad]: the truth is unwrapped before it is interpolated and the
        error is wrapped to (-π, π].

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> reading_error([0.5, 2.0], [1.5, 0.0], [0.0, 1.0], [1.0, 2.0])
    array([ 0., nan])

    Across ±π: the truth goes from 3.1 to 3.1 + 0.1832 rad, the reading -3.1 rad is
    2π - 3.1 - 3.1916 = -0.0084 rad from it.

    >>> reading_error([0.5], [-3.1], [0.0, 1.0], [3.1, -3.0], angle=True).round(4)
    array([-0.0084])

    """
    stamps = np.asarray(t_reading, dtype=np.float64)
    values = np.asarray(reading, dtype=np.float64)
    truth_t = np.asarray(t_truth, dtype=np.float64)
    truth_v = np.asarray(truth, dtype=np.float64)
    if truth_t.size == 0:
        return np.full(stamps.shape, np.nan)
    if angle:
        truth_v = np.unwrap(truth_v)
    error = values - np.interp(stamps, truth_t, truth_v, left=np.nan, right=np.nan)
    return np.asarray(wrap_to_pi(error), dtype=np.float64) if angle else error


def normal_fit(samples: ArrayLike) -> tuple[float, float, int]:
    """
    Return the mean, the standard deviation (n - 1 divisor) and the count of finite samples.

    NaN for the statistics that need more samples (mean: one, deviation: two).

    >>> normal_fit([1.0, 3.0, float('nan')])
    (2.0, 1.4142135623730951, 2)
    """
    values = np.asarray(samples, dtype=np.float64).ravel()
    values = values[np.isfinite(values)]
    mean = float(np.mean(values)) if values.size else math.nan
    std = float(np.std(values, ddof=1)) if values.size > 1 else math.nan
    return mean, std, int(values.size)
