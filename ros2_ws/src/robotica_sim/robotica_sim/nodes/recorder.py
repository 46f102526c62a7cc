"""
Recorder node: every topic of a run, serialized, into a rosbag2 directory (MCAP).

Subscribes to the topics named in ``topics`` (or, when empty, to every topic it discovers)
with ``raw=True``, so messages are written as received (CDR) by ``rosbags`` into
``output/`` (``metadata.yaml`` + ``.mcap``), readable by ``rosbags``, ``mcap`` and rosbag2.
Each topic's QoS follows what its publishers offer, as rosbag2 does (best effort and
transient-local only when every publisher offers them). Files named in ``metadata_files`` (the
run's scenario and parameters) are copied into the bag directory and stored in its metadata
(``custom_data``).

Service ``~/ready`` (std_srvs/Trigger) answers success once every requested topic is subscribed
and matched to a publisher. On SIGINT/SIGTERM the node drains what DDS already delivered, then
closes the bag.
"""
from pathlib import Path
import shutil
import signal
import time

from rclpy.clock import Clock, ClockType
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_sim.bag_types import ensure_type, jazzy_typestore, message_class
from rosbags.rosbag2 import StoragePlugin, Writer
from std_srvs.srv import Trigger

STORAGE = {'mcap': StoragePlugin.MCAP, 'sqlite3': StoragePlugin.SQLITE3}
QUIET_PERIOD = 0.3   # [s] wall clock without messages that ends the drain at shutdown
DRAIN_LIMIT = 5.0    # [s] wall clock, the longest drain


class RecorderNode(Node):
    """Record topics into one rosbag2 directory."""

    def __init__(self) -> None:
        super().__init__('recorder')
        output = declare(self, 'output', '', 'Bag directory to create (must not exist)',
                         read_only=True)
        self._topics = list(declare(self, 'topics', [''],
                                    'Topics to record; [""] or []: every topic discovered',
                                    read_only=True))
        self._topics = [t for t in self._topics if t]
        storage = declare(self, 'storage_id', 'mcap', f'Storage: one of {sorted(STORAGE)}',
                          read_only=True)
        files = [f for f in declare(self, 'metadata_files', [''],
                                    'Files copied into the bag and its custom_data',
                                    read_only=True) if f]
        period = declare(self, 'discovery_period', 0.1,
                         'Period of the search for new topics [s, wall clock]',
                         low=0.01, high=10.0, read_only=True)
        if not output:
            raise ValueError('parameter output (the bag directory) is required')
        if storage not in STORAGE:
            raise ValueError(f'storage_id must be one of {sorted(STORAGE)}, got {storage!r}')
        if Path(output).exists():
            raise ValueError(f'bag directory {output} exists already')
        for f in files:
            if not Path(f).is_file():
                raise ValueError(f'metadata file {f} does not exist')
        self._typestore = jazzy_typestore()
        self._writer = Writer(output, version=9, storage_plugin=STORAGE[storage])
        for f in files:
            self._writer.set_custom_data('robotica.' + Path(f).name, Path(f).read_text())
        self._writer.open()
        for f in files:
            shutil.copy(f, Path(output) / Path(f).name)
        self._output = output
        self._recorded = {}
        self._count = 0
        self._last_message = time.monotonic()
        self.create_service(Trigger, '~/ready', self._on_ready)
        # Wall-clock timer: discovery goes on even before any /clock arrives.
        self.create_timer(period, self._discover, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(f'recording into {output}: '
                               f'{", ".join(self._topics) if self._topics else "all topics"}')

    def _discover(self) -> None:
        for topic, types in self.get_topic_names_and_types():
            if topic in self._recorded or (self._topics and topic not in self._topics):
                continue
            if not self._topics and topic.endswith('/_action/status'):
                continue
            publishers = self.get_publishers_info_by_topic(topic)
            if not publishers:
                continue
            self._subscribe(topic, types[0], publishers)

    def _subscribe(self, topic: str, msgtype: str, publishers: list) -> None:
        try:
            ensure_type(self._typestore, msgtype)
            msg_class = message_class(msgtype)
        except (KeyError, AttributeError, ModuleNotFoundError, ValueError) as err:
            self.get_logger().warn(f'cannot record {topic}: {err}', throttle_duration_sec=30.0)
            return
        msgdef, _ = self._typestore.generate_msgdef(msgtype, ros_version=2)
        rihs01 = str(publishers[0].topic_type_hash)
        if not rihs01.startswith('RIHS01_'):
            rihs01 = self._typestore.hash_rihs01(msgtype)
        connection = self._writer.add_connection(topic, msgtype, msgdef=msgdef, rihs01=rihs01)
        best_effort = all(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
                          for p in publishers)
        latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                      for p in publishers)
        qos = QoSProfile(
            depth=1000,
            reliability=ReliabilityPolicy.BEST_EFFORT if best_effort
            else ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.TRANSIENT_LOCAL if latched
            else DurabilityPolicy.VOLATILE)

        def write(data: bytes, connection=connection) -> None:
            self._writer.write(connection, self.get_clock().now().nanoseconds, data)
            self._count += 1
            self._last_message = time.monotonic()

        self._recorded[topic] = self.create_subscription(msg_class, topic, write, qos, raw=True)
        self.get_logger().info(f'recording {topic} [{msgtype}]')

    def _on_ready(self, request: Trigger.Request, response: Trigger.Response
                  ) -> Trigger.Response:
        waiting = [t for t in self._topics if t not in self._recorded
                   or self._recorded[t].get_publisher_count() == 0]
        response.success = not waiting and bool(self._recorded)
        response.message = ('recording ' + ', '.join(sorted(self._recorded))
                            if response.success
                            else 'waiting for ' + (', '.join(waiting) or 'any topic'))
        return response

    def close(self, executor) -> None:
        """Take what DDS already delivered, then close the bag."""
        deadline = time.monotonic() + DRAIN_LIMIT
        self._last_message = time.monotonic()
        while (time.monotonic() - self._last_message < QUIET_PERIOD
               and time.monotonic() < deadline):
            executor.spin_once(timeout_sec=0.05)
        self._writer.close()
        self.get_logger().info(f'closed {self._output}: {self._count} messages')


def _record(node: RecorderNode, executor) -> int:
    stop = []
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.append(True))
    try:
        while not stop:
            executor.spin_once(timeout_sec=0.1)
    finally:
        node.close(executor)
    return 0


def main(args=None) -> None:
    """Record until SIGINT or SIGTERM."""
    run_node(RecorderNode, args, run=_record, executor_factory=EventsExecutor,
             signal_handler_options=SignalHandlerOptions.NO)
