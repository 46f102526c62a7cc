"""
Tests of robotica_sim.bags.info and ``robotica info`` on the bag of the ``bag`` fixture.

It holds 11 Float64 messages on /a at 10 Hz (t = 1.0 ... 2.0 s) and 3 on /b at 0.5 Hz
(t = 1.0, 3.0, 5.0 s), and a scenario in its custom_data, as the recorder stores it.
"""
import json
import subprocess
import sys

import pytest
from robotica_sim.bags.info import bag_info, BagError, format_info


def test_counts_rates_and_span(bag):
    info = bag_info(bag)
    topics = {t.name: t for t in info.topics}
    assert (topics['/a'].count, topics['/b'].count) == (11, 3)
    assert topics['/a'].rate == pytest.approx(10.0)
    assert topics['/b'].rate == pytest.approx(0.5)
    assert topics['/a'].msgtype == 'std_msgs/msg/Float64'
    assert (info.start, info.end, info.duration) == pytest.approx((1.0, 5.0, 4.0))
    assert info.message_count == 14
    assert (info.run.name, info.run.description) == ('ej9_3a', 'Ejemplo 9.3 (a)')
    assert info.run.settings == {'seed': 7, 'pacing': 'lockstep'}
    text = format_info(info)
    assert 'Scenario:     ej9_3a' in text and '/b' in text
    # An old bag (no run settings): the scenario file's settings, said to be so.
    assert 'seed 7, pacing lockstep (from the scenario file' in text


def test_not_a_bag_and_a_truncated_bag_are_clear_errors(tmp_path, bag):
    with pytest.raises(BagError, match='not a bag directory'):
        bag_info(tmp_path / 'missing')
    (tmp_path / 'empty').mkdir()
    with pytest.raises(BagError, match='no metadata.yaml'):
        bag_info(tmp_path / 'empty')
    data = next(bag.glob('*.mcap'))
    data.write_bytes(data.read_bytes()[:200])
    with pytest.raises(BagError, match=f'partial bag .*cut short.*robotica bag repair {bag}'):
        bag_info(bag)


def test_command_prints_json_and_fails_cleanly(tmp_path, bag):
    command = [sys.executable, '-m', 'robotica_sim.cli.main', 'info']
    done = subprocess.run([*command, str(bag), '--json'], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    summary = json.loads(done.stdout)
    assert summary['duration'] == pytest.approx(4.0) and len(summary['topics']) == 2
    assert summary['run']['name'] == 'ej9_3a'
    assert summary['run']['settings_from'] == 'scenario file'
    failed = subprocess.run([*command, str(tmp_path)], capture_output=True, text=True,
                            timeout=60)
    assert failed.returncode == 1
    assert 'no metadata.yaml' in failed.stderr and 'Traceback' not in failed.stderr
    # A partial bag: named as such, with the command that repairs it, exit 1.
    (bag / 'metadata.yaml').unlink()
    partial = subprocess.run([*command, str(bag)], capture_output=True, text=True, timeout=60)
    assert partial.returncode == 1 and partial.stderr.count('\n') == 1
    assert 'partial bag (no metadata.yaml' in partial.stderr
    assert f'`robotica bag repair {bag}`' in partial.stderr
