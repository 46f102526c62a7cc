"""
Repair a bag whose recorder died before closing it (``robotica bag repair``).

A killed :class:`robotica_sim.bags.writer.BagWriter` leaves MCAP files without their summary (the
last one also without its footer, possibly ending inside a record) and no ``metadata.yaml``; a file
cut short later (a full disk, a copy interrupted) lacks its footer although the ``metadata.yaml``
is there. :func:`partial_reason` tells such a *partial* bag (a finished MCAP file ends with the
MCAP magic bytes). The repair reads each file's records in order with ``mcap``'s stream reader
(CRCs checked) up to the first one that is incomplete, writes a finished copy of the file holding
every complete message, keeps the original as ``<file>.broken``, and writes ``metadata.yaml`` from
what was read: topics (type, definition, offered QoS, type hash, counts), files, and the run's
``custom_data`` (the ``robotica`` metadata records of the files, under what a ``metadata.yaml``
already there held; that file is kept as ``metadata.yaml.broken``). The effect of ``ros2 bag
reindex`` plus ``mcap recover``.

The originals are never lost: every finished copy is written beside its original first
(``<file>.repairing``), and the originals are renamed only once every copy is complete, so a
repair that is interrupted (Ctrl-C) or fails (a full disk) leaves the bag as it found it; an
original kept by an earlier repair (``<file>.broken``) is never overwritten. A storage file or
``metadata.yaml`` that is not a regular file (a FIFO, a device, a directory) is refused before
anything is opened: reading a FIFO would wait for a writer for ever.
"""
from dataclasses import dataclass, field
import os
from pathlib import Path
import re
import shlex
import struct

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Header, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer
from robotica_sim.bags.metadata import (bag_metadata, FileRecord, METADATA_FILE,
                                        qos_from_yaml, QOS_KEY, TopicRecord, TYPE_HASH_KEY,
                                        write_metadata)
from robotica_sim.bags.writer import CHUNK_SIZE, CUSTOM_DATA_RECORD, LIBRARY
import yaml

BROKEN_SUFFIX = '.broken'
PARTIAL_SUFFIX = '.repairing'   # a finished copy being written
MCAP_MAGIC = b'\x89MCAP0\r\n'   # the first and last bytes of a finished MCAP file
# What a truncated or torn record raises while it is parsed or decompressed.
READ_ERRORS = (McapError, EOFError, struct.error, ValueError, KeyError, IndexError,
               UnicodeDecodeError)


class RepairError(Exception):
    """The directory cannot be repaired; the message says why."""


@dataclass
class FileRepair:
    """What the repair of one file found: messages kept, and why reading stopped."""

    name: str
    messages: int
    complete: bool                 # the file had its footer: nothing was cut
    stopped_at: str = ''           # the error that ended the reading of an incomplete file


@dataclass
class RepairReport:
    """The outcome of :func:`repair_bag`."""

    bag: Path
    files: list[FileRepair] = field(default_factory=list)
    topics: list[TopicRecord] = field(default_factory=list)
    old_metadata: bool = False     # a metadata.yaml was there (kept as metadata.yaml.broken)

    @property
    def messages(self) -> int:
        """Return the messages the repaired bag holds."""
        return sum(f.messages for f in self.files)


def _split_index(path: Path) -> int:
    match = re.search(r'_(\d+)\.mcap$', path.name)
    return int(match.group(1)) if match else 0


def _storage_files(bag: Path) -> list[Path]:
    files = sorted(bag.glob('*.mcap'), key=lambda p: (_split_index(p), p.name))
    if not files:
        raise RepairError(f'{bag}: no .mcap file to repair')
    return files


def not_regular(bag: str | Path) -> list[str]:
    """
    Return the names of the bag's ``*.mcap`` and ``metadata.yaml`` that are not regular files.

    A FIFO, a device or a directory in their place cannot be a bag's file, and opening a FIFO
    blocks until a writer comes: callers refuse such a bag before they open anything.
    """
    bag = Path(bag)
    candidates = [*sorted(bag.glob('*.mcap')), bag / METADATA_FILE]
    return [f.name for f in candidates if (f.exists() or f.is_symlink()) and not f.is_file()]


