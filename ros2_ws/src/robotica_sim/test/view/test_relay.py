"""
Tests of the view relay (``robotica view``): a Foxglove client sees the graph and its messages.

A probe node publishes ``/odom`` (nav_msgs/Odometry as robotica's streams: reliable, transient
local), ``/robot_description`` (std_msgs/String, latched, published once before any client
connects) and ``imu/data_raw`` (sensor_msgs/Imu with sensor-data QoS: best effort, volatile).
The relay runs as its executable on a free port. The client is the ``websockets`` package
speaking the Foxglove WebSocket protocol (subprotocol ``foxglove.sdk.v1`` for foxglove-sdk 0.30):
JSON ``advertise`` messages list the channels; a ``subscribe`` request is answered by binary
``MessageData`` frames (opcode 1, subscription id u32, log time u64, little endian, then the
payload), whose CDR payload rclpy deserializes independently of the relay.
"""
import json
import signal
import socket
import struct
import time

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import qos_profile_sensor_data
from rclpy.serialization import deserialize_message
from robotica_kin.ros.qos import LATCHED_QOS, STREAM_PUB_QOS
from robotica_sim.nodes.view_relay import serve
from robotica_sim.view.relay import FoxgloveRelay, RelayStartError, SUBPROTOCOL
from sensor_msgs.msg import Imu
from std_msgs.msg import String
from websockets.sync.client import connect

URDF = '<robot name="probe"><link name="base_link"/></robot>'
MESSAGE_DATA = 1   # binary opcode of the Foxglove WebSocket protocol
HEADER = struct.Struct('<BIQ')


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


def odometry(k: int) -> Odometry:
    msg = Odometry()
    msg.header.stamp.sec, msg.header.frame_id, msg.child_frame_id = k, 'odom', 'base_link'
    msg.pose.pose.position.x, msg.pose.pose.position.y = 0.25 * k, -1.5
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = 0.6, 0.8
    msg.pose.covariance[0] = 1e-3 * k
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = 0.5, -0.125
    return msg


def connection(port: int, executor, spin, timeout: float = 10.0):
    """Return a connection to the relay on ``port``, retried while its process starts."""
    deadline = time.monotonic() + timeout
    while True:   # the port opens when the relay is built
        try:
            return connect(f'ws://127.0.0.1:{port}', subprotocols=[SUBPROTOCOL],
                           open_timeout=5.0, proxy=None)
        except ConnectionRefusedError:
            if time.monotonic() > deadline:
                raise
            spin(executor, lambda: False, timeout=0.1)


class FoxgloveClient:
    """The channels a Foxglove server advertised and the messages it sent, by subscription."""

    def __init__(self, ws) -> None:
        self.ws = ws
        self.channels: dict[str, dict] = {}
        self.messages: dict[int, list[tuple[int, bytes]]] = {}   # subscription -> (time, data)

    def read(self, timeout: float) -> None:
        """Take what the server sent within ``timeout`` [s]."""
        try:
            frame = self.ws.recv(timeout=timeout)
        except TimeoutError:
            return
        if isinstance(frame, bytes):
            opcode, subscription, log_time = HEADER.unpack_from(frame)
            assert opcode == MESSAGE_DATA
            self.messages.setdefault(subscription, []).append(
                (log_time, frame[HEADER.size:]))
        elif (message := json.loads(frame))['op'] == 'advertise':
            self.channels.update({c['topic']: c for c in message['channels']})

    def subscribe(self, topics: dict[int, str]) -> None:
        """Subscribe to each topic under its subscription id."""
        self.ws.send(json.dumps({'op': 'subscribe', 'subscriptions': [
            {'id': sub, 'channelId': self.channels[topic]['id']}
            for sub, topic in topics.items()]}))


