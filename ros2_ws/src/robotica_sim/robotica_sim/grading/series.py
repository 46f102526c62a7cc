"""
The time series of a recorded run: one loader for every command that reads a run's bag.

:func:`load_run` reads a rosbag2 directory (as ``robotica run`` and the ``recorder`` node write it)
with :func:`robotica_sim.bags.info.open_bag` and returns a :class:`RunSeries`: each known topic as
a :class:`Series` of float64 NumPy arrays, the reference path, the run as the bag records it (its
settings as run, its nodes and its scenario, from the metadata's ``custom_data``:
:mod:`robotica_sim.bags.run_record`) and the simulator's last status. ``robotica grade`` and
``robotica report`` compute from it, so that no other module decodes bags.

Times are seconds of simulated time: a message's header stamp (a topic whose stamps are all
zero, i.e. unstamped, falls back to its receive times); messages without a header
(``/cmd_vel``, ``/joint_torques``) use the bag's receive time; ``/clock`` its ``clock`` field.
Each series is in time order (stable sort by time when received out of order). Poses and
headings are REP-103 (x forward, y left, θ from the x axis, counter-clockwise); θ is the yaw
(z rotation) of the message's quaternion.

GPS fixes stay geodetic in their series; :func:`fixes_to_enu` turns them into the world's local
ENU frame at :func:`gps_origin`, the scenario's ``sensors.gps.origin`` (the GPS emulator's
origin, REP-103/105: x east, y north).

A run with a world (docs/world.md) also has its range sensors: the laser's ``/scan``, of which
at most :data:`MAX_SCANS` scans evenly spaced over the run are kept (a figure draws a few; an
hour of scans is not held in memory), and every reading of ``/sonar_<i>`` and
``/infrared_<i>``; the world's grid ``/map``; and the contacts of ``/bumper``.
:func:`run_world` builds the world to draw from the scenario's ``world:`` section (else
``/map``), :func:`sensor_mounts` gives each range topic's mount in ``base_link``.
"""
from dataclasses import dataclass, field
import math
from operator import attrgetter
from pathlib import Path
import re
from typing import Any, Callable, Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.trajectory.sampled_trajectory import trajectory_from_points
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.world.errors import WorldError
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.shapes import World
from robotica_kin.world.world_section import world_from_mapping
from robotica_sim.bags.info import BagError, open_bag
from robotica_sim.bags.run_record import custom_data, run_record, RunRecord

__all__ = ['MAX_SCANS', 'MSGTYPES', 'RANGE_MSGTYPE', 'RANGE_TOPIC', 'RunSeries', 'RunWorld',
           'Series', 'TOPICS', 'fixes_to_enu', 'gps_origin', 'load_run', 'run_world',
           'sensor_mounts']

TOPICS = {
    'clock': '/clock',
    'path': '/path',
    'truth': '/ground_truth/odom',
    'odom': '/odom',
    'cmd_vel': '/cmd_vel',
    'vehicle_command': '/vehicle_command',
    'tracking_error': '/path_tracker/tracking_error',
    'imu': '/imu/data',
    'compass': '/compass/heading',
    'gps': '/gps/fix',
    'joint_states': '/joint_states',
    'controller': '/joint_controller/controller_state',
    'trajectory': '/joint_controller/joint_trajectory',
    'torques': '/joint_torques',
    'status': '/simulator/status',
    'bumper': '/bumper',
    'scan': '/scan',
    'map': '/map',
    'force_control': '/joint_controller/force_control',
    'cartesian_control': '/joint_controller/cartesian_control',
}
"""The topics :func:`load_run` reads, by the role they play in a run."""

MSGTYPES = {
    'clock': 'rosgraph_msgs/msg/Clock',
    'path': 'nav_msgs/msg/Path',
    'truth': 'nav_msgs/msg/Odometry',
    'odom': 'nav_msgs/msg/Odometry',
    'cmd_vel': 'geometry_msgs/msg/Twist',
    'vehicle_command': 'robotica_msgs/msg/VehicleCommand',
    'tracking_error': 'robotica_msgs/msg/TrackingError',
    'imu': 'sensor_msgs/msg/Imu',
    'compass': 'sensor_msgs/msg/Imu',
    'gps': 'sensor_msgs/msg/NavSatFix',
    'joint_states': 'sensor_msgs/msg/JointState',
    'controller': 'robotica_msgs/msg/JointControllerState',
    'trajectory': 'trajectory_msgs/msg/JointTrajectory',
    'torques': 'std_msgs/msg/Float64MultiArray',
    'status': 'robotica_msgs/msg/SimulatorStatus',
    'bumper': 'robotica_msgs/msg/Contact',
    'scan': 'sensor_msgs/msg/LaserScan',
    'map': 'nav_msgs/msg/OccupancyGrid',
    'force_control': 'robotica_msgs/msg/ForceControlState',
    'cartesian_control': 'robotica_msgs/msg/CartesianControlState',
}
"""The message type each role's topic must have; a topic of another type is ignored."""

