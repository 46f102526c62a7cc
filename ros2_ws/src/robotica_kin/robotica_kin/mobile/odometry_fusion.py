"""
Odometry fusion: dead reckoning from encoder ticks (and gyro) in an EKF, with GPS and compass.

The estimator of the odometry node, without ROS: every encoder reading moves the estimate by the
wheels' travel since the previous one, by the slides' equations (catalog §13.6): ΔU = C_m Δticks
with C_m = 2π c / ticks_per_revolution (:func:`metres_per_tick`; each wheel with its own
nominal radius c_L, c_R when they differ), ΔU_c = (ΔU_l + ΔU_r)/2,
Δθ = (ΔU_r − ΔU_l)/b, applied by :func:`robotica_kin.mobile.odometry.odometry_increment` with
one of its rules (``euler``, ``midpoint`` or the exact arc (4.93), book §4.7.5); ΔU_c and Δθ
are the wheel speeds of book (4.109)-(4.110) times the interval. With the heading from a gyro
the heading increment is instead the integral of its yaw rate since the previous reading, and the
encoders give the distance only (synchronous drive, skid steer, slipping wheels; book §7.7.3).

The estimate and its covariance are those of
:class:`robotica_kin.mobile.ekf_localization.EkfLocalization`: the prediction propagates the
odometry error model (:class:`~robotica_kin.mobile.ekf_localization.OdometryNoise`, or the
gyro's variance), and position fixes (local ENU, ``odom``) and compass headings correct it,
each behind the filter's chi-square gate. A measurement is applied when it is added, except
that one newer than the estimate waits in a queue until an encoder reading reaches its time;
one older than the first encoder reading (replayed history) is dropped. After
``max_rejections`` rejections in a row of one sensor the filter is re-opened: the innovation
squared is added to the pose variances and the measurement applied again.

Times [s] come in as arguments (a message's stamp); the class never reads a clock. A stamp more
than :data:`~robotica_kin.bounds.MAX_TIME_JUMP` from the latest encoder reading's is refused
(``time_jumped``) and changes nothing, so that one absurd stamp cannot wedge the estimate; only
:data:`JUMP_CONFIRMATIONS` encoder readings in a row that agree with each other move the time
base there (``time_restarted``: a restarted clock, or a first reading that was the absurd one;
the rule of :class:`~robotica_kin.bounds.StampGate`).
Likewise a travel faster than :data:`~robotica_kin.bounds.MAX_SPEED` is refused
(``travel_refused``) until :data:`JUMP_CONFIRMATIONS` readings in a row make the new counts the
base (``ticks_rebased``: an encoder that was reset). What a node
would log comes back as :class:`FusionEvent` values. Everything is in REP-103 (θ from the x axis,
counter-clockwise), SI units; the pose lives in ``odom``, the twist in ``base_link`` (REP-105).
"""

import dataclasses
from dataclasses import dataclass, field
import math
import numbers
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.bounds import MAX_SPEED, MAX_TIME_JUMP, StampGate
from robotica_kin.finite import finite_real
from robotica_kin.geodetic import ORIGIN_PARAMETERS
from robotica_kin.mobile.ekf_localization import (EkfLocalization, increment_between_poses,
                                                  OdometryNoise)
from robotica_kin.mobile.odometry import odometry_increment, ODOMETRY_METHODS
from robotica_kin.mobile.vehicles import GEOMETRY_PARAMETERS, POSE_PARAMETERS
from robotica_kin.parameter_specs import ParameterSpec
from robotica_kin.types import Pose2D

__all__ = ['EVENT_KINDS', 'FusionEvent', 'GYRO_WAIT_READINGS', 'HEADING_SOURCES',
           'JUMP_CONFIRMATIONS', 'ODOMETRY_PARAMETERS', 'OdometryEstimate', 'OdometryFusion',
           'OdometryFusionParams', 'PENDING_LIMIT', 'SENSORS', 'STAMP_TOLERANCE',
           'metres_per_tick']

HEADING_SOURCES = ('encoders', 'gyro')
ODOMETRY_PARAMETERS: dict[str, ParameterSpec] = {
    'wheel_radius': dataclasses.replace(GEOMETRY_PARAMETERS['wheel_radius'],
                                        description='Nominal wheel radius c [m], book (4.109)'),
    'wheel_separation': dataclasses.replace(
        GEOMETRY_PARAMETERS['track'],
        description='Nominal track b between the odometry wheels [m], book (4.110)'),
    **{f'{side}_wheel_radius': ParameterSpec(
        0.0, f'Nominal {side} wheel radius c_{side[0].upper()} [m], book (4.109) per wheel '
        '(the systematic error of a UMBmark test); 0: wheel_radius', 0.0, 10.0)
       for side in ('left', 'right')},
    **POSE_PARAMETERS, **ORIGIN_PARAMETERS,
}
"""The odometry node's geometry, initial pose (odom frame) and geodetic origin: the ranges of
the simulated vehicle's (:data:`~robotica_kin.mobile.vehicles.GEOMETRY_PARAMETERS`)."""
"""Where the heading increments come from (:attr:`OdometryFusionParams.heading_source`)."""

