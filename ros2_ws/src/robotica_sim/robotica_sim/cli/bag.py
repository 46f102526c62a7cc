"""
Maintain recorded bags: ``robotica bag repair BAG``.

``repair`` makes a partial bag readable again: its recorder was killed (SIGKILL, power cut, a
crash) before it closed the bag, or a file was cut short later (with its ``metadata.yaml``
there). Every complete message is kept, the files are finished, and ``metadata.yaml`` is rebuilt
from them (the originals are kept as ``*.mcap.broken`` and ``metadata.yaml.broken``). See
:mod:`robotica_sim.bags.repair`.
"""
import argparse

from robotica_sim.bags.repair import repair_bag
from robotica_sim.cli.options import path

HELP = 'repair a bag whose recorder was killed (robotica bag repair BAG)'
EPILOG = """examples:
  robotica bag repair runs/demo-20261123-101500/bag
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica bag``."""
    actions = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    repair = actions.add_parser('repair', help="rebuild a killed recorder's bag",
                                description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    repair.add_argument('bag', type=path, help="bag directory (the recorder's output)")


def main(args: argparse.Namespace) -> int:
    """Run the action; return the exit code."""
    # A RepairError or an OSError is one line and exit 1 (robotica_sim.cli.main).
    report = repair_bag(args.bag)
    for f in report.files:
        state = 'complete' if f.complete else f'cut short ({f.stopped_at})'
        print(f'{f.name}: {f.messages} messages kept, {state}')
    print(f'{report.bag}: {report.messages} messages of {len(report.topics)} topics; '
          'metadata.yaml rebuilt' + (' (the old one kept as metadata.yaml.broken)'
                                     if report.old_metadata else ''))
    return 0
