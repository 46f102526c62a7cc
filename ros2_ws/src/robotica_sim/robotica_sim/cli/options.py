"""
Argument types of the ``robotica`` verbs: numbers with their ranges, and ROS domain ids.

Each is an ``argparse`` ``type``: a value out of range is refused while the command line is
parsed (one line, exit 2), so that no verb starts work with a value it cannot honour (a replay
at ``--rate 1e-9`` that never ends, a report that tries to draw the robot every nanosecond).

>>> real(0.0, 10.0)('2.5'), integer(1)('3')
(2.5, 3)
>>> real(0.0, 10.0, low_open=True)('0')
Traceback (most recent call last):
argparse.ArgumentTypeError: must be > 0 and <= 10, got 0
"""
import argparse
import math
from typing import Callable, Optional

__all__ = ['DDS_SAFE_DOMAIN_MAX', 'DOMAIN_ID_MAX', 'domain_id', 'domain_warning', 'integer',
           'real']

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