SENSORS = ('position', 'heading')
"""The corrections: a position fix (GPS/DGPS, ENU) and a heading (compass)."""

EVENT_KINDS = ('waiting_for_gyro', 'went_on_without_samples', 'stale_dropped', 'time_went_back',
               'queue_full', 'invalid_heading', 'refused', 'rejected', 'reopened', 'time_jumped',
               'time_restarted', 'travel_refused', 'ticks_rebased')
"""Kinds of :class:`FusionEvent`, described there."""

PENDING_LIMIT = 1000        # measurements waiting for the estimate to reach their time
GYRO_WAIT_READINGS = 25     # encoder readings that wait for a late gyro/compass (0.5 s at 50 Hz)
STAMP_TOLERANCE = 1e-9      # [s] stamps closer than this are the same time
JUMP_CONFIRMATIONS = 3      # agreeing encoder readings in a row that move the time or tick base


def metres_per_tick(wheel_radius: float, ticks_per_revolution: int) -> float:
    """
    Return the encoder conversion factor C_m = 2π c / ticks_per_revolution [m/tick].

    The slides' C_m = π D / (n C_e) (catalog §13.6) with the wheel diameter D = 2c and the
    counts per wheel revolution n C_e (pulses per revolution × decoding × gear ratio).

    Parameters
    ----------
    wheel_radius : float
        Wheel radius c [m], finite and > 0 (book (4.109)).
    ticks_per_revolution : int
        Encoder counts per wheel revolution, an integer > 0.

    Returns
    -------
    float
        Wheel travel per count [m].

    Raises
    ------
    ValueError
        If ``wheel_radius`` is not finite and > 0 or ``ticks_per_revolution`` is not a
        positive integer.

    Examples
    --------
    >>> metres_per_tick(0.1, 1000)  # 0.6283 mm per count
    0.0006283185307179586

    """
    if (isinstance(ticks_per_revolution, bool)
            or not isinstance(ticks_per_revolution, numbers.Integral)
            or ticks_per_revolution <= 0):
        raise ValueError(
            f'ticks_per_revolution must be an integer > 0, got {ticks_per_revolution!r}')
    if not (math.isfinite(wheel_radius) and wheel_radius > 0.0):
        raise ValueError(f'wheel_radius must be finite and > 0 m, got {wheel_radius!r}')
    return 2.0 * math.pi * wheel_radius / int(ticks_per_revolution)


