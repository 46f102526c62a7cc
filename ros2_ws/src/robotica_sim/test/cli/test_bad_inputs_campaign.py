"""
A second campaign of bad inputs against every ``robotica`` verb (issue 16, "Done when").

Independent of test_bad_inputs.py (whose helpers it imports): other arguments (empty strings,
FIFOs, devices, symlink loops, numbers YAML 1.1 reads as strings), other files (metadata.yaml
malformed, of another bag, lying, a FIFO in place of a file, a bag of no message, a bag whose
scenario names the other kind of robot, rubrics wrong in every way), output failures (a full
disk: /dev/full and RLIMIT_FSIZE; a closed pipe; a directory that cannot be written), signals
(SIGINT and SIGTERM while the command starts and while each long verb works), and numbers that
did not describe what ran. Each case is a bad argument (one line on stderr, exit 2), an input
or I/O failure (one line, exit 1), or a bad input that must now be read correctly (exit 0, the
right number); never a traceback, an "internal error" or a hang (a watchdog fails a case that
blocks). Most cases run in-process through :func:`robotica_sim.cli.main.run_verb`; signals and
resource limits need a real process.
"""
from contextlib import contextmanager
import importlib.util
import os
from pathlib import Path
import resource
import shutil
import signal
import subprocess
import sys
import time

import pytest
from robotica_sim.bags.run_record import record_end
from robotica_sim.cli.main import run_verb
from robotica_sim.grading.series import load_run
from robotica_sim.runs.scenario import load_scenario
import yaml

TEST = Path(__file__).resolve().parents[1]


