"""
A folder of submissions graded: one row per student's run, as a table, CSV, JSON and reports.

A submission folder holds one folder per student: either one bag (``DIR/<student>/bag`` or
``DIR/<student>/metadata.yaml``) or several runs (``DIR/<student>/<run>/bag``). The student
is the first folder of a bag's path under ``DIR``, the run the rest of it (without a last
``bag``). Each bag's entry is :func:`robotica_sim.grading.entry.grade_bag`'s. A check on a
metric the bag cannot provide is ``missing`` (never 0): it fails, and the cell says so. The
files leave out what varies between two gradings of the same bags (the time taken), so that
the grades of a bag are the same every time.
"""
import csv
import json
from pathlib import Path
from typing import Any, Optional

from robotica_sim.grading.entry import format_entry, format_value, table

__all__ = ['MISSING', 'check_cell', 'student_run', 'submission_rows', 'submissions_table',
           'write_submissions']

MISSING = 'missing'
"""The cell of a check whose metric the bag cannot provide."""


def student_run(bag: Path, root: Path) -> tuple[str, str]:
    """
    Return the student and the run of ``bag`` in the submission folder ``root``.

    >>> student_run(Path('sub/ana/ej9_1/bag'), Path('sub'))
    ('ana', 'ej9_1')
    >>> student_run(Path('sub/ana/bag'), Path('sub'))
    ('ana', '')
    """
    parts = list(bag.relative_to(root).parts) if bag.is_relative_to(root) else [bag.name]
    if not parts:   # the root is the bag
        return root.name, ''
    if len(parts) > 1 and parts[-1] == 'bag':
        parts = parts[:-1]
    return parts[0], '/'.join(parts[1:])


def check_cell(check: dict) -> str:
    """
    Return a check's cell: its value and PASS or FAIL, or ``missing``.

    >>> check_cell({'value': 0.05, 'passed': True, 'missing': False})
    '0.05 PASS'
    >>> check_cell({'value': None, 'passed': False, 'missing': True})
    'missing'
    """
    if check.get('missing'):
        return MISSING
    return f'{format_value(check["value"])} {"PASS" if check["passed"] else "FAIL"}'


def _checks(entries: list[dict]) -> list[str]:
    names: list[str] = []
    for entry in entries:
        names += [c['metric'] for c in entry['checks'] if c['metric'] not in names]
    return names


def submission_rows(entries: list[dict], root: Path) -> list[dict]:
    """
    Return one row per bag, sorted by student and run: what the table, CSV and JSON hold.

    A row: ``student``, ``run``, ``bag``, ``status`` (pass, fail, ok, error), ``passed`` and
    ``checks`` (counts), ``error``, ``checks_by_metric`` (each check's value, None when
    missing, passed, missing and message) and ``metrics`` (every metric's value; absent ones
    left out).
    """
    rows = []
    for entry in entries:
        student, run = student_run(Path(entry['bag']), root)
        rows.append({
            'student': student, 'run': run, 'bag': entry['bag'], 'status': entry['status'],
            'passed': sum(c['passed'] for c in entry['checks']),
            'checks': len(entry['checks']), 'error': entry['error'],
            'checks_by_metric': {c['metric']: {
                **{k: c.get(k) for k in ('value', 'min', 'max', 'passed', 'missing',
                                         'message')},
                **({'value': None} if c.get('missing') else {})} for c in entry['checks']},
            'metrics': entry['metrics'], 'absent': entry['absent']})
    return sorted(rows, key=lambda r: (r['student'], r['run']))


def _total(row: dict) -> str:
    if row['status'] == 'error':
        return 'ERROR'
    return f'{row["passed"]}/{row["checks"]}' if row['checks'] else row['status'].upper()


def submissions_table(rows: list[dict]) -> str:
    """Return the table: student, run, one column per check (value PASS/FAIL), total."""
    checks = sorted({m for r in rows for m in r['checks_by_metric']},
                    key=lambda m: (m != 'scenario', m))
    body = [[r['student'], r['run'] or '-',
             *[check_cell(r['checks_by_metric'][m]) if m in r['checks_by_metric'] else ''
               for m in checks], _total(r)] for r in rows]
    text = table(['student', 'run', *checks, 'total'], body)
    errors = [f'  {r["student"]}{"/" + r["run"] if r["run"] else ""}: {r["error"]}'
              for r in rows if r['status'] == 'error']
    return '\n'.join([text, *errors])


def _csv_value(value: Any) -> Any:
    if value is None:
        return ''
    if isinstance(value, list):
        return json.dumps(value)
    return value


def write_submissions(entries: list[dict], root: Path, output: Path,
                      rubric: Optional[dict]) -> dict[str, Path]:
    """
    Write ``grades.csv``, ``grades.json`` and ``reports/<student>.md`` into ``output``.

    Returns the files written by kind (``csv``, ``json``, ``reports``: the folder).
    """
    rows = submission_rows(entries, root)
    checks = sorted({m for r in rows for m in r['checks_by_metric']})
    metrics = sorted({m for r in rows for m in r['metrics']}) if not checks else []
    output.mkdir(parents=True, exist_ok=True)
    files = {'csv': output / 'grades.csv', 'json': output / 'grades.json',
             'reports': output / 'reports'}
    with open(files['csv'], 'w', newline='', encoding='utf-8') as out:
        writer = csv.writer(out)
        writer.writerow(['student', 'run', 'status', 'passed', 'checks',
                         *[f'{m}{suffix}' for m in checks for suffix in ('', '_result')],
                         *metrics, 'error', 'bag'])
        for r in rows:
            cells = []
            for m in checks:
                check = r['checks_by_metric'].get(m)
                if check is None:
                    cells += ['', '']
                elif check['missing']:
                    cells += [MISSING, MISSING]
                else:
                    cells += [_csv_value(check['value']), 'pass' if check['passed'] else 'fail']
            writer.writerow([r['student'], r['run'], r['status'], r['passed'], r['checks'],
                             *cells, *[_csv_value(r['metrics'].get(m)) if m in r['metrics']
                                       else MISSING for m in metrics],
                             r['error'] or '', r['bag']])
    students = sorted({r['student'] for r in rows})
    report = {'path': str(root), 'rubric': rubric, 'students': [
        {'student': s, 'runs': [{k: v for k, v in r.items() if k != 'student'}
                                for r in rows if r['student'] == s]} for s in students]}
    files['json'].write_text(json.dumps(report, indent=2) + '\n', encoding='utf-8')
    files['reports'].mkdir(exist_ok=True)
    by_bag = {e['bag']: e for e in entries}
    for s in students:
        mine = [r for r in rows if r['student'] == s]
        lines = [f'# {s}', '']
        for r in mine:
            entry = by_bag[r['bag']]
            lines += [f'## {r["run"] or "run"}: {_total(r)}', '', '```',
                      format_entry(entry) if entry['status'] != 'error' else entry['error'],
                      '```', '']
        (files['reports'] / f'{s}.md').write_text('\n'.join(lines), encoding='utf-8')
    return files
