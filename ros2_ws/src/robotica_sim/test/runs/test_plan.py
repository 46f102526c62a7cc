"""Tests of robotica_sim.runs.plan: the nodes, parameters and topics of a scenario's run."""
import math
from pathlib import Path
import textwrap

import numpy as np
import pytest
from robotica_kin.robots import two_link_arm
from robotica_sim.runs.plan import (ARM_RECORDED_TOPICS, CONTROLLER_STATE_TOPIC, path_points,
                                    plan_run, RECORDED_TOPICS, recorded_topics, STATUS_TOPIC,
                                    TRACKING_ERROR_TOPIC, TRAJECTORY_TOPIC)
from robotica_sim.runs.scenario import load_scenario, PathSpec, Scenario, ScenarioError

SHIPPED = Path(__file__).resolve().parents[2] / 'scenarios'
DEMO = SHIPPED / 'demo.yaml'
START_ORDER = ['path_publisher', 'encoder_emulator', 'odometry', 'path_tracker',
               'state_publisher', 'markers', 'simulator']


def write(tmp_path, text, name='scenario.yaml'):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def by_name(nodes):
    return {node.name: node for node in nodes}


@pytest.fixture(scope='module')
def demo():
    return load_scenario(str(DEMO))


@pytest.fixture(scope='module')
def demo_plan(demo):
    return plan_run(demo)


def test_nodes_in_start_order(demo_plan):
    assert [node.name for node in demo_plan] == START_ORDER
    assert [(node.package, node.executable) for node in demo_plan] == [
        ('robotica_ctrl', 'path_publisher'),
        ('robotica_sim', 'encoder_emulator'),
        ('robotica_sim', 'odometry'),
        ('robotica_ctrl', 'path_tracker'),
        ('robotica_kin', 'state_publisher'),
        ('robotica_sim', 'markers'),
        ('robotica_sim', 'simulator'),
    ]


def test_demo_parameters(demo, demo_plan):
    nodes = by_name(demo_plan)
    simulator, odometry = nodes['simulator'].parameters, nodes['odometry'].parameters
    assert simulator['vehicle.type'] == 'differential'
    assert simulator['vehicle.wheel_radius'] == odometry['wheel_radius'] == 0.1
    assert simulator['vehicle.track'] == odometry['wheel_separation'] == 0.4
    for params in (simulator, odometry):
        assert (params['initial_pose.x'], params['initial_pose.y'],
                params['initial_pose.theta']) == (0.0, 0.0, 0.0)
    assert simulator['end_time'] == demo.duration == 32.0
    assert simulator['autostart'] is False
    assert simulator['step_period'] == 0.02
    assert simulator['pacing'] == 'lockstep'
    assert odometry['integration_method'] == 'exact_arc'
    assert odometry['odom_frame_id'] == 'odom'
    assert nodes['path_publisher'].parameters['frame_id'] == 'odom'
    assert nodes['encoder_emulator'].parameters == {
        'pulses_per_revolution': 1024, 'decoding': 4, 'gear_ratio': 1.0,
        'missed_count_probability': 0.0, 'seed': demo.seed * 10 + 1,
        'left_wheel_joint': 'left_wheel_joint', 'right_wheel_joint': 'right_wheel_joint'}
    tracker = nodes['path_tracker'].parameters
    assert tracker == {'law': 'pure_pursuit',
                       'pure_pursuit.lookahead_distance': 0.5,
                       'pure_pursuit.desired_linear_velocity': 0.5,
                       'pure_pursuit.max_angular_velocity': 1.5,
                       'command_type': 'twist', 'wheelbase': 0.5,
                       'enable_stamped_cmd_vel': False, 'wait_for_path': True}
    assert all(type(v) is float for k, v in tracker.items()
               if k not in ('law', 'command_type', 'enable_stamped_cmd_vel', 'wait_for_path'))
    assert simulator['enable_stamped_cmd_vel'] is False   # one value for both ends of cmd_vel


def test_parameter_values_are_plain_ros_types(demo_plan):
    # rclpy parameters: bool, int, float, str or a homogeneous list of them (no numpy scalars).
    for node in demo_plan:
        for name, value in node.parameters.items():
            assert type(value) in (bool, int, float, str, list), (node.name, name, value)
            if isinstance(value, list):
                assert value and len({type(v) for v in value}) == 1, (node.name, name)
                assert type(value[0]) in (float, str), (node.name, name)


