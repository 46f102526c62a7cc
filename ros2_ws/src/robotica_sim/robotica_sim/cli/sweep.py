"""
Sweep a scenario's parameters: run every combination on a Dask cluster, grade it, plot it.

``--vary KEY=V1,V2,...`` (repeatable: the cartesian product) varies a dotted key of the
scenario (``tracker.lookahead_distance``, ``robot.wheel_radius``, ``duration``); ``--seeds N``
runs each combination with seeds 0..N-1. Every combination is validated before any run starts
(an unknown key or a bad value is one line, exit 2). Each run is ``robotica run`` in its own
folder with its own ROS domain id (from ``--domain-ids``; two runs at once never share one),
on a local Dask cluster of ``--workers`` processes or on the cluster at ``--scheduler``. A run
that fails is reported and the others go on. The output folder holds scenarios/ and runs/
(one per run), results.csv, results.json and <metric>.png (the metric against the first
varied key: each run and the mean). How a course runs this on its machines: docs/sweeps.md.

Exit codes: 0 every run succeeded, 1 some runs failed (listed), 2 usage error (a bad --vary,
an unknown key or invalid value, an unknown metric or rubric, an output folder that exists),
130 interrupted (the cluster is closed and every run stopped).
"""
import argparse
import csv
import json
import math
from pathlib import Path
import random
import sys
import time
from typing import Any, Optional

from robotica_sim.batch.cluster import dask_client, default_workers, map_on_cluster
from robotica_sim.batch.job import run_job, RunJob
from robotica_sim.batch.sweep import (parse_domain_ids, parse_vary, sweep_runs, SweepRun,
                                      write_scenarios)
from robotica_sim.cli.options import integer, nonempty, output_problem, path, real
from robotica_sim.grading.entry import format_value, table
from robotica_sim.grading.metrics import METRICS
from robotica_sim.grading.rubric import load_rubric, resolve_rubric, Rubric, RubricError

HELP = 'run a scenario over a grid of parameter values on a Dask cluster, grade and plot it'
EPILOG = """examples:
  robotica sweep demo --vary tracker.lookahead_distance=0.5,1,2,4 --seeds 5
  robotica sweep ej9_1 --vary tracker.lookahead_distance=0.5,1 --vary robot.wheelbase=0.5,1
  robotica sweep demo --vary tracker.desired_linear_velocity=0.25,0.5 --duration 10 \\
      --workers 2 --domain-ids 40-60 --output sweeps/speed
  robotica sweep demo --vary tracker.lookahead_distance=0.5,1,2 --scheduler tcp://10.0.0.5:8786
"""
MAX_WORKERS = 256