def _sibling(relative: str):
    """Import a test module of this package by its path (the test folders are no packages)."""
    path = TEST / relative
    spec = importlib.util.spec_from_file_location(f'campaign_{path.stem}', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


BAD_INPUTS = _sibling('cli/test_bad_inputs.py')     # _run_verb, _assert_one_line, _write_bag
GRADE = _sibling('cli/test_grade.py')               # write_run: a mobile run
REPORT = _sibling('grading/test_report.py')         # write_arm_bag, write_mobile_bag
REPAIR = _sibling('bags/test_repair.py')            # killed_bag: a recorder killed
_run_verb, _assert_one_line = BAD_INPUTS._run_verb, BAD_INPUTS._assert_one_line
WATCHDOG = 20.0   # [s] a case that takes longer hangs (a FIFO opened for reading waits for ever)


def _edit_metadata(bag: Path, edit) -> None:
    """Apply ``edit`` to the bag's rosbag2_bagfile_information (a dict) and write it back."""
    path = bag / 'metadata.yaml'
    data = yaml.safe_load(path.read_text())
    edit(data['rosbag2_bagfile_information'])
    path.write_text(yaml.safe_dump(data))


def _set_robot(bag: Path, robot_type: str) -> None:
    """Make the scenario recorded in the bag name ``robot_type`` (a scenario that lies)."""
    def edit(information):
        custom = information['custom_data']
        scenario = yaml.safe_load(custom['robotica.scenario.yaml'])
        scenario['robot'] = {'type': robot_type}
        custom['robotica.scenario.yaml'] = yaml.safe_dump(scenario)
    _edit_metadata(bag, edit)


def _lie(information) -> None:
    """Claim 1e9 messages, 11 days and a topic with 99 messages that the file does not hold."""
    information['duration'] = {'nanoseconds': 10**15}
    information['message_count'] = 10**9
    for topic in information['topics_with_message_count']:
        topic['message_count'] = 123456
    information['topics_with_message_count'].append({'topic_metadata': {
        'name': '/ghost', 'type': 'std_msgs/msg/Float64', 'serialization_format': 'cdr',
        'offered_qos_profiles': [], 'type_description_hash': ''}, 'message_count': 99})


RUBRICS = {   # name: text; every one is refused with exit 2
    'key twice': 'checks:\n  rms_cross_track: {max: 0.1}\n  rms_cross_track: {max: 100}\n',
    'section twice': 'checks:\n  completion: {min: 0.1}\nchecks:\n  completion: {min: 0.9}\n',
    'a list': '- checks\n',
    'checks a list': 'checks: [rms_cross_track]\n',
    'NaN bound': 'checks:\n  rms_cross_track: {max: .nan}\n',
    'bound beyond float': 'checks:\n  rms_cross_track: {max: 1e400}\n',
    'bound as text': 'checks:\n  rms_cross_track: {max: "0.1"}\n',
    'bound as bool': 'checks:\n  rms_cross_track: {max: true}\n',
    'min above max': 'checks:\n  rms_cross_track: {max: 0.1, min: 0.2}\n',
    'scenario a number': 'scenario: 5\nchecks:\n  completion: {min: 0.1}\n',
    'scenario empty': "scenario: ''\nchecks:\n  completion: {min: 0.1}\n",
    'scenario empty list': 'scenario: []\nchecks:\n  completion: {min: 0.1}\n',
    'parameter negative': 'parameters: {goal_tolerance: -1}\nchecks:\n  completion: {min: 0.1}\n',
    'parameter zero': 'parameters: {goal_tolerance: 0}\nchecks:\n  completion: {min: 0.1}\n',
    'parameters a list': 'parameters: [1]\nchecks:\n  completion: {min: 0.1}\n',
    'title a list': 'rubric: [a]\nchecks:\n  completion: {min: 0.1}\n',
    'empty bound': 'checks:\n  completion: {}\n',
    'unknown bound key': 'checks:\n  completion: {min: 0.1, avg: 2}\n',
    'metric in capitals': 'checks:\n  Completion: {min: 0.1}\n',
    'tab': 'checks:\n  completion: {min: 0.1}\n\t',
    'python tag': 'checks:\n  completion: {min: !!python/name:os.system }\n',
    'empty file': '',
    'a megabyte': 'a' * 1_500_000,
    'alias bomb': 'a: &a [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n' + ''.join(
        f'{x}: &{x} [{", ".join([f"*{y}"] * 10)}]\n' for y, x in zip('abcdefgh', 'bcdefghi'))
    + 'checks:\n  completion: {min: 0.1}\n',
}


@pytest.fixture(scope='module')
def inputs(tmp_path_factory) -> dict:
    """Write the campaign's inputs once: bags good, broken and lying, rubrics, odd files."""
    root = tmp_path_factory.mktemp('campaign')
    clock = BAD_INPUTS._write_bag(root / 'clock')
    mobile = GRADE.write_run(root / 'mobile', 0.05)
    REPORT.write_arm_bag(root / 'arm')
    found = {'root': root, 'clock': clock, 'mobile': mobile, 'arm': root / 'arm'}
    os.mkfifo(root / 'fifo')
    os.symlink(root / 'loop', root / 'loop')
    (root / 'empty_file').write_text('')
    (root / 'empty_dir').mkdir()
    found.update({name: root / name for name in ('fifo', 'loop', 'empty_file', 'empty_dir')})
    mcap = next(clock.glob('*.mcap')).name

    def variant(name: str, source: Path = clock) -> Path:
        found[name] = root / name
        shutil.copytree(source, found[name])
        return found[name]
    magic = b'\x89MCAP0\r\n'   # an MCAP file's first and last bytes: looks finished
    (variant('garbage') / mcap).write_bytes(magic + os.urandom(5000) + magic)
    (variant('random') / mcap).write_bytes(os.urandom(5000))         # looks cut short
    (variant('zero_mcap') / mcap).write_bytes(b'')
    other = variant('other_metadata')                                 # metadata of another bag
    shutil.copy(mobile / 'metadata.yaml', other / 'metadata.yaml')
    (variant('metadata_malformed') / 'metadata.yaml').write_text(
        'rosbag2_bagfile_information: [unclosed\n')
    (variant('metadata_list') / 'metadata.yaml').write_text('- 1\n')
    _edit_metadata(variant('metadata_wrong_types'), lambda i: i.update(
        topics_with_message_count='x', duration={'nanoseconds': 'long'}))
    _edit_metadata(variant('metadata_lies'), _lie)
    swapped = variant('metadata_of_another_run', mobile)   # files named alike, as runs' are
    next(swapped.glob('*.mcap')).rename(swapped / next(found['arm'].glob('*.mcap')).name)
    shutil.copy(found['arm'] / 'metadata.yaml', swapped / 'metadata.yaml')
    for name, path in (('metadata_dir', 'metadata.yaml'), ('metadata_fifo', 'metadata.yaml'),
                       ('mcap_fifo', mcap), ('mcap_dir', mcap)):
        target = variant(name) / path
        target.unlink()
        os.mkfifo(target) if name.endswith('fifo') else target.mkdir()
    _set_robot(variant('arm_says_mobile', found['arm']), 'differential')
    for name, offset in (('truth_inf', float('inf')), ('truth_nan', float('nan')),
                         ('truth_1e308', 1e308)):   # a user's node published them
        found[name] = GRADE.write_run(root / name, offset)
    _set_robot(variant('mobile_says_arm', mobile), 'manipulator')
    from rosbags.rosbag2 import StoragePlugin, Writer
    from robotica_sim.bags.typestore import jazzy_typestore
    writer = Writer(root / 'no_message', version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    writer.add_connection('/clock', 'rosgraph_msgs/msg/Clock', typestore=jazzy_typestore())
    writer.close()
    found['no_message'] = root / 'no_message'
    for number, (name, text) in enumerate(RUBRICS.items()):
        found[f'rubric{number}'] = root / f'rubric{number}.yaml'
        found[f'rubric{number}'].write_text(text)
    found['rubric_1e3'] = root / 'rubric_1e3.yaml'    # YAML 1.2 floats without a dot
    found['rubric_1e3'].write_text('checks:\n  rms_cross_track: {max: 1e3, min: 1e-3}\n')
    return found


# (verb, class, command with {placeholders} of `inputs`, exit code, words the line holds)
CASES = [
    ('info', 'argument', 'info ""', 2, ['must not be empty']),
    ('info', 'argument', 'info {fifo}', 1, ['not a bag directory']),
    ('info', 'argument', 'info {loop}', 1, ['not a bag directory']),
    ('info', 'argument', 'info /dev/null', 1, ['not a bag directory']),
    ('info', 'argument', 'info {empty_file}', 1, ['not a bag directory']),
    ('info', 'file', 'info {garbage}', 1, ['a partial bag', 'cut short (no MCAP footer)']),
    ('info', 'file', 'info {random}', 1, ['partial bag', 'robotica bag repair']),
    ('info', 'file', 'info {zero_mcap}', 1, ['partial bag', 'robotica bag repair']),
    ('info', 'file', 'info {other_metadata}', 1, ['missing']),
    ('info', 'file', 'info {metadata_malformed}', 1, ['Could not load YAML']),
    ('info', 'file', 'info {metadata_list}', 1, ['cannot read the bag']),
    ('info', 'file', 'info {metadata_wrong_types}', 1, ['cannot read the bag']),
    ('info', 'file', 'info {metadata_lies}', 1, ['does not describe the data',
                                                 '/ghost: 99 listed, 0 held']),
    ('info', 'file', 'info {metadata_of_another_run}', 1, ['does not describe the data',
                                                           'robotica bag repair']),
    ('info', 'file', 'info {metadata_dir}', 1, ['metadata.yaml not a regular file']),
    ('info', 'file', 'info {metadata_fifo}', 1, ['metadata.yaml not a regular file']),
    ('info', 'file', 'info {mcap_fifo}', 1, ['not a regular file']),
    ('info', 'file', 'info {mcap_dir}', 1, ['not a regular file']),
    ('play', 'argument', 'play ""', 2, ['must not be empty']),
    ('play', 'argument', 'play {clock} --rate ""', 2, ['--rate']),
    ('play', 'argument', 'play {clock} --rate 1e309', 2, ['--rate']),
    ('play', 'argument', 'play {clock} --rate -0', 2, ['--rate']),
    ('play', 'argument', 'play {clock} --wait 1e400', 2, ['--wait']),
    ('play', 'argument', 'play {clock} --remap /clock:=', 2, ['/from:=/to']),
    ('play', 'argument', 'play {clock} --remap :=/x', 2, ['/from:=/to']),
    ('play', 'argument', 'play {clock} --remap /clock:=/1st', 2, ['not a ROS topic name']),
    ('play', 'argument', 'play {clock} --remap /clock:=/a//b', 2, ['not a ROS topic name']),
    ('play', 'argument', 'play {clock} --remap /clock:=/a/ --wait 0', 2,
     ['not a ROS topic name']),
    ('play', 'argument', 'play {clock} --remap /clock:=/x /clock:=/y', 2, ['remapped twice']),
    ('play', 'argument', 'play {clock} --remap /clock:=/path', 2,
     ['/clock and /path would both be published as /path']),
    ('play', 'argument', 'play {arm} --remap /joint_torques:=/joint_states', 2,
     ['would both be published as /joint_states']),
    ('play', 'argument', 'play {clock} --topics ""', 2, ["--topics '': not a ROS topic name"]),
    ('play', 'argument', 'play {clock} --topics clock', 2, ["--topics 'clock': not a ROS"]),
    ('play', 'argument', 'play {clock} --topics /clock /odom', 2, ['no topic /odom', '/clock']),
    ('play', 'file', 'play {mcap_fifo}', 1, ['not a regular file']),
    ('play', 'file', 'play {metadata_malformed}', 1, ['Could not load YAML']),
    ('grade', 'argument', 'grade ""', 2, ['must not be empty']),
    ('grade', 'argument', 'grade {fifo}', 1, ['not a bag directory']),
    ('grade', 'argument', 'grade {loop}', 1, ['not a bag directory']),
    ('grade', 'argument', 'grade /dev/null', 1, ['not a bag directory']),
    ('grade', 'argument', 'grade {mobile} --jobs ""', 2, ['--jobs']),
    ('grade', 'argument', 'grade {mobile} --jobs 99999999999999999999999', 2, ['--jobs']),
    ('grade', 'argument', 'grade {mobile} --jobs 1000', 2, ['--jobs', '<= 64']),
    ('grade', 'argument', 'grade {mobile} --rubric ""', 2, ['must not be empty']),
    ('grade', 'argument', 'grade {mobile} --rubric {fifo}', 2, ['no rubric file']),
    ('grade', 'argument', 'grade {mobile} --rubric {loop}', 2, ['no rubric file']),
    ('grade', 'argument', 'grade {mobile} --rubric /dev/zero', 2, ['no rubric file']),
    ('grade', 'argument', 'grade {mobile} --rubric {empty_dir}', 2, ['no rubric file']),
    ('grade', 'file', 'grade {mcap_fifo}', 1, ['not a regular file']),
    ('grade', 'file', 'grade {metadata_malformed}', 1, ['Could not load YAML']),
    ('grade', 'file', 'grade {garbage}', 1, ['a partial bag', 'cut short (no MCAP footer)']),
    ('grade', 'file', 'grade {zero_mcap}', 1, ['partial bag']),
    ('grade', 'file', 'grade {no_message}', 1, ['holds no message']),
    ('grade', 'file', 'grade {truth_inf}', 1, ['/ground_truth/odom holds values no run']),
    ('grade', 'file', 'grade {truth_nan}', 1, ['/ground_truth/odom holds values no run']),
    ('grade', 'file', 'grade {truth_1e308}', 1, ['e.g. 1e+308']),
    ('grade', 'file', 'grade {other_metadata}', 1, ['missing']),
    ('grade', 'file', 'grade {metadata_of_another_run}', 1, ['does not describe the data']),
    *[('grade', 'file', f'grade {{mobile}} --rubric {{rubric{number}}}', 2,
       [f'rubric{number}.yaml'])
      for number in range(len(RUBRICS))],
    ('grade', 'output', 'grade {mobile} --json ""', 2, ['must not be empty']),
    ('grade', 'output', 'grade {mobile} --json {empty_dir}', 2, ['a directory']),
    ('grade', 'output', 'grade {mobile} --json {root}/none/grades.json', 2, ['no directory']),
    ('grade', 'output', 'grade {mobile} --json /sys/robotica-grades.json', 2,
     ['cannot write /sys/robotica-grades.json']),
    ('grade', 'output', 'grade {mobile} --json /dev/full', 1, ['No space left on device']),
    ('report', 'argument', 'report ""', 2, ['must not be empty']),
    ('report', 'argument', 'report {loop}', 1, ['not a bag directory']),
    ('report', 'argument', 'report {mobile} --robot-every ""', 2, ['--robot-every']),
    ('report', 'file', 'report {mcap_fifo}', 1, ['not a regular file']),
    ('report', 'file', 'report {no_message}', 1, ['holds no message']),
    ('report', 'file', 'report {truth_inf}', 1, ['/ground_truth/odom holds values no run']),
    ('report', 'file', 'report {truth_1e308}', 1, ['e.g. 1e+308']),
    ('report', 'file', 'report {metadata_malformed}', 1, ['Could not load YAML']),
    ('report', 'file', 'report {metadata_lies}', 1, ['does not describe the data']),
    ('report', 'output', 'report {mobile} --output ""', 2, ['must not be empty']),
    ('report', 'output', 'report {mobile} --output {fifo}', 2, ['cannot write the report']),
    ('report', 'output', 'report {mobile} --output /dev/full', 2, ['cannot write the report']),
    ('report', 'output', 'report {mobile} --output /sys/kernel', 2,
     ['cannot write the report into /sys/kernel']),
    ('bag', 'argument', 'bag repair ""', 2, ['must not be empty']),
    ('bag', 'argument', 'bag repair {loop}', 1, ['not a directory']),
    ('bag', 'argument', 'bag repair /dev/null', 1, ['not a directory']),
    ('bag', 'file', 'bag repair {mcap_fifo}', 1, ['not a regular file']),
    ('bag', 'file', 'bag repair {mcap_dir}', 1, ['not a regular file']),
    ('bag', 'file', 'bag repair {metadata_dir}', 1, ['not a regular file']),
    ('bag', 'file', 'bag repair {garbage}', 1, ['no complete message', 'nothing was changed']),
    ('bag', 'file', 'bag repair {random}', 1, ['no complete message', 'nothing was changed']),
    ('bag', 'file', 'bag repair {zero_mcap}', 1, ['no complete message']),
    ('bench', 'argument', 'bench kin --count ""', 2, ['--count']),
    ('bench', 'argument', 'bench kin --count 1.5', 2, ['--count']),
    ('bench', 'argument', 'bench kin --seed 4294967296', 2, ['--seed']),
    ('bench', 'argument', 'bench kin --count 10000000', 2, ['--count', '<= 100000']),
    ('bench', 'argument', 'bench kin --baseline-ik-count 1000000', 2, ['<= 10000']),
    ('bench', 'argument', 'bench arm --loop-duration 1e5', 2, ['--loop-duration', '<= 600']),
    ('bench', 'argument', 'bench tracking --plots ""', 2, ['must not be empty']),
    ('bench', 'argument', 'bench tracking --laws', 2, ['--laws']),
    ('bench', 'argument', 'bench arm --loop-duration nan', 2, ['--loop-duration']),
    ('bench', 'argument', 'bench recorder --rates 1 nan', 2, ['--rates']),
    ('bench', 'output', 'bench tracking --plots {fifo}/plots', 2, ['cannot create']),
    ('run', 'argument', 'run ""', 2, ['must not be empty']),
    ('run', 'argument', 'run {fifo}', 2, ['no scenario file']),
    ('run', 'argument', 'run {loop}', 2, ['no scenario file']),
    ('run', 'argument', 'run /dev/zero', 2, ['no scenario file']),
    ('run', 'argument', 'run {empty_dir}', 2, ['no scenario file']),
    ('run', 'argument', 'run ej9_1 --timeout 1e-300', 2, ['--timeout', '>= 1']),
    ('run', 'argument', 'run ej9_1 --discovery-timeout 0.5', 2, ['--discovery-timeout']),
    ('run', 'argument', 'run ej9_1 --duration 1e400', 2, ['--duration']),
    ('run', 'output', 'run ej9_1 --output-dir ""', 2, ['must not be empty']),
    ('run', 'output', 'run ej9_1 --output-dir /sys/robotica-run', 2, ['cannot create']),
    ('run', 'output', 'run ej9_1 --output-dir {fifo}/run', 2, ['Not a directory']),
    ('run', 'output', 'run ej9_1 --output-dir {loop}/run', 2, ['symbolic links']),
]


class _Hung(BaseException):
    """A case outlived the watchdog (BaseException: run_verb does not report it as a bug)."""


@pytest.fixture
def watchdog():
    """Fail a case that blocks (a FIFO opened for reading) instead of hanging the suite."""
    def expire(signum, frame):
        raise _Hung(f'no answer in {WATCHDOG} s')
    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, WATCHDOG)
    yield
    signal.setitimer(signal.ITIMER_REAL, 0.0)
    signal.signal(signal.SIGALRM, previous)


def test_the_campaign_is_new_and_covers_every_verb():
    old = {command for command, _ in BAD_INPUTS.VERB_CASES}
    assert not old & {command for _, _, command, _, _ in CASES}
    assert {verb for verb, *_ in CASES} == {'info', 'play', 'grade', 'report', 'bag', 'bench',
                                            'run'}
    assert len({command for _, _, command, _, _ in CASES}) == len(CASES)


@pytest.mark.parametrize('verb, kind, command, expected, words', CASES,
                         ids=[c[2] for c in CASES])
def test_a_bad_input_is_one_line(capsys, inputs, watchdog, verb, kind, command, expected,
                                 words):
    argv = [word.format(**inputs) for word in _split(command)]
    code, lines, out = _run_verb(capsys, argv)
    line = _assert_one_line(code, lines, expected)
    assert line.startswith(f'robotica {verb}'), line
    for word in words:
        assert word.format(**inputs) in line, line
    if expected == 2 and verb == 'grade':
        assert out == ''   # refused before the grading


def _split(command: str) -> list[str]:
    """Split a command at spaces; "" is an empty argument."""
    return ['' if word == '""' else word for word in command.split(' ')]


def test_a_rubric_parameter_error_names_the_file_once(capsys, inputs):
    number = list(RUBRICS).index('parameter zero')
    code, lines, _ = _run_verb(capsys, ['grade', inputs['mobile'], '--rubric',
                                        inputs[f'rubric{number}']])
    line = _assert_one_line(code, lines, 2)
    assert line.count(f'rubric{number}.yaml') == 1 and 'goal_tolerance' in line


def test_a_json_path_that_cannot_be_created_is_refused_before_grading(capsys, inputs):
    code, lines, out = _run_verb(capsys, ['grade', inputs['mobile'], '--json',
                                          inputs['root'] / 'none' / 'grades.json'])
    assert code == 2 and out == '' and not (inputs['root'] / 'none').exists()


# --- what is read must be what the bag holds ----------------------------------------------

def test_yaml_12_numbers_are_numbers_in_a_rubric_and_a_scenario(capsys, inputs, tmp_path):
    code, _, out = _run_verb(capsys, ['grade', inputs['mobile'], '--rubric',
                                      inputs['rubric_1e3']])
    assert code == 0 and 'PASS: 1/1' in out   # 0.001 <= 0.05 <= 1000 m
    scenario = tmp_path / 'scenario.yaml'
    scenario.write_text(BAD_INPUTS.BASE.replace('duration: 5.0', 'duration: 2e1'))
    assert load_scenario(str(scenario)).duration == 20.0
    scenario.write_text(BAD_INPUTS.BASE.replace('lookahead_distance: 0.5',
                                                'lookahead_distance: 1e400'))
    code, lines, _ = _run_verb(capsys, ['run', scenario, '--output-dir', tmp_path / 'run'])
    assert 'must be a finite number' in _assert_one_line(code, lines, 2)


def test_without_another_runs_metadata_the_repair_reads_the_data(capsys, tmp_path, inputs):
    bag = shutil.copytree(inputs['metadata_of_another_run'], tmp_path / 'bag')
    (bag / 'metadata.yaml').rename(tmp_path / 'metadata.yaml')
    assert _run_verb(capsys, ['bag', 'repair', bag])[0] == 0
    run = load_run(bag)   # the mobile run's data, no longer the arm's scenario (rosbags'
    assert run.scenario_name is None and run.counts == {   # writer kept none in the file)
        '/clock': 51, '/ground_truth/odom': 51, '/path': 1}


@pytest.mark.parametrize('bag, figure', [('arm_says_mobile', 'joint_positions.png'),
                                         ('mobile_says_arm', 'trajectory.png')])
def test_a_report_draws_what_the_bag_holds_whatever_its_scenario_says(capsys, inputs,
                                                                      tmp_path, bag, figure):
    code, lines, out = _run_verb(capsys, ['report', inputs[bag], '--output', tmp_path])
    assert code == 0 and not lines, lines
    assert (tmp_path / figure).is_file() and figure in out


def test_how_a_run_ended_is_shown_by_info_and_grade(capsys, tmp_path):
    bag = GRADE.write_run(tmp_path / 'bag', 0.05, run='scenario: straight\nduration: 60.0\n'
                          'nodes: [{name: simulator, command: robotica_sim/simulator}]\n')
    record_end(bag, 'completed')
    assert 'ended early' not in _run_verb(capsys, ['info', bag])[2]
    record_end(bag, 'interrupted (Ctrl-C or SIGTERM)')
    code, _, out = _run_verb(capsys, ['info', bag])
    assert code == 0 and 'duration 60 s (as run); ended early: interrupted' in out
    code, _, out = _run_verb(capsys, ['grade', bag])
    assert code == 0 and 'ended early: interrupted' in out


# --- bag repair leaves the bag as it found it when it cannot finish -------------------------

def _files(bag: Path) -> dict[str, int]:
    return {f.name: f.stat().st_size for f in bag.iterdir()}


def test_an_earlier_repairs_original_is_never_overwritten(capsys, tmp_path):
    bag = REPAIR.killed_bag(tmp_path / 'bag', flushed=20, unflushed=5, cut=7)
    mcap = next(bag.glob('*.mcap'))
    mcap.with_name(mcap.name + '.broken').write_bytes(b'the first original')
    before = _files(bag)
    code, lines, _ = _run_verb(capsys, ['bag', 'repair', bag])
    assert '.mcap.broken exists' in _assert_one_line(code, lines, 1)
    assert _files(bag) == before


@contextmanager
def _disk_of(limit: int):
    """Let this process write files of at most ``limit`` bytes, as a full disk would."""
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    previous = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)   # EFBIG, not death
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, previous)


