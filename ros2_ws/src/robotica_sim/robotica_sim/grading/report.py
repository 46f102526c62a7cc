"""
Figures and an HTML page of a recorded run: what ``robotica report`` writes.

:func:`write_report` takes the time series of a run
(:class:`robotica_sim.grading.series.RunSeries`,
read by :func:`robotica_sim.grading.series.load_run`) and writes PNG figures (Matplotlib's Agg
renderer, 8 x 5 in at 100 dpi) and an ``index.html`` that shows them with captions, beside the
scenario, the simulator's status and the bag's topics. A figure is drawn only when the bag holds
the topics it needs:

* mobile robot: ``trajectory`` (the reference path, the true trajectory and the ``/odom``
  estimate in the x-y plane of the path frame, equal axes, the robot drawn every
  ``robot_every`` s), ``tracking_errors`` (cross-track, heading), ``commands``,
  ``estimation`` (``/odom`` minus truth with the ±3σ band of its covariance) and one figure per
  sensor, ``gyro``, ``compass``, ``gps``: the reading against the truth and a histogram of the
  reading's error with its fitted normal density;
* manipulator (book ch. 8): ``joint_positions``, ``joint_velocities``, ``joint_torques`` and
  ``joint_errors`` (e = q_d - q, book (8.30)), one panel per joint.

A sensor's error is the reading minus the ground truth interpolated linearly at the reading's
stamp (:func:`reading_error`); for angles the truth is unwrapped before it is interpolated and
the difference is wrapped to (-π, π]. GPS fixes enter the world frame as the local ENU frame of
the scenario's ``sensors.gps.origin`` (the GPS emulator's origin, REP-103/105: x east, y north).
Units are SI, angles in radians, headings REP-103 (θ from the x axis, counter-clockwise).
Matplotlib is imported only when the figures are drawn, never at import.
"""
from dataclasses import dataclass
import html
import math
from pathlib import Path
from typing import Any, Callable, Optional, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.geodetic import GeodeticOrigin
from robotica_sim.grading.series import RunSeries, Series

if TYPE_CHECKING:   # Matplotlib is imported lazily, when figures are drawn
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ['auto_robot_every', 'default_output', 'FigureFile', 'fixes_to_enu', 'gps_origin',
           'normal_fit', 'reading_error', 'render_html', 'Report', 'ReportError',
           'robot_poses', 'write_report']

DPI = 100                     # [dots per inch] of the PNG files
FIGURE_SIZE = (8.0, 5.0)      # [in] width, height of a figure
PANEL_HEIGHT = 1.9            # [in] per row of joint panels beyond two rows
ROBOT_MARKS = 15              # at most this many intervals between robot poses (automatic)
ROBOT_EVERY_STEPS = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0, 600.0)  # [s]
ROBOT_SIZE = 0.035            # length of the robot's triangle / larger span of the x-y plot
HISTOGRAM_BINS = 40
HISTOGRAM_HEADROOM = 1.35    # y range / highest bar, for the legend


class ReportError(Exception):
    """The run has nothing the report can draw; the message says what it needs."""


@dataclass(frozen=True)
class FigureFile:
    """One PNG of a report: its file, title and caption (plain text)."""

    path: Path
    title: str
    caption: str


@dataclass(frozen=True)
class Report:
    """What :func:`write_report` wrote: the HTML page and the figures, in page order."""

    index: Path
    figures: tuple[FigureFile, ...]


@dataclass(frozen=True)
class _Plan:
    """A figure the run's topics allow: its file stem, title and drawing function."""

    name: str
    title: str
    draw: Callable[['Figure'], str]   # draws into the figure, returns the caption


# --- numbers behind the figures -----------------------------------------------------------

def default_output(bag: str | Path) -> Path:
    """
    Return the directory a report of ``bag`` goes to when none is given.

    ``<run>/report`` beside the bag when the bag directory is named ``bag`` (the layout
    ``robotica run`` writes, ``runs/<run>/bag``), else ``<bag>_report`` beside it.

    >>> default_output('runs/demo-1/bag').as_posix(), default_output('/data/b1').as_posix()
    ('runs/demo-1/report', '/data/b1_report')
    """
    path = Path(bag)
    if path.name == 'bag':
        return path.parent / 'report'
    return path.parent / f'{path.name}_report'


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