def test_robot_and_initial_pose_reach_simulator_and_odometry(tmp_path):
    path = write(tmp_path, """\
        duration: 12.5
        step_period: 0.05
        pacing: realtime
        robot:
          wheel_radius: 0.05
          wheel_separation: 0.3
          initial_pose: [1.0, -2.0, 0.5]
        odometry:
          integration_method: midpoint
        path:
          shape: circle
          frame_id: map
          center: [1.0, 0.0]
          radius: 1.0
        sensors:
          encoders:
            pulses_per_revolution: 250
            decoding: 2
        tracker:
          lookahead_distance: 1
        """)
    nodes = by_name(plan_run(load_scenario(str(path))))
    simulator, odometry = nodes['simulator'].parameters, nodes['odometry'].parameters
    assert simulator['vehicle.wheel_radius'] == odometry['wheel_radius'] == 0.05
    assert simulator['vehicle.track'] == odometry['wheel_separation'] == 0.3
    for params in (simulator, odometry):
        assert params['initial_pose.x'] == 1.0
        assert params['initial_pose.y'] == -2.0
        assert params['initial_pose.theta'] == 0.5
    assert simulator['end_time'] == 12.5
    assert simulator['step_period'] == 0.05
    assert simulator['pacing'] == 'realtime'
    assert simulator['autostart'] is False
    assert odometry['integration_method'] == 'midpoint'
    assert odometry['odom_frame_id'] == 'map'
    assert nodes['path_publisher'].parameters['frame_id'] == 'map'
    assert nodes['encoder_emulator'].parameters['pulses_per_revolution'] == 250
    assert nodes['encoder_emulator'].parameters['decoding'] == 2
    gain = nodes['path_tracker'].parameters['pure_pursuit.lookahead_distance']
    assert type(gain) is float and gain == 1.0   # an integer gain is passed as a float


def test_demo_path_is_the_rounded_rectangle(demo_plan):
    params = by_name(demo_plan)['path_publisher'].parameters
    x, y = params['x'], params['y']
    assert len(x) == len(y) > 2
    assert (x[0], y[0]) == (0.0, 0.0)
    assert (x[-1], y[-1]) == (0.0, 0.0)       # closed
    steps = [math.hypot(x[i + 1] - x[i], y[i + 1] - y[i]) for i in range(len(x) - 1)]
    assert max(steps) <= 0.05 * (1.0 + 1e-12)   # spacing
    assert min(steps) > 0.0
    # x in [-r, W - r], y in [0, H] (the shape starts at the beginning of the bottom straight).
    assert min(x) == pytest.approx(-0.8, abs=1e-12) and max(x) == pytest.approx(3.2, abs=1e-12)
    assert min(y) == pytest.approx(0.0, abs=1e-12) and max(y) == pytest.approx(3.0, abs=1e-12)
    # Length 2 (W + H) - 8 r + 2 pi r (12.63 m), less the chord deficit of the four corners:
    # a piece of angle a <= spacing / r has chord 2 r sin(a/2) >= r a (1 - a^2 / 24).
    width, height, r, spacing = 4.0, 3.0, 0.8, 0.05
    exact = 2.0 * (width + height) - 8.0 * r + 2.0 * math.pi * r
    deficit = 2.0 * math.pi * r * (spacing / r) ** 2 / 24.0
    length = math.fsum(steps)
    assert exact == pytest.approx(12.63, abs=5e-3)
    assert exact - deficit - 1e-9 <= length <= exact + 1e-9


def test_path_points_of_a_straight_line():
    scenario = Scenario(name='line', path=PathSpec(
        shape='straight_line', args={'start': [0.0, 0.0], 'end': [3.0, 4.0], 'spacing': 1.0}))
    points = path_points(scenario)
    assert len(points) == 6   # 5 m in pieces of <= 1 m
    for i, (x, y) in enumerate(points):
        assert (x, y) == pytest.approx((0.6 * i, 0.8 * i), abs=1e-12)
    assert all(type(c) is float for point in points for c in point)


