"""
A scenario value a node would refuse at start-up is refused by the plan, before any process.

Each case is a value that ``robotica run`` used to accept and a node then refused after the
other processes had started (exit 1). The plan now runs each node's own start-up check (the
core function the node builds its model with, the ranges it declares), so ``robotica run``
answers with one line naming the scenario key and the allowed range, exit code 2, and starts
nothing. The node tests (``test/nodes``) check that the nodes still refuse the same values.
"""
import pytest
from robotica_ctrl.joint_control.control_laws import make_joint_law
from robotica_ctrl.mobile.tracking_laws import check_gains, TRACKER_PARAMETERS
from robotica_ctrl.trajectory.joint_reference import reference_samples
from robotica_kin.mobile.vehicles import GEOMETRY_PARAMETERS
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.robots import puma560
from robotica_sim.cli.main import run_verb
from robotica_sim.runs.plan import plan_run
from robotica_sim.runs.scenario import load_scenario, resolve_scenario_path, ScenarioError
from robotica_sim.runs.supervisor import ProcessSupervisor
from robotica_sim.sensors.compass import compass_params
from robotica_sim.sensors.encoder import encoder_params
from robotica_sim.sensors.gps import gps_configuration
from robotica_sim.sensors.gyro import gyro_params
from robotica_sim.simulation.arm import arm_simulation
from robotica_sim.simulation.vehicle import vehicle_simulation
import yaml


def _variant(shipped: str, changes: dict) -> str:
    """Return the text of a shipped scenario with ``changes`` (dotted key -> value) made."""
    data = yaml.safe_load(resolve_scenario_path(shipped).read_text())
    for dotted, value in changes.items():
        *sections, key = dotted.split('.')
        parent = data
        for name in sections:
            parent = parent.setdefault(name, {})
        parent[key] = value
    return yaml.safe_dump(data)