def gps_origin(scenario: Optional[dict]) -> GeodeticOrigin:
    """
    Return the geodetic origin of the world's ENU frame: the scenario's ``sensors.gps.origin``.

    The origin the GPS emulator was given (latitude, longitude [deg], height [m]); the
    scenario default (:class:`robotica_sim.runs.scenario.GpsSpec`) when the scenario has none.

    Raises
    ------
    ValueError
        If the scenario's origin is not three numbers in range.

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


# --- the report ---------------------------------------------------------------------------

def write_report(run: RunSeries, directory: str | Path, robot_every: Optional[float] = None,
                 progress: Optional[Callable[[str], None]] = None) -> Report:
    """
    Write the figures of ``run`` and their ``index.html`` into ``directory`` (created).

    Parameters
    ----------
    run : RunSeries
        The run's time series.
    directory : str or Path
        Where the PNG files and ``index.html`` go; existing files of the same names are
        replaced.
    robot_every : float, optional
        Period [s] at which the robot is drawn on the trajectory; by default
        :func:`auto_robot_every` of the time the true (else the /odom) trajectory covers.
    progress : callable, optional
        Called with ``'figure k/n: name'`` before each figure is drawn.

    Returns
    -------
    Report
        The page and the figures written, in the page's order.

    Raises
    ------
    ReportError
        If the run has no topic any figure needs.
    ValueError
        If ``robot_every`` is not > 0 s, or the scenario's GPS origin is invalid.
    OSError
        If ``directory`` cannot be created or written.

    """
    if robot_every is not None and not robot_every > 0.0:
        raise ValueError(f'robot_every must be > 0 s, got {robot_every!r}')
    every = robot_every if robot_every is not None else auto_robot_every(_span(run))
    plans = _plans(run, every)
    if not plans:
        raise ReportError(
            f'{run.bag}: nothing to plot: a mobile run needs /ground_truth/odom, /odom, /path, '
            '/cmd_vel or /vehicle_command, /path_tracker/tracking_error; an arm run '
            '/joint_states or /joint_controller/controller_state')
    from matplotlib.figure import Figure

    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    figures = []
    for number, plan in enumerate(plans, start=1):
        if progress is not None:
            progress(f'figure {number}/{len(plans)}: {plan.name}')
        fig = Figure(figsize=FIGURE_SIZE, dpi=DPI)
        caption = plan.draw(fig)
        fig.tight_layout()
        path = out / f'{plan.name}.png'
        fig.savefig(path, dpi=DPI)
        figures.append(FigureFile(path, plan.title, caption))
    index = out / 'index.html'
    index.write_text(render_html(run, figures), encoding='utf-8')
    return Report(index, tuple(figures))


def render_html(run: RunSeries, figures: list[FigureFile]) -> str:
    """Return the report page: scenario, status, topics and the figures with their captions."""
    scenario = run.scenario or {}
    name = str(scenario.get('name', run.bag.name))
    rows = [('bag', str(run.bag)), ('duration', f'{run.duration:.3f} s (simulated)')]
    for key in ('name', 'description', 'seed', 'pacing'):
        if key in scenario:
            rows.append((key, str(scenario[key])))
    robot = scenario.get('robot')
    if isinstance(robot, dict) and 'type' in robot:
        rows.append(('robot', str(robot['type'])))
    if run.status:
        status = run.status
        rows.append(('simulator', ', '.join(
            f'{key.replace("_", " ")} {status[key]:.3g}' if isinstance(status[key], float)
            else f'{key.replace("_", " ")} {status[key]}'
            for key in ('step', 'real_time_factor', 'lockstep_timeouts', 'stale_command_stops',
                        'finished') if key in status)))
    esc = html.escape
    parts = [
        '<!DOCTYPE html>', '<html lang="en">', '<head>', '<meta charset="utf-8">',
        f'<title>robotica report: {esc(name)}</title>',
        '<style>body{font-family:sans-serif;max-width:60em;margin:auto;padding:1em}'
        'table{border-collapse:collapse;margin-bottom:1em}'
        'td,th{border:1px solid #ccc;padding:.2em .6em;text-align:left}'
        'td.n{text-align:right}figure{margin:2em 0}img{max-width:100%}'
        'figcaption{color:#333}</style>',
        '</head>', '<body>', f'<h1>robotica report: {esc(name)}</h1>', '<h2>Run</h2>',
        '<table>']
    parts += [f'<tr><th>{esc(key)}</th><td>{esc(value)}</td></tr>' for key, value in rows]
    parts += ['</table>', '<h2>Topics</h2>',
              '<table><tr><th>topic</th><th>type</th><th>messages</th></tr>']
    parts += [f'<tr><td>{esc(topic)}</td><td>{esc(run.msgtypes.get(topic, ""))}</td>'
              f'<td class="n">{count}</td></tr>' for topic, count in sorted(run.counts.items())]
    parts += ['</table>', '<h2>Figures</h2>', '<ol>']
    parts += [f'<li><a href="#{esc(f.path.stem)}">{esc(f.title)}</a></li>' for f in figures]
    parts.append('</ol>')
    for number, figure in enumerate(figures, start=1):
        parts += [f'<figure id="{esc(figure.path.stem)}">',
                  f'<img src="{esc(figure.path.name)}" alt="{esc(figure.title)}">',
                  f'<figcaption><b>Figure {number}. {esc(figure.title)}.</b> '
                  f'{esc(figure.caption)}</figcaption>', '</figure>']
    parts += ['</body>', '</html>', '']
    return '\n'.join(parts)


def _span(run: RunSeries) -> float:
    """Return the time [s] the trajectory covers (the run's duration when it has no truth)."""
    for series in (run.truth, run.odom):
        if series is not None and len(series) > 1:
            return float(series.t[-1] - series.t[0])
    return run.duration


def _is_arm(run: RunSeries) -> bool:
    """Return whether the run is a manipulator's: from its scenario, else from its topics."""
    robot = (run.scenario or {}).get('robot')
    if isinstance(robot, dict) and 'type' in robot:
        return robot['type'] == 'manipulator'
    return run.controller is not None or run.torques is not None or run.is_manipulator


def _plans(run: RunSeries, every: float) -> list[_Plan]:
    """Return the figures the run's topics allow, in the page's order."""
    plans = []
    truth, odom, cmd, controller = run.truth, run.odom, run.cmd, run.controller
    if _is_arm(run):
        if run.joint_states is not None or controller is not None:
            plans.append(_Plan('joint_positions', 'Joint positions',
                               lambda fig: _joint_figure(fig, run, 'position')))
            plans.append(_Plan('joint_velocities', 'Joint velocities',
                               lambda fig: _joint_figure(fig, run, 'velocity')))
        if run.joint_states is not None or controller is not None or run.torques is not None:
            plans.append(_Plan('joint_torques', 'Joint torques',
                               lambda fig: _joint_torques(fig, run)))
        if controller is not None:
            plans.append(_Plan('joint_errors', 'Joint position errors',
                               lambda fig: _joint_errors(fig, run, controller)))
        return plans
    if truth is not None or odom is not None or run.path is not None:
        plans.append(_Plan('trajectory', 'Trajectory in the x-y plane',
                           lambda fig: _trajectory(fig, run, every)))
    if run.tracking_error is not None:
        errors = run.tracking_error
        plans.append(_Plan('tracking_errors', 'Tracking errors',
                           lambda fig: _tracking_errors(fig, errors)))
    if cmd is not None:
        plans.append(_Plan('commands', 'Commands', lambda fig: _commands(fig, cmd, truth)))
    if truth is None:
        return plans
    if odom is not None:
        plans.append(_Plan('estimation', 'Estimation error of /odom',
                           lambda fig: _estimation(fig, odom, truth)))
    imu, compass, gps = run.imu, run.compass, run.gps
    if imu is not None:
        plans.append(_Plan('gyro', 'Gyroscope', lambda fig: _gyro(fig, imu, truth)))
    if compass is not None:
        plans.append(_Plan('compass', 'Compass', lambda fig: _compass(fig, compass, truth)))
    if gps is not None:
        origin = gps_origin(run.scenario)
        plans.append(_Plan('gps', 'GPS', lambda fig: _gps(fig, gps, truth, origin)))
    return plans


# --- drawing helpers ----------------------------------------------------------------------

def _rms(values: NDArray[np.float64]) -> float:
    finite = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(finite**2))) if finite.size else math.nan


