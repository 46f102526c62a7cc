"""
Benchmarks of robotica, printed as a table (Markdown, ready for the README) or JSON.

``robotica bench arm`` measures the manipulator loop (PUMA 560 at 1 kHz under computed torque):
the pure core, the DDS round trip that bounds a lockstep loop, and the full ROS loop; see
:mod:`robotica_sim.benchmarks.arm`. ``robotica bench kin`` times ``fkine``, ``jacob0`` and
``ikine`` of the PUMA 560 and the planar 3R per call and batched, next to a plain NumPy
baseline (the product of Craig's link matrices, and HEMERO's pseudo-inverse ``ikine``) measured
in the same run; see
:mod:`robotica_sim.benchmarks.kinematics`. ``robotica bench tracking`` runs every tracking law
on the differential, tricycle and Ackermann vehicles along four paths, on the true pose and on
the EKF's (encoders, compass, DGPS), and reports cross-track, heading, settling, control effort
and the time per ``update`` call; see :mod:`robotica_sim.benchmarks.tracking`. ``robotica bench
recorder`` offers the recorder node message rates from 5 000 to 30 000 per second and counts
what reaches its bag; see :mod:`robotica_sim.benchmarks.recorder`. ``robotica bench view`` runs
the demo with and without TF and markers, interleaved, and once with the Foxglove relay, whose
forwarded messages it compares with the bag's; see :mod:`robotica_sim.benchmarks.visualisation`.
``robotica bench raycast`` times a 360-beam scan against 200 walls and a 1000 x 1000 grid,
next to a plain NumPy loop and a Python cell traversal; see
:mod:`robotica_sim.benchmarks.raycast`. ``robotica bench laws`` times the ``update`` of every law
of the joint controller on the PUMA 560 against the 1 ms servo period and runs each in closed
loop (joint laws on θ_i = sin t, Cartesian laws on a 10 cm line, force laws against the plane of
Ej. 8.10); see :mod:`robotica_sim.benchmarks.control_laws`. ``robotica bench planning`` times
grid A* on random 200 x 200 and 1000 x 1000 grids against a textbook Python A*, SciPy's and
NetworkX's shortest paths on the same graph, all costs checked equal, and the course's
parallel-parking planner (the plan, the planner node's search, the detection) in a second
table; see :mod:`robotica_sim.benchmarks.planning` and
:mod:`robotica_sim.benchmarks.parking_planning`.
"""
import argparse
import dataclasses
import json
import math
from pathlib import Path
import sys
import time

from robotica_ctrl.mobile.tracking_laws import LAWS
from robotica_sim.benchmarks.arm import (core_benchmark, dynamics_benchmark, loop_benchmark,
                                         round_trip_benchmark)
from robotica_sim.benchmarks.control_laws import (control_law_benchmark, format_law_table,
                                                  law_rows_json)
from robotica_sim.benchmarks.kinematics import BenchmarkRow, run_kinematics_benchmark
from robotica_sim.benchmarks.measurement_row import MeasurementRow
from robotica_sim.benchmarks.mobile import mobile_core_benchmark
from robotica_sim.benchmarks.parking_planning import (format_parking_table, parking_benchmark,
                                                      parking_rows_json)
from robotica_sim.benchmarks.planning import (format_planning_table, planning_benchmark,
                                              planning_rows_json, REPEATS, SIZES)
from robotica_sim.benchmarks.raycast import raycast_benchmark
from robotica_sim.benchmarks.recorder import RATES, recorder_benchmark
from robotica_sim.benchmarks.tracking import (format_tracking_table, PATHS, plot_tracking,
                                              POSE_SOURCES, tracking_benchmark, VEHICLES)
from robotica_sim.benchmarks.visualisation import visualisation_benchmark
from robotica_sim.benchmarks.your_node import your_node_benchmark
from robotica_sim.cli.options import integer, path, real

HELP = ('measure the speed of the kinematics, the arm loop, the mobile loop, the tracking '
        "laws, the recorder, the viewer, a user's node, ray casting, the arm's control laws or "
        'grid and parking planning '
        '(robotica bench kin|arm|mobile|tracking|recorder|view|your_node|raycast|laws|planning)')
