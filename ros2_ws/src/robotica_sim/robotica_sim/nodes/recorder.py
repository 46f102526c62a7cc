"""
Recorder node: every topic of a run, serialized, into a crash-safe rosbag2 directory (MCAP).

Subscribes to the topics named in ``topics`` (or, when empty, to every topic it discovers)
with ``raw=True``, so messages are written as received (CDR) by
:class:`robotica_sim.bags.writer.BagWriter` into ``output/`` (``metadata.yaml`` + ``.mcap``
files), readable by ``rosbags``, ``mcap`` and rosbag2. Each topic's QoS follows what its
publishers offer, as rosbag2 does (best effort and transient-local only when every publisher
offers them); the offered profiles and the type hash are stored with the topic. Files named in
``metadata_files`` (the run's scenario and parameters) are copied into the bag directory and,
with the versions of the software (``robotica.versions``), stored in its ``custom_data``, as
are the nodes that published each recorded topic (``robotica.publishers``: who ran).
Messages that DDS reports lost before they reached the recorder are logged and counted in
``robotica.messages_lost``.

Crash safety: what was received is written to disk every ``flush_period`` s; after a SIGKILL,
``robotica bag repair`` makes the bag readable up to then. ``max_bag_size`` and
``max_bag_duration`` split the bag into several files.

Service ``~/ready`` (std_srvs/Trigger) answers success once every requested topic (but those of
``optional_topics``) is subscribed and matched to a publisher. Topic ``~/progress``
(std_msgs/Header) carries, every ``progress_period`` s of wall clock while it advances, the
oldest of the newest stamps written on the ``progress_topics`` (``/clock``: its clock; any other:
the stamp its message opens with, a std_msgs/Header's): a lockstep simulator follows it
(``lockstep.follow_topics``), so that a run never outruns its recording. Without that, a 1 kHz
arm run on two cores shared with other work outran the recorder by more than its subscription
depth, and DDS silently dropped 314 of 10 001 joint states before they reached it. Progress on
``/clock`` alone was not enough: the recorder reads each topic on its own, and in a 1 kHz run on
an overloaded machine its ``/clock`` reader was up to date while its controller_state reader
lagged by more than the writer's history (keep last 500), which lost 514 of 20 001 messages; so
``robotica run`` lists every per-step topic of the run that is certain to be published. Until
each of them has been written once, nothing is published (a listed topic that never came would
hold the simulator back, each step by up to its ``lockstep.timeout``); so a progress topic that
is not one of ``topics`` (when given) or is optional is left out (with a warning; none left: no
progress). On SIGINT/SIGTERM the node drains what DDS already delivered, then closes the bag.
"""
from pathlib import Path
import shutil
import signal
import struct
import time

from rclpy.clock import Clock, ClockType
from rclpy.event_handler import QoSMessageLostInfo, SubscriptionEventCallbacks
from rclpy.experimental import EventsExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from robotica_kin.ros.convert import header_stamp, seconds_to_stamp
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import STREAM_PUB_QOS
from robotica_sim.bags.metadata import qos_to_dict
from robotica_sim.bags.run_record import PUBLISHERS_KEY
from robotica_sim.bags.typestore import ensure_type, jazzy_typestore, message_class
from robotica_sim.bags.writer import BagWriter, COMPRESSION
from robotica_sim.runs.software_versions import software_versions
from std_msgs.msg import Header
from std_srvs.srv import Trigger
import yaml

SUBSCRIPTION_DEPTH = 1000   # messages a topic may fall behind before DDS drops the oldest
QUIET_PERIOD = 0.3   # [s] wall clock without messages that ends the drain at shutdown
DRAIN_LIMIT = 5.0    # [s] wall clock, the longest drain
UNKNOWN_NODE = '_NODE_NAME_UNKNOWN_'   # rmw's name of a publisher whose node is not known yet


def split_progress_topics(progress_topics: list[str], topics: list[str], optional: set[str]
                          ) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """
    Return the progress topics kept and those left out (not recorded, or optional).

    A topic kept must be recorded (one of ``topics`` when that is given) and certain to come
    (not ``optional``: one that never came would hold a lockstep run back), since no progress is
    published until every topic kept has been written once.

    >>> split_progress_topics(['/clock', '/x', '/y'], ['/clock', '/x'], {'/x'})
    (('/clock',), ('/x', '/y'))
    """
    listed = tuple(dict.fromkeys(t for t in progress_topics if t))
    kept = tuple(t for t in listed if (not topics or t in topics) and t not in optional)
    return kept, tuple(t for t in listed if t not in kept)


