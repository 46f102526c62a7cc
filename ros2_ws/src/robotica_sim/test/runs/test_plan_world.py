"""Tests of a scenario's world: and navigator: sections and the nodes the plan makes of them."""
import textwrap

import pytest
from robotica_sim.runs.plan import MAP_TOPIC, NAVIGATOR_STATE_TOPIC, plan_run, recorded_topics
from robotica_sim.runs.plan import TRACKING_ERROR_TOPIC
from robotica_sim.runs.scenario import load_scenario, ScenarioError

BASE = """\
name: corridor
duration: 10.0
robot: {type: differential}
path: {shape: straight_line, start: [0.0, 0.0], end: [8.0, 0.0]}
"""
WORLD = """\
world:
  walls: [[-1.0, 0.5, 9.0, 0.5], [-1.0, -0.7, 9.0, -0.7]]
"""


def scenario(tmp_path, text):
    path = tmp_path / 'scenario.yaml'
    path.write_text(BASE + text)
    return str(path)


def by_name(nodes):
    return {node.name: node for node in nodes}


def test_a_navigator_replaces_the_tracker_in_a_world(tmp_path):
    path = scenario(tmp_path, WORLD + textwrap.dedent("""\
        navigator:
          behaviour: potential
          goal: [8, 0]
          wall: {desired_distance: 1}
          stall.window: 3
          pose_source: ground_truth
    """))
    loaded = load_scenario(path)
    nodes = by_name(plan_run(loaded))
    assert 'path_tracker' not in nodes
    navigator = nodes['reactive_navigator']
    assert navigator.parameters == {'behaviour': 'potential', 'goal': [8.0, 0.0],
                                    'wall.desired_distance': 1.0, 'stall.window': 3.0,
                                    'pose_source': 'ground_truth'}
    assert nodes['world_publisher'].parameters == {'world_file': path}
    topics = recorded_topics(loaded)
    assert NAVIGATOR_STATE_TOPIC in topics and MAP_TOPIC in topics
    assert TRACKING_ERROR_TOPIC not in topics


def test_without_a_world_or_a_navigator_nothing_changes(tmp_path):
    nodes = by_name(plan_run(load_scenario(scenario(tmp_path, ''))))
    assert 'path_tracker' in nodes and 'world_publisher' not in nodes
    assert 'reactive_navigator' not in nodes


@pytest.mark.parametrize('text, message', [
    ('world:\n  boxes: [{center: [0, 0], size: [1, -1]}]\n',
     'world.boxes[0].size: width and height must be > 0 m'),
    ('world:\n  doors: []\n', 'world.doors: unknown key'),
    ('world:\n  map: nothere.yaml\n', 'nothere.yaml'),
    ('navigator: {behaviour: fly}\n', 'navigator.behaviour must be one of'),
    ('navigator: {behaviour: vff, wall: {k_distance: -1}}\n',
     'navigator.wall.k_distance must be in'),
    ('navigator: {behaviour: vff, wheels: 3}\n',
     'navigator.wheels is not a parameter of the reactive navigator'),
    ('navigator: {behaviour: vff}\ntracker: {law: pure_pursuit}\n',
     'the reactive navigator replaces the path tracker'),
    ('navigator: {behaviour: vff, goal: [1, .nan]}\n', 'navigator.goal must be'),
])
def test_bad_sections_are_one_line_before_anything_starts(tmp_path, text, message):
    with pytest.raises(ScenarioError) as err:
        plan_run(load_scenario(scenario(tmp_path, text)))
    assert message in str(err.value) and '\n' not in str(err.value)
