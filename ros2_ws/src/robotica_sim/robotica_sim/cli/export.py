"""
Export a recorded run's time series as tables: one file per topic, CSV or Apache Parquet.

One row per message: ``t`` (the receive time in the bag [s], simulated in a ``robotica run``
bag), then the message's fields flattened into columns (``pose.pose.position.x``; stamps as
float seconds; short numeric arrays one column per element; longer arrays and arrays of
messages as JSON). For a spreadsheet (CSV) or pandas (``pandas.read_parquet``). Core:
``robotica_sim.bags.export``; the rules: docs/recording.md#export.
"""
import argparse
from pathlib import Path
import sys

from robotica_sim.bags.export import export_bag, EXPORT_FORMATS
from robotica_sim.cli.options import nonempty, output_problem, path

HELP = "write a bag's topics as CSV or Parquet tables"
EPILOG = """examples:
  robotica export runs/demo-20261123-101500/bag
  robotica export runs/demo-20261123-101500/bag --format parquet --topics /odom /ground_truth/odom
  robotica export runs/demo-20261123-101500/bag --output tables/
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica export``."""
    parser.add_argument('bag', type=path, help='bag directory (with metadata.yaml)')
    parser.add_argument('--format', choices=EXPORT_FORMATS, default='csv',
                        help='table format: csv (a spreadsheet) or parquet (pandas, Arrow)')
    parser.add_argument('--topics', nargs='+', type=nonempty, default=None, metavar='TOPIC',
                        help='topics to export (default: every topic of the bag)')
    parser.add_argument('--output', type=path, default=None,
                        help='directory of the tables, created if needed; a table file that '
                        'exists is not overwritten (default: BAG-FORMAT beside the bag)')


def main(args: argparse.Namespace) -> int:
    """Write the tables and list them; return the exit code."""
    bag = Path(args.bag)
    output = args.output or bag.resolve().parent / f'{bag.resolve().name}-{args.format}'
    problem = output_problem(output, directory=True)
    if problem:
        print(f'robotica export: error: {problem}', file=sys.stderr)
        return 2
    # An ExportError is one line and exit 2, a BagError exit 1 (robotica_sim.cli.main).
    for table in export_bag(bag, output, args.format, args.topics):
        print(f'{table.path}: {table.topic}, {table.rows} rows x {table.columns} columns')
    return 0
