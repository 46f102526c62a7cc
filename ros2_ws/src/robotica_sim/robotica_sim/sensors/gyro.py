"""
Single-axis rate-gyro error model: true angular rate -> measured rate, sample by sample.

Book §7.7.3 (seed catalogue §5.7) describes mechanical, MEMS (Coriolis; "range up to
100 °/s") and optical gyros and names their drift without numbers; Part 15 of the catalogue
lists the error terms an emulator needs (bias, bias instability and random walk, angle random
walk, scale factor, rate saturation, quantisation) and the slides [S] (§13.6) the MEMS parts
(ITG-3200, MPU-6050). The terms follow IEEE Std 952-1997 and Gazebo's IMU noise model
(white noise, a turn-on bias drawn once, a dynamic bias that is a first-order Gauss-Markov
process with a correlation time). One sample over the period dt is

    y = sat(quant((1 + s) ω + b_0 + b_gm + b_rw + n)),

* n: white rate noise (angle random walk), σ_n = N / √dt, N the noise density [rad/s/√Hz]
  (the sample is the mean rate over dt);
* b_0: turn-on bias, ``initial_bias`` plus a normal draw of ``initial_bias_stddev``, constant
  until :meth:`GyroModel.reset`;
* b_gm: first-order Gauss-Markov bias, stationary standard deviation ``bias_instability`` and
  correlation time T, discretised exactly: b_gm <- φ b_gm + σ √(1 - φ²) w, φ = exp(-dt/T);
  it starts in its stationary distribution;
* b_rw: rate random walk, b_rw <- b_rw + K √dt w, K [rad/s²/√Hz = rad/s^1.5], from 0;
* s: scale-factor error; quant rounds to the nearest multiple of ``resolution``; sat clips to
  ±``saturation``.

``bias_instability`` is the Gauss-Markov σ (Gazebo's ``dynamic_bias_stddev``), not the flicker
floor B read off an Allan plot; a Gauss-Markov bias shows on the Allan plot as a hump whose top
is about 0.6 σ at τ of about 2 T. One model is one axis; a 3-axis IMU uses three.
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.parameter_specs import ParameterSpec, seed_spec
from robotica_sim.sensors.preset_terms import params_from_parameters, preset_term_specs
from scipy.signal import lfilter

__all__ = ['GYRO_PARAMETERS', 'GYRO_PRESETS', 'GYRO_TERMS', 'GyroModel', 'GyroParams',
           'gyro_params', 'gyro_term_specs']

_DEG = math.pi / 180.0   # [rad] per degree
_HOUR = 3600.0           # [s] per hour


@dataclass(frozen=True)
class GyroParams:
    """
    Error terms of one gyro axis; the defaults are an ideal gyro (see :data:`GYRO_PRESETS`).

    Raises ValueError for a non-finite or negative term, T <= 0, s <= -1 or saturation <= 0.

    >>> GyroParams(noise_density=1e-4).noise_density
    0.0001
    """

    noise_density: float = 0.0          # N [rad/s/√Hz]: white rate noise (angle random walk)
    bias_instability: float = 0.0       # σ_b [rad/s]: Gauss-Markov bias stationary std. dev.
    bias_correlation_time: float = 100.0  # T [s]: Gauss-Markov correlation time, > 0
    random_walk: float = 0.0            # K [rad/s²/√Hz = rad/s^1.5]: rate random walk
    initial_bias: float = 0.0           # b_0 mean [rad/s]: turn-on bias
    initial_bias_stddev: float = 0.0    # [rad/s]: spread of the turn-on bias (run to run)
    scale_factor_error: float = 0.0     # s [-]: y = (1 + s) ω + ..., > -1
    saturation: float = math.inf        # [rad/s]: output clipped to ±saturation, > 0
    resolution: float = 0.0             # [rad/s]: output quantum (LSB), 0 = none

    def __post_init__(self) -> None:
        for name in ('noise_density', 'bias_instability', 'random_walk', 'initial_bias_stddev',
                     'resolution'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (math.isfinite(self.bias_correlation_time) and self.bias_correlation_time > 0.0):
            raise ValueError('bias_correlation_time must be finite and > 0 s, got '
                             f'{self.bias_correlation_time!r}')
        if not math.isfinite(self.initial_bias):
            raise ValueError(f'initial_bias must be finite, got {self.initial_bias!r}')
        if not (math.isfinite(self.scale_factor_error) and self.scale_factor_error > -1.0):
            raise ValueError('scale_factor_error must be finite and > -1, got '
                             f'{self.scale_factor_error!r}')
        if not (self.saturation > 0.0):  # inf allowed: no saturation
            raise ValueError(f'saturation must be > 0 rad/s (inf: none), got {self.saturation!r}')


# Grades of gyro. Book values (§7.7.3, catalogue Part 15): MEMS range "up to 100 °/s"; nothing
# else is quantified there. MPU-6050 values from its product specification (rate noise spectral
# density 0.005 °/s/√Hz, sensitivity scale-factor tolerance ±3 %). All other numbers are
# assumptions (ext.) of typical order of magnitude for each grade (cf. Groves, "Principles of
# GNSS, Inertial and Multisensor Integrated Navigation Systems", 2nd ed., 2013, ch. 4): the
# turn-on bias is the residual after a still calibration at start-up, and K is chosen so that
# the random-walk line K √(τ/3) reaches the bias-instability level at τ ≈ 10 T.
GYRO_PRESETS: dict[str, GyroParams] = {
    # Consumer MEMS (MPU-6050 / ITG-3200 class, the slides' parts).
    'mems_consumer': GyroParams(
        noise_density=0.005 * _DEG,               # 0.005 °/s/√Hz (MPU-6050)
        bias_instability=20.0 * _DEG / _HOUR,     # 20 °/h (ext.)
        bias_correlation_time=100.0,              # (ext.)
        random_walk=60.0 * _DEG / _HOUR / 60.0,   # 60 °/h/√h (ext.)
        initial_bias_stddev=0.05 * _DEG,          # 0.05 °/s after calibration (ext.)
        scale_factor_error=0.01,                  # 1 %, within MPU-6050's ±3 %
        saturation=100.0 * _DEG,                  # 100 °/s: book §7.7.3 MEMS range
        resolution=200.0 * _DEG / 2 ** 16,        # 16-bit over ±100 °/s (ext.)
    ),
    # Tactical-grade MEMS IMU.
    'mems_tactical': GyroParams(
        noise_density=0.15 * _DEG / 60.0,         # ARW 0.15 °/√h (ext.)
        bias_instability=1.0 * _DEG / _HOUR,      # 1 °/h (ext.)
        bias_correlation_time=300.0,              # (ext.)
        random_walk=2.0 * _DEG / _HOUR / 60.0,    # 2 °/h/√h (ext.)
        initial_bias_stddev=5.0 * _DEG / _HOUR,   # 5 °/h (ext.)
        scale_factor_error=3e-4,                  # 300 ppm (ext.)
        saturation=400.0 * _DEG,                  # 400 °/s (ext.)
        resolution=0.0,                           # 32-bit output: negligible
    ),
    # Closed-loop fibre-optic gyro (one of the five optical technologies of §7.7.3).
    'fog': GyroParams(
        noise_density=0.02 * _DEG / 60.0,         # ARW 0.02 °/√h (ext.)
        bias_instability=0.05 * _DEG / _HOUR,     # 0.05 °/h (ext.)
        bias_correlation_time=1000.0,             # (ext.)
        random_walk=0.05 * _DEG / _HOUR / 60.0,   # 0.05 °/h/√h (ext.)
        initial_bias_stddev=0.5 * _DEG / _HOUR,   # 0.5 °/h (ext.)
        scale_factor_error=1e-4,                  # 100 ppm (ext.)
        saturation=500.0 * _DEG,                  # 500 °/s (ext.)
        resolution=0.0,                           # digital closed loop: negligible
    ),
}
"""Gyro grades by name; values and sources in the comments of the source."""


def _check_dt(dt: float) -> float:
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f'dt must be finite and > 0 s, got {dt!r}')
    return float(dt)


class GyroModel:
    """
    One gyro axis with the error terms of :class:`GyroParams` (module docstring).

    Each sample draws three standard normals (Gauss-Markov, random walk, white noise, in that
    order) from the model's own generator, so :meth:`measure` called n times and
    :meth:`measure_many` on n rates give the same readings (up to rounding) for the same seed.

    Parameters
    ----------
    params : GyroParams
        Error terms.
    seed : int or numpy.random.Generator
        Seed of the model's generator, or a generator to draw from (then shared).

    Examples
    --------
    >>> gyro = GyroModel(GyroParams(initial_bias=0.01, scale_factor_error=0.02), seed=1)
    >>> gyro.measure(1.0, dt=0.01)   # (1 + s) ω + b_0
    1.03
    >>> GyroModel(GyroParams(noise_density=0.001), seed=1).variance(0.01)   # N² / dt
    0.0001

    """

    def __init__(self, params: GyroParams, seed: int | np.random.Generator) -> None:
        if not isinstance(params, GyroParams):
            raise ValueError(f'params must be GyroParams, got {type(params).__name__}')
        self._params = params
        self._rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self._turn_on_bias = 0.0
        self._gm_bias = 0.0
        self._rw_bias = 0.0
        self.reset()

    @property
    def params(self) -> GyroParams:
        """Return the error terms."""
        return self._params

    @params.setter
    def params(self, params: GyroParams) -> None:
        """
        Change the error terms from the next sample on (a parameter set at run time).

        The bias states go on from their values (the Gauss-Markov bias then relaxes to its new
        σ_b with its new T); the turn-on bias is drawn again only by :meth:`reset`.
        Raises ValueError unless ``params`` is a GyroParams.
        """
        if not isinstance(params, GyroParams):
            raise ValueError(f'params must be GyroParams, got {type(params).__name__}')
        self._params = params

    @property
    def bias(self) -> float:
        """Return the current total bias b_0 + b_gm + b_rw [rad/s] (the ground truth)."""
        return self._turn_on_bias + self._gm_bias + self._rw_bias

    def reset(self) -> None:
        """Power the gyro on again: new turn-on bias, stationary Gauss-Markov bias, b_rw = 0."""
        p = self._params
        draw = self._rng.standard_normal(2)
        self._turn_on_bias = p.initial_bias + p.initial_bias_stddev * float(draw[0])
        self._gm_bias = p.bias_instability * float(draw[1])
        self._rw_bias = 0.0

    def variance(self, dt: float) -> float:
        """
        Return the variance [rad²/s²] of the white part of one sample at period ``dt`` [s].

        N²/dt plus the quantisation noise resolution²/12: the covariance an
        ``sensor_msgs/Imu`` message should report (biases are not white and are left out).
        Raises ValueError unless dt is finite and > 0.
        """
        dt = _check_dt(dt)
        p = self._params
        return p.noise_density ** 2 / dt + p.resolution ** 2 / 12.0

    def _output(self, rate: NDArray[np.float64]) -> NDArray[np.float64]:
        p = self._params
        if p.resolution > 0.0:
            rate = p.resolution * np.rint(rate / p.resolution)
        return np.clip(rate, -p.saturation, p.saturation)

    def _gauss_markov_gain(self, dt: float) -> tuple[float, float]:
        p = self._params
        phi = math.exp(-dt / p.bias_correlation_time)
        gain = p.bias_instability * math.sqrt(-math.expm1(-2.0 * dt / p.bias_correlation_time))
        return phi, gain

    def measure(self, true_rate: float, dt: float) -> float:
        """
        Return one reading [rad/s] of the true rate ``true_rate`` [rad/s] over ``dt`` [s].

        The biases advance by dt first, then the sample is formed (module docstring).
        Raises ValueError for a non-finite rate or dt <= 0.
        """
        dt = _check_dt(dt)
        if not math.isfinite(true_rate):
            raise ValueError(f'true_rate must be finite, got {true_rate!r}')
        p = self._params
        w = self._rng.standard_normal(3)
        phi, gain = self._gauss_markov_gain(dt)
        self._gm_bias = phi * self._gm_bias + gain * float(w[0])
        self._rw_bias += p.random_walk * math.sqrt(dt) * float(w[1])
        white = p.noise_density / math.sqrt(dt) * float(w[2])
        ideal = ((1.0 + p.scale_factor_error) * true_rate + self._turn_on_bias + self._gm_bias
                 + self._rw_bias + white)
        return float(self._output(np.array(ideal)))

    def measure_many(self, true_rates: ArrayLike, dt: float) -> NDArray[np.float64]:
        """
        Return readings [rad/s], shape (n,), of the true rates ``true_rates`` (n,) [rad/s].

        The samples are consecutive at the period ``dt`` [s]: the same as n calls of
        :meth:`measure`, vectorised (the Gauss-Markov recursion as a first-order IIR filter,
        the random walk as a cumulative sum). The model's state moves to the last sample.
        Raises ValueError for a non-finite rate, a shape other than (n,) or dt <= 0.
        """
        dt = _check_dt(dt)
        rates = np.asarray(true_rates, dtype=np.float64)
        if rates.ndim != 1:
            raise ValueError(f'true_rates must have shape (n,), got shape {rates.shape}')
        if not np.all(np.isfinite(rates)):
            raise ValueError('true_rates must be finite')
        n = rates.size
        if n == 0:
            return np.empty(0)
        p = self._params
        w = self._rng.standard_normal((n, 3))
        phi, gain = self._gauss_markov_gain(dt)
        gm, _ = lfilter([gain], [1.0, -phi], w[:, 0], zi=[phi * self._gm_bias])
        rw = self._rw_bias + p.random_walk * math.sqrt(dt) * np.cumsum(w[:, 1])
        white = p.noise_density / math.sqrt(dt) * w[:, 2]
        self._gm_bias = float(gm[-1])
        self._rw_bias = float(rw[-1])
        ideal = (1.0 + p.scale_factor_error) * rates + self._turn_on_bias + gm + rw + white
        return self._output(ideal)


GYRO_TERMS: dict[str, ParameterSpec] = {
    'noise_density': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].noise_density,
        'White rate noise density N [rad/s/sqrt(Hz)] (angle random walk), §7.7.3', 0.0, 1.0),
    'bias_instability': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].bias_instability,
        'Gauss-Markov bias stationary std. dev. sigma_b [rad/s], §7.7.3 drift; assumption '
        '(ext.)', 0.0, 1.0),
    'bias_correlation_time': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].bias_correlation_time,
        'Correlation time T [s] of the Gauss-Markov bias; assumption (ext.)', 1e-3, 1e7),
    'random_walk': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].random_walk,
        'Rate random walk K [rad/s^1.5]; assumption (ext.)', 0.0, 1.0),
    'initial_bias': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].initial_bias,
        'Mean turn-on bias b_0 [rad/s]; assumption (ext.)', -1.0, 1.0),
    'initial_bias_stddev': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].initial_bias_stddev,
        'Spread of the turn-on bias, run to run [rad/s]; assumption (ext.)', 0.0, 1.0),
    'scale_factor_error': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].scale_factor_error,
        'Scale-factor error s [-]: y = (1 + s) omega + ...; datasheet (MPU-6050 +-3 %) or '
        'assumption (ext.)', -0.5, 0.5),
    'saturation': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].saturation,
        'Output clipped to +-saturation [rad/s]; book §7.7.3: MEMS range up to 100 deg/s',
        1e-3, 1e4),
    'resolution': ParameterSpec(
        GYRO_PRESETS['mems_consumer'].resolution,
        'Output quantum (LSB) [rad/s], 0: none; assumption (ext.)', 0.0, 1.0),
}
"""The error terms of :class:`GyroParams` as node parameters, at the default preset's values
(each preset's are :func:`gyro_term_specs`)."""

GYRO_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('mems_consumer', 'Gyro grade: the starting values of the error '
                            'terms (a term given explicitly overrides it)',
                            choices=tuple(GYRO_PRESETS)),
    'seed': seed_spec('Seed of the noise and bias draws'),
    **GYRO_TERMS,
}
"""The gyro emulator node's parameters by name: :func:`gyro_params`."""


