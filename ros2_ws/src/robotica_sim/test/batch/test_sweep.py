"""
Tests of robotica_sim.batch.sweep: --vary and --seeds into runs, each validated before any run.

Reference values are the demo scenario's own file (shipped scenarios/demo.yaml: seed 1,
lookahead_distance 0.5 m) and the product of the values given.
"""
import pytest
from robotica_sim.batch.sweep import (apply_setting, parse_domain_ids, parse_vary, sweep_runs,
                                      Variation, write_scenarios)
from robotica_sim.runs.scenario import load_scenario, ScenarioError
from robotica_sim.runs.templates import render_template


def test_vary_values_are_yaml():
    assert parse_vary('tracker.lookahead_distance=0.5,1,2,4') == Variation(
        'tracker.lookahead_distance', (0.5, 1, 2, 4))
    assert parse_vary('robot.initial_pose=[0,0,0],[1,0,0]').values == ([0, 0, 0], [1, 0, 0])
    assert parse_vary('sensors.gyro.enabled=true,false').values == (True, False)


@pytest.mark.parametrize('text, message', [
    ('tracker.lookahead_distance', 'expected KEY=V1,V2'),
    ('=1,2', 'expected KEY=V1,V2'),
    ('Tracker.L=1', 'expected KEY=V1,V2'),
    ('tracker.lookahead_distance=', 'give one or more values'),
    ('tracker.lookahead_distance=1,,2', 'not YAML'),
    ('tracker.lookahead_distance=0.5,0.5', 'repeated'),
    ('name=a,b', 'name cannot be varied'),
])
def test_bad_vary_syntax_is_a_scenario_error(text, message):
    with pytest.raises(ScenarioError, match=message):
        parse_vary(text)


def test_the_runs_are_the_product_times_the_seeds():
    runs = sweep_runs('demo', [parse_vary('tracker.lookahead_distance=0.5,1,2'),
                               parse_vary('tracker.desired_linear_velocity=0.25,0.5')], seeds=2,
                      fixed={'duration': 2.0})
    assert len(runs) == 3 * 2 * 2
    assert len({r.name for r in runs}) == 12
    assert runs[0].settings == {'tracker.lookahead_distance': 0.5,
                                'tracker.desired_linear_velocity': 0.25, 'seed': 0}
    last = runs[-1]
    assert last.settings == {'tracker.lookahead_distance': 2,
                             'tracker.desired_linear_velocity': 0.5, 'seed': 1}
    assert last.scenario.tracker.gains['lookahead_distance'] == 2.0
    assert last.scenario.seed == 1 and last.scenario.duration == 2.0
    assert last.scenario.name == 'demo'   # a rubric pinned to the scenario still applies


def test_without_seeds_the_scenario_seed_is_kept(tmp_path):
    (run,) = sweep_runs('demo', [parse_vary('robot.wheel_radius=0.12')])
    assert run.settings == {'robot.wheel_radius': 0.12}
    files = write_scenarios([run], tmp_path / 'scenarios')
    loaded = load_scenario(str(files[run.name]))
    assert loaded.seed == 1 and loaded.robot.wheel_radius == 0.12   # demo.yaml: seed 1
    assert loaded.tracker.gains['lookahead_distance'] == 0.5


@pytest.mark.parametrize('vary, message', [
    ('tracker.lookahed_distance=1,2', 'tracker.lookahed_distance is not a gain of pure_pursuit'),
    ('robot.wheel_size=0.1', 'robot: unknown key(s) wheel_size'),
    ('tracker.lookahead_distance=1,-1', 'tracker.lookahead_distance=-1, seed=0: '
     'tracker.lookahead_distance must be in [0.01, 100], got -1.0'),
    ('robot.wheel_radius=0.1,abc', "robot.wheel_radius: expected a number, got 'abc'"),
    ('duration=0', 'duration must be at least one step_period'),
    ('robot.wheel_radius.x=1', 'robot.wheel_radius is a value, not a section'),
])
def test_every_combination_is_checked_before_any_run(vary, message):
    with pytest.raises(ScenarioError) as error:
        sweep_runs('demo', [parse_vary(vary)], seeds=2)
    assert message in str(error.value)
    assert '\n' not in str(error.value)
    assert str(error.value).startswith('demo.yaml with ')


def test_conflicting_options_are_refused():
    with pytest.raises(ScenarioError, match='varied twice'):
        sweep_runs('demo', [parse_vary('seed=1,2'), parse_vary('seed=3')])
    with pytest.raises(ScenarioError, match='--vary seed and --seeds'):
        sweep_runs('demo', [parse_vary('seed=1,2')], seeds=2)
    with pytest.raises(ScenarioError, match='no_such_scenario'):
        sweep_runs('no_such_scenario', [])


def test_apply_setting_does_not_change_its_input():
    data = {'tracker': {'law': 'pure_pursuit'}}
    assert apply_setting(data, 'robot.wheel_radius', 0.2) == {
        'tracker': {'law': 'pure_pursuit'}, 'robot': {'wheel_radius': 0.2}}
    assert data == {'tracker': {'law': 'pure_pursuit'}}


@pytest.mark.parametrize('text, ids', [('40-43', (40, 41, 42, 43)), ('7', (7,)),
                                       ('1-2,9', (1, 2, 9))])
def test_domain_id_pools(text, ids):
    assert parse_domain_ids(text) == ids


@pytest.mark.parametrize('text', ['', '5-3', '1-300', 'a-b', '1,1', '-1'])
def test_bad_domain_id_pools(text):
    with pytest.raises(ValueError):
        parse_domain_ids(text)


def test_a_users_node_keeps_running_in_its_scenarios_folder(tmp_path):
    lab = tmp_path / 'lab'
    lab.mkdir()
    for file_name, text in render_template('tracker', 'mine').items():
        (lab / file_name).write_text(text)
    runs = sweep_runs(str(lab / 'mine.yaml'),
                      [parse_vary('tracker.external.parameters.heading_gain=0.5,2')])
    files = write_scenarios(runs, tmp_path / 'sweep' / 'scenarios')   # another folder
    for run, gain in zip(runs, (0.5, 2.0)):
        external = load_scenario(str(files[run.name])).tracker.external
        assert external.folder == str(lab)
        assert external.parameters['heading_gain'] == gain