def _max_abs(values: NDArray[np.float64]) -> float:
    finite = values[np.isfinite(values)]
    return float(np.max(np.abs(finite))) if finite.size else math.nan


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

def _trajectory(fig: 'Figure', run: RunSeries, every: float) -> str:
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


def _tracking_errors(fig: 'Figure', errors: Series) -> str:
    panels = [('cross_track', 'cross-track e_y [m]', 'm'), ('heading', 'heading e_θ [rad]', 'rad')]
    if 'along_track' in errors.columns and np.any(errors['along_track'] != 0.0):
        panels.append(('along_track', 'along-track e_x [m]', 'm'))
    axes = _time_axes(fig, len(panels))
    stats = []
    for ax, (column, label, unit) in zip(axes, panels):
        values = errors[column]
        ax.plot(errors.t, values, color='C3', linewidth=1.0)
        ax.axhline(0.0, color='k', linewidth=0.6)
        ax.set_ylabel(label)
        stats.append(f'{column.replace("_", "-")} RMS {_rms(values):.3g} {unit}, '
                     f'max |e| {_max_abs(values):.3g} {unit}')
    axes[0].set_title('Tracking errors (/path_tracker/tracking_error)')
    return ('Errors of the path tracker against its reference, as it computed them '
            '(cross-track > 0 left of the path; heading = robot minus path tangent, wrapped to '
            '(-π, π]): ' + '; '.join(stats) + '.')


