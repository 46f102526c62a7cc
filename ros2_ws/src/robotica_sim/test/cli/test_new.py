"""Tests of ``robotica new``: a user's node, its scenario and its rubric from a template."""
import os

from robotica_sim.cli.main import run_verb
from robotica_sim.runs.plan import plan_run
from robotica_sim.runs.scenario import load_scenario
import yaml


def test_writes_a_node_its_scenario_and_its_rubric(tmp_path, capsys):
    assert run_verb(['new', 'tracker', 'steer', '--output-dir', str(tmp_path / 'lab')]) == 0
    folder = tmp_path / 'lab'
    assert sorted(p.name for p in folder.iterdir()) == ['steer.py', 'steer.yaml',
                                                        'steer_rubric.yaml']
    assert os.access(folder / 'steer.py', os.X_OK)
    assert "super().__init__('steer')" in (folder / 'steer.py').read_text()
    scenario = load_scenario(str(folder / 'steer.yaml'))
    assert scenario.name == 'steer'
    assert scenario.tracker.external.command == ('python3', 'steer.py')
    tracker = [n for n in plan_run(scenario) if n.role == 'tracker']
    assert tracker[0].cwd == str(folder)
    rubric = yaml.safe_load((folder / 'steer_rubric.yaml').read_text())
    assert rubric['scenario'] == 'steer'
    out = capsys.readouterr().out
    assert f'robotica run {folder / "steer.yaml"}' in out


def test_every_role_has_a_template(tmp_path):
    for role, section in (('estimator', 'odometry'), ('joint_controller', 'controller')):
        assert run_verb(['new', role, f'my_{role}', '--output-dir', str(tmp_path)]) == 0
        scenario = load_scenario(str(tmp_path / f'my_{role}.yaml'))
        assert getattr(scenario, section).external.command == ('python3', f'my_{role}.py')


def test_existing_files_are_kept_unless_forced(tmp_path, capsys):
    (tmp_path / 'mine.py').write_text('my own work\n')
    assert run_verb(['new', 'tracker', 'mine', '--output-dir', str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and 'mine.py exist(s) already (--force overwrites)' in err
    assert (tmp_path / 'mine.py').read_text() == 'my own work\n'
    assert not (tmp_path / 'mine.yaml').exists()
    assert run_verb(['new', 'tracker', 'mine', '--output-dir', str(tmp_path), '--force']) == 0
    assert 'rclpy' in (tmp_path / 'mine.py').read_text()


def test_bad_name_and_unknown_role(tmp_path, capsys):
    assert run_verb(['new', 'tracker', '1st-try', '--output-dir', str(tmp_path)]) == 2
    assert 'NAME must be a letter followed by letters, digits or _' in capsys.readouterr().err
    assert run_verb(['new', 'planner', 'x', '--output-dir', str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "invalid choice: 'planner'" in err and err.count('\n') == 1
    assert list(tmp_path.iterdir()) == []
