"""
Scenarios: what a run is made of (robot, path, sensors, tracker, pacing, seed, duration).

Two kinds of run: a mobile robot (``robot.type`` one of
:data:`robotica_kin.mobile.vehicles.VEHICLE_TYPES`, sections ``path``, ``sensors``, ``odometry``,
``tracker``) and a manipulator (``robot.type: manipulator``, sections
``arm``, ``reference``, ``controller``, book ch. 8). A section of the other kind is an error.

A scenario is a YAML file, validated strictly when loaded: an unknown or repeated key, a value
of the wrong type or out of range, a file that is not UTF-8 text gives a :class:`ScenarioError`
of one line naming the file and the key, never a silently ignored setting. The plan checks the
rest (:mod:`robotica_sim.runs.plan`: the path shape and its arguments, the tracker's law and
gains). Shipped scenarios live in ``share/robotica_sim/scenarios`` and can be named without
their extension (``robotica run demo``; :func:`robotica_sim.runs.shipped.resolve_shipped`).
"""
import dataclasses
from dataclasses import dataclass, field, fields, is_dataclass
import math
from pathlib import Path
import typing
from typing import Any, Optional

from robotica_kin.mobile.odometry import ODOMETRY_METHODS
from robotica_kin.mobile.vehicles import VEHICLE_TYPES
from robotica_kin.world.errors import WorldError
from robotica_kin.world.world_section import world_from_mapping
from robotica_sim.runs.shipped import resolve_shipped
from robotica_sim.runs.strict_yaml import read_strict_yaml
from robotica_sim.sensors.gps import GPS_PRESETS
from robotica_sim.sensors.gyro import GYRO_PRESETS


class ScenarioError(ValueError):
    """A scenario file that cannot be used; the message names the file and the key."""


@dataclass(frozen=True)
class RobotSpec:
    """The simulated robot (book §4.7.4): a vehicle configuration, or ``manipulator``."""

    type: str = 'differential'  # noqa: A003 (the scenario key)
    wheel_radius: float = 0.1                      # c [m]
    wheel_separation: float = 0.4                  # b [m], track of the odometry wheels' axle
    wheelbase: float = 0.5                         # l [m], steered vehicles
    base_radius: float = 0.2                       # [m], omni_three
    half_length: float = 0.2                       # [m], mecanum
    max_steering_angle: float = 1.2                # [rad], steered vehicles
    icr_scale: float = 1.0                         # skid_steer
    traction_time_constant: float = 0.0            # [s] first-order lag; 0: none
    steering_time_constant: float = 0.0            # [s]
    longitudinal_slip: float = 0.0                 # [-] in [0, 1)
    initial_pose: tuple[float, ...] = (0.0, 0.0, 0.0)   # x [m], y [m], theta [rad] REP-103
    footprint_radius: float = 0.0                  # [m] contact circle; 0: the outline
    footprint_polygon: tuple[float, ...] = ()      # [x1, y1, x2, y2, ...] [m] base_link; ()


@dataclass(frozen=True)
class PathSpec:
    """The reference path: a shape of ``robotica_ctrl.mobile.path_shapes`` and its arguments."""

    shape: str = 'rounded_rectangle'
    frame_id: str = 'odom'
    args: dict = field(default_factory=dict)       # keyword arguments of the shape function


@dataclass(frozen=True)
class EncoderSpec:
    """Wheel encoders (book §7.3.2): counts per wheel revolution = PPR x decoding x gear."""

    pulses_per_revolution: int = 1024
    decoding: int = 4                              # x1, x2 or x4 quadrature
    gear_ratio: float = 1.0                        # encoder revolutions per wheel revolution
    missed_count_probability: float = 0.0