def test_a_full_disk_during_repair_leaves_the_bag_unchanged(capsys, tmp_path):
    bag = REPAIR.killed_bag(tmp_path / 'bag', flushed=3000, unflushed=5, cut=7)
    before = _files(bag)
    with _disk_of(20_000):
        code, lines, _ = _run_verb(capsys, ['bag', 'repair', bag])
    assert 'File too large' in _assert_one_line(code, lines, 1)
    assert _files(bag) == before
    code, _, out = _run_verb(capsys, ['bag', 'repair', bag])
    assert code == 0 and '3000 messages of 1 topics' in out


def test_a_full_disk_while_the_report_is_drawn_is_exit_1(capsys, tmp_path, inputs):
    with _disk_of(2_000):
        code, lines, _ = _run_verb(capsys, ['report', inputs['mobile'], '--output',
                                            tmp_path / 'report'])
    assert 'File too large' in _assert_one_line(code, lines, 1)


@pytest.mark.parametrize('argv', [['info', '{mobile}'], ['info', '{mobile}', '--json'],
                                  ['grade', '{mobile}'], ['grade', '{mobile}', '--json', '-']])
def test_stdout_on_a_full_disk_or_a_closed_pipe_is_one_line(capsys, monkeypatch, inputs,
                                                            argv):
    argv = [word.format(**inputs) for word in argv]
    with open('/dev/full', 'w') as full:   # block-buffered, as stdout into a file or a pipe
        monkeypatch.setattr(sys, 'stdout', full)
        code = run_verb(argv)
        monkeypatch.undo()
    lines = capsys.readouterr().err.splitlines()
    assert 'stdout: No space left on device' in _assert_one_line(code, lines, 1)
    read, write = os.pipe()
    os.close(read)   # the reader is gone (| head) before the command writes
    with open(write, 'w') as pipe:
        monkeypatch.setattr(sys, 'stdout', pipe)
        code = run_verb(argv)
        monkeypatch.undo()
    assert code == 141 and capsys.readouterr().err == ''


