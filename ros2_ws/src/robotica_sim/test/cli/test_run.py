"""
Tests of ``robotica run``'s service call and of its end.

A lost reply is resent, not waited for forever; a bag that lacks per-step messages is an error,
exit 1, the bag kept.
"""
import argparse
import json
from pathlib import Path
import time

import pytest
from rclpy.task import Future
from robotica_sim.cli import run
from robotica_sim.grading.summary import RunSummary
from std_srvs.srv import Trigger


class LossyClient:
    """A Trigger client whose first ``lost`` replies never arrive."""

    srv_name = '/recorder/ready'

    def __init__(self, lost: int):
        self.lost = lost
        self.calls = 0
        self.removed = 0

    def wait_for_service(self, timeout_sec: float) -> bool:
        return True

    def call_async(self, request: Trigger.Request) -> Future:
        self.calls += 1
        future = Future()
        if self.calls > self.lost:
            future.set_result(Trigger.Response(success=True, message='ready'))
        return future

    def remove_pending_request(self, future: Future) -> None:
        self.removed += 1


class WaitingExecutor:
    """Spins by sleeping out the timeout when the future is not done."""

    def spin_once(self, timeout_sec: float) -> None:
        pass

    def spin_until_future_complete(self, future: Future, timeout_sec: float) -> None:
        if not future.done():
            time.sleep(min(timeout_sec, 0.01))


@pytest.fixture
def short_retry(monkeypatch):
    monkeypatch.setattr(run, 'CALL_RETRY', 0.01)


def test_a_lost_reply_is_requested_again(short_retry):
    client = LossyClient(lost=2)
    answer = run._call(WaitingExecutor(), client, time.monotonic() + 5.0)
    assert answer.success and answer.message == 'ready'
    assert client.calls == 3 and client.removed == 2


def test_no_reply_until_the_deadline_fails_with_the_service_name(short_retry):
    client = LossyClient(lost=10 ** 6)
    with pytest.raises(run.RunFailed, match='/recorder/ready did not answer'):
        run._call(WaitingExecutor(), client, time.monotonic() + 0.1)
    assert client.calls > 1


def summary(missing):
    return RunSummary(bag='runs/x/bag', duration=20.0, steps=20000, real_time_factor=2.0,
                      lockstep_timeouts=0, message_count=79487, final_cross_track=None,
                      rms_cross_track=None, rms_joint_error=[0.01], max_late_joint_error=[0.02],
                      missing=missing)


def args(as_json=False):
    return argparse.Namespace(json=as_json, view=False, host='localhost', port=8765)


@pytest.mark.parametrize('as_json', [False, True])
def test_a_bag_that_lacks_steps_is_an_error_and_exit_1(capsys, as_json):
    lost = {'/joint_controller/controller_state': 514}
    code = run._print_summary(args(as_json), 'ej8_4', Path('runs/x/bag'), summary(lost), {}, 0,
                              Path('view_relay.log'))
    out, err = capsys.readouterr()
    assert code == 1
    assert err.splitlines() == [
        'robotica run: error: the recording is incomplete: the bag lacks 514 messages of '
        'per-step topics (the recorder fell behind; an overloaded machine?); the bag is kept: '
        'runs/x/bag']
    if as_json:
        printed = json.loads(out)
        assert printed['missing'] == lost and printed['exit_code'] == 1
    else:
        assert out.splitlines()[0] == 'bag: runs/x/bag'
        assert out.splitlines()[1].endswith(
            '; RECORDING INCOMPLETE: /joint_controller/controller_state 19487 of 20001 steps '
            '(the recorder fell behind)')


def test_a_complete_bag_keeps_the_exit_code(capsys):
    assert run._print_summary(args(), 'ej8_4', Path('b'), summary({}), {}, 0, Path('v')) == 0
    assert run._print_summary(args(), 'ej8_4', Path('b'), summary({}), {}, 130, Path('v')) == 130
    assert capsys.readouterr().err == ''
    assert run._print_summary(args(), 'ej8_4', Path('b'), summary({'/clock': 1}), {}, 130,
                              Path('v')) == 130   # interrupted stays interrupted
