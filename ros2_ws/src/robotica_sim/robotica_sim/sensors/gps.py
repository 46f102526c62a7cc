"""
GPS / DGPS / RTK position-error model in a local ENU frame (book §7.7.5; catalog §5.7, Part 15).

The book lists the error sources of a GPS fix (ionosphere, troposphere, multipath, Selective
Availability, satellite and receiver clocks, ephemeris) and its accuracy: stand-alone 50-100 m
in the SA era, DGPS 1-5 m and down to a few centimetres with the carrier phase (seed catalog
§5.7 and the GPS/DGPS rows of Part 15). Most of those errors change slowly, so a fix error is
modelled, per ENU axis i, as

    e_i(t_k) = x_i(t_k) + w_i(k),

* x_i: a first-order Gauss–Markov process with correlation time τ and stationary standard
  deviation σ_GM,i, discretised exactly for any interval Δt = t_k - t_(k-1) between fixes:
  x(t_k) = φ x(t_(k-1)) + σ_GM sqrt(1 - φ²) n_k, φ = exp(-Δt/τ), n_k ~ N(0, 1); its
  autocorrelation is σ_GM² exp(-|Δt|/τ). It starts in its stationary distribution.
* w_i: white noise N(0, σ_w²) (receiver noise), independent between fixes.

**Statistics.** ``horizontal_stddev`` and ``vertical_stddev`` are the *total* 1σ per axis
(east and north share the horizontal one; white part included): σ_GM² = σ² - σ_w², and the
reported covariance diag(σ_h², σ_h², σ_v²) [m²] is the honest marginal variance of the error.
Accuracy figures convert to a per-axis σ for a circular normal horizontal error
(r² = e_E² + e_N²): DRMS = sqrt(E[r²]) = √2 σ, **2DRMS = 2√2 σ** (≈ 95-98 % of fixes; the
statistic of the SPS specification and of the SA-era figures), **CEP = sqrt(2 ln 2) σ**
≈ 1.1774 σ (50 % of fixes); a vertical "95 %" or "2σ" figure is 2σ.

**Fixes and time.** :meth:`GpsModel.measure` is called with the simulation time t [s] and the
true antenna position; fixes are due on the grid t0 + k / update_rate anchored at the first call.
A call at or after a due instant returns a :class:`GpsFix` of the position passed in, stamped t
(slots missed between two calls are skipped, so a caller must step at least as fast as the
update rate to get every fix); other calls return ``None``. The node publishes the fix at
``available_at`` = stamp + latency.

**Dropouts.** A two-state Markov chain (signal on/off) steps once per due slot: it loses the
signal with probability p = ``dropout_probability`` and regains it with probability
q = (1 / update_rate) / ``dropout_mean_duration`` (geometric outages, mean duration D =
``dropout_mean_duration``); the fraction of lost fixes is p / (p + q). Several slots at once
use the exact n-step transition P(off after n | on) = p (1 - (1 - p - q)^n) / (p + q) (and
symmetrically). No fix is returned while the signal is off; the Gauss–Markov error keeps
evolving and is sampled at the next fix over the whole interval.

**Status.** ``status`` names the solution and maps to ``sensor_msgs/NavSatStatus`` the way
ROS NMEA drivers map the GGA fix quality (:data:`NAVSAT_STATUS`): 'fix' (GGA 1, stand-alone)
-> STATUS_FIX = 0, 'dgps' (GGA 2, code differential) -> STATUS_SBAS_FIX = 1, 'rtk' (GGA 4/5,
carrier-phase differential) -> STATUS_GBAS_FIX = 2. A base-station DGPS such as the book's is
strictly a ground-based augmentation too; the drivers' mapping is kept so that only a
centimetre-level fix reads as STATUS_GBAS_FIX.
"""

from collections.abc import Mapping
import dataclasses
from dataclasses import dataclass, fields
import math
import numbers
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real
from robotica_kin.geodetic import GeodeticOrigin, ORIGIN_PARAMETERS
from robotica_kin.parameter_specs import (parameter_values, ParameterError, ParameterSpec,
                                          seed_spec)
