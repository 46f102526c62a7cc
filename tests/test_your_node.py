"""
A user's own node in a run (docs/your_node.md): the templates pass, broken nodes are named.

Each template that ``robotica new`` writes runs unchanged in its lockstep scenario and passes
its rubric (``robotica grade`` exit 0), and the bag shows that the user's node, not robotica's,
published the role's answer. Deliberately broken trackers (one never publishes, one publishes
NaN, one hangs at t = 2 s, one dies at t = 3 s, one exits at once) end the run with exit 1 and
one message that names the node, what it did and the contract, and leave no process behind.
"""
import json
import subprocess
import textwrap

import pytest
from rosbags.highlevel import AnyReader
import yaml

pytestmark = [pytest.mark.slow, pytest.mark.ros]
RUN_TIMEOUT = 300   # [s] wall clock


def robotica(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(['robotica', *args], capture_output=True, text=True, cwd=cwd,
                          timeout=RUN_TIMEOUT)


def publishers(bag) -> dict:
    """Return the nodes that published each recorded topic (the recorder's custom data)."""
    metadata = yaml.safe_load((bag / 'metadata.yaml').read_text())
    custom = metadata['rosbag2_bagfile_information']['custom_data']
    return yaml.safe_load(custom['robotica.publishers'])


@pytest.mark.parametrize('role, answer', [('tracker', '/cmd_vel'), ('estimator', '/odom'),
                                          ('joint_controller', '/joint_torques')])
def test_template_passes_its_rubric(tmp_path, ros_domain, role, answer):
    made = robotica('new', role, 'mine', '--output-dir', str(tmp_path))
    assert made.returncode == 0, made.stderr
    run = robotica('run', str(tmp_path / 'mine.yaml'), '--output-dir', str(tmp_path / 'run'),
                   '--visualisation', 'off', '--json', '--quiet')
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert summary['lockstep_timeouts'] == 0
    bag = tmp_path / 'run' / 'bag'
    node = {'tracker': '/path_tracker', 'estimator': '/odometry',
            'joint_controller': '/joint_controller'}[role]
    assert publishers(bag)[answer] == [node]
    ran = yaml.safe_load((tmp_path / 'run' / 'run.yaml').read_text())
    mine = [n for n in ran['nodes'] if n['name'] == node[1:]]
    assert mine[0]['started_by'] == 'user' and mine[0]['command'].endswith('mine.py')
    grade = robotica('grade', str(bag), '--rubric', str(tmp_path / 'mine_rubric.yaml'))
    assert grade.returncode == 0, grade.stdout + grade.stderr
    assert 'PASS' in grade.stdout.splitlines()[-1]
    with AnyReader([bag]) as reader:   # one answer per step (lockstep), every step answered
        counts = {c.topic: c.msgcount for c in reader.connections}
    steps = round(summary['duration'] / ran['step_period'])
    assert steps <= counts[answer] <= steps + 2


BROKEN = {
    'silent': """
        def on_odom(self, msg):
            pass   # never answers
    """,
    'nan': """
        def on_odom(self, msg):
            self.pub.publish(Twist(linear=Vector3(x=math.nan)))
    """,
    'hangs': """
        def on_odom(self, msg):
            if msg.header.stamp.sec >= 2:
                time.sleep(3600)   # a callback that never returns
            self.pub.publish(Twist())
    """,
    'dies': """
        def on_odom(self, msg):
            if msg.header.stamp.sec >= 3:
                os._exit(1)
            self.pub.publish(Twist())
    """,
}


def broken_tracker(folder, kind: str) -> None:
    """Write ``<kind>.py`` (a tracker broken as ``BROKEN[kind]`` says) and ``<kind>.yaml``."""
    body = textwrap.indent(textwrap.dedent(BROKEN[kind]), '    ')
    (folder / f'{kind}.py').write_text(textwrap.dedent('''\
        import math
        import os
        import time

        from geometry_msgs.msg import Twist, Vector3
        from nav_msgs.msg import Odometry
        import rclpy
        from rclpy.node import Node


        class Broken(Node):
            def __init__(self):
                super().__init__('broken')
                self.create_subscription(Odometry, 'odom', self.on_odom, 10)
                self.pub = self.create_publisher(Twist, 'cmd_vel', 10)
        ''') + body + textwrap.dedent('''

        rclpy.init()
        rclpy.spin(Broken())
        '''))
    scenario = yaml.safe_load(robotica('new', 'tracker', 'x', '--output-dir',
                                       str(folder / 'x')).returncode == 0
                              and (folder / 'x' / 'x.yaml').read_text())
    scenario.update(name=kind, duration=8.0)
    scenario['tracker'] = {'external': {'command': ['python3', f'{kind}.py'],
                                        'answer_timeout': 2.0}}
    (folder / f'{kind}.yaml').write_text(yaml.safe_dump(scenario))


def still_running(script) -> str:
    return subprocess.run(['pgrep', '-af', str(script)], capture_output=True,
                          text=True).stdout.strip()


@pytest.mark.parametrize('kind, says', [
    ('silent', ['`silent.py` never published cmd_vel for step 0 within 2 s',
                'it subscribes to: /odom [nav_msgs/msg/Odometry]',
                'it publishes: /cmd_vel [geometry_msgs/msg/Twist]',
                'The contract of a tracker is: in: odom (nav_msgs/msg/Odometry, stream)']),
    ('nan', ['`nan.py` published a cmd_vel with a non-finite linear.x (seen by t = ',
             'The contract of a tracker is']),
    ('hangs', ['`hangs.py` stopped answering: no cmd_vel for 2 s since t = 2.',
               'it subscribes to: /odom']),
    ('dies', ['`dies.py` (the tracker) exited with code 1 by t = 3.']),
])
def test_broken_tracker_is_named(tmp_path, ros_domain, kind, says):
    broken_tracker(tmp_path, kind)
    run = robotica('run', f'{kind}.yaml', '--output-dir', str(tmp_path / 'run'),
                   '--visualisation', 'off', '--quiet', cwd=tmp_path)
    assert run.returncode == 1, run.stderr
    failure = next(line for line in run.stderr.splitlines()
                   if line.startswith('robotica run: failed: '))
    for text in says:
        assert text in failure, failure
    assert (tmp_path / 'run' / 'bag' / 'metadata.yaml').is_file()   # the run is kept
    assert not still_running(tmp_path / f'{kind}.py')


def test_a_command_that_exits_at_once(tmp_path, ros_domain):
    (tmp_path / 'quit.py').write_text('raise SystemExit(3)\n')
    broken_tracker(tmp_path, 'silent')
    scenario = yaml.safe_load((tmp_path / 'silent.yaml').read_text())
    scenario['tracker']['external']['command'] = ['python3', 'quit.py']
    (tmp_path / 'quit.yaml').write_text(yaml.safe_dump(scenario))
    run = robotica('run', 'quit.yaml', '--output-dir', str(tmp_path / 'run'), '--quiet',
                   '--visualisation', 'off', cwd=tmp_path)
    assert run.returncode == 1
    assert 'robotica run: failed: `quit.py` (the tracker) exited with code 3' in run.stderr
    assert not still_running(tmp_path / 'quit.py')
