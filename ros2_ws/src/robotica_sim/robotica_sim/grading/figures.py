"""
The figures of ``robotica report``: one function per figure, drawn into a Matplotlib figure.

Each public ``name(fig, ...)`` draws one figure of a run's time series
(:class:`robotica_sim.grading.series.RunSeries`) into a :class:`matplotlib.figure.Figure` and
returns its caption (plain text, with the figure's statistics); which figures a run gets, the
files and the page are :mod:`robotica_sim.grading.report`'s. :func:`auto_robot_every` and
:func:`robot_poses` choose where the robot is drawn on the trajectory. The figures:

* mobile robot: ``trajectory`` (the reference path, the true trajectory and the ``/odom``
  estimate in the x-y plane of the path frame, equal axes, the robot drawn every
  ``robot_every`` s; in a run with a world, also the world, the range readings at intervals
  (:func:`laser_points`, :func:`range_beam`) and the contacts), ``tracking_errors``
  (cross-track and heading errors of the ground truth against ``/path`` by
  :func:`robotica_sim.grading.metrics.truth_path_errors`, the projection ``robotica grade`` uses,
  beside the tracker's own ``/path_tracker/tracking_error``),
  ``commands``, ``estimation`` (``/odom`` minus truth with the ±3σ band of its covariance)
  and one figure per sensor, ``gyro``, ``compass``, ``gps``: the reading against the truth
  and a histogram of the reading's error with its fitted normal density;
* manipulator (book ch. 8): ``joint_positions``, ``joint_velocities``, ``joint_torques`` and
  ``joint_errors`` (e = q_d - q, book (8.30)), one panel per joint;
* a sweep (``robotica sweep``): ``sweep_metric``, a metric against the varied value.

The numbers come from the grading core: a sensor's error is
:func:`~robotica_sim.grading.metrics.reading_error` (the reading minus the truth interpolated
at its stamp; angles wrapped to (-π, π]), its fit
:func:`~robotica_sim.grading.metrics.normal_fit`, every RMS
:func:`~robotica_sim.grading.metrics.rms` (over the finite samples: a reading outside the
truth's time span has no error). GPS fixes enter the world frame as the local ENU frame of the
scenario's ``sensors.gps.origin`` (:func:`~robotica_sim.grading.series.fixes_to_enu`).
Units are SI, angles in radians, headings REP-103 (θ from the x axis, counter-clockwise).
Matplotlib is imported only when a figure is drawn, never at import.
"""
import math
from typing import Any, Optional, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.geodetic import GeodeticOrigin
from robotica_sim.grading.metrics import (max_abs, MetricParams, normal_fit, reading_error,
                                          rms, truth_path_errors)
from robotica_sim.grading.series import (fixes_to_enu, RANGE_TOPIC, run_world, RunSeries,
                                         RunWorld, sensor_mounts, Series)

if TYPE_CHECKING:   # Matplotlib is imported lazily, when figures are drawn
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ['DPI', 'FIGURE_SIZE', 'auto_robot_every', 'commands', 'compass', 'estimation', 'gps',
           'gyro', 'joint_errors', 'joint_figure', 'joint_torques', 'laser_points',
           'range_beam', 'robot_poses', 'scan_every', 'sweep_metric', 'tracking_errors',
           'trajectory']

DPI = 100                     # [dots per inch] of the PNG files
FIGURE_SIZE = (8.0, 5.0)      # [in] width, height of a figure
PANEL_HEIGHT = 1.9            # [in] per row of joint panels beyond two rows
ROBOT_MARKS = 15              # at most this many intervals between robot poses (automatic)
ROBOT_EVERY_STEPS = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0, 600.0)  # [s]
ROBOT_SIZE = 0.035            # length of the robot's triangle / larger span of the x-y plot
SCAN_MARKS = 10              # range readings drawn at about this many times over a run
SCAN_MARKS_MAX = 12          # ... at the robot's times when they are at most this many
RANGE_TOLERANCE = 1.0        # [s] a Range reading is drawn within this of its time
WORLD_COLOUR = '0.3'
GRID_RGBA = (0.45, 0.45, 0.45, 0.85)      # occupied cells
UNKNOWN_RGBA = (0.8, 0.8, 0.8, 0.35)      # unknown cells
HISTOGRAM_BINS = 40
HISTOGRAM_HEADROOM = 1.35    # y range / highest bar, for the legend


# --- the robot on the trajectory ----------------------------------------------------------

def auto_robot_every(duration: float) -> float:
    """
    Return the period [s] at which the robot is drawn over a run of ``duration`` [s].

    The shortest of :data:`ROBOT_EVERY_STEPS` that draws at most :data:`ROBOT_MARKS` intervals.

    >>> auto_robot_every(10.0), auto_robot_every(30.0), auto_robot_every(60.0)
    (1.0, 2.0, 5.0)
    """
    for step in ROBOT_EVERY_STEPS:
        if duration / step <= ROBOT_MARKS:
            return step
    return ROBOT_EVERY_STEPS[-1]


def scan_every(duration: float, robot_every: float) -> float:
    """
    Return the period [s] at which range readings are drawn over a run of ``duration`` [s].

    The robot's period ``robot_every`` when it gives at most :data:`SCAN_MARKS_MAX`
    intervals (the readings drawn where the robot is), else the shortest of
    :data:`ROBOT_EVERY_STEPS` that gives at most :data:`SCAN_MARKS`.

    >>> scan_every(40.0, 5.0), scan_every(40.0, 0.5), scan_every(600.0, 60.0)
    (5.0, 5.0, 60.0)
    """
    if robot_every > 0.0 and duration / robot_every <= SCAN_MARKS_MAX:
        return robot_every
    for step in ROBOT_EVERY_STEPS:
        if duration / step <= SCAN_MARKS:
            return step
    return ROBOT_EVERY_STEPS[-1]