class RecorderNode(GuardedNode):
    """Record topics into one rosbag2 directory."""

    def __init__(self) -> None:
        super().__init__('recorder')
        output = declare(self, 'output', '', 'Bag directory to create (must not exist)',
                         read_only=True)
        self._topics = list(declare(self, 'topics', [''],
                                    'Topics to record; [""] or []: every topic discovered',
                                    read_only=True))
        self._topics = [t for t in self._topics if t]
        self._optional = {t for t in declare(
            self, 'optional_topics', [''],
            'Topics of "topics" that ~/ready does not wait for (an optional output of a '
            "user's node: recorded when it is published)", read_only=True) if t}
        compression = declare(self, 'compression', 'zstd',
                              f'MCAP chunk compression: one of {sorted(COMPRESSION)}',
                              read_only=True)
        max_size = declare(self, 'max_bag_size', 0,
                           'Start a new file at this size [bytes]; 0: one file', low=0, high=2**62,
                           read_only=True)
        max_duration = declare(self, 'max_bag_duration', 0.0,
                               'Start a new file after this much receive time [s]; 0: one file',
                               low=0.0, high=1e7, read_only=True)
        flush_period = declare(self, 'flush_period', 1.0,
                               'Longest time a received message stays in memory only [s, wall '
                               'clock]: what a SIGKILL can lose', low=0.01, high=60.0,
                               read_only=True)
        files = [f for f in declare(self, 'metadata_files', [''],
                                    'Files copied into the bag and its custom_data',
                                    read_only=True) if f]
        period = declare(self, 'discovery_period', 0.1,
                         'Period of the search for new topics [s, wall clock]',
                         low=0.01, high=10.0, read_only=True)
        progress_period = declare(self, 'progress_period', 0.05,
                                  'Period of ~/progress, how far progress_topics are recorded '
                                  '[s, wall clock]', low=0.001, high=10.0, read_only=True)
        progress_topics = declare(self, 'progress_topics', ['/clock'],
                                  'Stamped topics (/clock, or messages opening with a '
                                  'std_msgs/Header): ~/progress is the oldest of their newest '
                                  'stamps written; [""]: none', read_only=True)
        if not output:
            raise ValueError('parameter output (the bag directory) is required')
        if compression not in COMPRESSION:
            raise ValueError(f'compression must be one of {sorted(COMPRESSION)}, '
                             f'got {compression!r}')
        if Path(output).exists():
            raise ValueError(f'bag directory {output} exists already')
        self._progress_topics, left_out = split_progress_topics(progress_topics, self._topics,
                                                                self._optional)
        for f in files:
            if not Path(f).is_file():
                raise ValueError(f'metadata file {f} does not exist')
        custom = {'robotica.' + Path(f).name: Path(f).read_text() for f in files}
        custom['robotica.versions'] = yaml.safe_dump(software_versions(), sort_keys=False)
        self._typestore = jazzy_typestore()
        self._writer = BagWriter(output, compression=compression, max_bag_size=max_size,
                                 max_bag_duration=max_duration, flush_period=flush_period,
                                 custom_data=custom)
        for f in files:
            shutil.copy(f, Path(output) / Path(f).name)
        self._lost: dict[str, int] = {}
        self._publishing_nodes: dict[str, set[str]] = {}   # topic -> publishing nodes seen
        self._unresolved: set[str] = set()   # topics with a publisher whose node is unknown yet
        # Wall-clock timer: the chunk in progress reaches the disk even when no message comes.
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self.create_timer(flush_period, self._writer.flush, clock=wall)
        self._output = output
        self._recorded = {}
        self._count = 0
        self._last_message = time.monotonic()
        self.create_service(Trigger, '~/ready', self._on_ready)
        self._progress_pub = self.create_publisher(Header, '~/progress', STREAM_PUB_QOS)
        self._newest: dict[str, float] = {}   # progress topic -> newest stamp written [s]
        self._progress_sent = -1.0   # [s]
        self.create_timer(progress_period, self._publish_progress, clock=wall)
        # Wall-clock timer: discovery goes on even before any /clock arrives.
        self.create_timer(period, self._discover, clock=wall)
        if left_out:
            self.get_logger().warn(f'progress_topics {list(left_out)} left out: not recorded or '
                                   'optional' + ('' if self._progress_topics
                                                 else '; no ~/progress'))
        self.get_logger().info(f'recording into {output}: '
                               f'{", ".join(self._topics) if self._topics else "all topics"}')

    def _discover(self) -> None:
        for topic in list(self._unresolved):
            self._note_publishers(topic, self.get_publishers_info_by_topic(topic))
        for topic, types in self.get_topic_names_and_types():
            if topic in self._recorded or (self._topics and topic not in self._topics):
                continue
            if not self._topics and (topic.endswith('/_action/status')
                                     or topic == self._progress_pub.topic_name):
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
        index = self._writer.add_topic(topic, msgtype, msgdef, rihs01,
                                       [qos_to_dict(p.qos_profile) for p in publishers])
        self._note_publishers(topic, publishers)
        best_effort = all(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
                          for p in publishers)
        latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                      for p in publishers)
        qos = QoSProfile(
            depth=SUBSCRIPTION_DEPTH,
            reliability=ReliabilityPolicy.BEST_EFFORT if best_effort
            else ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.TRANSIENT_LOCAL if latched
            else DurabilityPolicy.VOLATILE)
        writer = self._writer
        now = self._receive_time

        def write(data: bytes) -> None:
            writer.write(index, now(), data)
            self._count += 1
            self._last_message = time.monotonic()

        def write_stamped(data: bytes) -> None:
            write(data)
            try:   # the newest, not the largest: one stray stamp must not stick
                self._newest[topic] = header_stamp(data)
            except (ValueError, IndexError, struct.error):   # malformed: recorded, not followed
                pass

        def lost(info: QoSMessageLostInfo) -> None:
            self._lost[topic] = int(info.total_count)
            self.get_logger().warn(f'{topic}: {info.total_count} messages lost before they '
                                   'reached the recorder', throttle_duration_sec=1.0)

        self._recorded[topic] = self.create_subscription(
            msg_class, topic, write_stamped if topic in self._progress_topics else write, qos,
            raw=True, event_callbacks=SubscriptionEventCallbacks(message_lost=lost))
        self.get_logger().info(f'recording {topic} [{msgtype}]')

    def _note_publishers(self, topic: str, publishers: list) -> None:
        """Store the nodes publishing ``topic`` in the bag (when new ones are seen)."""
        seen = self._publishing_nodes.setdefault(topic, set())
        if any(p.node_name == UNKNOWN_NODE for p in publishers):
            self._unresolved.add(topic)
        else:
            self._unresolved.discard(topic)
        names = {f'{p.node_namespace.rstrip("/")}/{p.node_name}' for p in publishers
                 if p.node_name != UNKNOWN_NODE}    # a participant not yet fully discovered
        if not names <= seen:
            seen |= names
            self._writer.set_custom_data(PUBLISHERS_KEY, yaml.safe_dump(
                {t: sorted(n) for t, n in sorted(self._publishing_nodes.items())}))

    def _publish_progress(self) -> None:
        """Publish the oldest newest stamp of the progress topics, when it has changed."""
        if not self._progress_topics or len(self._newest) < len(self._progress_topics):
            return   # one not written yet: none
        progress = min(self._newest.values())
        if progress != self._progress_sent and progress >= 0.0:
            self._progress_sent = progress
            self._progress_pub.publish(Header(stamp=seconds_to_stamp(progress)))

    def _receive_time(self) -> int:
        """Return the receive time [ns]: simulated with use_sim_time, else the system clock."""
        if self.get_clock().ros_time_is_active:
            return self.get_clock().now().nanoseconds
        return time.time_ns()   # 0.1 µs instead of 3.5 µs for Clock.now() at 20 000 msg/s

    def _on_ready(self, request: Trigger.Request, response: Trigger.Response
                  ) -> Trigger.Response:
        waiting = [t for t in self._topics if t not in self._optional and (
            t not in self._recorded or self._recorded[t].get_publisher_count() == 0)]
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
        for topic in self._recorded:
            self._note_publishers(topic, self.get_publishers_info_by_topic(topic))
        if self._lost:
            self._writer.set_custom_data('robotica.messages_lost', yaml.safe_dump(self._lost))
        information = self._writer.close()
        self.get_logger().info(f'closed {self._output}: {self._count} messages in '
                               f'{len(information["files"])} file(s)'
                               + (f', lost before recording: {self._lost}' if self._lost
                                  else ''))


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