@pytest.mark.ros
def test_client_sees_every_topic_and_decodes_odom(start_node, ros_node, spin, read_output):
    node, executor = ros_node
    odom_pub = node.create_publisher(Odometry, 'odom', STREAM_PUB_QOS)
    imu_pub = node.create_publisher(Imu, 'imu/data_raw', qos_profile_sensor_data)
    node.create_publisher(String, 'robot_description', LATCHED_QOS).publish(String(data=URDF))
    port = free_port()
    started = time.time_ns()
    relay = start_node('robotica_sim', 'view_relay', '-p', f'port:={port}')
    with connection(port, executor, spin) as ws:
        client = FoxgloveClient(ws)
        sent = {}

        def pump_until(predicate, timeout: float = 10.0) -> bool:
            """Publish /odom and an IMU reading, spin, read the client until ``predicate()``."""
            deadline = time.monotonic() + timeout
            while not predicate() and time.monotonic() < deadline:
                k = len(sent)
                sent[k] = odometry(k)
                odom_pub.publish(sent[k])
                imu_pub.publish(Imu())
                spin(executor, lambda: False, timeout=0.01)
                client.read(timeout=0.04)
            return predicate()

        def published_topics() -> dict[str, str]:
            return {topic: types[0] for topic, types in node.get_topic_names_and_types()
                    if node.count_publishers(topic)}

        assert pump_until(lambda: {'/odom', '/robot_description', '/imu/data_raw'}
                          <= published_topics().keys() <= client.channels.keys()), \
            f'{sorted(client.channels)} advertised\n{read_output(relay)}'
        for topic, msgtype in published_topics().items():
            channel = client.channels[topic]
            assert (channel['schemaName'], channel['schemaEncoding'], channel['encoding']) == \
                (msgtype, 'ros2msg', 'cdr'), topic
        schema = client.channels['/odom']['schema']
        assert schema.startswith('std_msgs/Header header\nstring child_frame_id\n')
        for definition in ('MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\n'
                           'float64[36] covariance',
                           'MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\n'
                           'float64 w', 'MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec'):
            assert definition in schema

        client.subscribe({1: '/odom', 2: '/robot_description', 3: '/imu/data_raw'})
        assert pump_until(lambda: len(client.messages.get(1, [])) >= 5
                          and client.messages.get(2) and client.messages.get(3))
        for log_time, data in client.messages[1]:
            odom = deserialize_message(data, Odometry)
            assert odom == sent[odom.header.stamp.sec]
            assert started < log_time < time.time_ns()
        for _, data in client.messages[2]:   # latched: published before the client connected
            assert deserialize_message(data, String).data == URDF

    relay.send_signal(signal.SIGINT)
    assert relay.wait(timeout=10) == 0
    output = read_output(relay)
    forwarded = int(output.split('/odom ')[-1].split(',')[0])
    assert forwarded >= len(client.messages[1])
    assert 'Traceback' not in output


@pytest.mark.ros
def test_port_in_use_is_refused(start_node, read_output):
    with socket.socket() as busy:
        busy.bind(('127.0.0.1', 0))
        busy.listen()
        port = busy.getsockname()[1]
        relay = start_node('robotica_sim', 'view_relay', '-p', f'port:={port}')
        assert relay.wait(timeout=15) == 2
        assert f'cannot listen on ws://127.0.0.1:{port}: address already in use' in \
            read_output(relay)
        with pytest.raises(RelayStartError, match='address already in use'):
            serve(port=port, args=[])


def test_relay_refuses_a_busy_port_and_a_second_advertisement():
    first = FoxgloveRelay(port=0)
    try:
        with pytest.raises(ValueError, match=f'127.0.0.1:{first.port}: address already in use'):
            FoxgloveRelay(port=first.port)
        first.advertise('/a', 'std_msgs/msg/String', 'string data\n')
        with pytest.raises(ValueError, match='/a is advertised already'):
            first.advertise('/a', 'std_msgs/msg/String', 'string data\n')
    finally:
        first.close()