def footprint_polygon(scenario: dict | None) -> NDArray[np.float64] | None:
    """
    Return the scenario's ``robot.footprint_polygon`` as (v, 2) [m] in base_link, else None.

    >>> footprint_polygon({'robot': {'footprint_polygon': [0, 0, 1, 0, 1, 1]}}).shape
    (3, 2)
    >>> footprint_polygon({'robot': {}}) is None
    True
    """
    values = ((scenario or {}).get('robot') or {}).get('footprint_polygon')
    try:
        polygon = np.asarray(values, dtype=np.float64).reshape(-1, 2)
    except (TypeError, ValueError):
        return None
    return polygon if len(polygon) >= 3 and np.isfinite(polygon).all() else None


def robot_poses(t: ArrayLike, x: ArrayLike, y: ArrayLike, theta: ArrayLike,
                every: float) -> NDArray[np.float64]:
    """
    Return the poses (x [m], y [m], θ [rad]) sampled at t0, t0 + every, ... <= t_end.

    Each pose is the first sample at or after its time; ``t`` [s] must be non-decreasing.

    Returns
    -------
    ndarray, shape (k, 3)
        The poses, k = floor((t_end - t0) / every) + 1; (0, 3) for no samples.

    Raises
    ------
    ValueError
        If ``every`` is not > 0 s.

    Examples
    --------
    >>> robot_poses([0.0, 0.5, 1.0, 1.5], [0, 1, 2, 3], [0, 0, 0, 0], [0, 0, 1, 1], 1.0)
    array([[0., 0., 0.],
           [2., 0., 1.]])

    """
    if not every > 0.0:
        raise ValueError(f'every must be > 0 s, got {every!r}')
    times = np.asarray(t, dtype=np.float64)
    poses = np.column_stack([np.asarray(v, dtype=np.float64) for v in (x, y, theta)])
    if times.size == 0:
        return np.zeros((0, 3))
    marks = np.arange(times[0], times[-1] + 1e-9 * max(1.0, abs(times[-1])), every)
    index = np.minimum(np.searchsorted(times, marks - 1e-9), times.size - 1)
    return poses[index]


# --- range readings in the map frame ---------------------------------------------------------

def _sensor_pose(pose: ArrayLike, mount: ArrayLike) -> tuple[float, float, float]:
    """Return the sensor's (x, y, yaw) in the map frame: ``pose`` composed with ``mount``."""
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64).ravel()[:3])
    mx, my, myaw = (float(v) for v in np.asarray(mount, dtype=np.float64).ravel()[:3])
    c, s = math.cos(theta), math.sin(theta)
    return x + c * mx - s * my, y + s * mx + c * my, theta + myaw


