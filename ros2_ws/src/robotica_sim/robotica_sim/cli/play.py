"""
Replay a recorded bag: its topics republished in time order, with /clock, at a rate factor.

The ``ros2 bag play`` of the pip route (rosbag2 cannot be installed from PyPI). Every selected
topic (``--topics``; all by default) is published again as recorded (serialized, not decoded)
at its receive time in the bag, scaled by ``--rate``, on its own name or the one ``--remap``
gives it (two topics on one name are refused). ``/clock`` is replayed when the bag has it
(``robotica run`` records it); otherwise it is published at each message's bag time, so nodes
with ``use_sim_time`` follow the replay. Publishers are reliable; a topic with a single message
(a path, a model) is also transient-local, so that a node started later still receives it. The
player waits ``--wait`` seconds for subscribers to match before it starts, shows its progress on
stderr and exits with 0 at the end, 1 for a bag it cannot read, 2 for bad arguments (a topic the
bag does not have, a remapping that is not a ROS name), 130 on Ctrl-C or SIGTERM.
"""
import argparse
import sys
import time

from robotica_sim.bags.info import BagError
from robotica_sim.bags.player import open_playback, parse_remaps, wall_time
from robotica_sim.bags.typestore import message_class
from robotica_sim.cli.options import path, real

HELP = 'republish a bag in time order with /clock'
EPILOG = """examples:
  robotica play runs/demo-20261123-101500/bag
  robotica play BAG --rate 5                          five times faster
  robotica play BAG --topics /odom /ground_truth/odom --remap /odom:=/replayed/odom
"""
PROGRESS_PERIOD = 1.0   # [s] wall clock between progress lines
ACK_TIMEOUT = 2.0       # [s] longest wait per topic for the subscribers' acknowledgements
MIN_RATE = 1e-3         # a day's bag at this rate replays in about 3 years: slower is a typo
MAX_RATE = 1e6


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica play``."""
    parser.add_argument('bag', type=path, help='bag directory (with metadata.yaml)')
    parser.add_argument('--rate', type=real(MIN_RATE, MAX_RATE), default=1.0,
                        help=f'speed-up of the replay ({MIN_RATE:g} to {MAX_RATE:g}; 2: twice '
                        'as fast)')
    parser.add_argument('--topics', nargs='+', default=None, metavar='TOPIC',
                        help='replay only these topics (default: all)')
    parser.add_argument('--remap', nargs='+', default=[], metavar='FROM:=TO',
                        help='publish topic FROM as TO')
    parser.add_argument('--wait', type=real(0.0, 3600.0), default=1.0,
                        help='seconds to wait for subscribers to match before the start')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')


def main(args: argparse.Namespace) -> int:
    """Replay the bag; return the exit code."""
    # A SelectionError (a remapping or topic that cannot be) is one line and exit 2, a BagError
    # one line and exit 1 (robotica_sim.cli.main).
    playback = open_playback(args.bag, args.topics, parse_remaps(args.remap))
    import rclpy
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from rclpy.signals import SignalHandlerOptions
    from rosgraph_msgs.msg import Clock

    # No ROS arguments (rcl would read --remap's FROM:=TO as a deprecated remapping of its own),
    # and no rclpy signal handlers: Ctrl-C and SIGTERM raise KeyboardInterrupt here (see
    # robotica_sim.cli.main), so the replay stops between two publications, never inside one.
    rclpy.init(args=[], signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('robotica_play')
    try:
        publishers = {}
        for topic in playback.topics.values():
            try:
                msg_class = message_class(topic.msgtype)
            except (ImportError, AttributeError, ValueError):
                print(f'robotica play: skipping {topic.name}: type {topic.msgtype} is not '
                      'installed', file=sys.stderr)
                continue
            latched = topic.count == 1
            qos = QoSProfile(depth=1 if latched else 1000,
                             reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL if latched
                             else DurabilityPolicy.VOLATILE)
            publishers[topic.name] = node.create_publisher(msg_class, topic.output, qos)
        outputs = {t.output for t in playback.topics.values() if t.name in publishers}
        clock = None if '/clock' in outputs else node.create_publisher(Clock, '/clock', 10)
        time.sleep(args.wait)   # discovery: let subscribers match before the first message
        return _play(playback, publishers, clock, args)   # Ctrl-C: 'interrupted', 130 (cli.main)
    finally:
        playback.close()
        node.destroy_node()
        rclpy.try_shutdown()


def _play(playback, publishers: dict, clock, args: argparse.Namespace) -> int:
    from builtin_interfaces.msg import Time
    from rosgraph_msgs.msg import Clock

    start, duration = playback.start, (playback.end - playback.start) * 1e-9
    wall_start = time.monotonic()
    next_report, count, last_clock = wall_start + PROGRESS_PERIOD, 0, None
    try:
        for stamp, topic, data in playback.messages():
            delay = wall_time(stamp, start, wall_start, args.rate) - time.monotonic()
            if delay > 0.0:
                time.sleep(delay)
            if clock is not None and stamp != last_clock:
                clock.publish(Clock(clock=Time(sec=stamp // 1_000_000_000,
                                               nanosec=stamp % 1_000_000_000)))
                last_clock = stamp
            if topic.name in publishers:
                publishers[topic.name].publish(data)
                count += 1
            if not args.quiet and time.monotonic() >= next_report:
                next_report += PROGRESS_PERIOD
                print(f'robotica play: {(stamp - start) * 1e-9:.2f} / {duration:.2f} s, '
                      f'{count} messages', file=sys.stderr, flush=True)
    except BagError as err:
        print(f'robotica play: {err} after {count} messages', file=sys.stderr)
        return 1
    # Reliable samples still in flight are lost if the publisher goes away before the
    # subscribers acknowledge them (a round trip lost the bag's last message that way).
    from rclpy.duration import Duration
    for publisher in publishers.values():
        publisher.wait_for_all_acked(Duration(seconds=ACK_TIMEOUT))
    if not args.quiet:
        print(f'robotica play: done, {count} messages of {len(publishers)} topics in '
              f'{time.monotonic() - wall_start:.2f} s', file=sys.stderr)
    return 0
