"""
Recorder throughput: the message rates the ``recorder`` node takes without losing any.

For each offered rate, a publisher in this process sends ``sensor_msgs/Imu`` messages (a
typical stream, 324 bytes serialized) on one reliable topic (keep-last 1000, the history of a
busy publisher) at that rate for a few seconds, in 1 ms batches, to a recorder node running in
its own process (EventsExecutor, MCAP with zstd). The recorder is then stopped (SIGINT: it
drains what DDS delivered and closes the bag) and the bag's message count is compared with the
count sent. Reported per rate: the rate achieved by the publisher, the messages recorded and
lost, and the recorder's CPU time per message.
"""
import os
from pathlib import Path
import resource
import signal
import subprocess
import tempfile
import time
from typing import Callable, Optional

from ament_index_python.packages import get_package_prefix
from robotica_sim.benchmarks.measurement_row import MeasurementRow
import yaml

TOPIC = '/bench/imu'
RATES = (5_000, 10_000, 20_000, 30_000)   # [messages/s]
BATCH_PERIOD = 0.001                      # [s] the publisher tops up its count every 1 ms


def _recorded(bag: Path) -> int:
    information = yaml.safe_load((bag / 'metadata.yaml').read_text())
    return sum(t['message_count']
               for t in information['rosbag2_bagfile_information']['topics_with_message_count']
               if t['topic_metadata']['name'] == TOPIC)


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def throughput_run(rate: float, seconds: float) -> tuple[int, float, int, float]:
    """
    Offer ``rate`` messages/s for ``seconds``; return (sent, achieved rate, recorded, CPU [s]).

    The CPU time is the recorder process's, user plus system, over its whole life.
    """
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import Imu

    recorder_exe = Path(get_package_prefix('robotica_sim')) / 'lib' / 'robotica_sim' / 'recorder'
    with tempfile.TemporaryDirectory() as tmp:
        bag = Path(tmp) / 'bag'
        cpu_before = _children_cpu()
        recorder = subprocess.Popen(
            [str(recorder_exe), '--ros-args', '-p', f'output:={bag}',
             '-p', f"topics:=['{TOPIC}']", '--log-level', 'warn'],
            env=dict(os.environ), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        rclpy.init()
        node = rclpy.create_node('recorder_benchmark')
        publisher = node.create_publisher(
            Imu, TOPIC, QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE))
        try:
            deadline = time.monotonic() + 30.0
            while publisher.get_subscription_count() == 0:
                if time.monotonic() > deadline or recorder.poll() is not None:
                    raise RuntimeError('the recorder did not subscribe within 30 s')
                time.sleep(0.05)
            time.sleep(0.5)    # the recorder's side of the match
            msg = Imu()
            sent = 0
            start = time.monotonic()
            while (elapsed := time.monotonic() - start) < seconds:
                target = int(rate * elapsed)
                while sent < target:
                    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(sent, 1_000_000)
                    publisher.publish(msg)
                    sent += 1
                time.sleep(BATCH_PERIOD)
            achieved = sent / (time.monotonic() - start)
            publisher.wait_for_all_acked()
        finally:
            node.destroy_node()
            rclpy.try_shutdown()
            recorder.send_signal(signal.SIGINT)
            try:
                recorder.wait(timeout=60)
            except subprocess.TimeoutExpired:
                recorder.kill()
                recorder.wait()
                raise RuntimeError('the recorder did not close its bag within 60 s of SIGINT')
        if not (bag / 'metadata.yaml').is_file():
            raise RuntimeError(f'the recorder exited with {recorder.returncode} without '
                               'closing its bag')
        return sent, achieved, _recorded(bag), _children_cpu() - cpu_before


def recorder_benchmark(rates: tuple[float, ...] = RATES, seconds: float = 5.0,
                       progress: Optional[Callable[[str], None]] = None
                       ) -> list[MeasurementRow]:
    """Run :func:`throughput_run` at each rate; return one row per rate."""
    rows = []
    for rate in rates:
        if progress:
            progress(f'recorder at {rate:g} messages/s for {seconds:g} s')
        sent, achieved, recorded, cpu = throughput_run(rate, seconds)
        rows.append(MeasurementRow(
            f'recorder, offered {rate:g} msg/s', recorded / (sent / achieved), 'msg/s recorded',
            f'{sent} sent at {achieved:.0f} msg/s, {recorded} recorded, {sent - recorded} '
            f'lost; recorder CPU {1e6 * cpu / max(recorded, 1):.1f} µs per message'))
    return rows