def laser_points(ranges: ArrayLike, angle_min: float, angle_increment: float,
                 range_min: float, range_max: float, pose: ArrayLike,
                 mount: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
    """
    Return the returns (k, 2) [m] of a LaserScan in the map frame.

    Beam i has angle ``angle_min + i angle_increment`` [rad] in the laser's frame, which sits at
    ``mount`` (x [m], y [m], yaw [rad]) in ``base_link``, at the robot's ``pose`` (x, y, θ) in
    the map frame. Only valid readings become points: REP-117's +-inf and NaN, and any range
    outside [``range_min``, ``range_max``] (sensor_msgs/LaserScan), are left out.

    >>> laser_points([1.0, float('inf'), 2.0], -1.5707963267948966, 1.5707963267948966,
    ...              0.1, 5.0, [1.0, 0.0, 1.5707963267948966], [0.5, 0.0, 0.0]).round(9) + 0.0
    array([[ 2. ,  0.5],
           [-1. ,  0.5]])
    """
    r = np.asarray(ranges, dtype=np.float64).ravel()
    with np.errstate(invalid='ignore'):
        valid = np.isfinite(r) & (r >= range_min) & (r <= range_max)
    x, y, yaw = _sensor_pose(pose, mount)
    angles = yaw + angle_min + angle_increment * np.flatnonzero(valid)
    return np.column_stack([x + r[valid] * np.cos(angles), y + r[valid] * np.sin(angles)])


def range_beam(reading: float, pose: ArrayLike, mount: ArrayLike) -> NDArray[np.float64]:
    """
    Return the beam (2, 2) [m] of a Range reading in the map frame: sensor, then the echo.

    The sensor sits at ``mount`` (x [m], y [m], yaw [rad]) in ``base_link``, the robot at
    ``pose`` (x, y, θ) in the map frame; the echo lies ``reading`` [m] along the beam's axis.

    >>> range_beam(0.5, [1.0, 1.0, 0.0], [0.2, 0.0, 1.5707963267948966]).round(9) + 0.0
    array([[1.2, 1. ],
           [1.2, 1.5]])
    """
    x, y, yaw = _sensor_pose(pose, mount)
    return np.array([[x, y], [x + reading * math.cos(yaw), y + reading * math.sin(yaw)]])


def _pose_at(truth: Series, t: float) -> Optional[NDArray[np.float64]]:
    """Return the true pose (3,) at ``t`` [s] (linear; θ unwrapped), None outside its span."""
    if not len(truth) or not truth.t[0] - 1e-9 <= t <= truth.t[-1] + 1e-9:
        return None
    theta = np.unwrap(truth['theta'])
    return np.array([np.interp(t, truth.t, truth['x']), np.interp(t, truth.t, truth['y']),
                     np.interp(t, truth.t, theta)])


def _nearest(times: NDArray[np.float64], t: float) -> int:
    """Return the index of the time nearest ``t`` in the sorted, non-empty ``times``."""
    k = int(np.searchsorted(times, t))
    if k == 0:
        return 0
    if k == len(times) or t - times[k - 1] <= times[k] - t:
        return k - 1
    return k


# --- drawing helpers ----------------------------------------------------------------------

def _finite(values: ArrayLike) -> NDArray[np.float64]:
    """Return the finite samples of ``values``, flattened (NaN: no error at that stamp)."""
    flat = np.asarray(values, dtype=np.float64).ravel()
    return flat[np.isfinite(flat)]


def _rms_max(values: ArrayLike) -> tuple[float, float]:
    """Return the RMS and the largest |value| of the finite samples; NaN, NaN if none."""
    finite = _finite(values)
    if finite.size == 0:
        return math.nan, math.nan
    return rms(finite), max_abs(finite)


def _stats_text(name: str, values: ArrayLike, unit: str) -> str:
    """Return ``'<name> RMS <rms> <unit>, max |e| <max> <unit>'`` of an error's samples."""
    rms_error, max_error = _rms_max(values)
    return f'{name} RMS {rms_error:.3g} {unit}, max |e| {max_error:.3g} {unit}'


def _time_axes(fig: 'Figure', rows: int) -> list['Axes']:
    """Return ``rows`` stacked axes sharing the time axis, labelled on the bottom one."""
    axes = list(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    axes[-1].set_xlabel('time t [s]')
    for ax in axes:
        ax.grid(True, alpha=0.3)
    return axes


def _wrap_breaks(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return wrapped angles [rad] with NaN where they jump by more than π (no vertical line)."""
    out = np.array(values, dtype=np.float64)
    if out.size > 1:
        out[1:][np.abs(np.diff(values)) > math.pi] = np.nan
    return out


def _histogram(ax: 'Axes', samples: NDArray[np.float64], unit: str, label: str,
               colour: str) -> tuple[float, float, int]:
    """Draw the samples' density histogram and the fitted normal (σ, μ in its legend label)."""
    mean, std, count = normal_fit(samples)
    finite = samples[np.isfinite(samples)]
    if count < 2 or not std > 0.0:
        ax.text(0.5, 0.5, 'too few readings', ha='center', va='center', transform=ax.transAxes)
        return mean, std, count
    ax.hist(finite, bins=HISTOGRAM_BINS, density=True, color=colour, alpha=0.45)
    grid = np.linspace(mean - 4.0 * std, mean + 4.0 * std, 200)
    density = np.exp(-0.5 * ((grid - mean) / std)**2) / (std * math.sqrt(2.0 * math.pi))
    ax.plot(grid, density, color=colour, linewidth=1.5,
            label=f'{label}: σ = {std:.2g}, μ = {mean:.2g} {unit}')
    bottom, top = ax.get_ylim()
    ax.set_ylim(bottom, top * HISTOGRAM_HEADROOM)   # room for the legend above the bars
    ax.set_xlabel(f'error [{unit}]')
    ax.set_ylabel(f'density [1/{unit}]')
    ax.grid(True, alpha=0.3)
    return mean, std, count


def _sensor_axes(fig: 'Figure') -> tuple['Axes', 'Axes']:
    """Return a wide time-series axes and a narrow histogram axes beside it."""
    grid = fig.add_gridspec(1, 2, width_ratios=(1.7, 1.0))
    return fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])


# --- the world, the range readings and the contacts on the trajectory ---------------------

def _draw_world(ax: 'Axes', found: RunWorld) -> str:
    """Draw the world under the trajectories (map frame); return its sentence of the caption."""
    from matplotlib.patches import Circle
    from matplotlib.transforms import Affine2D

    world, parts = found.world, []
    grid = world.grid
    if grid is not None:
        image = np.zeros((grid.height, grid.width, 4))
        image[grid.data < 0] = UNKNOWN_RGBA
        image[grid.occupied] = GRID_RGBA
        x0, y0, yaw = grid.origin
        width, height = grid.width * grid.resolution, grid.height * grid.resolution
        placed = Affine2D().rotate(yaw).translate(x0, y0)
        ax.imshow(image, origin='lower', extent=(0.0, width, 0.0, height),
                  transform=placed + ax.transData, interpolation='nearest', zorder=0.5)
        ax.update_datalim(placed.transform([[0.0, 0.0], [width, 0.0], [0.0, height],
                                            [width, height]]))
        parts.append(f'the occupied cells of its grid ({grid.width} x {grid.height} cells of '
                     f'{grid.resolution:g} m, grey)')
    label: Optional[str] = 'walls and obstacles'
    segments = np.asarray(world.segments, dtype=np.float64).reshape(-1, 4)
    if len(segments):
        # One line, segments separated by NaN: (x1, x2, NaN) per segment.
        xs = np.column_stack([segments[:, 0], segments[:, 2], np.full(len(segments), np.nan)])
        ys = np.column_stack([segments[:, 1], segments[:, 3], np.full(len(segments), np.nan)])
        ax.plot(xs.ravel(), ys.ravel(), color=WORLD_COLOUR, linewidth=1.5, zorder=1.2,
                solid_capstyle='butt', label=label)
        label = None
        parts.append('walls and polygon edges (dark lines)')
    for cx, cy, radius in np.asarray(world.circles, dtype=np.float64).reshape(-1, 3):
        ax.add_patch(Circle((cx, cy), radius, facecolor='0.75', edgecolor=WORLD_COLOUR,
                            linewidth=1.5, zorder=1.2, label=label))
        label = None
    if len(world.circles):
        parts.append('circles')
    text = (f' The world ({found.source}) is drawn in the map frame, the frame of the ground '
            f'truth: ' + ', '.join(parts) + '.')
    if found.note:
        text += f' Note: {found.note}.'
    return text


def _laser_snapshots(run: RunSeries, truth: Series, marks: NDArray[np.float64],
                     mount: NDArray[np.float64]) -> tuple[NDArray[np.float64], int]:
    """Return the returns (k, 2) of the scans nearest ``marks`` and the number of scans."""
    scans = run.scans
    if scans is None or not len(scans) or not len(mount):
        return np.zeros((0, 2)), 0
    chosen = sorted({_nearest(scans.t, float(t)) for t in marks})
    points = []
    for k in chosen:
        pose = _pose_at(truth, float(scans.t[k]))
        if pose is not None:
            points.append(laser_points(scans['ranges'][k], scans['angle_min'][k],
                                       scans['angle_increment'][k], scans['range_min'][k],
                                       scans['range_max'][k], pose, mount[0]))
    return (np.vstack(points) if points else np.zeros((0, 2))), len(points)


def _range_snapshots(run: RunSeries, truth: Series, marks: NDArray[np.float64],
                     tolerance: float) -> dict[tuple[str, bool], list[NDArray[np.float64]]]:
    """Return the beams (2, 2) at ``marks`` by (kind, echo): a no-echo one to max_range."""
    beams: dict[tuple[str, bool], list[NDArray[np.float64]]] = {}
    mounts = {kind: sensor_mounts(run.scenario, kind) for kind in ('sonar', 'infrared')
              if any(topic.startswith(f'/{kind}_') for topic in run.ranges)}
    for topic, readings in run.ranges.items():
        match = RANGE_TOPIC.fullmatch(topic)
        if match is None or not len(readings):
            continue
        kind, index = match.group(1), int(match.group(2))
        if index >= len(mounts[kind]):
            continue
        chosen = sorted({k for k in (_nearest(readings.t, float(t)) for t in marks)
                         if np.any(np.abs(readings.t[k] - marks) <= tolerance)})
        for k in chosen:
            reading, longest = float(readings['range'][k]), float(readings['max_range'][k])
            pose = _pose_at(truth, float(readings.t[k]))
            if pose is None or not reading >= 0.0:
                continue   # NaN or negative: no reading
            echo = reading < longest   # max_range or +inf: no echo (REP-117)
            beams.setdefault((kind, echo), []).append(
                range_beam(reading if echo else longest, pose, mounts[kind][index]))
    return beams


def _clip_to(beam: NDArray[np.float64], box: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``beam`` (2, 2) ended where it leaves ``box`` ((x0, y0), (x1, y1)), if sooner."""
    start, end = beam
    (x0, y0), (x1, y1) = box
    step = end - start
    fraction = 1.0
    for axis, (low, high) in enumerate(((x0, x1), (y0, y1))):
        if step[axis] > 0.0:
            fraction = min(fraction, (high - start[axis]) / step[axis])
        elif step[axis] < 0.0:
            fraction = min(fraction, (low - start[axis]) / step[axis])
    return np.array([start, start + max(fraction, 0.0) * step])


def _draw_readings(ax: 'Axes', run: RunSeries, truth: Series, every: float) -> str:
    """Draw the range readings every ``every`` [s] in the map frame; the caption's sentence."""
    marks = np.arange(truth.t[0], truth.t[-1] + 1e-9 * max(1.0, abs(truth.t[-1])), every)
    points, count = _laser_snapshots(run, truth, marks, sensor_mounts(run.scenario, 'laser'))
    parts = []
    if count:
        ax.plot(points[:, 0], points[:, 1], '.', color='C4', alpha=0.8, markersize=5.0,
                markeredgewidth=0.0, zorder=1.3, label=f'laser returns every {every:g} s')
        parts.append(f'the returns of the /scan nearest each time ({count} scans, '
                     f'{len(points)} points; +-inf, NaN and out-of-range readings, REP-117, '
                     'not drawn)')
    beams = _range_snapshots(run, truth, marks, min(RANGE_TOLERANCE, every / 2.0))
    # No-echo beams end at the edge of what is drawn so far (the world, the trajectories, the
    # laser returns), with a margin: max_range (10.7 m for a sonar) would dwarf the world.
    box = ax.dataLim.get_points()
    box += np.array([[-1.0], [1.0]]) * max(0.05 * float(np.max(box[1] - box[0])), 0.3)
    for kind, colour in (('sonar', 'C9'), ('infrared', 'C6')):
        echoes, silent = beams.get((kind, True), []), beams.get((kind, False), [])
        if not echoes and not silent:
            continue
        for drawn, style, label in ((echoes, '-', f'{kind} echoes every {every:g} s'),
                                    (silent, ':', f'{kind}: no echo')):
            if drawn:
                if style == ':' and np.all(np.isfinite(box)):
                    drawn = [_clip_to(beam, box) for beam in drawn]
                lines = np.concatenate([np.vstack([b, [np.nan, np.nan]]) for b in drawn])
                ax.plot(lines[:, 0], lines[:, 1], style, color=colour, alpha=0.7,
                        linewidth=1.0 if style == '-' else 1.4, zorder=1.3, label=label)
        parts.append(f'{len(echoes) + len(silent)} {kind} readings as lines from the sensor '
                     f'along its axis, to the echo (solid; {len(echoes)}) or, for a reading '
                     f'of max_range (no echo; {len(silent)}), dotted towards max_range')
    if not parts:
        return ''
    return (f' Every {every:g} s, the range readings nearest that time, placed by the sensor '
            "mounts of the scenario and the true pose at each reading's stamp: "
            + '; '.join(parts) + '.')


def _draw_contacts(ax: 'Axes', run: RunSeries, truth: Optional[Series]) -> str:
    """Mark where /bumper goes from free to in contact; return the caption's sentence."""
    bumper = run.bumper
    if bumper is None or not len(bumper):
        return ''
    touching = np.asarray(bumper['in_contact']) > 0.5
    starts = np.flatnonzero(touching & ~np.concatenate([[False], touching[:-1]]))
    places = []
    for k in starts:
        point = [bumper.columns[c][k] if c in bumper.columns else math.nan for c in 'xy']
        if not all(math.isfinite(v) for v in point) and truth is not None:
            pose = _pose_at(truth, float(bumper.t[k]))
            point = [math.nan, math.nan] if pose is None else list(pose[:2])
        if all(math.isfinite(v) for v in point):
            places.append(point)
    if places:
        xy = np.array(places)
        ax.plot(xy[:, 0], xy[:, 1], 'x', color='C3', markersize=10, markeredgewidth=2.5,
                zorder=5, label=f'contact ({len(starts)})')
    times = ', '.join(f'{bumper.t[k]:.2f}' for k in starts)
    return (f' Contacts (/bumper from free to in contact): {len(starts)}'
            + (f', at t = {times} s, marked by red crosses at the contact point.' if len(starts)
               else '.'))


# --- mobile figures -----------------------------------------------------------------------

def trajectory(fig: 'Figure', run: RunSeries, every: float) -> str:
    """
    Draw the path, the true trajectory and the /odom estimate in the x-y plane; return the caption.

    The robot is drawn as a triangle at the true (else the /odom) pose every ``every`` [s]
    (:func:`robot_poses`); a timed path (a trajectory) is marked at the same times.
    """
    from matplotlib.patches import Polygon

    ax = fig.add_subplot()
    spans = []
    found = run_world(run)
    world_text = _draw_world(ax, found) if found is not None else ''
    if run.path is not None and len(run.path):
        ax.plot(run.path[:, 0], run.path[:, 1], '--', color='0.3', linewidth=1.5,
                label='path (reference)')
        spans.append(run.path)
    truth, odom = run.truth, run.odom
    if truth is not None and len(truth):
        ax.plot(truth['x'], truth['y'], color='C0', linewidth=1.5, label='true trajectory')
        spans.append(np.column_stack([truth['x'], truth['y']]))
    if odom is not None and len(odom):
        ax.plot(odom['x'], odom['y'], color='C1', linewidth=1.0, label='/odom estimate')
        spans.append(np.column_stack([odom['x'], odom['y']]))
    drawn = truth if truth is not None and len(truth) else odom
    caption = ('Reference path (dashed), true trajectory (/ground_truth/odom) and the /odom '
               'estimate in the x-y plane of the path frame [m], equal axes.')
    if drawn is not None and len(drawn):
        points = np.vstack(spans)
        size = ROBOT_SIZE * max(float(np.ptp(points[:, 0])), float(np.ptp(points[:, 1])), 0.2)
        poses = robot_poses(drawn.t, drawn['x'], drawn['y'], drawn['theta'], every)
        outline = footprint_polygon(run.scenario)
        body = size * np.array([[0.6, 0.0], [-0.4, 0.35], [-0.4, -0.35]]) if outline is None \
            else outline
        if outline is not None:   # the body at true scale, and where it ended
            poses = np.vstack([poses, [drawn['x'][-1], drawn['y'][-1], drawn['theta'][-1]]])
        for k, (x, y, theta) in enumerate(poses):
            rotation = np.array([[math.cos(theta), -math.sin(theta)],
                                 [math.sin(theta), math.cos(theta)]])
            ax.add_patch(Polygon(body @ rotation.T + (x, y), closed=True, facecolor='C2',
                                 edgecolor='k', linewidth=0.6, alpha=0.55, zorder=1.5,
                                 label=f'robot every {every:g} s' if k == 0 else None))
        ax.plot(drawn['x'][0], drawn['y'][0], 'o', color='k', markersize=5, zorder=4,
                label='start')
        source = 'true' if drawn is truth else '/odom'
        caption += (f' The robot is drawn as a triangle pointing along its heading at the '
                    f'{source} pose every {every:g} s; the dot marks the start.'
                    if outline is None else
                    f' The robot is drawn as its body (robot.footprint_polygon, true scale) at '
                    f'the {source} pose every {every:g} s and at the end; the dot marks the '
                    'start.')
        if run.path is not None and run.path_times is not None and len(run.path_times) > 1:
            marks = robot_poses(drawn.t, drawn.t, drawn.t, drawn.t, every)[:, 0]
            reference = np.column_stack([
                np.interp(marks, run.path_times, run.path[:, i]) for i in range(2)])
            ax.plot(reference[:, 0], reference[:, 1], 'x', color='C3', markersize=6,
                    markeredgewidth=1.5, zorder=4, label='reference at the same times')
            caption += (' The path is a timed trajectory: the crosses mark where the '
                        'reference is at the times the robot is drawn.')
    if truth is not None and odom is not None and len(truth) and len(odom):
        final = math.hypot(odom['x'][-1] - truth['x'][-1], odom['y'][-1] - truth['y'][-1])
        caption += f' Final position error of /odom: {final:.3f} m.'
    title = 'Path, true trajectory and /odom estimate'
    if found is not None:
        caption += world_text
        if truth is not None and len(truth):
            caption += _draw_readings(ax, run, truth, scan_every(
                float(truth.t[-1] - truth.t[0]), every))
        caption += _draw_contacts(ax, run, truth)
        title += ' in the world'
    ax.set_aspect('equal', adjustable='datalim')
    ax.set_xlabel('x [m]')
    ax.set_ylabel('y [m]')
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize='small', loc='best')
    return caption


def tracking_errors(fig: 'Figure', run: RunSeries, window: float) -> str:
    """
    Draw the tracking errors, the truth's against ``/path`` and the tracker's; return the caption.

    The truth's are :func:`~robotica_sim.grading.metrics.truth_path_errors` with ``window``
    [m], the numbers ``robotica grade`` gives; the tracker publishes the errors of the pose it
    reads.
    """
    truth, reported = run.truth, run.tracking_error
    true: dict[str, NDArray[np.float64]] = {}
    if truth is not None and len(truth) and run.path is not None and len(run.path) >= 2:
        _, true['cross_track'], true['heading'], _ = truth_path_errors(
            run, MetricParams(search_window=window))
    panels = [('cross_track', 'cross-track e_y [m]', 'm'), ('heading', 'heading e_θ [rad]', 'rad')]
    if reported is not None and 'along_track' in reported.columns and np.any(
            reported['along_track'] != 0.0):
        panels.append(('along_track', 'along-track e_x [m]', 'm'))
    axes = _time_axes(fig, len(panels))
    true_stats, reported_stats = [], []
    for ax, (column, label, unit) in zip(axes, panels):
        if truth is not None and column in true:
            ax.plot(truth.t, true[column], color='C3', linewidth=1.2,
                    label='truth against /path')
            true_stats.append(_stats_text(column.replace('_', '-'), true[column], unit))
        if reported is not None:
            ax.plot(reported.t, reported[column], color='C0', linewidth=1.0,
                    linestyle='--' if true else '-', label='tracker (tracking_error)')
            reported_stats.append(_stats_text(column.replace('_', '-'), reported[column], unit))
        ax.axhline(0.0, color='k', linewidth=0.6)
        ax.set_ylabel(label)
    if true and reported is not None:
        axes[0].legend(fontsize='small', loc='upper right', ncols=2)
    axes[0].set_title('Tracking errors against /path' if true
                      else 'Tracking errors (/path_tracker/tracking_error)')
    caption = ('Tracking errors over simulated time (cross-track > 0 left of the path; heading '
               '= robot minus path tangent, wrapped to (-π, π]).')
    if true:
        caption += (' True errors, of the ground truth against /path (solid), projected as '
                    f'robotica grade does (closest point within {window:g} m of the progress): '
                    + '; '.join(true_stats) + '.')
    if reported is not None:
        caption += (' As the tracker computed them from the pose it reads '
                    f'(/path_tracker/tracking_error{", dashed" if true else ""}): '
                    + '; '.join(reported_stats) + '.')
    return caption


def commands(fig: 'Figure', cmd: Series, truth: Optional[Series]) -> str:
    """Draw the velocity commands of /cmd_vel or /vehicle_command and the truth; the caption."""
    panels: list[tuple[str, str, Optional[str]]]   # column, axis label, truth's column
    if 'w' in cmd.columns:
        topic = '/cmd_vel (geometry_msgs/Twist)'
        panels = [('v', 'linear v [m/s]', 'v'), ('w', 'angular ω [rad/s]', 'w')]
    else:
        topic = '/vehicle_command (robotica_msgs/VehicleCommand)'
        panels = [('v', 'speed v [m/s]', 'v'), ('steering', 'steering α [rad]', None)]
        if 'steering_rate' in cmd.columns and np.any(cmd['steering_rate'] != 0.0):
            panels.append(('steering_rate', "steering rate α' [rad/s]", None))
    axes = _time_axes(fig, len(panels))
    for ax, (column, label, true_column) in zip(axes, panels):
        ax.plot(cmd.t, cmd[column], color='C0', linewidth=1.0, label='command')
        if truth is not None and true_column is not None and true_column in truth.columns:
            ax.plot(truth.t, truth[true_column], color='C1', linewidth=1.0, alpha=0.8,
                    linestyle='--', label='true (/ground_truth/odom)')
            ax.legend(fontsize='small', loc='best')
        ax.set_ylabel(label)
    axes[0].set_title(f'Commands on {topic.split(" ")[0]}')
    return (f'Commands on {topic} over simulated time, with the true velocities where the '
            'ground truth has them (the difference is the traction lag and slip of the vehicle).')


def estimation(fig: 'Figure', odom: Series, truth: Series) -> str:
    """Draw /odom minus the truth with the ±3σ band of its covariance; return the caption."""
    panels = [('x', 'var_x', 'e_x [m]', 'm', False), ('y', 'var_y', 'e_y [m]', 'm', False),
              ('theta', 'var_theta', 'e_θ [rad]', 'rad', True)]
    axes = _time_axes(fig, 3)
    stats = []
    for ax, (column, variance, label, unit, angle) in zip(axes, panels):
        error = reading_error(odom.t, odom[column], truth.t, truth[column], angle=angle)
        ax.plot(odom.t, error, color='C3', linewidth=1.0, label='/odom - truth')
        ax.axhline(0.0, color='k', linewidth=0.6)
        text = f'{column} RMS {rms(_finite(error)):.3g} {unit}'
        if variance in odom.columns:
            bound = 3.0 * np.sqrt(np.maximum(odom[variance], 0.0))
            ax.fill_between(odom.t, -bound, bound, color='C0', alpha=0.2, linewidth=0.0,
                            label='±3σ (covariance)')
            finite = np.isfinite(error)
            inside = float(np.mean(np.abs(error[finite]) <= bound[finite])) if finite.any() \
                else math.nan
            text += f', {100.0 * inside:.1f} % inside ±3σ'
        stats.append(text)
        ax.set_ylabel(label)
    axes[0].legend(fontsize='small', loc='upper right', ncols=2)
    axes[0].set_title('Estimation error: /odom minus ground truth')
    return ('Error of the /odom pose against the ground truth interpolated at its stamps (x, y '
            'in the odom frame; θ wrapped to (-π, π]), with the ±3σ band of the covariance '
            'the estimator published: ' + '; '.join(stats) + '.')


def gyro(fig: 'Figure', imu: Series, truth: Series) -> str:
    """Draw the gyro's yaw rate against the truth and its error histogram; the caption."""
    series, hist = _sensor_axes(fig)
    series.plot(truth.t, truth['w'], color='C0', linewidth=2.0, label='true ω')
    series.plot(imu.t, imu['wz'], color='C1', linewidth=0.7, label='gyro ω_z')
    series.set_xlabel('time t [s]')
    series.set_ylabel('yaw rate [rad/s]')
    series.set_title('Gyro /imu/data vs truth')
    series.grid(True, alpha=0.3)
    series.legend(fontsize='small', loc='best')
    error = reading_error(imu.t, imu['wz'], truth.t, truth['w'])
    mean, std, count = _histogram(hist, error, 'rad/s', 'ω_z - ω', 'C1')
    hist.set_title(f'Gyro error, {count} readings')
    hist.legend(fontsize='x-small', loc='upper left')
    return ('Yaw rate of the gyro (/imu/data angular_velocity.z) against the true angular '
            'velocity, and the histogram of its error (reading minus truth at the stamp of the '
            f'reading) with the fitted normal density: mean (bias) {mean:.3g} rad/s, '
            f'σ {std:.3g} rad/s.')


def compass(fig: 'Figure', headings: Series, truth: Series) -> str:
    """Draw the compass heading against the truth and its error histogram; the caption."""
    series, hist = _sensor_axes(fig)
    series.plot(truth.t, _wrap_breaks(np.asarray(wrap_to_pi(truth['theta']))), color='C0',
                linewidth=2.0, label='true θ')
    series.plot(headings.t, _wrap_breaks(np.asarray(wrap_to_pi(headings['theta']))),
                color='C1', linewidth=0.7, label='compass θ')
    series.set_ylim(-math.pi - 0.3, math.pi + 0.3)
    series.set_xlabel('time t [s]')
    series.set_ylabel('heading θ [rad]')
    series.set_title('Compass /compass/heading vs truth')
    series.grid(True, alpha=0.3)
    series.legend(fontsize='small', loc='lower right')
    error = reading_error(headings.t, headings['theta'], truth.t, truth['theta'], angle=True)
    mean, std, count = _histogram(hist, error, 'rad', 'θ_c - θ', 'C1')
    hist.set_title(f'Compass error, {count} readings')
    hist.legend(fontsize='x-small', loc='upper left')
    return ('Heading of the compass (yaw of /compass/heading, REP-103: from the x axis, '
            'counter-clockwise) against the true heading, both wrapped to (-π, π], and the '
            'histogram of its error (wrapped) with the fitted normal density: mean '
            f'{mean:.3g} rad, σ {std:.3g} rad.')


def gps(fig: 'Figure', fixes: Series, truth: Series, origin: GeodeticOrigin) -> str:
    """
    Draw the GPS fixes in the ENU frame of ``origin`` against the truth; return the caption.

    Beside the x-y plane: the error (fix minus truth) over time and its histograms.
    """
    enu = fixes_to_enu(origin, fixes['latitude'], fixes['longitude'], fixes['altitude'])
    grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.0))
    plane = fig.add_subplot(grid[:, 0])
    over_time = fig.add_subplot(grid[0, 1])
    hist = fig.add_subplot(grid[1, 1])
    plane.plot(truth['x'], truth['y'], color='C0', linewidth=1.2, label='true position')
    plane.plot(enu[:, 0], enu[:, 1], '.', color='C1', markersize=3, label='GPS fix (ENU)')
    plane.set_aspect('equal', adjustable='datalim')
    plane.set_xlabel('x east [m]')
    plane.set_ylabel('y north [m]')
    plane.set_title('GPS /gps/fix vs truth')
    plane.grid(True, alpha=0.3)
    plane.legend(fontsize='small', loc='best')
    errors = [reading_error(fixes.t, enu[:, i], truth.t, truth[c]) for i, c in enumerate('xy')]
    for error, name, colour in zip(errors, ('east', 'north'), ('C1', 'C2')):
        over_time.plot(fixes.t, error, '.', color=colour, markersize=2.5, label=name)
    over_time.axhline(0.0, color='k', linewidth=0.6)
    over_time.set_xlabel('time t [s]')
    over_time.set_ylabel('error [m]')
    over_time.set_title('GPS error over time')
    over_time.grid(True, alpha=0.3)
    over_time.legend(fontsize='x-small', loc='upper right', ncols=2)
    stats = [_histogram(hist, error, 'm', name, colour)
             for error, name, colour in zip(errors, ('east', 'north'), ('C1', 'C2'))]
    hist.set_title(f'GPS error, {stats[0][2]} fixes')
    hist.legend(fontsize='x-small', loc='upper left')
    claimed = ''
    if 'var_e' in fixes.columns and 'var_n' in fixes.columns:
        sigma_e, sigma_n = (math.sqrt(np.nanmean(fixes[c])) for c in ('var_e', 'var_n'))
        claimed = (f' The covariance of the fixes claims σ {sigma_e:.3g} m east and '
                   f'{sigma_n:.3g} m north (mean variance).')
    latitude, longitude = origin.latitude_deg, origin.longitude_deg
    return ('GPS fixes (/gps/fix) converted to the local ENU frame of the origin '
            f'{abs(latitude):g}° {"N" if latitude >= 0.0 else "S"}, '
            f'{abs(longitude):g}° {"E" if longitude >= 0.0 else "W"}, {origin.altitude:g} m '
            '(x east, y north) against the true position, their error (fix minus truth at the '
            'stamp of the fix) over time and its histograms with fitted normal densities: east '
            f'mean {stats[0][0]:.3g} m, σ {stats[0][1]:.3g} m; north mean {stats[1][0]:.3g} m, '
            f'σ {stats[1][1]:.3g} m.' + claimed)


