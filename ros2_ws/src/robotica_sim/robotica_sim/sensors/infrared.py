"""
Infrared proximity sensor (book §7.4): a short, narrow beam that sees bright surfaces only.

Book §7.4 (seed catalogue Part 5.5 and Part 15): reflective near-infrared sensors (880 nm for
example) detect within a characteristic range; the emulator's terms are a range threshold and
the target's reflectivity. One reading of a sensor:

1. ``cone_rays`` rays across its narrow cone [-cone_half_angle, cone_half_angle] are cast on the
   world model; the nearest surface within ``max_range`` is the target, at range r;
2. the returned intensity is I = ρ / r² (ρ the target's reflectivity in [0, 1], r in metres: a
   white diffuse surface 1 m away returns about 1), an assumption (ext.) of a diffuse target
   filling the spot; below ``intensity_threshold`` there is no detection and the reading is
   ``max_range`` (as the sonar's "no echo");
3. a target nearer than ``min_range`` reads ``min_range`` (triangulating sensors fold back
   below their minimum; that ambiguity is not modelled, (ext.));
4. the range takes normal noise σ = ``range_noise`` + ``range_noise_per_metre``·r and is
   clipped to [min_range, max_range].

The world model has no reflectivity per element yet, so a world is given one reflectivity,
``default_reflectivity`` unless the caller passes another (ext.). Assumptions (ext.): the spot
is a few rays (no beam profile), no ambient light, no incidence dependence of the return.
"""

from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.parameter_specs import ParameterSpec, seed_spec
from robotica_kin.world import cast_rays, World
from robotica_sim.sensors.preset_terms import params_from_parameters, preset_term_specs
from robotica_sim.sensors.range_beams import (check_mounts, cone_offsets, mounted_frames,
                                              noisy_readings)

__all__ = ['INFRARED_MOUNTS', 'INFRARED_PARAMETERS', 'INFRARED_PRESETS', 'INFRARED_TERMS',
           'InfraredParams', 'infrared_params', 'infrared_ranges', 'infrared_term_specs']

_DEG = math.pi / 180.0   # [rad] per degree


@dataclass(frozen=True)
class InfraredParams:
    """
    One infrared sensor's beam, ranges, threshold and noise; defaults: Sharp GP2Y0A21-like.

    Raises ValueError for a non-finite term, a cone half-angle outside (0, 90°), fewer than
    one ray, min_range < 0 or >= max_range, a negative threshold or noise, a reflectivity
    outside [0, 1] or a rate <= 0.
    """

    cone_half_angle: float = 2.0 * _DEG    # [rad] half the beam (ext.)
    cone_rays: int = 3                     # rays across the cone (ext.)
    min_range: float = 0.1                 # [m] (ext.)
    max_range: float = 0.8                 # [m] nothing detected reads this (ext.)
    intensity_threshold: float = 0.25      # [1/m²] least ρ / r² detected (ext.)
    default_reflectivity: float = 0.5      # ρ [-] of the world's surfaces (ext.)
    range_noise: float = 0.005             # σ0 [m] (ext.)
    range_noise_per_metre: float = 0.02    # k [m/m]: σ = σ0 + k r (ext.)
    rate: float = 26.0                     # [Hz] readings per second (ext.)

    def __post_init__(self) -> None:
        for name in ('cone_half_angle', 'min_range', 'max_range', 'intensity_threshold',
                     'default_reflectivity', 'range_noise', 'range_noise_per_metre', 'rate'):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f'{name} must be finite, got {getattr(self, name)!r}')
        if not 0.0 < self.cone_half_angle < math.pi / 2:
            raise ValueError(f'cone_half_angle must be in (0, pi/2) rad, got '
                             f'{self.cone_half_angle!r}')
        if not (isinstance(self.cone_rays, int) and self.cone_rays >= 1):
            raise ValueError(f'cone_rays must be an integer >= 1, got {self.cone_rays!r}')
        if not 0.0 <= self.min_range < self.max_range:
            raise ValueError(f'min_range must be >= 0 m and < max_range, got {self.min_range!r}')
        if not self.intensity_threshold >= 0.0:
            raise ValueError(f'intensity_threshold must be >= 0, got '
                             f'{self.intensity_threshold!r}')
        if not 0.0 <= self.default_reflectivity <= 1.0:
            raise ValueError(f'default_reflectivity must be in [0, 1], got '
                             f'{self.default_reflectivity!r}')
        if not (self.range_noise >= 0.0 and self.range_noise_per_metre >= 0.0):
            raise ValueError('range_noise must be >= 0 m and range_noise_per_metre >= 0, got '
                             f'{self.range_noise!r}, {self.range_noise_per_metre!r}')
        if not self.rate > 0.0:
            raise ValueError(f'rate must be > 0 Hz, got {self.rate!r}')


# Sensors. The book gives 880 nm as an example wavelength and no numbers for range or
# threshold: every value is an assumption (ext.) after the makers' published figures.
INFRARED_PRESETS: dict[str, InfraredParams] = {
    # Sharp GP2Y0A21YK-like: 0.1-0.8 m, 38 ms a reading; sees 18 % grey paper at 0.8 m
    # (threshold below 0.18 / 0.64 = 0.28) (ext.).
    'sharp_gp2y0a21': InfraredParams(),
    # Sharp GP2Y0A02YK-like: 0.2-1.5 m, 50 ms a reading (ext.).
    'sharp_gp2y0a02': InfraredParams(min_range=0.2, max_range=1.5, intensity_threshold=0.07,
                                     rate=20.0),
}
"""Infrared sensors by name; values and sources in the comments of the source."""