from robotica_kin.types import Vector
from robotica_kin.urdf import SENSOR_FRAME_PARAMETERS

__all__ = [
    'GPS_PARAMETERS', 'GPS_PRESETS', 'GPS_STATUSES', 'GPS_TERMS', 'GpsFix', 'GpsModel',
    'GpsParams', 'NAVSAT_STATUS', 'gps_configuration', 'gps_params', 'gps_preset',
    'gps_term_specs', 'stddev_from_2drms', 'stddev_from_cep',
]

GPS_STATUSES = ('fix', 'dgps', 'rtk')
"""Solution types of a fix, in increasing accuracy."""

NAVSAT_STATUS: Mapping[str, int] = MappingProxyType({'fix': 0, 'dgps': 1, 'rtk': 2})
"""``sensor_msgs/NavSatStatus.status`` of each solution type: STATUS_FIX, _SBAS_FIX, _GBAS_FIX."""

_TWO_DRMS_PER_SIGMA = 2.0 * math.sqrt(2.0)  # 2DRMS / σ per axis, circular normal
_CEP_PER_SIGMA = math.sqrt(2.0 * math.log(2.0))  # CEP / σ per axis, circular normal
_SLOT_TOL = 1e-6  # [slots] a call this close before a due instant counts as on time


def stddev_from_2drms(two_drms: float) -> float:
    """
    Return the per-axis 1σ [m] of a circular normal horizontal error of given 2DRMS [m].

    2DRMS = 2 sqrt(E[e_E² + e_N²]) = 2√2 σ (module docstring).

    >>> round(stddev_from_2drms(100.0), 3)  # SPS with SA: 100 m 2DRMS
    35.355
    """
    return two_drms / _TWO_DRMS_PER_SIGMA


def stddev_from_cep(cep: float) -> float:
    """
    Return the per-axis 1σ [m] of a circular normal horizontal error of given CEP [m].

    CEP, the radius holding 50 % of the fixes, is sqrt(2 ln 2) σ (Rayleigh median).

    >>> round(stddev_from_cep(2.5), 3)
    2.123
    """
    return cep / _CEP_PER_SIGMA


