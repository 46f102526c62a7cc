"""
The ``metadata.yaml`` of a rosbag2 directory (version 9, Jazzy) and rosbag2's MCAP conventions.

One place for what :mod:`robotica_sim.bags.writer` writes when a bag is closed and what
:mod:`robotica_sim.bags.repair` writes for a bag whose recorder was killed: the topics with their
type, RIHS01 type hash, offered QoS profiles and message counts; the files with their time span
and counts; the run's ``custom_data``. In an MCAP file, rosbag2 keeps a topic's offered QoS
profiles (YAML text) and type hash in the channel's metadata (keys ``offered_qos_profiles`` and
``topic_type_hash``), the schema is the ``ros2msg`` definition, the messages are ``cdr``.
"""
from dataclasses import dataclass, field
import os
from pathlib import Path
from typing import Any, Optional

import yaml

METADATA_FILE = 'metadata.yaml'
VERSION = 9
QOS_KEY = 'offered_qos_profiles'
TYPE_HASH_KEY = 'topic_type_hash'
MESSAGE_ENCODING = 'cdr'
SCHEMA_ENCODING = 'ros2msg'
PROFILE = 'ros2'


@dataclass
class TopicRecord:
    """One topic of a bag: name, type, definition, type hash, offered QoS and message count."""

    name: str
    msgtype: str                  # 'pkg/msg/Type'
    msgdef: str                   # ros2msg text with its dependencies (rosbag2's layout)
    type_hash: str                # 'RIHS01_<64 hex>'
    offered_qos: list[dict] = field(default_factory=list)   # rosbag2 v9 QoS dictionaries
    count: int = 0


@dataclass
class FileRecord:
    """One storage file of a bag: its name, message count and time span [ns, receive time]."""

    name: str
    count: int = 0
    start: Optional[int] = None
    end: Optional[int] = None

    def note(self, log_time: int) -> None:
        """Count one message received at ``log_time`` [ns]."""
        self.count += 1
        if self.start is None or log_time < self.start:
            self.start = log_time
        if self.end is None or log_time > self.end:
            self.end = log_time


def qos_to_dict(profile: Any) -> dict:
    """
    Return the rosbag2 v9 dictionary of an ``rclpy.qos.QoSProfile`` (an offered profile).

    Durations are split into ``sec`` and ``nsec`` as rosbag2 writes them (an infinite duration
    is 9223372036 s 854775807 ns).
    """
    def duration(value: Any) -> dict:
        sec, nsec = divmod(int(value.nanoseconds), 1_000_000_000)
        return {'sec': sec, 'nsec': nsec}
    return {
        'history': profile.history.name.lower(),
        'depth': int(profile.depth),
        'reliability': profile.reliability.name.lower(),
        'durability': profile.durability.name.lower(),
        'deadline': duration(profile.deadline),
        'lifespan': duration(profile.lifespan),
        'liveliness': profile.liveliness.name.lower(),
        'liveliness_lease_duration': duration(profile.liveliness_lease_duration),
        'avoid_ros_namespace_conventions': bool(profile.avoid_ros_namespace_conventions),
    }


def qos_yaml(profiles: list[dict]) -> str:
    """Return the offered QoS profiles as the YAML text rosbag2 stores in a channel."""
    return yaml.safe_dump(profiles, sort_keys=False).strip() if profiles else ''


def qos_from_yaml(text: str) -> list[dict]:
    """Parse a channel's ``offered_qos_profiles`` text; malformed or empty text gives []."""
    try:
        profiles = yaml.safe_load(text) if text else []
    except yaml.YAMLError:
        return []
    return profiles if isinstance(profiles, list) else []


def bag_metadata(storage_id: str, topics: list[TopicRecord], files: list[FileRecord],
                 custom_data: dict[str, str]) -> dict:
    """Return the ``rosbag2_bagfile_information`` dictionary of a bag (version 9)."""
    spans = [f for f in files if f.count]
    start = min((f.start for f in spans if f.start is not None), default=0)
    end = max((f.end for f in spans if f.end is not None), default=0)
    return {
        'version': VERSION,
        'storage_identifier': storage_id,
        'duration': {'nanoseconds': max(0, end - start)},
        'starting_time': {'nanoseconds_since_epoch': start},
        'message_count': sum(f.count for f in files),
        'topics_with_message_count': [
            {'topic_metadata': {'name': t.name, 'type': t.msgtype,
                                'serialization_format': MESSAGE_ENCODING,
                                'offered_qos_profiles': t.offered_qos,
                                'type_description_hash': t.type_hash},
             'message_count': t.count}
            for t in topics],
        'compression_format': '',    # MCAP compresses its chunks itself (storage level)
        'compression_mode': '',
        'relative_file_paths': [f.name for f in files],
        'files': [{'path': f.name,
                   'starting_time': {'nanoseconds_since_epoch': f.start or 0},
                   'duration': {'nanoseconds': (f.end or 0) - (f.start or 0)},
                   'message_count': f.count} for f in files],
        'custom_data': dict(custom_data) or None,
        'ros_distro': 'jazzy',
    }


def write_metadata(bag: Path, information: dict) -> None:
    """Write ``bag/metadata.yaml`` atomically (a temporary file, then a rename)."""
    text = yaml.safe_dump({'rosbag2_bagfile_information': information}, sort_keys=False)
    tmp = Path(bag) / (METADATA_FILE + '.tmp')
    tmp.write_text(text)
    os.replace(tmp, Path(bag) / METADATA_FILE)
