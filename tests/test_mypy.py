"""
Static type check of the functional core with mypy (STYLE.md §4: mypy runs on the core in CI).

The ROS shells (``nodes``, ``cli``, ``ros``) are left out: rclpy ships no type stubs.
"""
from pathlib import Path
import subprocess
import sys

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.linter
def test_mypy_core():
    packages = [str(ROOT / 'ros2_ws/src' / p / p)
                for p in ('robotica_kin', 'robotica_ctrl', 'robotica_sim')]
    result = subprocess.run(
        [sys.executable, '-m', 'mypy', '--ignore-missing-imports', '--no-error-summary',
         '--cache-dir', str(ROOT / 'ros2_ws/log/mypy_cache'),
         '--exclude', '/nodes/', '--exclude', '/cli/', '--exclude', '/ros/', *packages],
        capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
