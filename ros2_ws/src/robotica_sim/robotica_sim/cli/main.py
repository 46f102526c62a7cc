"""
Entry point of the ``robotica`` command (``robotica <verb> ...``).

Every verb ends in one of these exit codes, with at most one line on stderr for an error:

- 0 success;
- 1 the work failed: a run or a check failed, a bag cannot be read (not a bag, truncated,
  nothing to plot), an I/O error (the file system refused a read or a write);
- 2 usage: a bad option or option value (an empty path among them), a scenario or rubric
  that is not valid (missing, undecodable, a wrong or repeated key or value), a topic or
  remapping a bag cannot replay, an output that cannot be created where it is asked for;
- 130 interrupted (Ctrl-C, SIGINT or SIGTERM; after a Ctrl-C that came while an extension
  module loaded, CPython may end the process by SIGINT itself, which a shell shows as 130
  too); 141 stdout closed early (``robotica info BAG | head``), silently, like a command
  ended by SIGPIPE.

The mapping is made here, once, for the error classes of the project (:func:`usage_errors`,
:func:`failure_errors`) and ``OSError``; a verb catches only what it reports differently. An
unexpected exception is a bug: one line names it (``ROBOTICA_TRACEBACK=1`` shows the
traceback). Ctrl-C and SIGTERM are handled from the first instant: the verbs and their
libraries (rclpy, NumPy, SciPy: a second or two) are imported under the same handlers, so that
an interrupted start is ``interrupted`` and 130 too, never a traceback of the import.
"""
import argparse
import importlib
import importlib.machinery
import os
import signal
import sys
import threading
from types import FrameType, ModuleType
from typing import NoReturn, Optional

VERBS = ('run', 'new', 'info', 'play', 'grade', 'report', 'export', 'bag', 'bench', 'view',
         'node', 'params', 'sweep', 'assignment')
"""The verbs, each a module of this package (imported when the command line is parsed)."""
EXIT_INTERRUPTED = 130
IMPORT_RETRY = 0.05   # [s] after which a signal deferred by an extension's import comes again
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


def usage_errors() -> tuple[type[Exception], ...]:
    """Return the error classes that are a bad argument or input (exit 2)."""
    from robotica_sim.bags.export import ExportError
    from robotica_sim.bags.player import SelectionError
    from robotica_sim.grading.rubric import RubricError
    from robotica_sim.runs.assignment import AssignmentError
    from robotica_sim.runs.scenario import ScenarioError
    return ScenarioError, RubricError, SelectionError, ExportError, AssignmentError


def failure_errors() -> tuple[type[Exception], ...]:
    """Return the error classes that are work that failed (exit 1)."""
    from robotica_sim.bags.info import BagError
    from robotica_sim.bags.repair import RepairError
    from robotica_sim.grading.report import ReportError
    return BagError, RepairError, ReportError


def _verb(name: str) -> ModuleType:
    return importlib.import_module(f'robotica_sim.cli.{name}')


def build_parser(names: tuple[str, ...] = VERBS) -> argparse.ArgumentParser:
    """Return the parser of the command and of the verbs ``names`` (each imports its module)."""
    parser = OneLineParser(
        prog='robotica', description='Run, record, inspect and benchmark robotica.',
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
        epilog='example: robotica run demo')
    verbs = parser.add_subparsers(dest='verb', required=True, metavar='VERB')
    for name, module in ((name, _verb(name)) for name in names):
        sub = verbs.add_parser(name, help=module.HELP, description=module.__doc__,
                               formatter_class=argparse.RawDescriptionHelpFormatter,
                               epilog=module.EPILOG)
        module.add_arguments(sub)
        sub.set_defaults(handler=module.main)
    return parser


def _interrupt(signum: int, frame: Optional[FrameType]) -> None:
    """
    End the verb on SIGINT or SIGTERM: raise KeyboardInterrupt, its cleanup runs.

    Not while an extension module initialises: raised in Python code that its initialisation
    calls (Matplotlib's ft2font imports NumPy), the interrupt became "ImportError:
    initialization failed" and then a fatal error of the interpreter at its exit. Then the
    signal is sent again a moment later, until the initialisation is over.
    """
    if _initialising_extension(frame):
        timer = threading.Timer(IMPORT_RETRY, signal.pthread_kill,
                                (threading.main_thread().ident, signum))
        timer.daemon = True
        timer.start()
        return
    raise KeyboardInterrupt


def _initialising_extension(frame: Optional[FrameType]) -> bool:
    """Return whether ``frame`` runs within the creation of an extension module."""
    while frame is not None:
        if frame.f_code.co_name in ('create_module', 'exec_module') and isinstance(
                frame.f_locals.get('self'), importlib.machinery.ExtensionFileLoader):
            return True
        frame = frame.f_back
    return False


def _silence_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's final flush does not fail again."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)


def _flush_stdout() -> None:
    """
    Flush stdout, so that a full disk or a closed pipe is found while the verb can say so.

    Left to the interpreter's exit (stdout is block-buffered when it is not a terminal), the
    failure is two lines of "Exception ignored" and exit code 120.
    """
    try:
        sys.stdout.flush()
    except OSError as err:
        _silence_stdout()
        raise OSError(err.errno, err.strerror, 'stdout') from None


def _interrupted(name: str) -> int:
    print(f'{name}: interrupted', file=sys.stderr)
    return EXIT_INTERRUPTED


def _os_error(err: OSError) -> str:
    if err.strerror and err.filename is not None:
        return f'{err.filename}: {err.strerror}'
    return str(err.strerror or err)


def run_verb(argv: Optional[list[str]] = None) -> int:
    """Parse the command line, run the verb and return its exit code (see the module)."""
    # SIGTERM ends a verb as Ctrl-C does: its cleanup runs (a run stops its nodes).
    previous = {s: signal.signal(s, _interrupt) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        return _run(argv)
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _run(argv: Optional[list[str]]) -> int:
    words = sys.argv[1:] if argv is None else argv
    name = ' '.join(['robotica', *[w for w in words if not w.startswith('-')][:1]])
    try:
        try:
            # The verb asked for only, when there is one: a verb does not wait for the imports
            # of the others (rclpy, Matplotlib: 4.2 s to start ``robotica node`` became 2.4).
            verb = name.split()[1:]
            args = build_parser(tuple(verb) if verb and verb[0] in VERBS else VERBS
                                ).parse_args(argv)
        except SystemExit as done:   # --help (0) or a usage error (2), already printed
            return done.code if isinstance(done.code, int) else 0
        name = ' '.join(['robotica', args.verb] + ([args.action] if 'action' in args else []))
        usage, failures = usage_errors(), failure_errors()
    except KeyboardInterrupt:
        return _interrupted(name)
    try:
        code = args.handler(args)
        _flush_stdout()
        return code
    except BrokenPipeError:
        # The reader went away (| head): nothing more to say, and nowhere to say it.
        _silence_stdout()
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt:
        return _interrupted(name)
    except usage as err:
        print(f'{name}: error: {one_line(str(err))}', file=sys.stderr)
        return 2
    except failures as err:
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
