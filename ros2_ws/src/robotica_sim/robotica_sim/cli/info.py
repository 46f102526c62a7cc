"""
Show what a recorded run holds, like ``ros2 bag info``: topics, types, counts, rates, duration.

Reads a rosbag2 directory as ``robotica run`` and the ``recorder`` node write it (MCAP), and
also prints the run's scenario (name, seed, pacing) stored in the bag's metadata. A path that is
not a bag, or a bag that cannot be read, gets one line saying why and exit code 1.
"""
import argparse
import dataclasses
import json

from robotica_sim.bags.info import bag_info, format_info
from robotica_sim.cli.options import path

HELP = 'show the topics, counts, rates and scenario of a recorded bag'
EPILOG = """examples:
  robotica info runs/demo-20261123-101500/bag
  robotica info runs/demo-20261123-101500/bag --json
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica info``."""
    parser.add_argument('bag', type=path, help='bag directory (with metadata.yaml)')
    parser.add_argument('--json', action='store_true', help='print the summary as JSON')


def main(args: argparse.Namespace) -> int:
    """Print the bag's summary; return the exit code."""
    info = bag_info(args.bag)   # a BagError is one line and exit 1 (robotica_sim.cli.main)
    if args.json:
        summary = dataclasses.asdict(info)
        summary['path'] = str(info.path)
        summary['duration'] = info.duration
        print(json.dumps(summary, indent=2))
    else:
        print(format_info(info))
    return 0
