"""
The Foxglove side of ``robotica view``: serialized ROS 2 messages relayed to the Foxglove app.

A :class:`FoxgloveRelay` is a Foxglove WebSocket server (the maintained ``foxglove-sdk``, protocol
``foxglove.websocket.v1``) with one channel per relayed ROS 2 topic, as foxglove_bridge serves
them: schema name the type (``nav_msgs/msg/Odometry``), schema encoding ``ros2msg`` (the message
definition with its dependencies, the text an MCAP bag of rosbag2 holds), message encoding
``cdr`` (the bytes as received, never deserialized here). The log time of a message is its
receive time. The server sends each message to the clients subscribed to its channel.

Latched topics (every publisher transient local: ``/robot_description``, ``/tf_static``, a
path, a map) reach a client that subscribes after they were published: the relay keeps the last
message of each publisher (as many of the newest as there are publishers) and sends them again,
with their receive times, when a client subscribes to the channel. Every client subscribed to
the channel then receives them once more (the protocol has no per-client send in this SDK
version's channel API).

The ROS side (discovery, subscriptions, QoS) is the node
:mod:`robotica_sim.nodes.view_relay`; this module imports no ROS package.
"""
from collections import deque
import queue

import foxglove
from foxglove.websocket import ChannelView, Client, ServerListener
from robotica_sim.bags.metadata import MESSAGE_ENCODING, SCHEMA_ENCODING

__all__ = ['DEFAULT_HOST', 'DEFAULT_PORT', 'FoxgloveRelay', 'RelayStartError', 'SUBPROTOCOL']

DEFAULT_HOST = '127.0.0.1'   # loopback: nothing listens off the machine unless asked
DEFAULT_PORT = 8765          # the port of foxglove_bridge and of the Foxglove app's default
SUBPROTOCOL = 'foxglove.sdk.v1'   # 0.30 speaks only this one (older: foxglove.websocket.v1)
_BIND_ERROR = 'Failed to bind port: '


class RelayStartError(ValueError):
    """The server cannot listen on the host and port asked for (port in use, unknown host)."""


class FoxgloveRelay(ServerListener):
    """
    A Foxglove WebSocket server relaying serialized (CDR) ROS 2 messages, one channel per topic.

    Parameters
    ----------
    host
        Address to listen on; ``127.0.0.1`` keeps the server on this machine, ``0.0.0.0``
        exposes it to the network (anyone who reaches the port sees every topic).
    port
        TCP port; 0 picks a free one (:attr:`port` tells which).
    name
        Server name shown by the Foxglove app.

    Raises :class:`RelayStartError` (a ``ValueError``) when the server cannot listen, naming
    the address and the reason (e.g. ``address already in use``).

    """

    def __init__(self, host: str = DEFAULT_HOST, port: int = DEFAULT_PORT,
                 name: str = 'robotica view') -> None:
        # A context of its own: channels of another relay in the same process stay apart.
        self._context = foxglove.Context()
        self._channels: dict[str, foxglove.Channel] = {}
        self._topics_by_id: dict[int, str] = {}
        self._latched: dict[str, deque[tuple[int, bytes]]] = {}   # topic -> (log time, data)
        self._replays: queue.SimpleQueue[str] = queue.SimpleQueue()   # SDK thread -> caller's
        self.counts: dict[str, int] = {}   # topic -> messages handed to the server
        try:
            self._server = foxglove.start_server(name=name, host=host, port=port,
                                                 server_listener=self, context=self._context)
        except RuntimeError as err:
            reason = str(err).split(_BIND_ERROR, 1)[-1]
            raise RelayStartError(f'cannot listen on ws://{host}:{port}: '
                                  f'{reason[:1].lower() + reason[1:]}') from None
        self.host = host
        self.port = self._server.port

    @property
    def url(self) -> str:
        """Return the address a Foxglove client connects to (``ws://host:port``)."""
        return f'ws://{self.host}:{self.port}'

    def advertise(self, topic: str, msgtype: str, msgdef: str, latched: bool = False) -> None:
        """
        Offer ``topic`` to the clients: type ``msgtype`` (``pkg/msg/Name``), definition ``msgdef``.

        ``msgdef`` is the ``ros2msg`` text with the definitions it depends on (rosbag2's MCAP
        schema). A ``latched`` topic's last messages are sent again to each new subscriber.
        Raises ValueError if ``topic`` is advertised already.
        """
        if topic in self._channels:
            raise ValueError(f'topic {topic} is advertised already')
        schema = foxglove.Schema(name=msgtype, encoding=SCHEMA_ENCODING, data=msgdef.encode())
        channel = foxglove.Channel(topic, schema=schema, message_encoding=MESSAGE_ENCODING,
                                   context=self._context)
        self._channels[topic] = channel
        self._topics_by_id[channel.id()] = topic
        self.counts[topic] = 0
        if latched:
            self._latched[topic] = deque(maxlen=1)

    def set_latched_depth(self, topic: str, publishers: int) -> None:
        """Keep the last ``publishers`` messages of latched ``topic`` (one per publisher)."""
        kept = self._latched.get(topic)
        if kept is not None and kept.maxlen != max(1, publishers):
            self._latched[topic] = deque(kept, maxlen=max(1, publishers))

    def forward(self, topic: str, data: bytes, log_time: int) -> None:
        """Send one serialized message of ``topic``, received at ``log_time`` [ns since epoch]."""
        self._channels[topic].log(data, log_time=log_time)
        self.counts[topic] += 1
        kept = self._latched.get(topic)
        if kept is not None:
            kept.append((log_time, data))

    def replay_latched(self) -> int:
        """
        Send the kept messages of latched topics that a client subscribed to since the last call.

        Call it from the thread that calls :meth:`forward` (the SDK reports subscriptions on a
        thread of its own); return the number of messages sent.
        """
        sent = 0
        while True:
            try:
                topic = self._replays.get_nowait()
            except queue.Empty:
                return sent
            for log_time, data in list(self._latched[topic]):
                self._channels[topic].log(data, log_time=log_time)
                sent += 1

    # -- ServerListener: called by the SDK on a thread of its own ----------------------------
    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        """Queue the replay of a latched topic for a new subscriber."""
        topic = self._topics_by_id.get(channel.id)
        if topic in self._latched:
            self._replays.put(topic)

    def summary(self) -> str:
        """
        Return one line: the messages forwarded per topic, busiest first.

        >>> relay = FoxgloveRelay.__new__(FoxgloveRelay)
        >>> relay.counts = {'/tf': 20, '/odom': 50, '/map': 0}
        >>> relay.summary()
        'forwarded 70 messages: /odom 50, /tf 20, /map 0'
        """
        ranked = sorted(self.counts.items(), key=lambda item: (-item[1], item[0]))
        return (f'forwarded {sum(self.counts.values())} messages: '
                + ', '.join(f'{topic} {count}' for topic, count in ranked))

    def close(self) -> None:
        """Stop the server: clients are disconnected, the port is free again."""
        self._server.stop()