EPILOG = """examples:
  robotica bench kin                       1000 configurations per robot, Markdown table
  robotica bench kin --count 200 --json    quicker, machine-readable
  robotica bench arm                       core, DDS round trip and ROS loop of the PUMA 560
  robotica bench arm --loop-duration 0     without the (slow) full ROS loop
  robotica bench mobile                    core and ROS loop of the figure eight, all sensors
  robotica bench tracking --plots docs/tracking
                                           every law x vehicle x path x pose source (about
                                           2 min on 2 cores), table and PNG figures
  robotica bench tracking --laws pure_pursuit gpc --vehicles ackermann --poses ground_truth
  robotica bench recorder                  messages/s the recorder takes without loss
  robotica bench recorder --rates 20000 --loop-duration 10
  robotica bench view                      the demo 3 times with and 3 without TF and markers,
                                           then once with the Foxglove relay (about 2 min)
  robotica bench view --runs 1 --no-relay
  robotica bench your_node                 the demo 3 times with the built-in and 3 with a
                                           Python tracker (robotica new's template)
  robotica bench raycast                   360-beam scans against walls and a grid (seconds)
  robotica bench raycast --count 200 --json
  robotica bench laws                      every joint-controller law: µs per update against
                                           the 1 ms servo period, closed-loop error (10 s)
  robotica bench laws --duration 0.5 --count 100
  robotica bench planning                  grid A* on 200x200 and 1000x1000 against a Python
                                           A*, SciPy and NetworkX, then the parking planner
                                           (about 2 min)
  robotica bench planning --skip-networkx --repeats 2 --sizes 200
  robotica bench planning --skip-parking   grid A* only
"""
SUITES = ('kin', 'arm', 'mobile', 'tracking', 'recorder', 'view', 'your_node', 'raycast',
          'laws', 'planning')
# Upper bounds of the sizes: beyond them a benchmark runs for hours (1e7 DDS round trips, a
# day-long ROS loop) or fills the memory (1e7 batched Jacobians are 2.9 GB), and a typo should
# not be taken for such a request.
MAX_COUNT = 100_000
MAX_BASELINE_IK = 10_000
MAX_LOOP_DURATION = 600.0   # [s]
MAX_VIEW_RUNS = 50          # demo runs each way of bench view
MAX_LAW_RUN = 600.0         # [s] simulated, cap of bench laws' closed-loop runs
MAX_PLAN_REPEATS = 100      # timed searches per method of bench planning
MAX_PLAN_SIZE = 2000        # cells a side of bench planning's grids (4 million cells)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica bench``."""
    parser.add_argument('suite', choices=SUITES,
                        help='what to measure: kin = kinematics, arm = the manipulator loop, '
                        'mobile = the vehicle loop with every sensor and the EKF, '
                        'tracking = the path-tracking laws on three vehicles, '
                        "recorder = the recorder node's throughput, "
                        "view = the cost of TF and markers and the relay's throughput, "
                        "your_node = the cost of a user's Python tracker in the demo, "
                        'raycast = ray casting on the world model, '
                        "laws = the joint controller's control laws on the PUMA 560, "
                        'planning = grid A* against a Python A*, SciPy and NetworkX, and the '
                        'parallel-parking planner')
    parser.add_argument('--count', type=integer(1, MAX_COUNT), default=1000,
                        help='kin: random configurations per robot; arm: simulated steps of '
                        'the core and DDS round trips; raycast: scans per world; laws: update '
                        'calls per timed batch '
                        '(default 1000; arm: at least 5000 steps '
                        f'are used for the core; at most {MAX_COUNT})')
    parser.add_argument('--loop-duration', type=real(0.0, MAX_LOOP_DURATION),
                        help='arm, mobile: simulated seconds of the full ROS loop; 0 skips it '
                        '(default 5 for arm, 60 for mobile); recorder: seconds per rate '
                        f'(default 5); at most {MAX_LOOP_DURATION:g}', default=None)
    parser.add_argument('--rates', type=real(0.0, 1e7, low_open=True), nargs='+',
                        default=list(RATES), metavar='RATE',
                        help='recorder: offered rates [messages/s]')
    parser.add_argument('--baseline-ik-count', type=integer(1, MAX_BASELINE_IK), default=100,
                        help='poses given to the slow baseline ikine (default 100, at most '
                        f'{MAX_BASELINE_IK})')
    parser.add_argument('--seed', type=integer(0, 2**32 - 1), default=0,
                        help='kin: seed of the configurations; tracking: seed of the sensor '
                        'noise; raycast: seed of the worlds and origins; planning: seed of the '
                        'grids (default 0)')
    parser.add_argument('--laws', nargs='+', choices=LAWS, default=list(LAWS),
                        metavar='LAW', help=f'tracking: laws to run, of {", ".join(LAWS)}')
    parser.add_argument('--vehicles', nargs='+', choices=VEHICLES, default=list(VEHICLES),
                        metavar='VEHICLE',
                        help=f'tracking: vehicles to run, of {", ".join(VEHICLES)}')
    parser.add_argument('--paths', nargs='+', choices=PATHS, default=list(PATHS),
                        metavar='PATH', help=f'tracking: paths to run, of {", ".join(PATHS)}')
    parser.add_argument('--poses', nargs='+', choices=POSE_SOURCES, default=list(POSE_SOURCES),
                        metavar='POSE', help='tracking: pose given to the laws, of '
                        f'{", ".join(POSE_SOURCES)} (the simulated truth, or the EKF fusing '
                        'encoders, compass and DGPS)')
    parser.add_argument('--plots', type=path, metavar='DIR',
                        help='tracking: also write the PNG figures into DIR (created)')
    parser.add_argument('--runs', type=integer(1, MAX_VIEW_RUNS), default=3,
                        help='view, your_node: demo runs each way (with and without TF and '
                        "markers; with robotica's and a user's tracker) "
                        f'(default 3, at most {MAX_VIEW_RUNS})')
    parser.add_argument('--no-relay', action='store_true',
                        help='view: without the run with the Foxglove relay')
    parser.add_argument('--duration', type=real(0.0, MAX_LAW_RUN, low_open=True), default=None,
                        help='laws: cap of every closed-loop run [s, simulated] (default none: '
                        '5 s per joint and force law, 3 learning trials of 2π s, a 2 s line)')
    parser.add_argument('--repeats', type=integer(1, MAX_PLAN_REPEATS), default=REPEATS,
                        help='planning: timed searches per method, the minimum reported '
                        f'(default {REPEATS}, at most {MAX_PLAN_REPEATS})')
    parser.add_argument('--sizes', type=integer(2, MAX_PLAN_SIZE), nargs='+',
                        default=list(SIZES), metavar='N',
                        help='planning: grids of N x N cells '
                        f'(default {" ".join(map(str, SIZES))}, at most {MAX_PLAN_SIZE})')
    parser.add_argument('--skip-networkx', action='store_true',
                        help='planning: without NetworkX (its 1000 x 1000 graph takes seconds '
                        'and about a gigabyte)')
    parser.add_argument('--skip-parking', action='store_true',
                        help='planning: without the parallel-parking table (the plan, the '
                        "planner node's search and the detection: about 20 s at 5 repeats)")
    parser.add_argument('--json', action='store_true', help='print JSON instead of a table')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')