@dataclass(frozen=True)
class GyroSpec:
    """
    The gyroscope (book §7.7.3): a grade of ``robotica_sim.sensors.gyro.GYRO_PRESETS``.

    Each error term left out (None) is the preset's; one given overrides it (the node's
    parameter of that name, ``robotica_sim.sensors.gyro.GYRO_TERMS``, checked by the plan).
    """

    enabled: bool = False
    preset: str = 'mems_consumer'
    noise_density: Optional[float] = None          # N [rad/s/√Hz]
    bias_instability: Optional[float] = None       # σ_b [rad/s]
    bias_correlation_time: Optional[float] = None  # T [s]
    random_walk: Optional[float] = None            # K [rad/s^1.5]
    initial_bias: Optional[float] = None           # [rad/s]
    initial_bias_stddev: Optional[float] = None    # [rad/s]
    scale_factor_error: Optional[float] = None     # s [-]
    saturation: Optional[float] = None             # [rad/s]
    resolution: Optional[float] = None             # [rad/s]


@dataclass(frozen=True)
class CompassSpec:
    """The compass / magnetometer (book §7.7.2)."""

    enabled: bool = False
    noise_stddev: float = 2e-7                     # [T] per axis
    hard_iron: tuple[float, ...] = (0.0, 0.0, 0.0)     # [T]
    tilt_error: float = 0.0                        # [rad]


@dataclass(frozen=True)
class GpsDropoutSpec:
    """The GPS signal outages (None: the preset's)."""

    probability: Optional[float] = None            # p [-] of losing the signal at each fix
    mean_duration: Optional[float] = None          # D [s] mean outage


@dataclass(frozen=True)
class GpsSpec:
    """
    The GPS receiver (book §7.7.5): a preset of ``robotica_sim.sensors.gps.GPS_PRESETS``.

    Each term left out (None) is the preset's; one given overrides it (the node's parameter of
    that name, ``robotica_sim.sensors.gps.GPS_TERMS``, checked by the plan).
    """

    enabled: bool = False
    preset: str = 'dgps'
    origin: tuple[float, ...] = (37.41, -6.0, 10.0)    # latitude, longitude [deg], height [m]
    horizontal_stddev: Optional[float] = None      # σ_h [m] per axis, total
    vertical_stddev: Optional[float] = None        # σ_v [m], total
    correlation_time: Optional[float] = None       # τ [s] of the Gauss–Markov part
    white_stddev: Optional[float] = None           # σ_w [m], white part
    update_rate: Optional[float] = None            # [Hz]
    latency: Optional[float] = None                # [s]
    dropout: GpsDropoutSpec = GpsDropoutSpec()
    status: Optional[str] = None                   # fix, dgps or rtk


@dataclass(frozen=True)
class RangeSensorSpec:
    """
    A range sensor on the world (laser scanner, sonar ring, infrared sensors; book §7.4, §12.3).

    ``preset`` gives the starting values of its terms ('' the emulator's default); every other
    key is one of the emulator's parameters (a term, ``mount``/``mounts``), checked by the plan.
    """

    enabled: bool = False
    preset: str = ''
    settings: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SensorsSpec:
    """Sensor emulators of the run (encoders always; the others when enabled)."""

    encoders: EncoderSpec = EncoderSpec()
    gyro: GyroSpec = GyroSpec()
    compass: CompassSpec = CompassSpec()
    gps: GpsSpec = GpsSpec()
    laser: RangeSensorSpec = RangeSensorSpec()
    sonar: RangeSensorSpec = RangeSensorSpec()
    infrared: RangeSensorSpec = RangeSensorSpec()


@dataclass(frozen=True)
class ExternalSpec:
    """
    A user's own node in a role of the run (docs/your_node.md), instead of robotica's.

    The command runs in ``folder`` (default: the scenario file's), with ``--ros-args`` added:
    the node is renamed to the role's node name, gets ``parameters`` (and ``use_sim_time``)
    from the run's parameter file and the ``remappings`` (its topic name -> a topic of the
    role's contract).
    """

    command: tuple[str, ...] = ()                  # argv, e.g. [python3, my_tracker.py]
    parameters: dict = field(default_factory=dict)     # its ROS parameters
    remappings: dict = field(default_factory=dict)     # its name -> the contract's name
    answer_timeout: float = 5.0                    # [s] wall clock: the longest wait for an
    #                                                answer (the first, and every later one)
    folder: str = ''                               # where it runs; '' or relative: from the
    #                                                scenario file's folder


