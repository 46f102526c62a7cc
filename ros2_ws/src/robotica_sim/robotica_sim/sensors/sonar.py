"""
Ultrasonic sonar ring (book §1.4, §7.4, §12.3): time-of-flight ranges and their failures.

Book §7.4 (seed catalogue Part 5.5 and Part 15): an ultrasonic sensor measures the time of
flight of a pulse (30 kHz – 1 MHz, §1.4), with poor lateral resolution: its beam is a cone. It
fails in two ways the emulator reproduces: beyond a **critical incidence angle** a surface
reflects the pulse away and returns no echo; and by **specular multipath** (fig. 7.19) the
pulse reflected away by a near object O reaches a second surface O' whose echo comes back, so
the sensor reports a range longer than O's: O is missed. One transducer's reading:

1. ``cone_rays`` rays across the cone [-cone_half_angle, cone_half_angle] are cast from the
   transducer on the world model;
2. a ray that meets a surface at an incidence <= ``critical_angle`` gives a direct echo at its
   range r;
3. a ray meeting it beyond the critical angle is reflected specularly (d' = d - 2 (d·n) n) and
   cast again from the hit point; when the second surface is hit, the direction from it to the
   transducer lies within the cone, the way back is clear and the second surface's incidence
   towards the transducer is <= ``critical_angle``, the echo comes back along that path and
   reads half the total path length, (r1 + r2 + r3) / 2, longer than the true distance;
4. the nearest echo of the cone wins (the first to arrive); with none within ``max_range`` the
   reading is ``max_range`` (the book's "no echo"); an echo nearer than ``min_range`` (the
   transducer's ring-down blanking) reads ``min_range``;
5. the range is scaled by ``speed_of_sound`` / c(T), the speed the sensor assumes over the air's
   c(T) = 331.3 √(1 + T / 273.15) m/s at ``air_temperature`` T [°C] (ext.), then takes normal
   noise σ = ``range_noise`` + ``range_noise_per_metre``·r (the S/N falls with distance) and is
   clipped to [min_range, max_range]. A reading of ``max_range`` carries no noise.

A ring fires in a **firing sequence** (:class:`SonarRing`): ``firing_groups`` g groups, the
transducer i in group i mod g, one group per cycle at ``cycle_rate`` [Hz] (g = 1: all at once);
the others keep their last reading. Assumptions (ext.): the cone is a few rays in the plane
(no side lobes, no energy model), the second bounce of multipath is the only one (no third
surface), no crosstalk between transducers fired together, the pulse's flight is instantaneous
against the robot's motion.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.parameter_specs import ParameterSpec, seed_spec
from robotica_kin.world import cast_rays, World
from robotica_sim.sensors.preset_terms import params_from_parameters, preset_term_specs
from robotica_sim.sensors.range_beams import (check_mounts, cone_offsets, mounted_frames,
                                              noisy_readings)

__all__ = ['SONAR_MOUNTS', 'SONAR_PARAMETERS', 'SONAR_PRESETS', 'SONAR_TERMS', 'SonarParams',
           'SonarRing', 'sonar_params', 'sonar_ranges', 'sonar_term_specs', 'speed_of_sound']

_DEG = math.pi / 180.0   # [rad] per degree
_EPSILON = 1e-9          # [m] the second cast starts this far off the first surface


def speed_of_sound(temperature: float) -> float:
    """
    Return the speed of sound in dry air [m/s] at ``temperature`` [°C] (ext.).

    c = 331.3 √(1 + T / 273.15), the ideal-gas law about 0 °C.

    >>> round(speed_of_sound(20.0), 1)
    343.2
    """
    return 331.3 * math.sqrt(1.0 + temperature / 273.15)


@dataclass(frozen=True)
class SonarParams:
    """
    One transducer's beam, ranges and errors (module docstring); defaults: Polaroid 6500-like.

    Raises ValueError for a non-finite term, a cone half-angle outside (0, 90°), fewer than
    one ray, min_range < 0 or >= max_range, a critical angle outside (0, 90°], negative
    noise, a speed of sound <= 0, a temperature below -273.15 °C, groups < 1 or a rate <= 0.
    """

    cone_half_angle: float = 15.0 * _DEG    # [rad] half the beam's width (ext.)
    cone_rays: int = 5                      # rays across the cone (ext.)
    min_range: float = 0.15                 # [m] blanking: nearer echoes read this (ext.)
    max_range: float = 10.7                 # [m] no echo reads this (ext.)
    critical_angle: float = 25.0 * _DEG     # [rad] book §7.4: no echo beyond (value ext.)
    range_noise: float = 0.01               # σ0 [m] (ext.)
    range_noise_per_metre: float = 0.01     # k [m/m]: σ = σ0 + k r, §1.4 low S/N (ext.)
    speed_of_sound: float = 343.2           # [m/s] the speed the sensor assumes (ext.)
    air_temperature: float = 20.0           # [°C] the air's, c(T) (ext.)
    firing_groups: int = 1                  # groups fired in turn, one a cycle (ext.)
    cycle_rate: float = 10.0                # [Hz] firing cycles per second (ext.)

    def __post_init__(self) -> None:
        for name in ('cone_half_angle', 'min_range', 'max_range', 'critical_angle',
                     'range_noise', 'range_noise_per_metre', 'speed_of_sound',
                     'air_temperature', 'cycle_rate'):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f'{name} must be finite, got {getattr(self, name)!r}')
        if not 0.0 < self.cone_half_angle < math.pi / 2:
            raise ValueError(f'cone_half_angle must be in (0, pi/2) rad, got '
                             f'{self.cone_half_angle!r}')
        if not (isinstance(self.cone_rays, int) and self.cone_rays >= 1):
            raise ValueError(f'cone_rays must be an integer >= 1, got {self.cone_rays!r}')
        if not 0.0 <= self.min_range < self.max_range:
            raise ValueError(f'min_range must be >= 0 m and < max_range, got {self.min_range!r}')
        if not 0.0 < self.critical_angle <= math.pi / 2:
            raise ValueError(f'critical_angle must be in (0, pi/2] rad, got '
                             f'{self.critical_angle!r}')
        if not (self.range_noise >= 0.0 and self.range_noise_per_metre >= 0.0):
            raise ValueError('range_noise must be >= 0 m and range_noise_per_metre >= 0, got '
                             f'{self.range_noise!r}, {self.range_noise_per_metre!r}')
        if not self.speed_of_sound > 0.0:
            raise ValueError(f'speed_of_sound must be > 0 m/s, got {self.speed_of_sound!r}')
        if not self.air_temperature > -273.15:
            raise ValueError(f'air_temperature must be > -273.15 °C, got '
                             f'{self.air_temperature!r}')
        if not (isinstance(self.firing_groups, int) and self.firing_groups >= 1):
            raise ValueError(f'firing_groups must be an integer >= 1, got '
                             f'{self.firing_groups!r}')
        if not self.cycle_rate > 0.0:
            raise ValueError(f'cycle_rate must be > 0 Hz, got {self.cycle_rate!r}')

    @property
    def scale(self) -> float:
        """Return the factor of a time-of-flight range: assumed speed over the air's."""
        return self.speed_of_sound / speed_of_sound(self.air_temperature)