def format_table(rows: list[BenchmarkRow]) -> str:
    """Return the rows as a Markdown table (times in µs per configuration)."""
    lines = ['| robot | function | route | mode | n | median [µs] | p95 [µs] | success '
             '| × raw Pinocchio |',
             '|---|---|---|---|---:|---:|---:|---:|---:|']
    for row in rows:
        p95 = '' if row.p95_us is None else f'{row.p95_us:.1f}'
        success = '' if row.success_rate is None else f'{100.0 * row.success_rate:.1f} %'
        ratio = '' if row.ratio is None else f'{row.ratio:.1f}×'
        lines.append(f'| {row.robot} | {row.function} | {row.route} | {row.mode} | {row.count} '
                     f'| {row.median_us:.2f} | {p95} | {success} | {ratio} |')
    return '\n'.join(lines)


def main(args: argparse.Namespace) -> int:
    """Run the benchmark and print its table; return the exit code."""
    show = not args.quiet and sys.stderr.isatty()

    def progress(message: str) -> None:
        if show:
            print(f'robotica bench: {message} ...', file=sys.stderr, flush=True)

    if args.suite == 'arm':
        return _arm(args, progress)
    if args.suite == 'mobile':
        return _mobile(args, progress)
    if args.suite == 'tracking':
        return _tracking(args, progress)
    if args.suite == 'recorder':
        return _recorder(args, progress)
    if args.suite == 'view':
        return _view(args, progress)
    if args.suite == 'your_node':
        return _your_node(args, progress)
    if args.suite == 'raycast':
        return _print_rows(args, raycast_benchmark(args.count, args.seed, progress))
    if args.suite == 'laws':
        return _laws(args, progress)
    if args.suite == 'planning':
        return _planning(args, progress)
    rows = run_kinematics_benchmark(args.count, args.baseline_ik_count, args.seed, progress)
    if args.json:
        print(json.dumps([dataclasses.asdict(row) for row in rows], indent=2))
    else:
        print(format_table(rows))
    return 0


def _loop_duration(args: argparse.Namespace, default: float) -> float | None:
    return default if args.loop_duration is None else args.loop_duration


