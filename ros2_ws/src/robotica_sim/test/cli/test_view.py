"""Tests of ``robotica view`` and ``robotica run --view``: the Foxglove relay from the command."""
import importlib.util
import os
from pathlib import Path
import signal
import socket
import subprocess
import sys

from nav_msgs.msg import Odometry
import pytest
from rclpy.serialization import deserialize_message
from robotica_kin.ros.qos import STREAM_PUB_QOS
from robotica_sim.cli.main import run_verb


def _relay_tests():
    """Import test/view/test_relay.py (the test folders are no packages) for its client."""
    path = Path(__file__).resolve().parents[1] / 'view' / 'test_relay.py'
    spec = importlib.util.spec_from_file_location('view_test_relay', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


RELAY = _relay_tests()
FoxgloveClient, connection, free_port = RELAY.FoxgloveClient, RELAY.connection, RELAY.free_port
ROBOTICA = [sys.executable, '-m', 'robotica_sim.cli.main']


def robotica(*args: str, **kwargs) -> subprocess.Popen:
    """Start ``robotica ARGS`` (stdout and stderr piped, text)."""
    return subprocess.Popen([*ROBOTICA, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=dict(os.environ), **kwargs)


@pytest.mark.parametrize('argv', [
    ['view', '--port', '0'], ['view', '--port', '65536'], ['view', '--host', ''],
    ['run', 'demo', '--view', '--port', '-1'], ['run', 'demo', '--view', '--port', '8e3']])
def test_a_bad_host_or_port_is_a_usage_error_in_one_line(capsys, argv):
    assert run_verb(argv) == 2
    out, err = capsys.readouterr()
    assert out == '' and err.count('\n') == 1
    assert err.startswith(f'robotica {argv[0]}: error: argument --') and \
        ('--port' in err or '--host' in err)


@pytest.mark.ros
def test_view_on_a_busy_port_says_so_in_one_line_and_exits_2(ros_domain):
    with socket.socket() as busy:
        busy.bind(('127.0.0.1', 0))
        busy.listen()
        port = busy.getsockname()[1]
        out, err = robotica('view', '--port', str(port)).communicate(timeout=60)
    assert err == f'robotica view: error: cannot listen on ws://127.0.0.1:{port}: address ' \
        'already in use (os error 98)\n'
    assert out == ''


@pytest.mark.ros
@pytest.mark.parametrize('stop', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_view_relays_the_graph_until_a_signal_then_exits_0(ros_node, spin, stop):
    node, executor = ros_node
    odom = node.create_publisher(Odometry, 'odom', STREAM_PUB_QOS)
    port = free_port()
    view = robotica('view', '--port', str(port))
    try:
        with connection(port, executor, spin) as ws:
            client = FoxgloveClient(ws)

            def advertised() -> bool:
                odom.publish(RELAY.odometry(0))
                client.read(timeout=0.1)
                return '/odom' in client.channels

            assert spin(executor, advertised, timeout=15.0), sorted(client.channels)
        assert client.channels['/odom']['schemaName'] == 'nav_msgs/msg/Odometry'
        view.send_signal(stop)
        out, err = view.communicate(timeout=20)
    finally:
        view.kill()
    assert view.returncode == 0, err
    assert 'Traceback' not in err and 'interrupted' not in err
    assert f'Foxglove WebSocket server on ws://127.0.0.1:{port}' in err


@pytest.mark.ros
@pytest.mark.slow
def test_run_with_view_relays_odom_during_the_run(ros_node, spin, tmp_path):
    node, executor = ros_node
    port = free_port()
    run = robotica('run', 'demo', '--duration', '2', '--view', '--port', str(port), '--quiet',
                   '--output-dir', str(tmp_path / 'run'))
    try:
        with connection(port, executor, spin, timeout=60.0) as ws:   # the run starts first
            client = FoxgloveClient(ws)

            def odom_advertised() -> bool:
                client.read(timeout=0.1)
                return '/odom' in client.channels or run.poll() is not None

            spin(executor, odom_advertised, timeout=60.0)
            assert '/odom' in client.channels, sorted(client.channels)
            client.subscribe({1: '/odom'})
            spin(executor, lambda: client.read(timeout=0.1) or 1 in client.messages
                 or run.poll() is not None, timeout=60.0)
        out, err = run.communicate(timeout=120)
    finally:
        run.kill()
    assert run.returncode == 0, err
    assert f'view: relayed on ws://127.0.0.1:{port}' in out
    assert client.channels['/odom']['schemaEncoding'] == 'ros2msg'
    odom = deserialize_message(client.messages[1][-1][1], Odometry)
    assert (odom.header.frame_id, odom.child_frame_id) == ('odom', 'base_link')
    assert 'forwarded' in (tmp_path / 'run' / 'logs' / 'view_relay.log').read_text()
