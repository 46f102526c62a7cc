"""
One job of a sweep, run on a Dask worker: a ``robotica run`` of one scenario, then its grade.

:func:`run_job` takes a ROS domain id of the sweep's pool that no other running job holds (a
``distributed.Lock`` per id, on the scheduler), runs ``robotica run FILE --output-dir DIR
--domain-id D --json --quiet`` as a subprocess, grades the bag it wrote
(:func:`robotica_sim.grading.entry.grade_bag`) and returns a small JSON-ready record. A run
that fails is a record with ``status: failed`` and the reason, never an exception into Dask,
so that it does not stop the sweep. When the worker goes away (the sweep is interrupted, the
cluster closed) the run gets SIGTERM and stops its nodes: nothing is left running.
"""
import ctypes
from dataclasses import dataclass
from pathlib import Path
import signal
import subprocess
import sys
import time
from typing import Any, Callable, Optional

from robotica_sim.grading.entry import grade_bag
from robotica_sim.grading.rubric import Rubric

__all__ = ['RunJob', 'run_job']

STOP_WAIT = 30.0       # [s] for a run to stop its nodes after SIGTERM, before SIGKILL
DOMAIN_RETRY = 0.5     # [s] between two looks for a free domain id
_PR_SET_PDEATHSIG = 1  # prctl(2)


@dataclass(frozen=True)
class RunJob:
    """What one run of a sweep needs (it travels to a Dask worker: plain data only)."""

    name: str                      # 'run-003'
    scenario_file: str             # its scenario YAML
    run_dir: str                   # the output folder of ``robotica run`` (must not exist)
    settings: dict                 # the varied keys of this run
    domain_ids: tuple[int, ...]    # the sweep's pool of ROS domain ids
    rubric: Optional[Rubric] = None
    timeout: Optional[float] = None   # [s] wall clock, before the run is stopped


def _stop_with_parent() -> None:
    """In the run's process: get SIGTERM when the worker thread that started it ends."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except (OSError, AttributeError):   # not Linux: the cluster's close must do
        pass


def _take_domain(ids: tuple[int, ...]) -> tuple[int, Callable[[], None]]:
    """
    Return a domain id no other job holds and its release, waiting until one is free.

    Outside a Dask worker (a job run in this process) the first id is taken.
    """
    try:
        from distributed import get_worker, Lock
        get_worker()
    except (ImportError, ValueError):
        return ids[0], lambda: None
    while True:
        for domain in ids:
            lock = Lock(f'robotica-ros-domain-{domain}')
            if lock.acquire(blocking=False):
                return domain, lock.release
        time.sleep(DOMAIN_RETRY)


def _command(job: RunJob, domain: int) -> list[str]:
    return [sys.executable, '-m', 'robotica_sim.cli.main', 'run', job.scenario_file,
            '--output-dir', job.run_dir, '--domain-id', str(domain), '--json', '--quiet']


def _reason(text: str) -> str:
    """Return the line of a run's stderr that says why it failed."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    said = [line for line in lines if line.startswith('robotica run')]
    return (said or lines or [''])[0]


def _run(job: RunJob, domain: int) -> tuple[int, str, str]:
    """Run ``robotica run``; return its exit code, stdout and stderr."""
    Path(job.run_dir).parent.mkdir(parents=True, exist_ok=True)
    process = subprocess.Popen(_command(job, domain), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               preexec_fn=_stop_with_parent)
    try:
        out, err = process.communicate(timeout=job.timeout)
    except BaseException as exc:   # a timeout, or the worker interrupted: stop it cleanly
        process.send_signal(signal.SIGTERM)
        try:
            out, err = process.communicate(timeout=STOP_WAIT)
        except subprocess.TimeoutExpired:
            process.kill()
            out, err = process.communicate()
        if not isinstance(exc, subprocess.TimeoutExpired):
            raise
        err += f'\nthe run took longer than {job.timeout:g} s wall clock; stopped'
        return 1, out, err
    return process.returncode, out, err


def run_job(job: RunJob) -> dict:
    """
    Run and grade one run of a sweep; return its record (never raises for a failed run).

    The record: ``run``, ``settings``, ``domain_id``, ``run_dir``, ``status`` (``ok``, or
    ``failed`` with ``error`` the reason), ``exit_code``, ``wall_time`` [s] of the run,
    ``started`` and ``ended`` (seconds since the epoch: while it held its domain), the bag's
    ``metrics``, ``checks`` and ``failed`` checks as :func:`grade_bag` gives them.
    """
    record: dict[str, Any] = {
        'run': job.name, 'settings': job.settings, 'domain_id': None, 'run_dir': job.run_dir,
        'status': 'failed', 'error': None, 'exit_code': None, 'wall_time': None,
        'started': None, 'ended': None, 'metrics': {}, 'absent': {}, 'checks': [], 'failed': []}
    domain, release = _take_domain(job.domain_ids)
    record['domain_id'] = domain
    start = time.monotonic()
    record['started'] = time.time()   # [s] since the epoch, while it held the domain
    try:
        code, _, err = _run(job, domain)
    except OSError as exc:
        record['error'] = f'cannot start robotica run: {exc.strerror or exc}'
        return record
    finally:
        record['ended'] = time.time()
        release()
    record['exit_code'] = code
    record['wall_time'] = round(time.monotonic() - start, 3)
    if code != 0:
        record['error'] = (_reason(err) or f'robotica run exited with code {code}')
        return record
    entry = grade_bag(Path(job.run_dir) / 'bag', job.rubric)
    if entry['status'] == 'error':
        record['error'] = entry['error']
        return record
    record.update(status='ok', metrics=entry['metrics'], absent=entry['absent'],
                  checks=entry['checks'], failed=entry['failed'])
    return record