def _arm(args: argparse.Namespace, progress) -> int:
    duration = _loop_duration(args, 5.0)
    if duration is None:
        return 2
    progress('core: simulator and controller in one loop')
    rows: list[MeasurementRow] = core_benchmark(max(args.count, 5000))
    progress('dynamics functions against raw Pinocchio')
    rows += dynamics_benchmark(max(args.count, 5000), args.seed)
    progress('DDS round trips through an echo process')
    rows += round_trip_benchmark(args.count)
    if duration > 0.0:
        progress(f'full ROS loop, {duration:g} s simulated')
        rows += loop_benchmark(duration)
    return _print_rows(args, rows)


def _mobile(args: argparse.Namespace, progress) -> int:
    duration = _loop_duration(args, 60.0)
    if duration is None:
        return 2
    progress('core: vehicle, sensors, EKF and pure pursuit in one loop, 60 s simulated')
    rows = mobile_core_benchmark(60.0, args.seed)
    if duration > 0.0:
        progress(f'full ROS loop, {duration:g} s simulated')
        rows += loop_benchmark(duration, 'figure_eight_differential',
                               '8 node processes (simulator, 4 sensors, odometry, tracker, path)')
    return _print_rows(args, rows)


def _recorder(args: argparse.Namespace, progress) -> int:
    seconds = _loop_duration(args, 5.0)
    if seconds is None or seconds == 0.0 or min(args.rates) <= 0.0:
        print('robotica bench: recorder needs --loop-duration > 0 and --rates > 0',
              file=sys.stderr)
        return 2
    try:
        rows = recorder_benchmark(tuple(args.rates), seconds, progress)
    except RuntimeError as err:
        print(f'robotica bench: recorder: {err}', file=sys.stderr)
        return 1
    return _print_rows(args, rows)


def _view(args: argparse.Namespace, progress) -> int:
    try:
        rows = visualisation_benchmark(args.runs, not args.no_relay, progress)
    except (RuntimeError, ValueError) as err:
        print(f'robotica bench: view: {err}', file=sys.stderr)
        return 1
    return _print_rows(args, rows)


def _your_node(args: argparse.Namespace, progress) -> int:
    try:
        rows = your_node_benchmark(args.runs, progress)
    except RuntimeError as err:
        print(f'robotica bench: your_node: {err}', file=sys.stderr)
        return 1
    return _print_rows(args, rows)


def _print_rows(args: argparse.Namespace, rows: list[MeasurementRow]) -> int:
    if args.json:
        print(json.dumps([dataclasses.asdict(row) for row in rows], indent=2))
    else:
        lines = ['| what | value | how |', '|---|---:|---|']
        lines += [f'| {row.what} | {row.value:.1f} {row.unit} | {row.detail} |' for row in rows]
        print('\n'.join(lines))
    return 0


def _laws(args: argparse.Namespace, progress) -> int:
    rows = control_law_benchmark(args.count, args.duration, progress)
    if args.json:
        print(json.dumps(law_rows_json(rows), indent=2))
    else:
        print(format_law_table(rows))
    return 0


def _planning(args: argparse.Namespace, progress) -> int:
    try:
        rows = planning_benchmark(args.sizes, args.repeats, args.seed, not args.skip_networkx,
                                  progress)
    except RuntimeError as err:   # a CostMismatch among them: the comparison failed
        print(f'robotica bench: planning: FAILED: {err}', file=sys.stderr)
        return 1
    parking = [] if args.skip_parking else parking_benchmark(repeats=args.repeats,
                                                             progress=progress)
    if args.json:
        print(json.dumps({'grid': planning_rows_json(rows),
                          'parking': parking_rows_json(parking)}, indent=2))
    else:
        print(format_planning_table(rows))
        if parking:
            print()
            print(format_parking_table(parking))
    return 0


def _tracking(args: argparse.Namespace, progress) -> int:
    if args.plots:   # before the runs, not after them
        try:
            Path(args.plots).mkdir(parents=True, exist_ok=True)
        except OSError as err:
            print(f'robotica bench: error: cannot create {args.plots}: {err.strerror or err}',
                  file=sys.stderr)
            return 2
    start = time.perf_counter()
    results = tracking_benchmark(args.laws, args.vehicles, args.paths, args.poses, args.seed,
                                 progress)
    progress(f'tracking: {len(results)} runs in {time.perf_counter() - start:.0f} s')
    if args.plots:
        progress(f'tracking: figures into {args.plots}')
        plot_tracking(results, args.plots)
    if args.json:   # a run that never settles has settling_distance null
        rows = [{name: None if isinstance(value, float) and not math.isfinite(value) else value
                 for name, value in result.metrics().items()} for result in results]
        print(json.dumps(rows, indent=2))
    else:
        print(format_tracking_table(results))
    return 0
