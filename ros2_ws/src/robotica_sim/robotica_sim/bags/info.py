"""
What a recorded run holds: topics, types, counts, rates, duration and the run's scenario.

:func:`bag_info` reads a rosbag2 directory (``metadata.yaml`` and its MCAP file, as the
``recorder`` node writes it) with ``rosbags`` and returns a :class:`BagInfo`: the
``ros2 bag info`` of this route (ros2cli cannot be installed from pip), plus what the recorder
stored in the metadata's ``custom_data``: the run that was recorded (its settings as run, the
nodes that ran, :mod:`robotica_sim.bags.run_record`). Times are the bag's receive times [s]
(simulated time for a ``use_sim_time`` recorder).
"""

from dataclasses import dataclass
from pathlib import Path

from robotica_sim.bags.repair import (metadata_mismatch, not_regular, partial_reason,
                                      repair_command)
from robotica_sim.bags.run_record import custom_data, run_record, RunRecord
from rosbags.highlevel import AnyReader

__all__ = ['BagError', 'BagInfo', 'TopicInfo', 'bag_info', 'format_info', 'open_bag']


class BagError(Exception):
    """The path is not a readable bag; the message says why, on one line."""

    def __init__(self, message: str) -> None:
        super().__init__(' '.join(str(message).split()))   # rosbags' YAML errors span lines


@dataclass(frozen=True)
class TopicInfo:
    """
    One topic of a bag.

    ``rate`` [Hz] is (count - 1) / (last - first) over the topic's own receive times, or 0 for
    fewer than two messages or no time between them.
    """

    name: str
    msgtype: str
    count: int
    first: float   # [s] receive time of the first message
    last: float    # [s] receive time of the last message
    rate: float    # [Hz]


@dataclass(frozen=True)
class BagInfo:
    """A bag's summary: its topics, time span, storage and the run's scenario."""

    path: Path
    topics: tuple[TopicInfo, ...]
    start: float        # [s] first receive time
    end: float          # [s] last receive time
    message_count: int
    size: int           # [bytes] of the bag's files
    compression: str    # '' when none
    run: RunRecord      # the run's settings and nodes as the bag records them

    @property
    def duration(self) -> float:
        """Return the time between the first and the last message [s]."""
        return self.end - self.start


def open_bag(path: str | Path) -> AnyReader:
    """
    Return an open ``rosbags`` reader of the rosbag2 directory ``path`` (close it after use).

    Raises
    ------
    BagError
        If ``path`` is not a bag directory, or its metadata or data cannot be read (a
        truncated file, a missing ``metadata.yaml`` or one that does not describe the data, a
        FIFO or a device in place of a file).

    """
    bag = Path(path)
    if not bag.is_dir():
        raise BagError(f'{bag}: not a bag directory (a rosbag2 bag is a directory with '
                       'metadata.yaml)')
    irregular = not_regular(bag)
    if irregular:
        raise BagError(f'{bag}: {", ".join(irregular)} not a regular file')
    partial = partial_reason(bag)
    if partial:
        raise BagError(f'{bag}: a partial bag ({partial}): `{repair_command(bag)}` recovers '
                       'what was recorded')
    if not (bag / 'metadata.yaml').is_file():
        raise BagError(f'{bag}: not a bag directory: no metadata.yaml')
    mismatch = metadata_mismatch(bag)
    if mismatch:
        raise BagError(f'{bag}: metadata.yaml does not describe the data ({mismatch}); move it '
                       f'away and `{repair_command(bag)}` rebuilds it from the data')
    try:
        reader = AnyReader([bag])
        reader.open()
    except Exception as err:   # rosbags raises its own errors, OSError and struct errors
        raise BagError(f'{bag}: cannot read the bag: {err}') from None
    return reader


def bag_info(path: str | Path) -> BagInfo:
    """
    Return the summary of the rosbag2 directory ``path``.

    Raises
    ------
    BagError
        As :func:`open_bag`, also for data that cannot be read past the bag's summary.

    """
    bag = Path(path)
    reader = open_bag(bag)
    try:
        times: dict[str, list[int]] = {c.topic: [] for c in reader.connections}
        types = {c.topic: c.msgtype for c in reader.connections}
        for connection, timestamp, _ in reader.messages():
            times[connection.topic].append(timestamp)
        compression = getattr(reader.readers[0], 'compression_format', '') or ''
    except Exception as err:   # a truncated chunk surfaces only while reading
        raise BagError(f'{bag}: cannot read the bag: {err}') from None
    finally:
        reader.close()
    topics = []
    for name in sorted(times):
        stamps = times[name]
        first = stamps[0] * 1e-9 if stamps else 0.0
        last = stamps[-1] * 1e-9 if stamps else 0.0
        rate = (len(stamps) - 1) / (last - first) if len(stamps) > 1 and last > first else 0.0
        topics.append(TopicInfo(name, types[name], len(stamps), first, last, rate))
    counted = [t for t in topics if t.count]
    start = min((t.first for t in counted), default=0.0)
    end = max((t.last for t in counted), default=0.0)
    size = sum(f.stat().st_size for f in bag.iterdir() if f.is_file())
    return BagInfo(bag, tuple(topics), start, end, sum(t.count for t in topics), size,
                   compression, run_record(custom_data(bag)))


def format_info(info: BagInfo) -> str:
    """Return ``info`` as the text ``robotica info`` prints (aligned like ``ros2 bag info``)."""
    lines = [f'Bag:          {info.path}',
             f'Size:         {info.size / 1e6:.2f} MB'
             + (f' ({info.compression} compressed)' if info.compression else ''),
             f'Duration:     {info.duration:.3f} s',
             f'Start:        {info.start:.3f} s',
             f'End:          {info.end:.3f} s',
             f'Messages:     {info.message_count}']
    lines += [f'{label + ":" if label else "":<14}{text}' for label, text in info.run.lines()]
    width = max((len(t.name) for t in info.topics), default=5)
    type_width = max((len(t.msgtype) for t in info.topics), default=4)
    lines.append(f'Topics:       {len(info.topics)}')
    lines.append(f'  {"topic":<{width}}  {"type":<{type_width}}  {"count":>7}  {"rate [Hz]":>9}')
    for t in info.topics:
        lines.append(f'  {t.name:<{width}}  {t.msgtype:<{type_width}}  {t.count:>7}  '
                     f'{t.rate:>9.2f}')
    return '\n'.join(lines)
