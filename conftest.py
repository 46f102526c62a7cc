"""Fixtures shared by the node and end-to-end tests: real processes on a private ROS domain.

Every test that touches ROS gets its own ``ROS_DOMAIN_ID`` and loopback-only discovery
(``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, set by ``scripts/env.sh`` and enforced here), so
tests never see each other's nodes and no DDS traffic leaves the machine. When the suite runs in
several processes (``pytest -n``, as ``scripts/test.sh`` does), each process has its own share
of the domain ids, so two tests running at once never share a domain.
"""
import itertools
import os
from pathlib import Path
import signal
import subprocess
import time

import pytest


def _worker() -> tuple[int, int]:
    """Return this pytest process's index and how many run the suite (``pytest -n``)."""
    name = os.environ.get('PYTEST_XDIST_WORKER', '')
    return (int(name[2:]) if name[:2] == 'gw' else 0), int(
        os.environ.get('PYTEST_XDIST_WORKER_COUNT', '1'))


WORKER, WORKERS = _worker()
DOMAINS = range(1, 102)   # the ids whose DDS ports stay below the ephemeral range
MY_DOMAINS = DOMAINS[WORKER::WORKERS]
"""The domains of this process: each of ``pytest -n`` workers has its own, never shared."""
if WORKERS > 1:   # tests that run on the session's domain (no ros_domain fixture): one each
    os.environ['ROS_DOMAIN_ID'] = str(MY_DOMAINS[0])
_domains = itertools.count(os.getpid() % 40)


@pytest.fixture
def ros_domain(monkeypatch):
    """Give the test a fresh ROS domain of this process's own and loopback-only discovery."""
    domain = MY_DOMAINS[1 + next(_domains) % (len(MY_DOMAINS) - 1)]
    monkeypatch.setenv('ROS_DOMAIN_ID', str(domain))
    monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    monkeypatch.delenv('ROS_LOCALHOST_ONLY', raising=False)
    return domain


@pytest.fixture
def ros_node(ros_domain):
    """Yield an in-process rclpy node (and its executor) on the test's domain."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    context = rclpy.Context()
    rclpy.init(context=context, domain_id=ros_domain)
    node = rclpy.create_node('test_probe', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    yield node, executor
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown(context=context)


def spin_until(executor, predicate, timeout: float = 15.0) -> bool:
    """Spin ``executor`` until ``predicate()`` is true or ``timeout`` [s] passes."""
    deadline = time.monotonic() + timeout
    while not predicate() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    return predicate()


@pytest.fixture
def spin():
    """Return :func:`spin_until`."""
    return spin_until


def publish_until(executor, publisher, msg, predicate, period: float = 0.25,
                  timeout: float = 15.0) -> bool:
    """
    Publish ``msg`` every ``period`` [s] until ``predicate()`` is true or ``timeout`` [s] passes.

    Graph discovery (``get_subscription_count``) can report a match before the node's own
    output writer has matched the test's reader, so the answer to a single message may go
    nowhere; for a node that answers each input with an output, resending is the way to wait.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        publisher.publish(msg)
        if spin_until(executor, predicate, min(period, deadline - time.monotonic())):
            return True
    return predicate()


@pytest.fixture
def publish():
    """Return :func:`publish_until`."""
    return publish_until


def call_service(executor, client, request, attempts: int = 3, timeout: float = 10.0):
    """
    Call a service and return its response, sending the request again if no answer comes.

    ``wait_for_service`` can return before the server's reply writer has matched the client's
    reply reader; a request answered in that window is lost (the reply has nowhere to go). The
    services of robotica are idempotent, so asking again is safe; ``None`` after ``attempts``.
    """
    assert client.wait_for_service(timeout_sec=15.0)
    for _ in range(attempts):
        future = client.call_async(request)
        if spin_until(executor, future.done, timeout):
            return future.result()
        client.remove_pending_request(future)
    return None


@pytest.fixture
def call():
    """Return :func:`call_service`."""
    return call_service


def executable(package: str, name: str) -> str:
    """Return the installed executable of a node (``ros2 run`` would run the same file)."""
    from ament_index_python.packages import get_package_prefix

    path = Path(get_package_prefix(package)) / 'lib' / package / name
    assert path.is_file(), f'{path} missing: run scripts/setup.sh'
    return str(path)


@pytest.fixture
def start_node(ros_domain, tmp_path):
    """Start node executables in real processes; stop them all at teardown."""
    procs = []

    def start(package: str, name: str, *ros_args: str) -> subprocess.Popen:
        log = open(tmp_path / f'{name}-{len(procs)}.log', 'w+b')
        proc = subprocess.Popen([executable(package, name), '--ros-args', *ros_args],
                                stdout=log, stderr=subprocess.STDOUT, env=dict(os.environ))
        proc.log = log
        procs.append(proc)
        return proc

    yield start
    for proc in procs:
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        proc.log.close()


def output_of(proc: subprocess.Popen) -> str:
    """Return what a process started by ``start_node`` has printed so far."""
    proc.log.flush()
    proc.log.seek(0)
    return proc.log.read().decode(errors='replace')


@pytest.fixture
def read_output():
    """Return :func:`output_of`."""
    return output_of


def check_fuzz_survived(proc: subprocess.Popen, received: dict, recovered: bool,
                        allow_nan: dict | None = None, allow_inf: dict | None = None) -> None:
    """
    Assert what every fuzz test asserts of a node after its hostile burst.

    It recovered (normal output on valid input), is still running, published no non-finite
    number on any output (``allow_nan`` maps a topic to the fields documented as NaN when not
    known, ``allow_inf`` to those where ±inf is documented: REP-117 ranges) and printed no
    traceback.
    """
    from robotica_kin.ros.guarded import non_finite_fields
    assert recovered, f'no normal output after the burst:\n{output_of(proc)}'
    assert proc.poll() is None
    for topic, messages in received.items():
        bad = [non_finite_fields(m, (allow_nan or {}).get(topic, ()),
                                 allow_inf=(allow_inf or {}).get(topic, ())) for m in messages]
        assert not any(bad), f'{topic} published non-finite {[b for b in bad if b][:3]}'
    assert 'Traceback' not in output_of(proc)


@pytest.fixture
def fuzz_survived():
    """Return :func:`check_fuzz_survived`."""
    return check_fuzz_survived