_DEFAULT = INFRARED_PRESETS['sharp_gp2y0a21']

INFRARED_MOUNTS = (0.15, 0.0, 0.0, 0.1, 0.1, 0.785398, 0.1, -0.1, -0.785398)
"""The default sensors: one ahead and two at ±45° at the front corners: (x [m], y [m], yaw
[rad]) in base_link, three numbers a sensor (the node's ``mounts``)."""

INFRARED_TERMS: dict[str, ParameterSpec] = {
    'cone_half_angle': ParameterSpec(_DEFAULT.cone_half_angle, 'Half the beam [rad]; '
                                     'assumption (ext.)', 1e-4, 1.5),
    'cone_rays': ParameterSpec(_DEFAULT.cone_rays, 'Rays cast across the cone [-]; the '
                               'nearest surface is the target; assumption (ext.)', 1, 101),
    'min_range': ParameterSpec(_DEFAULT.min_range, 'Minimum range [m]; assumption (ext.)',
                               0.0, 100.0),
    'max_range': ParameterSpec(_DEFAULT.max_range, 'Maximum range [m]: nothing detected '
                               'reads it; §7.4 characteristic range (ext.)', 1e-3, 100.0),
    'intensity_threshold': ParameterSpec(
        _DEFAULT.intensity_threshold, 'Least returned intensity rho / r^2 [1/m^2] detected, '
        '§7.4 target reflectivity; assumption (ext.)', 0.0, 1e6),
    'default_reflectivity': ParameterSpec(
        _DEFAULT.default_reflectivity, "Reflectivity rho [-] of the world's surfaces; "
        'assumption (ext.)', 0.0, 1.0),
    'range_noise': ParameterSpec(_DEFAULT.range_noise, 'Range noise sigma0 [m]; assumption '
                                 '(ext.)', 0.0, 10.0),
    'range_noise_per_metre': ParameterSpec(
        _DEFAULT.range_noise_per_metre, 'Range noise growth k [m/m]: sigma = sigma0 + k r; '
        'assumption (ext.)', 0.0, 1.0),
    'rate': ParameterSpec(_DEFAULT.rate, 'Readings per second [Hz]; assumption (ext.)',
                          1e-3, 1e4),
}
"""The terms of :class:`InfraredParams` as node parameters, at the default preset's values."""

INFRARED_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('sharp_gp2y0a21', 'Infrared sensor: the starting values of the '
                            'terms (a term given explicitly overrides it)',
                            choices=tuple(INFRARED_PRESETS)),
    'seed': seed_spec('Seed of the range noise draws'),
    **INFRARED_TERMS,
}
"""The infrared emulator node's parameters by name: :func:`infrared_params`."""


def infrared_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`INFRARED_TERMS` with the values of the sensor ``preset`` as defaults.

    >>> infrared_term_specs('sharp_gp2y0a02')['max_range'].default
    1.5
    """
    return preset_term_specs(INFRARED_TERMS, INFRARED_PRESETS, INFRARED_PARAMETERS['preset'],
                             preset)


def infrared_params(parameters: dict) -> InfraredParams:
    """
    Return the sensor of the node's ``parameters`` (names of INFRARED_PARAMETERS).

    >>> infrared_params({'max_range': 0.5}).max_range
    0.5
    """
    return params_from_parameters(parameters, INFRARED_PARAMETERS, INFRARED_TERMS,
                                  INFRARED_PRESETS)


def infrared_ranges(params: InfraredParams, world: World, pose: ArrayLike, mounts: ArrayLike,
                    rng: np.random.Generator,
                    reflectivity: Optional[float] = None) -> NDArray[np.float64]:
    """
    Return the readings (n,) [m] of the sensors at ``mounts`` (n, 3) (module docstring).

    ``pose`` is the robot's (x, y, θ) in the map frame, each mount (x, y, yaw) in
    ``base_link``; ``reflectivity`` ρ of the world's surfaces (None: the params' default).
    ``max_range`` where nothing is detected. One normal draw per sensor. Raises ValueError
    for a non-finite pose, bad mounts or ρ outside [0, 1].

    >>> world = World(walls=[[0.5, -5.0, 0.5, 5.0]])
    >>> p = InfraredParams(range_noise=0.0, range_noise_per_metre=0.0)
    >>> rng = np.random.default_rng(0)
    >>> infrared_ranges(p, world, [0, 0, 0], [[0, 0, 0]], rng).tolist()   # 0.5 / 0.25 = 2
    [0.5]
    >>> infrared_ranges(p, world, [0, 0, 0], [[0, 0, 0]], rng, reflectivity=0.05).tolist()
    [0.8]
    """
    p = params
    rho = p.default_reflectivity if reflectivity is None else float(reflectivity)
    if not 0.0 <= rho <= 1.0:
        raise ValueError(f'reflectivity must be in [0, 1], got {reflectivity!r}')
    origins, axes = mounted_frames(pose, check_mounts(mounts))
    offsets = cone_offsets(p.cone_half_angle, p.cone_rays)
    hits = cast_rays(world, np.repeat(origins, len(offsets), axis=0),
                     (axes[:, None] + offsets).ravel(), p.max_range)
    nearest = hits.ranges.reshape(len(axes), len(offsets)).min(axis=1)
    with np.errstate(divide='ignore'):
        intensity = rho / nearest ** 2
    seen = np.isfinite(nearest) & (intensity >= p.intensity_threshold)
    return noisy_readings(rng, nearest, seen, p.min_range, p.max_range, p.range_noise,
                          p.range_noise_per_metre)