# (case, shipped scenario, changes, the words of the one line: the key and what it must be)
CASES = [
    # joint_trajectory_publisher (robotica_ctrl.trajectory.joint_reference)
    ('sine period 0', 'ej8_2', {'reference.period': 0},
     'reference.period must be > 0 s, got [0.0]'),
    ('unknown generator', 'ej8_2', {'reference.generator': 'spline'},
     "reference.generator must be one of ('sine', 'pol3', 'pol5', 'parab'), got 'spline'"),
    ('sample period of 100 s', 'ej8_2', {'reference.sample_period': 100},
     'reference.sample_period must be in [0.0001, 10], got 100.0'),
    ('reference of 2e7 points', 'ej8_2', {'duration': 2000.0, 'reference.sample_period': 1e-4},
     'duration of 2001 s gives about 2e+07 points'),
    ('overflowing sine', 'ej8_2', {'reference.period': 1e-300},
     'reference: the sine trajectory is not finite'),
    ('via points of the wrong size', 'ej8_2', {'reference': {
        'generator': 'pol3', 'positions': [0, 1, 2], 'segment_durations': [1]}},
     'reference.positions must hold points x 2 values'),
    ('parab accelerations of 3 joints', 'ej8_2', {'reference': {
        'generator': 'parab', 'positions': [0, 0, 1, 1], 'segment_durations': [1],
        'acceleration': [1, 1, 1]}}, 'reference.acceleration must hold 1 or 2 values, got 3'),
    # joint_controller (robotica_ctrl.joint_control.control_laws)
    ('unknown joint law', 'ej8_2', {'controller.law': 'lqr'},
     "controller.law must be one of ('pid', 'computed_torque', 'adaptive_computed_torque', "
     "'slotine_li', 'model_reference', 'learning'), got 'lqr'"),
    ('negative kp', 'ej8_2', {'controller.kp': -1}, 'controller.kp must be >= 0, got -1.0'),
    ('kp of 3 joints', 'ej8_2', {'controller.kp': [1, 2, 3]},
     'controller.kp must be a scalar or have shape (2,)'),
    ('unknown joint gain', 'ej8_2', {'controller.kpp': 1}, "computed_torque has no gain ['kpp']"),
    ('negative filter time', 'ej8_2', {'controller.law': 'pid',
                                       'controller.derivative_time_constant': -1},
     'controller.derivative_time_constant must be >= 0'),
    # joint_controller's task-space laws (robotica_ctrl.joint_control.task_laws)
    ('force law without a surface', 'ej8_11', {'arm.environment': {}},
     'controller.law hybrid presses on a surface: give arm.environment'),
    ('task axes of 4 numbers', 'ej8_10', {'controller.task.axes': [1, 0, 0, 1]},
     'controller.task.axes must be 3, 6 or 9 numbers'),
    ('task axes not orthonormal', 'ej8_10', {'controller.task.axes': [1, 0, 0, 1, 1, 0]},
     'controller.task.axes rotation must have orthonormal columns'),
    ('unknown task key', 'ej8_10', {'controller.task.stiffness': 3},
     'unknown key controller.task.stiffness; known: '),
    ('negative stiffness gain', 'ej8_10', {'controller.kp': [-10, 10]},
     'controller.kp must be'),
    ('force rise time negative', 'ej8_11', {'controller.task.force.time_constant': [-1, 0]},
     'controller.task.force.time_constant must be >= 0 s'),
    ('cartesian goal of 3 numbers', 'puma_operational_space',
     {'controller.cartesian.goal': [0.6, 0.1, 0.1]}, 'controller.cartesian.goal must be 6'),
    ('learning mu that diverges', 'ej8_9', {'controller.mu': 300},
     'controller.mu = [300.0, 300.0] makes the learning diverge'),
    ('trial longer than the run', 'ej8_9', {'controller.trial_period': 1000},
     'controller.trial_period must be 0 (one trial) or in [step_period, duration] s'),
    # planner (robotica_ctrl.planning.planners)
    ('planner goal of 3 numbers', 'room_astar', {'planner.goal': [1, 2, 3]},
     'planner.goal must be (x, y) [m]'),
    ('unknown planner method', 'room_astar', {'planner.method': 'rrt'},
     "planner.method must be one of ('astar',"),
    ('unknown planner option', 'room_astar', {'planner.horizon': 3},
     'unknown key planner.horizon; known: '),
    ('twelve neighbours', 'room_astar', {'planner.neighbours': 12},
     'planner.neighbours must be 8 or 16, got 12'),
    ('negative robot radius', 'room_astar', {'planner.robot_radius': -1},
     'planner.robot_radius must be in [0, 100]'),
    ('planner and a path', 'room_astar', {'path': {'shape': 'straight_line'}},
     'sections planner and path'),
    # the parking planner (robotica_ctrl.planning.parking.parking_search)
    ('parking with a goal', 'street_parking', {'planner.goal': [1, 2]},
     'planner.goal: the parking method parks in the space its pass finds; give no goal'),
    ('parking sonar index out of range', 'street_parking', {'planner.sonar': 1},
     'planner.sonar must be the index of one of the 1 sonar mounts (0 to 0), got 1'),
    ('parking without a sonar', 'street_parking', {'sensors.sonar.enabled': False},
     'planner: the parking method reads a side sonar: enable sensors.sonar'),
    ('parking sonar looking ahead', 'street_parking', {'sensors.sonar.mounts': [3.4, 0, 0]},
     'planner: sensor_pose must look sideways'),
    ('parking mode unknown', 'street_parking', {'planner.parking.execution': 'fast'},
     "planner.parking.execution must be one of ('geometric', 'progressive')"),
    ('parking width zero', 'street_parking', {'robot.footprint_polygon': [0, 0, 1, 0, 1, 0]},
     'planner.parking.c1 must be in'),
    ('sonar index without parking', 'room_astar', {'planner.sonar': 0},
     'planner.sonar is for the parking method only'),
    ('footprint polygon odd', 'street_parking', {'robot.footprint_polygon': [0, 0, 1, 0, 1]},
     'robot: footprint.polygon must be [x1, y1, x2, y2, ...] with 3 vertices or more'),
    # arm_simulator's environment and the F/T sensor
    ('surface normal zero', 'ej8_10', {'arm.environment.normal': [0, 0, 0]},
     'arm.environment.normal must not be zero'),
    ('surface stiffness negative', 'ej8_10', {'arm.environment.stiffness': -1},
     'arm.environment.stiffness must be in [0, 1e+09]'),
    ('unknown F/T preset', 'ej8_10', {'arm.ft_sensor.preset': 'piezo'},
     'arm.ft_sensor.preset must be one of'),
    # arm_simulator (robotica_sim.simulation.arm)
    ('tau_max zero', 'ej8_2', {'arm.tau_max': [0]}, 'arm.tau_max must be > 0 N m per joint'),
    ('tau_max negative', 'ej8_2', {'arm.tau_max': [-1.0, 2.0]},
     'arm.tau_max must be > 0 N m per joint'),
    ('tau_max of 3 joints', 'ej8_2', {'arm.tau_max': [1, 2, 3]},
     'arm.tau_max needs 1 or 2 values, got 3'),
    ('negative unmodelled friction', 'ej8_2', {'arm.unmodelled_viscous': [-0.1]},
     'arm.unmodelled_viscous must be finite and >= 0'),
    ('initial positions of 3 joints', 'ej8_2', {'arm.initial_positions': [0, 0, 0]},
     'arm.initial_positions must have shape (2,)'),
    ('payload of 20 t', 'ej8_2', {'arm.payload': {'mass': 20000, 'com': [0, 0, 0], 'time': 1}},
     'arm.payload.mass must be in [0, 10000], got 20000.0'),
    ('a massless link', 'ej8_2', {'arm.masses': [2.0, 0.0]},
     'arm: the mass matrix M(q0) is singular'),
    ('arm step of 0.5 s', 'ej8_2', {'step_period': 0.5},
     'step_period must be in (0, 0.1] s, got 0.5'),
    # path_tracker (robotica_ctrl.mobile.tracking_laws)
    ('unknown pose source', 'demo', {'tracker.pose_source': 'bogus'},
     "tracker.pose_source must be one of ('odom', 'ground_truth'), got 'bogus'"),
    ('zero cross-track bound', 'demo', {'tracker.max_cross_track': 0},
     'tracker.max_cross_track must be in [0.001, 1e+06], got 0.0'),
    ('look-ahead bounds crossed', 'demo', {'tracker': {
        'law': 'adaptive_pure_pursuit', 'min_lookahead': 3.0, 'max_lookahead': 1.0}},
     'tracker: need 0 < minimum <= maximum [m], got 3.0, 1.0'),
    ('fractional horizon', 'demo', {'tracker': {'law': 'gpc', 'n1': 2.5}},
     'tracker.n1 must be an integer, got 2.5'),
    ('unknown frenet variant', 'demo', {'tracker': {'law': 'frenet', 'variant': 'bogus'}},
     "tracker.variant must be one of ('linear', 'nonlinear'), got 'bogus'"),
    ('a list for a number', 'demo', {'tracker.lookahead_distance': [0.5, 1.0]},
     'tracker.lookahead_distance must be one number, got [0.5, 1.0]'),
    ('a number for a profile', 'demo', {'tracker': {'law': 'open_loop', 'times': 1.0}},
     'tracker.times must be a list of numbers, got 1.0'),
    ('a path of one distinct point', 'demo', {'path': {
        'shape': 'unicycle_trajectory', 'start': [0, 0, 0], 'segments': [[1, 0, 1e-10]],
        'step': 1e-11}}, 'path: a path needs at least 2 distinct points, got 1'),
    # simulator (robotica_kin.mobile.vehicles, robotica_sim.simulation.vehicle)
    ('wheelbase of 200 m', 'demo', {'robot.type': 'bicycle', 'robot.wheelbase': 200.0},
     'robot.wheelbase must be in [0.001, 100], got 200.0'),
    ('steering limit next to pi/2', 'demo', {'robot.type': 'bicycle',
                                             'robot.max_steering_angle': 1.5705},
     'robot.max_steering_angle must be in [0.001, 1.57], got 1.5705'),
    ('slip of 0.95', 'demo', {'robot.longitudinal_slip': 0.95},
     'robot.longitudinal_slip must be in [0, 0.9], got 0.95'),
    ('traction lag of 100 s', 'demo', {'robot.traction_time_constant': 100.0},
     'robot.traction_time_constant must be in [0, 60], got 100.0'),
    ('icr scale of 20', 'demo', {'robot.type': 'skid_steer', 'robot.icr_scale': 20.0},
     'robot.icr_scale must be in [1, 10], got 20.0'),
    ('start 2000 km away', 'demo', {'robot.initial_pose': [2e6, 0, 0]},
     'robot.initial_pose[0] (x) must be in [-1e+06, 1e+06], got 2000000.0'),
    ('wheel of 20 m', 'demo', {'robot.wheel_radius': 20.0},
     'robot.wheel_radius must be in [0.001, 10], got 20.0'),
    # odometry (robotica_kin.mobile.odometry_fusion.ODOMETRY_PARAMETERS)
    ('nominal wheel of 10.8 m', 'demo', {'robot.wheel_radius': 9.0,
                                         'odometry.wheel_radius_error': 0.2},
     'robot.wheel_radius x (1 + odometry.wheel_radius_error) must be in [0.001, 10], got 10.'),
    ('origin 200 km high, no GPS', 'demo', {'sensors.gps.origin': [37.0, -6.0, 2e5]},
     'sensors.gps.origin[2] (altitude) must be in [-10000, 100000], got 200000.0'),
    # encoder_emulator (robotica_sim.sensors.encoder)
    ('fractional counts per turn', 'demo', {'sensors.encoders': {
        'pulses_per_revolution': 1023, 'decoding': 1, 'gear_ratio': 1.5}},
     'sensors.encoders: pulses_per_revolution x decoding x gear_ratio must be an integer'),
    ('2e7 pulses', 'demo', {'sensors.encoders.pulses_per_revolution': 20_000_000},
     'sensors.encoders.pulses_per_revolution must be in [1, 10000000], got 20000000'),
    ('gear ratio of 1e5', 'demo', {'sensors.encoders.gear_ratio': 1e5},
     'sensors.encoders.gear_ratio must be in [0.001, 10000], got 100000.0'),
    # compass_emulator (robotica_sim.sensors.compass)
    ('compass tilt of 0.6 rad', 'demo', {'sensors.compass': {'enabled': True,
                                                             'tilt_error': 0.6}},
     'sensors.compass.tilt_error must be in [-0.5, 0.5], got 0.6'),
    ('compass noise of 1 mT', 'demo', {'sensors.compass': {'enabled': True,
                                                           'noise_stddev': 1e-3}},
     'sensors.compass.noise_stddev must be in [0, 0.0001], got 0.001'),
    # gps_emulator (robotica_sim.sensors.gps)
    ('origin 200 km high', 'demo', {'sensors.gps': {'enabled': True,
                                                    'origin': [37.0, -6.0, 2e5]}},
     'sensors.gps.origin[2] (altitude) must be in [-10000, 100000], got 200000.0'),
    ('GPS white part beyond the total', 'demo', {'sensors.gps': {'enabled': True,
                                                                 'preset': 'rtk',
                                                                 'white_stddev': 0.1}},
     'sensors.gps.white_stddev must be in [0, min(horizontal_stddev, vertical_stddev)]'),
    ('GPS outage shorter than a fix', 'demo', {'sensors.gps': {
        'enabled': True, 'update_rate': 1.0, 'dropout': {'mean_duration': 0.5}}},
     'sensors.gps.dropout.mean_duration must be >= one fix period'),
    # gyro_emulator (robotica_sim.sensors.gyro)
    ('gyro scale factor of 60 %', 'demo', {'sensors.gyro': {'enabled': True,
                                                            'scale_factor_error': 0.6}},
     'sensors.gyro.scale_factor_error must be in [-0.5, 0.5], got 0.6'),
]