def gyro_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`GYRO_TERMS` with the values of the grade ``preset`` as their defaults.

    The node declares the terms with these defaults once it has read ``preset``, so that a
    term given explicitly (``-p``, ``--params-file``, a scenario) overrides the preset's.
    Raises ParameterError for an unknown preset.

    >>> gyro_term_specs('fog')['saturation'].default == GYRO_PRESETS['fog'].saturation
    True
    """
    return preset_term_specs(GYRO_TERMS, GYRO_PRESETS, GYRO_PARAMETERS['preset'], preset)


def gyro_params(parameters: Mapping[str, Any]) -> GyroParams:
    """
    Return the gyro of the emulator node's ``parameters`` (names of GYRO_PARAMETERS).

    The grade ``preset`` gives every error term; a term in ``parameters`` replaces its value.
    Raises :class:`~robotica_kin.parameter_specs.ParameterError` naming the parameter for a
    value out of its range or choices, or refused by :class:`GyroParams`.

    >>> gyro_params({'preset': 'fog'}) == GYRO_PRESETS['fog']
    True
    >>> gyro_params({'preset': 'fog', 'noise_density': 1e-3}).noise_density
    0.001
    """
    return params_from_parameters(parameters, GYRO_PARAMETERS, GYRO_TERMS, GYRO_PRESETS)