# Transducers. The book names the terms (beam cone, max range, critical angle, multipath) but
# gives no numbers: every value is an assumption (ext.) after the makers' published figures.
SONAR_PRESETS: dict[str, SonarParams] = {
    # Polaroid 6500 ranging module with the 600-series electrostatic transducer: 0.15-10.7 m,
    # a beam about 30° wide (±15°), 1 % of range; 16 fired in 4 groups of 4 (ext.).
    'polaroid_6500': SonarParams(firing_groups=4, cycle_rate=20.0),
    # MaxBotix LV-EZ1-like: 0.15-6.45 m, a narrower beam, 2.5 cm resolution, 20 Hz (ext.).
    'maxbotix_ez1': SonarParams(cone_half_angle=10.0 * _DEG, max_range=6.45,
                                range_noise=0.025, range_noise_per_metre=0.005,
                                cycle_rate=20.0),
}
"""Sonar transducers by name; values and sources in the comments of the source."""

_DEFAULT = SONAR_PRESETS['polaroid_6500']

SONAR_MOUNTS = tuple(float(v) for k in range(8) for v in (
    0.2 * math.cos(k * math.pi / 4), 0.2 * math.sin(k * math.pi / 4), k * math.pi / 4))
"""The default ring: 8 transducers every 45° on a circle of 0.2 m, facing out: (x [m], y [m],
yaw [rad]) in base_link, three numbers a transducer (the node's ``mounts``)."""