@pytest.fixture
def no_process(monkeypatch):
    """Record every node process a run would start (none must be)."""
    started = []
    monkeypatch.setattr(ProcessSupervisor, 'start',
                        lambda self, name, argv: started.append(name))
    return started


def test_a_planner_needs_a_world(tmp_path):
    data = yaml.safe_load(resolve_scenario_path('room_astar').read_text())
    del data['world']
    (tmp_path / 'no_world.yaml').write_text(yaml.safe_dump(data))
    with pytest.raises(ScenarioError, match='section planner needs a world: section'):
        load_scenario(str(tmp_path / 'no_world.yaml'))


def test_the_shipped_bases_are_valid(tmp_path):
    for shipped in ('demo', 'ej8_2'):
        (tmp_path / f'{shipped}.yaml').write_text(_variant(shipped, {}))
        assert plan_run(load_scenario(str(tmp_path / f'{shipped}.yaml')))


def test_every_node_family_has_cases():
    sections = {words.split('.')[0].split(':')[0].split(' ')[0] for _, _, _, words in CASES}
    assert {'reference', 'controller', 'arm', 'step_period', 'tracker', 'path', 'robot',
            'sensors'} <= sections
    assert len({case for case, _, _, _ in CASES}) == len(CASES)


@pytest.mark.parametrize('case, shipped, changes, words', CASES, ids=[c[0] for c in CASES])
def test_run_refuses_in_one_line_before_any_process(tmp_path, capsys, no_process, case, shipped,
                                                    changes, words):
    scenario = tmp_path / 'scenario.yaml'
    scenario.write_text(_variant(shipped, changes))
    out = tmp_path / 'run'
    code = run_verb(['run', str(scenario), '--output-dir', str(out), '--quiet'])
    lines = capsys.readouterr().err.splitlines()
    assert code == 2, lines
    assert len(lines) == 1, lines
    assert lines[0].startswith(f'robotica run: error: {scenario}: '), lines[0]
    assert words in lines[0]
    assert 'Traceback' not in lines[0]
    assert no_process == [] and not out.exists()