@pytest.mark.parametrize('path_yaml, expected', [
    ('shape: spiral\n', 'path.shape'),
    ('shape: __init__\n', 'path.shape'),
    ('shape: circle\nradius: -1.0\ncenter: [0.0, 0.0]\n', 'radius'),
    ('shape: circle\nradius: 1.0\n', 'circle'),                       # center missing
    ('shape: rounded_rectangle\nwidth: 4.0\nheight: 3.0\ncorner_radius: 0.8\n'
     'widht: 4.0\n', 'widht'),                                         # unknown argument
    ('shape: rounded_rectangle\nwidth: "4"\nheight: 3.0\ncorner_radius: 0.8\n',
     'rounded_rectangle'),                                             # wrong type
    ('shape: rounded_rectangle\nwidth: 1.0\nheight: 3.0\ncorner_radius: 0.8\n',
     'corner_radius'),                                                 # 2 r > width
    ('shape: figure_eight\nradius: .nan\n', 'radius'),
    ('shape: straight_line\nstart: [0.0, 0.0]\nend: [0.0, 0.0]\n', 'differ'),
])
def test_bad_path_is_a_scenario_error(tmp_path, path_yaml, expected):
    text = 'path:\n' + textwrap.indent(path_yaml, '  ')
    path = write(tmp_path, text)
    scenario = load_scenario(str(path))
    with pytest.raises(ScenarioError, match=expected) as info:
        plan_run(scenario)
    assert str(path) in str(info.value)


def test_recorded_topics_cover_the_remappings(demo_plan):
    targets = [target for node in demo_plan for target in node.remappings.values()]
    assert targets, 'the plan remaps at least the tracker path'
    for target in targets:
        assert target.startswith('/')
        assert target in RECORDED_TOPICS
    assert len(set(RECORDED_TOPICS)) == len(RECORDED_TOPICS)


def test_private_topics_match_the_node_names(demo_plan):
    # The tracker publishes ~/tracking_error and the simulator ~/status: private names resolve
    # under the node names of the plan.
    nodes = by_name(demo_plan)
    assert TRACKING_ERROR_TOPIC == f'/{nodes["path_tracker"].name}/tracking_error'
    assert STATUS_TOPIC == f'/{nodes["simulator"].name}/status'
    assert nodes['path_tracker'].remappings == {'/path_tracker/path': '/path'}
    assert {TRACKING_ERROR_TOPIC, STATUS_TOPIC} <= set(RECORDED_TOPICS)


def test_bool_gain_is_refused(tmp_path):
    path = write(tmp_path, """\
        path: {shape: circle, center: [0.0, 0.0], radius: 1.0}
        tracker:
          lookahead_distance: true
        """)
    with pytest.raises(ScenarioError, match='lookahead_distance'):
        plan_run(load_scenario(str(path)))


def test_open_loop_is_planned_as_any_law(tmp_path):
    # Ej. 4.9 (c): the profile's rows become the tracker's gains open_loop.<name>, lists of
    # floats; the tracking-error topic is recorded as for every law (it stays empty).
    scenario = load_scenario(str(SHIPPED / 'ej4_9c.yaml'))
    tracker = by_name(plan_run(scenario))['path_tracker'].parameters
    assert tracker['law'] == 'open_loop'
    assert tracker['open_loop.times'] == [0.0, 30.0]
    assert tracker['open_loop.linear'] == [0.125, 0.5]
    assert tracker['open_loop.angular'] == [-0.25, 0.5]
    assert TRACKING_ERROR_TOPIC in recorded_topics(scenario)
    path = write(tmp_path, """\
        path: {shape: circle, center: [0.0, 0.0], radius: 1.0}
        tracker: {law: open_loop, times: [0.0], linear: [1.0], angular: [1.0],
                  lookahead_distance: 1.0}
        """)
    with pytest.raises(ScenarioError, match='lookahead_distance is not a gain of open_loop'):
        plan_run(load_scenario(str(path)))


