"""
Argument types of the ``robotica`` verbs: numbers with their ranges, and ROS domain ids.

Each is an ``argparse`` ``type``: a value out of range is refused while the command line is
parsed (one line, exit 2), so that no verb starts work with a value it cannot honour (a replay
at ``--rate 1e-9`` that never ends, a report that tries to draw the robot every nanosecond, an
empty path that would mean the current directory).

>>> real(0.0, 10.0)('2.5'), integer(1)('3')
(2.5, 3)
>>> real(0.0, 10.0, low_open=True)('0')
Traceback (most recent call last):
argparse.ArgumentTypeError: must be > 0 and <= 10, got 0
"""
import argparse
import math
from pathlib import Path
import tempfile
from typing import Callable, Optional

__all__ = ['DDS_SAFE_DOMAIN_MAX', 'DOMAIN_ID_MAX', 'domain_id', 'domain_warning', 'integer',
           'nonempty', 'output_problem', 'path', 'real']

DOMAIN_ID_MAX = 232
"""The largest ROS 2 domain id: above it the DDS ports pass 65535."""
DDS_SAFE_DOMAIN_MAX = 101
"""The largest domain id whose DDS ports (7400 + 250 id + ...) stay below Linux's ephemeral
ports (32768-60999); above it a participant may find its port taken."""


def _bounds(low: Optional[float], high: Optional[float], low_open: bool) -> str:
    parts = []
    if low is not None:
        parts.append(f'{">" if low_open else ">="} {low:g}')
    if high is not None:
        parts.append(f'<= {high:g}')
    return ' and '.join(parts)


def real(low: Optional[float] = None, high: Optional[float] = None,
         low_open: bool = False) -> Callable[[str], float]:
    """
    Return a type that parses a finite number in [low, high] ((low, high] if ``low_open``).

    None for a bound means none on that side.
    """
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'expected a number, got {text!r}') from None
        if not math.isfinite(value) or (low is not None and (
                value < low or (low_open and value == low))) or (
                high is not None and value > high):
            raise argparse.ArgumentTypeError(
                f'must be {_bounds(low, high, low_open) or "finite"}, got {text}')
        return value
    parse.__name__ = 'number'   # argparse names the type in its messages
    return parse


def integer(low: Optional[int] = None, high: Optional[int] = None) -> Callable[[str], int]:
    """Return a type that parses an integer in [low, high] (None: no bound on that side)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'expected an integer, got {text!r}') from None
        if (low is not None and value < low) or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f'must be {_bounds(low, high, False)}, got {text}')
        return value
    parse.__name__ = 'integer'
    return parse


def nonempty(value: str) -> str:
    """
    Parse a name or path that must not be empty.

    >>> nonempty('demo')
    'demo'
    >>> nonempty('')
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must not be empty
    """
    if not value.strip():
        raise argparse.ArgumentTypeError('must not be empty')
    return value


def path(value: str) -> Path:
    """
    Parse a path; an empty one is refused (``Path('')`` is the current directory).

    >>> path('runs/demo/bag').as_posix()
    'runs/demo/bag'
    """
    return Path(nonempty(value))


def output_problem(output: Path, directory: bool = False) -> str:
    """
    Return why a verb could not write ``output`` where it is asked for, '' when it can.

    A verb asks before its work (a grading, a report), so that a path that cannot be written
    is a usage error found at once, not after minutes of work. ``directory``: ``output`` is a
    directory, created with its parents; else a file, whose directory must exist. A file is
    created and removed there to learn whether the file system accepts one (a read-only
    directory, ``/sys``). A later failure to write (a full disk) is an I/O error.

    >>> output_problem(Path('/'), directory=False), output_problem(Path('/none/x.json'))
    ('/ is a directory', 'no directory /none')
    """
    if not directory and output.is_dir():
        return f'{output} is a directory'
    folder = output if directory else output.parent
    if not directory and not folder.is_dir():
        return f'no directory {folder}'
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as err:
        return f'cannot write into {folder}: {err.strerror or err}'
    return ''


def domain_id(text: str) -> int:
    """
    Parse a ROS domain id, 0 to :data:`DOMAIN_ID_MAX`.

    >>> domain_id('150')
    150
    """
    return integer(0, DOMAIN_ID_MAX)(text)


def domain_warning(domain: int) -> Optional[str]:
    """
    Return the warning for a domain id above :data:`DDS_SAFE_DOMAIN_MAX`, else None.

    >>> domain_warning(101) is None, domain_warning(150).startswith('domain id 150')
    (True, True)
    """
    if domain <= DDS_SAFE_DOMAIN_MAX:
        return None
    port = 7400 + 250 * domain
    return (f'domain id {domain} > {DDS_SAFE_DOMAIN_MAX}: its DDS ports ({port}-{port + 249}) '
            'lie in the ephemeral port range (32768-60999 on Linux), where another program may '
            'hold one; use 0-101 if discovery fails')
