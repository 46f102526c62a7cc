"""Tests of robotica_sim.grading.rubric: strict validation; checks of metrics against bounds."""
from pathlib import Path

import pytest
from robotica_sim.grading.metrics import RunMetrics
from robotica_sim.grading.rubric import (Bound, check_metrics, load_rubric, parse_rubric,
                                         resolve_rubric, RubricError)
from robotica_sim.runs import shipped as shipped_module

SHIPPED = sorted((Path(__file__).resolve().parents[2] / 'rubrics').glob('*.yaml'))


def test_a_rubric_is_parsed_with_its_bounds_and_parameters():
    rubric = parse_rubric({'rubric': 'ej9_1 pure pursuit', 'scenario': 'ej9_1',
                           'parameters': {'goal_tolerance': 0.3},
                           'checks': {'rms_cross_track': {'max': 0.2},
                                      'completion': {'min': 0.95, 'max': 1}}})
    assert rubric.title == 'ej9_1 pure pursuit' and rubric.scenario == ('ej9_1',)
    assert rubric.checks == {'rms_cross_track': Bound(None, 0.2),
                             'completion': Bound(0.95, 1.0)}
    assert rubric.params.goal_tolerance == 0.3 and rubric.params.search_window == 2.0


@pytest.mark.parametrize('data, message', [
    ([1, 2], 'a rubric is a YAML mapping'),
    ({'checks': {}}, 'checks must be a non-empty mapping'),
    ({'checks': {'rms_crosstrack': {'max': 1}}},
     "unknown metric 'rms_crosstrack' in checks; known metrics: rms_cross_track, "),
    ({'checks': {'completion': {'min': 'high'}}}, r'checks.completion.min must be a finite'),
    ({'checks': {'completion': {'min': True}}}, r'checks.completion.min must be a finite'),
    ({'checks': {'completion': {'min': 0.9, 'max': 0.5}}}, 'min 0.9 > max 0.5'),
    ({'checks': {'completion': {'minimum': 0.9}}}, 'unknown key.*minimum; use min and/or max'),
    ({'checks': {'completion': 0.9}}, 'must be a mapping with min and/or max'),
    ({'checks': {'completion': {'min': 0.9}}, 'title': 'x'}, 'unknown key.*title'),
    ({'checks': {'completion': {'min': 0.9}}, 'scenario': 7},
     'scenario must be a scenario name or a list'),
    ({'checks': {'completion': {'min': 0.9}}, 'parameters': {'tolerance': 1.0}},
     'unknown parameter.*tolerance; known: goal_tolerance'),
    ({'checks': {'completion': {'min': 0.9}}, 'parameters': {'settling_band': 2.0}},
     'settling_band must be < 1'),
])
def test_invalid_rubrics_are_refused_with_the_reason(data, message):
    with pytest.raises(RubricError, match=message):
        parse_rubric(data, 'r.yaml')


def test_files_malformed_yaml_and_missing(tmp_path):
    bad = tmp_path / 'bad.yaml'
    bad.write_text('checks:\n  completion: {min: 0.9\n')
    with pytest.raises(RubricError, match='bad.yaml: not valid YAML'):
        load_rubric(bad)
    with pytest.raises(RubricError, match='none.yaml: cannot read'):
        load_rubric(tmp_path / 'none.yaml')
    good = tmp_path / 'good.yaml'
    good.write_text('checks:\n  completion: {min: 0.9}\n')
    assert load_rubric(good).title == 'good'          # title defaults to the file's name


def test_rubrics_are_found_by_path_or_shipped_name(tmp_path, monkeypatch):
    # A fake share directory stands for the installed package.
    (tmp_path / 'rubrics').mkdir()
    for name in ('alpha', 'beta'):
        (tmp_path / 'rubrics' / f'{name}.yaml').write_text('checks: {time: {max: 1}}\n')
    monkeypatch.setattr(shipped_module, 'get_package_share_directory',
                        lambda package: str(tmp_path))
    assert resolve_rubric('alpha') == tmp_path / 'rubrics' / 'alpha.yaml'
    assert resolve_rubric('beta.yaml') == tmp_path / 'rubrics' / 'beta.yaml'
    local = tmp_path / 'alpha'   # a file of that name here is taken first
    local.write_text('checks: {time: {max: 2}}\n')
    assert resolve_rubric(str(local)) == local
    with pytest.raises(RubricError, match="no rubric file 'gamma'; shipped rubrics: alpha, beta$"):
        resolve_rubric('gamma')