def test_ej8_4_plan_wires_the_arm_loop():
    scenario = load_scenario(str(SHIPPED / 'ej8_4.yaml'))
    nodes = by_name(plan_run(scenario))
    assert list(nodes) == ['joint_trajectory_publisher', 'joint_controller', 'simulator',
                           'state_publisher', 'markers']
    assert nodes['simulator'].executable == 'arm_simulator'
    # The arm drawn from the plant's DH table: (alpha, a, theta, d, sigma) of the 2R, a = 0, l1.
    described = nodes['state_publisher'].parameters
    assert (described['robot'], described['dh_table']) == (
        '', [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0])
    # The markers draw the reference tool pose on the same arm.
    assert nodes['markers'].parameters == {'robot': '', 'dh_table': described['dh_table']}
    plant, controller = nodes['simulator'].parameters, nodes['joint_controller'].parameters
    # The plant is the true arm (2, 1 kg), the controller's model the wrong one (2.1, 0.9 kg).
    assert plant['dyn_table'] == np.ravel(two_link_arm(2.0, 1.0, 3.0, 1.0)[1]).tolist()
    assert controller['dyn_table'] == np.ravel(two_link_arm(2.1, 0.9, 3.0, 1.0)[1]).tolist()
    assert plant['robot'] == controller['robot'] == ''
    assert plant['gravity'] == controller['gravity'] == [0.0, -9.81, 0.0]
    assert (plant['payload.mass'], plant['payload.com'], plant['payload.time']) == (
        2.0, [1.0, 0.0, 0.0], 10.0)
    assert (plant['pacing'], plant['step_period'], plant['end_time']) == ('lockstep', 0.001, 20.0)
    assert controller['law'] == 'computed_torque'
    assert (controller['computed_torque.kp'], controller['computed_torque.kv']) == ([25.0], [10.0])
    assert controller['first_period'] == 0.001
    reference = nodes['joint_trajectory_publisher']
    assert reference.remappings == {'joint_trajectory': TRAJECTORY_TOPIC}
    assert reference.parameters['sine.amplitude'] == [0.15]
    assert reference.parameters['sine.phase'] == [0.0, math.pi / 2]
    assert reference.parameters['joint_names'] == ['joint_1', 'joint_2']
    assert reference.parameters['duration'] > scenario.duration


@pytest.mark.parametrize('name, on_sim_time', [
    ('demo', {'encoder_emulator', 'odometry', 'path_tracker'}),
    ('ej8_4', set()),
])
def test_only_nodes_that_read_the_clock_run_on_sim_time(name, on_sim_time):
    # The simulator owns the time; the one-shot publishers and the joint controller (which
    # answers each state with its stamp) never read their clocks, so they do not take /clock.
    nodes = plan_run(load_scenario(str(SHIPPED / f'{name}.yaml')))
    assert {node.name for node in nodes if node.use_sim_time} == on_sim_time


