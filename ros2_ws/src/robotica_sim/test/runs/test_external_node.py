"""Tests of a user's node in a scenario: the ``external`` key and the plan's checks of it."""
from pathlib import Path
import sys
import textwrap

import pytest
from robotica_sim.runs.plan import (CONTROLLER_STATE_TOPIC, optional_topics, plan_run,
                                    TRACKING_ERROR_TOPIC)
from robotica_sim.runs.scenario import load_scenario, ScenarioError

DEMO = (Path(__file__).resolve().parents[2] / 'scenarios' / 'demo.yaml').read_text()
ARM = (Path(__file__).resolve().parents[2] / 'scenarios' / 'ej8_1.yaml').read_text()


def scenario_with(tmp_path, section: str, body: str, base: str = DEMO):
    """Write ``base`` with ``section`` replaced by ``body`` (YAML under the section)."""
    lines, skipping = [], False
    for line in base.splitlines():
        if line.startswith(f'{section}:'):
            skipping = True
            continue
        if skipping and (line.startswith(' ') or not line.strip()):
            continue
        skipping = False
        lines.append(line)
    text = '\n'.join(lines) + f'\n{section}:\n' + textwrap.indent(textwrap.dedent(body), '  ')
    path = tmp_path / 'scenario.yaml'
    path.write_text(text)
    (tmp_path / 'mine.py').write_text('print("a node")\n')
    return str(path)


def by_name(nodes):
    return {node.name: node for node in nodes}


def test_an_external_tracker_replaces_the_path_tracker(tmp_path):
    nodes = by_name(plan_run(load_scenario(scenario_with(tmp_path, 'tracker', """
        external:
          command: [python3, mine.py, --fast]
          parameters: {gain: 2.0, names: [a, b], enabled: true}
          remappings: {my_cmd: cmd_vel, errors: ~/tracking_error}
    """))))
    tracker = nodes['path_tracker']
    assert tracker.role == 'tracker' and tracker.package == ''
    assert Path(tracker.command[0]).name.startswith('python3')
    assert tracker.command[1:] == ('mine.py', '--fast')
    assert tracker.cwd == str(tmp_path) and tracker.label == 'mine.py'
    assert tracker.parameters == {'gain': 2.0, 'names': ['a', 'b'], 'enabled': True}
    assert tracker.remappings == {'my_cmd': '/cmd_vel',
                                  'errors': '/path_tracker/tracking_error'}
    assert tracker.use_sim_time
    assert nodes['odometry'].command == ()   # the other roles stay robotica's


def test_optional_outputs_are_recorded_not_awaited(tmp_path):
    mobile = load_scenario(scenario_with(tmp_path, 'tracker', 'external: {command: [ls]}\n'))
    assert optional_topics(mobile) == (TRACKING_ERROR_TOPIC,)
    assert optional_topics(load_scenario(scenario_with(tmp_path, 'tracker', 'law: stanley\n')
                                         .replace('stanley', 'pure_pursuit'))) == ()
    arm = load_scenario(scenario_with(tmp_path, 'controller', 'external: {command: [ls]}\n',
                                      base=ARM))
    assert optional_topics(arm) == (CONTROLLER_STATE_TOPIC,)
    assert by_name(plan_run(arm))['joint_controller'].role == 'joint_controller'


def test_an_external_estimator(tmp_path):
    scenario = load_scenario(scenario_with(tmp_path, 'odometry', """
        external: {command: [python3, mine.py], answer_timeout: 2.0}
    """))
    assert scenario.odometry.external.answer_timeout == 2.0
    assert by_name(plan_run(scenario))['odometry'].role == 'estimator'


@pytest.mark.parametrize('section, body, message', [
    ('tracker', 'external: {command: [no_such_program_here]}',
     "tracker.external.command: 'no_such_program_here' is not an executable on PATH"),
    ('tracker', 'external: {command: [./nothere.sh]}',
     "tracker.external.command: './nothere.sh' is not an executable file"),
    ('tracker', 'external: {command: [python3, missing.py]}',
     "tracker.external.command: no script 'missing.py' in"),
    ('tracker', 'external: {command: []}',
     'tracker.external: command must be a non-empty list of non-empty strings'),
    ('tracker', 'external: {command: [ls], answer_timeout: 0.0}',
     'answer_timeout in [0.1, 600] s'),
    ('tracker', 'external: {command: [ls], remappings: {my_cmd: cmd_vel_out}}',
     "tracker.external.remappings: my_cmd -> 'cmd_vel_out': not a topic of the contract of a "
     'tracker; its topics: odom, path, ground_truth/odom, cmd_vel, ~/tracking_error'),
    ('tracker', 'external: {command: [ls], remappings: {"bad name": cmd_vel}}',
     "tracker.external.remappings: 'bad name' is not a topic name"),
    ('tracker', 'external: {command: [ls], parameters: {use_sim_time: false}}',
     'use_sim_time is set by the run'),
    ('tracker', 'external: {command: [ls], parameters: {gain: [1, a]}}',
     "tracker.external.parameters.gain: [1, 'a'] is not a parameter value"),
    ('tracker', 'external: {command: [ls], parameters: {gain: .nan}}',
     'tracker.external.parameters.gain: nan is not a parameter value'),
    ('tracker', 'law: pure_pursuit\nexternal: {command: [ls]}',
     "tracker.external replaces robotica's own node: tracker.law would be ignored"),
    ('odometry', 'fuse_gps: false\nexternal: {command: [ls]}',
     'odometry.external replaces'),
    ('tracker', 'external: {command: [ls], unknown: 1}',
     'tracker.external: unknown key(s) unknown'),
    ('path', 'shape: circle\nexternal: {command: [ls]}', 'path (circle)'),
])
def test_a_bad_external_node_is_refused_before_anything_starts(
        tmp_path, section, body, message):
    with pytest.raises(ScenarioError, match='^' + str(tmp_path / 'scenario.yaml')) as err:
        plan_run(load_scenario(scenario_with(tmp_path, section, body + '\n')))
    assert message in str(err.value)
    assert '\n' not in str(err.value)


def test_an_executable_path_from_the_scenarios_folder(tmp_path):
    path = scenario_with(tmp_path, 'tracker', 'external: {command: [./node.sh]}\n')
    (tmp_path / 'node.sh').write_text('#!/bin/sh\n')
    (tmp_path / 'node.sh').chmod(0o755)
    tracker = by_name(plan_run(load_scenario(path)))['path_tracker']
    assert tracker.command == (str(tmp_path / 'node.sh'),) and tracker.label == 'node.sh'
    assert sys.executable   # the interpreter the tests run: python3 is on PATH beside it


def test_the_folder_it_runs_in(tmp_path):
    (tmp_path / 'nodes').mkdir()
    (tmp_path / 'nodes' / 'other.py').write_text('print("a node")\n')
    path = scenario_with(tmp_path, 'tracker',
                         'external: {command: [python3, other.py], folder: nodes}\n')
    tracker = by_name(plan_run(load_scenario(path)))['path_tracker']
    assert tracker.cwd == str(tmp_path / 'nodes')
    path = scenario_with(tmp_path, 'tracker',
                         'external: {command: [python3, other.py], folder: gone}\n')
    with pytest.raises(ScenarioError, match="tracker.external.folder: no folder '.*gone'"):
        plan_run(load_scenario(path))
