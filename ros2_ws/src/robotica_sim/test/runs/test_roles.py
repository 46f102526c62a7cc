"""Tests of robotica_sim.runs.roles: the contract of each role a user's node can take."""
import pytest
from robotica_sim.runs.roles import (COMMAND, LATCHED, role_contract, ROLE_SECTIONS, ROLES,
                                     STREAM, topic_name)


@pytest.mark.parametrize('name', sorted(ROLES))
def test_each_role_answers_with_a_required_output(name):
    role = ROLES[name]
    required = [t.name for t in role.outputs if t.required]
    assert role.answer == required[0]
    assert role.answers in [t.name for t in role.inputs if t.required]
    assert all(t.qos in (STREAM, LATCHED, COMMAND) for t in role.topics)
    assert ROLE_SECTIONS[role.section] is role


def test_a_steered_tracker_answers_on_vehicle_command():
    steered = role_contract('tracker', steered=True)
    assert steered.answer == 'vehicle_command'
    assert [t.name for t in steered.outputs] == ['vehicle_command', '~/tracking_error']
    assert role_contract('tracker').answer == 'cmd_vel'
    assert role_contract('estimator', steered=True) is ROLES['estimator']


def test_an_unknown_role_lists_the_roles():
    with pytest.raises(ValueError, match='no role .planner.; the roles: tracker, estimator, '
                                         'joint_controller'):
        role_contract('planner')


def test_contract_text_names_topics_types_and_timing():
    text = ROLES['tracker'].text()
    assert text.startswith('in: odom (nav_msgs/msg/Odometry, stream), path (nav_msgs/msg/Path,'
                           ' latched)')
    assert text.endswith('answers each odom message with exactly one cmd_vel')


@pytest.mark.parametrize('name, node, absolute', [
    ('cmd_vel', 'path_tracker', '/cmd_vel'), ('/clock', 'x', '/clock'),
    ('~/joint_trajectory', 'joint_controller', '/joint_controller/joint_trajectory')])
def test_topic_name(name, node, absolute):
    assert topic_name(name, node) == absolute
