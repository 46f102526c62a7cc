"""Tests of assignment folders: init's files, the manifest's validation and the folder's checks."""
from pathlib import Path

import pytest
from robotica_sim.runs.assignment import (AssignmentError, check_assignment, init_files,
                                          load_assignment, MANIFEST, RUBRIC_FILE, SCENARIO_FILE,
                                          STATEMENT_FILE)
from robotica_sim.runs.scenario import load_scenario
from robotica_sim.runs.templates import render_template


def write_assignment(folder: Path, role: str = 'tracker', name: str = 'lab_node') -> Path:
    """Write the assignment ``init`` writes for ``role`` into ``folder``; return it."""
    folder.mkdir(parents=True, exist_ok=True)
    files = init_files(role, name, 'Lab 3: yours', render_template(role, name))
    for file_name, text in files.items():
        (folder / file_name).write_text(text)
    return folder


def edit(path: Path, old: str, new: str) -> None:
    """Replace ``old`` (which must be there) by ``new`` in the file ``path``."""
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


def failures(folder: Path) -> list[str]:
    """Return the lines of the checks of ``folder`` that failed."""
    return [c.line() for c in check_assignment(load_assignment(folder)).checks if not c.passed]


@pytest.mark.parametrize('role', ['tracker', 'estimator', 'joint_controller'])
def test_init_writes_a_folder_that_check_accepts(tmp_path, role):
    folder = write_assignment(tmp_path / 'lab', role)
    assert sorted(p.name for p in folder.iterdir()) == sorted(
        [MANIFEST, STATEMENT_FILE, 'lab_node.py', SCENARIO_FILE, RUBRIC_FILE])
    assignment = load_assignment(folder)
    assert (assignment.title, assignment.role) == ('Lab 3: yours', role)
    assert (assignment.scenarios, assignment.rubric) == ((SCENARIO_FILE,), RUBRIC_FILE)
    assert assignment.template == assignment.hand_in == 'lab_node.py'
    checked = check_assignment(assignment)
    assert [c.line() for c in checked.checks if not c.passed] == []
    assert checked.passed and checked.scenarios == (SCENARIO_FILE,)
    assert checked.rubric is not None and checked.rubric.scenario == ('lab_node',)