@dataclass(frozen=True)
class OdometryFusionParams:
    """
    Tunables of :class:`OdometryFusion`; ``__post_init__`` raises ValueError on a bad value.

    >>> OdometryFusionParams(heading_source='gyro').integration_method
    'exact_arc'
    """

    wheel_radius: float = 0.1                 # c [m], book (4.109)
    wheel_separation: float = 0.4             # b [m] between the odometry wheels, book (4.110)
    left_wheel_radius: float = 0.0            # c_L [m] of the left wheel; 0: wheel_radius
    right_wheel_radius: float = 0.0           # c_R [m] of the right wheel; 0: wheel_radius
    integration_method: str = 'exact_arc'     # ODOMETRY_METHODS: slides §13.6, book (4.93)
    heading_source: str = 'encoders'          # HEADING_SOURCES
    odometry_noise: OdometryNoise = field(default_factory=OdometryNoise)   # [m²/m, rad²/...]
    gyro_bias_stddev: float = 1e-3            # [rad/s] gyro bias uncertainty (heading 'gyro')
    gps_bias_stddev: float = 0.0              # σ_b [m] per axis; > 0: two Gauss–Markov states
    gps_bias_correlation_time: float = 60.0   # τ [s] of that GPS error (inf: constant)
    gps_white_stddev: float = 0.0             # σ_w [m] white part of a fix; 0: R - σ_b² I
    wait_for_compass: bool = False            # readings wait for the compass reading of their t
    max_rejections: int = 10                  # gate rejections in a row before re-opening

    def __post_init__(self) -> None:
        """Reject non-finite or out-of-range values and unknown names."""
        for name, unit in (('wheel_radius', 'm'), ('wheel_separation', 'm')):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0 {unit}, got {value!r}')
        for name, unit in (('gyro_bias_stddev', 'rad/s'), ('gps_bias_stddev', 'm'),
                           ('gps_white_stddev', 'm'), ('left_wheel_radius', 'm'),
                           ('right_wheel_radius', 'm')):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0 {unit}, got {value!r}')
        if math.isnan(self.gps_bias_correlation_time) or not self.gps_bias_correlation_time > 0:
            raise ValueError('gps_bias_correlation_time must be > 0 s, got '
                             f'{self.gps_bias_correlation_time!r}')
        if self.integration_method not in ODOMETRY_METHODS:
            raise ValueError(f'integration_method must be one of {ODOMETRY_METHODS}, '
                             f'got {self.integration_method!r}')
        if self.heading_source not in HEADING_SOURCES:
            raise ValueError(f'heading_source must be one of {HEADING_SOURCES}, got '
                             f'{self.heading_source!r}')
        if not isinstance(self.odometry_noise, OdometryNoise):
            raise ValueError(f'odometry_noise must be an OdometryNoise, got '
                             f'{self.odometry_noise!r}')
        if (isinstance(self.max_rejections, bool)
                or not isinstance(self.max_rejections, numbers.Integral)
                or self.max_rejections < 1):
            raise ValueError(f'max_rejections must be an integer >= 1, got '
                             f'{self.max_rejections!r}')

    @property
    def wheel_radii(self) -> tuple[float, float]:
        """
        Return the nominal (c_L, c_R) [m]: each wheel's radius, or ``wheel_radius`` where 0.

        >>> OdometryFusionParams(wheel_radius=0.1, right_wheel_radius=0.101).wheel_radii
        (0.1, 0.101)
        """
        return (self.left_wheel_radius or self.wheel_radius,
                self.right_wheel_radius or self.wheel_radius)


@dataclass(frozen=True)
class FusionEvent:
    """
    Something :class:`OdometryFusion` did that its caller may report; it changes nothing.

    ``kind`` is one of :data:`EVENT_KINDS`:

    * ``waiting_for_gyro``: the first encoder reading waits for a gyro to be connected;
    * ``went_on_without_samples``: the reading of time ``t`` waited for its gyro (or compass)
      sample through :data:`GYRO_WAIT_READINGS` readings and went on with the samples so far;
    * ``stale_dropped``: ``count`` measurements older than the first reading (time ``t``)
      were dropped;
    * ``time_went_back``: a reading of time ``t`` older than the estimate's ``t_previous``
      was ignored;
    * ``queue_full``: the oldest measurement waiting for its time was dropped;
    * ``invalid_heading``: a heading of time ``t`` without a finite yaw and a finite,
      positive variance was ignored;
    * ``refused``: the filter refused a ``sensor`` measurement (``error``: its ValueError);
    * ``rejected``: the innovation gate rejected a ``sensor`` measurement (``count``: gate
      rejections since the start);
    * ``reopened``: after ``max_rejections`` rejections of ``sensor`` in a row the covariance
      was inflated and the measurement tried again (``applied``: whether it then passed);
    * ``time_jumped``: an input of time ``t`` (an encoder reading, or a ``sensor``
      measurement) more than ``MAX_TIME_JUMP`` from the encoder time ``t_previous`` was
      refused;
    * ``time_restarted``: :data:`JUMP_CONFIRMATIONS` agreeing encoder readings in a row so far
      from ``t_previous`` restarted the time base at ``t`` (the pose is kept, the travel in
      between is lost);
    * ``travel_refused``: a reading of time ``t`` whose travel since the previous one is faster
      than ``MAX_SPEED`` was ignored;
    * ``ticks_rebased``: the last of :data:`JUMP_CONFIRMATIONS` such readings in a row became
      the new tick base at ``t`` (its travel is not applied).

    ``sensor`` is one of :data:`SENSORS`; times [s].
    """

    kind: str
    t: float = math.nan
    t_previous: float = math.nan
    sensor: str = ''
    count: int = 0
    error: str = ''
    applied: bool = False


@dataclass(frozen=True)
class OdometryEstimate:
    """
    The estimate once an encoder reading is applied: what an odometry message carries.

    Attributes
    ----------
    t : float
        Time of the reading [s].
    pose : ndarray, shape (3,)
        (x [m], y [m], θ [rad]) of ``base_link`` in ``odom``.
    covariance : ndarray, shape (3, 3)
        Its covariance [m², m·rad, rad²].
    twist : tuple of float
        (v [m/s], ω [rad/s]) in ``base_link`` over the last interval.

    """

    t: float
    pose: Pose2D
    covariance: NDArray[np.float64]
    twist: tuple[float, float]


