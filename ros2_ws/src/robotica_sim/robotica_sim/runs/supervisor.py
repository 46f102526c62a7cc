"""
Start, watch and stop the node processes of a run; none is left behind.

Each node runs in its own session (Ctrl-C in the terminal reaches only the supervising
command, which then stops the nodes: :meth:`ProcessSupervisor.stop_all`) and asks the kernel
for SIGTERM if the supervisor dies (``PR_SET_PDEATHSIG``), so that no node outlives a killed
run. Output goes to one log file per node.

Faults are told apart: :meth:`ProcessSupervisor.died` names the processes that ended on their own
(a crash, a kill), :meth:`ProcessSupervisor.watch` notes those found stopped (SIGSTOP, a
debugger: state ``T`` or ``t`` in ``/proc/<pid>/stat``) and :attr:`ProcessSupervisor.stalled`
keeps them, so that a run can name the node that died or stalled. A stopped process is
continued before it is asked to stop.
"""
import ctypes
import os
from pathlib import Path
import signal
import subprocess
import time
from typing import Optional

_PR_SET_PDEATHSIG = 1


def _die_with_parent() -> None:
    ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)


class ProcessSupervisor:
    """The processes of one run, by name, with their log files under ``log_dir``."""

    def __init__(self, log_dir: Path, env: dict) -> None:
        self._log_dir = Path(log_dir)
        self._log_dir.mkdir(parents=True, exist_ok=True)
        self._env = env
        self._procs: dict[str, subprocess.Popen] = {}
        self.stalled: dict[str, int] = {}   # name -> times it was found stopped
        self._stopping: set[str] = set()

    def start(self, name: str, argv: list[str], cwd: Optional[str] = None) -> None:
        """Start process ``name`` running ``argv`` (in folder ``cwd``, default this one's)."""
        log = open(self.log_path(name), 'wb')
        try:
            self._procs[name] = subprocess.Popen(
                argv, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                env=self._env, cwd=cwd, start_new_session=True, preexec_fn=_die_with_parent)
        finally:
            log.close()

    def log_path(self, name: str) -> Path:
        """Return the log file of process ``name``."""
        return self._log_dir / f'{name}.log'

    def returncode(self, name: str) -> Optional[int]:
        """Return the exit code of ``name``, or None while it runs."""
        return self._procs[name].poll()

    def exited(self) -> dict[str, int]:
        """Return the processes that have exited, with their exit codes."""
        return {n: p.returncode for n, p in self._procs.items() if p.poll() is not None}

    def died(self) -> dict[str, int]:
        """Return the processes that exited before they were asked to stop, with their codes."""
        return {n: c for n, c in self.exited().items() if n not in self._stopping}

    def watch(self) -> list[str]:
        """Note and return the processes found stopped now (state T or t: SIGSTOP, traced)."""
        stopped = []
        for name, proc in self._procs.items():
            try:
                stat = Path(f'/proc/{proc.pid}/stat').read_text()
            except OSError:    # it has exited (and been reaped)
                continue
            if stat[stat.rindex(')') + 2:][:1] in ('T', 't'):
                stopped.append(name)
                self.stalled[name] = self.stalled.get(name, 0) + 1
        return stopped

    def stop(self, names: list[str], timeout: float = 10.0) -> dict[str, int]:
        """
        Stop ``names`` at once: SIGINT, then SIGTERM, then SIGKILL, ``timeout`` [s] apart at most.

        Return their exit codes. A stopped process (SIGSTOP) is continued first: it would not
        see SIGINT.
        """
        procs = {name: self._procs[name] for name in names}
        for name, proc in procs.items():
            if proc.poll() is None:
                self._stopping.add(name)
                proc.send_signal(signal.SIGCONT)
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
            running = [p for p in procs.values() if p.poll() is None]
            if not running:
                break
            for proc in running:
                proc.send_signal(sig)
            deadline = time.monotonic() + timeout
            for proc in running:
                try:
                    proc.wait(timeout=max(0.0, deadline - time.monotonic()))
                except subprocess.TimeoutExpired:
                    pass
        return {name: proc.wait() for name, proc in procs.items()}

    def stop_all(self, first: list[str], last: list[str], timeout: float = 10.0
                 ) -> dict[str, int]:
        """
        Stop every process; return their exit codes.

        ``first`` are stopped one after the other, then all the others at once, then ``last``
        one after the other (a recorder, which must see everything the others published).
        Stopping the others at once instead of one by one ended a run 1.5 s sooner.
        """
        codes = {}
        for name in (n for n in first if n in self._procs):
            codes.update(self.stop([name], timeout))
        codes.update(self.stop([n for n in self._procs if n not in first and n not in last],
                               timeout))
        for name in (n for n in last if n in self._procs):
            codes.update(self.stop([name], timeout))
        return codes

    def tail(self, name: str, lines: int = 15) -> str:
        """Return the last ``lines`` lines of the log of ``name``."""
        try:
            text = self.log_path(name).read_text(errors='replace')
        except OSError:
            return ''
        return '\n'.join(text.splitlines()[-lines:])


def local_environment() -> dict:
    """Return this process's environment with loopback-only discovery unless it sets another."""
    env = dict(os.environ)
    env.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    env.pop('ROS_LOCALHOST_ONLY', None)   # deprecated; when set it overrides the range
    return env


def child_environment(domain_id: int) -> dict:
    """Return the environment of the run's processes: loopback-only discovery, its domain."""
    env = local_environment()
    env['ROS_DOMAIN_ID'] = str(domain_id)
    env.setdefault('PYTHONUNBUFFERED', '1')
    env.setdefault('RCUTILS_COLORIZED_OUTPUT', '0')
    return env
