"""
Tests of the plan's pacing of a lockstep run by its recording (robotica_sim.runs.plan).

The recorder's ``progress_topics`` are the run's per-step stamped topics certain to come: for an
arm ``/clock``, ``/joint_states`` and robotica's joint controller's telemetry (the telemetry of
the law: controller_state for a joint law, force_control or cartesian_control for a task-space
law, none for a user's controller); for a vehicle ``/clock``, the ground truth, the wheel
encoders, the enabled gyro and compass and robotica's odometry; ``/clock`` alone in real time.
Each is recorded, not optional, and opens with a stamp that ``header_stamp`` reads (checked by
serializing a message of each type with a known stamp). The simulator's ``lockstep.max_lag`` is
min(0.5 s, 200 steps): 0.2 s at 1 kHz, 0.5 s at 50 Hz.
"""
from dataclasses import replace
from pathlib import Path

from nav_msgs.msg import Odometry
import pytest
from rclpy.serialization import serialize_message
from robotica_kin.ros.convert import header_stamp, seconds_to_stamp
from robotica_msgs.msg import (CartesianControlState, ForceControlState, JointControllerState,
                               WheelEncoders)
from robotica_sim.runs.plan import (lockstep_max_lag, optional_topics, plan_run, progress_topics,
                                    recorded_topics)
from robotica_sim.runs.scenario import ExternalSpec, load_scenario
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState

SHIPPED = Path(__file__).resolve().parents[2] / 'scenarios'
STATE = '/joint_controller/controller_state'
TYPES = {'/clock': Clock, '/joint_states': JointState, STATE: JointControllerState,
         '/joint_controller/force_control': ForceControlState,
         '/joint_controller/cartesian_control': CartesianControlState,
         '/ground_truth/odom': Odometry, '/odom': Odometry, '/wheel_encoders': WheelEncoders,
         '/imu/data': Imu, '/compass/heading': Imu}
"""The type of each topic a run may list, as the nodes publish it (their own declarations)."""


def scenario(name: str, **changes):
    return replace(load_scenario(str(SHIPPED / f'{name}.yaml')), **changes)


def simulator(scenario) -> dict:
    return {n.name: n for n in plan_run(scenario)}['simulator'].parameters


@pytest.mark.parametrize('name, expected', [
    ('ej8_2', ['/clock', '/joint_states', STATE]),       # computed torque, 1 kHz
    ('ej8_10', ['/clock', '/joint_states', '/joint_controller/force_control']),   # stiffness
    ('puma_operational_space', ['/clock', '/joint_states',
                                '/joint_controller/cartesian_control']),
    ('demo', ['/clock', '/ground_truth/odom', '/wheel_encoders', '/odom']),
])
def test_the_progress_topics_of_a_lockstep_run(name, expected):
    assert scenario(name).pacing == 'lockstep'
    assert list(progress_topics(scenario(name))) == expected


def test_a_users_node_is_not_waited_for():
    arm = scenario('ej8_2')
    arm = replace(arm, controller=replace(arm.controller, external=ExternalSpec(command=('ls',))))
    assert progress_topics(arm) == ('/clock', '/joint_states')
    demo = scenario('demo')
    demo = replace(demo, odometry=replace(demo.odometry, external=ExternalSpec(command=('ls',))))
    assert progress_topics(demo) == ('/clock', '/ground_truth/odom', '/wheel_encoders')


def test_enabled_gyro_and_compass_are_waited_for():
    demo = scenario('demo')
    sensors = replace(demo.sensors, gyro=replace(demo.sensors.gyro, enabled=True),
                      compass=replace(demo.sensors.compass, enabled=True))
    assert progress_topics(replace(demo, sensors=sensors)) == (
        '/clock', '/ground_truth/odom', '/wheel_encoders', '/imu/data', '/compass/heading',
        '/odom')


def test_in_real_time_the_progress_is_the_clock():
    assert progress_topics(scenario('ej8_2', pacing='realtime')) == ('/clock',)
    assert progress_topics(scenario('demo', pacing='realtime')) == ('/clock',)


@pytest.mark.parametrize('path', sorted(SHIPPED.glob('*.yaml')), ids=lambda p: p.stem)
def test_every_progress_topic_is_recorded_certain_and_stamped(path):
    for visualisation in (True, False):
        run = replace(load_scenario(str(path)), visualisation=visualisation)
        topics = progress_topics(run)
        assert set(topics) <= set(recorded_topics(run)), path.stem
        assert not set(topics) & set(optional_topics(run)), path.stem
        for topic in topics:
            msg = TYPES[topic]()
            if topic == '/clock':
                msg.clock = seconds_to_stamp(12.345)
            else:
                msg.header.stamp = seconds_to_stamp(12.345)
                msg.header.frame_id = 'frame'
            assert header_stamp(serialize_message(msg)) == 12.345, topic


def test_the_lag_bound_is_at_most_200_steps():
    assert lockstep_max_lag(0.001) == 0.2
    assert lockstep_max_lag(0.002) == 0.4
    assert lockstep_max_lag(0.0025) == 0.5
    assert lockstep_max_lag(0.02) == 0.5
    assert simulator(scenario('ej8_2'))['lockstep.max_lag'] == 0.2   # 1 kHz arm
    assert simulator(scenario('demo'))['lockstep.max_lag'] == 0.5    # 50 Hz vehicle