def _commands(fig: 'Figure', cmd: Series, truth: Optional[Series]) -> str:
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


def _estimation(fig: 'Figure', odom: Series, truth: Series) -> str:
    panels = [('x', 'var_x', 'e_x [m]', 'm', False), ('y', 'var_y', 'e_y [m]', 'm', False),
              ('theta', 'var_theta', 'e_θ [rad]', 'rad', True)]
    axes = _time_axes(fig, 3)
    stats = []
    for ax, (column, variance, label, unit, angle) in zip(axes, panels):
        error = reading_error(odom.t, odom[column], truth.t, truth[column], angle=angle)
        ax.plot(odom.t, error, color='C3', linewidth=1.0, label='/odom - truth')
        ax.axhline(0.0, color='k', linewidth=0.6)
        text = f'{column} RMS {_rms(error):.3g} {unit}'
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


def _gyro(fig: 'Figure', imu: Series, truth: Series) -> str:
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


def _compass(fig: 'Figure', compass: Series, truth: Series) -> str:
    series, hist = _sensor_axes(fig)
    series.plot(truth.t, _wrap_breaks(np.asarray(wrap_to_pi(truth['theta']))), color='C0',
                linewidth=2.0, label='true θ')
    series.plot(compass.t, _wrap_breaks(np.asarray(wrap_to_pi(compass['theta']))),
                color='C1', linewidth=0.7, label='compass θ')
    series.set_ylim(-math.pi - 0.3, math.pi + 0.3)
    series.set_xlabel('time t [s]')
    series.set_ylabel('heading θ [rad]')
    series.set_title('Compass /compass/heading vs truth')
    series.grid(True, alpha=0.3)
    series.legend(fontsize='small', loc='lower right')
    error = reading_error(compass.t, compass['theta'], truth.t, truth['theta'], angle=True)
    mean, std, count = _histogram(hist, error, 'rad', 'θ_c - θ', 'C1')
    hist.set_title(f'Compass error, {count} readings')
    hist.legend(fontsize='x-small', loc='upper left')
    return ('Heading of the compass (yaw of /compass/heading, REP-103: from the x axis, '
            'counter-clockwise) against the true heading, both wrapped to (-π, π], and the '
            'histogram of its error (wrapped) with the fitted normal density: mean '
            f'{mean:.3g} rad, σ {std:.3g} rad.')


def _gps(fig: 'Figure', gps: Series, truth: Series, origin: GeodeticOrigin) -> str:
    enu = fixes_to_enu(origin, gps['latitude'], gps['longitude'], gps['altitude'])
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
    errors = [reading_error(gps.t, enu[:, i], truth.t, truth[c]) for i, c in enumerate('xy')]
    for error, name, colour in zip(errors, ('east', 'north'), ('C1', 'C2')):
        over_time.plot(gps.t, error, '.', color=colour, markersize=2.5, label=name)
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
    if 'var_e' in gps.columns and 'var_n' in gps.columns:
        sigma_e, sigma_n = (math.sqrt(np.nanmean(gps[c])) for c in ('var_e', 'var_n'))
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


def _joint_figure(fig: 'Figure', run: RunSeries, kind: str) -> str:
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


def _joint_torques(fig: 'Figure', run: RunSeries) -> str:
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
            peak = max(peak, _max_abs(applied[:, i]))
        if commanded is not None and i < commanded.shape[1] and commanded_series is not None:
            ax.plot(commanded_series.t, commanded[:, i], color='C1', linewidth=1.0,
                    linestyle='--', label='commanded τ')
            peak = max(peak, _max_abs(commanded[:, i]))
        peaks.append(f'{names[i]} {peak:.3g}')
        ax.set_ylabel('τ [N m]')
        ax.set_title(names[i], fontsize='medium')
    if count:
        axes[0].legend(fontsize='small', loc='best')
    fig.suptitle('Joint torques', fontsize='large')
    return ('Torque per joint [N m]: applied by the simulator (effort of /joint_states, '
            f'solid) and commanded by the controller ({source}, dashed). Peak |τ| [N m]: '
            + ', '.join(peaks) + '.')


def _joint_errors(fig: 'Figure', run: RunSeries, controller: Series) -> str:
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
        stats.append(f'{names[i]} RMS {_rms(error[:, i]):.3g} rad, max '
                     f'{_max_abs(error[:, i]):.3g} rad, final {error[-1, i]:.3g} rad')
    fig.suptitle('Joint position errors e = q_d - q', fontsize='large')
    return ('Position error of each joint, e = q_d - q [rad] (book (8.30)), as the controller '
            'computed it (/joint_controller/controller_state): ' + '; '.join(stats) + '.')
