"""
End-to-end: ``robotica run ej8_2`` in lockstep (trajectory publisher, joint controller and arm
simulator in their own processes, recorded); the bag checked against the book.

Ej. 8.2/8.4 (book §8.3.2): computed torque + PD with the wrong masses m̂ = [2.1, 0.9] kg on the
2R arm of Ej. 5.1; the book quotes the joint velocities at t = 10 s, q'(10) = [-0.2352, -0.0089]
rad/s, and the catalog's independent simulation gives q(10) = [0.00563, -0.21322] rad. The run
is cut at 10 s to keep the test short.
"""
import json
from pathlib import Path
import subprocess

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

pytestmark = [pytest.mark.slow, pytest.mark.ros]
SCENARIO = Path(__file__).resolve().parents[1] / 'ros2_ws/src/robotica_sim/scenarios/ej8_2.yaml'
DURATION = 10.0
STEPS = round(DURATION / 0.001)


@pytest.fixture(scope='module')
def arm_run(tmp_path_factory):
    # Without the viewer's nodes (state publisher, markers: two more processes at 1 kHz), which
    # nothing here reads.
    run_dir = tmp_path_factory.mktemp('ej8_2') / 'run'
    proc = subprocess.run(['robotica', 'run', str(SCENARIO), '--duration', str(DURATION),
                           '--visualisation', 'off', '--output-dir', str(run_dir), '--json',
                           '--quiet'],
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr
    messages = {}
    with AnyReader([run_dir / 'bag']) as reader:
        for connection, _, raw in reader.messages():
            messages.setdefault(connection.topic, []).append(
                reader.deserialize(raw, connection.msgtype))
    return messages, json.loads(proc.stdout)


def _stamp(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def test_every_state_is_answered_once(arm_run):
    messages, summary = arm_run
    states = messages['/joint_states']
    assert len({_stamp(m) for m in states}) == STEPS + 1
    assert len(messages['/joint_torques']) == len(states)
    assert len(messages['/joint_controller/controller_state']) == len(states)
    assert len(messages['/joint_controller/joint_trajectory']) == 1
    status = messages['/simulator/status'][-1]
    assert status.finished and status.step == STEPS
    assert status.lockstep_timeouts == 0 and status.stale_command_stops == 0
    assert summary['lockstep_timeouts'] == 0


def test_state_at_ten_seconds_is_the_books(arm_run):
    messages, _ = arm_run
    (last,) = [m for m in messages['/joint_states'] if abs(_stamp(m) - DURATION) < 1e-9]
    np.testing.assert_allclose(last.velocity, [-0.2352, -0.0089], atol=1e-3)
    np.testing.assert_allclose(last.position, [0.00563, -0.21322], atol=2e-4)


def test_controller_state_reports_the_reference(arm_run):
    messages, _ = arm_run
    for state in messages['/joint_controller/controller_state'][::997]:
        t = _stamp(state)
        expected = 0.15 * np.array([np.sin(np.pi * t / 2), np.cos(np.pi * t / 2)])
        np.testing.assert_allclose(state.reference_position, expected, atol=1e-6)
    late = [s for s in messages['/joint_controller/controller_state'] if _stamp(s) > 5.0]
    error = np.abs([s.position_error for s in late]).max(axis=0)
    # Catalog Part 6, Ej. 8.2: max |e| for t > 5 s ≈ [0.0067, 0.0753] rad (computed there).
    np.testing.assert_allclose(error, [0.0067, 0.0753], rtol=0.05)
