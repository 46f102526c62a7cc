"""
Extended Kalman filter that fuses odometry with GPS position fixes and compass headings.

The state is the planar pose (x [m], y [m], θ [rad]) of ``base_link`` in the local ENU frame
(``odom``; REP-103: θ from the x (east) axis, counter-clockwise) and its 3×3 covariance P,
optionally augmented with the time-correlated error (b_E, b_N) [m] of the GPS fixes.

* **Prediction** from an odometry increment (Δs [m], Δθ [rad]): the exact circular arc of book
  (4.93) (§4.7.2; the same update as :func:`robotica_kin.mobile.odometry.odometry_increment`
  'exact_arc', written in its chord form, smooth through Δθ = 0), so dead reckoning (4.131)
  (§4.7.5) is what the filter does between fixes. Δs = ΔU_c and Δθ come from the wheel encoders
  (slides [S]: ΔU_c = (ΔU_i + ΔU_d)/2, Δθ = (ΔU_d - ΔU_i)/b), or Δθ from an integrated gyro.
* **Odometry noise**: the proportional error model of :class:`OdometryNoise` (standard practice,
  not in the book: the book and the slides only say that odometry errors grow with the
  distance travelled, catalog §2.9, §13.6).
* **Corrections**: a GPS/DGPS position fix already converted to the local ENU frame (book
  §7.7.5: DGPS 1-5 m) and a compass heading (book §7.7.2), each behind a chi-square innovation
  gate; covariance update in Joseph form.
* **Time-correlated GPS error** (optional): the slowly varying error of the fixes (book
  §7.7.5: atmosphere, multipath, ...) as two more states, a first-order Gauss–Markov process
  per ENU axis (shaping-filter augmentation, Gelb 1974 §4.5; not in the book), so that fixes at
  several hertz do not make the filter overconfident (see :class:`EkfLocalization`).

Seed catalog sections 2.7, 2.9, 5.7, 13.5 and 13.6. The estimator, the motion model and its
Jacobians are separate functions, in the manner of PythonRobotics' EKF example.
"""

from dataclasses import dataclass
import math
import numbers

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import finite_real
from robotica_kin.types import Pose2D, Vector
from scipy.special import gammaincinv

__all__ = [
    'EkfLocalization',
    'OdometryNoise',
    'WHITE_VARIANCE_FLOOR_RATIO',
    'chi_square_threshold',
    'increment_between_poses',
    'motion_jacobians',
    'motion_model',
]

_SERIES_HALF_ANGLE = 0.1  # |Δθ/2| [rad] below which d/dh (sin h / h) uses its Taylor series
_SYMMETRY_TOLERANCE = 1e-9  # relative asymmetry / negative eigenvalue tolerated in a covariance

WHITE_VARIANCE_FLOOR_RATIO = 1e-2
"""Floor of the white fix variance, as a fraction of σ_b², when it is derived from a total R."""


# --- validation helpers -------------------------------------------------------------------


def _nonnegative_scalar(value: float, name: str, unit: str) -> float:
    number = finite_real(name, value)
    if number < 0.0:
        raise ValueError(f'{name} must be >= 0 {unit}, got {value!r}')
    return number


