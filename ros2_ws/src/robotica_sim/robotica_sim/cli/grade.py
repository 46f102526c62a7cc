"""
Grade recorded runs: compute their metrics and check them against a rubric.

PATH is a bag directory (as ``robotica run`` writes it: runs/<run>/bag) or a folder searched
at any depth for bags, graded in parallel. Without ``--rubric`` the metrics are printed; with
it each check is printed as metric | value | bound | PASS/FAIL, and the exit code is 1 when a
check fails. A folder gives one summary line per bag. ``--json`` writes every bag's metrics
and checks. Metrics, units and the rubric format: docs/grading.md.

Exit codes: 0 every check passed (or metrics only), 1 a check failed, a bag could not be read
or the --json file could not be written (a full disk), 2 usage error (bad arguments, a rubric
that is not valid, a --json file that cannot be created where it is asked for: refused before
the grading), 130 interrupted.
"""
import argparse
from concurrent.futures import as_completed, Future, ProcessPoolExecutor
import json
import math
import os
from pathlib import Path
import signal
import sys
import time
from typing import Any

from robotica_sim.bags.info import BagError
from robotica_sim.bags.run_record import RunRecord
from robotica_sim.cli.main import one_line
from robotica_sim.cli.options import integer, nonempty, output_problem, path
from robotica_sim.grading.metrics import compute_metrics, METRICS
from robotica_sim.grading.rubric import (Bound, check_metrics, load_rubric, resolve_rubric,
                                         Rubric)
from robotica_sim.grading.series import load_run, TOPICS

HELP = 'compute the metrics of recorded runs and check them against a rubric'
EPILOG = """examples:
  robotica grade runs/ej9_1-20261123-101500/bag                    metrics of one run
  robotica grade runs/ej9_1-20261123-101500/bag --rubric ej9_1     check a shipped rubric
  robotica grade submissions/ --rubric my_rubric.yaml --json grades.json --jobs 4
"""

# Worker processes: each holds 43 MB once NumPy and rosbags are loaded, more with a bag's data
# (the 1024 allowed before would need 44 GB and more); more than the CPUs grade no faster.
MAX_JOBS = 64
# Topics the metrics read (the sensors are left out: only `robotica report` plots them).
GRADED_TOPICS = tuple(TOPICS[role] for role in (
    'clock', 'path', 'truth', 'odom', 'cmd_vel', 'vehicle_command', 'tracking_error',
    'joint_states', 'controller', 'torques'))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica grade``."""
    parser.add_argument('path', type=path,
                        help='a bag directory, or a folder searched (any depth) for bags')
    parser.add_argument('--rubric', type=nonempty, default=None,
                        help='rubric YAML file, or the name of a shipped rubric')
    parser.add_argument('--json', type=path, default=None, metavar='OUT.json',
                        help="write every bag's metrics and checks as JSON ('-': stdout)")
    parser.add_argument('--jobs', type=integer(1, MAX_JOBS), default=os.cpu_count() or 1,
                        help=f'bags graded in parallel, at most {MAX_JOBS} (default: CPUs, '
                        f'{os.cpu_count()})')
    parser.add_argument('--quiet', action='store_true', help='no progress lines on stderr')


def find_bags(root: Path) -> list[Path]:
    """
    Return the bag directories at ``root`` or below it, sorted.

    A bag is a directory holding ``metadata.yaml`` or a storage file (``.mcap``, ``.db3``),
    so that a bag whose recorder was killed is found and reported rather than skipped.
    """
    if (root / 'metadata.yaml').is_file():
        return [root]
    found = {p.parent for pattern in ('metadata.yaml', '*.mcap', '*.db3')
             for p in root.rglob(pattern)}
    return sorted(found)


def _json_value(value: Any) -> Any:
    """Return ``value`` with non-finite floats as None (JSON has no NaN)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [_json_value(v) for v in value]
    return value


