"""
Round trip of ``robotica play``: a bag written here is replayed, recorded again, and compared.

Reference: the bag of test_bag_info (11 Float64 on /a at 10 Hz from t = 1 s, 3 on /b at
0.5 Hz), written with rosbags. The recorder node runs on the replayed /clock (use_sim_time),
so the messages come back with their data, order and (to one clock tick) their times.
"""
import signal
import subprocess
import sys

import pytest
from rosbags.highlevel import AnyReader

pytestmark = pytest.mark.ros


def read(path):
    with AnyReader([path]) as reader:
        return [(c.topic, t, bytes(raw)) for c, t, raw in reader.messages()]


def test_record_play_record_gives_the_same_messages(bag, start_node, tmp_path):
    out = tmp_path / 'again'
    recorder = start_node('robotica_sim', 'recorder', '-p', f'output:={out}',
                          '-p', "topics:=['/a', '/b', '/replayed']", '-p', 'use_sim_time:=true')
    done = subprocess.run([sys.executable, '-m', 'robotica_sim.cli.main', 'play', str(bag),
                           '--rate', '2', '--wait', '3', '--remap', '/b:=/replayed'],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert 'done, 14 messages of 2 topics' in done.stderr
    recorder.send_signal(signal.SIGINT)
    assert recorder.wait(timeout=20) == 0
    original, again = read(bag), read(out)
    renamed = [('/replayed' if topic == '/b' else topic, data) for topic, _, data in original]
    assert [(topic, data) for topic, _, data in again] == renamed
    for (_, t0, _), (_, t1, _) in zip(original, again):
        assert abs(t1 - t0) <= 100_000_000   # [ns] within one tick of the 10 Hz topic


def test_play_refuses_bad_arguments(bag, tmp_path):
    command = [sys.executable, '-m', 'robotica_sim.cli.main', 'play']
    for arguments, code, text in (([str(bag), '--rate', '0'], 2, '--rate: must be >= 0.001'),
                                  ([str(bag), '--remap', 'a=b'], 2, 'must read /from:=/to'),
                                  ([str(bag), '--topics', '/c'], 2, 'no topic /c'),
                                  ([str(tmp_path)], 1, 'not a bag directory')):
        done = subprocess.run(command + arguments, capture_output=True, text=True, timeout=60)
        assert done.returncode == code, (arguments, done.stderr)
        assert text in done.stderr and 'Traceback' not in done.stderr
