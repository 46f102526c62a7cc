"""
Every node a plan starts accepts the parameters of the plan, at the edges of what it accepts.

The other side of ``test/runs/test_plan_node_checks.py`` (a value beyond a node's range is
refused by the plan): scenarios with values at the bounds of the nodes' ranges are planned, and
each node of the plan is built in-process with its planned parameters (as ``robotica run``
passes them, through a parameters file), which must not raise. A range moved on one side only
fails here or there.
"""
import importlib

import pytest
import rclpy
from robotica_sim.runs.plan import plan_run
from robotica_sim.runs.scenario import load_scenario, resolve_scenario_path
import yaml

pytestmark = pytest.mark.ros

NODE_CLASSES = {
    'state_publisher': 'robotica_kin.nodes.state_publisher:StatePublisherNode',
    'path_publisher': 'robotica_ctrl.nodes.path_publisher:PathPublisherNode',
    'path_tracker': 'robotica_ctrl.nodes.path_tracker:PathTrackerNode',
    'joint_trajectory_publisher':
        'robotica_ctrl.nodes.joint_trajectory_publisher:JointTrajectoryPublisherNode',
    'joint_controller': 'robotica_ctrl.nodes.joint_controller:JointControllerNode',
    'encoder_emulator': 'robotica_sim.nodes.encoder_emulator:EncoderEmulatorNode',
    'gyro_emulator': 'robotica_sim.nodes.gyro_emulator:GyroEmulatorNode',
    'compass_emulator': 'robotica_sim.nodes.compass_emulator:CompassEmulatorNode',
    'gps_emulator': 'robotica_sim.nodes.gps_emulator:GpsEmulatorNode',
    'odometry': 'robotica_sim.nodes.odometry:OdometryNode',
    'simulator': 'robotica_sim.nodes.simulator:SimulatorNode',
    'arm_simulator': 'robotica_sim.nodes.arm_simulator:ArmSimulatorNode',
    'markers': 'robotica_sim.nodes.markers:MarkersNode',
}

EDGES = [
    ('demo', {'robot': {'type': 'bicycle', 'wheelbase': 100.0, 'max_steering_angle': 1.57,
                        'wheel_radius': 10.0, 'wheel_separation': 100.0,
                        'longitudinal_slip': 0.9, 'traction_time_constant': 60.0,
                        'initial_pose': [1e6, -1e6, 0.0]},
              'tracker': {'law': 'pure_pursuit', 'max_cross_track': 1e6,
                          'pose_source': 'ground_truth'}}),
    ('demo', {'robot': {'type': 'skid_steer', 'icr_scale': 10.0, 'wheel_radius': 1e-3},
              'sensors': {'encoders': {'pulses_per_revolution': 10_000_000, 'decoding': 1,
                                       'gear_ratio': 1e-3, 'missed_count_probability': 0.5},
                          'gyro': {'enabled': True},
                          'compass': {'enabled': True, 'tilt_error': -0.5,
                                      'noise_stddev': 1e-4, 'hard_iron': [1e-3, 0.0, -1e-3]},
                          'gps': {'enabled': True, 'origin': [-90.0, 180.0, 1e5]}},
              'tracker': {'law': 'gpc', 'n1': 1, 'n2': 200, 'nu': 200,
                          'max_cross_track': 1e-3}}),
    ('ej8_2', {'reference': {'generator': 'sine', 'amplitude': 0.15, 'period': 1e-3,
                             'sample_period': 1e-4},
               'arm': {'model': 'two_link_arm', 'masses': [2.0, 1.0], 'lengths': [3.0, 1.0],
                       'tau_max': [1e-9], 'unmodelled_viscous': [0.0, 1e3],
                       'payload': {'mass': 1e4, 'com': [0.0, 0.0, 0.0], 'time': 1e7}},
               'step_period': 0.1, 'duration': 1.0}),
    ('ej8_2', {'reference': {'generator': 'parab', 'positions': [0.0, 0.0, 1.0, 1.0],
                             'segment_durations': [2.0], 'acceleration': [10.0],
                             'sample_period': 10.0},
               'controller': {'law': 'pid', 'kp': [0.0, 1e6], 'derivative_time_constant': 0.0},
               'step_period': 1e-4, 'duration': 1.0}),
]


def _scenario(tmp_path, shipped: str, changes: dict) -> str:
    """Return a copy of a shipped scenario with whole sections replaced by ``changes``."""
    data = {**yaml.safe_load(resolve_scenario_path(shipped).read_text()), **changes}
    path = tmp_path / f'{shipped}_edge.yaml'
    path.write_text(yaml.safe_dump(data))
    return str(path)


def _node_class(executable: str):
    module, name = NODE_CLASSES[executable].split(':')
    return getattr(importlib.import_module(module), name)


@pytest.mark.parametrize('shipped, changes', EDGES, ids=[f'{s}-{i}' for i, (s, _) in
                                                         enumerate(EDGES)])
def test_every_planned_node_accepts_its_parameters(tmp_path, ros_domain, shipped, changes):
    plan = plan_run(load_scenario(_scenario(tmp_path, shipped, changes)))
    params_file = tmp_path / 'params.yaml'
    for spec in plan:
        params_file.write_text(yaml.safe_dump({spec.name: {'ros__parameters': {
            'use_sim_time': spec.use_sim_time, **spec.parameters}}}))
        rclpy.init(args=['--ros-args', '-r', f'__node:={spec.name}', '--params-file',
                         str(params_file)], domain_id=ros_domain)
        try:
            node = _node_class(spec.executable)()   # raises what the node refuses
            node.destroy_node()
        finally:
            rclpy.try_shutdown()