class _Rewriter:
    """Copy the complete records of damaged files into finished ones, gathering the metadata."""

    def __init__(self) -> None:
        self.topics: dict[str, TopicRecord] = {}
        self.custom_data: dict[str, str] = {}

    def rewrite(self, source: Path, target: Path) -> tuple[FileRecord, FileRepair]:
        """Copy the complete messages of ``source`` into a new, finished ``target``."""
        schemas: dict[int, Schema] = {}
        channels: dict[int, tuple[int, TopicRecord]] = {}   # source id -> (target id, topic)
        record = FileRecord(source.name)   # the copy takes the original's name
        outcome = FileRepair(source.name, 0, complete=False)
        with open(source, 'rb') as stream, open(target, 'xb') as out:
            writer = Writer(out, chunk_size=CHUNK_SIZE, compression=CompressionType.ZSTD)
            writer.start(profile='ros2', library=LIBRARY)
            target_schemas: dict[int, int] = {}
            try:
                for item in StreamReader(stream, validate_crcs=True).records:
                    if isinstance(item, Header):
                        continue
                    if isinstance(item, Schema):
                        schemas.setdefault(item.id, item)
                    elif isinstance(item, Channel) and item.id not in channels:
                        channels[item.id] = self._channel(writer, item, schemas, target_schemas)
                    elif isinstance(item, Message) and item.channel_id in channels:
                        channel, topic = channels[item.channel_id]
                        writer.add_message(channel, item.log_time, item.data, item.publish_time,
                                           item.sequence)
                        record.note(item.log_time)
                        topic.count += 1
                    elif isinstance(item, Metadata) and item.name == CUSTOM_DATA_RECORD:
                        self.custom_data.update(item.metadata)
                        writer.add_metadata(item.name, item.metadata)
                outcome.complete = True
            except READ_ERRORS as err:
                outcome.stopped_at = f'{type(err).__name__}: {err}'.rstrip(': ')
            writer.finish()
        outcome.messages = record.count
        return record, outcome

    def _channel(self, writer: Writer, channel: Channel, schemas: dict[int, Schema],
                 target_schemas: dict[int, int]) -> tuple[int, TopicRecord]:
        schema = schemas.get(channel.schema_id)
        if schema is None:
            raise McapError(f'channel {channel.topic} names unknown schema {channel.schema_id}')
        if schema.id not in target_schemas:
            target_schemas[schema.id] = writer.register_schema(schema.name, schema.encoding,
                                                               schema.data)
        topic = self.topics.setdefault(channel.topic, TopicRecord(
            channel.topic, schema.name, schema.data.decode(),
            channel.metadata.get(TYPE_HASH_KEY, ''),
            qos_from_yaml(channel.metadata.get(QOS_KEY, ''))))
        target = writer.register_channel(channel.topic, channel.message_encoding,
                                         target_schemas[schema.id], channel.metadata)
        return target, topic


FOOTER = struct.Struct('<BQQQI')   # opcode 0x02, length 20, summary start, offset start, CRC
FOOTER_OPCODE = 0x02


def _finished(path: Path) -> bool:
    """
    Return whether the MCAP file ``path`` is closed: magic, a footer record, magic.

    The footer's opcode, its length (20) and a summary start inside the file are checked: a
    file that only ends with the magic bytes (random bytes, a file glued from pieces) is not
    closed, and ``robotica bag repair`` takes what it can of it.
    """
    if not path.is_file():   # never open a FIFO (it blocks) or a device
        return False
    try:
        with open(path, 'rb') as stream:
            size = stream.seek(0, os.SEEK_END)
            if size < 2 * len(MCAP_MAGIC) + FOOTER.size:
                return False
            stream.seek(0)
            head = stream.read(len(MCAP_MAGIC))
            stream.seek(-(FOOTER.size + len(MCAP_MAGIC)), os.SEEK_END)
            tail = stream.read()
    except OSError:
        return False
    opcode, length, summary_start, _, _ = FOOTER.unpack_from(tail)
    return (head == MCAP_MAGIC and tail[FOOTER.size:] == MCAP_MAGIC
            and opcode == FOOTER_OPCODE and length == FOOTER.size - 9
            and summary_start < size)


def partial_reason(bag: str | Path) -> str:
    """
    Return why the recorder's directory ``bag`` is a partial bag, or '' when it is not one.

    A partial bag has MCAP files but no ``metadata.yaml`` (its recorder was killed), or a file
    that ends before its footer (cut short); :func:`repair_bag` makes it readable.
    """
    bag = Path(bag)
    if not bag.is_dir():
        return ''
    files = sorted(bag.glob('*.mcap'))
    if not files:
        return ''
    if not (bag / METADATA_FILE).exists():
        return f'no {METADATA_FILE}: the recorder did not close it (killed?)'
    cut = [f.name for f in files if not _finished(f)]
    if cut:
        return f'{", ".join(cut)} cut short (no MCAP footer)'
    return ''