@dataclass(frozen=True)
class OdometrySpec:
    """Dead reckoning and fusion settings (the odometry node), or a user's estimator."""

    integration_method: str = 'exact_arc'
    heading_source: str = 'encoders'               # or 'gyro' (needs sensors.gyro)
    fuse_gps: bool = False                         # needs sensors.gps
    fuse_compass: bool = False                     # needs sensors.compass
    wheel_radius_error: float = 0.0                # [-] nominal c = true c (1 + error)
    left_wheel_radius_error: float = 0.0           # [-] nominal c_L = true c (1 + e + e_L)
    right_wheel_radius_error: float = 0.0          # [-] nominal c_R = true c (1 + e + e_R)
    track_error: float = 0.0                       # [-] nominal b = true b (1 + error)
    external: Optional[ExternalSpec] = None        # a user's estimator instead


@dataclass(frozen=True)
class TrackerSpec:
    """The path tracker: its law and the law's gains (``<law>.<gain>``), or a user's node."""

    law: str = 'pure_pursuit'
    gains: dict = field(default_factory=dict)
    external: Optional[ExternalSpec] = None


@dataclass(frozen=True)
class NavigatorSpec:
    """
    The reactive navigator instead of the path tracker (§9.6, §12.7): its behaviour and gains.

    ``gains`` are the node's parameters by name (``wall.desired_distance``, ``goal``, ...,
    given nested or dotted); an empty ``behaviour``: no navigator, the tracker runs.
    """

    behaviour: str = ''
    gains: dict = field(default_factory=dict)


@dataclass(frozen=True)
class PlannerSpec:
    """
    A planner instead of the fixed path (book ch. 12): its method, the goal and its options.

    ``options`` are the planner node's parameters by name (``robot_radius``, ``neighbours``,
    ``smooth``, ``parking.pass_length``, ...); an empty ``method``: no planner, the ``path``
    section's path is followed. Method ``parking`` takes no goal: it parks in the first space
    the side sonar number ``sonar`` (of ``sensors.sonar.mounts``) finds on its pass.
    """

    method: str = ''
    goal: tuple[float, ...] = ()                   # (x, y) [m] in the world's frame
    sonar: int = -1                                # parking: the side sonar's index
    options: dict = field(default_factory=dict)


ARM_MODELS = ('puma560', 'two_link_arm', 'pp_robot')
MIN_STEP_PERIOD = 1e-4              # [s] simulated
MAX_STEPS = 10_000_000              # simulation steps of a run (duration / step_period)
SEED_MAX = (2**31 - 1) // 10 - 1
"""The largest seed: each sensor emulator gets 10 seed + k (k < 10), which its ``seed``
parameter takes up to 2**31 - 1."""
INT64_MAX = 2**63 - 1               # an integer parameter of a node is int64
MOBILE_SECTIONS = ('path', 'sensors', 'odometry', 'tracker', 'navigator', 'world', 'planner')
MAX_ANSWER_TIMEOUT = 600.0          # [s] of an external node's answer_timeout
ARM_SECTIONS = ('arm', 'reference', 'controller')


@dataclass(frozen=True)
class PayloadSpec:
    """A payload grasped during the run (Ej. 8.4)."""

    mass: float = 0.0                              # [kg]; 0: none
    com: tuple[float, ...] = (0.0, 0.0, 0.0)       # [m] in the last link's frame {n}
    time: float = 0.0                              # [s] simulated


@dataclass(frozen=True)
class ArmSpec:
    """The simulated manipulator (the plant, book ch. 5)."""

    model: str = 'puma560'                         # one of ARM_MODELS
    masses: tuple[float, ...] = ()                 # two_link_arm: (m1, m2) [kg], Ej. 5.1
    lengths: tuple[float, ...] = ()                # two_link_arm: (l1, l2) [m]
    gravity: tuple[float, ...] = (0.0, 0.0, -9.81)     # [m/s^2] in the base frame {0}
    initial_positions: tuple[float, ...] = ()      # q(0) [rad | m]; () = zeros
    initial_velocities: tuple[float, ...] = ()     # q'(0); () = zeros
    tau_max: tuple[float, ...] = ()                # [N m], 1 or n values; () = none
    unmodelled_viscous: tuple[float, ...] = ()     # [N m s], 1 or n values (App. A)
    respect_limits: bool = True
    payload: PayloadSpec = PayloadSpec()
    environment: dict = field(default_factory=dict)   # a compliant plane (§8.7): stiffness, ...
    ft_sensor: dict = field(default_factory=dict)     # a wrist F/T sensor (§7.6): preset, ...