# --- manipulator figures ------------------------------------------------------------------

def _joint_names(run: RunSeries, count: int) -> list[str]:
    for series in (run.joint_states, run.controller):
        if series is not None and len(series.names) == count:
            return list(series.names)
    return [f'joint {i + 1}' for i in range(count)]


def _joint_axes(fig: 'Figure', count: int) -> list['Axes']:
    """Return one axes per joint (one column up to three joints, else two), time shared."""
    columns = 1 if count <= 3 else 2
    rows = math.ceil(count / columns)
    if rows > 2:
        fig.set_size_inches(FIGURE_SIZE[0], FIGURE_SIZE[1] + PANEL_HEIGHT * (rows - 2))
    grid = fig.subplots(rows, columns, sharex=True, squeeze=False)
    axes = [grid[i // columns, i % columns] for i in range(count)]
    for ax in grid.ravel()[count:]:
        ax.set_visible(False)
    for i, ax in enumerate(axes):
        ax.grid(True, alpha=0.3)
        if i + columns >= count:   # the lowest axes of its column
            ax.set_xlabel('time t [s]')
    return axes


def _matrix(series: Optional[Series], column: str) -> Optional[NDArray[np.float64]]:
    """Return the (n, joints) column of ``series``, or None if absent or empty."""
    if series is None or column not in series.columns:
        return None
    values = np.asarray(series[column], dtype=np.float64)
    if values.ndim != 2 or values.shape[1] == 0 or values.shape[0] == 0:
        return None
    return values


def joint_figure(fig: 'Figure', run: RunSeries, kind: str) -> str:
    """Draw the joints' ``kind`` ('position' or 'velocity') and its reference; the caption."""
    symbol, unit, plural = (('q', 'rad', 'positions') if kind == 'position'
                            else ("q'", 'rad/s', 'velocities'))
    measured = _matrix(run.joint_states, kind)
    reference = _matrix(run.controller, f'reference_{kind}')
    count = max((m.shape[1] for m in (measured, reference) if m is not None), default=0)
    axes = _joint_axes(fig, max(count, 1))
    names = _joint_names(run, count)
    for i, ax in enumerate(axes[:count]):
        if measured is not None and i < measured.shape[1] and run.joint_states is not None:
            ax.plot(run.joint_states.t, measured[:, i], color='C0', linewidth=1.2,
                    label=symbol)
        if reference is not None and i < reference.shape[1] and run.controller is not None:
            ax.plot(run.controller.t, reference[:, i], color='C1', linewidth=1.0,
                    linestyle='--', label=f'{symbol}_d (reference)')
        ax.set_ylabel(f'{symbol} [{unit}]')
        ax.set_title(names[i], fontsize='medium')
    axes[0].legend(fontsize='small', loc='best')
    fig.suptitle(f'Joint {plural}: measured (/joint_states) vs reference', fontsize='large')
    return (f'Joint {plural} {symbol} [{unit}] from /joint_states (solid) and the '
            f'reference {symbol}_d of the controller (dashed, '
            '/joint_controller/controller_state), one panel per joint.')


def joint_torques(fig: 'Figure', run: RunSeries) -> str:
    """Draw the applied and the commanded torque of each joint; return the caption."""
    applied = _matrix(run.joint_states, 'effort')
    commanded_series: Optional[Series]
    if run.torques is not None:
        commanded_series, commanded = run.torques, _matrix(run.torques, 'effort')
        source = '/joint_torques'
    else:
        commanded_series, commanded = run.controller, _matrix(run.controller, 'effort')
        source = '/joint_controller/controller_state'
    count = max((m.shape[1] for m in (applied, commanded) if m is not None), default=0)
    axes = _joint_axes(fig, max(count, 1))
    names = _joint_names(run, count)
    peaks = []
    for i, ax in enumerate(axes[:count]):
        peak = 0.0
        if applied is not None and i < applied.shape[1] and run.joint_states is not None:
            ax.plot(run.joint_states.t, applied[:, i], color='C0', linewidth=1.2,
                    label='applied τ')
            peak = max(peak, _rms_max(applied[:, i])[1])
        if commanded is not None and i < commanded.shape[1] and commanded_series is not None:
            ax.plot(commanded_series.t, commanded[:, i], color='C1', linewidth=1.0,
                    linestyle='--', label='commanded τ')
            peak = max(peak, _rms_max(commanded[:, i])[1])
        peaks.append(f'{names[i]} {peak:.3g}')
        ax.set_ylabel('τ [N m]')
        ax.set_title(names[i], fontsize='medium')
    if count:
        axes[0].legend(fontsize='small', loc='best')
    fig.suptitle('Joint torques', fontsize='large')
    return ('Torque per joint [N m]: applied by the simulator (effort of /joint_states, '
            f'solid) and commanded by the controller ({source}, dashed). Peak |τ| [N m]: '
            + ', '.join(peaks) + '.')


def joint_errors(fig: 'Figure', run: RunSeries, controller: Series) -> str:
    """Draw each joint's position error e = q_d - q (book (8.30)); return the caption."""
    error = _matrix(controller, 'position_error')
    if error is None:
        error = np.zeros((len(controller), 0))
    count = error.shape[1]
    axes = _joint_axes(fig, max(count, 1))
    names = _joint_names(run, count)
    stats = []
    for i, ax in enumerate(axes[:count]):
        ax.plot(controller.t, error[:, i], color='C3', linewidth=1.0)
        ax.axhline(0.0, color='k', linewidth=0.6)
        ax.set_ylabel('e [rad]')
        ax.set_title(names[i], fontsize='medium')
        rms_error, max_error = _rms_max(error[:, i])
        stats.append(f'{names[i]} RMS {rms_error:.3g} rad, max {max_error:.3g} rad, '
                     f'final {error[-1, i]:.3g} rad')
    fig.suptitle('Joint position errors e = q_d - q', fontsize='large')
    return ('Position error of each joint, e = q_d - q [rad] (book (8.30)), as the controller '
            'computed it (/joint_controller/controller_state): ' + '; '.join(stats) + '.')


def sweep_metric(fig: 'Figure', key: str, points: list[tuple[Any, str, float]], metric: str,
                 unit: str) -> str:
    """
    Draw a sweep's ``metric`` against the varied ``key``: each run, and the mean per value.

    ``points`` are ``(x, group, value)``: the value of ``key``, the other varied keys as a
    label ('' when only one key is varied: one line) and the run's metric (NaN: not drawn).
    Numbers are placed on a numeric axis, other values one per tick in their first order.
    Returns the caption.
    """
    ax = fig.add_subplot(1, 1, 1)
    xs = list(dict.fromkeys(p[0] for p in points))
    numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
    place = {x: (float(x) if numeric else float(i)) for i, x in enumerate(xs)}
    groups = list(dict.fromkeys(p[1] for p in points))
    means = []
    for colour, group in enumerate(groups):
        mine = [(place[x], v) for x, g, v in points if g == group and math.isfinite(v)]
        if not mine:
            continue
        ax.plot([p[0] for p in mine], [p[1] for p in mine], 'o', color=f'C{colour}',
                alpha=0.45, markersize=5, label=f'each run{", " + group if group else ""}')
        at = sorted({p[0] for p in mine})
        mean = [float(np.mean([v for x, v in mine if x == a])) for a in at]
        ax.plot(at, mean, '-', color=f'C{colour}', linewidth=1.5,
                label=f'mean{", " + group if group else ""}')
        means += [f'{a:g}: {m:.4g}' if numeric else f'{xs[int(a)]}: {m:.4g}'
                  for a, m in zip(at, mean)]
    if not numeric:
        ax.set_xticks(range(len(xs)), [str(x) for x in xs])
    ax.set_xlabel(key)
    ax.set_ylabel(f'{metric} [{unit}]' if unit and unit != '-' else metric)
    ax.grid(True, alpha=0.3)
    if means:
        ax.legend(fontsize='small', loc='best')
    fig.suptitle(f'{metric} against {key}', fontsize='large')
    return (f'{metric} of each run (dots) and its mean over the runs of each value (line) '
            f'against {key}. Means: ' + ('; '.join(means) or 'none (no run gave the metric)')
            + '.')
