"""
Start a node by package and executable name, as ``ros2 run`` does (the pip route has no ``ros2``).

``robotica node PKG EXECUTABLE [ARGS ...]`` replaces itself (``exec``) by the executable that
``ros2 run PKG EXECUTABLE`` would run, ``<prefix of PKG>/lib/PKG/EXECUTABLE`` found through the
ament index (``AMENT_PREFIX_PATH``, set by ``scripts/env.sh``), with the same arguments
(``--ros-args -p name:=value -r from:=to --params-file FILE ...``) and the same environment, in
which discovery stays on this machine (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` unless set
otherwise). Signals and the exit code are the node's own. An unknown package or executable: one
line listing those that exist, exit code 2.

``robotica node --list`` prints the packages that have executables, ``robotica node --list PKG``
the executables of PKG, one a line: what the bash completion of ``scripts/completion.bash``
(sourced by ``scripts/env.sh``) offers after ``robotica node``. The completion runs
``python3 -m robotica_sim.cli.node [PKG]``, the same lists without the import of every verb
(0.2 s instead of 2 s).
"""
import argparse
import os
from pathlib import Path
import sys
from typing import Optional

from ament_index_python.packages import get_packages_with_prefixes
from robotica_sim.runs.supervisor import local_environment

HELP = 'start a node by package and executable name (ros2 run on the pip route)'
EPILOG = """examples:
  robotica node robotica_sim simulator --ros-args -p pacing:=realtime
  robotica node --list                     packages with executables
  robotica node --list robotica_ctrl       the executables of robotica_ctrl
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica node``."""
    parser.add_argument('--list', action='store_true',
                        help='print the packages with executables, or the executables of '
                        'PACKAGE, one a line, and exit')
    parser.add_argument('package', nargs='?', metavar='PACKAGE', help='package of the node')
    parser.add_argument('executable', nargs='?', metavar='EXECUTABLE',
                        help='executable of the node in the package')
    parser.add_argument('node_args', nargs=argparse.REMAINDER, metavar='ARGS',
                        help='arguments of the node (--ros-args ...)')


def executables(prefix: str, package: str) -> list[str]:
    """Return the executables ``ros2 run`` finds for ``package`` installed under ``prefix``."""
    folder = Path(prefix) / 'lib' / package
    if not folder.is_dir():
        return []
    return sorted(f.name for f in folder.iterdir()
                  if f.is_file() and os.access(f, os.X_OK))


def packages() -> dict[str, str]:
    """Return the packages that have executables, each with its install prefix."""
    return {name: prefix for name, prefix in sorted(get_packages_with_prefixes().items())
            if executables(prefix, name)}


def listing(package: Optional[str]) -> list[str]:
    """Return the packages with executables, or the executables of ``package`` (none: [])."""
    found = packages()
    if package is None:
        return list(found)
    return executables(found[package], package) if package in found else []


def main(args: argparse.Namespace) -> int:
    """List, or replace this process by the node; return 2 for an unknown name."""
    if args.list:
        print('\n'.join(listing(args.package)))
        return 0
    found = packages()
    if args.package is None or args.executable is None:
        print('robotica node: error: PACKAGE and EXECUTABLE are required (robotica node --list '
              'lists them)', file=sys.stderr)
        return 2
    if args.package not in found:
        print(f'robotica node: error: no package {args.package!r} with executables; there are: '
              f'{", ".join(found) or "none (source scripts/env.sh)"}', file=sys.stderr)
        return 2
    names = executables(found[args.package], args.package)
    if args.executable not in names:
        print(f'robotica node: error: no executable {args.executable!r} in {args.package}; '
              f'there are: {", ".join(names)}', file=sys.stderr)
        return 2
    path = str(Path(found[args.package]) / 'lib' / args.package / args.executable)
    sys.stdout.flush()
    os.execve(path, [path, *args.node_args], local_environment())


if __name__ == '__main__':   # the lists of --list, for the shell's completion
    print('\n'.join(listing(sys.argv[1] if len(sys.argv) > 1 else None)))
