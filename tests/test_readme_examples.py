r"""
The README's hand-started examples, run as written: the robot must move.

Each code block made only of ``robotica node`` commands is started, one process a command, on a
private domain.

A block's ``\`` continuation lines are joined, and each command is split as a shell would
(``shlex``); ``robotica`` is the command of ``bin/`` (put on PATH by ``scripts/env.sh``). A mobile
robot moves when its ``/ground_truth/odom`` position changes, an arm when its ``/joint_states``
positions do.
"""
import os
from pathlib import Path
import re
import shlex
import shutil
import signal
import subprocess

from nav_msgs.msg import Odometry
import numpy as np
import pytest
from robotica_kin.ros.qos import STREAM_SUB_QOS
from sensor_msgs.msg import JointState

README = Path(__file__).resolve().parents[1] / 'README.md'
MOVED = 0.05     # [m] of the vehicle, [rad] of a joint
TIMEOUT = 60.0   # [s] wall clock for the robot to move after its nodes start


def node_blocks() -> list[list[str]]:
    """Return the README's bash blocks that hold only ``robotica node`` commands."""
    blocks = []
    for body in re.findall(r'```bash\n(.*?)```', README.read_text(), flags=re.S):
        commands = [line.strip() for line in body.replace('\\\n', ' ').splitlines()
                    if line.strip()]
        if commands and all(c.startswith('robotica node ') for c in commands):
            blocks.append(commands)
    return blocks


BLOCKS = node_blocks()


def test_the_readme_has_a_mobile_and_an_arm_example():
    executables = [{shlex.split(c)[3] for c in block} for block in BLOCKS]
    assert executables == [{'path_publisher', 'path_tracker', 'simulator'},
                           {'arm_simulator', 'joint_controller', 'joint_trajectory_publisher'}]


@pytest.mark.ros
@pytest.mark.parametrize('block', [   # the arm: 8 s, 37 s on a loaded machine
    pytest.param(BLOCKS[0], id='mobile'), pytest.param(BLOCKS[1], id='arm',
                                                       marks=pytest.mark.slow)])
def test_a_readme_example_moves_the_robot(block, ros_node, spin, tmp_path):
    node, executor = ros_node
    assert shutil.which('robotica'), 'robotica not on PATH: source scripts/env.sh'
    positions = []
    if any('arm_simulator' in command for command in block):
        node.create_subscription(JointState, 'joint_states',
                                 lambda m: positions.append(np.array(m.position)),
                                 STREAM_SUB_QOS)
    else:
        node.create_subscription(
            Odometry, 'ground_truth/odom', lambda m: positions.append(
                np.array([m.pose.pose.position.x, m.pose.pose.position.y])), STREAM_SUB_QOS)
    procs = []
    try:
        for k, command in enumerate(block):
            log = open(tmp_path / f'{k}.log', 'w+b')
            procs.append((subprocess.Popen(shlex.split(command), stdout=log,
                                           stderr=subprocess.STDOUT, env=dict(os.environ)),
                          log))

        def moved() -> bool:
            return bool(positions) and np.max(np.abs(positions[-1] - positions[0])) > MOVED

        assert spin(executor, moved, timeout=TIMEOUT), '\n'.join(
            log.name for _, log in procs)
        assert all(proc.poll() is None for proc, _ in procs)
    finally:
        for proc, log in procs:
            proc.send_signal(signal.SIGINT)
        for proc, log in procs:
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            log.close()
