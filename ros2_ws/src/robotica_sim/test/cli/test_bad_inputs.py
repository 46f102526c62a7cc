"""
Bad input to every ``robotica`` verb: one line on stderr, the documented exit code, no traceback.

The corpus of bad scenarios is written into ``tmp_path`` by the tests; each must be refused
by ``robotica run`` with exit code 2 before the run directory is made (no node starts). The
verbs are run in-process through :func:`robotica_sim.cli.main.run_verb` (the entry point of
the command without its ``sys.exit``), a few through the real ``robotica`` command.
"""
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

import pytest
from robotica_sim.bags.typestore import jazzy_typestore
from robotica_sim.cli.main import run_verb
from rosbags.rosbag2 import StoragePlugin, Writer

BASE = """name: base
duration: 5.0
seed: 1
step_period: 0.02
robot:
  type: differential
path:
  shape: straight_line
  start: [0.0, 0.0]
  end: [5.0, 0.0]
tracker:
  law: pure_pursuit
  lookahead_distance: 0.5
"""
ARM = """name: arm
duration: 2.0
step_period: 0.001
robot:
  type: manipulator
arm:
  model: two_link_arm
  masses: [1.0, 1.0]
  lengths: [0.5, 0.5]
controller:
  law: computed_torque
"""


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new)


