"""
The recorder's ``~/progress``: the oldest of the newest stamps written on ``progress_topics``.

The recorder records ``/clock`` (rosgraph_msgs/Clock) and ``/x`` (sensor_msgs/JointState, a
message that opens with a std_msgs/Header) with ``progress_topics: [/clock, /x]``. Reference: the
stamps this test publishes. Nothing is published while ``/x`` has not been written once; then the
progress follows whichever topic is behind (``/x`` at 0.4 s and 0.9 s while ``/clock`` is at 1 s
and 2 s; ``/clock`` at 2 s once ``/x`` is at 3 s). A progress topic that the recorder does not
record, or one that is optional (it may never come, and would hold a lockstep run back), is left
out with a warning: with ``topics: [/clock]`` and ``progress_topics: [/clock, /y]`` the progress
is ``/clock``'s.
"""
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.convert import seconds_to_stamp, stamp_to_seconds
from robotica_sim.nodes.recorder import split_progress_topics
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from std_msgs.msg import Header
from std_srvs.srv import Trigger


def test_progress_topics_not_recorded_or_optional_are_left_out():
    assert split_progress_topics(['/clock', '', '/x', '/clock'], [], set()) == (
        ('/clock', '/x'), ())
    assert split_progress_topics(['/clock', '/y'], ['/clock', '/y'], {'/y'}) == (
        ('/clock',), ('/y',))
    assert split_progress_topics(['/clock'], ['/counter'], set()) == ((), ('/clock',))
    assert split_progress_topics([''], [], set()) == ((), ())


QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def recording(start_node, ros_node, spin, call, out, topics: dict, progress_topics: str):
    """Record ``topics`` (name: type) once ready; return the recorder, publishers, progress."""
    node, executor = ros_node
    recorder = start_node('robotica_sim', 'recorder', '-p', f'output:={out}',
                          '-p', f'topics:={list(topics)}',
                          '-p', f'progress_topics:={progress_topics}',
                          '-p', 'progress_period:=0.01')
    publishers = {topic: node.create_publisher(kind, topic, QOS)
                  for topic, kind in topics.items()}
    progress: list[float] = []
    node.create_subscription(Header, '/recorder/progress',
                             lambda m: progress.append(stamp_to_seconds(m.stamp)), QOS)
    # Ready once it has found, subscribed and matched every topic (its discovery runs every
    # 0.1 s, later under load): ask until it is.
    ready = node.create_client(Trigger, '/recorder/ready')
    for _ in range(100):
        answer = call(executor, ready, Trigger.Request())
        if answer is not None and answer.success:
            break
        spin(executor, lambda: False, timeout=0.1)
    assert answer is not None and answer.success, answer
    return recorder, publishers, progress


def clock_at(t: float) -> Clock:
    return Clock(clock=seconds_to_stamp(t))


@pytest.mark.ros
def test_progress_follows_the_slower_topic(start_node, ros_node, spin, publish, call, tmp_path):
    _, executor = ros_node
    _, publishers, progress = recording(start_node, ros_node, spin, call, tmp_path / 'bag',
                                        {'/clock': Clock, '/x': JointState},
                                        "['/clock', '/x']")
    clock, x = publishers['/clock'], publishers['/x']

    def stamped(t: float) -> JointState:
        return JointState(header=Header(stamp=seconds_to_stamp(t)), name=['j'], position=[t])

    # /clock alone, however far: no progress (/x has not been written).
    assert not publish(executor, clock, clock_at(1.0), lambda: bool(progress), period=0.1,
                       timeout=1.0)
    assert publish(executor, x, stamped(0.4), lambda: 0.4 in progress)
    publish(executor, clock, clock_at(2.0), lambda: False, period=0.05, timeout=0.2)
    assert publish(executor, x, stamped(0.9), lambda: 0.9 in progress)
    assert publish(executor, x, stamped(3.0), lambda: 2.0 in progress)
    spin(executor, lambda: False, timeout=0.3)
    # Never ahead of the slower topic: /x's 3 s is not progress while /clock is at 2 s (1 s
    # only if the recorder got /x's 3 s before /clock's 2 s: two writers, no order between them).
    assert progress[0] == 0.4 and progress[-1] == 2.0, progress
    assert set(progress) <= {0.4, 0.9, 1.0, 2.0} and progress == sorted(progress), progress


@pytest.mark.ros
def test_an_unrecorded_progress_topic_is_left_out(start_node, ros_node, spin, publish, call,
                                                  tmp_path, read_output):
    _, executor = ros_node
    recorder, publishers, progress = recording(start_node, ros_node, spin, call,
                                               tmp_path / 'bag', {'/clock': Clock},
                                               "['/clock', '/y']")
    assert publish(executor, publishers['/clock'], clock_at(1.5), lambda: 1.5 in progress)
    assert "progress_topics ['/y'] left out" in read_output(recorder)
