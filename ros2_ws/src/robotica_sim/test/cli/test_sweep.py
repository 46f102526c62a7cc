"""
Tests of ``robotica sweep`` (robotica_sim.cli.sweep).

Bad input is refused before anything starts (nothing written, no cluster). One end-to-end
sweep of the demo (2 s simulated a run) on a two-worker local Dask cluster: two runs that
complete and one whose scenario file is broken after the validation (its ``robotica run``
fails), which is reported without stopping the others.
"""
import csv
import json
import os

import psutil
import pytest
from robotica_sim.cli import sweep
from robotica_sim.cli.main import run_verb
import yaml


def _pool(domain: int) -> str:
    """Return two domain ids of this pytest process's share (conftest.py: MY_DOMAINS)."""
    stride = int(os.environ.get('PYTEST_XDIST_WORKER_COUNT', '1'))
    other = domain + stride if domain + stride <= 101 else domain - stride
    return f'{domain},{other}'


@pytest.mark.parametrize('argv, message', [
    (['--vary', 'tracker.lookahed_distance=1,2'], 'is not a gain of pure_pursuit'),
    (['--vary', 'tracker.lookahead_distance=1,-1'], 'lookahead_distance must be in'),
    (['--vary', 'robot.wheel_radius'], 'expected KEY=V1,V2'),
    (['--vary', 'robot.wheel_radius=0.1', '--metric', 'rms_crosstrack'], 'unknown metric'),
    (['--vary', 'robot.wheel_radius=0.1', '--rubric', 'no_such_rubric'], 'no rubric file'),
    (['--vary', 'robot.wheel_radius=0.1', '--domain-ids', '300'], 'ids must be in 0-232'),
])
def test_bad_input_is_one_line_exit_2_and_nothing_starts(tmp_path, capsys, argv, message):
    out = tmp_path / 'sweep'
    assert run_verb(['sweep', 'demo', *argv, '--output', str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count('\n') == 1
    assert not out.exists()


def test_an_existing_output_is_refused(tmp_path, capsys):
    assert run_verb(['sweep', 'demo', '--vary', 'seed=1', '--output', str(tmp_path)]) == 2
    assert 'exists already' in capsys.readouterr().err


def test_help_has_examples(capsys):
    assert run_verb(['sweep', '--help']) == 0
    text = capsys.readouterr().out
    assert 'examples:' in text and '--vary' in text and '--scheduler' in text


@pytest.mark.slow
@pytest.mark.ros
def test_a_sweep_on_two_workers_reports_a_failed_run_and_finishes_the_others(
        tmp_path, capsys, monkeypatch, ros_domain):
    write = sweep.write_scenarios

    def break_one(runs, folder):   # after the validation: only the run itself can fail
        files = write(runs, folder)
        files['run-001'].write_text('robot: {wheel_radius: oops}\n')
        return files
    monkeypatch.setattr(sweep, 'write_scenarios', break_one)
    out = tmp_path / 'sweep'
    pool = _pool(ros_domain)
    code = run_verb(['sweep', 'demo', '--vary', 'robot.wheel_radius=0.1,0.11,0.12',
                     '--duration', '2', '--workers', '2', '--domain-ids', pool,
                     '--output', str(out)])
    captured = capsys.readouterr()
    assert code == 1
    assert '[robotica sweep] 3/3 done, 1 failed' in captured.err
    assert 'run-001 failed: ' in captured.out
    with open(out / 'results.csv', newline='') as f:
        rows = list(csv.DictReader(f))
    assert [(r['run'], r['status'], r['robot.wheel_radius']) for r in rows] == [
        ('run-000', 'ok', '0.1'), ('run-001', 'failed', '0.11'), ('run-002', 'ok', '0.12')]
    assert 'robot.wheel_radius' in rows[1]['error']   # robotica run's own reason
    runs = json.loads((out / 'results.json').read_text())['runs']
    ids = {int(i) for i in pool.split(',')}
    for run in runs:
        assert run['domain_id'] in ids
    for run in (runs[0], runs[2]):
        recorded = yaml.safe_load((out / 'runs' / run['run'] / 'run.yaml').read_text())
        assert recorded['domain_id'] == run['domain_id']
        assert (out / 'runs' / run['run'] / 'bag' / 'metadata.yaml').is_file()
        assert run['metrics']['time'] == pytest.approx(2.0, abs=0.05)   # --duration 2
        assert yaml.safe_load((out / 'scenarios' / f'{run["run"]}.yaml').read_text())[
            'robot']['wheel_radius'] == run['settings']['robot.wheel_radius']
    assert len({r['run_dir'] for r in runs}) == 3
    # Two runs that held their domains at the same time never shared one.
    for a in runs:
        for b in runs:
            if a is not b and a['started'] < b['ended'] and b['started'] < a['ended']:
                assert a['domain_id'] != b['domain_id']
    assert (out / 'rms_cross_track.png').stat().st_size > 0
    # Nothing of the sweep is left running.
    left = [p.info['cmdline'] for p in psutil.process_iter(['cmdline'])
            if str(out) in ' '.join(p.info['cmdline'] or [])]
    assert left == []
