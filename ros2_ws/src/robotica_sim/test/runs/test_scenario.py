"""Tests of robotica_sim.runs.scenario: loading and strict validation of scenario files."""
from pathlib import Path
import textwrap

from ament_index_python.packages import PackageNotFoundError
import pytest

from robotica_sim.runs import shipped as shipped_module
from robotica_sim.runs.scenario import load_scenario, resolve_scenario_path, ScenarioError

PACKAGE_DIR = Path(__file__).resolve().parents[2]
SHIPPED = PACKAGE_DIR / 'scenarios'
DEMO = SHIPPED / 'demo.yaml'


def write(tmp_path, text, name='bad.yaml'):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_demo_scenario():
    demo = load_scenario(str(DEMO))
    assert demo.name == 'demo'
    assert demo.source == str(DEMO)
    assert demo.duration == 32.0
    assert demo.seed == 1
    assert demo.pacing == 'lockstep'
    assert demo.step_period == 0.02
    assert demo.robot.type == 'differential'
    assert (demo.robot.wheel_radius, demo.robot.wheel_separation) == (0.1, 0.4)
    assert demo.robot.initial_pose == (0.0, 0.0, 0.0)
    assert demo.path.shape == 'rounded_rectangle'
    assert demo.path.frame_id == 'odom'
    assert demo.path.args == {'width': 4.0, 'height': 3.0, 'corner_radius': 0.8,
                              'spacing': 0.05}
    encoders = demo.sensors.encoders
    assert encoders.pulses_per_revolution * encoders.decoding == 4096
    assert demo.odometry.integration_method == 'exact_arc'
    assert demo.tracker.law == 'pure_pursuit'
    assert demo.tracker.gains == {'lookahead_distance': 0.5, 'desired_linear_velocity': 0.5,
                                  'max_angular_velocity': 1.5}


def test_types_of_loaded_values(tmp_path):
    # Integers in the file become floats where the field is a float; ints stay ints.
    path = write(tmp_path, """\
        duration: 10
        seed: 3
        robot:
          wheel_radius: 1
          initial_pose: [1, 2, 0]
        """, name='ints.yaml')
    loaded = load_scenario(str(path))
    assert type(loaded.duration) is float and loaded.duration == 10.0
    assert type(loaded.robot.wheel_radius) is float
    assert loaded.robot.initial_pose == (1.0, 2.0, 0.0)
    assert all(type(v) is float for v in loaded.robot.initial_pose)
    assert type(loaded.seed) is int and loaded.seed == 3


def test_name_defaults_to_the_file_stem(tmp_path):
    path = write(tmp_path, 'duration: 5.0\n', name='my_run.yaml')
    assert load_scenario(str(path)).name == 'my_run'


def test_free_form_sections_are_folded(tmp_path):
    path = write(tmp_path, """\
        path:
          shape: circle
          center: [1.0, 2.0]
          radius: 1.5
        tracker:
          lookahead_distance: 0.7
        """, name='circle.yaml')
    loaded = load_scenario(str(path))
    assert loaded.path.shape == 'circle'
    assert loaded.path.frame_id == 'odom'   # not given: the default
    assert loaded.path.args == {'center': [1.0, 2.0], 'radius': 1.5}
    assert loaded.tracker.law == 'pure_pursuit'
    assert loaded.tracker.gains == {'lookahead_distance': 0.7}


@pytest.mark.parametrize('text, keys', [
    ('colour: red\n', ['colour']),
    ('robot:\n  wheel_radiuss: 0.1\n', ['robot', 'wheel_radiuss']),
    ('sensors:\n  encoders:\n    resolution: 10\n', ['sensors.encoders', 'resolution']),
    ('duration: ten\n', ['duration']),
    ('duration: "10"\n', ['duration']),
    ('duration: true\n', ['duration']),
    ('robot:\n  wheel_radius: false\n', ['robot.wheel_radius']),
    ('seed: true\n', ['seed']),
    ('seed: 1.5\n', ['seed']),
    ('step_period: .nan\n', ['step_period']),
    ('duration: .inf\n', ['duration']),
    ('robot:\n  initial_pose: [0.0, .nan, 0.0]\n', ['robot.initial_pose[1]']),
    ('robot:\n  initial_pose: [0.0, 0.0]\n', ['robot.initial_pose']),
    ('robot:\n  initial_pose: [0.0, 0.0, 0.0, 0.0]\n', ['robot.initial_pose']),
    ('robot:\n  initial_pose: 0.0\n', ['robot.initial_pose']),
    ('robot:\n  initial_pose: [0.0, x, 0.0]\n', ['robot.initial_pose[1]']),
    ('pacing: fast\n', ['pacing']),
    ('duration: 0.0\n', ['duration']),
    ('duration: -1.0\n', ['duration']),
    ('step_period: 2.0\n', ['step_period']),
    ('robot:\n  wheel_radius: -0.1\n', ['robot.wheel_radius']),
    ('robot:\n  wheel_separation: 0\n', ['robot.wheel_separation']),
    ('robot: 3\n', ['robot']),
    ('path: [1, 2]\n', ['path']),
    ('tracker: pure_pursuit\n', ['tracker']),
    ('sensors:\n  encoders:\n    pulses_per_revolution: 0\n',
     ['sensors.encoders', 'pulses_per_revolution']),
    ('sensors:\n  encoders:\n    pulses_per_revolution: 4096.0\n',
     ['sensors.encoders.pulses_per_revolution']),
    ('sensors:\n  encoders:\n    decoding: 3\n', ['sensors.encoders', 'decoding']),
    ('sensors:\n  gps:\n    preset: glonass\n', ['sensors.gps.preset']),
    ('odometry:\n  heading_source: gyro\n', ['sensors.gyro.enabled']),
    ('odometry:\n  fuse_gps: true\n', ['sensors.gps.enabled']),
    ('robot:\n  type: hovercraft\n', ['robot.type']),
    ('name: 5\n', ['name']),
    ('odometry:\n  integration_method: 2\n', ['odometry.integration_method']),
    ('robot:\n  type: manipulator\narm:\n  model: scara\n', ['arm.model']),
    ('robot:\n  type: manipulator\narm:\n  model: two_link_arm\n  masses: [1.0]\n',
     ['arm.masses']),
    ('robot:\n  type: manipulator\narm:\n  masses: [1.0, 2.0]\n', ['arm.masses']),
    ('robot:\n  type: manipulator\ncontroller:\n  model_masses: [1.0, 2.0]\n',
     ['controller.model_masses']),
    ('robot:\n  type: manipulator\narm:\n  payload:\n    mass: -2.0\n', ['arm.payload']),
    ('robot:\n  type: manipulator\narm:\n  respect_limits: 1\n', ['arm.respect_limits']),
    ('robot:\n  type: manipulator\npath: {shape: circle}\n', ['path']),
    ('tracker:\n  law: pure_pursuit\ncontroller:\n  law: pid\n', ['controller']),
])
def test_bad_value_names_the_file_and_key(tmp_path, text, keys):
    path = write(tmp_path, text)
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    message = str(info.value)
    assert str(path) in message
    for key in keys:
        assert key in message