# (case, file contents, words the one line must hold)
CORPUS = [
    ('unknown law', _edit(BASE, 'pure_pursuit', 'pure_persuit'),
     ['tracker.law must be one of', "'pure_persuit'"]),
    ('misspelt gain', _edit(BASE, 'lookahead_distance', 'lookahead_distanc'),
     ['lookahead_distanc is not a gain of pure_pursuit', 'lookahead_distance']),
    ('gain of the wrong type', _edit(BASE, '0.5', '"half"'), ['tracker.lookahead_distance']),
    ('gain out of range', _edit(BASE, 'lookahead_distance: 0.5', 'lookahead_distance: -1.0'),
     ['tracker.lookahead_distance must be in']),
    ('gain list', _edit(BASE, 'lookahead_distance: 0.5', 'lookahead_distance: []'),
     ['tracker.lookahead_distance']),
    ('unknown path shape', _edit(BASE, 'straight_line', 'spiral'),
     ['path.shape must be one of', "'spiral'"]),
    ('missing shape argument', _edit(BASE, '  end: [5.0, 0.0]\n', ''), ['end']),
    ('unknown shape argument', _edit(BASE, '  end: [5.0, 0.0]\n', '  end: [5.0, 0.0]\n  r: 1\n'),
     ["'r'"]),
    ('mistyped shape argument', _edit(BASE, 'end: [5.0, 0.0]', 'end: five'), ['path']),
    ('shape argument of one number', _edit(BASE, 'end: [5.0, 0.0]', 'end: 5.0'), ['end']),
    ('equal ends', _edit(BASE, 'end: [5.0, 0.0]', 'end: [0.0, 0.0]'), ['must differ']),
    ('path of a billion points', _edit(BASE, 'end: [5.0, 0.0]', 'end: [5.0, 0.0]\n  spacing: '
                                       '1.0e-9'), ['points, more than']),
    ('huge circle', _edit(BASE, 'shape: straight_line\n  start: [0.0, 0.0]\n  end: [5.0, 0.0]',
                          'shape: circle\n  center: [0, 0]\n  radius: 1.0e+200'),
     ['path (circle)']),
    ('zero spacing', _edit(BASE, 'end: [5.0, 0.0]', 'end: [5.0, 0.0]\n  spacing: 0'),
     ['spacing must be a number > 0']),
    ('trajectory of tiny steps', _edit(
        BASE, 'shape: straight_line\n  start: [0.0, 0.0]\n  end: [5.0, 0.0]',
        'shape: unicycle_trajectory\n  start: [0, 0, 0]\n  segments: [[1, 0, 1000]]\n'
        '  step: 1.0e-9'), ['points, more than']),
    ('duplicate top-level key', BASE + 'seed: 2\n', ["key 'seed' given twice", 'line']),
    ('duplicate nested key', _edit(BASE, 'type: differential', 'type: differential\n  type: '
                                   'tricycle'), ["key 'type' given twice"]),
    ('zero duration', _edit(BASE, 'duration: 5.0', 'duration: 0'), ['duration']),
    ('duration shorter than a step', _edit(BASE, 'duration: 5.0', 'duration: 1.0e-9'),
     ['at least one step_period']),
    ('negative duration', _edit(BASE, 'duration: 5.0', 'duration: -1'), ['duration']),
    ('endless duration', _edit(BASE, 'duration: 5.0', 'duration: 1.0e+12'),
     ['at most 10000000 steps']),
    ('infinite duration', _edit(BASE, 'duration: 5.0', 'duration: .inf'), ['finite']),
    ('NaN duration', _edit(BASE, 'duration: 5.0', 'duration: .nan'), ['finite']),
    ('integer beyond float', _edit(BASE, 'duration: 5.0', 'duration: ' + '9' * 400),
     ['finite number']),
    ('duration as text', _edit(BASE, 'duration: 5.0', 'duration: five'), ['expected a number']),
    ('tiny step period', _edit(BASE, 'step_period: 0.02', 'step_period: 1.0e-9'),
     ['step_period must be in']),
    ('step period of 2 s', _edit(BASE, 'step_period: 0.02', 'step_period: 2.0'),
     ['step_period must be in']),
    ('huge seed', _edit(BASE, 'seed: 1', 'seed: 99999999999999999999'), ['seed']),
    ('seed beyond the nodes', _edit(BASE, 'seed: 1', 'seed: 3000000000'), ['seed must be in']),
    ('negative seed', _edit(BASE, 'seed: 1', 'seed: -1'), ['seed must be in']),
    ('seed as float', _edit(BASE, 'seed: 1', 'seed: 1.5'), ['expected an integer']),
    ('seed as bool', _edit(BASE, 'seed: 1', 'seed: true'), ['expected an integer']),
    ('unknown top-level key', BASE + 'speed: 3\n', ['unknown key(s) speed']),
    ('unknown robot type', _edit(BASE, 'differential', 'hovercraft'), ['robot.type']),
    ('bad pacing', BASE + 'pacing: fast\n', ['pacing must be lockstep or realtime']),
    ('name with a slash', _edit(BASE, 'name: base', 'name: ../../etc'), ['name must be']),
    ('empty name', _edit(BASE, 'name: base', "name: ''"), ['name must be']),
    ('robot as a list', _edit(BASE, 'robot:\n  type: differential', 'robot: [1, 2]'),
     ['expected a mapping']),
    ('initial pose of two numbers', _edit(BASE, 'type: differential', 'type: differential\n'
                                          '  initial_pose: [0, 0]'), ['initial_pose']),
    ('wheel radius zero', _edit(BASE, 'type: differential', 'type: differential\n'
                                '  wheel_radius: 0'), ['wheel_radius']),
    ('gyro heading without a gyro', BASE + 'odometry:\n  heading_source: gyro\n',
     ['needs sensors.gyro.enabled']),
    ('latitude 91', BASE + 'sensors:\n  gps:\n    enabled: true\n    origin: [91, 0, 0]\n',
     ['sensors.gps.origin']),
    ('arm section in a mobile run', BASE + 'arm:\n  model: puma560\n', ['do not apply']),
    ('pulses beyond int64', BASE + 'sensors:\n  encoders:\n    pulses_per_revolution: '
     + '9' * 30 + '\n', ['pulses_per_revolution']),
    ('not YAML', 'name: [unclosed\n', ['not valid YAML']),
    ('tab indentation', 'name: x\nrobot:\n\ttype: differential\n', ['not valid YAML']),
    ('a list, not a mapping', '- 1\n- 2\n', ['a scenario is a YAML mapping']),
    ('empty file', '', ['a scenario is a YAML mapping']),
    ('python object tag', 'name: !!python/object:os.system x\n', ['not valid YAML']),
    ('alias bomb', 'a: &a [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n' + ''.join(
        f'{x}: &{x} [{", ".join([f"*{y}"] * 10)}]\n' for y, x in zip('abcdefgh', 'bcdefghi'))
     + 'name: bomb\npath:\n  shape: polyline\n  points: *i\n', ['more than 1000000 values']),
    ('arm: unknown model', _edit(ARM, 'two_link_arm', 'scara'), ['arm.model']),
    ('arm: one mass', _edit(ARM, 'masses: [1.0, 1.0]', 'masses: [1.0]'), ['arm.masses']),
    ('arm: unknown reference key', ARM + 'reference:\n  wobble: 1\n',
     ['unknown key reference.wobble']),
    ('arm: gain as text', ARM + '  kp: lots\n', ['controller.kp']),
]


