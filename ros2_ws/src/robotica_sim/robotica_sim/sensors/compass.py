"""
Three-axis magnetometer and the heading a level digital compass computes from it.

Book §7.7.2 (seed catalogue §5.7 and Part 15): a fluxgate compass gives the heading from two
orthogonal horizontal sense windings, θ = atan(V_x / V_y) (7.13) (here atan2); its errors are
the local ferromagnetic deviation (compensated with iron spheres and magnets), the magnetic
declination (place and time, from charts) and tilt (it needs a level platform). The model:

* Earth field in ENU (x east, y north, z up) from the total intensity F, the inclination
  (dip) I, positive downwards, and the declination D, positive east of true north:
  B_w = F (cos I sin D, cos I cos D, -sin I).
* The sensor frame has the attitude R = Rz(ψ) R_tilt in ENU: the robot's yaw ψ (REP-103, from
  east, counter-clockwise) and a tilt ε about a horizontal axis of ``base_link`` at the angle
  ``tilt_axis`` from its x axis (a slope or a mounting error that the compass ignores). The
  field in the sensor frame is Rᵀ B_w (``sensor_msgs/MagneticField`` convention: field in the
  sensor's frame, in tesla).
* Deviation: m = S Rᵀ B_w + h + n with the soft-iron matrix S, the hard-iron offset h [T] and
  white noise n of standard deviation σ per axis.
* Heading, as a level compass computes it with the declination corrected:
  ψ_c = wrap(atan2(m_x, m_y) - D). For a level, iron-free sensor m_x = H sin(ψ + D),
  m_y = H cos(ψ + D) (H = F cos I), so ψ_c = ψ exactly.

Hard iron gives the classical one-cycle deviation (sin ψ, cos ψ), symmetric soft iron a
two-cycle one (sin 2ψ, cos 2ψ), the antisymmetric part of soft iron a constant, and tilt a
one-cycle error of amplitude about ε tan I.
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import finite_real
from robotica_kin.parameter_specs import parameter_values, ParameterSpec, seed_spec

__all__ = ['COMPASS_PARAMETERS', 'CompassModel', 'CompassParams', 'compass_params', 'earth_field',
           'heading_error_curve', 'heading_noise_stddev']

_DEG = math.pi / 180.0  # [rad] per degree


def _readonly(name: str, value: ArrayLike, shape: tuple[int, ...]) -> NDArray[np.float64]:
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be an array of numbers of shape {shape}, got {value!r}') \
            from err
    if array.shape != shape:
        raise ValueError(f'{name} must have shape {shape}, got shape {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'{name} must be finite, got {array!r}')
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class CompassParams:
    """
    Site field and sensor errors of a magnetic compass; the defaults are an ideal sensor.

    The site defaults are the IGRF-13 field at Seville (37.39° N, 5.98° W, sea level, 2025.0):
    F = 43.6 µT, I = 51.1°, D = -0.2° (take F, I, D for another site from the IGRF/WMM or a
    national declination chart, as the book says for D). ``hard_iron`` and ``soft_iron``
    become read-only float64 arrays.

    Raises ValueError for a non-finite value, F <= 0, |I| > π/2, |D| > π, |ε| >= π/2, σ < 0,
    wrong shapes or a singular soft-iron matrix.

    >>> CompassParams().soft_iron
    array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]])
    """

    declination: float = -0.2 * _DEG      # D [rad]: magnetic north east of true north, > 0
    inclination: float = 51.1 * _DEG      # I [rad]: dip below the horizontal, > 0 downwards
    field_strength: float = 43.6e-6       # F [T]: total intensity of the Earth field
    hard_iron: ArrayLike = (0.0, 0.0, 0.0)  # h (3,) [T]: offset in the sensor frame
    soft_iron: ArrayLike = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))  # S (3, 3) [-]
    tilt_error: float = 0.0               # ε [rad]: tilt of the sensor about a horizontal axis
    tilt_axis: float = 0.0                # [rad]: that axis, from base_link x towards y
    noise_stddev: float = 0.0             # σ [T]: white noise per axis

    def __post_init__(self) -> None:
        for name in ('declination', 'inclination', 'field_strength', 'tilt_error', 'tilt_axis',
                     'noise_stddev'):
            finite_real(name, getattr(self, name))
        if abs(self.declination) > math.pi:
            raise ValueError(f'declination must be in [-pi, pi] rad, got {self.declination!r}')
        if abs(self.inclination) > 0.5 * math.pi:
            raise ValueError(f'inclination must be in [-pi/2, pi/2] rad, got {self.inclination!r}')
        if not self.field_strength > 0.0:
            raise ValueError(f'field_strength must be > 0 T, got {self.field_strength!r}')
        if not abs(self.tilt_error) < 0.5 * math.pi:
            raise ValueError(f'tilt_error must be in (-pi/2, pi/2) rad, got {self.tilt_error!r}')
        if self.noise_stddev < 0.0:
            raise ValueError(f'noise_stddev must be >= 0 T, got {self.noise_stddev!r}')
        object.__setattr__(self, 'hard_iron', _readonly('hard_iron', self.hard_iron, (3,)))
        soft_iron = _readonly('soft_iron', self.soft_iron, (3, 3))
        if np.linalg.cond(soft_iron) > 1e12:
            raise ValueError(f'soft_iron must be invertible, got {soft_iron!r}')
        object.__setattr__(self, 'soft_iron', soft_iron)


def earth_field(params: CompassParams) -> NDArray[np.float64]:
    """
    Return the Earth field B_w (3,) [T] in ENU: F (cos I sin D, cos I cos D, -sin I).

    >>> earth_field(CompassParams(declination=0.0, inclination=math.pi / 6.0, field_strength=5e-5))
    array([ 0.00000000e+00,  4.33012702e-05, -2.50000000e-05])
    """
    f, i, d = params.field_strength, params.inclination, params.declination
    return f * np.array([math.cos(i) * math.sin(d), math.cos(i) * math.cos(d), -math.sin(i)])


def _tilt_matrix(params: CompassParams) -> NDArray[np.float64]:
    """Rotation by ε about the unit axis (cos a, sin a, 0) of base_link (Rodrigues)."""
    angle, a = params.tilt_error, params.tilt_axis
    u = np.array([math.cos(a), math.sin(a), 0.0])
    cross = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return (math.cos(angle) * np.eye(3) + math.sin(angle) * cross
            + (1.0 - math.cos(angle)) * np.outer(u, u))


def _sensor_matrix(params: CompassParams) -> NDArray[np.float64]:
    """Return S R_tiltᵀ (3, 3): from the level, yawed frame to the (iron-distorted) reading."""
    return np.asarray(params.soft_iron) @ _tilt_matrix(params).T


def _level_field(b_w: NDArray[np.float64], yaws: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return Rz(ψ)ᵀ B_w, shape (k, 3), for the yaws (k,)."""
    c, s = np.cos(yaws), np.sin(yaws)
    return np.stack([c * b_w[0] + s * b_w[1], -s * b_w[0] + c * b_w[1],
                     np.full_like(yaws, b_w[2])], axis=1)


