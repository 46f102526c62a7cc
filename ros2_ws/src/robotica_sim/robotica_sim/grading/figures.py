"""
The figures of ``robotica report``: one function per figure, drawn into a Matplotlib figure.

Each public ``name(fig, ...)`` draws one figure of a run's time series
(:class:`robotica_sim.grading.series.RunSeries`) into a :class:`matplotlib.figure.Figure` and
returns its caption (plain text, with the figure's statistics); which figures a run gets, the
files and the page are :mod:`robotica_sim.grading.report`'s. :func:`auto_robot_every` and
:func:`robot_poses` choose where the robot is drawn on the trajectory. The figures:

* mobile robot: ``trajectory`` (the reference path, the true trajectory and the ``/odom``
  estimate in the x-y plane of the path frame, equal axes, the robot drawn every
  ``robot_every`` s), ``tracking_errors`` (cross-track and heading errors of the ground truth
  against ``/path`` by :func:`robotica_sim.grading.metrics.path_errors`, the projection
  ``robotica grade`` uses, beside the tracker's own ``/path_tracker/tracking_error``),
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
from robotica_ctrl.mobile.path import PolylinePath
from robotica_kin.angles import wrap_to_pi
from robotica_kin.geodetic import GeodeticOrigin
from robotica_sim.grading.metrics import (max_abs, normal_fit, path_errors, reading_error,
                                          rms)
from robotica_sim.grading.series import fixes_to_enu, RunSeries, Series

if TYPE_CHECKING:   # Matplotlib is imported lazily, when figures are drawn
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ['DPI', 'FIGURE_SIZE', 'auto_robot_every', 'commands', 'compass', 'estimation', 'gps',
           'gyro', 'joint_errors', 'joint_figure', 'joint_torques', 'robot_poses',
           'sweep_metric', 'tracking_errors', 'trajectory']

DPI = 100                     # [dots per inch] of the PNG files
FIGURE_SIZE = (8.0, 5.0)      # [in] width, height of a figure
PANEL_HEIGHT = 1.9            # [in] per row of joint panels beyond two rows
ROBOT_MARKS = 15              # at most this many intervals between robot poses (automatic)
ROBOT_EVERY_STEPS = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0, 600.0)  # [s]
ROBOT_SIZE = 0.035            # length of the robot's triangle / larger span of the x-y plot
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
        body = size * np.array([[0.6, 0.0], [-0.4, 0.35], [-0.4, -0.35]])
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
                    f'{source} pose every {every:g} s; the dot marks the start.')
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
    ax.set_aspect('equal', adjustable='datalim')
    ax.set_xlabel('x [m]')
    ax.set_ylabel('y [m]')
    ax.set_title('Path, true trajectory and /odom estimate')
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize='small', loc='best')
    return caption


def tracking_errors(fig: 'Figure', run: RunSeries, window: float) -> str:
    """
    Draw the tracking errors, the truth's against ``/path`` and the tracker's; return the caption.

    The truth's are :func:`~robotica_sim.grading.metrics.path_errors` with ``window`` [m], the
    numbers ``robotica grade`` gives; the tracker publishes the errors of the pose it reads.
    """
    truth, reported = run.truth, run.tracking_error
    true: dict[str, NDArray[np.float64]] = {}
    if truth is not None and len(truth) and run.path is not None and len(run.path) >= 2:
        _, true['cross_track'], true['heading'] = path_errors(
            PolylinePath(run.path), truth['x'], truth['y'], truth['theta'], window)
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