def _domains(text: str) -> tuple[int, ...]:
    try:
        return parse_domain_ids(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica sweep``."""
    parser.add_argument('scenario', type=nonempty,
                        help='scenario YAML file, or the name of a shipped one')
    parser.add_argument('--vary', action='append', default=[], metavar='KEY=V1,V2,...',
                        help='a dotted scenario key and its values (repeat: every '
                        'combination)')
    parser.add_argument('--seeds', type=integer(1, 1000), default=None, metavar='N',
                        help='run each combination with seeds 0..N-1 (default: the '
                        "scenario's seed, once)")
    parser.add_argument('--rubric', type=nonempty, default=None,
                        help='rubric YAML file or shipped name (default: the shipped rubric '
                        "of the scenario's name, if any; else metrics only)")
    parser.add_argument('--metric', type=nonempty, default=None,
                        help='metric to plot (default: rms_cross_track, or rms_joint_error '
                        'for an arm)')
    parser.add_argument('--output', type=path, default=None, metavar='DIR',
                        help='output folder, must not exist (default: sweeps/<name>-<time>)')
    parser.add_argument('--duration', type=real(0.0, 1e7, low_open=True), default=None,
                        help="override the scenario's duration in every run [s, simulated]")
    parser.add_argument('--visualisation', choices=['on', 'off'], default='off',
                        help='/tf, markers and the state publisher in each run')
    parser.add_argument('--workers', type=integer(1, MAX_WORKERS), default=None,
                        help='worker processes of the local Dask cluster, one run each at a '
                        f'time (default: CPUs, {default_workers()}, at most the runs)')
    parser.add_argument('--scheduler', type=nonempty, default=None, metavar='ADDRESS',
                        help='run on the Dask cluster of this scheduler (tcp://HOST:8786) '
                        'instead of a local one')
    parser.add_argument('--domain-ids', type=_domains, default=parse_domain_ids('1-101'),
                        metavar='IDS', help='pool of ROS domain ids for the runs (40-60 or '
                        '40,41,45); runs at once never share one (default: 1-101)')
    parser.add_argument('--json', action='store_true', help='print the results as JSON')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')


def _log(args: argparse.Namespace, text: str) -> None:
    if not args.quiet:
        print(f'[robotica sweep] {text}', file=sys.stderr, flush=True)


def _rubric(args: argparse.Namespace, name: str) -> Optional[Rubric]:
    if args.rubric is not None:
        return load_rubric(resolve_rubric(args.rubric))   # a RubricError: exit 2
    try:
        return load_rubric(resolve_rubric(name))
    except RubricError:
        return None


def _metric_value(value: Any) -> float:
    """Return a metric's value for the plot: a per-joint list by its largest joint."""
    if isinstance(value, list):
        finite = [v for v in value if isinstance(v, (int, float)) and math.isfinite(v)]
        return max(finite) if finite else math.nan
    if isinstance(value, bool):
        return float(value)
    return float(value) if isinstance(value, (int, float)) else math.nan


def _cell(value: Any) -> Any:
    if value is None:
        return ''
    return json.dumps(value) if isinstance(value, (list, dict)) else value


def write_results(results: list[dict], keys: list[str], output: Path) -> None:
    """Write results.csv (one row per run) and results.json into ``output``."""
    metrics = [m for m in METRICS if any(m in r['metrics'] for r in results)]
    with open(output / 'results.csv', 'w', newline='', encoding='utf-8') as out:
        writer = csv.writer(out)
        writer.writerow(['run', 'status', *keys, 'domain_id', *metrics, 'checks_passed',
                         'checks', 'wall_time', 'error', 'run_dir'])
        for r in results:
            writer.writerow([r['run'], r['status'], *[_cell(r['settings'].get(k)) for k in keys],
                             r['domain_id'], *[_cell(r['metrics'].get(m)) for m in metrics],
                             sum(c['passed'] for c in r['checks']), len(r['checks']),
                             _cell(r['wall_time']), r['error'] or '', r['run_dir']])
    (output / 'results.json').write_text(json.dumps({'runs': results}, indent=2) + '\n',
                                         encoding='utf-8')


def plot_results(results: list[dict], keys: list[str], metric: str, output: Path) -> Path:
    """Draw ``metric`` against the first varied key into ``<metric>.png``; return the file."""
    from matplotlib.figure import Figure
    from robotica_sim.grading import figures

    x_key = keys[0] if keys else 'seed'
    # One line per value of the other varied keys; the seeds are averaged over.
    others = [k for k in keys[1:] if k != 'seed']
    points = []
    for r in results:
        if r['status'] != 'ok' or metric not in r['metrics']:
            continue
        group = ', '.join(f'{k}={r["settings"][k]}' for k in others)
        points.append((r['settings'].get(x_key, 0), group, _metric_value(r['metrics'][metric])))
    fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
    figures.sweep_metric(fig, x_key, points, metric, METRICS[metric].unit)
    fig.tight_layout()
    file = output / f'{metric}.png'
    fig.savefig(file, dpi=figures.DPI)
    return file


def _jobs(args, runs: list[SweepRun], files: dict, output: Path, rubric) -> list[RunJob]:
    ids = list(args.domain_ids)
    # Another sweep on this machine may use the same default pool: start at a random id.
    if args.domain_ids == parse_domain_ids('1-101'):
        turn = random.randrange(len(ids))
        ids = ids[turn:] + ids[:turn]
    return [RunJob(run.name, str(files[run.name].resolve()),
                   str((output / 'runs' / run.name).resolve()), run.settings, tuple(ids),
                   rubric, timeout=2.0 * (120.0 + 10.0 * run.scenario.duration))
            for run in runs]


def _print(args, results: list[dict], keys: list[str], metric: str, output: Path) -> None:
    if args.json:
        print(json.dumps({'output': str(output), 'metric': metric, 'runs': results}))
        return
    rows = [[r['run'], *[str(r['settings'].get(k, '')) for k in keys], r['status'].upper(),
             format_value(r['metrics'].get(metric)) if r['status'] == 'ok' else '',
             f'{sum(c["passed"] for c in r["checks"])}/{len(r["checks"])}' if r['checks']
             else ''] for r in results]
    print(table(['run', *keys, 'status', metric, 'checks'], rows))
    for r in results:
        if r['status'] != 'ok':
            print(f'{r["run"]} failed: {r["error"]} (folder {r["run_dir"]})')
    print(f'output: {output}')


def main(args: argparse.Namespace) -> int:
    """Run the sweep; return the exit code."""
    # Every problem of the command line and of every combination before anything starts; a
    # ScenarioError or RubricError is one line and exit 2 (robotica_sim.cli.main).
    variations = [parse_vary(text) for text in args.vary]
    fixed: dict[str, Any] = {'visualisation': args.visualisation == 'on'}
    if args.duration is not None:
        fixed['duration'] = args.duration
    runs = sweep_runs(args.scenario, variations, args.seeds, fixed)
    name = runs[0].scenario.name
    metric = args.metric or ('rms_joint_error' if runs[0].scenario.is_manipulator
                             else 'rms_cross_track')
    if metric not in METRICS:
        print(f'robotica sweep: error: unknown metric {metric!r}; known: '
              f'{", ".join(METRICS)}', file=sys.stderr)
        return 2
    rubric = _rubric(args, name)
    output = args.output or Path('sweeps') / f'{name}-{time.strftime("%Y%m%d-%H%M%S")}'
    if output.exists():
        print(f'robotica sweep: error: {output} exists already', file=sys.stderr)
        return 2
    problem = output_problem(output, directory=True)
    if problem:
        print(f'robotica sweep: error: cannot write {output}: {problem}', file=sys.stderr)
        return 2
    keys = [v.key for v in variations] + (['seed'] if args.seeds is not None else [])
    jobs = _jobs(args, runs, write_scenarios(runs, output / 'scenarios'), output, rubric)
    workers = min(args.workers or default_workers(), len(jobs), len(args.domain_ids))
    where = args.scheduler or f'a local cluster of {workers} worker{"s" * (workers > 1)}'
    _log(args, f'{len(jobs)} runs of {name} on {where}; output {output}'
               + (f'; rubric {rubric.title}' if rubric else ''))
    failed = 0

    def progress(done: int, result: dict) -> None:
        nonlocal failed
        failed += result['status'] != 'ok'
        _log(args, f'{done}/{len(jobs)} done, {failed} failed'
                   + (f' ({result["run"]}: {result["error"]})' if result['status'] != 'ok'
                      else ''))
    try:
        with dask_client(workers, args.scheduler) as client:
            results = map_on_cluster(client, run_job, jobs, [j.name for j in jobs], progress)
    except KeyboardInterrupt:
        print('robotica sweep: interrupted; the cluster is closed and its runs stopped',
              file=sys.stderr)
        return 130
    write_results(results, keys, output)
    if any(r['status'] == 'ok' and metric in r['metrics'] for r in results):
        _log(args, f'plot: {plot_results(results, keys, metric, output)}')
    else:
        _log(args, f'no plot: no run gave {metric}')
    _print(args, results, keys, metric, output)
    return 1 if any(r['status'] != 'ok' for r in results) else 0
