"""
Start, watch and stop the node processes of a run; none is left behind.

Each node runs in its own session (Ctrl-C in the terminal reaches only the supervising
command, which then stops the nodes in order) and asks the kernel for SIGTERM if the supervisor
dies (``PR_SET_PDEATHSIG``), so that no node outlives a killed run. Output goes to one log file
per node.
"""
import ctypes
import os
from pathlib import Path
import signal
import subprocess
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

    def start(self, name: str, argv: list[str]) -> None:
        """Start process ``name`` running ``argv``."""
        log = open(self.log_path(name), 'wb')
        try:
            self._procs[name] = subprocess.Popen(
                argv, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                env=self._env, start_new_session=True, preexec_fn=_die_with_parent)
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

    def stop(self, name: str, timeout: float = 10.0) -> int:
        """Stop ``name``: SIGINT, then SIGTERM, then SIGKILL, ``timeout`` [s] apart at most."""
        proc = self._procs[name]
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
            if proc.poll() is not None:
                break
            proc.send_signal(sig)
            try:
                proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                continue
        return proc.wait()

    def stop_all(self, order: list[str], timeout: float = 10.0) -> dict[str, int]:
        """Stop the named processes one after the other, then any others; return exit codes."""
        names = [n for n in order if n in self._procs]
        names += [n for n in self._procs if n not in names]
        return {name: self.stop(name, timeout) for name in names}

    def tail(self, name: str, lines: int = 15) -> str:
        """Return the last ``lines`` lines of the log of ``name``."""
        try:
            text = self.log_path(name).read_text(errors='replace')
        except OSError:
            return ''
        return '\n'.join(text.splitlines()[-lines:])


def child_environment(domain_id: int) -> dict:
    """Return the environment of the run's processes: loopback-only discovery, its domain."""
    env = dict(os.environ)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = env.get('ROS_AUTOMATIC_DISCOVERY_RANGE',
                                                   'LOCALHOST')
    env.pop('ROS_LOCALHOST_ONLY', None)
    env['ROS_DOMAIN_ID'] = str(domain_id)
    env.setdefault('PYTHONUNBUFFERED', '1')
    env.setdefault('RCUTILS_COLORIZED_OUTPUT', '0')
    return env
