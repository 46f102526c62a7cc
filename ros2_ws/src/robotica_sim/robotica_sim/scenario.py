"""
Scenarios: what a run is made of (robot, path, sensors, tracker, pacing, seed, duration).

A scenario is a YAML file, validated strictly when loaded: an unknown key, a value of the wrong
type or out of range gives a :class:`ScenarioError` naming the key, never a silently ignored
setting. Shipped scenarios live in ``share/robotica_sim/scenarios`` and can be named without
their extension (``robotica run demo``).
"""
from dataclasses import dataclass, field, fields, is_dataclass
import math
from pathlib import Path
import typing
from typing import Any, Optional

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
from robotica_kin.mobile.odometry import ODOMETRY_METHODS
import yaml


class ScenarioError(ValueError):
    """A scenario file that cannot be used; the message names the file and the key."""


@dataclass(frozen=True)
class RobotSpec:
    """The simulated robot (book §4.7.4, differential drive)."""

    type: str = 'differential_drive'  # noqa: A003 (the scenario key)
    wheel_radius: float = 0.1                      # c [m]
    wheel_separation: float = 0.4                  # b [m]
    initial_pose: tuple[float, ...] = (0.0, 0.0, 0.0)   # x [m], y [m], theta [rad] REP-103


@dataclass(frozen=True)
class PathSpec:
    """The reference path: a shape of ``robotica_ctrl.path_shapes`` and its arguments."""

    shape: str = 'rounded_rectangle'
    frame_id: str = 'odom'
    args: dict = field(default_factory=dict)       # keyword arguments of the shape function


@dataclass(frozen=True)
class EncoderSpec:
    """Wheel encoders (book §7.3.2)."""

    ticks_per_revolution: int = 4096               # [ticks/rev]


@dataclass(frozen=True)
class SensorsSpec:
    """Sensor emulators of the run."""

    encoders: EncoderSpec = EncoderSpec()


@dataclass(frozen=True)
class OdometrySpec:
    """Dead reckoning settings."""

    integration_method: str = 'exact_arc'


@dataclass(frozen=True)
class TrackerSpec:
    """The path tracker: its law and the law's gains (parameters ``<law>.<gain>``)."""

    law: str = 'pure_pursuit'
    gains: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Scenario:
    """A whole run."""

    name: str
    description: str = ''
    duration: float = 30.0                         # [s] simulated
    seed: int = 0
    pacing: str = 'lockstep'                       # 'lockstep' or 'realtime'
    step_period: float = 0.02                      # [s] simulated
    robot: RobotSpec = RobotSpec()
    path: PathSpec = PathSpec()
    sensors: SensorsSpec = SensorsSpec()
    odometry: OdometrySpec = OdometrySpec()
    tracker: TrackerSpec = TrackerSpec()
    source: Optional[str] = None                   # the file it was loaded from

    def __post_init__(self) -> None:
        checks = [
            (self.duration > 0.0 and math.isfinite(self.duration), 'duration must be > 0 s'),
            (self.pacing in ('lockstep', 'realtime'), 'pacing must be lockstep or realtime'),
            (0.0 < self.step_period <= 1.0, 'step_period must be in (0, 1] s'),
            (self.robot.type == 'differential_drive',
             'robot.type: only differential_drive is simulated so far'),
            (self.robot.wheel_radius > 0.0, 'robot.wheel_radius must be > 0 m'),
            (self.robot.wheel_separation > 0.0, 'robot.wheel_separation must be > 0 m'),
            (len(self.robot.initial_pose) == 3
             and all(math.isfinite(v) for v in self.robot.initial_pose),
             'robot.initial_pose must be 3 finite numbers [x, y, theta]'),
            (self.sensors.encoders.ticks_per_revolution >= 1,
             'sensors.encoders.ticks_per_revolution must be >= 1'),
            (self.odometry.integration_method in ODOMETRY_METHODS,
             f'odometry.integration_method must be one of {ODOMETRY_METHODS}'),
        ]
        for ok, message in checks:
            if not ok:
                raise ScenarioError(f'{self.source or self.name}: {message}')


def _convert(value: Any, kind: Any, where: str) -> Any:
    if is_dataclass(kind):
        if not isinstance(value, dict):
            raise ScenarioError(f'{where}: expected a mapping, got {value!r}')
        return _build(kind, value, where)
    origin = typing.get_origin(kind)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise ScenarioError(f'{where}: expected a list of numbers, got {value!r}')
        return tuple(_convert(v, float, f'{where}[{i}]') for i, v in enumerate(value))
    if kind is dict:
        if not isinstance(value, dict):
            raise ScenarioError(f'{where}: expected a mapping, got {value!r}')
        return dict(value)
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f'{where}: expected a number, got {value!r}')
        if not math.isfinite(value):
            raise ScenarioError(f'{where}: must be finite, got {value!r}')
        return float(value)
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ScenarioError(f'{where}: expected an integer, got {value!r}')
        return value
    if kind in (str, Optional[str]):
        if not isinstance(value, str):
            raise ScenarioError(f'{where}: expected a string, got {value!r}')
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


def _normalise(data: dict) -> dict:
    """Fold the free-form sections (path shape arguments, tracker gains) into their fields."""
    data = dict(data)
    if isinstance(data.get('path'), dict):
        path = dict(data['path'])
        data['path'] = {k: path.pop(k) for k in ('shape', 'frame_id') if k in path}
        data['path']['args'] = path
    if isinstance(data.get('tracker'), dict):
        tracker = dict(data['tracker'])
        data['tracker'] = {'gains': tracker, **({'law': tracker.pop('law')}
                                                if 'law' in tracker else {})}
    return data


def resolve_scenario_path(name_or_path: str) -> Path:
    """Return the file of a scenario given as a path or as a shipped scenario's name."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    try:
        shipped = Path(get_package_share_directory('robotica_sim')) / 'scenarios'
    except PackageNotFoundError:
        shipped = None
    if shipped is not None:
        for candidate in (shipped / name_or_path, shipped / f'{name_or_path}.yaml'):
            if candidate.is_file():
                return candidate
    names = sorted(p.stem for p in shipped.glob('*.yaml')) if shipped else []
    raise ScenarioError(f'no scenario file {name_or_path!r}; shipped scenarios: '
                        f'{", ".join(names) or "none found"}')


def load_scenario(name_or_path: str) -> Scenario:
    """Load and validate a scenario (a YAML file or a shipped scenario's name)."""
    path = resolve_scenario_path(name_or_path)
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as err:
        raise ScenarioError(f'{path}: not valid YAML: {err}') from None
    if not isinstance(data, dict):
        raise ScenarioError(f'{path}: a scenario is a YAML mapping')
    data.setdefault('name', path.stem)
    data['source'] = str(path)
    return _build(Scenario, _normalise(data), str(path))
