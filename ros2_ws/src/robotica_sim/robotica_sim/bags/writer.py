"""
A rosbag2 directory written with the ``mcap`` library: crash-safe, split by size or duration.

Layout as rosbag2 Jazzy writes it: ``<bag>/<bag>_0.mcap``, ``<bag>_1.mcap``, ... and
``metadata.yaml`` (version 9, see :mod:`robotica_sim.bags.metadata`), readable by ``rosbags``,
``mcap`` and rosbag2. Messages are stored serialized (CDR) as received, with the receive time
as log and publish time.

Crash safety: every ``flush_period`` seconds of wall clock the chunk in progress is closed and
written to the file, so a recorder killed by SIGKILL leaves every message received up to
``flush_period`` before the kill on disk. Such a file has no summary section and the bag no
``metadata.yaml`` (as with rosbag2); ``robotica bag repair`` (:mod:`robotica_sim.bags.repair`)
rebuilds both. Everything a repair needs is in the MCAP files: the schemas, the channels with
their offered QoS and type hash, and the run's ``custom_data`` (an MCAP metadata record
``robotica`` written at the start of each file).

Splitting: a new file starts when the current one holds ``max_bag_size`` bytes or spans
``max_bag_duration`` seconds of receive time (0: no limit), as rosbag2's options of the same
names.
"""
from pathlib import Path
import time
from typing import BinaryIO, Optional

from mcap.writer import CompressionType, Writer
from robotica_sim.bags.metadata import (bag_metadata, FileRecord, MESSAGE_ENCODING, PROFILE,
                                        QOS_KEY, qos_yaml, SCHEMA_ENCODING, TopicRecord,
                                        TYPE_HASH_KEY, write_metadata)
import yaml

COMPRESSION = {'zstd': CompressionType.ZSTD, 'none': CompressionType.NONE}
CHUNK_SIZE = 1 << 20          # [bytes] uncompressed, the longest chunk between flushes
CUSTOM_DATA_RECORD = 'robotica'
LIBRARY = 'robotica bag_writer (mcap)'


class BagWriter:
    """
    Write one rosbag2 directory; :meth:`close` it (also after an error) to finish it.

    Parameters
    ----------
    path
        Bag directory to create; it must not exist.
    compression
        ``'zstd'`` (chunk compression) or ``'none'``.
    max_bag_size
        [bytes] start a new file at this size; 0: never.
    max_bag_duration
        [s] start a new file when the current one spans this much receive time; 0: never.
    flush_period
        [s, wall clock] longest time a received message stays in memory only.
    custom_data
        Key-value strings stored in the metadata (the run's scenario, parameters, versions).

    """

    def __init__(self, path: str | Path, *, compression: str = 'zstd', max_bag_size: int = 0,
                 max_bag_duration: float = 0.0, flush_period: float = 1.0,
                 custom_data: Optional[dict[str, str]] = None) -> None:
        if compression not in COMPRESSION:
            raise ValueError(f'compression must be one of {sorted(COMPRESSION)}, '
                             f'got {compression!r}')
        if max_bag_size < 0 or max_bag_duration < 0 or not flush_period > 0:
            raise ValueError('max_bag_size and max_bag_duration must be >= 0 and flush_period '
                             '> 0')
        self.path = Path(path)
        if self.path.exists():
            raise FileExistsError(f'bag directory {self.path} exists already')
        self.path.mkdir(parents=True)
        self._compression = COMPRESSION[compression]
        self._max_size = int(max_bag_size)
        self._max_duration = int(max_bag_duration * 1e9)
        self._flush_period = float(flush_period)
        self.custom_data = dict(custom_data or {})
        self.topics: list[TopicRecord] = []
        self.files: list[FileRecord] = []
        self._channels: dict[int, int] = {}     # topic index -> channel id of the current file
        self._next_flush = 0.0
        self._closed = False
        self._stream: BinaryIO
        self._mcap: Writer
        self._open_file()

    # -- files --------------------------------------------------------------------------------
    def _open_file(self) -> None:
        name = f'{self.path.name}_{len(self.files)}.mcap'
        self._stream = open(self.path / name, 'xb')
        self._mcap = Writer(self._stream, chunk_size=CHUNK_SIZE, compression=self._compression)
        self._mcap.start(profile=PROFILE, library=LIBRARY)
        if self.custom_data:
            self._mcap.add_metadata(CUSTOM_DATA_RECORD, self.custom_data)
        self.files.append(FileRecord(name))
        self._channels = {}
        for index in range(len(self.topics)):
            self._register(index)
        self.flush()

    def _finish_file(self) -> None:
        information = bag_metadata('mcap', self.topics, self.files, self.custom_data)
        self._mcap.add_metadata('rosbag2', {'serialized_metadata': yaml.safe_dump(information)})
        self._mcap.finish()
        self._stream.close()

    def _register(self, index: int) -> None:
        topic = self.topics[index]
        schema = self._mcap.register_schema(topic.msgtype, SCHEMA_ENCODING,
                                            topic.msgdef.encode())
        self._channels[index] = self._mcap.register_channel(
            topic.name, MESSAGE_ENCODING, schema,
            {QOS_KEY: qos_yaml(topic.offered_qos), TYPE_HASH_KEY: topic.type_hash})

    # -- writing ------------------------------------------------------------------------------
    def add_topic(self, name: str, msgtype: str, msgdef: str, type_hash: str,
                  offered_qos: Optional[list[dict]] = None) -> int:
        """Add a topic (``msgtype`` 'pkg/msg/Type'); return its index for :meth:`write`."""
        if any(t.name == name for t in self.topics):
            raise ValueError(f'topic {name} was added already')
        self.topics.append(TopicRecord(name, msgtype, msgdef, type_hash,
                                       list(offered_qos or [])))
        self._register(len(self.topics) - 1)
        return len(self.topics) - 1

    def write(self, topic: int, log_time: int, data: bytes) -> None:
        """Write one serialized message of topic index ``topic`` received at ``log_time`` [ns]."""
        current = self.files[-1]
        if current.count and (
                (self._max_size and self._stream.tell() >= self._max_size)
                or (self._max_duration
                    and log_time - (current.start or 0) >= self._max_duration)):
            self._finish_file()
            self._open_file()
            current = self.files[-1]
        self._mcap.add_message(self._channels[topic], log_time, data, log_time)
        current.note(log_time)
        self.topics[topic].count += 1
        if time.monotonic() >= self._next_flush:
            self.flush()

    def set_custom_data(self, key: str, value: str) -> None:
        """
        Store ``key: value`` in the bag's ``custom_data``; also in the current file at once.

        The file gets a ``robotica`` metadata record holding the pair, so that a repair after a
        kill finds it (a later record of a key wins).
        """
        self.custom_data[key] = value
        if not self._closed:
            self._mcap.add_metadata(CUSTOM_DATA_RECORD, {key: value})

    def flush(self) -> None:
        """Write the chunk in progress to the file (the OS has it even if the process dies)."""
        if not self._closed:
            self._mcap.flush()
        self._next_flush = time.monotonic() + self._flush_period

    def close(self) -> dict:
        """Finish the last file and write ``metadata.yaml``; return its information."""
        if not self._closed:
            self._finish_file()
            self._closed = True
        information = bag_metadata('mcap', self.topics, self.files, self.custom_data)
        write_metadata(self.path, information)
        return information