@pytest.mark.parametrize('path', SHIPPED, ids=[p.stem for p in SHIPPED])
def test_shipped_rubrics_are_valid(path):
    rubric = load_rubric(path)
    assert rubric.checks and rubric.title


def metrics():
    return RunMetrics(
        values={'rms_cross_track': 0.15, 'finished': False, 'collisions': None,
                'rms_joint_error': [0.01, 0.07], 'settling_time': [0.5, None]},
        notes={'collisions': 'the scenario has no map or obstacles',
               'settling_time': 'n/a for a joint whose error ends outside the band'},
        absent={'max_position_error': 'needs topic /odom, which the bag lacks'},
        joint_names=('shoulder', 'elbow'))


def check(checks, scenario=None, run_scenario='ej9_1'):
    data = {'checks': checks}
    if scenario:
        data['scenario'] = scenario
    return check_metrics(parse_rubric(data), metrics(), run_scenario)


def test_scalar_bounds_are_inclusive():
    (ok,) = check({'rms_cross_track': {'max': 0.15}})
    (low,) = check({'rms_cross_track': {'min': 0.2}})
    assert ok.passed and ok.message == ''
    assert not low.passed and low.message == 'rms_cross_track = 0.15, want >= 0.2'


def test_a_flag_is_checked_as_0_or_1():
    (result,) = check({'finished': {'min': 1}})
    assert not result.passed and result.value is False


def test_per_joint_bounds_apply_to_every_joint():
    (result,) = check({'rms_joint_error': {'max': 0.05}})
    assert not result.passed and 'elbow = 0.07' in result.message and 'shoulder' not in (
        result.message)
    (settling,) = check({'settling_time': {'max': 1.0}})
    assert not settling.passed and 'elbow n/a' in settling.message
    assert 'outside the band' in settling.message
    (passed,) = check({'rms_joint_error': {'max': 0.1}})
    assert passed.passed


def test_absent_and_undefined_metrics_fail_with_the_reason():
    absent, undefined = check({'max_position_error': {'max': 0.5}, 'collisions': {'max': 0}})
    assert not absent.passed and absent.message == (
        'metric max_position_error needs topic /odom, which the bag lacks')
    assert not undefined.passed and undefined.message == (
        'metric collisions is n/a: the scenario has no map or obstacles')


def test_the_scenario_must_match_when_named():
    first, _ = check({'rms_cross_track': {'max': 1}}, scenario='ej9_1')
    assert first.metric == 'scenario' and first.passed
    first, _ = check({'rms_cross_track': {'max': 1}}, scenario='ej9_2')
    assert not first.passed and "for scenario 'ej9_2', the bag ran 'ej9_1'" in first.message
    first, _ = check({'rms_cross_track': {'max': 1}}, scenario='ej9_2', run_scenario=None)
    assert not first.passed and first.value == 'none'
    assert 'the bag records no scenario' in first.message
    first, _ = check({'rms_cross_track': {'max': 1}}, scenario=['ej9_2', 'ej9_1'])
    assert first.passed
    first, _ = check({'rms_cross_track': {'max': 1}}, scenario=['ej9_2', 'ej9_3a'])
    assert not first.passed and 'for scenarios ej9_2, ej9_3a' in first.message


@pytest.mark.parametrize('scenario', [3, [], [''], ['a', 2], {'name': 'a'}])
def test_a_scenario_that_is_not_a_name_or_a_list_of_names_is_refused(scenario):
    with pytest.raises(RubricError, match='scenario must be a scenario name or a list'):
        parse_rubric({'scenario': scenario, 'checks': {'completion': {'min': 0.5}}})


def test_every_shipped_rubric_is_pinned_to_shipped_scenarios():
    scenarios = {p.stem for p in (SHIPPED[0].parents[1] / 'scenarios').glob('*.yaml')}
    for path in SHIPPED:
        rubric = load_rubric(path)
        assert rubric.scenario and set(rubric.scenario) <= scenarios, path.name
