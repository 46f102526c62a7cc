"""
The functional core never imports rclpy (DESIGN.md, "functional core, ROS shell").

Core and shell are read from the folders: a module is shell when it lies in one of the shell
rooms (``nodes/`` hold nodes, ``cli/`` the command line, ``ros/`` the helpers every node
shares); every other module of the three Python packages is core. Each core module is imported
in a fresh interpreter, which then must not have loaded rclpy, any message package or
matplotlib.
"""
from pathlib import Path
import subprocess
import sys

import pytest

SRC = Path(__file__).resolve().parents[1] / 'ros2_ws' / 'src'
PACKAGES = ('robotica_kin', 'robotica_ctrl', 'robotica_sim')
SHELL_ROOMS = ('nodes', 'cli', 'ros')


def core_modules() -> list[str]:
    modules = []
    for package in PACKAGES:
        root = SRC / package
        for path in sorted((root / package).rglob('*.py')):
            parts = path.relative_to(root).with_suffix('').parts
            if any(p in SHELL_ROOMS for p in parts[1:-1]):
                continue
            modules.append('.'.join(p for p in parts if p != '__init__'))
    return modules


@pytest.mark.parametrize('module', core_modules())
def test_core_module_imports_no_ros(module):
    code = (f'import sys, {module}\n'
            "bad = [m for m in sys.modules if m.split('.')[0] in "
            "{'rclpy', 'rosidl_runtime_py', 'std_msgs', 'geometry_msgs', 'nav_msgs', "
            "'robotica_msgs', 'matplotlib'}]\n"
            'assert not bad, bad\n')
    paths = ':'.join(str(SRC / p) for p in PACKAGES)
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            env={'PYTHONPATH': paths, 'PATH': '/usr/bin:/bin'})
    assert result.returncode == 0, result.stderr
