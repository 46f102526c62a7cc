"""Tests of a scenario's ``visualisation`` switch: the viewer's nodes and topics on or off."""
from pathlib import Path

import pytest
from robotica_sim.runs.plan import plan_run, recorded_topics
from robotica_sim.runs.scenario import load_scenario, ScenarioError

SHIPPED = Path(__file__).resolve().parents[2] / 'scenarios'
VIEWER_TOPICS = {'/tf', '/tf_static', '/robot_description', '/markers'}


def scenario_file(tmp_path, shipped: str, visualisation: str) -> str:
    """Return a copy of a shipped scenario with ``visualisation: <value>`` added."""
    path = tmp_path / f'{shipped}.yaml'
    path.write_text((SHIPPED / f'{shipped}.yaml').read_text()
                    + f'visualisation: {visualisation}\n')
    return str(path)


def by_name(nodes):
    return {node.name: node for node in nodes}


def test_default_is_on_as_explicit_true(tmp_path):
    default = load_scenario(str(SHIPPED / 'demo.yaml'))
    explicit = load_scenario(scenario_file(tmp_path, 'demo', 'true'))
    assert default.visualisation is True
    assert plan_run(default) == plan_run(explicit)
    assert recorded_topics(default) == recorded_topics(explicit)


def test_demo_on(tmp_path):
    scenario = load_scenario(scenario_file(tmp_path, 'demo', 'true'))
    nodes = by_name(plan_run(scenario))
    assert {'state_publisher', 'markers'} <= set(nodes)
    assert nodes['odometry'].parameters.get('publish_tf', True) is True
    assert nodes['simulator'].parameters.get('truth_frame_id', 'base_link_truth') != ''
    assert VIEWER_TOPICS <= set(recorded_topics(scenario))


def test_demo_off(tmp_path):
    on = load_scenario(str(SHIPPED / 'demo.yaml'))
    scenario = load_scenario(scenario_file(tmp_path, 'demo', 'false'))
    nodes = plan_run(scenario)
    assert [node.name for node in nodes] == ['path_publisher', 'encoder_emulator', 'odometry',
                                             'path_tracker', 'simulator']
    named = by_name(nodes)
    assert named['odometry'].parameters['publish_tf'] is False
    assert named['simulator'].parameters['truth_frame_id'] == ''
    # Nothing else changes: the same parameters but the two switched off.
    reference = by_name(plan_run(on))
    for name, node in named.items():
        params = {k: v for k, v in node.parameters.items()
                  if k not in ('publish_tf', 'truth_frame_id')}
        assert params == reference[name].parameters
    assert recorded_topics(scenario) == (
        '/clock', '/cmd_vel', '/odom', '/ground_truth/odom', '/joint_states', '/wheel_encoders',
        '/path', '/path_tracker/tracking_error', '/simulator/status', '/rosout')


def test_arm_off(tmp_path):
    scenario = load_scenario(scenario_file(tmp_path, 'puma_computed_torque', 'false'))
    assert [node.name for node in plan_run(scenario)] == [
        'joint_trajectory_publisher', 'joint_controller', 'simulator']
    assert recorded_topics(scenario) == (
        '/clock', '/joint_states', '/joint_torques', '/joint_controller/controller_state',
        '/joint_controller/joint_trajectory', '/simulator/status', '/rosout')


def test_not_a_boolean(tmp_path):
    with pytest.raises(ScenarioError, match=r'visualisation: expected true or false'):
        load_scenario(scenario_file(tmp_path, 'demo', 'off_please'))
