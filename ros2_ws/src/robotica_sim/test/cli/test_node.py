"""Tests of ``robotica node``: a node started by name as ``ros2 run`` does, and its completion."""
import os
from pathlib import Path
import signal
import subprocess
import sys

from nav_msgs.msg import Path as PathMessage
import pytest
from robotica_kin.ros.qos import LATCHED_QOS
from robotica_sim.cli.main import run_verb

ROBOTICA = [sys.executable, '-m', 'robotica_sim.cli.main']
ROOT = Path(__file__).resolve().parents[5]


def robotica(capsys, *args: str) -> tuple[int, str, str]:
    """Run ``robotica ARGS`` in this process; return its exit code, stdout and stderr."""
    code = run_verb(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_an_unknown_package_is_one_line_naming_those_that_exist(capsys):
    code, out, err = robotica(capsys, 'node', 'no_such_package', 'simulator')
    assert code == 2 and out == ''
    assert err.startswith("robotica node: error: no package 'no_such_package' with "
                          'executables; there are: ')
    assert err.count('\n') == 1
    assert {'robotica_ctrl', 'robotica_kin', 'robotica_sim'} <= set(
        err.split('there are: ')[1].strip().split(', '))


def test_a_package_without_an_executable_is_a_usage_error(capsys):
    code, out, err = robotica(capsys, 'node', 'robotica_sim')
    assert (code, out) == (2, '')
    assert err == 'robotica node: error: PACKAGE and EXECUTABLE are required (robotica node ' \
        '--list lists them)\n'


def test_an_unknown_executable_is_one_line_naming_those_of_the_package(capsys):
    code, out, err = robotica(capsys, 'node', 'robotica_ctrl', 'simulator', '--ros-args', '-p',
                              'x:=1')
    assert code == 2 and out == ''
    assert err == ("robotica node: error: no executable 'simulator' in robotica_ctrl; there "
                   'are: joint_controller, joint_trajectory_publisher, mapper, path_publisher, '
                   'path_tracker, planner, reactive_navigator\n')


def test_list_and_completion_offer_the_same_names(capsys):
    packages = robotica(capsys, 'node', '--list')[1].split()
    assert {'robotica_ctrl', 'robotica_kin', 'robotica_sim'} <= set(packages)
    assert 'simulator' in robotica(capsys, 'node', '--list', 'robotica_sim')[1].split()
    script = (f'. {ROOT}/scripts/completion.bash; COMP_WORDS=(robotica node robotica_c); '
              'COMP_CWORD=2; _robotica_complete; echo "${COMPREPLY[@]}"; '
              'COMP_WORDS=(robotica node robotica_ctrl path_); COMP_CWORD=3; '
              '_robotica_complete; echo "${COMPREPLY[@]}"')
    lines = subprocess.run(['bash', '-c', script], capture_output=True, text=True,
                           timeout=60, check=True).stdout.splitlines()
    assert lines == ['robotica_ctrl', 'path_publisher path_tracker']


@pytest.mark.ros
@pytest.mark.parametrize('stop', [signal.SIGINT, signal.SIGTERM], ids=['SIGINT', 'SIGTERM'])
def test_the_node_replaces_the_command_with_its_arguments_and_local_discovery(
        ros_node, spin, stop):
    node, executor = ros_node
    env = dict(os.environ)
    env.pop('ROS_AUTOMATIC_DISCOVERY_RANGE')   # robotica node sets it as scripts/env.sh does
    env['ROS_LOCALHOST_ONLY'] = '0'            # deprecated, would override the range: removed
    proc = subprocess.Popen(
        [*ROBOTICA, 'node', 'robotica_ctrl', 'path_publisher', '--ros-args', '-r',
         '__node:=my_path', '-p', 'x:=[0.0,4.0]', '-p', 'y:=[0.0,1.0]'],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    try:
        # The node is in the graph before it has published: wait for its path, so that the
        # signal comes after the log line this test reads.
        paths = []
        node.create_subscription(PathMessage, 'path', paths.append, LATCHED_QOS)
        assert spin(executor, lambda: bool(paths) and 'my_path' in node.get_node_names(),
                    timeout=30.0)
        # The same process (exec), now the node's executable with the arguments as given.
        cmdline = Path(f'/proc/{proc.pid}/cmdline').read_bytes().split(b'\0')[:-1]
        assert cmdline[-7:] == [b'--ros-args', b'-r', b'__node:=my_path', b'-p',
                                b'x:=[0.0,4.0]', b'-p', b'y:=[0.0,1.0]']
        assert cmdline[-8].endswith(b'/install/robotica_ctrl/lib/robotica_ctrl/path_publisher')
        environ = Path(f'/proc/{proc.pid}/environ').read_bytes().split(b'\0')
        assert b'ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST' in environ
        assert not any(v.startswith(b'ROS_LOCALHOST_ONLY=') for v in environ)
        proc.send_signal(stop)
        out, _ = proc.communicate(timeout=20)
    finally:
        proc.kill()
    assert proc.returncode == 0, out
    assert 'published a path of 2 points' in out and 'Traceback' not in out
