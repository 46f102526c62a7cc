"""
Tests of robotica_sim.grading.summary on a synthetic bag written with rosbags in the test.

The bag holds the 2 m figure eight as ``/path`` and a ground truth 0.1 m to its left that starts
1 mm behind the crossing (where the path's end and start meet): the line must give RMS and
final cross-track 0.100 m, the offset written into the bag (a projection onto the whole path
followed the other lobe and gave 1.234 m), and agree with ``robotica grade``'s metric.

Arm bags written message by message with some per-step messages left out: the summary names
each short topic with its count (``missing``, ``RECORDING INCOMPLETE`` in the line).
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


# -- a recording that lost messages says so -------------------------------------------------
# A 1 kHz lockstep arm run of STEPS steps, written here message by message: the simulator's
# /clock and /joint_states and the controller's answers (/joint_torques, ~/controller_state)
# once per step, step 0 included (steps + 1 each, as a real ej8_2 bag holds: 20 001 of every
# one for 20 000 steps). Each test drops or repeats messages and states the count it expects.
STEPS, ARM_DT = 200, 0.001
CONTROLLER_STATE = '/joint_controller/controller_state'


def arm_bag(path, *, pacing='lockstep', drop=None, repeats=0, timeouts=0,
            controller_started_by='robotica', law_state=True):
    """
    Write the arm run's bag to ``path``; return it.

    ``drop``: topic -> the steps whose message is left out; ``repeats``: copies of step 0 that
    a lockstep simulator publishes again before the first answer (and the controller answers);
    ``timeouts``: the status's lockstep timeouts; ``law_state``: whether the controller
    publishes ~/controller_state (a task-space law does not).
    """
    drop = drop or {}
    store = jazzy_typestore()
    for msgtype in ('robotica_msgs/msg/SimulatorStatus', 'robotica_msgs/msg/JointControllerState'):
        ensure_type(store, msgtype)
    types = store.types
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    writer.set_custom_data('robotica.run.yaml', (
        f'scenario: ej8_4\npacing: {pacing}\nduration: {STEPS * ARM_DT}\nnodes:\n'
        f'- {{name: simulator, started_by: robotica}}\n'
        f'- {{name: joint_controller, started_by: {controller_started_by}}}\n'))
    topics = {'/clock': 'rosgraph_msgs/msg/Clock', '/joint_states': 'sensor_msgs/msg/JointState',
              '/joint_torques': 'std_msgs/msg/Float64MultiArray',
              CONTROLLER_STATE: 'robotica_msgs/msg/JointControllerState',
              '/simulator/status': 'robotica_msgs/msg/SimulatorStatus'}
    connections = {topic: writer.add_connection(topic, msgtype, typestore=store)
                   for topic, msgtype in topics.items()}

    def write(topic, k, t, msg):
        if k not in drop.get(topic, ()):
            writer.write(connections[topic], round(t * 1e9),
                         store.serialize_cdr(msg, topics[topic]))

    for k in [0] * repeats + list(range(STEPS + 1)):
        t = k * ARM_DT
        write('/joint_states', k, t, types['sensor_msgs/msg/JointState'](
            header=header(types, t), name=['q1', 'q2'], position=np.zeros(2),
            velocity=np.zeros(2), effort=np.zeros(2)))
        write('/clock', k, t, types['rosgraph_msgs/msg/Clock'](clock=stamp(types, t)))
        if k >= STEPS + 1 - timeouts:   # the last steps went on without an answer
            continue
        write('/joint_torques', k, t, types['std_msgs/msg/Float64MultiArray'](
            layout=types['std_msgs/msg/MultiArrayLayout'](dim=[], data_offset=0),
            data=np.zeros(2)))
        if law_state:
            write(CONTROLLER_STATE, k, t, types['robotica_msgs/msg/JointControllerState'](
                header=header(types, t), law='pid', joint_names=['q1', 'q2'],
                reference_position=np.zeros(2), reference_velocity=np.zeros(2),
                reference_acceleration=np.zeros(2), position_error=np.full(2, 0.01),
                velocity_error=np.zeros(2), effort=np.zeros(2)))
    write('/simulator/status', STEPS, STEPS * ARM_DT, types['robotica_msgs/msg/SimulatorStatus'](
        header=header(types, STEPS * ARM_DT), step=STEPS, real_time_factor=2.0,
        lockstep_timeouts=timeouts, stale_command_stops=0, finished=True, contacts=0,
        time_in_contact=0.0))
    writer.close()
    return path


def test_a_complete_recording_lacks_nothing(tmp_path):
    summary = summarize_bag(arm_bag(tmp_path / 'bag'))
    assert summary.steps == STEPS and summary.missing == {}
    assert 'INCOMPLETE' not in summary.line()
    assert summary.as_dict()['missing'] == {}


def test_lost_controller_states_are_named_with_their_count(tmp_path):
    # The ej8_4 failure: the recorder's keep-last queue of ~/controller_state overflowed.
    lost = set(range(50, 58)) | {STEPS}
    summary = summarize_bag(arm_bag(tmp_path / 'bag', drop={CONTROLLER_STATE: lost}))
    assert summary.missing == {CONTROLLER_STATE: 9}
    assert summary.line().endswith(
        f'; RECORDING INCOMPLETE: {CONTROLLER_STATE} 192 of 201 steps (the recorder fell '
        'behind)')
    assert summary.as_dict()['missing'] == {CONTROLLER_STATE: 9}


def test_every_topic_short_of_messages_is_named(tmp_path):
    summary = summarize_bag(arm_bag(tmp_path / 'bag', drop={
        '/clock': {3}, '/joint_states': {0, 1}, '/joint_torques': {7, 8, 9}}))
    assert summary.missing == {'/clock': 1, '/joint_states': 2, '/joint_torques': 3}
    assert ('/clock 200 of 201 steps, /joint_states 199 of 201 steps, /joint_torques 198 of '
            '201 steps') in summary.line()


def test_step_0_published_again_before_the_first_answer_hides_no_lost_state(tmp_path):
    # 3 more copies of step 0 (the controller's state stamped 0 s each time): 204 messages on
    # every topic; 2 states lost leave 202 messages but 199 distinct steps.
    summary = summarize_bag(arm_bag(tmp_path / 'bag', repeats=3,
                                    drop={CONTROLLER_STATE: {10, 20}}))
    assert summary.missing == {CONTROLLER_STATE: 2}


def test_steps_that_went_on_without_an_answer_are_not_losses(tmp_path):
    summary = summarize_bag(arm_bag(tmp_path / 'bag', timeouts=4))
    assert (summary.lockstep_timeouts, summary.missing) == (4, {})
    summary = summarize_bag(arm_bag(tmp_path / 'lost', timeouts=4,
                                    drop={CONTROLLER_STATE: {5}}))
    assert summary.missing == {CONTROLLER_STATE: 1}
    assert f'{CONTROLLER_STATE} 196 of 197 answered steps' in summary.line()


def test_answers_are_counted_only_in_lockstep(tmp_path):
    # In real time a controller may skip states; the simulator's own topics still count.
    summary = summarize_bag(arm_bag(tmp_path / 'bag', pacing='realtime',
                                    drop={CONTROLLER_STATE: {5, 6}, '/joint_torques': {5}}))
    assert summary.missing == {}
    summary = summarize_bag(arm_bag(tmp_path / 'sim', pacing='realtime',
                                    drop={'/joint_states': {5}}))
    assert summary.missing == {'/joint_states': 1}


def test_a_users_controller_is_held_to_its_torques_only(tmp_path):
    # Its ~/controller_state is optional (docs/your_node.md): not one per state.
    summary = summarize_bag(arm_bag(tmp_path / 'bag', controller_started_by='user',
                                    drop={CONTROLLER_STATE: {5}, '/joint_torques': {6}}))
    assert summary.missing == {'/joint_torques': 1}


def test_a_task_space_law_publishes_no_controller_state(tmp_path):
    summary = summarize_bag(arm_bag(tmp_path / 'bag', law_state=False))
    assert summary.missing == {}


def test_the_figure_eight_bag_without_a_run_record_lacks_nothing(figure_eight_bag):
    # Its ground truth and clock: one per step (999 steps, 1000 messages); no pacing recorded.
    assert summarize_bag(figure_eight_bag[0]).missing == {}


def test_grading_an_incomplete_recording_says_so(tmp_path):
    from robotica_sim.grading.entry import format_entry, grade_bag
    entry = grade_bag(arm_bag(tmp_path / 'short', drop={CONTROLLER_STATE: {5, 6}}), None)
    assert entry['incomplete'] == (f'{CONTROLLER_STATE} 199 of 201 steps (the recorder fell '
                                   'behind)')
    assert f'warning: the recording is incomplete: {CONTROLLER_STATE} 199 of 201' in \
        format_entry(entry)
    complete = grade_bag(arm_bag(tmp_path / 'full'), None)
    assert complete['incomplete'] == '' and 'warning' not in format_entry(complete)
