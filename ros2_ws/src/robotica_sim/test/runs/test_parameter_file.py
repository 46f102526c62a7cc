"""The parameter file of declared parameters, read back by an independent YAML parser."""
import math

from robotica_sim.runs.parameter_file import DeclaredParameter, parameter_file
import yaml

PARAMETERS = [
    DeclaredParameter('wheel_radius', 0.1, 'Wheel radius c [m]', 0.001, 10.0, read_only=True),
    DeclaredParameter('gain', 1.0, 'A float whose value is whole'),
    DeclaredParameter('big', 1e6, 'A large float', -1e6, 1e6),
    DeclaredParameter('port', 8765, 'TCP port\n0: any free port', 0, 65535, step=1),
    DeclaredParameter('enabled', False, 'A flag'),
    DeclaredParameter('frame_id', 'odom', 'Frame'),
    DeclaredParameter('answer', 'yes', 'A string YAML 1.1 would read as a bool'),
    DeclaredParameter('number_text', '1.0', 'A string that looks like a number'),
    DeclaredParameter('colon', 'a: b # c', 'A string with YAML syntax in it'),
    DeclaredParameter('empty', '', 'An empty string'),
    DeclaredParameter('topics', [''], 'A list of one empty string'),
    DeclaredParameter('masses', [2.0, 1.0], 'A list of floats'),
    DeclaredParameter('counts', [1, 2, 3], 'A list of integers'),
    DeclaredParameter('names', ['joint_1', 'joint_2'], 'A list of strings'),
    DeclaredParameter('sine.amplitude', [0.5], 'A dotted name'),
    DeclaredParameter('dh_table', None, 'Unset: no default', type_name='double array'),
]


def _file() -> str:
    return parameter_file('odometry', PARAMETERS, header='Generated.\nUse: --params-file')


def test_yaml_reads_back_the_values_with_their_types():
    data = yaml.safe_load(_file())
    expected = {p.name: p.value for p in PARAMETERS if p.value is not None}
    assert data == {'odometry': {'ros__parameters': expected}}
    values = data['odometry']['ros__parameters']
    # rclpy refuses an integer for a double parameter and a number for a string one.
    assert isinstance(values['gain'], float) and isinstance(values['big'], float)
    assert isinstance(values['port'], int) and values['enabled'] is False
    assert all(isinstance(values[n], str) for n in ('answer', 'number_text', 'empty'))
    assert all(isinstance(m, float) for m in values['masses'])
    assert math.isclose(values['big'], 1e6)


def test_every_parameter_follows_its_description_and_range():
    lines = _file().splitlines()
    for parameter in PARAMETERS:
        entry = next(i for i, line in enumerate(lines)
                     if line.lstrip('# ').startswith(f'{parameter.name}:'))
        limits = ([f'range [{parameter.low!r}, {parameter.high!r}]'
                   + (f', step {parameter.step!r}' if parameter.step else '')]
                  if parameter.low is not None else [])
        tail = '; '.join(limits + ['read-only'] * parameter.read_only)
        expected = [f'    # {d}' for d in parameter.description.splitlines() + [tail] if d]
        assert lines[entry - len(expected):entry] == expected, parameter.name
    assert '    # range [0, 65535], step 1' in lines
    assert '    # range [0.001, 10.0]; read-only' in lines


def test_an_unset_parameter_is_a_comment_with_its_type():
    assert '    # dh_table: <double array, unset by default>' in _file().splitlines()


def test_the_header_is_comments_before_the_node():
    lines = _file().splitlines()
    assert lines[:4] == ['# Generated.', '# Use: --params-file', 'odometry:',
                         '  ros__parameters:']