# --- signals -------------------------------------------------------------------------------

def _loaded(pid: int, library: str) -> bool:
    """Return whether the process ``pid`` has mapped a shared library whose path holds it."""
    try:
        return library in Path(f'/proc/{pid}/maps').read_text()
    except OSError:
        return False


def _interrupt(argv: list, signum: int, when) -> tuple[int, list[str]]:
    """Start the command, send ``signum`` once ``when(pid)``; return its code and stderr lines."""
    env = {k: v for k, v in os.environ.items() if k != 'PYTHONUNBUFFERED'}
    process = subprocess.Popen([sys.executable, '-m', 'robotica_sim.cli.main',
                                *map(str, argv)], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 60.0
    while not when(process.pid) and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    if process.poll() is not None:
        pytest.fail(f'the command ended before the signal: {process.communicate()[1]}')
    process.send_signal(signum)
    _, err = process.communicate(timeout=60)
    return process.returncode, err.splitlines()


def _assert_interrupted(code: int, lines: list[str], verb: str) -> None:
    # After an interrupt that came while an extension module loaded, CPython may end the
    # process by SIGINT itself (-2; a shell shows 130 for both).
    assert code in (130, -signal.SIGINT), (code, lines)
    assert lines == [f'robotica {verb}: interrupted'], lines


@pytest.fixture(scope='module')
def long_bag(tmp_path_factory) -> Path:
    """Return a bag of 120 s at 10 Hz: a replay that outlasts any of these tests."""
    return BAD_INPUTS._write_bag(tmp_path_factory.mktemp('long') / 'bag', seconds=120.0)


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM])
def test_a_signal_while_the_command_starts_is_interrupted_not_a_traceback(long_bag, signum):
    # NumPy's extension is mapped while the verbs are imported: the start is under way.
    code, lines = _interrupt(['play', long_bag, '--wait', '30', '--quiet'], signum,
                             lambda pid: _loaded(pid, '_multiarray_umath'))
    _assert_interrupted(code, lines, 'play')