@dataclass(frozen=True)
class ReferenceSpec:
    """The joint reference: a generator of ``joint_trajectory_publisher`` and its parameters."""

    generator: str = 'sine'
    args: dict = field(default_factory=dict)       # its parameters (sine.*, via.*, ...)


@dataclass(frozen=True)
class ControllerSpec:
    """The joint controller: its law, the law's gains and the model it believes in."""

    law: str = 'computed_torque'
    model_masses: tuple[float, ...] = ()           # two_link_arm estimate (m̂1, m̂2); () exact
    use_friction: bool = True
    trial_period: float = 0.0                      # [s] trials of learning (§8.5); 0: one
    task: dict = field(default_factory=dict)       # force laws: task frame and reference
    cartesian: dict = field(default_factory=dict)  # Cartesian laws: goal and duration
    gains: dict = field(default_factory=dict)
    external: Optional[ExternalSpec] = None        # a user's joint controller instead


@dataclass(frozen=True)
class Scenario:
    """A whole run."""

    name: str
    description: str = ''
    duration: float = 30.0                         # [s] simulated
    seed: int = 0
    pacing: str = 'lockstep'                       # 'lockstep' or 'realtime'
    step_period: float = 0.02                      # [s] simulated
    visualisation: bool = True                     # /tf, /robot_description, /markers
    robot: RobotSpec = RobotSpec()
    path: PathSpec = PathSpec()
    sensors: SensorsSpec = SensorsSpec()
    odometry: OdometrySpec = OdometrySpec()
    tracker: TrackerSpec = TrackerSpec()
    navigator: NavigatorSpec = NavigatorSpec()
    planner: PlannerSpec = PlannerSpec()
    world: dict = field(default_factory=dict)     # obstacles: robotica_kin.world.world_section
    arm: ArmSpec = ArmSpec()
    reference: ReferenceSpec = ReferenceSpec()
    controller: ControllerSpec = ControllerSpec()
    source: Optional[str] = None                   # the file it was loaded from

    @property
    def is_manipulator(self) -> bool:
        """Return whether the run simulates a manipulator (else a mobile robot)."""
        return self.robot.type == 'manipulator'

    def __post_init__(self) -> None:
        checks = [
            (MIN_STEP_PERIOD <= self.step_period <= 1.0,
             f'step_period must be in [{MIN_STEP_PERIOD:g}, 1] s, got {self.step_period:g}'),
            (self.duration >= self.step_period,
             f'duration must be at least one step_period ({self.step_period:g} s), '
             f'got {self.duration:g} s'),
            (self.duration <= MAX_STEPS * self.step_period,
             f'duration must be at most {MAX_STEPS} steps of {self.step_period:g} s '
             f'({MAX_STEPS * self.step_period:g} s), got {self.duration:g} s'),
            (0 <= self.seed <= SEED_MAX, f'seed must be in 0..{SEED_MAX}, got {self.seed}'),
            (self.pacing in ('lockstep', 'realtime'), 'pacing must be lockstep or realtime'),
            (0 < len(self.name) <= 100 and not self.name.startswith('.')
             and all(c.isprintable() and c not in '/\\' for c in self.name),
             'name must be 1 to 100 printable characters, no / or \\, not starting with .'),
            (self.robot.type in VEHICLE_TYPES + ('manipulator',),
             f'robot.type must be manipulator or one of {VEHICLE_TYPES}'),
            (self.arm.model in ARM_MODELS, f'arm.model must be one of {ARM_MODELS}'),
            (self.arm.model != 'two_link_arm' or (
                len(self.arm.masses) == len(self.arm.lengths) == 2
                and min(self.arm.masses) >= 0.0 and min(self.arm.lengths) > 0.0),
             'arm.masses and arm.lengths: two_link_arm needs [m1, m2] >= 0 kg and [l1, l2] > 0 m'),
            (self.arm.model == 'two_link_arm' or not (self.arm.masses or self.arm.lengths),
             "arm.masses and arm.lengths are for two_link_arm only (pp_robot is Ej. 8.10's, "
             'm1 = 2 kg, m2 = 0.35 kg)'),
            (len(self.arm.gravity) == 3, 'arm.gravity must be 3 values [m/s^2]'),
            (self.arm.payload.mass >= 0.0 and len(self.arm.payload.com) == 3
             and self.arm.payload.time >= 0.0,
             'arm.payload: mass >= 0 kg, com [x, y, z] m, time >= 0 s'),
            (self.controller.trial_period == 0.0
             or self.step_period <= self.controller.trial_period <= self.duration,
             'controller.trial_period must be 0 (one trial) or in [step_period, duration] s'),
            (len(self.controller.model_masses) in (0, 2) and (
                not self.controller.model_masses or self.arm.model == 'two_link_arm'),
             'controller.model_masses: [m1, m2] of a two_link_arm model'),
            (self.robot.wheel_radius > 0.0, 'robot.wheel_radius must be > 0 m'),
            (self.robot.wheel_separation > 0.0, 'robot.wheel_separation must be > 0 m'),
            (min(self.robot.wheelbase, self.robot.base_radius, self.robot.half_length) > 0.0,
             'robot.wheelbase, base_radius and half_length must be > 0 m'),
            (0.0 < self.robot.max_steering_angle < math.pi / 2.0,
             'robot.max_steering_angle must be in (0, pi/2) rad'),
            (self.robot.icr_scale >= 1.0, 'robot.icr_scale must be >= 1'),
            (min(self.robot.traction_time_constant, self.robot.steering_time_constant) >= 0.0,
             'robot.traction_time_constant and steering_time_constant must be >= 0 s'),
            (0.0 <= self.robot.longitudinal_slip < 1.0,
             'robot.longitudinal_slip must be in [0, 1)'),
            (len(self.robot.initial_pose) == 3
             and all(math.isfinite(v) for v in self.robot.initial_pose),
             'robot.initial_pose must be 3 finite numbers [x, y, theta]'),
            (self.sensors.encoders.pulses_per_revolution >= 1
             and self.sensors.encoders.decoding in (1, 2, 4)
             and self.sensors.encoders.gear_ratio > 0.0
             and 0.0 <= self.sensors.encoders.missed_count_probability <= 0.5,
             'sensors.encoders: pulses_per_revolution >= 1, decoding 1, 2 or 4, gear_ratio > 0, '
             'missed_count_probability in [0, 0.5]'),
            (self.sensors.gyro.preset in GYRO_PRESETS,
             f'sensors.gyro.preset must be one of {tuple(GYRO_PRESETS)}'),
            (self.sensors.gps.preset in GPS_PRESETS,
             f'sensors.gps.preset must be one of {tuple(GPS_PRESETS)}'),
            (len(self.sensors.gps.origin) == 3 and abs(self.sensors.gps.origin[0]) <= 90.0
             and abs(self.sensors.gps.origin[1]) <= 180.0,
             'sensors.gps.origin must be [latitude, longitude (deg), height (m)]'),
            (len(self.sensors.compass.hard_iron) == 3 and self.sensors.compass.noise_stddev >= 0.0,
             'sensors.compass: hard_iron [x, y, z] T and noise_stddev >= 0 T'),
            (self.odometry.heading_source in ('encoders', 'gyro'),
             'odometry.heading_source must be encoders or gyro'),
            (self.odometry.heading_source != 'gyro' or self.sensors.gyro.enabled,
             'odometry.heading_source gyro needs sensors.gyro.enabled'),
            (not self.odometry.fuse_gps or self.sensors.gps.enabled,
             'odometry.fuse_gps needs sensors.gps.enabled'),
            (not self.odometry.fuse_compass or self.sensors.compass.enabled,
             'odometry.fuse_compass needs sensors.compass.enabled'),
            (all(-0.5 < value < 0.5 for value in (
                self.odometry.wheel_radius_error, self.odometry.track_error,
                self.odometry.wheel_radius_error + self.odometry.left_wheel_radius_error,
                self.odometry.wheel_radius_error + self.odometry.right_wheel_radius_error)),
             'odometry.wheel_radius_error, track_error and wheel_radius_error + '
             '(left|right)_wheel_radius_error must be in (-0.5, 0.5)'),
            (self.odometry.integration_method in ODOMETRY_METHODS,
             f'odometry.integration_method must be one of {ODOMETRY_METHODS}'),
            *((spec is None or (0.1 <= spec.answer_timeout <= MAX_ANSWER_TIMEOUT
                                and spec.command and all(spec.command)),
               f'{section}.external: command must be a non-empty list of non-empty strings '
               f'and answer_timeout in [0.1, {MAX_ANSWER_TIMEOUT:g}] s')
              for section, spec in (('tracker', self.tracker.external),
                                    ('odometry', self.odometry.external),
                                    ('controller', self.controller.external))),
        ]
        for ok, message in checks:
            if not ok:
                raise ScenarioError(f'{self.source or self.name}: {message}')