_LAST = ('clock', 'status', 'path', 'trajectory', 'map', 'force_control', 'cartesian_control')
"""The roles of which only the last message is read."""

RANGE_TOPIC = re.compile(r'/(sonar|infrared)_(\d+)')
"""The topics of the sonar ring and the infrared sensors (full match): kind and index i."""
RANGE_MSGTYPE = 'sensor_msgs/msg/Range'

MAX_SCANS = 256
"""At most this many laser scans are kept, evenly spaced over the run (by arrival): 256 of
361 beams are 0.7 MB, whether the run lasted 40 s or an hour."""


@dataclass(frozen=True)
class Series:
    """
    Samples of one topic: ``t`` [s] (n,) and named columns, each (n,) or (n, k).

    ``names`` holds the joint names of a joint series (k columns in joint order), else ().

    Examples
    --------
    >>> s = Series(np.array([0.0, 0.1]), {'v': np.array([1.0, 2.0])})
    >>> len(s), s['v'].tolist()
    (2, [1.0, 2.0])

    """

    t: NDArray[np.float64]
    columns: dict[str, NDArray[np.float64]]
    names: tuple[str, ...] = ()

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        """Return column ``name``; KeyError names the available columns."""
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f'no column {name!r}; available: {", ".join(self.columns)}') from None

    def __len__(self) -> int:
        """Return the number of samples."""
        return len(self.t)


@dataclass(frozen=True)
class RunSeries:
    """
    Everything :func:`load_run` reads from a run's bag; an absent topic gives None.

    Columns (units; poses in the frame of their message, REP-103):

    - ``truth`` (``/ground_truth/odom``) and ``odom`` (``/odom``): ``x``, ``y`` [m], ``theta``
      [rad], ``v``, ``vy`` [m/s] (twist in ``base_link``), ``w`` [rad/s]; ``odom`` also
      ``var_x``, ``var_y`` [m^2], ``var_theta`` [rad^2], the diagonal of its pose covariance.
    - ``cmd``: from ``/cmd_vel`` (``geometry_msgs/Twist``) ``v`` [m/s], ``w`` [rad/s]; from
      ``/vehicle_command`` ``v`` [m/s], ``steering`` [rad], ``steering_rate`` [rad/s].
    - ``tracking_error``: ``cross_track`` [m] (> 0 left of the path), ``heading`` [rad],
      ``along_track`` [m], ``target_x``, ``target_y`` [m].
    - ``imu``: ``wz`` [rad/s]; ``compass``: ``theta`` [rad], ``var_theta`` [rad^2];
      ``gps``: ``latitude``, ``longitude`` [deg], ``altitude`` [m], ``var_e``, ``var_n`` [m^2].
    - ``joint_states``: ``position`` [rad | m], ``velocity`` [rad/s | m/s], ``effort``
      [N m | N], each (n, joints); ``controller``: ``reference_position``,
      ``reference_velocity``, ``position_error`` (e = q_d - q, book (8.30)),
      ``velocity_error``, ``effort``, each (n, joints) (what the controller reports);
      ``reference``: ``position``, ``velocity`` (n, joints), the reference
      (``/joint_controller/joint_trajectory``) at the times of ``joint_states``: what the
      grading compares the simulator's joints with; ``torques``: ``effort`` (n, joints).
    - ``bumper`` (``/bumper``, a simulator with a world): ``in_contact`` (1.0 or 0.0) each
      step, ``x``, ``y`` [m] the contact point on the obstacle, world frame (NaN when free).
    - ``scans`` (``/scan``, sensor_msgs/LaserScan in the laser's frame): ``ranges`` (n, beams)
      [m] as published (REP-117: +-inf and NaN kept; a scan with fewer beams padded with NaN),
      ``angle_min``, ``angle_increment`` [rad], ``range_min``, ``range_max`` [m]; at most
      :data:`MAX_SCANS` scans, evenly spaced over the run.
    - ``ranges``: each ``/sonar_<i>`` and ``/infrared_<i>`` topic (sensor_msgs/Range) by name:
      ``range``, ``min_range``, ``max_range`` [m], every reading.
    - ``map_grid``: the last ``/map`` (nav_msgs/OccupancyGrid, latched) as an
      :class:`~robotica_kin.world.occupancy_grid.OccupancyGrid`.
    - ``path_headings``: the yaw [rad], in (-π, π], of the orientation of every pose of the
      last ``/path`` (N,), as ``path``'s rows (NaN where a quaternion is not finite): a plan's
      vehicle headings, or a planner's tangents, or identity orientations (0);
      :func:`~robotica_sim.grading.metrics.segment_directions` decides which. None without a
      ``/path``.
    - ``task_final``: the last step of a task-space law (``/joint_controller/force_control``
      or ``cartesian_control``) as arrays by field: a force law's ``position_reference``,
      ``position`` [m], ``force_reference``, ``force`` [N] (task axes, NaN where a reference is
      not used); a Cartesian law's ``error`` [m, rad], ``min_singular_value``.
    """

    bag: Path
    scenario: dict | None               # parsed custom_data 'robotica.scenario.yaml'
    duration: float                     # [s] last /clock (0 if none)
    counts: dict[str, int]              # messages per topic read (every topic of the bag)
    path: NDArray[np.float64] | None    # (N, 2) [m] /path positions, path frame
    path_times: NDArray[np.float64] | None  # (N,) [s] pose stamps if strictly increasing
    truth: Series | None
    odom: Series | None
    cmd: Series | None
    tracking_error: Series | None
    imu: Series | None
    compass: Series | None
    gps: Series | None
    joint_states: Series | None
    controller: Series | None
    torques: Series | None
    status: dict | None                 # last /simulator/status
    reference: Series | None = None     # the joint trajectory at the joint states' times
    msgtypes: dict[str, str] = field(default_factory=dict)  # type of every topic of the bag
    ignored: dict[str, str] = field(default_factory=dict)   # known topic of another type: why
    run: RunRecord = field(default_factory=RunRecord)       # the run's settings and nodes
    bumper: Series | None = None        # the simulator's contacts with the world
    scans: Series | None = None         # /scan, subsampled to at most MAX_SCANS
    ranges: dict[str, Series] = field(default_factory=dict)   # /sonar_<i>, /infrared_<i>
    map_grid: OccupancyGrid | None = None   # the last /map
    task_final: dict[str, NDArray[np.float64]] | None = None   # a task-space law's last step
    path_headings: NDArray[np.float64] | None = None   # (N,) [rad] yaw of each /path pose

    @property
    def path_end_heading(self) -> float | None:
        """
        Return the yaw [rad] of the last ``/path`` pose's orientation: the heading to end with.

        A parking plan's orientations are the vehicle's headings, also on reverse segments.
        None without a ``/path``, for one without poses or with a last orientation that is not
        finite (``path_headings[-1]`` otherwise).
        """
        headings = self.path_headings
        if headings is None or not len(headings) or not math.isfinite(headings[-1]):
            return None
        return float(headings[-1])

    @property
    def is_manipulator(self) -> bool:
        """Return whether this is an arm run: joint states and no ground-truth odometry."""
        return self.joint_states is not None and self.truth is None

    @property
    def scenario_name(self) -> str | None:
        """Return the name of the scenario that ran (None when the bag records none)."""
        name = self.run.name if self.run.name is not None else (self.scenario or {}).get('name')
        return None if name is None else str(name)