@pytest.mark.parametrize('text, expected', [
    ('robot: [1, 2\n', 'not valid YAML'),          # unbalanced bracket
    ('duration: {a: 1\n', 'not valid YAML'),
    ('robot:\n  a: 1\n b: 2\n', 'not valid YAML'),  # bad indentation
    ('- name: demo\n- duration: 3.0\n', 'mapping'),  # a list, not a mapping
    ('just a string\n', 'mapping'),
    ('', 'mapping'),                                # empty file: None
])
def test_not_a_scenario_mapping(tmp_path, text, expected):
    path = write(tmp_path, text)
    with pytest.raises(ScenarioError, match=expected) as info:
        load_scenario(str(path))
    assert str(path) in str(info.value)


def test_scenario_error_is_a_value_error():
    assert issubclass(ScenarioError, ValueError)


def test_missing_file(tmp_path):
    missing = tmp_path / 'no_such_scenario.yaml'
    with pytest.raises(ScenarioError, match='no_such_scenario'):
        load_scenario(str(missing))


def test_a_directory_is_not_a_scenario(tmp_path):
    with pytest.raises(ScenarioError, match='no scenario file'):
        load_scenario(str(tmp_path))


def test_unknown_shipped_name():
    with pytest.raises(ScenarioError, match='no_such_scenario_xyz'):
        resolve_scenario_path('no_such_scenario_xyz')


def test_shipped_names_are_resolved_and_listed(tmp_path, monkeypatch):
    # A fake share directory stands for the installed package.
    (tmp_path / 'scenarios').mkdir()
    shipped = write(tmp_path / 'scenarios', 'duration: 3.0\n', name='alpha.yaml')
    write(tmp_path / 'scenarios', 'duration: 4.0\n', name='beta.yaml')
    monkeypatch.setattr(shipped_module, 'get_package_share_directory',
                        lambda package: str(tmp_path))
    assert resolve_scenario_path('alpha') == shipped
    assert resolve_scenario_path('alpha.yaml') == shipped
    assert load_scenario('alpha').duration == 3.0
    with pytest.raises(ScenarioError, match='alpha, beta'):
        resolve_scenario_path('gamma')


def test_without_an_installed_package_nothing_is_shipped(monkeypatch):
    def not_found(package):
        raise PackageNotFoundError(package)

    monkeypatch.setattr(shipped_module, 'get_package_share_directory', not_found)
    with pytest.raises(ScenarioError, match='none found'):
        resolve_scenario_path('demo_that_does_not_exist')


def test_a_path_is_taken_before_a_shipped_name(tmp_path):
    path = write(tmp_path, 'duration: 7.0\n', name='local.yaml')
    assert resolve_scenario_path(str(path)) == path


def test_unknown_keys_of_mixed_types(tmp_path):
    path = write(tmp_path, 'robot:\n  1: a\n  colour: red\n')
    with pytest.raises(ScenarioError, match='robot'):
        load_scenario(str(path))


def test_shipped_arm_scenarios_load():
    for name, payload, ki in (('ej8_1', 0.0, None), ('ej8_2', 0.0, None), ('ej8_3', 0.0, 100.0),
                              ('ej8_4', 2.0, None), ('ej8_5', 2.0, 25.0)):
        scenario = load_scenario(str(SHIPPED / f'{name}.yaml'))
        assert scenario.is_manipulator and scenario.name == name
        assert scenario.arm.model == 'two_link_arm'
        assert scenario.arm.masses == (2.0, 1.0) and scenario.arm.lengths == (3.0, 1.0)
        assert scenario.arm.payload.mass == payload
        assert scenario.controller.gains.get('ki') == ki
        assert scenario.controller.model_masses == (() if name == 'ej8_1' else (2.1, 0.9))
    for name, viscous in (('puma_computed_torque', ()),
                          ('puma_computed_torque_friction', (0.1, 0.0, 0.0, 0.0, 0.0, 0.0))):
        scenario = load_scenario(str(SHIPPED / f'{name}.yaml'))
        assert scenario.arm.model == 'puma560' and scenario.arm.unmodelled_viscous == viscous
        assert scenario.controller.gains == {'kp': 25.0, 'kv': 10.0}