def _short(value: Any) -> str:
    """Return the repr of a value from a file, cut to 60 characters."""
    text = repr(value)
    return text if len(text) <= 60 else f'{text[:57]}...'


def _convert(value: Any, kind: Any, where: str) -> Any:
    if is_dataclass(kind):
        if not isinstance(value, dict):
            raise ScenarioError(f'{where}: expected a mapping, got {_short(value)}')
        return _build(kind, value, where)
    origin = typing.get_origin(kind)
    if origin is typing.Union:   # Optional[<dataclass>]
        return _convert(value, typing.get_args(kind)[0], where)
    if origin is tuple:
        item = typing.get_args(kind)[0]
        if not isinstance(value, (list, tuple)):
            raise ScenarioError(f'{where}: expected a list of '
                                f'{"strings" if item is str else "numbers"}, got {_short(value)}')
        return tuple(_convert(v, item, f'{where}[{i}]') for i, v in enumerate(value))
    if kind is dict:
        if not isinstance(value, dict):
            raise ScenarioError(f'{where}: expected a mapping, got {_short(value)}')
        return dict(value)
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f'{where}: expected a number, got {_short(value)}')
        if abs(value) > 1e300 or not math.isfinite(value):   # 1e300: an int beyond float
            raise ScenarioError(f'{where}: must be a finite number, got {_short(value)}')
        return float(value)
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ScenarioError(f'{where}: expected an integer, got {_short(value)}')
        if abs(value) > INT64_MAX:
            raise ScenarioError(f'{where}: must be within +-(2**63 - 1), got {_short(value)}')
        return value
    if kind is bool:
        if not isinstance(value, bool):
            raise ScenarioError(f'{where}: expected true or false, got {_short(value)}')
        return value
    if kind in (str, Optional[str]):
        if not isinstance(value, str):
            raise ScenarioError(f'{where}: expected a string, got {_short(value)}')
        return value
    raise TypeError(f'{where}: unsupported field type {kind!r}')


