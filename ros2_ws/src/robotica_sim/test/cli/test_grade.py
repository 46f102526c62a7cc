"""
Tests of ``robotica grade`` (robotica_sim.cli.grade) on small synthetic runs.

Each run drives a straight 10 m path along x at 1 m/s for 5 s, ``offset`` metres to its left,
so its RMS cross-track error is ``offset`` and its completion 0.5: a good run (0.05 m) passes
the rubric below, a bad one (0.5 m) fails it.
"""
import argparse
import json
import math

import numpy as np
import pytest
from robotica_sim.bags.typestore import jazzy_typestore
from robotica_sim.cli import grade
from robotica_sim.cli.main import run_verb
from rosbags.rosbag2 import StoragePlugin, Writer

RUBRIC = """rubric: straight line
scenario: straight
checks:
  rms_cross_track: {max: 0.1}   # [m]
  completion: {min: 0.45}
"""


def write_run(path, offset, scenario='straight', run=None):
    """Write a run on the x axis at ``offset`` [m] to the left of a straight path."""
    store = jazzy_typestore()
    types = store.types
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    writer.set_custom_data('robotica.scenario.yaml', f'name: {scenario}\npacing: lockstep\n')
    if run is not None:
        writer.set_custom_data('robotica.run.yaml', run)

    def stamp(t):
        return types['builtin_interfaces/msg/Time'](sec=int(t), nanosec=round(t % 1 * 1e9))

    def header(t):
        return types['std_msgs/msg/Header'](stamp=stamp(t), frame_id='odom')

    def pose(x, y):
        return types['geometry_msgs/msg/Pose'](
            position=types['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
            orientation=types['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0))

    clock = writer.add_connection('/clock', 'rosgraph_msgs/msg/Clock', typestore=store)
    truth = writer.add_connection('/ground_truth/odom', 'nav_msgs/msg/Odometry',
                                  typestore=store)
    reference = writer.add_connection('/path', 'nav_msgs/msg/Path', typestore=store)
    path_msg = types['nav_msgs/msg/Path'](header=header(0.0), poses=[
        types['geometry_msgs/msg/PoseStamped'](header=header(0.0), pose=pose(x, 0.0))
        for x in (0.0, 10.0)])
    writer.write(reference, 0, store.serialize_cdr(path_msg, 'nav_msgs/msg/Path'))
    zero = types['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0)
    for k in range(51):
        t = 0.1 * k
        odom = types['nav_msgs/msg/Odometry'](
            header=header(t), child_frame_id='base_link',
            pose=types['geometry_msgs/msg/PoseWithCovariance'](pose=pose(t, offset),
                                                               covariance=np.zeros(36)),
            twist=types['geometry_msgs/msg/TwistWithCovariance'](
                twist=types['geometry_msgs/msg/Twist'](linear=zero, angular=zero),
                covariance=np.zeros(36)))
        writer.write(truth, round(t * 1e9), store.serialize_cdr(odom, 'nav_msgs/msg/Odometry'))
        writer.write(clock, round(t * 1e9), store.serialize_cdr(
            types['rosgraph_msgs/msg/Clock'](clock=stamp(t)), 'rosgraph_msgs/msg/Clock'))
    writer.close()
    return path


def test_a_bag_of_another_scenario_fails_a_pinned_rubric(tmp_path, capsys):
    rubric = tmp_path / 'pinned.yaml'
    rubric.write_text('scenario: straight\nchecks:\n  completion: {min: 0.1}\n')
    good = write_run(tmp_path / 'good', 0.05, scenario='circle')
    assert run_grade(good, '--rubric', rubric) == 1
    out = capsys.readouterr().out
    assert "scenario: the rubric is for scenario 'straight', the bag ran 'circle'" in out
    assert 'FAIL: 1/2 checks passed' in out
    # An old bag (no run settings): the scenario file's, said so.
    assert 'run: pacing lockstep (from the scenario file' in out


def test_what_ran_is_shown_not_the_scenario_file(tmp_path, capsys):
    ran = write_run(tmp_path / 'ran', 0.05, run='scenario: straight\npacing: realtime\n'
                    'duration: 3.0\noverrides: {pacing: realtime, duration: 3.0}\n')
    assert run_grade(ran, '--json', '-') == 0
    (entry,) = json.loads(capsys.readouterr().out)['bags']
    assert entry['run']['settings'] == {'pacing': 'realtime', 'duration': 3.0}
    assert entry['run']['settings_from'] == 'run'
    assert run_grade(ran) == 0
    assert 'run: pacing realtime, duration 3 s (as run, overridden: pacing realtime, ' \
        'duration 3.0)' in capsys.readouterr().out


def run_grade(*argv):
    """Run ``robotica grade`` as the command does (errors mapped to exit codes by cli.main)."""
    return run_verb(['grade', *(str(a) for a in argv)])


@pytest.fixture
def rubric(tmp_path):
    path = tmp_path / 'rubric.yaml'
    path.write_text(RUBRIC)
    return path


def test_a_good_run_passes_and_a_bad_run_fails(tmp_path, rubric, capsys):
    good = write_run(tmp_path / 'good', 0.05)
    bad = write_run(tmp_path / 'bad', 0.5)
    assert run_grade(good, '--rubric', rubric) == 0
    out = capsys.readouterr().out
    assert 'rms_cross_track' in out and 'PASS: 3/3 checks passed' in out
    assert run_grade(bad, '--rubric', rubric, '--json', tmp_path / 'bad.json') == 1
    out = capsys.readouterr().out
    assert 'FAIL: 2/3 checks passed' in out
    row = next(line for line in out.splitlines() if line.startswith('rms_cross_track'))
    assert row.split() == ['rms_cross_track', '0.5', 'm', '<=', '0.1', 'FAIL']
    (entry,) = json.loads((tmp_path / 'bad.json').read_text())['bags']
    assert entry['status'] == 'fail' and entry['failed'] == ['rms_cross_track']
    assert entry['checks'][1]['message'] == 'rms_cross_track = 0.5, want <= 0.1'
    assert entry['metrics']['rms_cross_track'] == pytest.approx(0.5)
    assert entry['metrics']['completion'] == pytest.approx(0.5)


def test_metrics_only_without_a_rubric(tmp_path, capsys):
    assert run_grade(write_run(tmp_path / 'bag', 0.2), '--json', '-') == 0
    (entry,) = json.loads(capsys.readouterr().out)['bags']
    assert entry['status'] == 'ok' and entry['scenario'] == 'straight'
    assert entry['metrics']['rms_cross_track'] == pytest.approx(0.2)
    assert entry['metrics']['path_length'] == pytest.approx(5.0)
    assert entry['units']['time'] == 's' and entry['metrics']['time'] == pytest.approx(5.0)
    assert entry['absent']['rms_position_error'] == 'needs topic /odom, which the bag lacks'


def test_a_missing_topic_fails_its_check_with_the_reason(tmp_path, capsys):
    rubric = tmp_path / 'odom.yaml'
    rubric.write_text('checks:\n  max_position_error: {max: 0.5}\n')
    assert run_grade(write_run(tmp_path / 'bag', 0.0), '--rubric', rubric) == 1
    assert 'metric max_position_error needs topic /odom, which the bag lacks' in (
        capsys.readouterr().out)


@pytest.mark.parametrize('text, message', [
    ('checks:\n  rms_cross_track: {max: 0.1\n', 'not valid YAML'),
    ('checks:\n  rms_crosstrack: {max: 0.1}\n', "unknown metric 'rms_crosstrack'"),
    ('checks:\n  completion: {min: 1, max: 0.5}\n', 'min 1 > max 0.5'),
])
def test_an_invalid_rubric_is_a_usage_error(tmp_path, capsys, text, message):
    rubric = tmp_path / 'r.yaml'
    rubric.write_text(text)
    assert run_grade(write_run(tmp_path / 'bag', 0.0), '--rubric', rubric) == 2
    err = capsys.readouterr().err
    assert message in err and err.count('\n') == 1


def test_an_unknown_rubric_name_lists_the_shipped_ones(tmp_path, capsys):
    assert run_grade(tmp_path, '--rubric', 'no_such_rubric') == 2
    assert "no rubric file 'no_such_rubric'; shipped rubrics:" in capsys.readouterr().err


def test_not_a_bag_is_one_line_and_exit_1(tmp_path, capsys):
    assert run_grade(tmp_path / 'missing') == 1
    err = capsys.readouterr().err
    assert 'not a bag directory or a folder of bags' in err and err.count('\n') == 1
    (tmp_path / 'empty').mkdir()
    assert run_grade(tmp_path / 'empty') == 1
    assert 'no bags found' in capsys.readouterr().err
    broken = write_run(tmp_path / 'broken', 0.0)
    data = next(broken.glob('*.mcap'))
    data.write_bytes(data.read_bytes()[:300])
    assert run_grade(broken) == 1
    captured = capsys.readouterr()
    assert 'partial bag' in captured.err and 'robotica bag repair' in captured.err
    assert captured.err.count('\n') == 1
    assert 'Traceback' not in captured.err + captured.out


def test_a_folder_is_graded_in_parallel(tmp_path, rubric, capsys):
    runs = tmp_path / 'runs'
    write_run(runs / 'a' / 'bag', 0.05)
    write_run(runs / 'b' / 'bag', 0.5)
    broken = write_run(runs / 'nested' / 'c' / 'bag', 0.0)
    (broken / 'metadata.yaml').unlink()           # as after a killed recorder
    out_json = tmp_path / 'grades.json'
    assert run_grade(runs, '--rubric', rubric, '--jobs', 2, '--json', out_json) == 1
    captured = capsys.readouterr()
    assert captured.err.count('graded ') == 3 and 'graded 3/3' in captured.err
    assert '3 bags: 1 pass, 1 fail, 1 error' in captured.out
    bags = json.loads(out_json.read_text())['bags']
    assert [(b['bag'].split('runs/')[1], b['status']) for b in bags] == [
        ('a/bag', 'pass'), ('b/bag', 'fail'), ('nested/c/bag', 'error')]
    assert bags[2]['error'].startswith(str(broken))   # open_bag's reason, about this bag
    assert math.isclose(bags[0]['metrics']['rms_cross_track'], 0.05)


def test_help_has_examples():
    parser = argparse.ArgumentParser(prog='robotica grade', epilog=grade.EPILOG,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    grade.add_arguments(parser)
    text = parser.format_help()
    assert 'examples:' in text and '--rubric' in text and '--jobs' in text
    with pytest.raises(SystemExit) as exit_info:
        parser.parse_args(['x', '--jobs', '0'])
    assert exit_info.value.code == 2


def test_a_folder_of_submissions_gives_a_table_csv_json_and_reports(tmp_path, capsys):
    import csv
    subs = tmp_path / 'submissions'
    write_run(subs / 'ana' / 'bag', 0.05)                 # one bag per student
    write_run(subs / 'ben' / 'try1' / 'bag', 0.5)         # one folder of runs per student
    write_run(subs / 'ben' / 'try2' / 'bag', 0.05)
    rubric = tmp_path / 'rubric.yaml'                     # /odom is in no bag: missing
    rubric.write_text(RUBRIC + '  max_position_error: {max: 0.5}\n')
    out = tmp_path / 'grades'
    assert run_grade(subs, '--rubric', rubric, '--output', out, '--workers', 2) == 1
    text = capsys.readouterr().out
    rows = {tuple(line.split()[:2]): line.split() for line in text.splitlines()
            if line.startswith(('ana', 'ben'))}
    assert set(rows) == {('ana', '-'), ('ben', 'try1'), ('ben', 'try2')}
    # columns: scenario first, then the checks by name; value and PASS/FAIL, or missing
    assert rows[('ana', '-')] == ['ana', '-', 'straight', 'PASS', '0.5', 'PASS', 'missing',
                                  '0.05', 'PASS', '3/4']
    assert rows[('ben', 'try1')][-3:] == ['0.5', 'FAIL', '2/4']
    with open(out / 'grades.csv', newline='') as f:
        table = list(csv.DictReader(f))
    assert [(r['student'], r['run'], r['status']) for r in table] == [
        ('ana', '', 'fail'), ('ben', 'try1', 'fail'), ('ben', 'try2', 'fail')]
    assert table[0]['max_position_error'] == 'missing' != '0'
    assert table[0]['max_position_error_result'] == 'missing'
    assert float(table[1]['rms_cross_track']) == pytest.approx(0.5)
    assert table[1]['rms_cross_track_result'] == 'fail' and table[1]['passed'] == '2'
    grades = json.loads((out / 'grades.json').read_text())
    assert [s['student'] for s in grades['students']] == ['ana', 'ben']
    ben = grades['students'][1]['runs']
    assert [r['run'] for r in ben] == ['try1', 'try2']
    missing = ben[1]['checks_by_metric']['max_position_error']
    assert missing['missing'] is True and missing['value'] is None and not missing['passed']
    assert 'needs topic /odom' in missing['message']
    report = (out / 'reports' / 'ben.md').read_text()
    assert '## try1: 2/4' in report and '## try2: 3/4' in report
    # The same bags give the same files, graded in one process or on the cluster.
    assert run_grade(subs, '--rubric', rubric, '--output', tmp_path / 'again', '--workers', 1,
                     '--quiet') == 1
    for name in ('grades.csv', 'grades.json', 'reports/ana.md'):
        assert (tmp_path / 'again' / name).read_text() == (out / name).read_text()