def test_sigint_while_matplotlib_loads_for_the_report(inputs):
    # Raised inside ft2font's initialisation, the interrupt was "ImportError: initialization
    # failed" (an internal error) and then a fatal error of the interpreter (-6).
    code, lines = _interrupt(['report', inputs['mobile'], '--output',
                              inputs['root'] / 'report_out'], signal.SIGINT,
                             lambda pid: _loaded(pid, 'ft2font'))
    _assert_interrupted(code, lines, 'report')


def test_sigint_while_repairing_leaves_the_bag_as_it_was(capsys, tmp_path):
    bag = REPAIR.killed_bag(tmp_path / 'bag', flushed=40_000, unflushed=5, cut=7)
    before = _files(bag)
    code, lines = _interrupt(['bag', 'repair', bag], signal.SIGINT,
                             lambda pid: any(bag.glob('*.repairing')))
    _assert_interrupted(code, lines, 'bag repair')
    assert _files(bag) == before   # no .broken, no half copy: a second repair loses nothing
    code, _, out = _run_verb(capsys, ['bag', 'repair', bag])
    assert code == 0 and '40000 messages of 1 topics' in out


@pytest.mark.slow
@pytest.mark.ros
def test_sigint_during_a_run_is_interrupted_and_the_bag_says_so(capsys, tmp_path, ros_domain):
    env = {**os.environ, 'PYTHONUNBUFFERED': '1'}
    process = subprocess.Popen(
        [sys.executable, '-m', 'robotica_sim.cli.main', 'run', 'ej9_1', '--duration', '60',
         '--output-dir', tmp_path / 'run'], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=env)
    for line in process.stderr:   # the simulation is under way: nodes call back into Python
        if 'running ej9_1' in line:
            break
    time.sleep(1.0)   # a second of simulation, so that the bag holds messages
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130, err
    assert 'interrupted; stopping the nodes' in err
    assert 'internal error' not in err and 'Traceback' not in err, err
    assert run_verb(['info', str(tmp_path / 'run' / 'bag')]) == 0
    assert 'ended early: interrupted (Ctrl-C or SIGTERM)' in capsys.readouterr().out
