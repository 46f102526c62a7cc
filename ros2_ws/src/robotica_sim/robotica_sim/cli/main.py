"""
Entry point of the ``robotica`` command (``robotica <verb> ...``).

Exit codes: 0 success, 1 the run or check failed, 2 usage error, 130 interrupted (Ctrl-C).
"""
import argparse
import sys
from typing import Optional

from robotica_sim.cli import bag, bench, grade, info, play, report, run

VERBS = {'run': run, 'info': info, 'play': play, 'grade': grade, 'report': report, 'bag': bag,
         'bench': bench}


def build_parser() -> argparse.ArgumentParser:
    """Return the parser of the command and its verbs."""
    parser = argparse.ArgumentParser(
        prog='robotica', description='Run, record, inspect and benchmark robotica.',
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
        epilog='example: robotica run demo')
    verbs = parser.add_subparsers(dest='verb', required=True, metavar='VERB')
    for name, module in VERBS.items():
        sub = verbs.add_parser(name, help=module.HELP, description=module.__doc__,
                               formatter_class=argparse.RawDescriptionHelpFormatter,
                               epilog=module.EPILOG)
        module.add_arguments(sub)
        sub.set_defaults(handler=module.main)
    return parser


def main(argv: Optional[list[str]] = None) -> None:
    """Parse the command line and run the verb."""
    args = build_parser().parse_args(argv)
    sys.exit(args.handler(args))


if __name__ == '__main__':
    main()
