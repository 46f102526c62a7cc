"""
The plan of a run: which nodes a scenario starts, with which parameters and remappings.

:func:`plan_run` turns a :class:`~robotica_sim.scenario.Scenario` into node specifications (one
process each) and the list of topics the recorder must record. It is pure data; starting the
processes is :mod:`robotica_sim.process_supervisor`'s job.
"""
from dataclasses import dataclass, field
import math

from robotica_ctrl import path_shapes
from robotica_sim.scenario import Scenario, ScenarioError

PATH_SHAPES = ('straight_line', 'circle', 'rounded_rectangle', 'figure_eight')
STATUS_TOPIC = '/simulator/status'
TRACKING_ERROR_TOPIC = '/path_tracker/tracking_error'
RECORDED_TOPICS = ('/clock', '/cmd_vel', '/odom', '/ground_truth/odom', '/joint_states',
                   '/wheel_encoders', '/path', TRACKING_ERROR_TOPIC, STATUS_TOPIC, '/rosout')


@dataclass(frozen=True)
class NodeSpec:
    """One node process: ``ros2 run <package> <executable>`` with parameters and remaps."""

    package: str
    executable: str
    name: str
    parameters: dict = field(default_factory=dict)
    remappings: dict = field(default_factory=dict)


def path_points(scenario: Scenario) -> list[list[float]]:
    """Return the scenario's reference path as a list of [x, y] points [m]."""
    spec = scenario.path
    where = scenario.source or scenario.name
    if spec.shape not in PATH_SHAPES:
        raise ScenarioError(f'{where}: path.shape must be one of {PATH_SHAPES}, '
                            f'got {spec.shape!r}')
    try:
        points = getattr(path_shapes, spec.shape)(**spec.args)
    except (TypeError, ValueError) as err:
        raise ScenarioError(f'{where}: path ({spec.shape}): {err}') from None
    return [[round(float(x), 9), round(float(y), 9)] for x, y in points]   # [m], to 1 nm


def plan_run(scenario: Scenario) -> list[NodeSpec]:
    """Return the nodes of a run, in start order (the recorder is added by the caller)."""
    where = scenario.source or scenario.name
    robot = scenario.robot
    x0, y0, theta0 = robot.initial_pose
    pose = {'initial_pose.x': x0, 'initial_pose.y': y0, 'initial_pose.theta': theta0}
    points = path_points(scenario)
    gains = {}
    for key, value in scenario.tracker.gains.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise ScenarioError(f'{where}: tracker.{key} must be a finite number, got {value!r}')
        gains[f'{scenario.tracker.law}.{key}'] = float(value)
    return [
        NodeSpec('robotica_sim', 'path_publisher', 'path_publisher', {
            'x': [p[0] for p in points], 'y': [p[1] for p in points],
            'frame_id': scenario.path.frame_id}),
        NodeSpec('robotica_sim', 'encoder_emulator', 'encoder_emulator', {
            'ticks_per_revolution': scenario.sensors.encoders.ticks_per_revolution}),
        NodeSpec('robotica_sim', 'odometry', 'odometry', {
            'wheel_radius': robot.wheel_radius, 'wheel_separation': robot.wheel_separation,
            'integration_method': scenario.odometry.integration_method,
            'odom_frame_id': scenario.path.frame_id, **pose}),
        NodeSpec('robotica_ctrl', 'path_tracker', 'path_tracker',
                 {'law': scenario.tracker.law, **gains},
                 remappings={'/path_tracker/path': '/path'}),
        NodeSpec('robotica_sim', 'simulator', 'simulator', {
            'robot.wheel_radius': robot.wheel_radius,
            'robot.wheel_separation': robot.wheel_separation,
            'step_period': scenario.step_period, 'pacing': scenario.pacing,
            'end_time': scenario.duration, 'autostart': False, **pose}),
    ]
