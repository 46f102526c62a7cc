"""
Entry point of the ``robotica`` command (``robotica <verb> ...``).

Every verb ends in one of these exit codes, with at most one line on stderr for an error:

- 0 success;
- 1 the work failed: a run or a check failed, a bag cannot be read (not a bag, truncated,
  nothing to plot), an I/O error (the file system refused a read or a write);
- 2 usage: a bad option or option value, a scenario or rubric that is not valid (missing,
  undecodable, a wrong key or value), an output that cannot be created where it is asked for;
- 130 interrupted (Ctrl-C, SIGINT or SIGTERM); 141 stdout closed early (``robotica info BAG |
  head``), silently, like a command ended by SIGPIPE.

The mapping is made here, once, for the error classes of the project (:data:`USAGE_ERRORS`,
:data:`FAILURE_ERRORS`) and ``OSError``; a verb catches only what it reports differently. An
unexpected exception is a bug: one line names it (``ROBOTICA_TRACEBACK=1`` shows the
traceback).
"""
import argparse
import os
import signal
import sys
from typing import NoReturn, Optional

from robotica_sim.bags.info import BagError
from robotica_sim.bags.repair import RepairError
from robotica_sim.cli import bag, bench, grade, info, play, report, run
from robotica_sim.grading.report import ReportError
from robotica_sim.grading.rubric import RubricError
from robotica_sim.runs.scenario import ScenarioError

VERBS = {'run': run, 'info': info, 'play': play, 'grade': grade, 'report': report, 'bag': bag,
         'bench': bench}
USAGE_ERRORS = (ScenarioError, RubricError)     # exit 2
FAILURE_ERRORS = (BagError, RepairError, ReportError)   # exit 1
EXIT_INTERRUPTED = 130
EXIT_BROKEN_PIPE = 141   # 128 + SIGPIPE


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line (the usage is in ``--help``)."""

    def error(self, message: str) -> NoReturn:
        """Print ``<prog>: error: <message>`` and exit with 2."""
        self.exit(2, f'{self.prog}: error: {one_line(message)} (see {self.prog} --help)\n')


def one_line(text: str) -> str:
    r"""
    Return ``text`` on one line: its lines stripped and joined by spaces.

    >>> one_line('not valid YAML:\n  line 3\n')
    'not valid YAML: line 3'
    """
    return ' '.join(line.strip() for line in str(text).splitlines() if line.strip())


def build_parser() -> argparse.ArgumentParser:
    """Return the parser of the command and its verbs."""
    parser = OneLineParser(
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


def _terminate(signum, frame) -> None:
    raise KeyboardInterrupt


def _os_error(err: OSError) -> str:
    if err.strerror and err.filename is not None:
        return f'{err.filename}: {err.strerror}'
    return str(err.strerror or err)


def run_verb(argv: Optional[list[str]] = None) -> int:
    """Parse the command line, run the verb and return its exit code (see the module)."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as done:   # --help (0) or a usage error (2), already printed
        return done.code if isinstance(done.code, int) else 0
    name = f'robotica {args.verb}'
    # SIGTERM ends a verb as Ctrl-C does: its cleanup runs (a run stops its nodes).
    signal.signal(signal.SIGTERM, _terminate)
    try:
        return args.handler(args)
    except BrokenPipeError:
        # The reader went away (| head): nothing more to say, and nowhere to say it. Point
        # stdout at /dev/null so that the interpreter's final flush does not fail again.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt:
        print(f'{name}: interrupted', file=sys.stderr)
        return EXIT_INTERRUPTED
    except USAGE_ERRORS as err:
        print(f'{name}: error: {one_line(str(err))}', file=sys.stderr)
        return 2
    except FAILURE_ERRORS as err:
        print(f'{name}: {one_line(str(err))}', file=sys.stderr)
        return 1
    except OSError as err:
        print(f'{name}: {one_line(_os_error(err))}', file=sys.stderr)
        return 1
    except MemoryError:
        print(f'{name}: out of memory', file=sys.stderr)
        return 1
    except Exception as err:
        if os.environ.get('ROBOTICA_TRACEBACK'):
            raise
        print(f'{name}: internal error: {type(err).__name__}: {one_line(str(err))} (a bug: '
              'please report it; ROBOTICA_TRACEBACK=1 shows the traceback)', file=sys.stderr)
        return 1


def main(argv: Optional[list[str]] = None) -> None:
    """Run the command (:func:`run_verb`) and exit with its code."""
    sys.exit(run_verb(argv))


if __name__ == '__main__':
    main()