@dataclass(frozen=True)
class GpsParams:
    """
    Error, rate and availability parameters of a GPS receiver (module docstring).

    The defaults are the ``'standalone'`` preset. Statistics are 1σ per axis of the total
    error (Gauss–Markov plus white); see :func:`stddev_from_2drms`, :func:`stddev_from_cep`.

    Raises
    ------
    ValueError
        If a number is not finite or out of range: stddevs, correlation time, update rate
        and mean outage must be > 0; ``white_stddev`` in [0, min(horizontal, vertical)];
        latency >= 0; ``dropout_probability`` in [0, 1); when it is > 0 the mean outage must
        last at least one fix period; ``status`` one of :data:`GPS_STATUSES`.

    Examples
    --------
    >>> params = GpsParams(horizontal_stddev=3.0, vertical_stddev=5.0, white_stddev=1.0)
    >>> params.covariance.diagonal()
    array([ 9.,  9., 25.])
    >>> params.correlated_stddev ** 2  # the Gauss-Markov share of the variance [m²]
    array([ 8.,  8., 24.])

    """

    horizontal_stddev: float = 2.5 / _CEP_PER_SIGMA  # σ_h [m] per axis (E, N), total
    vertical_stddev: float = 2.0 * 2.5 / _CEP_PER_SIGMA  # σ_v [m] (up), total
    correlation_time: float = 60.0  # τ [s] of the Gauss–Markov part
    white_stddev: float = 0.3  # σ_w [m] per axis, white part (included in σ_h, σ_v)
    update_rate: float = 5.0  # [Hz] fixes per second
    latency: float = 0.1  # [s] from the position's time to the fix's publication
    dropout_probability: float = 0.001  # p [-] of losing the signal at each fix
    dropout_mean_duration: float = 2.0  # D [s] mean outage
    status: str = 'fix'  # solution type, one of GPS_STATUSES

    def __post_init__(self) -> None:
        values = {f.name: finite_real(f.name, getattr(self, f.name))
                  for f in fields(self) if f.name != 'status'}
        for name in ('horizontal_stddev', 'vertical_stddev', 'correlation_time', 'update_rate',
                     'dropout_mean_duration'):
            if not values[name] > 0.0:
                raise ValueError(f'{name} must be > 0, got {values[name]!r}')
        white = values['white_stddev']
        limit = min(values['horizontal_stddev'], values['vertical_stddev'])
        if not 0.0 <= white <= limit:
            raise ValueError(f'white_stddev must be in [0, min(horizontal_stddev, '
                             f'vertical_stddev)] = [0, {limit!r}] m, got {white!r}')
        if not values['latency'] >= 0.0:
            raise ValueError(f'latency must be >= 0 s, got {values["latency"]!r}')
        probability = values['dropout_probability']
        if not 0.0 <= probability < 1.0:
            raise ValueError(f'dropout_probability must be in [0, 1), got {probability!r}')
        period = 1.0 / values['update_rate']
        if probability > 0.0 and values['dropout_mean_duration'] < period:
            raise ValueError(
                f'dropout_mean_duration must be >= one fix period 1/update_rate = {period!r} s '
                f'when dropout_probability > 0, got {values["dropout_mean_duration"]!r}')
        if self.status not in GPS_STATUSES:
            raise ValueError(f'status must be one of {GPS_STATUSES}, got {self.status!r}')

    @property
    def covariance(self) -> NDArray[np.float64]:
        """Total error covariance diag(σ_h², σ_h², σ_v²) [m²] in ENU, shape (3, 3)."""
        return np.diag(np.array([self.horizontal_stddev, self.horizontal_stddev,
                                 self.vertical_stddev]) ** 2)

    @property
    def correlated_stddev(self) -> Vector:
        """Stationary σ_GM = sqrt(σ² - σ_w²) [m] of the Gauss–Markov part, ENU, shape (3,)."""
        return np.sqrt(np.diagonal(self.covariance) - self.white_stddev**2)


# Presets. Accuracy figures are converted to the per-axis 1σ of the total error with the
# statistic named; '(ext.)' marks assumptions from current practice, not from the book.
GPS_PRESETS: Mapping[str, GpsParams] = MappingProxyType({
    # Stand-alone C/A-code GPS with Selective Availability. Book §7.7.5 (seed catalog §5.7 and
    # the GPS row of Part 15): "stand-alone accuracy 50-100 m (SA era)"; the upper figure is
    # the SPS specification of the time (1995 SPS Signal Specification, Annex A: 100 m 2DRMS
    # horizontal, 156 m 2σ vertical), so 2DRMS 100 m and 2σ_v = 156 m. SA dither wandered
    # over minutes: τ = 120 s (ext.); receiver noise 1 m, 1 Hz output, 0.5 s latency (ext.).
    'sa_standalone': GpsParams(
        horizontal_stddev=stddev_from_2drms(100.0),  # 35.36 m
        vertical_stddev=156.0 / 2.0,  # 78 m
        correlation_time=120.0, white_stddev=1.0, update_rate=1.0, latency=0.5,
        dropout_probability=0.001, dropout_mean_duration=10.0, status='fix'),
    # Stand-alone GPS today, SA off (ext.): a single-frequency receiver's datasheet figure of
    # 2.5 m CEP; vertical σ twice the horizontal per-axis σ (VDOP ≈ 2 HDOP); ionosphere,
    # troposphere and ephemeris errors drift over minutes: τ = 60 s; 5 Hz (ext.).
    'standalone': GpsParams(),
    # Code DGPS. Book §7.7.5 (catalog §5.7, DGPS row of Part 15): "DGPS accuracy 1-5 m";
    # its best figure, as modern SBAS/beacon DGPS meets it, read as 2DRMS 1 m (σ = 0.354 m).
    # Vertical 2x (ext.); residual multipath decorrelates in ~30 s (ext.).
    'dgps': GpsParams(
        horizontal_stddev=stddev_from_2drms(1.0),  # 0.354 m
        vertical_stddev=2.0 * stddev_from_2drms(1.0),  # 0.707 m
        correlation_time=30.0, white_stddev=0.1, update_rate=5.0, latency=0.1,
        dropout_probability=0.001, dropout_mean_duration=2.0, status='dgps'),
    # Carrier-phase RTK (fixed ambiguities). Book §7.7.5 (catalog §5.7): DGPS "down to a few
    # centimetres"; current receivers: ~1 cm + 1 ppm horizontal, vertical ~2x (ext.). Taken as
    # 2DRMS 2 cm (σ = 7.1 mm) on a short baseline; τ = 10 s, 10 Hz, 0.05 s latency (ext.).
    'rtk': GpsParams(
        horizontal_stddev=stddev_from_2drms(0.02),  # 7.1 mm
        vertical_stddev=2.0 * stddev_from_2drms(0.02),  # 14.1 mm
        correlation_time=10.0, white_stddev=0.002, update_rate=10.0, latency=0.05,
        dropout_probability=0.001, dropout_mean_duration=2.0, status='rtk'),
})
"""Named receiver presets, from the worst ('sa_standalone') to the best ('rtk')."""


