"""
Crash safety of the recorder: SIGKILL it mid-run, repair the bag, read what it had received.

A counter is published at 100 Hz (wall clock) while the recorder (flush_period 1 s) records;
the recorder is killed about 3 s in. Reference: the counters this test published. The repaired
bag must hold a gap-free run of them from the first recorded one up to at least the counter
published 1.5 s before the kill (the 1 s flush period plus delivery and scheduling slack on a
loaded 2-core machine).
"""
import signal
import time

import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_sim.bags.info import bag_info, BagError
from robotica_sim.bags.repair import repair_bag
from rosbags.highlevel import AnyReader
from std_msgs.msg import Float64
from std_srvs.srv import Trigger

pytestmark = pytest.mark.ros


def test_a_killed_recorder_leaves_a_repairable_bag(start_node, ros_node, spin, call, tmp_path):
    node, executor = ros_node
    out = tmp_path / 'bag'
    recorder = start_node('robotica_sim', 'recorder', '-p', f'output:={out}',
                          '-p', "topics:=['/counter']", '-p', 'flush_period:=1.0')
    pub = node.create_publisher(Float64, '/counter',
                                QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE))
    ready = node.create_client(Trigger, '/recorder/ready')
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    assert call(executor, ready, Trigger.Request()).success
    sent = []     # (wall time, counter)
    start = time.monotonic()
    while time.monotonic() - start < 3.0:
        sent.append((time.monotonic(), float(len(sent))))
        pub.publish(Float64(data=sent[-1][1]))
        spin(executor, lambda: False, timeout=0.01)
    recorder.send_signal(signal.SIGKILL)
    killed = time.monotonic()
    assert recorder.wait(timeout=10) == -signal.SIGKILL
    with pytest.raises(BagError, match='robotica bag repair'):
        bag_info(out)
    report = repair_bag(out)
    with AnyReader([out]) as reader:
        kept = [reader.deserialize(raw, c.msgtype).data for c, _, raw in reader.messages()]
    assert kept and kept == [kept[0] + i for i in range(len(kept))]    # in order, no gap
    assert report.messages == len(kept)
    before = [value for at, value in sent if at <= killed - 1.5]
    assert kept[-1] >= before[-1], (kept[-1], before[-1], len(sent))