def test_arm_runs_record_the_arm_topics():
    scenario = load_scenario(str(SHIPPED / 'puma_computed_torque_friction.yaml'))
    assert recorded_topics(scenario) == ARM_RECORDED_TOPICS
    assert {CONTROLLER_STATE_TOPIC, TRAJECTORY_TOPIC, '/joint_states', '/joint_torques',
            STATUS_TOPIC} <= set(ARM_RECORDED_TOPICS)
    nodes = by_name(plan_run(scenario))
    assert CONTROLLER_STATE_TOPIC == f'/{nodes["joint_controller"].name}/controller_state'
    assert nodes['simulator'].parameters['robot'] == 'puma560'
    assert nodes['simulator'].parameters['unmodelled_viscous'] == [0.1, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert 'unmodelled_viscous' not in nodes['joint_controller'].parameters


@pytest.mark.parametrize('reference, expected', [
    ('  spline_order: 3\n', 'unknown key reference.spline_order'),
    ('  amplitude: [0.1, .nan]\n', 'reference.amplitude must be a finite number'),
    ('  amplitude: yes\n', 'reference.amplitude must be a finite number'),
])
def test_bad_reference_is_a_scenario_error(tmp_path, reference, expected):
    path = write(tmp_path, 'robot:\n  type: manipulator\nreference:\n  generator: sine\n'
                 + reference)
    with pytest.raises(ScenarioError, match=expected):
        plan_run(load_scenario(str(path)))


def test_every_sensor_and_a_steered_vehicle(tmp_path):
    path = write(tmp_path, """\
        seed: 3
        robot:
          type: ackermann
          wheel_radius: 0.2
          wheel_separation: 0.5
          wheelbase: 0.8
        path:
          shape: circle
          center: [0.0, 1.0]
          radius: 1.0
        sensors:
          gyro: {enabled: true, preset: fog}
          compass: {enabled: true, hard_iron: [1.0e-6, 0.0, 0.0]}
          gps: {enabled: true, preset: rtk, origin: [40.0, -3.0, 600.0]}
        odometry:
          heading_source: gyro
          fuse_gps: true
          wheel_radius_error: 0.02
          track_error: -0.05
        """)
    scenario = load_scenario(str(path))
    nodes = by_name(plan_run(scenario))
    assert {'gyro_emulator', 'compass_emulator', 'gps_emulator'} <= set(nodes)
    seeds = [nodes[n].parameters['seed'] for n in ('encoder_emulator', 'gyro_emulator',
                                                   'compass_emulator', 'gps_emulator')]
    assert len(set(seeds)) == 4, 'every sensor draws its own noise'
    assert nodes['gyro_emulator'].parameters['preset'] == 'fog'
    assert nodes['compass_emulator'].parameters['hard_iron'] == [1.0e-6, 0.0, 0.0]
    gps = nodes['gps_emulator'].parameters
    odometry = nodes['odometry'].parameters
    for params in (gps, odometry):
        assert (params['origin.latitude'], params['origin.longitude'],
                params['origin.altitude']) == (40.0, -3.0, 600.0)
    # The odometry believes a nominal geometry off the true one by the given errors.
    assert odometry['wheel_radius'] == pytest.approx(0.2 * 1.02)
    assert odometry['wheel_separation'] == pytest.approx(0.5 * 0.95)
    assert odometry['heading_source'] == 'gyro' and odometry['fuse_gps'] is True
    # RTK: 2DRMS 2 cm with 2 mm white noise, 10 s correlation: the filter's model of it.
    assert odometry['gps_bias.stddev'] == pytest.approx(math.sqrt((0.02 / 2 / math.sqrt(2)) ** 2
                                                                  - 0.002 ** 2))
    assert odometry['gps_bias.correlation_time'] == 10.0
    tracker = nodes['path_tracker'].parameters
    assert tracker['command_type'] == 'steering' and tracker['wheelbase'] == 0.8
    assert nodes['simulator'].parameters['vehicle.type'] == 'ackermann'
    topics = recorded_topics(scenario)
    assert '/vehicle_command' in topics and '/cmd_vel' not in topics
    assert {'/imu/data', '/compass/heading', '/compass/magnetic_field', '/gps/fix'} <= set(topics)


def test_sensor_terms_pass_through_and_the_odometry_models_the_receiver_run(tmp_path):
    # Terms given override the preset in the emulators' parameters (only those given: the
    # others stay the preset's, which the node declares as its defaults); the odometry's GPS
    # error model is that of the receiver as configured, not of the bare preset.
    path = write(tmp_path, """\
        path: {shape: circle, center: [0.0, 1.0], radius: 1.0}
        sensors:
          gyro: {enabled: true, preset: fog, noise_density: 1.0e-3, saturation: 2.0}
          gps:
            enabled: true
            preset: dgps
            correlation_time: 120.0
            white_stddev: 0.2
            dropout: {probability: 0.0}
        odometry: {fuse_gps: true}
        """)
    nodes = by_name(plan_run(load_scenario(str(path))))
    gyro = nodes['gyro_emulator'].parameters
    assert {k: v for k, v in gyro.items() if k != 'seed'} == {
        'preset': 'fog', 'noise_density': 1e-3, 'saturation': 2.0}
    gps = nodes['gps_emulator'].parameters
    assert (gps['preset'], gps['correlation_time'], gps['white_stddev'],
            gps['dropout.probability']) == ('dgps', 120.0, 0.2, 0.0)
    assert 'latency' not in gps and 'dropout.mean_duration' not in gps
    odometry = nodes['odometry'].parameters
    sigma = 1.0 / (2.0 * math.sqrt(2.0))   # DGPS: 2DRMS 1 m
    assert odometry['gps_bias.stddev'] == pytest.approx(math.sqrt(sigma ** 2 - 0.2 ** 2))
    assert (odometry['gps_bias.correlation_time'], odometry['gps_bias.white_stddev']) \
        == (120.0, 0.2)


def test_per_wheel_radius_errors_add_to_the_common_one(tmp_path):
    base = ('path: {shape: circle, center: [0.0, 1.0], radius: 1.0}\n'
            'robot: {wheel_radius: 0.2}\n')
    plain = by_name(plan_run(load_scenario(str(write(tmp_path, base)))))
    assert 'left_wheel_radius' not in plain['odometry'].parameters   # 0: wheel_radius
    path = write(tmp_path, base + 'odometry: {wheel_radius_error: 0.01, '
                 'left_wheel_radius_error: -0.004, right_wheel_radius_error: 0.002}\n')
    odometry = by_name(plan_run(load_scenario(str(path))))['odometry'].parameters
    assert odometry['wheel_radius'] == pytest.approx(0.2 * 1.01)
    assert odometry['left_wheel_radius'] == pytest.approx(0.2 * (1.0 + 0.01 - 0.004))
    assert odometry['right_wheel_radius'] == pytest.approx(0.2 * (1.0 + 0.01 + 0.002))


def test_an_unknown_sensor_term_is_a_scenario_error(tmp_path):
    path = write(tmp_path, 'sensors:\n  gyro: {enabled: true, bias: 0.1}\n')
    with pytest.raises(ScenarioError, match=r'sensors.gyro: unknown key\(s\) bias'):
        load_scenario(str(path))


@pytest.mark.parametrize('vehicle_type, wheels', [
    ('differential', ['left_wheel_joint', 'right_wheel_joint']),
    ('mecanum', ['left_odometry_wheel_joint', 'right_odometry_wheel_joint'])])
def test_every_mobile_run_describes_its_vehicle_and_records_tf(tmp_path, vehicle_type, wheels):
    # The state publisher draws the simulated vehicle (the simulator's vehicle parameters), and
    # the encoder emulator reads the wheels under the names the simulator publishes (the URDF's).
    path = write(tmp_path, f"""\
        robot: {{type: {vehicle_type}, wheel_radius: 0.15, wheel_separation: 0.6}}
        path: {{shape: straight_line, start: [0, 0], end: [5, 0]}}
    """)
    scenario = load_scenario(path)
    nodes = by_name(plan_run(scenario))
    described = nodes['state_publisher'].parameters
    assert {k: v for k, v in described.items() if k.startswith('vehicle.')} == {
        key: value for key, value in nodes['simulator'].parameters.items()
        if key.startswith('vehicle.')}
    # The markers draw the same vehicle, and the GPS fixes in the odometry's ENU origin.
    drawn = nodes['markers'].parameters
    assert {k: v for k, v in drawn.items() if k.startswith('vehicle.')} == {
        k: v for k, v in described.items() if k.startswith('vehicle.')}
    assert {k: v for k, v in drawn.items() if k.startswith('origin.')} == {
        k: v for k, v in nodes['odometry'].parameters.items() if k.startswith('origin.')}
    # Its joint states replayed, as the inputs of every node off the lockstep loop.
    assert described['qos_overrides./joint_states.subscription.durability'] == 'transient_local'
    assert (described['vehicle.type'], described['vehicle.wheel_radius'],
            described['vehicle.track']) == (vehicle_type, 0.15, 0.6)
    encoder = nodes['encoder_emulator'].parameters
    assert [encoder['left_wheel_joint'], encoder['right_wheel_joint']] == wheels
    assert {'/tf', '/tf_static', '/robot_description'} <= set(recorded_topics(scenario))


def test_the_simulator_follows_the_per_step_outputs_off_its_loop(tmp_path):
    path = write(tmp_path, """\
        robot: {type: differential}
        path: {shape: straight_line, start: [0, 0], end: [5, 0]}
        sensors: {gyro: {enabled: true}, gps: {enabled: true}}
    """)
    nodes = {n.name: n for n in plan_run(load_scenario(path))}
    followed = nodes['simulator'].parameters['lockstep.follow_topics']
    assert followed == ['/recorder/progress', '/wheel_encoders', '/odom',
                        '/imu/data']   # not the few-hertz GPS
    published = {'/wheel_encoders': 'encoder_emulator', '/odom': 'odometry',
                 '/imu/data': 'gyro_emulator'}
    assert all(name in nodes for name in published.values())


def test_an_arm_simulator_follows_the_recording_only():
    scenario = load_scenario(str(SHIPPED / 'puma_computed_torque.yaml'))
    nodes = {n.name: n for n in plan_run(scenario)}
    assert nodes['simulator'].parameters['lockstep.follow_topics'] == ['/recorder/progress']
