"""Tests of a scenario's world: and navigator: sections and the nodes the plan makes of them."""
import textwrap

import pytest
from robotica_sim.runs.plan import MAP_TOPIC, NAVIGATOR_STATE_TOPIC, plan_run, recorded_topics
from robotica_sim.runs.plan import TRACKING_ERROR_TOPIC
from robotica_sim.runs.scenario import load_scenario, ScenarioError, with_overrides

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
    """Write the base scenario with ``text`` (its robot line replaced if text has one)."""
    base = BASE.replace('robot: {type: differential}\n', '') if 'robot:' in text else BASE
    path = tmp_path / 'scenario.yaml'
    path.write_text(base + text)
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


def test_range_sensors_on_the_world_feed_the_navigator(tmp_path):
    path = scenario(tmp_path, WORLD + textwrap.dedent("""\
        robot: {type: differential, footprint_radius: 0.25}
        sensors:
          laser: {enabled: true, preset: sick_lms200_mm, mount: [0.1, 0, 0], range_max: 6}
          sonar: {enabled: true, mounts: [0, 0.2, 1.5707963267948966, 0, -0.2, -1.5]}
        navigator: {behaviour: wall_following}
    """))
    loaded = load_scenario(path)
    nodes = by_name(plan_run(loaded))
    assert nodes['laser_emulator'].parameters == {
        'world_file': path, 'preset': 'sick_lms200_mm', 'mount': [0.1, 0.0, 0.0],
        'range_max': 6.0, 'seed': 5}
    mounts = [0.0, 0.2, 1.5707963267948966, 0.0, -0.2, -1.5]
    assert nodes['sonar_emulator'].parameters['mounts'] == mounts
    navigator = nodes['reactive_navigator'].parameters
    assert navigator['laser.pose'] == [0.1, 0.0, 0.0]
    assert navigator['range.topics'] == ['sonar_0', 'sonar_1']
    assert navigator['range.poses'] == mounts
    # The laser scans at the preset's 75 Hz, finer than the 50 Hz steps: no waiting possible.
    assert 'wait_for_ranges' not in navigator and navigator['laser.period'] == 1 / 75
    # polaroid_6500: 4 groups fired in turn at 20 Hz: each transducer every 0.2 s, from its
    # group's first cycle (transducer i in group i mod 4).
    assert navigator['range.periods'] == [0.2, 0.2]
    assert navigator['range.offsets'] == [0.0, 0.05]
    simulator = nodes['simulator'].parameters
    assert simulator['world_file'] == path and simulator['footprint.radius'] == 0.25
    topics = recorded_topics(loaded)
    assert {'/scan', '/sonar_0', '/sonar_1', '/bumper', '/map',
            '/world_publisher/markers'} <= set(topics)
    assert {'/scan', '/sonar_0'} <= set(simulator['lockstep.follow_topics'])


@pytest.mark.parametrize('text, message', [
    ('sensors: {laser: {enabled: true}}\n', 'sensors.laser needs a world: section'),
    (WORLD + 'sensors: {sonar: {enabled: true, beams: 3}}\n',
     'sensors.sonar.beams is not a parameter of the sonar emulator'),
    (WORLD + 'sensors: {sonar: {enabled: true, mounts: [0, 0]}}\n',
     'sensors.sonar.mounts must hold (x, y, yaw) triples'),
    (WORLD + 'sensors: {laser: {enabled: true, range_max: -1}}\n',
     'sensors.laser.range_max must be in'),
    (WORLD + 'sensors: {laser: {enabled: true, preset: nope}}\n',
     'sensors.laser.preset must be one of'),
    ('robot: {initial_pose: [0.0, 0.5, 0.0]}\n' + WORLD, 'inside an obstacle'),
])
def test_bad_sensors_and_poses_are_refused(tmp_path, text, message):
    path = scenario(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        plan_run(load_scenario(path))
    assert message in str(err.value) and '\n' not in str(err.value)


def test_a_lockstep_navigator_waits_for_sensors_slower_than_the_steps(tmp_path):
    path = scenario(tmp_path, WORLD + textwrap.dedent("""\
        sensors:
          laser: {enabled: true, scan_rate: 10}
        navigator: {behaviour: wall_following}
    """))
    navigator = by_name(plan_run(load_scenario(path)))['reactive_navigator'].parameters
    assert navigator['wait_for_ranges'] is True and navigator['laser.period'] == 0.1
    realtime = by_name(plan_run(with_overrides(load_scenario(path), pacing='realtime')))
    assert 'wait_for_ranges' not in realtime['reactive_navigator'].parameters