def gps_preset(name: str) -> GpsParams:
    """
    Return the preset :class:`GpsParams` called ``name`` (one of :data:`GPS_PRESETS`).

    Raises ValueError listing the known names for an unknown one.

    >>> gps_preset('rtk').status
    'rtk'
    """
    try:
        return GPS_PRESETS[name]
    except (KeyError, TypeError):
        raise ValueError(
            f'unknown GPS preset {name!r}; known presets: {", ".join(GPS_PRESETS)}') from None


@dataclass(frozen=True, eq=False)
class GpsFix:
    """
    One GPS fix in the local ENU frame (the node converts it to ``sensor_msgs/NavSatFix``).

    Attributes
    ----------
    stamp : float
        Time [s] of the position it reports (the ``t`` of the call that produced it).
    available_at : float
        Time [s] at which the receiver outputs it: ``stamp + latency``.
    enu : ndarray, shape (3,)
        Measured antenna position (east, north, up) [m], read-only.
    covariance : ndarray, shape (3, 3)
        Total error covariance in ENU [m²] (NavSatFix ``position_covariance``, type
        COVARIANCE_TYPE_DIAGONAL_KNOWN), read-only.
    status : str
        Solution type, one of :data:`GPS_STATUSES`.

    """

    stamp: float
    available_at: float
    enu: Vector
    covariance: NDArray[np.float64]
    status: str

    def __post_init__(self) -> None:
        for name, shape in (('enu', (3,)), ('covariance', (3, 3))):
            value = getattr(self, name)
            if isinstance(value, np.ndarray) and not value.flags.writeable:
                array = value  # already read-only (the model's shared covariance)
            else:
                array = np.array(value, dtype=np.float64)
                array.setflags(write=False)
            if array.shape != shape or array.dtype != np.float64:
                raise ValueError(f'{name} must be float64 of shape {shape}, got {value!r}')
            object.__setattr__(self, name, array)
        if self.status not in GPS_STATUSES:
            raise ValueError(f'status must be one of {GPS_STATUSES}, got {self.status!r}')

    @property
    def navsat_status(self) -> int:
        """``sensor_msgs/NavSatStatus.status`` of this fix (:data:`NAVSAT_STATUS`)."""
        return NAVSAT_STATUS[self.status]


