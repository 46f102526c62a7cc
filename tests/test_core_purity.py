"""
The functional core never imports rclpy (DESIGN.md, "functional core, ROS shell").

Core and shell are read from the folders: a module is shell when it lies in one of the shell
rooms (``nodes/`` hold nodes, ``cli/`` the command line, ``ros/`` the helpers every node
shares); every other module of the three Python packages is core. Each core module is imported
alone, in an interpreter that has imported nothing of robotica, ROS or matplotlib, which then
must not have loaded rclpy, any message package or matplotlib. The interpreters are forks of
one that has already imported the allowed heavy libraries (NumPy, SciPy, Pinocchio): 110
fresh interpreters took 65 s, the forks take a few seconds.
"""
import json
from pathlib import Path
import subprocess
import sys

import pytest

SRC = Path(__file__).resolve().parents[1] / 'ros2_ws' / 'src'
PACKAGES = ('robotica_kin', 'robotica_ctrl', 'robotica_sim')
SHELL_ROOMS = ('nodes', 'cli', 'ros')
FORBIDDEN = ('rclpy', 'rosidl_runtime_py', 'std_msgs', 'geometry_msgs', 'nav_msgs',
             'robotica_msgs', 'matplotlib')
PRELOADED = ('numpy', 'scipy.linalg', 'scipy.optimize', 'scipy.signal', 'scipy.spatial',
             'scipy.stats', 'pinocchio', 'yaml')
# Imports the preloaded libraries, checks that nothing forbidden came with them, then forks one
# child per module given on stdin; each child imports its module and reports what it loaded
# that is forbidden (or the import's error), one JSON line per module.
FORK_SERVER = """
import importlib, json, os, sys
forbidden, preloaded, modules = json.loads(sys.stdin.read())
def bad():
    return sorted(m for m in sys.modules if m.split('.')[0] in forbidden)
for name in preloaded:
    importlib.import_module(name)
assert not bad(), bad()
for module in modules:
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        try:
            importlib.import_module(module)
            result = {'module': module, 'bad': bad()}
        except BaseException as err:
            result = {'module': module, 'error': repr(err)}
        os.write(write, json.dumps(result).encode())
        os._exit(0)
    os.close(write)
    with os.fdopen(read) as pipe:
        print(pipe.read(), flush=True)
    os.waitpid(pid, 0)
"""


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


@pytest.fixture(scope='module')
def imports() -> dict[str, dict]:
    """Return, by core module, what importing it alone loaded that is forbidden."""
    paths = ':'.join(str(SRC / p) for p in PACKAGES)
    result = subprocess.run(
        [sys.executable, '-c', FORK_SERVER], capture_output=True, text=True, timeout=600,
        input=json.dumps([FORBIDDEN, PRELOADED, core_modules()]),
        env={'PYTHONPATH': paths, 'PATH': '/usr/bin:/bin'})
    assert result.returncode == 0, result.stderr
    reports = [json.loads(line) for line in result.stdout.splitlines()]
    return {report['module']: report for report in reports}


def test_the_preloaded_libraries_are_not_ros():
    assert not set(FORBIDDEN) & {name.split('.')[0] for name in PRELOADED}


@pytest.mark.parametrize('module', core_modules())
def test_core_module_imports_no_ros(imports, module):
    assert imports[module] == {'module': module, 'bad': []}
