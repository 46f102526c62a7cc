"""
A scenario's tracker may be ``reversing_pure_pursuit``: planned with its gains, node-checked.

On a bicycle (a steered robot) the tracker commands steering. The law takes pure pursuit's
gains under its own prefix (``reversing_pure_pursuit.<gain>``), and a gain out of its range is
refused by the plan naming the scenario key, before any process starts (as
``test_plan_node_checks`` does for the other laws).
"""
import pytest
from robotica_sim.runs.plan import plan_run
from robotica_sim.runs.scenario import load_scenario, resolve_scenario_path, ScenarioError
import yaml


def _demo_with_tracker(tmp_path, tracker):
    """Return the shipped demo scenario on a bicycle with ``tracker`` as its tracker, loaded."""
    data = yaml.safe_load(resolve_scenario_path('demo').read_text())
    data['tracker'] = tracker
    data['robot']['type'] = 'bicycle'
    path = tmp_path / 'reversing.yaml'
    path.write_text(yaml.safe_dump(data))
    return load_scenario(str(path))


def test_the_reversing_law_is_planned_with_its_gains(tmp_path):
    scenario = _demo_with_tracker(tmp_path, {'law': 'reversing_pure_pursuit',
                                             'lookahead_distance': 0.8})
    [tracker] = [node for node in plan_run(scenario) if node.executable == 'path_tracker']
    assert tracker.parameters['law'] == 'reversing_pure_pursuit'
    assert tracker.parameters['reversing_pure_pursuit.lookahead_distance'] == 0.8
    assert tracker.parameters['command_type'] == 'steering'
    assert tracker.parameters['wheelbase'] == scenario.robot.wheelbase


def test_a_bad_gain_of_the_reversing_law_is_refused_by_the_plan(tmp_path):
    scenario = _demo_with_tracker(tmp_path, {'law': 'reversing_pure_pursuit',
                                             'lookahead_distance': 0.0})
    with pytest.raises(ScenarioError, match=r'lookahead_distance must be in \[0.01, 100\]'):
        plan_run(scenario)