class GpsModel:
    """
    A GPS receiver: fixes at the update rate, Gauss–Markov + white error, dropouts.

    See the module docstring for the model. The class holds the fix schedule, the
    Gauss–Markov state and the on/off state; it never reads a clock and draws from its own
    generator only.

    Parameters
    ----------
    params : GpsParams
        Error, rate and availability parameters (e.g. ``gps_preset('dgps')``).
    seed : int or numpy.random.Generator
        Seed (an int >= 0) of the model's generator, or a generator to use.

    Raises
    ------
    ValueError
        If ``params`` is not a GpsParams or ``seed`` is neither an int >= 0 nor a Generator.

    Examples
    --------
    >>> model = GpsModel(GpsParams(update_rate=2.0, latency=0.2, dropout_probability=0.0), 1)
    >>> fix = model.measure(0.0, [10.0, 20.0, 0.0])
    >>> fix.stamp, fix.available_at, fix.status, fix.navsat_status
    (0.0, 0.2, 'fix', 0)
    >>> model.measure(0.25, [10.0, 20.0, 0.0]) is None  # next fix due at 0.5 s
    True

    """

    _params: GpsParams
    _rng: np.random.Generator
    _covariance: NDArray[np.float64]
    _sigma_gm: Vector
    _t0: float | None
    _last_t: float | None
    _next_slot: int
    _last_slot: int
    _signal_on: bool
    _error: Vector | None
    _error_t: float

    def __init__(self, params: GpsParams, seed: int | np.random.Generator) -> None:
        if not isinstance(params, GpsParams):
            raise ValueError(f'params must be a GpsParams, got {params!r}')
        if isinstance(seed, np.random.Generator):
            self._rng = seed
        elif isinstance(seed, numbers.Integral) and not isinstance(seed, bool) and seed >= 0:
            self._rng = np.random.default_rng(int(seed))
        else:
            raise ValueError(f'seed must be an int >= 0 or a numpy Generator, got {seed!r}')
        self._params = params
        self._covariance = params.covariance
        self._covariance.setflags(write=False)  # shared by all fixes
        self._sigma_gm = params.correlated_stddev
        self.reset()

    @property
    def params(self) -> GpsParams:
        """Return the receiver's parameters."""
        return self._params

    @params.setter
    def params(self, params: GpsParams) -> None:
        """
        Change the receiver's parameters from the next call on (a parameter set at run time).

        The error state and the signal go on; the Gauss–Markov error relaxes to its new σ_GM
        with its new τ. A new ``update_rate`` restarts the fix schedule at the next call (a fix
        is then due at once). Raises ValueError unless ``params`` is a GpsParams.
        """
        if not isinstance(params, GpsParams):
            raise ValueError(f'params must be a GpsParams, got {params!r}')
        if params.update_rate != self._params.update_rate:
            self._t0, self._next_slot, self._last_slot = None, 0, -1
        self._params = params
        self._covariance = params.covariance
        self._covariance.setflags(write=False)
        self._sigma_gm = params.correlated_stddev

    def reset(self) -> None:
        """Forget the schedule, the error state and any outage; the generator continues."""
        self._t0 = None
        self._last_t = None
        self._next_slot = 0
        self._last_slot = -1
        self._signal_on = True
        self._error = None
        self._error_t = 0.0

    def measure(self, t: float, true_enu: ArrayLike) -> GpsFix | None:
        """
        Return the fix due at time ``t`` [s] of the true position, or ``None``.

        Parameters
        ----------
        t : float
            Simulation time [s], not earlier than the previous call's.
        true_enu : array_like, shape (3,)
            True antenna position (east, north, up) [m] at ``t``, in the local ENU frame.

        Returns
        -------
        GpsFix or None
            A fix stamped ``t`` when one is due (module docstring), ``None`` between fixes
            and while the signal is lost.

        Raises
        ------
        ValueError
            If ``t`` is not finite or earlier than the previous call's, or ``true_enu`` is
            not a finite vector of shape (3,); the state is then left unchanged.

        """
        t = finite_real('t', t)
        position = np.asarray(true_enu, dtype=np.float64)
        if position.shape != (3,) or not np.isfinite(position).all():
            raise ValueError(f'true_enu must be a finite vector of shape (3,), got {true_enu!r}')
        if self._last_t is not None and t < self._last_t:
            raise ValueError(f'time went backwards: t = {t!r} s after {self._last_t!r} s')
        self._last_t = t
        if self._t0 is None:
            self._t0 = t
        slot = math.floor((t - self._t0) * self._params.update_rate + _SLOT_TOL)
        if slot < self._next_slot:
            return None
        self._next_slot = slot + 1
        self._step_signal(slot - self._last_slot)
        self._last_slot = slot
        if not self._signal_on:
            return None
        noise = self._rng.standard_normal(6)  # Gauss–Markov driving noise, then white noise
        error = self._correlated_error(t, noise[:3]) + self._params.white_stddev * noise[3:]
        return GpsFix(stamp=t, available_at=t + self._params.latency, enu=position + error,
                      covariance=self._covariance, status=self._params.status)

    def _step_signal(self, steps: int) -> None:
        """Advance the on/off chain by ``steps`` >= 1 fix slots (exact n-step transition)."""
        p = self._params.dropout_probability
        if p == 0.0 and self._signal_on:
            return
        q = min(1.0, 1.0 / (self._params.update_rate * self._params.dropout_mean_duration))
        settle = 1.0 - (1.0 - p - q) ** steps
        switch = (p if self._signal_on else q) / (p + q) * settle
        if self._rng.random() < switch:
            self._signal_on = not self._signal_on

    def _correlated_error(self, t: float, noise: Vector) -> Vector:
        """Gauss–Markov error [m] (ENU) at ``t``, exact over the time since the last sample."""
        sigma = self._sigma_gm
        if self._error is None:
            error = sigma * noise
        else:
            ratio = (t - self._error_t) / self._params.correlation_time
            error = (math.exp(-ratio) * self._error
                     + sigma * math.sqrt(-math.expm1(-2.0 * ratio)) * noise)
        self._error, self._error_t = error, t
        return error