class _Reading(NamedTuple):
    left_ticks: int
    right_ticks: int
    t: float                  # [s]
    metres_per_tick: tuple[float, float]    # [m/tick] (left, right)


class _Measurement(NamedTuple):
    t: float                  # [s]
    sensor: str               # one of SENSORS
    value: NDArray[np.float64]   # (east, north) [m] or (yaw,) [rad]
    noise: NDArray[np.float64]   # its covariance (2, 2) [m²] or (1, 1) [rad²]


class OdometryFusion:
    """
    Dead reckoning from encoder ticks (and gyro rates) in an EKF, corrected by fixes, headings.

    Feed it with :meth:`add_encoders`, :meth:`add_gyro`, :meth:`add_position` and
    :meth:`add_heading` in any order, and call :meth:`update` to apply the encoder readings
    whose heading increment is known. The first reading after construction or :meth:`reset`
    only starts the estimate (its time and tick counts). Each later one of time t:

    1. turns the tick differences into wheel travels ΔU_l, ΔU_r with :func:`metres_per_tick`;
    2. with ``heading_source='gyro'``, keeps their mean ΔU_c and takes the turn Δθ from the gyro
       samples up to t (each rate held over the interval since the previous sample), so that
       ΔU_r,l = ΔU_c ± b Δθ / 2, and the heading variance is the gyro's Σ σ_k² Δt_k² plus
       k_turn |Δθ| (scale factor) plus (σ_bias (t - t_previous))² (bias);
    3. moves the pose with ``odometry_increment`` (the chosen rule), and predicts the EKF with
       the arc (Δs, Δθ) between the two poses over dt = t - t_previous;
    4. sets the twist v = ΔU_c / dt, ω = (ΔU_r - ΔU_l) / (b dt) (book (4.109)-(4.110));
    5. applies the measurements of time <= t that were waiting, in time order.

    A reading that waits for its gyro sample (or, with ``wait_for_compass``, the compass
    reading of its time) goes on after :data:`GYRO_WAIT_READINGS` readings queued behind it.

    Parameters
    ----------
    params : OdometryFusionParams
        The tunables.
    initial_pose : array_like, shape (3,)
        (x [m], y [m], θ [rad]) of ``base_link`` in ``odom``.
    initial_covariance : array_like, shape (3, 3)
        Its covariance [m², m·rad, rad²], symmetric positive semi-definite.

    Raises
    ------
    ValueError
        If ``params`` is not an :class:`OdometryFusionParams` or the pose or covariance is
        invalid (see :meth:`reset`).

    Examples
    --------
    >>> fusion = OdometryFusion(OdometryFusionParams(wheel_radius=0.1, wheel_separation=0.4),
    ...                         [0.0, 0.0, 0.0], np.zeros((3, 3)))
    >>> fusion.add_encoders(0, 0, 1000, t=0.0)
    >>> fusion.add_encoders(1000, 1000, 1000, t=2.0)  # one revolution each: 2π c forward
    >>> estimates, events = fusion.update()
    >>> [e.t for e in estimates], estimates[-1].pose.round(6), fusion.twist
    ([0.0, 2.0], array([0.628319, 0.      , 0.      ]), (0.3141592653589793, 0.0))

    """

    _params: OdometryFusionParams
    _ekf: EkfLocalization
    _white_variance: float | None
    _last: _Reading | None
    _first_t: float | None
    _twist: tuple[float, float]
    _readings: list[_Reading]
    _gyro_samples: list[tuple[float, float, float]]
    _newest_gyro_t: float | None
    _newest_heading_t: float | None
    _gyro_t: float
    _pending: list[_Measurement]
    _streaks: dict[str, int]
    _rejections: int
    _stamps: StampGate
    _jumped: list[_Reading]
    _untravelled: int
    _events: list[FusionEvent]

    def __init__(self, params: OdometryFusionParams, initial_pose: ArrayLike,
                 initial_covariance: ArrayLike) -> None:
        if not isinstance(params, OdometryFusionParams):
            raise ValueError(f'params must be an OdometryFusionParams, got {params!r}')
        self._params = params
        self._white_variance = (params.gps_white_stddev ** 2 if params.gps_white_stddev > 0.0
                                else None)
        self._ekf = EkfLocalization(initial_pose, initial_covariance, params.odometry_noise,
                                    position_bias_stddev=params.gps_bias_stddev,
                                    position_bias_correlation_time=(
                                        params.gps_bias_correlation_time))
        self.reset(initial_pose, initial_covariance)

    def reset(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """
        Restart from ``pose`` (3,) [m, m, rad] with ``covariance`` (3, 3); forget every input.

        The next encoder reading starts the estimate again; queued readings, gyro samples and
        measurements, the twist and the rejection counts are dropped.

        Raises
        ------
        ValueError
            If the pose is not finite of shape (3,) or the covariance is not a finite,
            symmetric, positive semi-definite 3×3 matrix; the state is then unchanged.

        """
        self._ekf.reset(pose, covariance)
        self._last = None
        self._first_t = None
        self._twist = (0.0, 0.0)
        self._readings = []
        self._gyro_samples = []         # (t [s], rate [rad/s], variance) not yet integrated
        self._newest_gyro_t = None      # [s] stamp of the newest gyro sample received
        self._newest_heading_t = None   # [s] and of the newest compass reading
        self._gyro_t = 0.0              # [s] the gyro is integrated up to here
        self._pending = []
        self._streaks = {}
        self._rejections = 0
        self._stamps = StampGate(MAX_TIME_JUMP, JUMP_CONFIRMATIONS)   # of the encoder readings
        self._jumped = []               # the latest encoder readings refused for their time
        self._untravelled = 0           # readings in a row refused for their travel
        self._events = []               # what add_encoders did, for the next update()

    # -- inputs ------------------------------------------------------------------------------
    def add_encoders(self, left_ticks: int, right_ticks: int, ticks_per_revolution: int,
                     t: float) -> None:
        """
        Queue an encoder reading of time ``t`` [s] for :meth:`update`.

        ``left_ticks``, ``right_ticks`` are the cumulative counts of the odometry wheels
        (increasing forwards) and ``ticks_per_revolution`` their counts per wheel revolution.
        A reading of the same time as the last one queued (within :data:`STAMP_TOLERANCE`)
        replaces it: a state sent again is answered once.

        A reading more than ``MAX_TIME_JUMP`` from the latest one is refused (a
        ``time_jumped`` event at the next :meth:`update`) unless it is the last of
        :data:`JUMP_CONFIRMATIONS` agreeing ones in a row: these restart the time base.

        Raises
        ------
        ValueError
            If a count is not an integer, ``ticks_per_revolution`` is not a positive integer
            or ``t`` is not finite; nothing is queued.

        """
        for name, count in (('left_ticks', left_ticks), ('right_ticks', right_ticks)):
            if isinstance(count, bool) or not isinstance(count, numbers.Integral):
                raise ValueError(f'{name} must be an integer, got {count!r}')
        left_radius, right_radius = self._params.wheel_radii
        reading = _Reading(left_ticks, right_ticks, finite_real('t', t),
                           (metres_per_tick(left_radius, ticks_per_revolution),
                            metres_per_tick(right_radius, ticks_per_revolution)))
        reference = math.nan if self._stamps.latest is None else self._stamps.latest
        try:
            restart = self._stamps.check(reading.t) == 'restart'
        except ValueError:
            self._jumped = self._jumped[1 - JUMP_CONFIRMATIONS:] + [reading]
            self._events.append(FusionEvent('time_jumped', t=reading.t, t_previous=reference))
            return
        if restart:   # the time base moves to the agreeing readings refused so far and this one
            self._events.append(FusionEvent('time_restarted', t=reading.t,
                                            t_previous=reference))
            self._readings, self._last = self._jumped[1 - JUMP_CONFIRMATIONS:] + [reading], None
            self._jumped = []
            return
        self._jumped = []
        if self._readings and abs(self._readings[-1].t - reading.t) <= STAMP_TOLERANCE:
            self._readings[-1] = reading
        else:
            self._readings.append(reading)

    def add_gyro(self, t: float, rate: float, variance: float) -> bool:
        """
        Keep a gyro sample for the heading (``heading_source='gyro'``); return whether it is new.

        Parameters
        ----------
        t : float
            Time of the sample [s]; its rate holds over the interval since the previous sample.
        rate : float
            Yaw rate [rad/s] about the ``base_link`` z axis, counter-clockwise positive.
        variance : float
            Its variance [rad²/s²]; a negative value (unknown) counts as 0.

        Returns
        -------
        bool
            False for a sample not newer than the newest one (a repeat): it is ignored.

        Raises
        ------
        ValueError
            If ``t``, ``rate`` or ``variance`` is not finite, or ``t`` is more than
            ``MAX_TIME_JUMP`` from the encoder time; the sample is ignored.

        """
        if not all(math.isfinite(v) for v in (t, rate, variance)):
            raise ValueError(f'gyro sample must be finite, got t = {t!r} s, rate = {rate!r} '
                             f'rad/s, variance = {variance!r}')
        reference = self._jumped_from(t)
        if reference is not None:
            raise ValueError(f'gyro sample of t = {t!r} s is more than {MAX_TIME_JUMP} s from '
                             f'the encoder time {reference!r} s')
        if self._newest_gyro_t is not None and t <= self._newest_gyro_t + STAMP_TOLERANCE:
            return False
        self._newest_gyro_t = t
        self._gyro_samples.append((t, rate, max(variance, 0.0)))
        return True

    def add_position(self, t: float, position: ArrayLike,
                     covariance: ArrayLike) -> list[FusionEvent]:
        """
        Fuse a position fix of time ``t`` [s] once the estimate has reached ``t``.

        Parameters
        ----------
        t : float
            Time of the fix [s].
        position : array_like, shape (2,)
            (east [m], north [m]) of ``base_link`` in ``odom`` (local ENU).
        covariance : array_like, shape (2, 2)
            Its total covariance [m²] (bias and white part; see
            ``EkfLocalization.update_position``, whose checks apply when it is fused).

        Returns
        -------
        list of FusionEvent
            What happened to it or to the queue (``refused``, ``rejected``, ``reopened``,
            ``queue_full``).

        Raises
        ------
        ValueError
            If ``t`` is not finite.

        """
        value = np.array(position, dtype=np.float64)
        return self._defer(_Measurement(finite_real('t', t), 'position', value,
                                        np.array(covariance, dtype=np.float64)))

    def add_heading(self, t: float, yaw: float, variance: float) -> list[FusionEvent]:
        """
        Fuse a heading (compass) of time ``t`` [s] once the estimate has reached ``t``.

        A reading marks ``t`` as heard from the compass (``wait_for_compass``) even when it is
        unusable: a yaw or variance that is not finite, or a variance <= 0, is not fused and
        gives an ``invalid_heading`` event.

        Parameters
        ----------
        t : float
            Time of the reading [s].
        yaw : float
            Heading θ [rad], REP-103 (from the x (east) axis, counter-clockwise).
        variance : float
            Its variance [rad²], > 0.

        Returns
        -------
        list of FusionEvent
            What happened to it or to the queue.

        Raises
        ------
        ValueError
            If ``t`` is not finite.

        """
        t = finite_real('t', t)
        reference = self._jumped_from(t)
        if reference is not None:
            return [FusionEvent('time_jumped', t=t, t_previous=reference, sensor='heading')]
        self._newest_heading_t = t if self._newest_heading_t is None else max(
            t, self._newest_heading_t)
        if not (math.isfinite(yaw) and math.isfinite(variance) and variance > 0.0):
            return [FusionEvent('invalid_heading', t=t, sensor='heading')]
        return self._defer(_Measurement(t, 'heading', np.array([yaw], dtype=np.float64),
                                        np.array([[variance]], dtype=np.float64)))

    # -- the estimator -----------------------------------------------------------------------
    def update(self, gyro_connected: bool = True) -> tuple[list[OdometryEstimate],
                                                           list[FusionEvent]]:
        """
        Apply the queued encoder readings, in order, each once its heading increment is known.

        With the heading from the gyro, the first reading waits until ``gyro_connected`` (a
        node passes whether a gyro publisher is matched), and a later reading of time t waits
        for the gyro sample of time t; with ``wait_for_compass`` it also waits for the compass
        reading of time t, so that the compass is compared with the estimate of its own time.
        After :data:`GYRO_WAIT_READINGS` readings without them the oldest goes on with the
        samples so far; a sample that comes later still counts, at the next reading.

        Returns
        -------
        estimates : list of OdometryEstimate
            One per reading answered (the first one, each later one, and a repeat of the
            estimate's time, whose travel then counts at the next reading); none for a
            reading older than the estimate.
        events : list of FusionEvent
            What happened on the way, in order.

        """
        estimates: list[OdometryEstimate] = []
        events, self._events = self._events, []
        gyro = self._params.heading_source == 'gyro'
        while self._readings:
            t = self._readings[0].t
            if self._last is None:
                waiting = gyro and not gyro_connected
            else:
                waiting = any(on and (newest is None or newest < t - STAMP_TOLERANCE)
                              for on, newest in (
                                  (gyro, self._newest_gyro_t),
                                  (self._params.wait_for_compass, self._newest_heading_t)))
            if waiting and len(self._readings) <= GYRO_WAIT_READINGS:
                if self._last is None:
                    events.append(FusionEvent('waiting_for_gyro'))
                break
            if waiting:
                events.append(FusionEvent('went_on_without_samples', t=t))
            if self._apply_reading(self._readings.pop(0), events):
                estimates.append(OdometryEstimate(t, self._ekf.pose, self._ekf.covariance,
                                                  self._twist))
        return estimates, events

    def _apply_reading(self, reading: _Reading, events: list[FusionEvent]) -> bool:
        """Apply one encoder reading (steps 1-5 of the class); return whether to answer it."""
        t = reading.t
        if self._last is None:
            self._last = reading
            self._first_t = self._gyro_t = t
            # Replayed history from before the estimate starts (a restarted node): dropped;
            # and what is more than MAX_TIME_JUMP after it (a clock that jumped) too.
            self._gyro_samples = [g for g in self._gyro_samples
                                  if t + STAMP_TOLERANCE < g[0] <= t + MAX_TIME_JUMP]
            self._pending = [p for p in self._pending if p.t <= t + MAX_TIME_JUMP]
            if self._newest_gyro_t is not None and self._newest_gyro_t > t + MAX_TIME_JUMP:
                self._newest_gyro_t = max((g[0] for g in self._gyro_samples), default=None)
            if self._newest_heading_t is not None and self._newest_heading_t > t + MAX_TIME_JUMP:
                self._newest_heading_t = None
            stale = [p for p in self._pending if p.t < t - STAMP_TOLERANCE]
            if stale:
                self._pending = [p for p in self._pending if p.t >= t - STAMP_TOLERANCE]
                events.append(FusionEvent('stale_dropped', t=t, count=len(stale)))
            self._apply_due(t, events)
            return True
        t0 = self._last.t
        if abs(t - t0) <= STAMP_TOLERANCE:   # the same state again (lockstep start-up):
            return True                      # answer it again; any travel counts at the next
        if t < t0:
            events.append(FusionEvent('time_went_back', t=t, t_previous=t0))
            return False
        params = self._params
        left = reading.metres_per_tick[0] * (reading.left_ticks - self._last.left_ticks)
        right = reading.metres_per_tick[1] * (reading.right_ticks - self._last.right_ticks)
        if max(abs(left), abs(right)) > MAX_SPEED * (t - t0):
            self._untravelled += 1
            if self._untravelled < JUMP_CONFIRMATIONS:
                events.append(FusionEvent('travel_refused', t=t, t_previous=t0))
                return False
            events.append(FusionEvent('ticks_rebased', t=t, t_previous=t0))
            self._untravelled, self._last = 0, reading
            return True
        self._untravelled = 0
        self._last = reading
        heading_variance = None
        if params.heading_source == 'gyro':
            angle, gyro_variance = self._gyro_turn(t)
            # Keep the distance of the wheels, take the turn from the gyro (§7.7.3).
            centre, half_turn = 0.5 * (left + right), 0.5 * angle * params.wheel_separation
            left, right = centre - half_turn, centre + half_turn
            # The reported white noise, plus what a gyro's covariance leaves out: its scale
            # factor (k_turn per radian turned) and its bias over the interval.
            heading_variance = (gyro_variance + params.odometry_noise.k_turn * abs(angle)
                                + (params.gyro_bias_stddev * (t - t0)) ** 2)
        before = self._ekf.pose
        after = odometry_increment(before, left, right, params.wheel_separation,
                                   params.integration_method)
        distance, turn = increment_between_poses(before, after)
        self._ekf.predict(distance, turn, heading_variance=heading_variance, dt=t - t0)
        self._twist = (0.5 * (left + right) / (t - t0),
                       (right - left) / params.wheel_separation / (t - t0))
        self._apply_due(t, events)
        return True

    def _jumped_from(self, t: float) -> float | None:
        """Return the encoder time [s] if ``t`` [s] is more than ``MAX_TIME_JUMP`` from it."""
        reference = self._stamps.latest
        return reference if reference is not None and abs(t - reference) > MAX_TIME_JUMP \
            else None

    def _gyro_turn(self, t: float) -> tuple[float, float]:
        """
        Return the turn [rad] and its variance [rad²] from the gyro samples up to time ``t`` [s].

        Each sample's rate holds over the interval since the previous one (the gyro emulator's
        sample period); the first sample of a run covers the time since the first reading.
        """
        angle = variance = 0.0
        while self._gyro_samples and self._gyro_samples[0][0] <= t + STAMP_TOLERANCE:
            sample_t, rate, rate_variance = self._gyro_samples.pop(0)
            dt = max(sample_t - self._gyro_t, 0.0)
            angle += rate * dt
            variance += rate_variance * dt * dt
            self._gyro_t = max(self._gyro_t, sample_t)
        return angle, variance

    def _defer(self, measurement: _Measurement) -> list[FusionEvent]:
        """
        Apply a measurement once the estimate has reached its time.

        The sensors are separate processes: a compass reading of step k may arrive before the
        encoder reading that moves the estimate to step k, and compared with the pose of step
        k - 1 it would carry the turn of one step as an error. It waits in a queue (at most
        :data:`PENDING_LIMIT`) until then; a measurement older than the estimate is applied at
        once, and one older than the first encoder reading (replayed history) is dropped.
        """
        events: list[FusionEvent] = []
        t = measurement.t
        reference = self._jumped_from(t)
        if reference is not None:
            return [FusionEvent('time_jumped', t=t, t_previous=reference,
                                sensor=measurement.sensor)]
        if self._first_t is not None and t < self._first_t - STAMP_TOLERANCE:
            return events
        if self._last is not None and t <= self._last.t + STAMP_TOLERANCE:
            self._correct(measurement, events)
            return events
        if len(self._pending) >= PENDING_LIMIT:
            self._pending.pop(0)
            events.append(FusionEvent('queue_full', t=t))
        self._pending.append(measurement)
        return events

    def _apply_due(self, t: float, events: list[FusionEvent]) -> None:
        """Apply the queued measurements of time <= ``t`` [s], in time order."""
        due = sorted((p for p in self._pending if p.t <= t + STAMP_TOLERANCE),
                     key=lambda p: p.t)
        self._pending = [p for p in self._pending if p.t > t + STAMP_TOLERANCE]
        for measurement in due:
            self._correct(measurement, events)

    def _fuse(self, measurement: _Measurement) -> bool:
        """Apply one measurement through the EKF's gate; True if it passed."""
        if measurement.sensor == 'position':
            return self._ekf.update_position(measurement.value, measurement.noise,
                                             white_variance=self._white_variance)
        return self._ekf.update_heading(float(measurement.value[0]),
                                        float(measurement.noise[0, 0]))

    def _inflation(self, measurement: _Measurement) -> list[float]:
        """Return the innovation squared of a measurement per pose axis [m², m², rad²]."""
        if measurement.sensor == 'position':
            state = self._ekf.state
            predicted = state[:2] + (state[3:5] if state.size == 5 else 0.0)
            east, north = measurement.value
            return [(east - predicted[0]) ** 2, (north - predicted[1]) ** 2, 0.0]
        yaw = float(measurement.value[0])
        return [0.0, 0.0, math.remainder(yaw - self._ekf.pose[2], math.tau) ** 2]

    def _correct(self, measurement: _Measurement, events: list[FusionEvent]) -> None:
        """
        Fuse a measurement; after ``max_rejections`` rejections in a row, re-open the filter.

        A filter that has drifted (a gyro sample lost at start-up, a wheel that slipped) while
        believing itself accurate rejects every correction from then on. After too many
        consecutive rejections of one sensor, its innovation squared is added to the pose
        variances and the measurement is applied again.
        """
        sensor = measurement.sensor
        try:
            accepted = self._fuse(measurement)
        except ValueError as err:
            events.append(FusionEvent('refused', t=measurement.t, sensor=sensor, error=str(err)))
            return
        if accepted:
            self._streaks[sensor] = 0
            return
        self._streaks[sensor] = self._streaks.get(sensor, 0) + 1
        self._rejections += 1
        events.append(FusionEvent('rejected', t=measurement.t, sensor=sensor,
                                  count=self._rejections))
        if self._streaks[sensor] >= self._params.max_rejections:
            covariance = self._ekf.full_covariance
            covariance[np.diag_indices(3)] += self._inflation(measurement)
            self._ekf.reset(self._ekf.state, covariance)
            self._streaks[sensor] = 0
            events.append(FusionEvent('reopened', t=measurement.t, sensor=sensor,
                                      applied=self._fuse(measurement)))

    # -- outputs -----------------------------------------------------------------------------
    @property
    def params(self) -> OdometryFusionParams:
        """Return the tunables."""
        return self._params

    @property
    def pose(self) -> Pose2D:
        """Estimated pose of ``base_link`` in ``odom``: x [m], y [m], θ [rad]; a copy."""
        return self._ekf.pose

    @property
    def covariance(self) -> NDArray[np.float64]:
        """Covariance (3, 3) of the pose [m², m·rad, rad²], a copy."""
        return self._ekf.covariance

    @property
    def twist(self) -> tuple[float, float]:
        """Body velocity (v [m/s], ω [rad/s]) in ``base_link`` over the last interval."""
        return self._twist

    @property
    def time(self) -> float | None:
        """Time [s] of the estimate (the last encoder reading applied); None before the first."""
        return None if self._last is None else self._last.t

    @property
    def rejections(self) -> int:
        """Measurements rejected by the innovation gate since construction or :meth:`reset`."""
        return self._rejections