def _finite_array(value: ArrayLike, shape: tuple[int, ...], name: str) -> NDArray[np.float64]:
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be a real array of shape {shape}, got {value!r}') from None
    if array.shape != shape:
        raise ValueError(f'{name} must have shape {shape}, got {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'{name} must be finite, got {array!r}')
    return array


def _covariance(value: ArrayLike, size: int, name: str) -> NDArray[np.float64]:
    """Return ``value`` as a symmetric positive semi-definite (size, size) matrix."""
    matrix = _finite_array(value, (size, size), name)
    scale = max(float(np.max(np.abs(matrix))), np.finfo(np.float64).tiny)
    if np.max(np.abs(matrix - matrix.T)) > _SYMMETRY_TOLERANCE * scale:
        raise ValueError(f'{name} must be symmetric, got {matrix!r}')
    matrix = 0.5 * (matrix + matrix.T)
    if np.min(np.linalg.eigvalsh(matrix)) < -_SYMMETRY_TOLERANCE * scale:
        raise ValueError(f'{name} must be positive semi-definite, got {matrix!r}')
    return matrix


def _pose(value: ArrayLike, name: str = 'pose') -> Pose2D:
    pose = _finite_array(value, (3,), name)
    pose[2] = wrap_to_pi(float(pose[2]))
    return pose


# --- noise model and gate -----------------------------------------------------------------


@dataclass(frozen=True)
class OdometryNoise:
    """
    Proportional odometry error model: variances that grow with the distance and the turn.

    For an increment (Δs, Δθ) the odometry errors are taken as independent and zero-mean with

    * var(Δs) = k_distance |Δs|,
    * var(Δθ) = k_heading |Δs| + k_turn |Δθ|,

    so that over a path the variances add up in proportion to the distance travelled and the
    angle turned (standard practice, in the spirit of Chong & Kleeman 1997 whose per-wheel
    variances grow with the distance each wheel rolls; not in the book, whose §4.7.5 and the
    slides [S] only state that the error accumulates). Each coefficient must be finite and
    >= 0; ``__post_init__`` raises ValueError otherwise. The defaults are assumptions for a
    small indoor differential-drive robot (σ_s ≈ 3 cm and σ_θ ≈ 0.6° after 1 m straight).

    >>> OdometryNoise(k_distance=1e-3, k_heading=1e-4, k_turn=1e-3).covariance(2.0, 0.5)
    array([[0.002 , 0.    ],
           [0.    , 0.0007]])
    """

    k_distance: float = 1e-3  # [m²/m] variance of the travelled distance per metre
    k_heading: float = 1e-4  # [rad²/m] heading variance per metre travelled
    k_turn: float = 1e-3  # [rad²/rad] heading variance per radian turned

    def __post_init__(self) -> None:
        """Reject non-finite or negative coefficients."""
        for name, unit in (('k_distance', 'm²/m'), ('k_heading', 'rad²/m'),
                           ('k_turn', 'rad²/rad')):
            value = getattr(self, name)
            if (isinstance(value, bool) or not isinstance(value, numbers.Real)
                    or not (math.isfinite(value) and float(value) >= 0.0)):
                raise ValueError(f'{name} must be finite and >= 0 {unit}, got {value!r}')

    def covariance(
        self,
        delta_distance: float,
        delta_heading: float,
        heading_variance: float | None = None,
    ) -> NDArray[np.float64]:
        """
        Return the 2×2 covariance of the increment (Δs [m], Δθ [rad]).

        Parameters
        ----------
        delta_distance : float
            Travelled distance Δs [m] (negative when reversing).
        delta_heading : float
            Heading change Δθ [rad].
        heading_variance : float or None
            If given, var(Δθ) [rad²] from another source (an integrated gyro) replaces
            k_heading |Δs| + k_turn |Δθ|; must be >= 0.

        Returns
        -------
        ndarray, shape (2, 2)
            diag(var(Δs) [m²], var(Δθ) [rad²]).

        Raises
        ------
        ValueError
            On a non-finite input or a negative ``heading_variance``.

        """
        distance = abs(finite_real('delta_distance', delta_distance))
        turn = abs(finite_real('delta_heading', delta_heading))
        if heading_variance is None:
            var_heading = self.k_heading * distance + self.k_turn * turn
        else:
            var_heading = _nonnegative_scalar(heading_variance, 'heading_variance', 'rad²')
        return np.diag([self.k_distance * distance, var_heading])


def chi_square_threshold(probability: float, dof: int) -> float:
    """
    Return the chi-square quantile χ²_dof(probability), the gate on a squared innovation.

    A measurement whose normalised innovation squared ν = yᵀ S⁻¹ y exceeds it is rejected;
    a consistent filter rejects a fraction 1 - probability of good measurements. Computed as
    2 P⁻¹(dof/2, probability) (inverse regularised lower incomplete gamma function);
    ``probability = 1`` gives ``inf`` (no gate).

    Parameters
    ----------
    probability : float
        Gate probability, in (0, 1].
    dof : int
        Degrees of freedom, the measurement size (>= 1).

    Returns
    -------
    float
        The threshold on ν (dimensionless).

    Raises
    ------
    ValueError
        If ``probability`` is outside (0, 1] or ``dof`` < 1.

    Examples
    --------
    >>> round(chi_square_threshold(0.999, 2), 4)  # = -2 ln(0.001)
    13.8155
    >>> round(chi_square_threshold(0.95, 1), 4)  # = 1.96²
    3.8415

    """
    p = finite_real('gate_probability', probability)
    if not 0.0 < p <= 1.0:
        raise ValueError(f'gate_probability must be in (0, 1], got {probability!r}')
    if isinstance(dof, bool) or not isinstance(dof, int) or dof < 1:
        raise ValueError(f'dof must be an integer >= 1, got {dof!r}')
    if p == 1.0:
        return math.inf
    return float(2.0 * gammaincinv(0.5 * dof, p))


# --- motion model -------------------------------------------------------------------------


def _chord_factor(half_turn: float) -> tuple[float, float]:
    """Return f(h) = sin h / h and f'(h), with their limits 1 and 0 at h = 0."""
    if half_turn == 0.0:
        return 1.0, 0.0
    if abs(half_turn) < _SERIES_HALF_ANGLE:
        h2 = half_turn * half_turn
        # Σ (-1)^n 2n h^(2n-1) / (2n+1)!, n = 1..4; the next term is < 3e-16 h.
        series = -1.0 / 3.0 + h2 * (1.0 / 30.0 + h2 * (-1.0 / 840.0 + h2 / 45360.0))
        return math.sin(half_turn) / half_turn, half_turn * series
    value = math.sin(half_turn) / half_turn
    return value, (math.cos(half_turn) - value) / half_turn


def _increment(delta_distance: float, delta_heading: float) -> tuple[float, float]:
    return (finite_real('delta_distance', delta_distance),
            finite_real('delta_heading', delta_heading))


def _arc(x: float, y: float, theta: float, delta_s: float, delta_theta: float) -> Pose2D:
    """Exact-arc step on validated floats (see :func:`motion_model`)."""
    half_turn = 0.5 * delta_theta
    chord = delta_s * _chord_factor(half_turn)[0]
    return np.array([x + chord * math.cos(theta + half_turn),
                     y + chord * math.sin(theta + half_turn),
                     wrap_to_pi(theta + delta_theta)])


def _arc_jacobians(
    theta: float, delta_s: float, delta_theta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Jacobians F, G of the exact-arc step on validated floats (see :func:`motion_jacobians`)."""
    half_turn = 0.5 * delta_theta
    f, df = _chord_factor(half_turn)
    c, s = math.cos(theta + half_turn), math.sin(theta + half_turn)
    jac_state = np.array([[1.0, 0.0, 0.0 - delta_s * f * s],
                          [0.0, 1.0, delta_s * f * c],
                          [0.0, 0.0, 1.0]])
    jac_increment = np.array([[f * c, 0.5 * delta_s * (df * c - f * s)],
                              [f * s, 0.5 * delta_s * (df * s + f * c)],
                              [0.0, 1.0]])
    return jac_state, jac_increment


def motion_model(pose: ArrayLike, delta_distance: float, delta_heading: float) -> Pose2D:
    """
    Return the pose after driving an arc of length Δs while turning by Δθ.

    Book (4.93) in REP-103 and in chord form: with h = Δθ/2 and f(h) = sin h / h (f(0) = 1),

        x' = x + Δs f(h) cos(θ + h),   y' = y + Δs f(h) sin(θ + h),   θ' = θ + Δθ,

    identical to ``odometry_increment(..., method='exact_arc')`` ((Δs/Δθ)(sin(θ+Δθ) - sin θ)
    = Δs f(h) cos(θ + h)) and exact when v and ω are constant over the increment (§4.7.1).
    The chord has length Δs f(h) and points along the mean heading θ + Δθ/2.

    Parameters
    ----------
    pose : array_like, shape (3,)
        Pose (x [m], y [m], θ [rad]) of ``base_link`` in ``odom`` (ENU) before the motion.
    delta_distance : float
        Arc length Δs [m] travelled by the guide point, negative when reversing (ΔU_c).
    delta_heading : float
        Heading change Δθ [rad], counter-clockwise positive.

    Returns
    -------
    ndarray, shape (3,)
        Pose after the motion, θ wrapped to (-π, π].

    Raises
    ------
    ValueError
        On a non-finite input or a pose of the wrong shape.

    Examples
    --------
    >>> motion_model([0.0, 0.0, 0.0], 0.5 * math.pi, 0.5 * math.pi)  # quarter circle, R = 1 m
    array([1.        , 1.        , 1.57079633])

    """
    x, y, theta = (float(v) for v in _pose(pose))
    return _arc(x, y, theta, *_increment(delta_distance, delta_heading))


def motion_jacobians(
    pose: ArrayLike, delta_distance: float, delta_heading: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the Jacobians of :func:`motion_model` with respect to the pose and the increment.

    With h = Δθ/2, f = sin h / h, f' = df/dh and ψ = θ + h:

        F = ∂(x', y', θ')/∂(x, y, θ) = [[1, 0, -Δs f sin ψ], [0, 1, Δs f cos ψ], [0, 0, 1]]

        G = ∂(x', y', θ')/∂(Δs, Δθ) = [[f cos ψ, (Δs/2)(f' cos ψ - f sin ψ)],
                                        [f sin ψ, (Δs/2)(f' sin ψ + f cos ψ)],
                                        [0,       1                         ]]

    smooth through Δθ = 0 (f' uses its Taylor series for |h| < 0.1 rad).

    Parameters
    ----------
    pose : array_like, shape (3,)
        Pose (x [m], y [m], θ [rad]) in ``odom`` before the motion.
    delta_distance : float
        Arc length Δs [m].
    delta_heading : float
        Heading change Δθ [rad].

    Returns
    -------
    F : ndarray, shape (3, 3)
        Jacobian with respect to the state (x, y, θ).
    G : ndarray, shape (3, 2)
        Jacobian with respect to the increment (Δs [m], Δθ [rad]).

    Raises
    ------
    ValueError
        On a non-finite input or a pose of the wrong shape.

    Examples
    --------
    >>> F, G = motion_jacobians([0.0, 0.0, 0.0], 2.0, 0.0)  # straight along x
    >>> F
    array([[1., 0., 0.],
           [0., 1., 2.],
           [0., 0., 1.]])
    >>> G
    array([[1., 0.],
           [0., 1.],
           [0., 1.]])

    """
    theta = float(_pose(pose)[2])
    return _arc_jacobians(theta, *_increment(delta_distance, delta_heading))


def increment_between_poses(pose_before: ArrayLike, pose_after: ArrayLike) -> tuple[float, float]:
    """
    Return the arc increment (Δs [m], Δθ [rad]) that leads from one pose to the next.

    The inverse of :func:`motion_model` for |Δθ| < π: Δθ = wrap(θ₁ - θ₀) and Δs is the
    displacement projected on the chord direction θ₀ + Δθ/2, divided by f(Δθ/2) = sin h / h.
    Use it to feed the filter from two successive poses of an odometry source (e.g.
    :func:`robotica_kin.mobile.odometry.odometry_increment`, as
    :class:`robotica_kin.mobile.odometry_fusion.OdometryFusion` does); a displacement across the
    chord (which an arc cannot produce) is ignored.

    Parameters
    ----------
    pose_before, pose_after : array_like, shape (3,)
        Successive poses (x [m], y [m], θ [rad]) in the odometry frame.

    Returns
    -------
    tuple of float
        (Δs [m], negative when reversing; Δθ [rad] in (-π, π]).

    Raises
    ------
    ValueError
        On a non-finite input or a pose of the wrong shape.

    Examples
    --------
    >>> ds, dth = increment_between_poses([0.0, 0.0, 0.0], [1.0, 1.0, 0.5 * math.pi])
    >>> round(ds, 12), round(dth, 12)  # a quarter circle of R = 1 m
    (1.570796326795, 1.570796326795)

    """
    x0, y0, theta0 = (float(v) for v in _pose(pose_before, 'pose_before'))
    x1, y1, theta1 = (float(v) for v in _pose(pose_after, 'pose_after'))
    delta_theta = wrap_to_pi(theta1 - theta0)
    half_turn = 0.5 * delta_theta
    chord = (x1 - x0) * math.cos(theta0 + half_turn) + (y1 - y0) * math.sin(theta0 + half_turn)
    return chord / _chord_factor(half_turn)[0], delta_theta


# --- the filter ---------------------------------------------------------------------------


def _positive_time(value: float, name: str) -> float:
    """Return ``value`` as a float > 0 [s]; ``inf`` is allowed (NaN is not)."""
    if isinstance(value, (bool, str, bytes)):
        raise ValueError(f'{name} must be a real number, got {value!r}')
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be a real number, got {value!r}') from None
    if math.isnan(number) or not number > 0.0:
        raise ValueError(f'{name} must be > 0 s, got {value!r}')
    return number


def _augmented_size(value: ArrayLike, ndim: int, name: str) -> int:
    """Return 3 or 5, the size of ``value`` of shape (n,) * ndim; ValueError otherwise."""
    try:
        shape = np.shape(value)
    except (TypeError, ValueError):
        shape = None
    for size in (3, 5):
        if shape == (size,) * ndim:
            return size
    raise ValueError(f'{name} must have shape {(3,) * ndim} or {(5,) * ndim}, got '
                     f'{shape if shape is not None else value!r}')


class EkfLocalization:
    """
    Extended Kalman filter of the planar pose from odometry, GPS fixes and compass headings.

    * :meth:`predict` moves the pose by :func:`motion_model` and propagates
      P ← F P Fᵀ + G Q Gᵀ, Q from :class:`OdometryNoise`.
    * :meth:`update_position` fuses a position fix z = (x, y) [m] (H = [I₂ 0]);
      :meth:`update_heading` a heading z = θ [rad] (H = [0 0 1]), innovation wrapped to
      (-π, π].
    * Each update first gates the normalised innovation squared ν = yᵀ S⁻¹ y, S = H P Hᵀ + R,
      against :func:`chi_square_threshold` (``gate_probability``, dof = measurement size). A
      rejected update changes nothing, is counted in :attr:`rejected_updates` and returns
      False. An accepted one applies K = P Hᵀ S⁻¹, x ← x + K y, and the Joseph form
      P ← (I - K H) P (I - K H)ᵀ + K R Kᵀ, then symmetrises P.

    **Time-correlated GPS error (optional augmentation).** The error of successive fixes is
    not independent: most of it (atmosphere, multipath, satellite geometry; book §7.7.5,
    catalog §5.7) changes over tens of seconds. A filter that takes fixes at 5 Hz as
    independent averages that slow error as if it were white and becomes overconfident. With
    ``position_bias_stddev`` σ_b > 0 the state is augmented to (x, y, θ, b_E, b_N), b the
    error of the fix [m] in ENU, modelled per axis as a first-order Gauss–Markov process of
    stationary standard deviation σ_b and correlation time τ (``position_bias_correlation_time``;
    ``inf`` makes b a random constant), discretised exactly over the interval dt [s] that
    :meth:`predict` then requires:

        b ← φ b,   var ← φ² var + σ_b² (1 - φ²),   φ = exp(-dt/τ),

    so the stationary variance σ_b² is kept for any dt. A fix measures z = (x, y) + b + w,
    H = [I₂ 0 I₂], with only the *white* part w in R (see :meth:`update_position`); a
    compass heading has H = [0 0 1 0 0]. The bias starts at 0 with covariance σ_b² I₂,
    uncorrelated with the pose (the stationary distribution). This is the standard
    shaping-filter (state augmentation) treatment of coloured measurement noise (Gelb,
    *Applied Optimal Estimation*, 1974, §4.5; Bar-Shalom, Li & Kirubarajan 2001, §8.3; not in
    the book). Without augmentation (σ_b = 0, the default) the filter is the 3-state one.

    The filter never reads a clock: the caller calls :meth:`predict` with each odometry
    increment (and its duration when augmented) and the updates when measurements arrive,
    in time order.

    Parameters
    ----------
    initial_pose : array_like, shape (3,) (or (5,) when augmented)
        Pose (x [m], y [m], θ [rad]) of ``base_link`` in ``odom`` (local ENU); when
        augmented, a (5,) state may also give the initial bias (b_E, b_N) [m], else it is 0.
    initial_covariance : array_like, shape (3, 3) (or (5, 5) when augmented)
        Its covariance [m², m·rad, rad²], symmetric positive semi-definite; when augmented a
        (3, 3) one is completed with the stationary bias covariance σ_b² I₂ (no
        cross-covariance), a (5, 5) one is taken as is.
    odometry_noise : OdometryNoise
        Error model of the odometry increments.
    gate_probability : float
        Probability of the chi-square gate, in (0, 1]; 1 disables the gate.
    position_bias_stddev : float
        σ_b [m] per axis, stationary standard deviation of the time-correlated part of the GPS
        error; >= 0, 0 (default) disables the augmentation.
    position_bias_correlation_time : float
        τ [s] of that error, > 0, ``inf`` (default) for a constant bias. Validated even when
        the augmentation is off, and then unused.

    Raises
    ------
    ValueError
        On a non-finite, wrongly shaped, asymmetric or indefinite input, a gate probability
        outside (0, 1], a negative or non-finite ``position_bias_stddev``, a correlation time
        that is not > 0, or ``odometry_noise`` that is not an :class:`OdometryNoise`.

    Examples
    --------
    >>> ekf = EkfLocalization([0.0, 0.0, 0.0], np.diag([0.0, 0.0, 0.0]), OdometryNoise())
    >>> ekf.predict(10.0, 0.0)
    array([10.,  0.,  0.])
    >>> ekf.update_position([10.0, 0.2], np.diag([1.0, 1.0]))
    True
    >>> ekf.update_position([110.0, 0.0], np.diag([1.0, 1.0]))  # 100 m away: gated out
    False
    >>> ekf.rejected_updates
    1

    With the GPS error as a Gauss–Markov state (σ_b = 0.3 m, τ = 30 s):

    >>> ekf = EkfLocalization([0.0, 0.0, 0.0], np.zeros((3, 3)), OdometryNoise(),
    ...                       position_bias_stddev=0.3, position_bias_correlation_time=30.0)
    >>> ekf.full_covariance.diagonal().round(3)
    array([0.  , 0.  , 0.  , 0.09, 0.09])
    >>> ekf.predict(0.2, 0.0, dt=0.2)
    array([0.2, 0. , 0. ])
    >>> ekf.update_position([0.5, 0.1], 0.1 * np.eye(2))  # R total: white part 0.1 - 0.09
    True
    >>> ekf.position_bias.round(3)  # most of the offset (0.3, 0.1) is put down to GPS error
    array([0.269, 0.09 ])

    """

    _state: Vector
    _full_cov: NDArray[np.float64]
    _noise: OdometryNoise
    _gate_probability: float
    _gate_thresholds: dict[int, float]
    _bias_stddev: float
    _bias_time: float
    _rejected: int
    _last_nis: float | None

    def __init__(
        self,
        initial_pose: ArrayLike,
        initial_covariance: ArrayLike,
        odometry_noise: OdometryNoise,
        gate_probability: float = 0.999,
        position_bias_stddev: float = 0.0,
        position_bias_correlation_time: float = math.inf,
    ) -> None:
        if not isinstance(odometry_noise, OdometryNoise):
            raise ValueError(f'odometry_noise must be an OdometryNoise, got {odometry_noise!r}')
        self._gate_thresholds = {dof: chi_square_threshold(gate_probability, dof)
                                 for dof in (1, 2)}
        self._noise = odometry_noise
        self._gate_probability = float(gate_probability)
        self._bias_stddev = _nonnegative_scalar(position_bias_stddev, 'position_bias_stddev',
                                                'm')
        self._bias_time = _positive_time(position_bias_correlation_time,
                                         'position_bias_correlation_time')
        self.reset(initial_pose, initial_covariance)

    @property
    def _size(self) -> int:
        """Return the number of states: 3, or 5 with the GPS-bias augmentation."""
        return 5 if self._bias_stddev > 0.0 else 3

    def reset(self, pose: ArrayLike, covariance: ArrayLike) -> None:
        """
        Restart from ``pose`` (3,) [m, m, rad] with ``covariance`` (3, 3); zero the counters.

        When augmented, ``pose`` may be the (5,) state (x, y, θ, b_E, b_N) and ``covariance``
        its (5, 5) covariance; a (3,) pose restarts the bias at 0 and a (3, 3) covariance
        gives it the stationary covariance σ_b² I₂, uncorrelated with the pose.

        Raises
        ------
        ValueError
            If the pose is not finite of shape (3,) (or (5,)) or the covariance is not a
            finite, symmetric, positive semi-definite 3×3 (or 5×5) matrix; the state is then
            unchanged.

        """
        if self._size == 3:
            state = _pose(pose, 'initial_pose')
            full_cov = _covariance(covariance, 3, 'initial_covariance')
        else:
            state = np.zeros(5)
            size = _augmented_size(pose, 1, 'initial_pose')
            state[:size] = _finite_array(pose, (size,), 'initial_pose')
            state[2] = wrap_to_pi(float(state[2]))
            size = _augmented_size(covariance, 2, 'initial_covariance')
            full_cov = np.diag([0.0, 0.0, 0.0] + 2 * [self._bias_stddev ** 2])
            full_cov[:size, :size] = _covariance(covariance, size, 'initial_covariance')
        self._state = state
        self._full_cov = full_cov
        self._rejected = 0
        self._last_nis = None

    def predict(
        self,
        delta_distance: float,
        delta_heading: float,
        heading_variance: float | None = None,
        dt: float | None = None,
    ) -> Pose2D:
        """
        Propagate the state and covariance by one odometry increment; return the new pose.

        Parameters
        ----------
        delta_distance : float
            Arc length Δs [m] of the guide point since the last call (ΔU_c of slides [S]),
            negative when reversing.
        delta_heading : float
            Heading change Δθ [rad] since the last call, from the encoders (ΔU_d - ΔU_i)/b or
            from the integrated gyro rate.
        heading_variance : float or None
            Variance of Δθ [rad²] when it comes from another sensor (a gyro); ``None`` uses
            the odometry model k_heading |Δs| + k_turn |Δθ|.
        dt : float or None
            Time [s] since the previous :meth:`predict` (or since the start), > 0 and
            finite. Required with the GPS-bias augmentation, where it propagates the bias
            exactly (b ← φ b, var ← φ² var + σ_b² (1 - φ²), φ = exp(-dt/τ)); checked and
            unused without it.

        Returns
        -------
        ndarray, shape (3,)
            The predicted pose (x [m], y [m], θ [rad]) in ``odom``, a copy.

        Raises
        ------
        ValueError
            On a non-finite input, a negative ``heading_variance``, a ``dt`` that is not
            finite and > 0, or a missing ``dt`` with the augmentation; the state is then
            unchanged.

        """
        q = self._noise.covariance(delta_distance, delta_heading, heading_variance)
        delta_s, delta_theta = _increment(delta_distance, delta_heading)
        if dt is not None:
            interval = finite_real('dt', dt)
            if not interval > 0.0:
                raise ValueError(f'dt must be > 0 s, got {dt!r}')
        elif self._size == 5:
            raise ValueError('dt (the time [s] since the previous predict) is required when '
                             'the GPS position bias is estimated (position_bias_stddev > 0)')
        x, y, theta = (float(v) for v in self._state[:3])
        jac_pose, jac_increment_pose = _arc_jacobians(theta, delta_s, delta_theta)
        state = self._state.copy()
        state[:3] = _arc(x, y, theta, delta_s, delta_theta)
        if self._size == 3:
            jac_state, jac_increment = jac_pose, jac_increment_pose
        else:
            decay = interval / self._bias_time
            phi = math.exp(-decay)
            jac_state = np.zeros((5, 5))
            jac_state[:3, :3] = jac_pose
            jac_state[3:, 3:] = phi * np.eye(2)
            jac_increment = np.zeros((5, 2))
            jac_increment[:3] = jac_increment_pose
            state[3:] *= phi
        p = (jac_state @ self._full_cov @ jac_state.T
             + jac_increment @ q @ jac_increment.T)
        if self._size == 5:
            # σ_b² (1 - φ²), with expm1 for accuracy when dt << τ.
            p[3:, 3:] += -self._bias_stddev ** 2 * math.expm1(-2.0 * decay) * np.eye(2)
        self._state = state
        self._full_cov = 0.5 * (p + p.T)
        return self.pose

    def update_position(
        self,
        z_enu_xy: ArrayLike,
        R: ArrayLike,  # noqa: N803
        white_variance: float | None = None,
    ) -> bool:
        """
        Fuse a position fix (GPS/DGPS) given in the local ENU (``odom``) frame.

        Without augmentation the fix is z = (x, y) + w with w ~ N(0, R), independent of the
        other fixes. With it, z = (x, y) + b + w and only the white part w enters as
        measurement noise, R_white:

        * ``white_variance`` σ_w² · I₂ if given;
        * else R - σ_b² I₂, i.e. ``R`` is read as the total covariance of the fix (bias plus
          white, what a receiver or :mod:`robotica_sim.sensors.gps` reports), with its
          eigenvalues clipped from below at the floor
          ``WHITE_VARIANCE_FLOOR_RATIO`` · σ_b² = 0.01 σ_b² (a white σ of at least 10 % of
          σ_b) so that R_white stays positive definite when R <= σ_b² I₂.

        Parameters
        ----------
        z_enu_xy : array_like, shape (2,)
            Measured position (east [m], north [m]) of ``base_link`` in ``odom``, already
            converted from geodetic coordinates (e.g. with :mod:`robotica_kin.geodetic`) and
            corrected for the antenna lever arm by the caller.
        R : array_like, shape (2, 2)
            Its covariance [m²], symmetric positive semi-definite (DGPS σ ≈ 1-5 m, book
            §7.7.5); the total covariance of the fix. Validated in both cases.
        white_variance : float or None
            σ_w² [m²], >= 0 and finite, the variance per axis of the white part of the fix
            error; used only with the augmentation (validated and unused without it).

        Returns
        -------
        bool
            True if the fix passed the gate and was fused, False if it was rejected.

        Raises
        ------
        ValueError
            On a non-finite or wrongly shaped input, an asymmetric or indefinite ``R``, a
            negative ``white_variance``, or a singular innovation covariance; the state is
            then unchanged.

        """
        z = _finite_array(z_enu_xy, (2,), 'z_enu_xy')
        noise = _covariance(R, 2, 'R')
        white = (None if white_variance is None
                 else _nonnegative_scalar(white_variance, 'white_variance', 'm²'))
        if self._size == 3:
            observation = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
            return self._update(z - self._state[:2], observation, noise)
        if white is not None:
            noise = white * np.eye(2)
        else:
            variance = self._bias_stddev ** 2
            values, vectors = np.linalg.eigh(noise - variance * np.eye(2))
            values = np.maximum(values, WHITE_VARIANCE_FLOOR_RATIO * variance)
            noise = (vectors * values) @ vectors.T
            noise = 0.5 * (noise + noise.T)
        observation = np.array([[1.0, 0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0, 1.0]])
        return self._update(z - self._state[:2] - self._state[3:], observation, noise)

    def update_heading(self, z_theta: float, variance: float) -> bool:
        """
        Fuse a heading measurement (compass), the innovation wrapped to (-π, π].

        Parameters
        ----------
        z_theta : float
            Measured heading θ [rad] in REP-103 (from east, counter-clockwise); a compass
            azimuth α (from north, clockwise, corrected for declination) gives θ = π/2 - α.
        variance : float
            Its variance [rad²], >= 0.

        Returns
        -------
        bool
            True if the heading passed the gate and was fused, False if it was rejected.

        Raises
        ------
        ValueError
            On a non-finite input, a negative variance or a singular innovation covariance;
            the state is then unchanged.

        """
        z = finite_real('z_theta', z_theta)
        noise = np.array([[_nonnegative_scalar(variance, 'variance', 'rad²')]])
        innovation = np.array([wrap_to_pi(z - float(self._state[2]))])
        observation = np.zeros((1, self._size))
        observation[0, 2] = 1.0
        return self._update(innovation, observation, noise)

    def _update(
        self, innovation: Vector, observation: NDArray[np.float64], noise: NDArray[np.float64]
    ) -> bool:
        """Gate and apply a linear update with innovation y, matrix H and covariance R."""
        p = self._full_cov
        innovation_cov = observation @ p @ observation.T + noise
        try:
            chol = np.linalg.cholesky(innovation_cov)
        except np.linalg.LinAlgError:
            raise ValueError(
                f'innovation covariance is not positive definite: {innovation_cov!r} '
                '(zero prior and measurement variance)') from None
        whitened = np.linalg.solve(chol, innovation)
        nis = float(whitened @ whitened)
        self._last_nis = nis
        if nis > self._gate_thresholds[innovation.size]:
            self._rejected += 1
            return False
        # K = P Hᵀ S⁻¹ with S = L Lᵀ.
        gain = np.linalg.solve(chol.T, np.linalg.solve(chol, observation @ p)).T
        state = self._state + gain @ innovation
        state[2] = wrap_to_pi(float(state[2]))
        factor = np.eye(self._size) - gain @ observation
        updated = factor @ p @ factor.T + gain @ noise @ gain.T
        self._state = state
        self._full_cov = 0.5 * (updated + updated.T)
        return True

    @property
    def pose(self) -> Pose2D:
        """Estimated pose of ``base_link`` in ``odom``: x [m], y [m], θ [rad]; a copy."""
        return self._state[:3].copy()

    @property
    def covariance(self) -> NDArray[np.float64]:
        """Covariance P (3, 3) of the pose [m², m·rad, rad²], symmetric, a copy."""
        return self._full_cov[:3, :3].copy()

    @property
    def state(self) -> Vector:
        """Full state, a copy: (x, y, θ) [m, m, rad], then (b_E, b_N) [m] when augmented."""
        return self._state.copy()

    @property
    def full_covariance(self) -> NDArray[np.float64]:
        """Covariance (n, n) of :attr:`state`, n = 3 or 5 [m², m·rad, rad²], a copy."""
        return self._full_cov.copy()

    @property
    def position_bias(self) -> Vector:
        """Estimated GPS error (b_E, b_N) [m] in ENU, shape (2,); zeros when not augmented."""
        return self._state[3:].copy() if self._size == 5 else np.zeros(2)

    @property
    def position_bias_stddev(self) -> float:
        """σ_b [m] of the Gauss–Markov GPS error; 0 when the augmentation is off."""
        return self._bias_stddev

    @property
    def position_bias_correlation_time(self) -> float:
        """τ [s] of the Gauss–Markov GPS error (``inf``: constant bias)."""
        return self._bias_time

    @property
    def odometry_noise(self) -> OdometryNoise:
        """Odometry error model used by :meth:`predict`."""
        return self._noise

    @property
    def gate_probability(self) -> float:
        """Probability of the chi-square innovation gate (1 = no gate)."""
        return self._gate_probability

    @property
    def rejected_updates(self) -> int:
        """Count of updates rejected by the gate since construction or :meth:`reset`."""
        return self._rejected

    @property
    def last_nis(self) -> float | None:
        """Normalised innovation squared yᵀ S⁻¹ y of the last update (gated or not), or None."""
        return self._last_nis
