"""
Grade recorded runs: compute their metrics and check them against a rubric.

PATH is a bag directory (as ``robotica run`` writes it: runs/<run>/bag) or a folder searched
at any depth for bags, graded in parallel on a Dask cluster (a local one of ``--workers``
processes, or the one at ``--scheduler``). Without ``--rubric`` the metrics are printed; with
it each check is printed as metric | value | bound | PASS/FAIL, and the exit code is 1 when a
check fails. A folder is a folder of submissions, one folder per student (one bag, or one
folder per run): it gives one row per run (student, run, each check's value and PASS/FAIL or
``missing``, total), and ``--output DIR`` writes them as grades.csv, grades.json and one
report per student. ``--json`` writes every bag's metrics and checks. Metrics, units and the
rubric format: docs/grading.md; batch grading: docs/sweeps.md.

Exit codes: 0 every check passed (or metrics only), 1 a check failed, a bag could not be read
or the --json file could not be written (a full disk), 2 usage error (bad arguments, a rubric
that is not valid, a --json file that cannot be created where it is asked for: refused before
the grading), 130 interrupted.
"""
import argparse
import json
from pathlib import Path
import sys

from robotica_sim.batch.cluster import dask_client, default_workers
from robotica_sim.batch.grading import grade_bags
from robotica_sim.cli.main import one_line
from robotica_sim.cli.options import integer, nonempty, output_problem, path
from robotica_sim.grading.entry import format_entry, grade_bag
from robotica_sim.grading.rubric import load_rubric, resolve_rubric, Rubric
from robotica_sim.grading.submissions import (submission_rows, submissions_table,
                                              write_submissions)

HELP = 'compute the metrics of recorded runs and check them against a rubric'
EPILOG = """examples:
  robotica grade runs/ej9_1-20261123-101500/bag                    metrics of one run
  robotica grade runs/ej9_1-20261123-101500/bag --rubric ej9_1     check a shipped rubric
  robotica grade submissions/ --rubric my_rubric.yaml --output grades/ --workers 4
  robotica grade /shared/submissions --rubric ej9_1 --scheduler tcp://10.0.0.5:8786
"""

# Worker processes: each holds 43 MB once NumPy and rosbags are loaded, more with a bag's data
# (the 1024 allowed before would need 44 GB and more); more than the CPUs grade no faster.
MAX_JOBS = 64


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica grade``."""
    parser.add_argument('path', type=path,
                        help='a bag directory, or a folder searched (any depth) for bags')
    parser.add_argument('--rubric', type=nonempty, default=None,
                        help='rubric YAML file, or the name of a shipped rubric')
    parser.add_argument('--json', type=path, default=None, metavar='OUT.json',
                        help="write every bag's metrics and checks as JSON ('-': stdout)")
    parser.add_argument('--output', type=path, default=None, metavar='DIR',
                        help='a folder of submissions: write grades.csv, grades.json and '
                        'reports/<student>.md into DIR')
    parser.add_argument('--workers', '--jobs', dest='jobs', type=integer(1, MAX_JOBS),
                        default=default_workers(),
                        help=f'worker processes of the local Dask cluster, at most {MAX_JOBS} '
                        f'(default: CPUs, {default_workers()}); 1 grades in this process')
    parser.add_argument('--scheduler', type=nonempty, default=None, metavar='ADDRESS',
                        help='grade on the Dask cluster of this scheduler (tcp://HOST:8786) '
                        'instead of a local one')
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


def format_summary(entries: list[dict], root: Path) -> str:
    """Return the table of a folder: one row per student's run, then the tally."""
    counts = {s: sum(e['status'] == s for e in entries) for s in ('pass', 'fail', 'ok', 'error')}
    tally = ', '.join(f'{n} {s}' for s, n in counts.items() if n)
    return (submissions_table(submission_rows(entries, root))
            + f'\n{len(entries)} bag{"s" if len(entries) != 1 else ""}: {tally}')


def _grade_all(bags: list[Path], rubric: Rubric | None, args: argparse.Namespace) -> list[dict]:
    """Grade the bags (on a Dask cluster when more than one worker); progress on stderr."""
    def progress(done: int, entry: dict) -> None:
        if not args.quiet:
            print(f'graded {done}/{len(bags)} {entry["bag"]}: {entry["status"].upper()}',
                  file=sys.stderr, flush=True)
    if args.scheduler is None and (args.jobs == 1 or len(bags) == 1):
        entries = []
        for bag in bags:
            entries.append(grade_bag(bag, rubric))
            if len(bags) > 1:
                progress(len(entries), entries[-1])
        return entries
    with dask_client(min(args.jobs, len(bags)), args.scheduler) as client:
        return grade_bags(client, bags, rubric, progress)


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
    if args.output is not None and output_problem(args.output, directory=True):
        print(f'robotica grade: error: cannot write {args.output}: '
              f'{output_problem(args.output, directory=True)}', file=sys.stderr)
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
        entries = _grade_all(bags, rubric, args)
    except KeyboardInterrupt:
        print('robotica grade: interrupted', file=sys.stderr)
        return 130
    single = bags == [root]
    if single and entries[0]['status'] == 'error':
        print(f'robotica grade: {one_line(entries[0]["error"])}', file=sys.stderr)
    elif not to_stdout:
        print(format_entry(entries[0]) if single else format_summary(entries, root))
    rubric_info = None if rubric is None else {'title': rubric.title, 'source': rubric.source}
    if args.output is not None:
        files = write_submissions(entries, root, args.output, rubric_info)
        if not args.quiet:
            print(f'robotica grade: wrote {files["csv"]}, {files["json"]} and '
                  f'{files["reports"]}/', file=sys.stderr)
    if args.json is not None:
        report = {'path': str(root), 'rubric': rubric_info, 'bags': entries}
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