# The same value through the function the node builds its model with: what the node raises
# at start-up (test/nodes and robotica_ctrl's test/nodes start the nodes with such values).
@pytest.mark.parametrize('check, name', [
    (lambda: reference_samples({'joint_names': ['a'], 'sine.period': [0.0]}), 'sine.period'),
    (lambda: reference_samples({'joint_names': ['a'], 'generator': 'spline'}), 'generator'),
    (lambda: make_joint_law('pid', puma560(), {'kp': [-1.0]}), 'kp'),
    (lambda: make_joint_law('computed_torque', puma560(), {'kv': [1.0, 2.0]}), 'kv'),
    (lambda: make_joint_law('lqr', puma560(), {}), 'law'),
    (lambda: arm_simulation(puma560(), {'tau_max': [0.0]}, 1e-3), 'tau_max'),
    (lambda: arm_simulation(puma560(), {'tau_max': [1.0, 2.0]}, 1e-3), 'tau_max'),
    (lambda: TRACKER_PARAMETERS['pose_source'].check('pose_source', 'bogus'), 'pose_source'),
    (lambda: check_gains('gpc', {'n1': 2.5}), 'n1'),
    (lambda: vehicle_simulation({'longitudinal_slip': 0.95}, 0.02), 'longitudinal_slip'),
    (lambda: vehicle_simulation({'vehicle.wheelbase': 200.0}, 0.02), 'vehicle.wheelbase'),
    (lambda: encoder_params({'gear_ratio': 2e4}), 'gear_ratio'),
    (lambda: compass_params({'tilt_error': 0.6}), 'tilt_error'),
    (lambda: gps_configuration({'origin.altitude': 2e5}), 'origin.altitude'),
    (lambda: gps_configuration({'latency': -1.0}), 'latency'),
    (lambda: gyro_params({'bias_correlation_time': 0.0}), 'bias_correlation_time'),
])
def test_the_node_check_names_its_parameter(check, name):
    with pytest.raises(ParameterError) as info:
        check()
    assert info.value.name == name


def test_the_tracker_and_the_simulator_share_the_wheelbase_range():
    tracker, simulator = TRACKER_PARAMETERS['wheelbase'], GEOMETRY_PARAMETERS['wheelbase']
    assert (tracker.low, tracker.high) == (simulator.low, simulator.high)


def test_plan_run_raises_scenario_error(tmp_path):
    path = tmp_path / 'arm.yaml'
    path.write_text(_variant('ej8_2', {'reference.period': 0}))
    with pytest.raises(ScenarioError, match=r'reference\.period must be > 0 s'):
        plan_run(load_scenario(str(path)))