def grade_bag(bag: Path, rubric: Rubric | None) -> dict:
    """
    Grade one bag; return its JSON-ready entry (``status`` pass, fail, ok or error).

    Never raises for a bad bag: a bag that cannot be read or graded is an ``error`` entry
    with the reason.
    """
    start = time.perf_counter()
    entry: dict[str, Any] = {'bag': str(bag), 'scenario': None, 'run': None, 'status': 'error',
                             'error': None, 'metrics': {}, 'units': {}, 'notes': {},
                             'absent': {}, 'joint_names': [], 'checks': [], 'failed': []}
    try:
        run = load_run(bag, GRADED_TOPICS)
        metrics = compute_metrics(run, rubric.params if rubric else None)
    except BagError as err:
        entry['error'] = str(err)
        return entry
    except Exception as err:   # a corrupt bag can fail anywhere in decoding: report it
        entry['error'] = f'{bag}: cannot grade the bag: {type(err).__name__}: {err}'
        return entry
    entry.update(scenario=run.scenario_name, run=_run_entry(run.run),
                 joint_names=list(metrics.joint_names),
                 metrics={k: _json_value(v) for k, v in metrics.values.items()},
                 units={k: METRICS[k].unit for k in metrics.values},
                 notes=metrics.notes, absent=metrics.absent, status='ok')
    if rubric is not None:
        results = check_metrics(rubric, metrics, run.scenario_name)
        entry['checks'] = [
            {'metric': r.metric, 'value': _json_value(r.value),
             'min': r.bound.lower if r.bound else None,
             'max': r.bound.upper if r.bound else None,
             'passed': r.passed, 'message': r.message} for r in results]
        entry['failed'] = [r.metric for r in results if not r.passed]
        entry['status'] = 'fail' if entry['failed'] else 'pass'
    entry['seconds'] = round(time.perf_counter() - start, 3)
    return entry


def _run_entry(record: RunRecord) -> dict:
    """Return what ran as the bag records it: settings (and as text), nodes not ours."""
    return {'settings': record.settings, 'settings_from': record.settings_from,
            'overrides': record.overrides, 'ended': record.ended,
            'text': dict(record.lines()).get('Run', ''),
            'nodes_not_started_by_robotica': [n.name for n in record.foreign_nodes]}


def _run_line(run: dict | None) -> str:
    """
    Return the line of what ran, '' when the bag records nothing of it.

    >>> _run_line({'text': 'pacing realtime (as run)', 'nodes_not_started_by_robotica': ['me']})
    'run: pacing realtime (as run); not started by robotica run: me'
    """
    if not run:
        return ''
    parts = [run['text']] if run['text'] else []
    if run['nodes_not_started_by_robotica']:
        parts.append('not started by robotica run: '
                     + ', '.join(run['nodes_not_started_by_robotica']))
    return 'run: ' + '; '.join(parts) if any(parts) else ''


def _format_value(value: Any) -> str:
    if value is None:
        return 'n/a'
    if isinstance(value, bool):
        return 'yes' if value else 'no'
    if isinstance(value, list):
        return '[' + ', '.join(_format_value(v) for v in value) + ']'
    if isinstance(value, float):
        return f'{value:.4g}'
    return str(value)


