"""
Tests of robotica_sim.grading.summary on a synthetic bag written with rosbags in the test.

The bag holds the 2 m figure eight as ``/path`` and a ground truth 0.1 m to its left that starts
1 mm behind the crossing (where the path's end and start meet): the line must give RMS and
final cross-track 0.100 m, the offset written into the bag (a projection onto the whole path
followed the other lobe and gave 1.234 m), and agree with ``robotica grade``'s metric.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.path_shapes import figure_eight
from robotica_sim.bags.info import BagError
from robotica_sim.bags.typestore import ensure_type, jazzy_typestore
from robotica_sim.grading.metrics import compute_metrics
from robotica_sim.grading.series import load_run
from robotica_sim.grading.summary import summarize_bag
from rosbags.rosbag2 import StoragePlugin, Writer

RADIUS, OFFSET, SPEED, DT = 2.0, 0.1, 0.5, 0.02   # [m], [m], [m/s] along the path, [s]


def offset_pose(s):
    """Pose 0.1 m left of the figure eight at arc length ``s`` (figure_eight's definition)."""
    length = 4.0 * math.pi * RADIUS
    s %= length
    if s < 0.5 * length:   # upper circle, counter-clockwise: left is inward
        a, rho = -0.5 * math.pi + s / RADIUS, RADIUS - OFFSET
        return rho * math.cos(a), RADIUS + rho * math.sin(a), a + 0.5 * math.pi
    a, rho = 0.5 * math.pi - (s - 0.5 * length) / RADIUS, RADIUS + OFFSET   # lower: outward
    return rho * math.cos(a), -RADIUS + rho * math.sin(a), a - 0.5 * math.pi


def stamp(types, t):
    sec = int(math.floor(t))
    return types['builtin_interfaces/msg/Time'](sec=sec, nanosec=round((t - sec) * 1e9))


def header(types, t):
    return types['std_msgs/msg/Header'](stamp=stamp(types, t), frame_id='odom')


def pose(types, x, y, yaw):
    return types['geometry_msgs/msg/Pose'](
        position=types['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
        orientation=types['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=math.sin(yaw / 2),
                                                          w=math.cos(yaw / 2)))


@pytest.fixture(scope='module')
def figure_eight_bag(tmp_path_factory):
    store = jazzy_typestore()
    ensure_type(store, 'robotica_msgs/msg/SimulatorStatus')
    types = store.types
    path = tmp_path_factory.mktemp('summary') / 'bag'
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    connections = {topic: (writer.add_connection(topic, msgtype, typestore=store), msgtype)
                   for topic, msgtype in (('/path', 'nav_msgs/msg/Path'),
                                          ('/ground_truth/odom', 'nav_msgs/msg/Odometry'),
                                          ('/clock', 'rosgraph_msgs/msg/Clock'),
                                          ('/simulator/status',
                                           'robotica_msgs/msg/SimulatorStatus'))}

    def write(topic, t, msg):
        connection, msgtype = connections[topic]
        writer.write(connection, round(t * 1e9), store.serialize_cdr(msg, msgtype))

    points = figure_eight(RADIUS)
    write('/path', 0.0, types['nav_msgs/msg/Path'](header=header(types, 0.0), poses=[
        types['geometry_msgs/msg/PoseStamped'](header=header(types, 0.0),
                                               pose=pose(types, float(x), float(y), 0.0))
        for x, y in points]))
    steps = 1000   # 20 s: from 1 mm behind the crossing around most of the upper lobe
    for k in range(steps):
        t = k * DT
        x, y, yaw = offset_pose(-0.001 + SPEED * t)
        write('/ground_truth/odom', t, types['nav_msgs/msg/Odometry'](
            header=header(types, t), child_frame_id='base_link_truth',
            pose=types['geometry_msgs/msg/PoseWithCovariance'](pose=pose(types, x, y, yaw),
                                                               covariance=np.zeros(36)),
            twist=types['geometry_msgs/msg/TwistWithCovariance'](
                twist=types['geometry_msgs/msg/Twist'](
                    linear=types['geometry_msgs/msg/Vector3'](x=SPEED, y=0.0, z=0.0),
                    angular=types['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0)),
                covariance=np.zeros(36))))
        write('/clock', t, types['rosgraph_msgs/msg/Clock'](clock=stamp(types, t)))
    write('/simulator/status', (steps - 1) * DT, types['robotica_msgs/msg/SimulatorStatus'](
        header=header(types, (steps - 1) * DT), step=steps - 1, real_time_factor=12.5,
        lockstep_timeouts=2, stale_command_stops=0, finished=True, contacts=0,
        time_in_contact=0.0))
    writer.close()
    return path, steps


def test_summary_of_an_offset_figure_eight_from_behind_the_crossing(figure_eight_bag):
    bag, steps = figure_eight_bag
    summary = summarize_bag(bag)
    assert summary.rms_cross_track == pytest.approx(OFFSET, abs=5e-4)   # chords: 0.16 mm
    assert summary.final_cross_track == pytest.approx(OFFSET, abs=5e-4)
    assert summary.duration == pytest.approx((steps - 1) * DT)
    assert (summary.steps, summary.real_time_factor, summary.lockstep_timeouts) == (
        steps - 1, 12.5, 2)
    assert summary.message_count == 1 + 2 * steps + 1
    assert summary.rms_joint_error is None
    assert 'RMS cross-track 0.1000 m' in summary.line() or 'RMS cross-track 0.0999 m' in (
        summary.line())


def test_summary_and_grade_agree(figure_eight_bag):
    bag, _ = figure_eight_bag
    grade = compute_metrics(load_run(bag)).values['rms_cross_track']
    assert summarize_bag(bag).rms_cross_track == grade


def test_a_folder_that_is_not_a_bag_is_a_bag_error(tmp_path):
    with pytest.raises(BagError):
        summarize_bag(tmp_path)


def test_a_run_that_recorded_only_rosout_is_summarised(tmp_path):
    # A node refused its configuration: the bag holds only its /rosout lines. rosbags reads
    # every topic when given no connection: the summary must not decode those as /clock.
    store = jazzy_typestore()
    types = store.types
    path = tmp_path / 'bag'
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    rosout = writer.add_connection('/rosout', 'rcl_interfaces/msg/Log', typestore=store)
    writer.write(rosout, 0, store.serialize_cdr(types['rcl_interfaces/msg/Log'](
        stamp=stamp(types, 0.0), level=40, name='odometry', msg='invalid configuration',
        file='', function='', line=0), 'rcl_interfaces/msg/Log'))
    writer.close()
    summary = summarize_bag(path)
    assert (summary.duration, summary.steps, summary.message_count) == (0.0, 0, 1)
    assert summary.rms_cross_track is None and summary.rms_joint_error is None
