"""
What ``robotica play`` republishes, and when: a bag's messages in time order, selected, renamed.

The pure part of replay (the ROS part is :mod:`robotica_sim.cli.play`): :func:`open_playback`
reads a rosbag2 directory with ``rosbags`` and yields the messages of the selected topics as
recorded (serialized CDR, published again without decoding), each with its output topic after
the remappings; :func:`wall_time` maps a bag time to the wall-clock time it is due at a rate
factor. Times are the bag's receive times [ns] (simulated time for a ``use_sim_time``
recorder), in the order they were recorded.
"""

from dataclasses import dataclass
from pathlib import Path
import re
from typing import Iterator

from robotica_sim.bags.info import BagError, open_bag
from rosbags.highlevel import AnyReader

__all__ = ['PlaybackTopic', 'Playback', 'SelectionError', 'open_playback', 'parse_remaps',
           'wall_time']

# An absolute ROS 2 topic name: tokens of letters, digits and underscores, not starting with a
# digit, each after one '/' (rcl's rules, without substitutions or a namespace to resolve).
_TOPIC_NAME = re.compile(r'(/[A-Za-z_][A-Za-z0-9_]*)+')
_RULE = 'tokens of letters, digits and _, not starting with a digit, each after one /'


class SelectionError(ValueError):
    """The topics or remappings asked for cannot be replayed from this bag; says which and why."""


@dataclass(frozen=True)
class PlaybackTopic:
    """A topic to republish: its name in the bag, its output name, type and message count."""

    name: str
    output: str
    msgtype: str
    count: int


class Playback:
    """The selected topics of an open bag and an iterator over their messages."""

    def __init__(self, reader: AnyReader, topics: dict[str, PlaybackTopic]) -> None:
        self._reader = reader
        self.topics = topics

    @property
    def start(self) -> int:
        """Return the bag's first receive time [ns]."""
        return int(self._reader.start_time)

    @property
    def end(self) -> int:
        """Return the bag's last receive time [ns]."""
        return int(self._reader.end_time)

    def messages(self) -> Iterator[tuple[int, PlaybackTopic, bytes]]:
        """Yield (receive time [ns], topic, serialized message) in time order."""
        connections = [c for c in self._reader.connections if c.topic in self.topics]
        try:
            # An empty connection list would mean "every topic" to rosbags: read nothing then.
            for connection, timestamp, raw in (self._reader.messages(connections=connections)
                                               if connections else ()):
                yield timestamp, self.topics[connection.topic], bytes(raw)
        except Exception as err:   # a truncated chunk surfaces only while reading
            raise BagError(f'reading stopped: {err}') from None

    def close(self) -> None:
        """Close the bag."""
        self._reader.close()


def parse_remaps(remaps: list[str]) -> dict[str, str]:
    """
    Return ``['/from:=/to', ...]`` as {'/from': '/to'}, or raise SelectionError.

    Both names must be absolute ROS 2 topic names, and a topic is remapped at most once.

    >>> parse_remaps(['/odom:=/replayed/odom'])
    {'/odom': '/replayed/odom'}
    >>> parse_remaps(['/odom:=/2nd'])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    robotica_sim.bags.player.SelectionError: remapping '/odom:=/2nd': '/2nd' is not a ROS topic...
    """
    result: dict[str, str] = {}
    for remap in remaps:
        source, sep, target = remap.partition(':=')
        if not sep or not source.startswith('/') or not target.startswith('/'):
            raise SelectionError(f'remapping {remap!r} must read /from:=/to')
        for name in (source, target):
            if not _TOPIC_NAME.fullmatch(name):
                raise SelectionError(f'remapping {remap!r}: {name!r} is not a ROS topic name '
                                     f'({_RULE})')
        if source in result:
            raise SelectionError(f'{source} is remapped twice ({source}:={result[source]} and '
                                 f'{remap})')
        result[source] = target
    return result


def open_playback(path: str | Path, topics: list[str] | None = None,
                  remaps: dict[str, str] | None = None) -> Playback:
    """
    Open the bag ``path`` for replay of ``topics`` (all when None or empty), renamed by ``remaps``.

    Raises
    ------
    BagError
        If ``path`` is not a readable bag.
    SelectionError
        If a requested topic or a remapped one is not in the bag, or two selected topics would
        be published on one name (a remapping onto another topic's name).

    """
    bag = Path(path)
    reader = open_bag(bag)
    try:
        in_bag = {c.topic: c for c in reader.connections}
        for name in topics or []:
            if not _TOPIC_NAME.fullmatch(name):
                raise SelectionError(f'--topics {name!r}: not a ROS topic name ({_RULE})')
        unknown = [t for t in (topics or []) + list(remaps or {}) if t not in in_bag]
        if unknown:
            raise SelectionError(f'{bag}: no topic {unknown[0]} in the bag; it has '
                                 f'{", ".join(sorted(in_bag))}')
        selected: dict[str, PlaybackTopic] = {}
        outputs: dict[str, str] = {}
        for name in topics or sorted(in_bag):
            output = (remaps or {}).get(name, name)
            if output in outputs and outputs[output] != name:
                raise SelectionError(f'{outputs[output]} and {name} would both be published as '
                                     f'{output}: remap one of them elsewhere')
            outputs[output] = name
            connection = in_bag[name]
            selected[name] = PlaybackTopic(name, output, connection.msgtype,
                                           int(connection.msgcount))
    except SelectionError:
        reader.close()
        raise
    return Playback(reader, selected)


def wall_time(bag_time: int, bag_start: int, wall_start: float, rate: float) -> float:
    """
    Return the wall-clock time [s] at which a message received at ``bag_time`` [ns] is due.

    The bag's ``bag_start`` [ns] plays at ``wall_start`` [s]; ``rate`` > 0 is the speed-up.

    >>> wall_time(3_000_000_000, 1_000_000_000, 100.0, 2.0)
    101.0
    """
    return wall_start + (bag_time - bag_start) * 1e-9 / rate