GPS_TERMS: dict[str, ParameterSpec] = {
    'horizontal_stddev': ParameterSpec(
        GPS_PRESETS['dgps'].horizontal_stddev, 'Total error std. dev. per horizontal axis '
        '(east, north) sigma_h [m], book §7.7.5 accuracy as 1 sigma (2DRMS = 2 sqrt(2) sigma, '
        'CEP = 1.1774 sigma)', 1e-6, 1e3),
    'vertical_stddev': ParameterSpec(
        GPS_PRESETS['dgps'].vertical_stddev, 'Total error std. dev. up sigma_v [m]; '
        'assumption (ext.): twice sigma_h but for the SA-era 156 m 2 sigma', 1e-6, 1e3),
    'correlation_time': ParameterSpec(
        GPS_PRESETS['dgps'].correlation_time, 'Correlation time tau [s] of the Gauss-Markov '
        'part of the error; assumption (ext.)', 1e-3, 1e6),
    'white_stddev': ParameterSpec(
        GPS_PRESETS['dgps'].white_stddev, 'White part sigma_w [m] per axis, included in '
        'sigma_h and sigma_v (<= both); assumption (ext.)', 0.0, 1e3),
    'update_rate': ParameterSpec(
        GPS_PRESETS['dgps'].update_rate, 'Fixes per second [Hz]; assumption (ext.)',
        1e-3, 1e3),
    'latency': ParameterSpec(
        GPS_PRESETS['dgps'].latency, 'From the position time to the fix output [s]; '
        'assumption (ext.)', 0.0, 60.0),
    'dropout.probability': ParameterSpec(
        GPS_PRESETS['dgps'].dropout_probability, 'Probability p [-] of losing the signal at '
        'each fix; assumption (ext.)', 0.0, 0.999),
    'dropout.mean_duration': ParameterSpec(
        GPS_PRESETS['dgps'].dropout_mean_duration, 'Mean outage D [s], >= one fix period when '
        'p > 0; assumption (ext.)', 1e-3, 1e6),
    'status': ParameterSpec(GPS_PRESETS['dgps'].status, 'Solution type of the fixes '
                            '(NavSatStatus: fix, dgps -> SBAS, rtk -> GBAS)',
                            choices=GPS_STATUSES),
}
"""The fields of :class:`GpsParams` as node parameters, at the default preset's values (each
preset's are :func:`gps_term_specs`); ``dropout.*`` are ``dropout_*``."""

