"""Tests of ``robotica run``'s service call: a lost reply is resent, not waited for forever."""
import time

import pytest
from rclpy.task import Future
from robotica_sim.cli import run
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
