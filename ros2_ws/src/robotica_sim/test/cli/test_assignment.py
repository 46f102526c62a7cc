"""Tests of ``robotica assignment init|check``: exit codes, one-line errors, and a checked run."""
from pathlib import Path

import pytest
from robotica_sim.cli.main import run_verb


def assignment(capsys, *argv) -> tuple[int, list[str], str]:
    """Run ``robotica assignment ARGV``; return its exit code, stdout lines and stderr."""
    code = run_verb(['assignment', *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out.splitlines(), err


def edit(path: Path, old: str, new: str) -> None:
    """Replace ``old`` (which must be there) by ``new`` in the file ``path``."""
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


def test_init_writes_a_folder_that_check_passes(capsys, tmp_path):
    folder = tmp_path / 'lab3'
    code, out, err = assignment(capsys, 'init', 'estimator', folder, '--name', 'dr',
                                '--title', 'Lab 3')
    assert (code, err) == (0, '')
    assert out[0] == 'wrote ' + ', '.join(str(folder / f) for f in (
        'assignment.yaml', 'statement.md', 'dr.py', 'scenario.yaml', 'rubric.yaml'))
    code, out, err = assignment(capsys, 'check', folder)
    assert (code, err) == (0, '')
    assert out[0] == "OK    manifest: 'Lab 3', role estimator, 1 scenario(s)"
    assert out[-1] == 'PASS: 6 checks passed (--run also runs the template)'
    assert all(line.startswith('OK    ') for line in out[:-1])


def test_init_refuses_a_folder_that_is_not_empty_unless_forced(capsys, tmp_path):
    (tmp_path / 'notes.txt').write_text('mine')
    code, out, err = assignment(capsys, 'init', 'tracker', tmp_path)
    assert (code, out) == (2, [])
    assert err == (f'robotica assignment init: error: {tmp_path} is not empty (--force writes '
                   'the assignment into it, overwriting its files)\n')
    assert sorted(p.name for p in tmp_path.iterdir()) == ['notes.txt']
    code, _, err = assignment(capsys, 'init', 'tracker', tmp_path, '--force')
    assert (code, err) == (0, '')
    assert (tmp_path / 'my_tracker.py').is_file() and (tmp_path / 'notes.txt').read_text() == \
        'mine'


@pytest.mark.parametrize('argv, message', [
    (['init', 'tracker', '{tmp}/lab', '--name', '3d'], '--name must be a letter followed by '
     "letters, digits or _ (at most 63), got '3d'"),
    (['init', 'tracker', '{tmp}/file'], '{tmp}/file is a file, not a folder'),
    (['check', '{tmp}/none'], '{tmp}/none: no such folder'),
    (['check', '{tmp}', '--output-dir', '{tmp}/runs'], '--output-dir is where --run writes '
     'its runs: give --run too'),
])
def test_a_bad_argument_is_one_line_and_exit_2(capsys, tmp_path, argv, message):
    (tmp_path / 'file').write_text('')
    code, out, err = assignment(capsys, *[a.format(tmp=tmp_path) for a in argv])
    assert (code, out) == (2, [])
    assert err.startswith(f'robotica assignment {argv[0]}: error: '
                          f'{message.format(tmp=tmp_path)}')
    assert err.count('\n') == 1


def test_a_malformed_manifest_is_exit_2_and_a_failed_check_exit_1(capsys, tmp_path):
    folder = tmp_path / 'lab'
    assert assignment(capsys, 'init', 'tracker', folder)[0] == 0
    (folder / 'rubric.yaml').unlink()
    code, out, err = assignment(capsys, 'check', folder)
    assert (code, err) == (1, '')
    assert 'FAIL  files: missing rubric.yaml' in out
    assert out[-1] == 'FAIL: 1 of 4 checks failed'
    edit(folder / 'assignment.yaml', 'hand_in:', 'hand_out:')
    code, out, err = assignment(capsys, 'check', folder)
    assert (code, out) == (2, [])
    assert err.startswith(f'robotica assignment check: error: {folder / "assignment.yaml"}: '
                          'unknown key(s) hand_out; a manifest has title')
    assert err.count('\n') == 1


@pytest.mark.slow
@pytest.mark.ros
def test_check_run_runs_the_template_and_grades_its_bag(capsys, tmp_path, ros_domain):
    folder = tmp_path / 'lab'
    assert assignment(capsys, 'init', 'tracker', folder)[0] == 0
    # A short run (2 s of the 26-s path) and a completion bound it can meet.
    edit(folder / 'scenario.yaml', 'duration: 32.0', 'duration: 2.0')
    edit(folder / 'rubric.yaml', 'completion: {min: 0.95}', 'completion: {min: 0.02}')
    runs = tmp_path / 'runs'
    code, out, err = assignment(capsys, 'check', folder, '--run', '--output-dir', runs)
    assert code == 0, '\n'.join(out) + err
    assert out[-3:] == [
        f'OK    run scenario.yaml: 2 s simulated, {runs / "scenario" / "bag"}',
        'OK    grade scenario.yaml: PASS: 4/4 checks passed',
        f'PASS: the template passes rubric.yaml in every scenario; the runs: {runs}']
    assert (runs / 'scenario' / 'bag' / 'metadata.yaml').is_file()
    code, out, err = assignment(capsys, 'check', folder, '--run', '--output-dir', runs)
    assert (code, out) == (2, [])
    assert err == (f'robotica assignment check: error: {runs / "scenario"} exist(s) already: '
                   'give another --output-dir\n')