def _build(cls: Any, data: dict, where: str) -> Any:
    hints = typing.get_type_hints(cls)
    known = {f.name for f in fields(cls)}
    unknown = sorted(map(str, set(data) - known))
    if unknown:
        raise ScenarioError(f'{where}: unknown key(s) {", ".join(unknown)}; '
                            f'known: {", ".join(sorted(known))}')
    return cls(**{k: _convert(v, hints[k], f'{where}.{k}') for k, v in data.items()})


RANGE_SENSORS = ('laser', 'sonar', 'infrared')


def _normalise(data: dict) -> dict:
    """Fold the free-form sections (path shape arguments, tracker gains) into their fields."""
    data = dict(data)
    if isinstance(data.get('sensors'), dict):
        data['sensors'] = dict(data['sensors'])
        for kind in RANGE_SENSORS:
            if isinstance(data['sensors'].get(kind), dict):
                values = dict(data['sensors'][kind])
                data['sensors'][kind] = {'settings': values, **{
                    k: values.pop(k) for k in ('enabled', 'preset') if k in values}}
    if isinstance(data.get('path'), dict):
        path = dict(data['path'])
        data['path'] = {k: path.pop(k) for k in ('shape', 'frame_id') if k in path}
        data['path']['args'] = path
    for section, fixed, free in (('tracker', ('law', 'external'), 'gains'),
                                 ('reference', ('generator',), 'args'),
                                 ('controller', ('law', 'model_masses', 'use_friction',
                                                 'trial_period', 'task', 'cartesian',
                                                 'external'), 'gains'),
                                 ('navigator', ('behaviour',), 'gains'),
                                 ('planner', ('method', 'goal', 'sonar'), 'options')):
        if isinstance(data.get(section), dict):
            values = dict(data[section])
            data[section] = {free: values, **{k: values.pop(k) for k in fixed if k in values}}
    return data


