"""
Hand out an assignment: ``robotica assignment init ROLE DIR``, ``robotica assignment check DIR``.

``init`` writes a folder a teacher edits and hands out: ``assignment.yaml`` (the manifest),
``statement.md`` (the task, the contract, how to run, how it is graded, what to hand in), the
template node ``NAME.py`` (``robotica new``'s), ``scenario.yaml`` (runs it in the role) and
``rubric.yaml`` (grades the run). ``check`` validates the folder, one line per check: the
manifest, the files, each scenario (loads, plans, runs the template in the role), the rubric
(loads, names each scenario); with ``--run`` it runs the template through each scenario and
grades the bag with the rubric, the proof that the assignment can be solved. Exit codes: 0 all
good, 1 a check, a run or a grade failed, 2 no folder or a malformed manifest. The flow, for
teachers and students: docs/assignments.md.
"""
import argparse
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from robotica_sim.cli.options import nonempty, output_problem, path
from robotica_sim.runs.assignment import (AssignmentError, check_assignment, init_files,
                                          load_assignment)
from robotica_sim.runs.roles import ROLES
from robotica_sim.runs.templates import render_template

HELP = 'write and check an assignment folder (robotica assignment init|check)'
EPILOG = """examples:
  robotica assignment init tracker lab3 --title "Lab 3: a path tracker"
  robotica assignment check lab3              the manifest, files, scenarios and rubric
  robotica assignment check lab3 --run        and the template passes its rubric
"""
ROBOTICA = (sys.executable, '-m', 'robotica_sim.cli.main')
STOP_WAIT = 60.0   # [s] for a run to stop its nodes after an interrupt
MESSAGE_LINES = 20   # the last lines of a failed run's message shown


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica assignment``."""
    actions = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    init = actions.add_parser('init', help='write a new assignment folder', description=__doc__,
                              epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    init.add_argument('role', choices=list(ROLES),
                      help="the role students' nodes take in the run (docs/your_node.md)")
    init.add_argument('dir', type=path, help='the assignment folder to create')
    init.add_argument('--name', default=None,
                      help='name of the template node and its file NAME.py (a letter, then '
                      'letters, digits or _) (default: my_ROLE)')
    init.add_argument('--title', type=nonempty, default=None,
                      help="the assignment's title (default: A ROLE of your own)")
    init.add_argument('--force', action='store_true',
                      help="write into a folder that is not empty, overwriting the assignment's "
                      'files')
    check = actions.add_parser('check', help='check an assignment folder (and run it)',
                               description=__doc__, epilog=EPILOG,
                               formatter_class=argparse.RawDescriptionHelpFormatter)
    check.add_argument('dir', type=path, help='the assignment folder')
    check.add_argument('--run', action='store_true',
                       help='also run the template through each scenario (robotica run, '
                       'visualisation off) and grade the bag with the rubric')
    check.add_argument('--output-dir', type=path, default=None, metavar='RUNDIR',
                       help='with --run: the folder of the runs, one per scenario '
                       '(default: runs/<folder>-check-<time>)')


def main(args: argparse.Namespace) -> int:
    """Run the action; return the exit code."""
    return _init(args) if args.action == 'init' else _check(args)


def _init(args: argparse.Namespace) -> int:
    name = args.name if args.name is not None else f'my_{args.role}'
    try:
        template = render_template(args.role, name)
    except ValueError as err:
        raise AssignmentError(f'--name {err}') from None
    folder = args.dir
    if folder.exists() and not folder.is_dir():
        raise AssignmentError(f'{folder} is a file, not a folder')
    if folder.is_dir() and any(folder.iterdir()) and not args.force:
        raise AssignmentError(f'{folder} is not empty (--force writes the assignment into it, '
                              'overwriting its files)')
    problem = output_problem(folder, directory=True)
    if problem:
        raise AssignmentError(problem)
    title = args.title or f'A {args.role.replace("_", " ")} of your own'
    files = init_files(args.role, name, title, template)
    for file_name, text in files.items():
        target = folder / file_name
        target.write_text(text)
        if file_name.endswith('.py'):
            target.chmod(0o755)
    print(f'wrote {", ".join(str(folder / f) for f in files)}\n'
          f'edit {folder / "statement.md"}, the scenario and the rubric; then check that the '
          f'template passes:\n  robotica assignment check {folder} --run')
    return 0


def _check(args: argparse.Namespace) -> int:
    if args.output_dir is not None and not args.run:
        raise AssignmentError('--output-dir is where --run writes its runs: give --run too')
    assignment = load_assignment(args.dir)
    name = args.dir.resolve().name or 'assignment'
    runs = args.output_dir or Path('runs') / f'{name}-check-{time.strftime("%Y%m%d-%H%M%S")}'
    outputs = {s: runs / assignment.run_name(s) for s in assignment.scenarios}
    taken = [str(output) for output in outputs.values() if output.exists()]
    if args.run and taken:
        raise AssignmentError(f'{", ".join(taken)} exist(s) already: give another --output-dir')
    print(f'OK    manifest: {assignment.title!r}, role {assignment.role}, '
          f'{len(assignment.scenarios)} scenario(s)')
    checked = check_assignment(assignment)
    for check in checked.checks:
        print(check.line())
    if not checked.passed:
        print(f'FAIL: {sum(not c.passed for c in checked.checks)} of {len(checked.checks) + 1} '
              'checks failed')
        return 1
    if not args.run:
        print(f'PASS: {len(checked.checks) + 1} checks passed (--run also runs the template)')
        return 0
    problem = output_problem(runs, directory=True)
    if problem:
        raise AssignmentError(problem)
    failed = 0
    for scenario in checked.scenarios:
        failed += not _run_and_grade(assignment.path(scenario), scenario,
                                     assignment.path(assignment.rubric), outputs[scenario])
    if failed:
        print(f'FAIL: the template failed {failed} of {len(checked.scenarios)} run(s); '
              f'the runs: {runs}')
        return 1
    print(f'PASS: the template passes {assignment.rubric} in every scenario; the runs: {runs}')
    return 0


def _run_and_grade(scenario: Path, name: str, rubric: Path, output: Path) -> bool:
    """Run ``scenario`` into ``output``, grade its bag with ``rubric``; print both results."""
    # Absolute: the user's node runs in the scenario's folder, and finds its parameter file
    # in the run folder by the path the run gives it.
    run = _robotica('run', str(scenario), '--output-dir', str(output.resolve()),
                    '--visualisation', 'off', '--quiet', '--json')
    if run.returncode != 0:
        print(f'FAIL  run {name}: exit {run.returncode}, the run: {output}')
        _indented(run.stderr.splitlines()[-MESSAGE_LINES:])
        return False
    try:
        summary = json.loads(run.stdout)
        took = f'{summary["duration"]:g} s simulated'
    except (ValueError, KeyError, TypeError):
        took = 'done'
    print(f'OK    run {name}: {took}, {output / "bag"}')
    grade = _robotica('grade', str(output / 'bag'), '--rubric', str(rubric))
    last = (grade.stdout.strip().splitlines() or [''])[-1]
    if grade.returncode != 0:
        print(f'FAIL  grade {name}: {last or _first_line(grade.stderr)}')
        _indented(grade.stdout.splitlines())
        return False
    print(f'OK    grade {name}: {last}')
    return True


def _indented(lines: list[str]) -> None:
    """Print ``lines`` under the check they explain."""
    sys.stdout.write(''.join(f'      {line}\n' for line in lines))


def _first_line(text: str) -> str:
    return next((line.strip() for line in text.splitlines() if line.strip()), 'no message')


def _robotica(*argv: str) -> subprocess.CompletedProcess:
    """
    Run ``robotica ARGV`` and return it, its output captured as text.

    In its own session, so that a Ctrl-C reaches it once, from here: an interrupt stops it
    (SIGINT, as Ctrl-C would: a run stops its nodes) and is raised again.
    """
    proc = subprocess.Popen([*ROBOTICA, *argv], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ),
                            start_new_session=True)
    try:
        out, err = proc.communicate()
    except KeyboardInterrupt:
        proc.send_signal(signal.SIGINT)
        try:
            proc.communicate(timeout=STOP_WAIT)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)