_TERM_FIELDS = {name: name.replace('.', '_') for name in GPS_TERMS}   # parameter -> field

GPS_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('dgps', 'Receiver (book §7.7.5): the starting values of the '
                            'error terms (a term given explicitly overrides it)',
                            choices=tuple(GPS_PRESETS)),
    **ORIGIN_PARAMETERS,
    'antenna_height': SENSOR_FRAME_PARAMETERS['antenna_height'],   # gps_link's, in the URDF
    'seed': seed_spec('Seed of the error draws'),
    **GPS_TERMS,
}
"""The GPS emulator node's parameters by name: :func:`gps_configuration`."""


def gps_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`GPS_TERMS` with the values of the receiver ``preset`` as their defaults.

    The node declares the terms with these defaults once it has read ``preset``, so that a
    term given explicitly overrides the preset's. Raises ParameterError for an unknown preset.

    >>> gps_term_specs('rtk')['update_rate'].default
    10.0
    """
    GPS_PARAMETERS['preset'].check('preset', preset)
    params = GPS_PRESETS[preset]
    return {name: dataclasses.replace(spec, default=getattr(params, _TERM_FIELDS[name]))
            for name, spec in GPS_TERMS.items()}


def gps_params(parameters: Mapping[str, Any]) -> GpsParams:
    """
    Return the receiver of the emulator node's ``parameters`` (names of GPS_PARAMETERS).

    The receiver ``preset`` gives every term; a term in ``parameters`` replaces its value.
    Raises :class:`~robotica_kin.parameter_specs.ParameterError` naming the parameter for a
    value out of its range or choices, or refused by :class:`GpsParams`.

    >>> gps_params({'preset': 'rtk', 'dropout.probability': 0.0}).dropout_probability
    0.0
    >>> gps_params({}) == gps_preset('dgps')
    True
    """
    preset = parameters.get('preset', GPS_PARAMETERS['preset'].default)
    values = parameter_values({**GPS_PARAMETERS, **gps_term_specs(preset)}, parameters)
    try:
        return dataclasses.replace(GPS_PRESETS[preset], **{
            field_name: values[name] for name, field_name in _TERM_FIELDS.items()})
    except ValueError as err:
        name, _, reason = str(err).partition(' ')
        parameter = {field_name: name for name, field_name in _TERM_FIELDS.items()}.get(name)
        raise (ParameterError(parameter, reason) if parameter and reason else err) from None


def gps_configuration(parameters: Mapping[str, Any]) -> tuple[GpsParams, GeodeticOrigin]:
    """
    Return the receiver and the world origin of the emulator node's ``parameters``.

    ``parameters`` holds names of :data:`GPS_PARAMETERS` (missing ones take their defaults:
    the terms the preset's, others are ignored). Raises
    :class:`~robotica_kin.parameter_specs.ParameterError` for a value out of its range or
    choices.

    >>> params, origin = gps_configuration({'preset': 'rtk', 'origin.latitude': 40.0})
    >>> params.status, origin.latitude_deg
    ('rtk', 40.0)
    """
    values = parameter_values(GPS_PARAMETERS, {
        k: v for k, v in parameters.items() if k not in GPS_TERMS})
    return gps_params(parameters), GeodeticOrigin(
        values['origin.latitude'], values['origin.longitude'], values['origin.altitude'])
