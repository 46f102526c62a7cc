"""Tests of the process supervisor: the stop order, escalation and stopped processes."""
import signal
import sys
import time

from robotica_sim.runs.supervisor import ProcessSupervisor

# A child that notes the signal that ended it, with the time, in its log (SIGINT ignored when
# asked, as a wedged node would), then exits with code 0.
CHILD = """
import signal, sys, time
def end(signum, frame):
    print(signal.Signals(signum).name, time.monotonic(), flush=True)
    sys.exit(0)
signal.signal(signal.SIGTERM, end)
signal.signal(signal.SIGINT, signal.SIG_IGN if sys.argv[1] == 'deaf' else end)
print('up', flush=True)
while True:
    time.sleep(0.01)
"""


def _start(supervisor: ProcessSupervisor, names: dict[str, str]) -> None:
    for name, mode in names.items():
        supervisor.start(name, [sys.executable, '-c', CHILD, mode])
    deadline = time.monotonic() + 60.0
    while not all(supervisor.log_path(n).read_text().startswith('up') for n in names):
        assert time.monotonic() < deadline, 'the children did not start'
        time.sleep(0.05)


def _ended(supervisor: ProcessSupervisor, name: str) -> tuple[str, float]:
    signame, when = supervisor.log_path(name).read_text().splitlines()[-1].split()
    return signame, float(when)


def test_first_then_the_others_at_once_then_last(tmp_path):
    supervisor = ProcessSupervisor(tmp_path, {})
    _start(supervisor, {'simulator': 'ok', 'tracker': 'ok', 'odometry': 'ok', 'recorder': 'ok'})
    codes = supervisor.stop_all(['simulator'], ['recorder'])
    assert codes == {'simulator': 0, 'tracker': 0, 'odometry': 0, 'recorder': 0}
    ended = {name: _ended(supervisor, name) for name in codes}
    assert all(signame == 'SIGINT' for signame, _ in ended.values())
    assert ended['simulator'][1] < min(ended['tracker'][1], ended['odometry'][1])
    assert max(ended['tracker'][1], ended['odometry'][1]) < ended['recorder'][1]
    assert supervisor.died() == {}   # asked to stop: not a fault


def test_a_process_deaf_to_sigint_gets_sigterm_and_does_not_hold_up_the_others(tmp_path):
    supervisor = ProcessSupervisor(tmp_path, {})
    _start(supervisor, {'deaf': 'deaf', 'other': 'ok'})
    codes = supervisor.stop_all([], [], timeout=1.0)
    assert codes == {'deaf': 0, 'other': 0}
    assert _ended(supervisor, 'deaf')[0] == 'SIGTERM'
    assert _ended(supervisor, 'other')[0] == 'SIGINT'
    assert _ended(supervisor, 'other')[1] < _ended(supervisor, 'deaf')[1]


def test_a_stopped_process_is_continued_then_stopped(tmp_path):
    supervisor = ProcessSupervisor(tmp_path, {})
    _start(supervisor, {'stalled': 'ok'})
    supervisor._procs['stalled'].send_signal(signal.SIGSTOP)
    deadline = time.monotonic() + 10.0
    while 'stalled' not in supervisor.watch():
        assert time.monotonic() < deadline, 'SIGSTOP not seen'
        time.sleep(0.01)
    assert supervisor.stalled == {'stalled': 1}
    assert supervisor.stop_all([], []) == {'stalled': 0}
    assert _ended(supervisor, 'stalled')[0] == 'SIGINT'
