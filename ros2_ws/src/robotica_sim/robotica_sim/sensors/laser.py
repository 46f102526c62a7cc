"""
Laser scanner (book §7.4, §12.3): the ranges of a fan of beams, as ``sensor_msgs/LaserScan``.

Book §12.3 (seed catalogue Part 10.2 and Part 15): a time-of-flight or phase-shift laser has
a longer range than ultrasound and is poor at close range (0.3 m ↔ 2 ns round trip at
3·10⁸ m/s, which needs fast electronics); the emulator's terms are min range, range noise and
max range. One scan casts one ray per beam from the scanner's pose at the scan's time, at the
angles ``angle_min + i·angle_increment`` of the scanner's frame (REP-103, counter-clockwise
from its x axis), i = 0 … n - 1, n = floor((angle_max - angle_min) / angle_increment) + 1.
Each beam's reading, in the order of the checks, follows REP-117:

* NaN with probability ``dropout_probability`` (an erroneous reading: no echo decoded; an
  independent draw per beam, (ext.));
* +inf when the beam meets nothing within ``range_max`` (no return);
* -inf when what it meets is nearer than ``range_min`` (too close to measure);
* otherwise the true range r plus normal noise of standard deviation σ = ``range_noise`` +
  ``range_noise_per_metre``·r, clipped to [range_min, range_max] so that a reading stays in
  the message's interval (the clip biases only readings within a few σ of either end).

Assumptions (ext.): a beam is a ray (no spot size, no mixed pixels at edges); the scan is
instantaneous (the robot's motion during the sweep is not modelled, though the message's
``time_increment`` says what a rotating mirror would take); every surface returns the beam
(no reflectivity, glass or black surfaces). The book's 0.3 m ↔ 2 ns is taken as the default
``range_min``; the other defaults are the ``sick_lms200`` preset's.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.parameter_specs import ParameterSpec, seed_spec
from robotica_kin.world import cast_rays, World
from robotica_sim.sensors.preset_terms import params_from_parameters, preset_term_specs
from robotica_sim.sensors.range_beams import check_mounts, mounted_frames

__all__ = ['LASER_PARAMETERS', 'LASER_PRESETS', 'LASER_TERMS', 'LaserModel', 'LaserParams',
           'laser_params', 'laser_term_specs']

_DEG = math.pi / 180.0   # [rad] per degree


@dataclass(frozen=True)
class LaserParams:
    """
    A laser scanner's fan, rate and errors (module docstring); defaults: SICK LMS200-like.

    Raises ValueError for a non-finite term, angle_max <= angle_min, an increment <= 0 or
    wider than the fan, more than 100 000 beams, range_min < 0 or >= range_max, a rate <= 0,
    negative noise or a dropout probability outside [0, 1).

    >>> LaserParams().beams
    361
    """

    angle_min: float = -90.0 * _DEG        # [rad] first beam, in the scanner's frame
    angle_max: float = 90.0 * _DEG         # [rad] last beam (at most)
    angle_increment: float = 0.5 * _DEG    # [rad] between beams
    scan_rate: float = 75.0                # [Hz] scans per second
    range_min: float = 0.3                 # [m] nearer: -inf; book §12.3: 0.3 m ↔ 2 ns
    range_max: float = 80.0                # [m] beyond: +inf (no return)
    range_noise: float = 0.01              # σ0 [m] of a reading (ext.)
    range_noise_per_metre: float = 0.0     # k [m/m]: σ = σ0 + k r (ext.)
    dropout_probability: float = 0.0       # [-] of a NaN reading per beam (ext.)

    def __post_init__(self) -> None:
        for name in ('angle_min', 'angle_max', 'angle_increment', 'scan_rate', 'range_min',
                     'range_max', 'range_noise', 'range_noise_per_metre',
                     'dropout_probability'):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f'{name} must be finite, got {getattr(self, name)!r}')
        if not self.angle_max > self.angle_min:
            raise ValueError(f'angle_max must be > angle_min ({self.angle_min!r} rad), got '
                             f'{self.angle_max!r}')
        if not 0.0 < self.angle_increment <= self.angle_max - self.angle_min:
            raise ValueError('angle_increment must be > 0 and at most angle_max - angle_min, '
                             f'got {self.angle_increment!r}')
        if self.beams > 100_000:
            raise ValueError(f'angle_increment gives {self.beams} beams, more than 100000')
        if not self.scan_rate > 0.0:
            raise ValueError(f'scan_rate must be > 0 Hz, got {self.scan_rate!r}')
        if not 0.0 <= self.range_min < self.range_max:
            raise ValueError(f'range_min must be >= 0 m and < range_max, got {self.range_min!r}')
        if not (self.range_noise >= 0.0 and self.range_noise_per_metre >= 0.0):
            raise ValueError('range_noise must be >= 0 m and range_noise_per_metre >= 0, got '
                             f'{self.range_noise!r}, {self.range_noise_per_metre!r}')
        if not 0.0 <= self.dropout_probability < 1.0:
            raise ValueError('dropout_probability must be in [0, 1), got '
                             f'{self.dropout_probability!r}')

    @property
    def beams(self) -> int:
        """Return the number of beams n of a scan."""
        return int(math.floor((self.angle_max - self.angle_min) / self.angle_increment
                              + 1e-9)) + 1

    @property
    def angles(self) -> NDArray[np.float64]:
        """Return each beam's angle [rad] in the scanner's frame, n of them."""
        return np.asarray(self.angle_min + self.angle_increment * np.arange(self.beams),
                          dtype=np.float64)


# Scanners. The book gives only the 0.3 m ↔ 2 ns of §12.3 (taken as range_min); every other
# number is an assumption (ext.) after the makers' published specifications.
LASER_PRESETS: dict[str, LaserParams] = {
    # SICK LMS200-like, cm mode: 180° fan, 0.5° resolution, 80 m, 75 Hz (the LMS200 sweeps at
    # 75 Hz at 1°; the 0.5° scans interlace two sweeps); σ about 1 cm (ext.).
    'sick_lms200': LaserParams(),
    # SICK LMS200-like, mm mode: 8 m, σ about 5 mm (ext.).
    'sick_lms200_mm': LaserParams(range_max=8.0, range_noise=0.005),
    # Hokuyo URG-04LX-like: 240°, 0.352°, 0.02-4 m, 10 Hz, σ 1 cm (ext.).
    'hokuyo_urg04lx': LaserParams(angle_min=-120.0 * _DEG, angle_max=120.0 * _DEG,
                                  angle_increment=360.0 / 1024.0 * _DEG, scan_rate=10.0,
                                  range_min=0.02, range_max=4.0, range_noise=0.01,
                                  range_noise_per_metre=0.0),
}
"""Laser scanners by name; values and sources in the comments of the source."""

_DEFAULT = LASER_PRESETS['sick_lms200']

LASER_TERMS: dict[str, ParameterSpec] = {
    'angle_min': ParameterSpec(_DEFAULT.angle_min, 'First beam [rad] in the laser frame',
                               -math.pi, math.pi),
    'angle_max': ParameterSpec(_DEFAULT.angle_max, 'Last beam (at most) [rad] in the laser '
                               'frame', -math.pi, math.pi),
    'angle_increment': ParameterSpec(_DEFAULT.angle_increment, 'Angle between beams [rad]',
                                     1e-5, 2.0 * math.pi),
    'scan_rate': ParameterSpec(_DEFAULT.scan_rate, 'Scans per second [Hz]', 1e-3, 1e4),
    'range_min': ParameterSpec(_DEFAULT.range_min, 'Minimum range [m]: nearer reads -inf '
                               '(REP-117); book §12.3: 0.3 m <-> 2 ns', 0.0, 1e3),
    'range_max': ParameterSpec(_DEFAULT.range_max, 'Maximum range [m]: no return beyond '
                               'reads +inf (REP-117)', 1e-3, 1e5),
    'range_noise': ParameterSpec(_DEFAULT.range_noise, 'Range noise sigma0 [m]; assumption '
                                 '(ext.)', 0.0, 10.0),
    'range_noise_per_metre': ParameterSpec(
        _DEFAULT.range_noise_per_metre, 'Range noise growth k [m/m]: sigma = sigma0 + k r; '
        'assumption (ext.)', 0.0, 1.0),
    'dropout_probability': ParameterSpec(
        _DEFAULT.dropout_probability, 'Probability of a NaN (erroneous, REP-117) reading per '
        'beam [-]; assumption (ext.)', 0.0, 0.99),
}
"""The terms of :class:`LaserParams` as node parameters, at the default preset's values."""