def test_the_scenario_runs_the_template_and_the_files_name_each_other(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    scenario = load_scenario(str(folder / SCENARIO_FILE))
    assert scenario.name == 'lab_node'
    assert scenario.tracker.external.command == ('python3', 'lab_node.py')
    texts = ''.join(p.read_text() for p in folder.iterdir())
    assert 'my_tracker' not in texts and 'lab_node_rubric.yaml' not in texts
    assert f'robotica run {SCENARIO_FILE}' in (folder / STATEMENT_FILE).read_text()
    assert f'--rubric {RUBRIC_FILE}' in (folder / SCENARIO_FILE).read_text()


def test_the_statement_lists_the_rubrics_checks_and_what_to_hand_in(tmp_path):
    statement = (write_assignment(tmp_path / 'lab') / STATEMENT_FILE).read_text()
    assert statement.startswith('# Lab 3: yours\n')
    assert '- `rms_cross_track` <= 0.1 m\n' in statement
    assert '- `completion` >= 0.95\n' in statement
    assert 'docs/your_node.md' in statement
    assert '`lab_node.py` and the run folder `runs/lab_node-<time>/`' in statement


def test_a_title_with_yaml_syntax_is_read_back_as_written(tmp_path):
    folder = tmp_path / 'lab'
    folder.mkdir()
    title = 'Lab: #3 "quotes", [brackets] & a very long title that goes past the comments'
    files = init_files('tracker', 'n', title, render_template('tracker', 'n'))
    for file_name, text in files.items():
        (folder / file_name).write_text(text)
    assert load_assignment(folder).title == title


def test_a_missing_file_fails_its_check(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    (folder / RUBRIC_FILE).unlink()
    assert failures(folder) == [f'FAIL  files: missing {RUBRIC_FILE}']


def test_a_missing_scenario_is_not_loaded_but_said_missing(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    (folder / SCENARIO_FILE).unlink()
    checked = check_assignment(load_assignment(folder))
    assert [c.line() for c in checked.checks if not c.passed] == [
        f'FAIL  files: missing {SCENARIO_FILE}']
    assert checked.scenarios == ()


def test_an_unknown_manifest_key_is_refused(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    with open(folder / MANIFEST, 'a') as manifest:
        manifest.write('deadline: tomorrow\n')
    with pytest.raises(AssignmentError, match=r'assignment\.yaml: unknown key\(s\) deadline; '
                       'a manifest has title, role, scenarios'):
        load_assignment(folder)


@pytest.mark.parametrize('line, message', [
    ('role: driver', "role must be one of tracker, estimator, joint_controller, got 'driver'"),
    ('rubric: ../rubric.yaml', 'rubric must be a path inside the assignment folder'),
    ('scenarios: []', 'scenarios must be a scenario file or a non-empty list of them'),
    ('scenarios: [scenario.yaml, scenario.yaml]', 'scenarios: scenario.yaml given twice'),
    ('title: ""', 'title must be a non-empty string'),
    ('template: 3', 'template must be a file name in the assignment folder, got 3'),
])
def test_a_bad_manifest_value_is_refused_with_the_key(tmp_path, line, message):
    folder = write_assignment(tmp_path / 'lab')
    key = line.split(':')[0]
    text = (folder / MANIFEST).read_text().splitlines()
    (folder / MANIFEST).write_text('\n'.join(line if t.startswith(f'{key}:') else t
                                             for t in text))
    with pytest.raises(AssignmentError, match=message.replace('(', r'\(').replace(')', r'\)')):
        load_assignment(folder)


def test_a_manifest_without_a_key_a_twice_given_key_or_no_manifest_is_refused(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    edit(folder / MANIFEST, 'hand_in:', '# hand_in:')
    with pytest.raises(AssignmentError, match=r'missing key\(s\) hand_in'):
        load_assignment(folder)
    edit(folder / MANIFEST, '# hand_in:', 'rubric:')
    with pytest.raises(AssignmentError, match="key 'rubric' given twice"):
        load_assignment(folder)
    (folder / MANIFEST).unlink()
    with pytest.raises(AssignmentError, match=f'no {MANIFEST}'):
        load_assignment(folder)
    with pytest.raises(AssignmentError, match='no such folder'):
        load_assignment(tmp_path / 'none')


def test_a_scenario_whose_command_runs_a_missing_script_fails(tmp_path):
    folder = write_assignment(tmp_path / 'lab')
    edit(folder / SCENARIO_FILE, '[python3, lab_node.py]', '[python3, gone.py]')
    lines = failures(folder)
    assert len(lines) == 2
    assert lines[0].startswith(f'FAIL  scenario {SCENARIO_FILE}: ')
    assert lines[0].endswith(f"tracker.external.command: no script 'gone.py' in {folder}")
    assert lines[1] == (f"FAIL  role {SCENARIO_FILE}: the tracker runs 'python3 gone.py', not "
                        'the template lab_node.py')


@pytest.mark.parametrize('scenario, message', [
    ('scenario: [ej9_1, demo]\n', f'names ej9_1, demo, not lab_node (the name of '
     f'{SCENARIO_FILE}): the bags of its runs would fail the check "scenario"'),
    ('', 'names no scenario: add scenario: lab_node (else a bag of any run passes its checks)')])
def test_a_rubric_naming_another_or_no_scenario_fails(tmp_path, scenario, message):
    folder = write_assignment(tmp_path / 'lab')
    edit(folder / RUBRIC_FILE, 'scenario: lab_node\n', scenario)
    assert failures(folder) == [f'FAIL  rubric {RUBRIC_FILE} scenario: {message}']


def test_a_scenario_of_another_role_fails(tmp_path):
    folder = write_assignment(tmp_path / 'lab', role='estimator')
    edit(folder / MANIFEST, 'role: estimator', 'role: tracker')
    assert failures(folder) == [
        f"FAIL  role {SCENARIO_FILE}: the assignment's role is tracker: the scenario must give "
        'it (and it only) to a command with tracker: {external: {command: [...]}}; its roles '
        'of users: estimator']


@pytest.mark.parametrize('kind, file_name, old, new, reason', [
    ('rubric', RUBRIC_FILE, 'completion:', 'completeness:',
     "unknown metric 'completeness' in checks"),
    ('scenario', SCENARIO_FILE, 'seed: 1', 'seed: 1\nsede: 2', 'unknown key(s) sede')])
def test_a_file_that_does_not_load_fails_with_its_reason(tmp_path, kind, file_name, old, new,
                                                         reason):
    folder = write_assignment(tmp_path / 'lab')
    edit(folder / file_name, old, new)
    [line] = failures(folder)
    assert line.startswith(f'FAIL  {kind} {file_name}: ')
    assert reason in line