def _run_verb(capsys, argv: list[str]) -> tuple[int, list[str], str]:
    """Return the exit code, the stderr lines and stdout of ``robotica <argv>`` in-process."""
    code = run_verb([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, err.splitlines(), out


def _assert_one_line(code: int, lines: list[str], expected_code: int) -> str:
    assert code == expected_code, lines
    assert len(lines) == 1, lines
    assert 'Traceback' not in lines[0] and 'internal error' not in lines[0]
    return lines[0]


def test_the_corpus_is_big_enough():
    assert len(CORPUS) >= 40
    assert len({case for case, _, _ in CORPUS}) == len(CORPUS)


def test_the_base_scenarios_are_valid(tmp_path):
    from robotica_sim.runs.plan import plan_run
    from robotica_sim.runs.scenario import load_scenario
    for name, text in (('base', BASE), ('arm', ARM)):
        (tmp_path / f'{name}.yaml').write_text(text)
        assert plan_run(load_scenario(str(tmp_path / f'{name}.yaml')))


@pytest.mark.parametrize('case, text, words', CORPUS, ids=[c[0] for c in CORPUS])
def test_a_bad_scenario_is_one_line_and_exit_2(tmp_path, capsys, case, text, words):
    scenario = tmp_path / 'scenario.yaml'
    scenario.write_text(text)
    out = tmp_path / 'run'
    code, lines, _ = _run_verb(capsys, ['run', scenario, '--output-dir', out, '--quiet'])
    line = _assert_one_line(code, lines, 2)
    assert line.startswith(f'robotica run: error: {scenario}'), line
    for word in words:
        assert word in line
    assert not out.exists()   # refused before the run started


@pytest.mark.parametrize('content', [b'\x00\xff\xfe\x89PNG\r\n', b'name: caf\xe9\n'])
def test_an_undecodable_scenario_is_refused(tmp_path, capsys, content):
    scenario = tmp_path / 'binary.yaml'
    scenario.write_bytes(content)
    code, lines, _ = _run_verb(capsys, ['run', scenario, '--output-dir', tmp_path / 'run'])
    assert 'not a text file' in _assert_one_line(code, lines, 2)


@pytest.mark.parametrize('argv, words', [
    (['--duration', '-1'], ['argument --duration', 'got -1']),
    (['--duration', 'nan'], ['argument --duration']),
    (['--duration', '0.001'], ['--duration 0.001 (with', 'at least one step_period']),
    (['--timeout', '0'], ['argument --timeout']),
    (['--discovery-timeout', '-5'], ['argument --discovery-timeout']),
    (['--domain-id', '233'], ['argument --domain-id', '232']),
    (['--domain-id', 'x'], ['argument --domain-id', 'expected an integer']),
    (['--pacing', 'fast'], ['argument --pacing']),
])
def test_bad_options_of_run_blame_the_option(tmp_path, capsys, argv, words):
    scenario = tmp_path / 'base.yaml'
    scenario.write_text(BASE)
    code, lines, _ = _run_verb(capsys, ['run', scenario, '--output-dir', tmp_path / 'run',
                                        *argv])
    line = _assert_one_line(code, lines, 2)
    assert 'base.yaml:' not in line   # the option is at fault, not the file
    for word in words:
        assert word in line
    assert not (tmp_path / 'run').exists()


def test_a_domain_id_from_the_environment_is_checked(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv('ROS_DOMAIN_ID', '500')
    code, lines, _ = _run_verb(capsys, ['run', 'demo', '--output-dir', tmp_path / 'run'])
    assert 'ROS_DOMAIN_ID must be >= 0 and <= 232' in _assert_one_line(code, lines, 2)


def test_a_domain_id_above_101_is_allowed_with_a_warning():
    from robotica_sim.cli.options import domain_id, domain_warning
    assert domain_id('150') == 150 and domain_id('232') == 232
    assert domain_warning(101) is None
    assert '7400' not in domain_warning(150) and '44900' in domain_warning(150)


def _write_bag(path: Path, seconds: float = 2.0, rate: float = 10.0,
               with_path: bool = True) -> Path:
    """Write a bag with /clock at ``rate`` [Hz] for ``seconds`` [s], and a /path."""
    store = jazzy_typestore()
    types = store.types
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    clock = writer.add_connection('/clock', 'rosgraph_msgs/msg/Clock', typestore=store)
    for k in range(int(seconds * rate) + 1):
        t = round(k * 1e9 / rate)
        msg = types['rosgraph_msgs/msg/Clock'](clock=types['builtin_interfaces/msg/Time'](
            sec=t // 10**9, nanosec=t % 10**9))
        writer.write(clock, t, store.serialize_cdr(msg, 'rosgraph_msgs/msg/Clock'))
    if with_path:   # something `robotica report` can draw
        header = types['std_msgs/msg/Header'](
            stamp=types['builtin_interfaces/msg/Time'](sec=0, nanosec=0), frame_id='odom')
        poses = [types['geometry_msgs/msg/PoseStamped'](header=header, pose=types[
            'geometry_msgs/msg/Pose'](position=types['geometry_msgs/msg/Point'](x=x, y=0.0, z=0.0),
                                      orientation=types['geometry_msgs/msg/Quaternion'](
                                          x=0.0, y=0.0, z=0.0, w=1.0)))
            for x in (0.0, 1.0)]
        connection = writer.add_connection('/path', 'nav_msgs/msg/Path', typestore=store)
        writer.write(connection, 0, store.serialize_cdr(
            types['nav_msgs/msg/Path'](header=header, poses=poses), 'nav_msgs/msg/Path'))
    writer.close()
    return path


@pytest.fixture
def inputs(tmp_path) -> dict:
    """Bad inputs of every class: a missing path, a folder and files that are not bags."""
    folder = tmp_path / 'empty'
    folder.mkdir()
    text = tmp_path / 'notes.txt'
    text.write_text('not a bag\n')
    binary = tmp_path / 'binary'
    binary.mkdir()
    (binary / 'metadata.yaml').write_bytes(b'\x00\xff\xfe\x89PNG\r\n\x1a\n')
    return {'missing': tmp_path / 'missing', 'folder': folder, 'file': text,
            'binary': binary, 'bag': _write_bag(tmp_path / 'bag'), 'tmp': tmp_path}


# (verb and arguments with {placeholders} of the inputs fixture, exit code)
VERB_CASES = [
    ('info {missing}', 1), ('info {folder}', 1), ('info {file}', 1), ('info {binary}', 1),
    ('info', 2), ('info {bag} --jsn', 2),
    ('play {missing}', 1), ('play {folder}', 1), ('play {binary}', 1),
    ('play {bag} --rate 0', 2), ('play {bag} --rate 1e-9', 2), ('play {bag} --rate inf', 2),
    ('play {bag} --wait -1', 2), ('play {bag} --remap odom', 2),
    ('play {bag} --topics /nothing', 2),
    ('bag repair {missing}', 1), ('bag repair {file}', 1), ('bag repair {folder}', 1),
    ('bag fix {bag}', 2),
    ('grade {missing}', 1), ('grade {folder}', 1), ('grade {binary}', 1),
    ('grade {bag} --jobs 0', 2), ('grade {bag} --rubric {missing}', 2),
    ('grade {bag} --rubric {binary}/metadata.yaml', 2),
    ('grade {bag} --json {file}/x.json', 2),
    ('report {missing}', 1), ('report {folder}', 1), ('report {binary}', 1),
    ('report {bag} --robot-every 0', 2), ('report {bag} --robot-every 1e-9', 2),
    ('report {bag} --robot-every nan', 2), ('report {bag} --output {file}/report', 2),
    ('report {bag} --output /proc/robotica-report', 2), ('bag repair {binary}', 1),
    ('bench kin --count 0', 2), ('bench kin --seed -1', 2), ('bench kin --seed 1e99', 2),
    ('bench arm --loop-duration -1', 2), ('bench recorder --rates 0', 2),
    ('bench warp', 2), ('bench tracking --plots {file}/plots', 2),
    ('run {missing}', 2), ('run {file}', 2), ('run {binary}/metadata.yaml', 2),
    ('run {tmp}', 2), ('run demo --output-dir {file}/run', 2),
    ('run demo --output-dir /proc/robotica-run', 2),
    ('walk', 2), ('', 2),
]


@pytest.mark.parametrize('command, expected', VERB_CASES, ids=[c[0] or '(none)'
                                                               for c in VERB_CASES])
def test_every_verb_answers_bad_input_in_one_line(capsys, inputs, command, expected):
    argv = [word.format(**inputs) for word in command.split()]
    code, lines, _ = _run_verb(capsys, argv)
    line = _assert_one_line(code, lines, expected)
    assert line.startswith('robotica'), line


def test_report_refuses_to_draw_the_robot_too_often(capsys, inputs):
    code, lines, _ = _run_verb(capsys, ['report', inputs['bag'], '--robot-every', '1e-5'])
    line = _assert_one_line(code, lines, 2)
    assert 'at most 1000' in line and not (inputs['tmp'] / 'bag_report').exists()


def _robotica(*argv: str, **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, '-m', 'robotica_sim.cli.main', *map(str, argv)],
                            stderr=subprocess.PIPE, text=True, **kwargs)


def test_the_command_refuses_a_binary_scenario_in_one_line(tmp_path):
    scenario = tmp_path / 'binary.yaml'
    scenario.write_bytes(b'\x00\xff\xfe')
    process = _robotica('run', scenario, '--output-dir', tmp_path / 'run')
    _, err = process.communicate(timeout=60)
    _assert_one_line(process.returncode, err.splitlines(), 2)


def test_a_closed_stdout_ends_the_command_quietly(inputs):
    process = _robotica('info', inputs['bag'], stdout=subprocess.PIPE)
    process.stdout.close()   # like `| head` gone before the command writes
    _, err = process.communicate(timeout=60)
    assert process.returncode == 141 and err == ''


def test_sigterm_ends_play_cleanly(tmp_path):
    bag = _write_bag(tmp_path / 'long', seconds=120.0, rate=10.0)
    env = {**os.environ, 'PYTHONUNBUFFERED': '1'}
    process = _robotica('play', bag, '--wait', '0', env=env)
    deadline = time.monotonic() + 60.0
    line = process.stderr.readline()   # the first progress line: the replay is under way
    assert line.startswith('robotica play:') and time.monotonic() < deadline, line
    process.send_signal(signal.SIGTERM)
    _, rest = process.communicate(timeout=30)
    assert process.returncode == 130
    assert 'Traceback' not in rest and 'context is invalid' not in rest


HOSTILE_VALUES = ['x', -1, 0, 1e308, -1e308, [], {}, None, True, 10**30, [1, 'a'], [[1, 2]],
                  1e-300, '']


def _leaves(data: dict, prefix: tuple = ()):
    for key, value in data.items():
        yield prefix + (key,)
        if isinstance(value, dict):
            yield from _leaves(value, prefix + (key,))


@pytest.mark.parametrize('shipped', ['demo', 'ej8_2'])
def test_every_key_of_a_shipped_scenario_refuses_hostile_values(tmp_path, shipped):
    """Each key set to each hostile value: a valid scenario or one ScenarioError line."""
    import warnings

    from robotica_sim.runs.plan import plan_run
    from robotica_sim.runs.scenario import load_scenario, resolve_scenario_path, ScenarioError
    import yaml
    base = yaml.safe_load(resolve_scenario_path(shipped).read_text())
    scenario = tmp_path / 'hostile.yaml'
    for path in _leaves(base):
        for value in HOSTILE_VALUES:
            data = yaml.safe_load(yaml.safe_dump(base))
            parent = data
            for key in path[:-1]:
                parent = parent[key]
            parent[path[-1]] = value
            scenario.write_text(yaml.safe_dump(data))
            with warnings.catch_warnings():
                warnings.simplefilter('error')   # a warning would be a second line
                try:
                    plan_run(load_scenario(str(scenario)))
                except ScenarioError as err:
                    assert '\n' not in str(err), (path, value)
