"""
View relay node: every topic of the running graph, relayed to the Foxglove app (``robotica view``).

Discovers the graph's topics every ``discovery_period`` s (a topic that appears later is relayed
from then on), subscribes to each with ``raw=True`` (CDR bytes, as foxglove_bridge does) and
hands every message to a :class:`robotica_sim.view.relay.FoxgloveRelay`, a Foxglove WebSocket
server on ``ws://host:port`` (``127.0.0.1:8765`` by default: nothing listens off the machine
unless ``host`` says so). Each channel's schema is the type's full ``ros2msg`` definition, built
as the recorder builds a bag's (:mod:`robotica_sim.bags.typestore`); a message's log time is its
receive time (system clock).

Each subscription's QoS matches what the topic's publishers offer, as foxglove_bridge chooses it:
reliable when every publisher is reliable (else best effort, which matches any publisher),
transient local when every publisher is (``/robot_description``, ``/tf_static``, a path, a
map: their last messages reach a client that connects later, see the relay). A publisher that
appears after the subscription with a QoS it does not match is not relayed.

A host or port the server cannot listen on (a port in use) is a configuration error: one line
and exit code 2. SIGINT or SIGTERM stops the server and logs the messages forwarded per topic.
"""
import time
from typing import Any

import rclpy
from rclpy._rclpy_pybind11 import RCLError
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_sim.bags.typestore import ensure_type, jazzy_typestore, message_class
from robotica_sim.view.relay import DEFAULT_HOST, DEFAULT_PORT, FoxgloveRelay

SUBSCRIPTION_DEPTH = 100   # messages a topic may fall behind before DDS drops the oldest


def relay_qos(publishers: list[Any]) -> QoSProfile:
    """Return the QoS that matches every one of ``publishers`` (their TopicEndpointInfo)."""
    reliable = all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in publishers)
    latched = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                  for p in publishers)
    return QoSProfile(
        depth=SUBSCRIPTION_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)


class ViewRelayNode(GuardedNode):
    """Relay every topic of the graph to Foxglove clients."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__('view_relay', **kwargs)
        host = declare(self, 'host', DEFAULT_HOST,
                       'Address the WebSocket server listens on; 0.0.0.0 exposes every topic '
                       'to the network', read_only=True)
        port = declare(self, 'port', DEFAULT_PORT,
                       'TCP port of the WebSocket server; 0: any free port', low=0, high=65535,
                       read_only=True)
        period = declare(self, 'discovery_period', 0.1,
                         'Period of the search for new topics [s, wall clock]',
                         low=0.01, high=10.0, read_only=True)
        self.relay = FoxgloveRelay(host, port)
        self._typestore = jazzy_typestore()
        self._relayed: dict[str, Any] = {}
        self._refused: set[tuple[str, str]] = set()   # (topic, type) whose type is not known
        # Wall-clock timer: discovery goes on even before any /clock arrives.
        self.create_timer(period, self._discover, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(f'Foxglove WebSocket server on {self.relay.url}')

    def _discover(self) -> None:
        try:
            self.relay.replay_latched()
            for topic, types in self.get_topic_names_and_types():
                if topic in self._relayed:
                    self.relay.set_latched_depth(topic, self.count_publishers(topic))
                elif (topic, types[0]) not in self._refused:
                    publishers = self.get_publishers_info_by_topic(topic)
                    if publishers:
                        self._subscribe(topic, types[0], publishers)
        except RCLError:   # a graph query racing the shutdown of SIGINT/SIGTERM: not an error
            if self.context.ok():
                raise

    def _subscribe(self, topic: str, msgtype: str, publishers: list[Any]) -> None:
        try:
            ensure_type(self._typestore, msgtype)
            msg_class = message_class(msgtype)
        except (KeyError, AttributeError, ModuleNotFoundError, ValueError) as err:
            self.get_logger().warn(f'cannot relay {topic}: {err}')
            self._refused.add((topic, msgtype))
            return
        msgdef, _ = self._typestore.generate_msgdef(msgtype, ros_version=2)
        qos = relay_qos(publishers)
        latched = qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
        self.relay.advertise(topic, msgtype, msgdef, latched=latched)
        self.relay.set_latched_depth(topic, len(publishers))
        forward = self.relay.forward

        def relay(data: bytes) -> None:
            forward(topic, data, time.time_ns())   # 0.1 µs; Clock.now() takes 3.5 µs

        self._relayed[topic] = self.create_subscription(
            msg_class, topic, relay, qos, raw=True, safe_output=False)
        self.get_logger().info(f'relaying {topic} [{msgtype}]'
                               + (' (transient local)' if latched else ''))

    def destroy_node(self) -> None:
        """Stop the server, log the messages forwarded per topic, destroy the node."""
        self.relay.close()
        # Not the node's logger: after SIGINT its /rosout publisher is gone with the context.
        rclpy.logging.get_logger(f'{self.get_name()}.summary').info(self.relay.summary())
        super().destroy_node()


def serve(host: str = DEFAULT_HOST, port: int = DEFAULT_PORT,
          args: list[str] | None = None) -> None:
    """
    Relay the graph on ``ws://host:port`` until SIGTERM or SIGINT (``KeyboardInterrupt``).

    The function behind ``robotica view``: ``args`` are ROS arguments (``--ros-args ...``).
    Raises :class:`robotica_sim.view.relay.RelayStartError` (a ``ValueError``) when the server
    cannot listen (the port is in use, the host unknown). The server is stopped and the counts
    logged however it ends.
    """
    rclpy.init(args=args)   # its SIGINT and SIGTERM handlers shut the context down
    node: ViewRelayNode | None = None
    try:
        node = ViewRelayNode(parameter_overrides=[Parameter('host', value=host),
                                                  Parameter('port', value=port)])
        executor = EventsExecutor()
        executor.add_node(node)
        try:
            while rclpy.ok():
                executor.spin_once(timeout_sec=0.5)
        except ExternalShutdownException:   # SIGTERM during the wait
            pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


def main(args=None) -> None:
    """Relay until SIGINT or SIGTERM."""
    run_node(ViewRelayNode, args, executor_factory=EventsExecutor)