SONAR_TERMS: dict[str, ParameterSpec] = {
    'cone_half_angle': ParameterSpec(_DEFAULT.cone_half_angle, 'Half the beam cone [rad], '
                                     '§7.4; assumption (ext.)', 1e-3, 1.5),
    'cone_rays': ParameterSpec(_DEFAULT.cone_rays, 'Rays cast across the cone [-]; the '
                               'nearest echo wins; assumption (ext.)', 1, 101),
    'min_range': ParameterSpec(_DEFAULT.min_range, 'Minimum range [m] (blanking); '
                               'assumption (ext.)', 0.0, 100.0),
    'max_range': ParameterSpec(_DEFAULT.max_range, 'Maximum range [m]: no echo reads it, '
                               '§7.4; assumption (ext.)', 0.01, 1000.0),
    'critical_angle': ParameterSpec(_DEFAULT.critical_angle, 'Critical incidence angle '
                                    '[rad]: no echo beyond, §7.4; value assumption (ext.)',
                                    1e-3, math.pi / 2),
    'range_noise': ParameterSpec(_DEFAULT.range_noise, 'Range noise sigma0 [m]; assumption '
                                 '(ext.)', 0.0, 10.0),
    'range_noise_per_metre': ParameterSpec(
        _DEFAULT.range_noise_per_metre, 'Range noise growth k [m/m]: sigma = sigma0 + k r; '
        'assumption (ext.)', 0.0, 1.0),
    'speed_of_sound': ParameterSpec(_DEFAULT.speed_of_sound, 'Speed of sound the sensor '
                                    'assumes [m/s]; assumption (ext.)', 1.0, 2000.0),
    'air_temperature': ParameterSpec(_DEFAULT.air_temperature, 'Air temperature [degC]: '
                                     'c = 331.3 sqrt(1 + T/273.15); assumption (ext.)',
                                     -100.0, 100.0),
    'firing_groups': ParameterSpec(_DEFAULT.firing_groups, 'Groups fired in turn, one per '
                                   'cycle (transducer i in group i mod g) [-]; (ext.)', 1, 64),
    'cycle_rate': ParameterSpec(_DEFAULT.cycle_rate, 'Firing cycles per second [Hz]; '
                                'assumption (ext.)', 1e-3, 1e3),
}
"""The terms of :class:`SonarParams` as node parameters, at the default preset's values."""

SONAR_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('polaroid_6500', 'Sonar transducer: the starting values of the '
                            'terms (a term given explicitly overrides it)',
                            choices=tuple(SONAR_PRESETS)),
    'seed': seed_spec('Seed of the range noise draws'),
    **SONAR_TERMS,
}
"""The sonar emulator node's parameters by name: :func:`sonar_params`."""


def sonar_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`SONAR_TERMS` with the values of the transducer ``preset`` as defaults.

    >>> sonar_term_specs('maxbotix_ez1')['max_range'].default
    6.45
    """
    return preset_term_specs(SONAR_TERMS, SONAR_PRESETS, SONAR_PARAMETERS['preset'], preset)


def sonar_params(parameters: dict) -> SonarParams:
    """
    Return the transducer of the node's ``parameters`` (names of SONAR_PARAMETERS).

    >>> sonar_params({'preset': 'polaroid_6500', 'firing_groups': 2}).firing_groups
    2
    """
    return params_from_parameters(parameters, SONAR_PARAMETERS, SONAR_TERMS, SONAR_PRESETS)


def _echo_paths(params: SonarParams, world: World, origins: NDArray[np.float64],
                axes: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return each ray's echo range [m] (direct or multipath, before scaling); inf: none."""
    p = params
    offsets = cone_offsets(p.cone_half_angle, p.cone_rays)
    angles = (axes[:, None] + offsets).ravel()
    starts = np.repeat(origins, len(offsets), axis=0)
    first = cast_rays(world, starts, angles, 2.0 * p.max_range)
    direct = first.hit & (first.incidence <= p.critical_angle)
    echo = np.where(direct, first.ranges, np.inf)
    lost = np.nonzero(first.hit & ~direct)[0]
    if lost.size:
        d = np.column_stack([np.cos(angles[lost]), np.sin(angles[lost])])
        n = first.normals[lost]
        mirrored = d - 2.0 * (d * n).sum(axis=1)[:, None] * n
        second = cast_rays(world, first.points[lost] + _EPSILON * n,
                           np.arctan2(mirrored[:, 1], mirrored[:, 0]), 2.0 * p.max_range)
        ok = np.nonzero(second.hit)[0]
        i = lost[ok]
        back = starts[i] - second.points[ok]            # from O' to the transducer
        r3 = np.hypot(back[:, 0], back[:, 1])
        u = back / np.maximum(r3, 1e-300)[:, None]
        facing = (second.normals[ok] * u).sum(axis=1)   # cos of O's' incidence to the sensor
        axis_of = np.repeat(axes, len(offsets))[i]
        off_axis = np.abs(np.angle(np.exp(1j * (np.arctan2(-u[:, 1], -u[:, 0]) - axis_of))))
        seen = (facing >= math.cos(p.critical_angle)) & (off_axis <= p.cone_half_angle)
        if seen.any():
            j = np.nonzero(seen)[0]
            way_back = cast_rays(world, starts[i[j]],
                                 np.arctan2(-u[j, 1], -u[j, 0]), 2.0 * p.max_range)
            clear = way_back.ranges >= r3[j] * (1.0 - 1e-9) - 1e-9
            k = i[j][clear]
            echo[k] = 0.5 * (first.ranges[k] + second.ranges[ok][j][clear] + r3[j][clear])
    return echo.reshape(len(axes), len(offsets))