def metadata_mismatch(bag: str | Path) -> str:
    """
    Return how the bag's ``metadata.yaml`` contradicts its MCAP files, or '' when it does not.

    The messages per topic that the files' own summaries count are compared with those
    ``metadata.yaml`` lists (topics without messages are left out: a channel may be written
    only with its first message): a ``metadata.yaml`` copied from another bag (every
    ``robotica run`` names its file ``bag_0.mcap``) would make a reader show that bag's scenario
    and read only the topics it lists. '' also when there is nothing to compare (a file without
    a summary, a ``metadata.yaml`` that cannot be parsed: the reader says why).
    """
    bag = Path(bag)
    try:
        metadata = yaml.safe_load((bag / METADATA_FILE).read_text())
        information = metadata['rosbag2_bagfile_information']
        listed: dict[str, int] = {}
        for entry in information['topics_with_message_count']:
            name = str(entry['topic_metadata']['name'])
            listed[name] = listed.get(name, 0) + int(entry['message_count'])
        names = [str(name) for name in information['relative_file_paths']]
    except (OSError, KeyError, TypeError, ValueError, AttributeError, UnicodeDecodeError,
            yaml.YAMLError):
        return ''
    held: dict[str, int] = {}
    for name in names:
        path = bag / name
        if path.suffix != '.mcap' or not path.is_file():
            return ''
        try:
            with open(path, 'rb') as stream:
                summary = make_reader(stream).get_summary()
        except (OSError, *READ_ERRORS):
            return ''
        if summary is None or summary.statistics is None:
            return ''
        for channel, count in summary.statistics.channel_message_counts.items():
            topic = summary.channels[channel].topic
            held[topic] = held.get(topic, 0) + count
    differ = [f'{topic}: {listed.get(topic, 0)} listed, {held.get(topic, 0)} held'
              for topic in sorted(set(listed) | set(held))
              if listed.get(topic, 0) != held.get(topic, 0)]
    if not differ:
        return ''
    return f'messages per topic {"; ".join(differ[:3])}' + (
        f'; {len(differ) - 3} more topics differ' if len(differ) > 3 else '')


def needs_repair(bag: str | Path) -> bool:
    """Return whether ``bag`` is a partial bag (:func:`partial_reason`)."""
    return bool(partial_reason(bag))


def repair_command(bag: str | Path) -> str:
    """Return the command that repairs ``bag``, quoted for a POSIX shell."""
    return f'robotica bag repair {shlex.quote(str(bag))}'


def _recorded_custom_data(bag: Path) -> dict[str, str]:
    """Return the custom_data of the bag's ``metadata.yaml``; {} when there is none to read."""
    try:
        metadata = yaml.safe_load((bag / METADATA_FILE).read_text())
        custom = metadata['rosbag2_bagfile_information'].get('custom_data') or {}
    except (OSError, KeyError, TypeError, AttributeError, UnicodeDecodeError, yaml.YAMLError):
        return {}
    return {str(k): str(v) for k, v in custom.items()} if isinstance(custom, dict) else {}


def repair_bag(bag: str | Path) -> RepairReport:
    """
    Make the partial bag directory ``bag`` readable again; return what was kept.

    Raises
    ------
    RepairError
        If ``bag`` is not a directory, has no MCAP file, has a file that is not a regular file,
        still holds the originals of an earlier repair (``*.broken``), or is not partial (it has
        a ``metadata.yaml`` and every file its footer: nothing to repair).
    OSError
        If a file cannot be read or written; the bag is then left as it was.

    """
    bag = Path(bag)
    if not bag.is_dir():
        raise RepairError(f'{bag}: not a directory')
    sources = _storage_files(bag)
    irregular = not_regular(bag)
    if irregular:
        raise RepairError(f'{bag}: {", ".join(irregular)} not a regular file')
    if not needs_repair(bag):
        raise RepairError(f'{bag}: has a {METADATA_FILE} and every file is complete, so it was '
                          'closed properly; nothing to repair')
    kept = [p.name for p in [*sources, bag / METADATA_FILE]
            if p.with_name(p.name + BROKEN_SUFFIX).exists()]
    if kept:
        raise RepairError(f'{bag}: {kept[0]}{BROKEN_SUFFIX} exists (the original kept by an '
                          'earlier repair): move it away first, it would be overwritten')
    rewriter = _Rewriter()
    report = RepairReport(bag)
    copies = {source: source.with_name(source.name + PARTIAL_SUFFIX) for source in sources}
    records = []
    try:
        for source, copy in copies.items():
            copy.unlink(missing_ok=True)   # left by a repair that was killed
            record, outcome = rewriter.rewrite(source, copy)
            report.files.append(outcome)
            if record.count:
                records.append(record)
        if not records:
            raise RepairError(f'{bag}: no complete message in any file (nothing was changed)')
        # Every copy is complete: the originals become *.broken, the copies take their names;
        # a file with nothing complete in it (a split file just begun) leaves the bag.
        for source, copy in copies.items():
            os.replace(source, source.with_name(source.name + BROKEN_SUFFIX))
            if any(r.name == source.name for r in records):
                os.replace(copy, source)
    finally:
        for copy in copies.values():
            copy.unlink(missing_ok=True)
    report.topics = list(rewriter.topics.values())
    custom_data = {**rewriter.custom_data, **_recorded_custom_data(bag)}
    report.old_metadata = (bag / METADATA_FILE).exists()
    if report.old_metadata:
        os.replace(bag / METADATA_FILE, bag / (METADATA_FILE + BROKEN_SUFFIX))
    write_metadata(bag, bag_metadata('mcap', report.topics, records, custom_data))
    return report
