"""
An HTML page of a recorded run and its figures: what ``robotica report`` writes.

:func:`write_report` takes the time series of a run
(:class:`robotica_sim.grading.series.RunSeries`,
read by :func:`robotica_sim.grading.series.load_run`), chooses the figures its topics allow,
draws each with :mod:`robotica_sim.grading.figures` into a PNG file (Matplotlib's Agg
renderer, 8 x 5 in at 100 dpi) and writes an ``index.html`` (:func:`render_html`) that shows
them with their captions, beside the scenario, the simulator's status and the bag's topics. A
figure is drawn only when the bag holds the topics it needs:

* mobile robot: ``trajectory`` (/ground_truth/odom, /odom or /path; in a run with a world,
  the scenario's ``world:`` section or /map, also the world, the readings of /scan,
  /sonar_<i> and /infrared_<i> at intervals and the contacts of /bumper), ``tracking_errors``
  (/ground_truth/odom and /path, or /path_tracker/tracking_error), ``commands`` (/cmd_vel or
  /vehicle_command); with the ground truth also ``estimation`` (/odom), ``gyro``
  (/imu/data), ``compass`` (/compass/heading) and ``gps`` (/gps/fix, in the ENU frame of the
  scenario's ``sensors.gps.origin``);
* manipulator (book ch. 8): ``joint_positions``, ``joint_velocities``, ``joint_torques`` and
  ``joint_errors`` (/joint_states, /joint_controller/controller_state, /joint_torques).

Matplotlib is imported only when the figures are drawn, never at import.
"""
from dataclasses import dataclass
import html
from pathlib import Path
from typing import Callable, Optional, TYPE_CHECKING

from robotica_sim.grading import figures
from robotica_sim.grading.metrics import MetricParams
from robotica_sim.grading.series import gps_origin, run_world, RunSeries

if TYPE_CHECKING:   # Matplotlib is imported lazily, when figures are drawn
    from matplotlib.figure import Figure

__all__ = ['default_output', 'FigureFile', 'render_html', 'Report', 'ReportError',
           'write_report']


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
        :func:`~robotica_sim.grading.figures.auto_robot_every` of the time the true (else
        the /odom) trajectory covers.
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
    every = robot_every if robot_every is not None else figures.auto_robot_every(_span(run))
    plans = _plans(run, every)
    if not plans:
        raise ReportError(
            f'{run.bag}: nothing to plot: a mobile run needs /ground_truth/odom, /odom, /path, '
            '/cmd_vel or /vehicle_command, /path_tracker/tracking_error; an arm run '
            '/joint_states or /joint_controller/controller_state')
    from matplotlib.figure import Figure

    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for number, plan in enumerate(plans, start=1):
        if progress is not None:
            progress(f'figure {number}/{len(plans)}: {plan.name}')
        fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
        caption = plan.draw(fig)
        fig.tight_layout()
        path = out / f'{plan.name}.png'
        fig.savefig(path, dpi=figures.DPI)
        written.append(FigureFile(path, plan.title, caption))
    index = out / 'index.html'
    index.write_text(render_html(run, written), encoding='utf-8')
    return Report(index, tuple(written))


def render_html(run: RunSeries, files: list[FigureFile]) -> str:
    """
    Return the report page: what ran, status, topics and the figures with their captions.

    What ran is the bag's record (:meth:`robotica_sim.bags.run_record.RunRecord.lines`): the
    settings as run (the scenario file's only for a bag that records none, said so) and the
    nodes, a user's marked as not started by ``robotica run``.
    """
    scenario = run.scenario or {}
    name = str(run.scenario_name or run.bag.name)
    rows = [('bag', str(run.bag)), ('duration', f'{run.duration:.3f} s (simulated)')]
    rows += [(label.lower(), text) for label, text in run.run.lines()]
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
    parts += [f'<li><a href="#{esc(f.path.stem)}">{esc(f.title)}</a></li>' for f in files]
    parts.append('</ol>')
    for number, figure in enumerate(files, start=1):
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
    """
    Return whether the run is a manipulator's: from its topics, else from its scenario.

    The topics are what was recorded: a bag with joint topics and no mobile one is an arm's
    whatever its scenario says (and the reverse), so that a scenario that does not describe
    the bag cannot hide what it holds. A bag with both or neither follows its scenario.
    """
    arm = any(s is not None for s in (run.joint_states, run.controller, run.torques))
    mobile = any(s is not None for s in (run.truth, run.odom, run.cmd, run.tracking_error)) \
        or run.path is not None
    if arm != mobile:
        return arm
    robot = (run.scenario or {}).get('robot')
    if isinstance(robot, dict) and 'type' in robot:
        return robot['type'] == 'manipulator'
    return run.controller is not None or run.torques is not None


def _plans(run: RunSeries, every: float) -> list[_Plan]:
    """Return the figures the run's topics allow, in the page's order."""
    plans = []
    truth, odom, cmd, controller = run.truth, run.odom, run.cmd, run.controller
    if _is_arm(run):
        if run.joint_states is not None or controller is not None:
            plans.append(_Plan('joint_positions', 'Joint positions',
                               lambda fig: figures.joint_figure(fig, run, 'position')))
            plans.append(_Plan('joint_velocities', 'Joint velocities',
                               lambda fig: figures.joint_figure(fig, run, 'velocity')))
        if run.joint_states is not None or controller is not None or run.torques is not None:
            plans.append(_Plan('joint_torques', 'Joint torques',
                               lambda fig: figures.joint_torques(fig, run)))
        if controller is not None:
            plans.append(_Plan('joint_errors', 'Joint position errors',
                               lambda fig: figures.joint_errors(fig, run, controller)))
        return plans
    if truth is not None or odom is not None or run.path is not None:
        title = ('Trajectory in the world' if run_world(run) is not None
                 else 'Trajectory in the x-y plane')
        plans.append(_Plan('trajectory', title, lambda fig: figures.trajectory(fig, run, every)))
    if (truth is not None and run.path is not None and len(run.path) >= 2
            or run.tracking_error is not None):
        window = MetricParams().search_window   # as `robotica grade` without a rubric
        plans.append(_Plan('tracking_errors', 'Tracking errors',
                           lambda fig: figures.tracking_errors(fig, run, window)))
    if cmd is not None:
        plans.append(_Plan('commands', 'Commands',
                           lambda fig: figures.commands(fig, cmd, truth)))
    if truth is None:
        return plans
    if odom is not None:
        plans.append(_Plan('estimation', 'Estimation error of /odom',
                           lambda fig: figures.estimation(fig, odom, truth)))
    imu, compass, gps = run.imu, run.compass, run.gps
    if imu is not None:
        plans.append(_Plan('gyro', 'Gyroscope', lambda fig: figures.gyro(fig, imu, truth)))
    if compass is not None:
        plans.append(_Plan('compass', 'Compass',
                           lambda fig: figures.compass(fig, compass, truth)))
    if gps is not None:
        origin = gps_origin(run.scenario)
        plans.append(_Plan('gps', 'GPS', lambda fig: figures.gps(fig, gps, truth, origin)))
    return plans