def _check_sections(data: dict, where: str) -> None:
    """Refuse the sections of the other kind of run (they would be silently ignored)."""
    robot = data.get('robot')
    manipulator = isinstance(robot, dict) and robot.get('type') == 'manipulator'
    foreign = [k for k in (MOBILE_SECTIONS if manipulator else ARM_SECTIONS) if k in data]
    if foreign:
        kind = 'manipulator' if manipulator else 'mobile robot'
        raise ScenarioError(f'{where}: section(s) {", ".join(foreign)} do not apply to a '
                            f'{kind} run')
    if 'navigator' in data and 'tracker' in data:
        raise ScenarioError(f'{where}: sections navigator and tracker: the reactive navigator '
                            'replaces the path tracker; give one of them')
    if 'planner' in data and ('navigator' in data or 'path' in data):
        other = 'navigator' if 'navigator' in data else 'path'
        raise ScenarioError(f'{where}: sections planner and {other}: the planner makes the path '
                            'the tracker follows; give one of them')
    if 'planner' in data and 'world' not in data:
        raise ScenarioError(f'{where}: section planner needs a world: section to plan in')
    for section in ('tracker', 'odometry', 'controller'):
        values = data.get(section)
        if isinstance(values, dict) and 'external' in values and len(values) > 1:
            others = ', '.join(f'{section}.{k}' for k in sorted(map(str, values))
                               if k != 'external')
            raise ScenarioError(f"{where}: {section}.external replaces robotica's own node: "
                                f'{others} would be ignored; remove them (its parameters go in '
                                f'{section}.external.parameters)')


def resolve_scenario_path(name_or_path: str) -> Path:
    """Return the file of a scenario given as a path or as a shipped scenario's name."""
    try:
        return resolve_shipped(name_or_path, 'scenario')
    except FileNotFoundError as err:
        raise ScenarioError(str(err)) from None


def load_scenario(name_or_path: str) -> Scenario:
    """Load and validate a scenario (a YAML file or a shipped scenario's name)."""
    path = resolve_scenario_path(name_or_path)
    data = read_strict_yaml(path, ScenarioError)
    if not isinstance(data, dict):
        raise ScenarioError(f'{path}: a scenario is a YAML mapping, got {_short(data)}')
    data.setdefault('name', path.stem)
    data['source'] = str(path)
    _check_sections(data, str(path))
    scenario = _build(Scenario, _normalise(data), str(path))
    if scenario.world:
        try:   # every key and a map file checked now; the nodes load the same section
            world_from_mapping(scenario.world, path.parent)
        except WorldError as err:
            raise ScenarioError(f'{path}: {err}') from None
    return scenario


def with_overrides(scenario: Scenario, **options: Any) -> Scenario:
    """
    Return ``scenario`` with the command line's values (``duration=60.0``; None: not given).

    An invalid combination names the options, not the file: ``--duration 0.001 (with
    demo.yaml): duration must be at least one step_period (0.02 s), got 0.001 s``.
    """
    given = {key: value for key, value in options.items() if value is not None}
    try:
        return dataclasses.replace(scenario, **given)
    except ScenarioError as err:
        where = scenario.source or scenario.name
        flags = ', '.join(f'--{key.replace("_", "-")} {value}' for key, value in given.items())
        raise ScenarioError(f'{flags} (with {where}): '
                            f'{str(err).removeprefix(f"{where}: ")}') from None
