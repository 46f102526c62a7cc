"""
Write a node of your own for a role of a run: a template that keeps the role's contract.

``robotica new ROLE NAME`` writes into the current folder (or ``--output-dir``) ``NAME.py``, a
working node in plain rclpy (a proportional heading tracker, a dead-reckoning estimator, a PD
joint controller), ``NAME.yaml``, a scenario that runs it in that role, and
``NAME_rubric.yaml``, the rubric it passes. Run it with ``robotica run NAME.yaml`` and grade the
bag with ``robotica grade BAG --rubric NAME_rubric.yaml``; then change the law. The contracts:
docs/your_node.md.
"""
import argparse
from pathlib import Path
import sys

from robotica_sim.cli.options import path
from robotica_sim.runs.roles import ROLES
from robotica_sim.runs.templates import render_template

HELP = "write a node of your own for a run's role (tracker, estimator, joint_controller)"
EPILOG = """examples:
  robotica new tracker my_tracker          my_tracker.py, my_tracker.yaml, my_tracker_rubric.yaml
  robotica run my_tracker.yaml             run it in the demo, recorded
  robotica new joint_controller pd --output-dir lab3
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica new``."""
    parser.add_argument('role', choices=list(ROLES),
                        help='the role the node takes in a run (docs/your_node.md)')
    parser.add_argument('name', help='name of the node and of its files: a letter, then '
                        'letters, digits or _ (a ROS node name and a Python file name)')
    parser.add_argument('--output-dir', type=path, default=Path('.'),
                        help='folder to write the files into (created if missing)')
    parser.add_argument('--force', action='store_true', help='overwrite existing files')


def main(args: argparse.Namespace) -> int:
    """Write the template's files; return the exit code."""
    try:
        files = render_template(args.role, args.name)
    except ValueError as err:
        print(f'robotica new: error: NAME {err}', file=sys.stderr)
        return 2
    existing = [str(args.output_dir / f) for f in files if (args.output_dir / f).exists()]
    if existing and not args.force:
        print(f'robotica new: error: {", ".join(existing)} exist(s) already (--force '
              'overwrites)', file=sys.stderr)
        return 2
    args.output_dir.mkdir(parents=True, exist_ok=True)
    for file_name, text in files.items():
        target = args.output_dir / file_name
        target.write_text(text)
        if file_name.endswith('.py'):
            target.chmod(0o755)
    folder = args.output_dir
    print(f'wrote {", ".join(str(folder / f) for f in files)}\n'
          f'a {args.role} {ROLES[args.role].summary}; its contract: docs/your_node.md\n'
          f'run it:   robotica run {folder / f"{args.name}.yaml"}\n'
          f'grade it: robotica grade runs/{args.name}-<time>/bag --rubric '
          f'{folder / f"{args.name}_rubric.yaml"}')
    return 0