def sonar_ranges(params: SonarParams, world: World, pose: ArrayLike, mounts: ArrayLike,
                 rng: np.random.Generator) -> NDArray[np.float64]:
    """
    Return the readings (n,) [m] of the transducers at ``mounts`` (n, 3) fired together.

    ``pose`` is the robot's (x, y, θ) in the map frame, each mount (x, y, yaw) in
    ``base_link``. The nearest echo of each cone, scaled, noisy and clipped; ``max_range``
    for no echo (module docstring). One normal draw per transducer. Raises ValueError for a
    non-finite pose or bad mounts.

    >>> world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    >>> p = SonarParams(range_noise=0.0, range_noise_per_metre=0.0,
    ...                 speed_of_sound=speed_of_sound(20.0))
    >>> sonar_ranges(p, world, [0, 0, 0], [[0, 0, 0], [0, 0, math.pi]],
    ...              np.random.default_rng(0)).tolist()
    [2.0, 10.7]
    """
    p = params
    origins, axes = mounted_frames(pose, check_mounts(mounts))
    nearest = _echo_paths(p, world, origins, axes).min(axis=1) * p.scale
    heard = nearest <= p.max_range
    return noisy_readings(rng, nearest, heard, p.min_range, p.max_range, p.range_noise,
                          p.range_noise_per_metre)


class SonarRing:
    """
    A ring of transducers at ``mounts`` (n, 3) fired in groups in turn (module docstring).

    :attr:`readings` (n,) holds each transducer's last reading, NaN until it first fires.

    >>> ring = SonarRing(SonarParams(firing_groups=2), [[0, 0, 0], [0, 0, 1], [0, 0, 2]],
    ...                  np.random.default_rng(0))
    >>> [ring.fire(World(), [0, 0, 0]).tolist() for _ in range(3)]
    [[0, 2], [1], [0, 2]]
    >>> ring.readings.tolist()
    [10.7, 10.7, 10.7]
    """

    def __init__(self, params: SonarParams, mounts: ArrayLike,
                 rng: np.random.Generator) -> None:
        if not isinstance(params, SonarParams):
            raise ValueError(f'params must be SonarParams, got {type(params).__name__}')
        self.params = params
        self.mounts = check_mounts(mounts)
        self.readings = np.full(len(self.mounts), np.nan)
        self._rng = rng
        self._cycle = 0

    def fire(self, world: World, pose: ArrayLike) -> NDArray[np.int64]:
        """
        Fire this cycle's group from the robot's ``pose``; return the indices that fired.

        Their readings are updated in :attr:`readings`; the cycle moves to the next group.
        Raises ValueError for a non-finite pose (the cycle does not move).
        """
        group = self._cycle % self.params.firing_groups
        fired = np.arange(group, len(self.mounts), self.params.firing_groups)
        if fired.size:
            self.readings[fired] = sonar_ranges(self.params, world, pose, self.mounts[fired],
                                                self._rng)
        self._cycle += 1
        return fired