LASER_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('sick_lms200', 'Laser scanner: the starting values of the terms '
                            '(a term given explicitly overrides it)',
                            choices=tuple(LASER_PRESETS)),
    'seed': seed_spec('Seed of the noise and dropout draws'),
    **LASER_TERMS,
}
"""The laser emulator node's parameters by name: :func:`laser_params`."""


def laser_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`LASER_TERMS` with the values of the scanner ``preset`` as their defaults.

    >>> laser_term_specs('sick_lms200_mm')['range_max'].default
    8.0
    """
    return preset_term_specs(LASER_TERMS, LASER_PRESETS, LASER_PARAMETERS['preset'], preset)


def laser_params(parameters: dict) -> LaserParams:
    """
    Return the scanner of the node's ``parameters`` (names of LASER_PARAMETERS).

    The ``preset`` gives every term; a term in ``parameters`` replaces its value. Raises
    ParameterError naming the parameter.

    >>> laser_params({'preset': 'hokuyo_urg04lx', 'range_max': 5.6}).range_max
    5.6
    """
    return params_from_parameters(parameters, LASER_PARAMETERS, LASER_TERMS, LASER_PRESETS)


class LaserModel:
    """
    A laser scanner mounted at ``mount`` (x, y, yaw) in ``base_link``, drawing from ``rng``.

    >>> world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    >>> laser = LaserModel(LaserParams(angle_min=-0.1, angle_max=0.1, angle_increment=0.1,
    ...                                range_noise=0.0), np.random.default_rng(0))
    >>> laser.scan(world, [0.0, 0.0, 0.0]).round(6).tolist()   # 2 / cos(0.1), 2, 2 / cos(0.1)
    [2.010042, 2.0, 2.010042]
    """

    def __init__(self, params: LaserParams, rng: np.random.Generator,
                 mount: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        if not isinstance(params, LaserParams):
            raise ValueError(f'params must be LaserParams, got {type(params).__name__}')
        self.params = params
        self._rng = rng
        self._mount = check_mounts(mount, 'mount')

    def scan(self, world: World, pose: ArrayLike) -> NDArray[np.float64]:
        """
        Return one scan's readings (n,) [m] from the robot's ``pose`` (x, y, θ) in the map.

        REP-117: +inf no return, -inf too close, NaN dropout (module docstring).
        Raises ValueError for a non-finite pose.
        """
        p = self.params
        origins, yaws = mounted_frames(pose, self._mount)
        hits = cast_rays(world, origins[0], yaws[0] + p.angles, p.range_max)
        true = hits.ranges
        w = self._rng.standard_normal(true.shape)
        dropped = self._rng.random(true.shape) < p.dropout_probability
        sigma = p.range_noise + p.range_noise_per_metre * np.where(np.isfinite(true), true, 0.0)
        readings = np.clip(true + sigma * w, p.range_min, p.range_max)
        readings[~hits.hit] = np.inf
        readings[hits.hit & (true < p.range_min)] = -np.inf
        readings[dropped] = np.nan
        return readings