def _deterministic_field(params: CompassParams, yaws: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return S R_tiltᵀ Rz(ψ)ᵀ B_w + h, shape (k, 3) [T], for the yaws (k,) [rad]."""
    level = _level_field(earth_field(params), yaws)
    return level @ _sensor_matrix(params).T + np.asarray(params.hard_iron)


def _heading(params: CompassParams, field: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the level-compass heading wrap(atan2(m_x, m_y) - D) [rad] of fields (k, 3)."""
    return np.asarray(wrap_to_pi(np.arctan2(field[:, 0], field[:, 1]) - params.declination))


def _as_yaws(yaws: ArrayLike) -> NDArray[np.float64]:
    array = np.asarray(yaws, dtype=np.float64)
    if array.ndim > 1:
        raise ValueError(f'yaws must be a scalar or have shape (k,), got shape {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'yaws must be finite, got {yaws!r}')
    return np.atleast_1d(array)


def heading_error_curve(params: CompassParams, yaws: ArrayLike) -> NDArray[np.float64]:
    """
    Return the compass deviation ψ_c - ψ (k,) [rad], wrapped, at the true yaws ``yaws`` (k,).

    Deterministic (no noise): the deviation curve of hard iron, soft iron and tilt, for plots
    and tests. Raises ValueError for non-finite yaws or a shape other than (k,).

    >>> hard = CompassParams(hard_iron=(0.0, 0.0, 1e-5))   # vertical offset: no deviation
    >>> bool(np.abs(heading_error_curve(hard, np.linspace(-3.0, 3.0, 7))).max() < 1e-15)
    True
    """
    psi = _as_yaws(yaws)
    return np.asarray(wrap_to_pi(_heading(params, _deterministic_field(params, psi)) - psi))


def heading_noise_stddev(params: CompassParams) -> float:
    """
    Return the standard deviation [rad] of the heading due to the field noise.

    σ / (F cos I) to first order for a level, iron-free sensor (only the noise across the
    horizontal field turns the heading): the heading variance a node should report.

    >>> round(heading_noise_stddev(CompassParams(inclination=0.0, field_strength=5e-5,
    ...                                          noise_stddev=5e-7)), 12)
    0.01
    """
    return params.noise_stddev / (params.field_strength * math.cos(params.inclination))


class CompassModel:
    """
    A three-axis magnetometer read as a level digital compass (module docstring).

    Parameters
    ----------
    params : CompassParams
        Site field and sensor errors.
    seed : int or numpy.random.Generator
        Seed of the model's generator, or a generator to draw from (then shared).

    Examples
    --------
    >>> compass = CompassModel(CompassParams(declination=0.0, inclination=0.0,
    ...                                      field_strength=5e-5), seed=0)
    >>> field, heading = compass.measure(math.pi / 2.0)   # facing north: field straight ahead
    >>> np.round(field, 12), round(heading, 12)
    (array([5.e-05, 0.e+00, 0.e+00]), 1.570796326795)

    """

    def __init__(self, params: CompassParams, seed: int | np.random.Generator) -> None:
        if not isinstance(params, CompassParams):
            raise ValueError(f'params must be CompassParams, got {type(params).__name__}')
        self._params = params
        self._rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self._b_w = earth_field(params)
        self._matrix = _sensor_matrix(params)
        self._hard_iron = np.asarray(params.hard_iron)

    @property
    def params(self) -> CompassParams:
        """Return the site field and sensor errors."""
        return self._params

    def measure(self, true_yaw: float) -> tuple[NDArray[np.float64], float]:
        """
        Return one reading at the true yaw ``true_yaw`` [rad] (REP-103, ENU, from east).

        Returns
        -------
        field : ndarray, shape (3,)
            Magnetic field m [T] in the sensor frame (``base_link`` tilted by ε).
        heading : float
            Heading ψ_c [rad] in (-π, π] computed by the compass from m_x, m_y.

        Raises
        ------
        ValueError
            For a non-finite yaw.

        """
        if not math.isfinite(true_yaw):
            raise ValueError(f'true_yaw must be finite, got {true_yaw!r}')
        c, s = math.cos(true_yaw), math.sin(true_yaw)
        b_w = self._b_w
        level = np.array([c * b_w[0] + s * b_w[1], -s * b_w[0] + c * b_w[1], b_w[2]])
        field = (self._matrix @ level + self._hard_iron
                 + self._params.noise_stddev * self._rng.standard_normal(3))
        heading = math.atan2(field[0], field[1]) - self._params.declination
        return field, float(wrap_to_pi(heading))


COMPASS_PARAMETERS: dict[str, ParameterSpec] = {
    'declination': ParameterSpec(CompassParams.declination, 'Magnetic declination [rad], > 0 '
                                 'east', -math.pi, math.pi),
    'inclination': ParameterSpec(CompassParams.inclination, 'Magnetic inclination (dip) [rad], '
                                 '> 0 downwards', -math.pi / 2, math.pi / 2),
    'field_strength': ParameterSpec(CompassParams.field_strength, 'Earth field total intensity '
                                    '[T]', 1e-7, 1e-3),
    'hard_iron': ParameterSpec((0.0, 0.0, 0.0), 'Hard-iron offset (3 values) [T] in the sensor '
                               'frame', -1e-3, 1e-3),
    'soft_iron': ParameterSpec((1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
                               'Soft-iron matrix, 9 values row by row [-]', -1e3, 1e3),
    'tilt_error': ParameterSpec(0.0, 'Tilt of the sensor [rad]', -0.5, 0.5),
    'noise_stddev': ParameterSpec(2e-7, 'White noise per axis [T]', 0.0, 1e-4),
    'seed': seed_spec('Seed of the noise draws'),
}
"""The compass emulator node's parameters by name: :func:`compass_params`."""


def compass_params(parameters: Mapping[str, Any]) -> CompassParams:
    """
    Return the compass of the emulator node's ``parameters`` (names of COMPASS_PARAMETERS).

    Missing names take their defaults, others are ignored. Raises
    :class:`~robotica_kin.parameter_specs.ParameterError` for a value out of its range and
    ValueError as :class:`CompassParams` (e.g. a singular soft-iron matrix).

    >>> compass_params({'tilt_error': 0.1}).tilt_error
    0.1
    """
    values = parameter_values(COMPASS_PARAMETERS, parameters)
    if len(values['soft_iron']) != 9:
        raise ValueError(f'soft_iron must have 9 values (3x3 row by row), got '
                         f'{len(values["soft_iron"])}')
    soft_iron = values['soft_iron']
    return CompassParams(**{name: values[name] for name in (
        'declination', 'inclination', 'field_strength', 'tilt_error', 'noise_stddev')},
        hard_iron=tuple(values['hard_iron']),
        soft_iron=tuple(tuple(soft_iron[3 * i:3 * i + 3]) for i in range(3)))
