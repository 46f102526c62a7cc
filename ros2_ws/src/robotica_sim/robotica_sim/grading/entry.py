"""
One bag graded: its metrics and, with a rubric, its checks, as a JSON-ready entry.

:func:`grade_bag` is what ``robotica grade`` computes for each bag, and what a sweep's job
(:mod:`robotica_sim.batch.job`) and a batch grading (:mod:`robotica_sim.batch.grading`)
compute on a Dask worker. It never raises for a bad bag: the entry says ``error`` and why.
The same bag gives the same entry (``seconds``, the time it took, aside).
"""
import math
from pathlib import Path
import time
from typing import Any, Optional

from robotica_sim.bags.info import BagError
from robotica_sim.bags.run_record import RunRecord
from robotica_sim.grading.metrics import compute_metrics, METRICS
from robotica_sim.grading.rubric import Bound, check_metrics, Rubric
from robotica_sim.grading.series import load_run, TOPICS
from robotica_sim.grading.summary import incomplete_text, missing_messages

__all__ = ['GRADED_TOPICS', 'format_entry', 'format_value', 'grade_bag', 'json_value', 'table']

# Topics the metrics read (the sensors are left out: only `robotica report` plots them).
GRADED_TOPICS = tuple(TOPICS[role] for role in (
    'clock', 'path', 'truth', 'odom', 'cmd_vel', 'vehicle_command', 'tracking_error',
    'joint_states', 'controller', 'trajectory', 'torques', 'bumper', 'status'))


def json_value(value: Any) -> Any:
    """
    Return ``value`` with non-finite floats as None (JSON has no NaN).

    >>> json_value([1.0, float('nan')])
    [1.0, None]
    """
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [json_value(v) for v in value]
    return value


def grade_bag(bag: Path, rubric: Optional[Rubric]) -> dict:
    """
    Grade one bag; return its JSON-ready entry (``status`` pass, fail, ok or error).

    Never raises for a bad bag: a bag that cannot be read or graded is an ``error`` entry
    with the reason. A check on a metric the bag lacks has ``missing`` true (and fails).
    """
    start = time.perf_counter()
    entry: dict[str, Any] = {'bag': str(bag), 'scenario': None, 'run': None, 'status': 'error',
                             'incomplete': '',
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
    missing = missing_messages(run)
    entry['incomplete'] = ('' if run.status is None else incomplete_text(
        missing, int(run.status['step']), int(run.status['lockstep_timeouts'])))
    entry.update(scenario=run.scenario_name, run=_run_entry(run.run),
                 joint_names=list(metrics.joint_names),
                 metrics={k: json_value(v) for k, v in metrics.values.items()},
                 units={k: METRICS[k].unit for k in metrics.values},
                 notes=metrics.notes, absent=metrics.absent, status='ok')
    if rubric is not None:
        results = check_metrics(rubric, metrics, run.scenario_name)
        entry['checks'] = [
            {'metric': r.metric, 'value': json_value(r.value),
             'min': r.bound.lower if r.bound else None,
             'max': r.bound.upper if r.bound else None,
             'passed': r.passed, 'missing': r.metric in metrics.absent,
             'message': r.message} for r in results]
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


def format_value(value: Any) -> str:
    """Return a metric's value as the tables print it (4 significant digits, n/a)."""
    if value is None:
        return 'n/a'
    if isinstance(value, bool):
        return 'yes' if value else 'no'
    if isinstance(value, list):
        return '[' + ', '.join(format_value(v) for v in value) + ']'
    if isinstance(value, float):
        return f'{value:.4g}'
    return str(value)


def table(header: list[str], rows: list[list[str]]) -> str:
    """Return ``rows`` under ``header`` as a text table, columns padded to their widest."""
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
    if entry.get('incomplete'):   # the metrics measure what was recorded, not what ran
        lines.append(f'warning: the recording is incomplete: {entry["incomplete"]}')
    if entry['checks']:
        rows = []
        for check in entry['checks']:
            bound = ('' if check['min'] is None and check['max'] is None
                     else Bound(check['min'], check['max']).text())
            unit = METRICS[check['metric']].unit if check['metric'] in METRICS else ''
            rows.append([check['metric'], format_value(check['value']), unit, bound,
                         'PASS' if check['passed'] else 'FAIL'])
        lines.append(table(['metric', 'value', 'unit', 'bound', 'result'], rows))
        # The reasons the table does not show: absent or n/a metrics, joints, the scenario.
        lines.extend(f'  {c["metric"]}: {c["message"]}' for c in entry['checks']
                     if not c['passed'] and not isinstance(c['value'], (int, float)))
        failed = entry['failed']
        lines.append(f'{"FAIL" if failed else "PASS"}: {len(entry["checks"]) - len(failed)}/'
                     f'{len(entry["checks"])} checks passed')
    else:
        rows = [[name, format_value(value), entry['units'][name],
                 entry['notes'].get(name, '')] for name, value in entry['metrics'].items()]
        lines.append(table(['metric', 'value', 'unit', 'note'], rows))
    return '\n'.join(lines)
