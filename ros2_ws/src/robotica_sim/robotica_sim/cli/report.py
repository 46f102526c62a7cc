"""
Draw a recorded run: PNG figures and an HTML page that ties them together.

Reads a rosbag2 directory as ``robotica run`` writes it and draws what its topics allow. A
mobile robot: the path, the true trajectory and the /odom estimate in the x-y plane with the
robot drawn at intervals; the tracking errors (the truth's against /path, the numbers of
``robotica grade``, beside the tracker's own); the commands; the estimation error of /odom with
its ±3σ band; the gyro, compass and GPS readings against the truth with their error histograms.
A manipulator: joint positions and velocities against the references, torques and position
errors, one panel per joint. ``index.html`` shows the scenario, the bag's topics and every
figure with a caption.

The report goes to --output, by default ``<run>/report`` when the bag directory is named
``bag`` (``runs/<run>/bag``, as ``robotica run`` writes it), else ``<bag>_report`` beside the
bag. Exit codes: 0 written; 1 not a bag, a truncated bag, nothing to plot or a write that failed
(a full disk); 2 bad arguments or an output directory that cannot be written (found before the
figures are drawn).
"""
import argparse
import sys
import time

from robotica_sim.cli.main import one_line
from robotica_sim.cli.options import output_problem, path, real
from robotica_sim.grading.report import default_output, write_report
from robotica_sim.grading.series import load_run

HELP = 'draw a recorded run: PNG figures and an HTML page'
EPILOG = """examples:
  robotica report runs/demo-20261123-101500/bag
                       writes runs/demo-20261123-101500/report/index.html and its PNGs
  robotica report my_bag --output /tmp/my_report --robot-every 2
"""
MAX_ROBOTS = 1000   # robots drawn on the trajectory figure


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica report``."""
    parser.add_argument('bag', type=path, help='bag directory (with metadata.yaml)')
    parser.add_argument('--output', '-o', type=path, metavar='DIR',
                        help='directory of the report (created; files of the same names are '
                        'replaced); default <run>/report for runs/<run>/bag, else <bag>_report')
    parser.add_argument('--robot-every', type=real(0.0, 1e7, low_open=True), metavar='SECONDS',
                        help='period [s] of simulated time at which the robot is drawn on the '
                        'trajectory; default: 0.5, 1, 2, 5, 10 ... s, the shortest that draws '
                        f'at most 15 intervals; at most {MAX_ROBOTS} robots are drawn')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')


def main(args: argparse.Namespace) -> int:
    """Write the report of the bag; return the exit code."""
    show = not args.quiet and sys.stderr.isatty()

    def progress(message: str) -> None:
        if show:
            print(f'robotica report: {message}', file=sys.stderr, flush=True)

    start = time.perf_counter()
    output = args.output if args.output is not None else default_output(args.bag)
    progress(f'reading {args.bag}')
    run = load_run(args.bag)
    span = max([run.duration] + [float(s.t[-1] - s.t[0]) for s in (run.truth, run.odom)
                                 if s is not None and len(s) > 1])
    if args.robot_every is not None and span / args.robot_every > MAX_ROBOTS:
        print(f'robotica report: error: --robot-every {args.robot_every:g} would draw the robot '
              f'{span / args.robot_every:.3g} times over the {span:g} s run; at most '
              f'{MAX_ROBOTS}: use >= {span / MAX_ROBOTS:.3g}', file=sys.stderr)
        return 2
    problem = output_problem(output, directory=True)   # before any figure is drawn
    if problem:
        print(f'robotica report: error: cannot write the report into {output}: {problem}',
              file=sys.stderr)
        return 2
    try:
        report = write_report(run, output, args.robot_every, progress)
    except ValueError as err:   # the scenario's GPS origin
        print(f'robotica report: {one_line(str(err))}', file=sys.stderr)
        return 1
    # A write that fails later (a full disk) is an OSError: one line and exit 1 (cli.main).
    progress(f'done in {time.perf_counter() - start:.1f} s')
    print(f'{report.index} ({len(report.figures)} figures: '
          f'{", ".join(f.path.name for f in report.figures)})')
    return 0