def _stamp(msg: Any) -> float:
    """Return the header stamp [s] of ``msg``."""
    stamp = msg.header.stamp
    return stamp.sec + stamp.nanosec * 1e-9


def _times(stamps: NDArray[np.float64], receive: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the stamps [s], or the receive times [s] when every stamp is zero (unstamped)."""
    return receive if not np.any(stamps) else stamps


def _yaw(q: Any) -> float:
    """Return the yaw [rad] (rotation about z) of a quaternion, in (-π, π]."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _odometry(msg: Any) -> tuple[float, ...]:
    pose, twist = msg.pose.pose, msg.twist.twist
    cov = msg.pose.covariance
    return (_stamp(msg), pose.position.x, pose.position.y, _yaw(pose.orientation),
            twist.linear.x, twist.linear.y, twist.angular.z, cov[0], cov[7], cov[35])


def _truth(msg: Any) -> tuple[float, ...]:
    return _odometry(msg)[:7]


def _twist(msg: Any) -> tuple[float, ...]:
    return 0.0, msg.linear.x, msg.angular.z   # no header: receive times


def _vehicle_command(msg: Any) -> tuple[float, ...]:
    return _stamp(msg), msg.speed, msg.steering_angle, msg.steering_rate


def _tracking_error(msg: Any) -> tuple[float, ...]:
    return (_stamp(msg), msg.cross_track, msg.heading, msg.along_track, msg.target_point.x,
            msg.target_point.y)


def _imu(msg: Any) -> tuple[float, ...]:
    return _stamp(msg), msg.angular_velocity.z


def _compass(msg: Any) -> tuple[float, ...]:
    return _stamp(msg), _yaw(msg.orientation), msg.orientation_covariance[8]


def _bumper(msg: Any) -> tuple[float, ...]:
    return _stamp(msg), float(msg.in_contact), msg.point.x, msg.point.y


def _range(msg: Any) -> tuple[float, ...]:
    return _stamp(msg), msg.range, msg.min_range, msg.max_range


def _gps(msg: Any) -> tuple[float, ...]:
    cov = msg.position_covariance   # ENU: [0] east, [4] north
    return _stamp(msg), msg.latitude, msg.longitude, msg.altitude, cov[0], cov[4]


# Scalar series: topic role -> (columns after the stamp, the row extractor).
_SCALAR: dict[str, tuple[tuple[str, ...], Callable[[Any], tuple[float, ...]]]] = {
    'truth': (('x', 'y', 'theta', 'v', 'vy', 'w'), _truth),
    'odom': (('x', 'y', 'theta', 'v', 'vy', 'w', 'var_x', 'var_y', 'var_theta'), _odometry),
    'cmd_vel': (('v', 'w'), _twist),
    'vehicle_command': (('v', 'steering', 'steering_rate'), _vehicle_command),
    'tracking_error': (('cross_track', 'heading', 'along_track', 'target_x', 'target_y'),
                       _tracking_error),
    'imu': (('wz',), _imu),
    'compass': (('theta', 'var_theta'), _compass),
    'gps': (('latitude', 'longitude', 'altitude', 'var_e', 'var_n'), _gps),
    'bumper': (('in_contact', 'x', 'y'), _bumper),
}
_RANGE_COLUMNS = ('range', 'min_range', 'max_range')
_NAN_ALLOWED = {'bumper': ('x', 'y')}   # NaN when the robot is free

# Joint series: topic role -> (column -> message field).
_JOINT_FIELDS = {
    'joint_states': {'position': 'position', 'velocity': 'velocity', 'effort': 'effort'},
    'controller': {name: name for name in ('reference_position', 'reference_velocity',
                                           'position_error', 'velocity_error', 'effort')},
    'torques': {'effort': 'data'},
}


_Columns = dict[str, NDArray[np.float64]]

MAX_VALUE = 1e9
"""The largest magnitude of a value of a run (a pose [m], an angle [rad], a speed, a joint
value, a torque [SI]): beyond it, or not finite, the value is corrupt (no robot of the book
comes near; robotica_kin.bounds caps what nodes take far below it), and a metric or a figure
of it would overflow or be meaningless. GPS fixes and variances are not checked: a receiver
without a fix sends NaN, which the figures and metrics handle."""


def _corrupt(values: NDArray[np.float64], nan_allowed: bool) -> NDArray[np.bool_]:
    """Return where ``values`` are beyond :data:`MAX_VALUE` (inf too) or, if not allowed, NaN."""
    with np.errstate(invalid='ignore'):
        beyond = np.abs(values) > MAX_VALUE   # NaN compares False
    return beyond if nan_allowed else beyond | np.isnan(values)


def _check_values(path: Path, series: dict[str, 'Series | None'],
                  path_points: NDArray[np.float64] | None) -> None:
    """Raise BagError when a series of the run holds a corrupt value (see MAX_VALUE)."""
    checked: list[tuple[str, NDArray[np.float64], bool]] = []
    for role, samples in series.items():
        if samples is None or role == 'gps':
            continue
        # Times are not checked (a wall-clock stamp is 1.7e9 s). A joint series pads a
        # message with fewer joints than the first with NaN.
        checked += [(TOPICS[role], column,
                     role in _JOINT_FIELDS or name in _NAN_ALLOWED.get(role, ()))
                    for name, column in samples.columns.items() if not name.startswith('var_')]
    if path_points is not None:
        checked.append((TOPICS['path'], path_points, False))
    for topic, values, nan_allowed in checked:
        bad = _corrupt(values, nan_allowed)
        if np.any(bad):
            raise BagError(f'{path}: {topic} holds values no run can have (e.g. '
                           f'{values[bad].flat[0]:g}; not finite or beyond +-{MAX_VALUE:g}): '
                           'it cannot be graded or drawn')


def _in_time_order(t: NDArray[np.float64],
                   columns: _Columns) -> tuple[NDArray[np.float64], _Columns]:
    """Return ``t`` and ``columns`` sorted by time (stable), as received when already sorted."""
    if len(t) < 2 or bool(np.all(np.diff(t) >= 0.0)):
        return t, columns
    order = np.argsort(t, kind='stable')
    return t[order], {name: value[order] for name, value in columns.items()}


def _scalar_series(rows: list[tuple[float, ...]], receive: list[int],
                   columns: tuple[str, ...]) -> Series:
    data = np.array(rows, dtype=np.float64).reshape(len(rows), len(columns) + 1)
    t = _times(data[:, 0].copy(), np.array(receive, dtype=np.float64) * 1e-9)
    return Series(*_in_time_order(t, {name: data[:, i + 1].copy()
                                      for i, name in enumerate(columns)}))


def _joint_matrix(rows: tuple[Any, ...]) -> NDArray[np.float64]:
    """Stack per-message arrays into (n, k); ragged rows are padded with NaN."""
    widths = set(map(len, rows))
    if len(widths) <= 1:
        return np.array(rows, dtype=np.float64).reshape(len(rows), widths.pop() if widths else 0)
    out = np.full((len(rows), max(widths)), np.nan)
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
    return out


def _joint_series(role: str, msgs: list[tuple[Any, int]]) -> Series:
    """Build a joint series, reordering every message to the first message's joint order."""
    attrs = _JOINT_FIELDS[role]
    get = attrgetter(*attrs.values())
    rows = [get(msg) for msg, _ in msgs]
    if len(attrs) == 1:   # attrgetter of one name returns the value itself
        rows = [(row,) for row in rows]
    matrices = {column: _joint_matrix(values) for column, values in zip(attrs, zip(*rows))}
    receive = np.array([r for _, r in msgs], dtype=np.float64) * 1e-9
    if role == 'torques':   # std_msgs/Float64MultiArray: no header, no names
        return Series(*_in_time_order(receive, matrices))
    names_field = 'name' if role == 'joint_states' else 'joint_names'
    names = list(getattr(msgs[0][0], names_field))
    for i, (msg, _) in enumerate(msgs):
        msg_names = getattr(msg, names_field)
        if msg_names != names and sorted(msg_names) == sorted(names):
            order = [msg_names.index(n) for n in names]
            for matrix in matrices.values():
                if matrix.shape[1] == len(order):
                    matrix[i] = matrix[i, order]
    stamps = np.array([_stamp(msg) for msg, _ in msgs], dtype=np.float64)
    t, columns = _in_time_order(_times(stamps, receive), matrices)
    return Series(t, columns, tuple(names))


def _joint_reference(msg: Any, states: Series | None,
                     trial_period: float = 0.0) -> Series | None:
    """
    Return the joint reference at the joint states' times, or None without one of the two.

    The trajectory is interpolated as the joint controller does it
    (:func:`robotica_ctrl.trajectory.sampled_trajectory.trajectory_from_points`); stamped 0 it
    starts at the first joint state, else at its stamp; with a ``trial_period`` [s] > 0 it
    restarts every trial (iterative learning), as the controller restarts it. None too for a
    trajectory that does not name the states' joints or is not one (the controller refused it
    as well).
    """
    if msg is None or states is None or len(states) == 0:
        return None
    try:
        trajectory = trajectory_from_points(msg.joint_names, msg.points, list(states.names))
    except ValueError:
        return None
    stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
    start = stamp if stamp > 0.0 else float(states.t[0])
    elapsed = states.t - start
    if trial_period > 0.0:
        elapsed = elapsed - np.floor(elapsed / trial_period + 1e-9) * trial_period
    samples = [trajectory.sample(t) for t in elapsed]
    return Series(states.t, {'position': np.array([s.q_d for s in samples]),
                             'velocity': np.array([s.qd_d for s in samples])}, states.names)


def _task_final(decoded: dict[str, Any]) -> dict[str, NDArray[np.float64]] | None:
    """Return the last step of a task-space law by field (RunSeries.task_final), or None."""
    if 'force_control' in decoded:
        msg = decoded['force_control']
        return {name: np.asarray(getattr(msg, name), dtype=np.float64) for name in
                ('position_reference', 'position', 'force_reference', 'force')}
    if 'cartesian_control' in decoded:
        msg = decoded['cartesian_control']
        return {'error': np.asarray(msg.error, dtype=np.float64),
                'min_singular_value': np.array(msg.min_singular_value)}
    return None


def _trial_period(scenario: dict | None) -> float:
    """Return the scenario's ``controller.trial_period`` [s], 0 when it has none."""
    controller = (scenario or {}).get('controller')
    value = controller.get('trial_period', 0.0) if isinstance(controller, dict) else 0.0
    return float(value) if isinstance(value, (int, float)) and value > 0.0 else 0.0


def _scan_series(msgs: list[tuple[Any, int]]) -> Series:
    """Return the scans of sensor_msgs/LaserScan messages (see :class:`RunSeries`)."""
    stamps = np.array([_stamp(msg) for msg, _ in msgs], dtype=np.float64)
    receive = np.array([r for _, r in msgs], dtype=np.float64) * 1e-9
    columns = {name: np.array([getattr(msg, name) for msg, _ in msgs], dtype=np.float64)
               for name in ('angle_min', 'angle_increment', 'range_min', 'range_max')}
    columns['ranges'] = _joint_matrix(tuple(np.asarray(msg.ranges, dtype=np.float64)
                                            for msg, _ in msgs))
    return Series(*_in_time_order(_times(stamps, receive), columns))


def _grid(msg: Any) -> OccupancyGrid | None:
    """Return a nav_msgs/OccupancyGrid as an OccupancyGrid; None if it is not a valid one."""
    info = msg.info
    try:
        data = np.asarray(msg.data, dtype=np.int8).reshape(info.height, info.width)
        origin = (info.origin.position.x, info.origin.position.y, _yaw(info.origin.orientation))
        return OccupancyGrid(data, info.resolution, origin)
    except (ValueError, WorldError):   # a size that is not width x height, bad cells
        return None


def _path(msg: Any) -> tuple[NDArray[np.float64], NDArray[np.float64] | None,
                             NDArray[np.float64]]:
    """
    Return a nav_msgs/Path's positions (N, 2) [m], its stamps if increasing, its headings (N,).

    The headings [rad] are the yaws of the poses' orientations (a parking plan's vehicle
    headings, which on a reverse segment point against the travel), NaN where an orientation
    is not finite.
    """
    points = np.array([[p.pose.position.x, p.pose.position.y] for p in msg.poses],
                      dtype=np.float64).reshape(-1, 2)
    stamps = np.array([p.header.stamp.sec + p.header.stamp.nanosec * 1e-9 for p in msg.poses],
                      dtype=np.float64)
    timed = len(stamps) >= 2 and bool(np.all(np.diff(stamps) > 0.0))
    headings = np.array([_yaw(p.pose.orientation) for p in msg.poses], dtype=np.float64)
    return points, stamps if timed else None, headings


def load_run(bag: str | Path, topics: Iterable[str] | None = None) -> RunSeries:
    """
    Read a run's bag; only the listed topics if given (``/clock`` is always read).

    Parameters
    ----------
    bag : str or Path
        The rosbag2 directory (``metadata.yaml`` and its MCAP file).
    topics : iterable of str, optional
        Topic names among :data:`TOPICS`'s values and range topics (:data:`RANGE_TOPIC`);
        the others come back as None.

    Returns
    -------
    RunSeries

    Raises
    ------
    BagError
        If ``bag`` is not a readable bag (see :func:`robotica_sim.bags.info.open_bag`), its
        data cannot be read or decoded, it holds no message, or a value no run can have
        (:data:`MAX_VALUE`).
    ValueError
        If ``topics`` names a topic that :func:`load_run` does not know.

    """
    path = Path(bag)
    roles_by_topic = {topic: role for role, topic in TOPICS.items()}
    for_ranges: set[str] = set()
    if topics is not None:
        wanted = set(topics)
        unknown = sorted(t for t in wanted - set(roles_by_topic)
                         if not RANGE_TOPIC.fullmatch(t))
        if unknown:
            raise ValueError(f'unknown topics {unknown}; known: {", ".join(TOPICS.values())}')
        wanted.add(TOPICS['clock'])
        roles_by_topic = {t: r for t, r in roles_by_topic.items() if t in wanted}
        for_ranges = {t for t in wanted if RANGE_TOPIC.fullmatch(t)}
    reader = open_bag(path)
    try:
        # Counted as read, not taken from metadata.yaml (which may not describe the data).
        counts = {c.topic: 0 for c in reader.connections}
        msgtypes = {c.topic: c.msgtype for c in reader.connections}
        for c in reader.connections:   # /sonar_<i>, /infrared_<i>: every one, or those wanted
            if RANGE_TOPIC.fullmatch(c.topic) and (topics is None or c.topic in for_ranges):
                roles_by_topic[c.topic] = 'range'
        expected = {topic: MSGTYPES.get(role, RANGE_MSGTYPE)
                    for topic, role in roles_by_topic.items()}
        connections = [c for c in reader.connections if c.topic in roles_by_topic
                       and c.msgtype == expected[c.topic]]
        ignored = {c.topic: f'it has type {c.msgtype}, not {expected[c.topic]}'
                   for c in reader.connections
                   if c.topic in roles_by_topic and c not in connections}
        rows: dict[str, list[tuple[float, ...]]] = {role: [] for role in _SCALAR}
        receive_times: dict[str, list[int]] = {role: [] for role in _SCALAR}
        joint_msgs: dict[str, list[tuple[Any, int]]] = {role: [] for role in _JOINT_FIELDS}
        range_rows: dict[str, list[tuple[float, ...]]] = {}
        range_receive: dict[str, list[int]] = {}
        kept_scans: list[tuple[Any, bytes, int]] = []   # every stride-th scan, in arrival
        scans_seen, stride = 0, 1
        last: dict[str, tuple[Any, bytes]] = {}
        decoded_ids = {c.id for c in connections}
        for connection, receive, raw in reader.messages():
            counts[connection.topic] += 1
            if connection.id not in decoded_ids:
                continue
            role = roles_by_topic[connection.topic]
            if role in _LAST:   # the last matters
                last[role] = (connection, raw)
                continue
            if role == 'scan':   # keep every stride-th; past MAX_SCANS, every other one
                if scans_seen % stride == 0:
                    kept_scans.append((connection, raw, receive))
                    if len(kept_scans) > MAX_SCANS:
                        kept_scans, stride = kept_scans[::2], 2 * stride
                scans_seen += 1
                continue
            msg = reader.deserialize(raw, connection.msgtype)
            if role == 'range':
                range_rows.setdefault(connection.topic, []).append(_range(msg))
                range_receive.setdefault(connection.topic, []).append(receive)
            elif role in _SCALAR:
                rows[role].append(_SCALAR[role][1](msg))
                receive_times[role].append(receive)
            else:
                joint_msgs[role].append((msg, receive))
        decoded: dict[str, Any] = {role: reader.deserialize(raw, c.msgtype)
                                   for role, (c, raw) in last.items()}
        scan_msgs = [(reader.deserialize(raw, c.msgtype), receive)
                     for c, raw, receive in kept_scans]
    except Exception as err:   # rosbags raises its own errors, struct and decoding errors
        raise BagError(f'{path}: cannot read the bag: {err}') from None
    finally:
        reader.close()
    if not any(counts.values()):
        raise BagError(f'{path}: the bag holds no message (its recorder received nothing)')
    record = run_record(custom_data(path))
    series = {role: _scalar_series(r, receive_times[role], _SCALAR[role][0]) if r else None
              for role, r in rows.items()}
    joints = {role: _joint_series(role, m) if m else None for role, m in joint_msgs.items()}
    duration = 0.0
    if 'clock' in decoded:
        clock = decoded['clock'].clock
        duration = clock.sec + clock.nanosec * 1e-9
    path_points = path_times = path_headings = None
    if 'path' in decoded:
        path_points, path_times, path_headings = _path(decoded['path'])
    _check_values(path, {**series, **joints}, path_points)
    status = None
    if 'status' in decoded:
        s = decoded['status']
        status = {'step': int(s.step), 'real_time_factor': float(s.real_time_factor),
                  'lockstep_timeouts': int(s.lockstep_timeouts),
                  'stale_command_stops': int(s.stale_command_stops),
                  'finished': bool(s.finished)}
    return RunSeries(
        bag=path, scenario=record.scenario or None, run=record, duration=duration, counts=counts,
        path=path_points, path_times=path_times, truth=series['truth'], odom=series['odom'],
        cmd=series['cmd_vel'] if series['cmd_vel'] is not None else series['vehicle_command'],
        tracking_error=series['tracking_error'], imu=series['imu'], compass=series['compass'],
        gps=series['gps'], joint_states=joints['joint_states'], controller=joints['controller'],
        reference=_joint_reference(decoded.get('trajectory'), joints['joint_states'],
                                   _trial_period(record.scenario)),
        torques=joints['torques'], status=status, msgtypes=msgtypes, ignored=ignored,
        bumper=series['bumper'], scans=_scan_series(scan_msgs) if scan_msgs else None,
        ranges={topic: _scalar_series(rows, range_receive[topic], _RANGE_COLUMNS)
                for topic, rows in sorted(range_rows.items(), key=lambda i: _range_key(i[0]))},
        map_grid=_grid(decoded['map']) if 'map' in decoded else None,
        task_final=_task_final(decoded), path_headings=path_headings)


def _range_key(topic: str) -> tuple[str, int]:
    """Return (kind, index) of a range topic, to order /sonar_2 before /sonar_10."""
    match = RANGE_TOPIC.fullmatch(topic)
    return (match.group(1), int(match.group(2))) if match else (topic, 0)


def gps_origin(scenario: dict | None) -> GeodeticOrigin:
    """
    Return the geodetic origin of the world's ENU frame: the scenario's ``sensors.gps.origin``.

    The origin the GPS emulator was given (latitude, longitude [deg], height [m]); the
    scenario default (:class:`robotica_sim.runs.scenario.GpsSpec`) when the scenario has none.

    Raises
    ------
    ValueError
        If the scenario's origin is not three numbers in range.

    Examples
    --------
    >>> gps_origin({'sensors': {'gps': {'origin': [40.0, -3.7, 650.0]}}}).latitude_deg
    40.0

    """
    origin: Any = None
    sensors = (scenario or {}).get('sensors')
    if isinstance(sensors, dict) and isinstance(sensors.get('gps'), dict):
        origin = sensors['gps'].get('origin')
    if origin is None:
        # Imported here: robotica_sim.runs.scenario loads SciPy (through the gyro model), seconds
        # that a report without GPS, or with the origin in its scenario, need not spend.
        from robotica_sim.runs.scenario import GpsSpec
        origin = GpsSpec().origin
    if not isinstance(origin, (list, tuple)) or len(origin) != 3:
        raise ValueError(f'sensors.gps.origin must be [latitude, longitude, height], '
                         f'got {origin!r}')
    return GeodeticOrigin(*(float(v) for v in origin))


def fixes_to_enu(origin: GeodeticOrigin, latitude: ArrayLike, longitude: ArrayLike,
                 altitude: ArrayLike) -> NDArray[np.float64]:
    """
    Return GPS fixes (latitude, longitude [deg], height [m]) as ENU positions [m] at ``origin``.

    Fixes without a valid position (NaN, as a receiver without a fix may send, or a latitude
    outside [-90, 90] deg) give NaN rows instead of an error.

    Returns
    -------
    ndarray, shape (n, 3)
        (east, north, up) [m], REP-103 x east, y north.

    Examples
    --------
    >>> origin = GeodeticOrigin(37.41, -6.0, 10.0)
    >>> fixes_to_enu(origin, [37.41, float('nan')], [-6.0, 0.0], [12.0, 0.0]).round(6)
    array([[0., 0., 2.],
           [nan, nan, nan]])

    """
    fixes = np.column_stack([np.asarray(v, dtype=np.float64).ravel()
                             for v in (latitude, longitude, altitude)])
    valid = np.all(np.isfinite(fixes), axis=1) & (np.abs(fixes[:, 0]) <= 90.0)
    enu = np.full(fixes.shape, np.nan)
    if valid.any():
        enu[valid] = np.reshape(origin.geodetic_to_enu(*fixes[valid].T), (-1, 3))
    return enu


@dataclass(frozen=True)
class RunWorld:
    """The world of a run, to draw: its obstacles and what could not be drawn (``note``)."""

    world: World
    source: str      # where it comes from: "the scenario's world: section", "/map", ...
    note: str = ''   # e.g. the scenario's map file could not be loaded, so /map is drawn


def run_world(run: RunSeries) -> RunWorld | None:
    """
    Return the world the run ran in, or None for a run without one.

    The scenario's ``world:`` section
    (:func:`robotica_kin.world.world_section.world_from_mapping`). Its ``map:`` file is
    relative to the scenario's folder, which the bag does not record: it is looked for beside
    the bag and in the bag's parent folder (``runs/<run>/``). When it is not
    found (or not valid), the grid the run published on ``/map`` takes its place, or, without
    one, only the geometric obstacles are drawn; ``note`` says so. A run whose scenario has no
    world but whose bag has ``/map`` gets that grid. Never raises for a bad world: the note says
    why nothing is drawn.

    >>> run = RunSeries(Path('b'), {'world': {'walls': [[0, 0, 1, 0]]}}, 0.0, {}, *[None] * 13)
    >>> run_world(run).world.walls.tolist()
    [[0.0, 0.0, 1.0, 0.0]]

    """
    section = (run.scenario or {}).get('world')
    if section is None:
        if run.map_grid is None:
            return None
        return RunWorld(World(grid=run.map_grid), '/map')
    source = "the scenario's world: section"
    if not isinstance(section, dict) or 'map' not in section:
        try:
            return RunWorld(world_from_mapping(section, Path()), source)
        except WorldError as err:
            return _bad_world(run, str(err))
    errors = []
    for folder in (run.bag.parent, run.bag.parent.parent):
        try:
            return RunWorld(world_from_mapping(section, folder), source)
        except WorldError as err:
            errors.append(str(err))
    geometry = {key: value for key, value in section.items() if key != 'map'}
    try:
        world = world_from_mapping(geometry, Path())
    except WorldError as err:
        return _bad_world(run, str(err))
    missing = f'the map file {section["map"]!r} could not be loaded ({errors[0]})'
    if run.map_grid is not None:
        return RunWorld(World(walls=world.walls, circles=world.circles,
                              polygons=world.polygons, grid=run.map_grid),
                        f'{source} and /map', f'{missing}; its grid is the one the run '
                        'published on /map')
    return RunWorld(world, source, f'{missing} and the bag has no /map: only the walls, '
                    'polygons and circles are drawn')


def _bad_world(run: RunSeries, error: str) -> RunWorld | None:
    """Return /map as the world when the scenario's world: section is not valid, else None."""
    if run.map_grid is None:
        return None
    return RunWorld(World(grid=run.map_grid), '/map',
                    f"the scenario's world: section is not valid ({error}); /map is drawn")


def sensor_mounts(scenario: dict | None, kind: str) -> NDArray[np.float64]:
    """
    Return the mounts (k, 3) (x [m], y [m], yaw [rad] in ``base_link``) of a kind of sensor.

    ``kind`` is ``'laser'`` (``sensors.laser.mount``, default (0, 0, 0)), ``'sonar'`` or
    ``'infrared'`` (``sensors.<kind>.mounts``, default
    :data:`robotica_sim.sensors.sonar.SONAR_MOUNTS`,
    :data:`robotica_sim.sensors.infrared.INFRARED_MOUNTS`): row i is the sensor of topic
    ``/<kind>_<i>`` (the laser's ``/scan``). Mounts that are not numbers in triples give (0, 3).

    >>> sensor_mounts({'sensors': {'sonar': {'mounts': [0.2, 0.0, 0.0]}}}, 'sonar').tolist()
    [[0.2, 0.0, 0.0]]
    >>> sensor_mounts(None, 'laser').tolist()
    [[0.0, 0.0, 0.0]]

    """
    sensors = (scenario or {}).get('sensors')
    spec = sensors.get(kind) if isinstance(sensors, dict) else None
    key = 'mount' if kind == 'laser' else 'mounts'
    mounts = spec.get(key) if isinstance(spec, dict) else None
    if mounts is None:
        if kind == 'laser':
            mounts = (0.0, 0.0, 0.0)
        elif kind == 'sonar':
            from robotica_sim.sensors.sonar import SONAR_MOUNTS
            mounts = SONAR_MOUNTS
        elif kind == 'infrared':
            from robotica_sim.sensors.infrared import INFRARED_MOUNTS
            mounts = INFRARED_MOUNTS
        else:
            raise ValueError(f"kind must be 'laser', 'sonar' or 'infrared', got {kind!r}")
    try:
        values = np.asarray(mounts, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        return np.zeros((0, 3))
    if values.size % 3 or not np.all(np.isfinite(values)):
        return np.zeros((0, 3))
    return values.reshape(-1, 3)
