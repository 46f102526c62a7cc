"""
Benchmarks of robotica, printed as a table (Markdown, ready for the README) or JSON.

``robotica bench kin`` times ``fkine``, ``jacob0`` and ``ikine`` of the PUMA 560 and the planar
3R per call and batched, next to a plain NumPy baseline (the product of Craig's link matrices,
and HEMERO's pseudo-inverse ``ikine``) measured in the same run; see
:mod:`robotica_sim.kinematics_benchmark`.
"""
import argparse
import dataclasses
import json
import sys

from robotica_sim.kinematics_benchmark import BenchmarkRow, run_kinematics_benchmark

HELP = 'measure the speed of the kinematics (robotica bench kin)'
EPILOG = """examples:
  robotica bench kin                       1000 configurations per robot, Markdown table
  robotica bench kin --count 200 --json    quicker, machine-readable
"""
SUITES = ('kin',)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica bench``."""
    parser.add_argument('suite', choices=SUITES, help='what to measure: kin = kinematics')
    parser.add_argument('--count', type=int, default=1000,
                        help='random configurations per robot (default 1000)')
    parser.add_argument('--baseline-ik-count', type=int, default=100,
                        help='poses given to the slow baseline ikine (default 100)')
    parser.add_argument('--seed', type=int, default=0, help='seed of the configurations')
    parser.add_argument('--json', action='store_true', help='print JSON instead of a table')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')


def format_table(rows: list[BenchmarkRow]) -> str:
    """Return the rows as a Markdown table (times in µs per configuration)."""
    lines = ['| robot | function | route | mode | n | median [µs] | p95 [µs] | success |',
             '|---|---|---|---|---:|---:|---:|---:|']
    for row in rows:
        p95 = '' if row.p95_us is None else f'{row.p95_us:.1f}'
        success = '' if row.success_rate is None else f'{100.0 * row.success_rate:.1f} %'
        lines.append(f'| {row.robot} | {row.function} | {row.route} | {row.mode} | {row.count} '
                     f'| {row.median_us:.1f} | {p95} | {success} |')
    return '\n'.join(lines)


def main(args: argparse.Namespace) -> int:
    """Run the benchmark and print its table; return the exit code."""
    if args.count < 1 or args.baseline_ik_count < 1:
        print('robotica bench: --count and --baseline-ik-count must be >= 1', file=sys.stderr)
        return 2
    show = not args.quiet and sys.stderr.isatty()

    def progress(message: str) -> None:
        if show:
            print(f'robotica bench: {message} ...', file=sys.stderr, flush=True)

    rows = run_kinematics_benchmark(args.count, args.baseline_ik_count, args.seed, progress)
    if args.json:
        print(json.dumps([dataclasses.asdict(row) for row in rows], indent=2))
    else:
        print(format_table(rows))
    return 0