def _table(header: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ['  '.join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip()
             for row in [header, *rows]]
    lines.insert(1, '  '.join('-' * w for w in widths))
    return '\n'.join(lines)


def format_entry(entry: dict) -> str:
    """Return one bag's metrics (or checks, when graded with a rubric) as a table."""
    lines = [f'bag: {entry["bag"]}' + (f' (scenario {entry["scenario"]})'
                                       if entry['scenario'] else '')]
    lines += [line for line in [_run_line(entry.get('run'))] if line]
    if entry['checks']:
        rows = []
        for check in entry['checks']:
            bound = ('' if check['min'] is None and check['max'] is None
                     else Bound(check['min'], check['max']).text())
            unit = METRICS[check['metric']].unit if check['metric'] in METRICS else ''
            rows.append([check['metric'], _format_value(check['value']), unit, bound,
                         'PASS' if check['passed'] else 'FAIL'])
        lines.append(_table(['metric', 'value', 'unit', 'bound', 'result'], rows))
        # The reasons the table does not show: absent or n/a metrics, joints, the scenario.
        lines.extend(f'  {c["metric"]}: {c["message"]}' for c in entry['checks']
                     if not c['passed'] and not isinstance(c['value'], (int, float)))
        failed = entry['failed']
        lines.append(f'{"FAIL" if failed else "PASS"}: {len(entry["checks"]) - len(failed)}/'
                     f'{len(entry["checks"])} checks passed')
    else:
        rows = [[name, _format_value(value), entry['units'][name],
                 entry['notes'].get(name, '')] for name, value in entry['metrics'].items()]
        lines.append(_table(['metric', 'value', 'unit', 'note'], rows))
    return '\n'.join(lines)


def format_summary(entries: list[dict], root: Path) -> str:
    """Return the one-line-per-bag summary of a folder."""
    def name(entry: dict) -> str:
        bag = Path(entry['bag'])
        return str(bag.relative_to(root)) if bag.is_relative_to(root) else str(bag)
    rows = [[name(e), e['status'].upper(),
             e['error'] if e['status'] == 'error' else ', '.join(e['failed'])]
            for e in entries]
    counts = {s: sum(e['status'] == s for e in entries) for s in ('pass', 'fail', 'ok', 'error')}
    tally = ', '.join(f'{n} {s}' for s, n in counts.items() if n)
    return (_table(['bag', 'result', 'failed checks'], rows)
            + f'\n{len(entries)} bag{"s" if len(entries) != 1 else ""}: {tally}')


def _leave_signals_to_the_parent() -> None:
    """Ignore Ctrl-C and SIGTERM in a worker: the parent cancels the pool and says so, once."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)


def _grade_all(bags: list[Path], rubric: Rubric | None, jobs: int, quiet: bool) -> list[dict]:
    """Grade the bags (in a process pool when more than one job); progress on stderr."""
    def progress(done: int, entry: dict) -> None:
        if not quiet:
            print(f'graded {done}/{len(bags)} {entry["bag"]}: {entry["status"].upper()}',
                  file=sys.stderr, flush=True)
    entries: dict[Path, dict] = {}
    if jobs == 1 or len(bags) == 1:
        for bag in bags:
            entries[bag] = grade_bag(bag, rubric)
            if len(bags) > 1:
                progress(len(entries), entries[bag])
        return [entries[bag] for bag in bags]
    with ProcessPoolExecutor(max_workers=min(jobs, len(bags)),
                             initializer=_leave_signals_to_the_parent) as pool:
        # Largest bags first, so that the last one to finish is a small one.
        by_size = sorted(bags, key=lambda bag: -sum(
            f.stat().st_size for f in bag.iterdir() if f.is_file()))
        futures: dict[Future, Path] = {pool.submit(grade_bag, bag, rubric): bag
                                       for bag in by_size}
        try:
            for future in as_completed(futures):
                entries[futures[future]] = future.result()
                progress(len(entries), entries[futures[future]])
        except KeyboardInterrupt:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
    return [entries[bag] for bag in bags]


def main(args: argparse.Namespace) -> int:
    """Grade the bag or folder; return the exit code."""
    # A RubricError is one line and exit 2 (robotica_sim.cli.main).
    rubric = None if args.rubric is None else load_rubric(resolve_rubric(args.rubric))
    to_stdout = args.json is not None and str(args.json) == '-'
    if args.json is not None and not to_stdout:   # before the grading, not after it
        problem = output_problem(args.json)
        if problem:
            print(f'robotica grade: error: cannot write {args.json}: {problem}', file=sys.stderr)
            return 2
    root: Path = args.path
    if not root.is_dir():
        print(f'robotica grade: {root}: not a bag directory or a folder of bags',
              file=sys.stderr)
        return 1
    bags = find_bags(root)
    if not bags:
        print(f'robotica grade: {root}: no bags found (a bag is a directory with '
              'metadata.yaml)', file=sys.stderr)
        return 1
    try:
        entries = _grade_all(bags, rubric, args.jobs, args.quiet)
    except KeyboardInterrupt:
        print('robotica grade: interrupted', file=sys.stderr)
        return 130
    single = bags == [root]
    if single and entries[0]['status'] == 'error':
        print(f'robotica grade: {one_line(entries[0]["error"])}', file=sys.stderr)
    elif not to_stdout:
        print(format_entry(entries[0]) if single else format_summary(entries, root))
    if args.json is not None:
        report = {'path': str(root),
                  'rubric': None if rubric is None else {'title': rubric.title,
                                                         'source': rubric.source},
                  'bags': entries}
        text = json.dumps(report, indent=2)
        if to_stdout:
            print(text)
        else:
            try:
                out = open(args.json, 'w')
            except OSError as err:   # where it was asked for: a usage error
                print(f'robotica grade: error: cannot write {args.json}: '
                      f'{err.strerror or err}', file=sys.stderr)
                return 2
            with out:   # a failed write (a full disk) is an I/O error: exit 1 (cli.main)
                out.write(text + '\n')
    return 0 if all(e['status'] in ('pass', 'ok') for e in entries) else 1
