"""
Path following in the Frenet frame of the path (book §9.4.3–§9.4.4, (9.83)-(9.117)).

Error model (§9.4.3.1). M is the projection of the guide point P on the path, s its arc
length, d the signed distance from M to P along the path normal and θ̃ = θ - θ_c the heading
of the vehicle relative to the path tangent, c(s) the path curvature at M. For a vehicle with
speed v and yaw rate ω (book (9.87)):

    s' = v cos θ̃ / (1 - c d),    d' = v sin θ̃,    θ̃' = ω - v c cos θ̃ / (1 - c d).

With the auxiliary input u = ω - v c cos θ̃ / (1 - c d) (9.90) the heading error obeys θ̃' = u
(9.91), and the two path-following laws of §9.4.3 choose u; the speed v(t) is not controlled:

* ``'linear'`` (9.93): u = -k1 v d - k2 |v| θ̃, k1 > 0 [1/m²], k2 > 0 [1/m]. Its linearisation
  d'' + k2 |v| d' + k1 v² d = 0 (9.94) becomes, in the distance travelled ρ = ∫|v| dt (9.96),
  d_ρρ + k2 d_ρ + k1 d = 0 (9.97): with k1 = b², k2 = 2 δ b (9.98; printed "k1 = ω_n²") the path
  is approached like a second-order system of natural frequency b [1/m] and damping δ in ρ, at
  any speed (:func:`gains_from_damping`).
* ``'nonlinear'`` (9.99): u = -k1 v d sin θ̃ / θ̃ - k(v) θ̃ with k(v) = k2 |v|, which matches the
  linear law near (d, θ̃) = (0, 0). Lyapunov function V = k1 d²/2 + θ̃²/2 (9.102; printed with
  k2) gives V' = -k(v) θ̃²; convergence holds from d(0)² + θ̃(0)²/k1 < 1 / limsup c² (9.101;
  printed without the square on d), see :func:`in_convergence_region`.

The yaw rate is ω = u + v c cos θ̃ / (1 - c d) and the curvature γ = ω / v; with k(v) = k2 |v|
both laws give a γ that does not depend on |v|, so :class:`FrenetPathFollower` can lower the
speed to respect ``max_angular_velocity`` without changing the path it drives.

Bicycle model with steering dynamics (§9.4.4). With small heading errors and the curvature γ
as the state of a first-order steering actuator γ' = (u - γ)/τ, the state x = (d, θ̃, γ) obeys
x' = A x + B u (9.111)-(9.113) and the state feedback u = -k1 d - k2 θ̃ - k3 γ (9.114) gives the
characteristic equation τ s³ + (1 + k3) s² + v k2 s + v² k1 = 0 (9.116), stable by Routh's
criterion (9.117) (:func:`routh_table`, :func:`routh_stable`).

Book to REP-103. The book measures headings from the world y axis (θ = φ + π/2); the
difference θ̃ = φ̃ = φ - φ_c is the same in both. In §9.4.3 the book's ξ (with ξ' = v sin φ̃,
(9.85) printed "sin φ") is positive to the left, so d = ξ and the laws read as printed. In
§9.4.4 the book's ξ (ξ' = -v sin φ, (9.106)) is positive to the right: there d = -ξ, the book's
k1 is -k1 here, k2 and k3 are unchanged, and the book's (9.116) τ s³ + (k3 + 1) s² + v k2 s -
v² k1 and condition k1/τ < 0 of (9.117) become the forms above with k1 > 0. The printed closed
loop matrix (9.115) has the wrong sign on k1/τ and k2/τ; (9.116) is right.
"""

from dataclasses import dataclass, fields
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_ctrl.mobile.tracker_base import check_pose, PathTrackerBase, TrackerOutput
from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import finite_real

__all__ = [
    'characteristic_polynomial',
    'frenet_angular_velocity',
    'frenet_error_rates',
    'frenet_errors',
    'FRENET_LAWS',
    'FrenetErrors',
    'FrenetParams',
    'FrenetPathFollower',
    'gains_from_damping',
    'in_convergence_region',
    'MIN_FRENET_SCALE',
    'path_following_input',
    'routh_stable',
    'routh_table',
    'steering_feedback',
    'steering_state_matrices',
]

FRENET_LAWS = ('linear', 'nonlinear')
"""Names of the path-following laws of §9.4.3: (9.93) and (9.99)."""

MIN_FRENET_SCALE = 0.1
"""Floor of the factor 1 - c d in the curvature feed-forward of :func:`frenet_angular_velocity`.

The Frenet frame is singular at the centre of curvature (c d = 1); closer than 10 % of the
radius of curvature to it the feed-forward is held at its value for 1 - c d = 0.1.
"""


@dataclass(frozen=True)
class FrenetErrors:
    """
    Frenet coordinates of the vehicle with respect to the path (book fig. 9.23).

    Attributes
    ----------
    lateral_error : float
        d [m]: signed distance from the projection M to the guide point P, > 0 when the vehicle
        is left of the path (the book's ξ of §9.4.3).
    heading_error : float
        θ̃ = θ - θ_c [rad] in (-π, π], > 0 when the vehicle points to the left of the path
        tangent (the book's φ̃).
    path_curvature : float
        c(s) = γ_c [1/m] of the path at M, > 0 when the path turns left.

    Raises
    ------
    ValueError
        If a value is not finite, or ``|heading_error| > π``.

    Examples
    --------
    >>> FrenetErrors(0.5, 0.1, 0.0).lateral_error
    0.5

    """

    lateral_error: float
    heading_error: float
    path_curvature: float

    def __post_init__(self) -> None:
        values = (self.lateral_error, self.heading_error, self.path_curvature)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f'Frenet errors must be finite, got {values!r}')
        if abs(self.heading_error) > math.pi:
            raise ValueError(f'heading_error must be in [-pi, pi] rad, got {self.heading_error!r}')


def frenet_errors(pose: ArrayLike, projection: PathProjection,
                  path_curvature: float = 0.0) -> FrenetErrors:
    """
    Return the Frenet errors (d, θ̃, c) of ``pose`` from its projection onto the path.

    d is the projection's cross-track offset (> 0 left) and θ̃ = wrap(θ - θ_c) with θ_c the
    path tangent heading at the projection (book fig. 9.23, φ̃ = φ - φ_c).

    Parameters
    ----------
    pose : array_like, shape (3,)
        Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
    projection : PathProjection
        Projection of the pose's position onto the path (:meth:`PolylinePath.project`).
    path_curvature : float, optional
        Path curvature c(s) [1/m] at the projection, > 0 turning left (0 on a straight line).

    Returns
    -------
    FrenetErrors

    Raises
    ------
    ValueError
        If ``pose`` is not a finite (3,) vector or ``path_curvature`` is not finite.

    >>> path = PolylinePath([[0.0, 0.0], [4.0, 0.0]])
    >>> frenet_errors([1.0, -0.5, 0.25], path.project([1.0, -0.5]))
    FrenetErrors(lateral_error=-0.5, heading_error=0.25, path_curvature=0.0)

    """
    x = check_pose(pose)
    return FrenetErrors(projection.cross_track,
                        wrap_to_pi(float(x[2]) - projection.tangent_heading),
                        float(path_curvature))


def frenet_error_rates(errors: FrenetErrors | ArrayLike, linear: float,
                       angular: float) -> NDArray[np.float64]:
    """
    Return (s', d', θ̃') of the Frenet error model, book (9.87).

    s' = v cos θ̃ / (1 - c d), d' = v sin θ̃, θ̃' = ω - c s'.

    Parameters
    ----------
    errors : FrenetErrors or array_like, shape (3,)
        The errors, or (d [m], θ̃ [rad], c [1/m]).
    linear : float
        Vehicle speed v [m/s].
    angular : float
        Vehicle yaw rate ω [rad/s].

    Returns
    -------
    ndarray, shape (3,)
        s' [m/s], d' [m/s], θ̃' [rad/s].

    Raises
    ------
    ValueError
        If a value is not finite, ``errors`` has a wrong size, or 1 - c d <= 0 (the vehicle is
        at or beyond the path's centre of curvature, where the frame is singular).

    >>> frenet_error_rates([0.5, 0.0, 1.0], 1.0, 0.0)  # circle of radius 1, half way inside
    array([ 2.,  0., -2.])

    """
    d, heading, c = _error_triple(errors)
    v, w = finite_real('linear', linear), finite_real('angular', angular)
    scale = 1.0 - c * d
    if not scale > 0.0:
        raise ValueError(f'1 - c d must be > 0 (vehicle short of the centre of curvature), '
                         f'got {scale!r}')
    s_rate = v * math.cos(heading) / scale
    return np.array([s_rate, v * math.sin(heading), w - c * s_rate])


def gains_from_damping(natural_frequency: float, damping: float) -> tuple[float, float]:
    """
    Return (k1 [1/m²], k2 [1/m]) of the linear law for natural frequency b and damping δ.

    Book (9.98) (printed "k1 = ω_n²"): k1 = b², k2 = 2 δ b, so that the lateral error obeys
    d_ρρ + 2 δ b d_ρ + b² d = 0 in the distance travelled ρ (9.97). The poles in time at speed
    v are |v| b (-δ ± sqrt(δ² - 1)).

    Parameters
    ----------
    natural_frequency : float
        b [1/m] (rad per metre travelled), > 0; 1/b is the book's "tracking distance".
    damping : float
        δ, > 0 (1 = critical damping).

    Raises
    ------
    ValueError
        If a value is not positive and finite.

    >>> gains_from_damping(2.0, 0.5)
    (4.0, 2.0)

    """
    b = _positive('natural_frequency', natural_frequency)
    delta = _positive('damping', damping)
    return b * b, 2.0 * delta * b


@dataclass(frozen=True)
class FrenetParams:
    """
    Tunables of :class:`FrenetPathFollower` and :func:`frenet_angular_velocity`.

    Raises
    ------
    ValueError
        If ``law`` is not one of :data:`FRENET_LAWS`, or a number is not positive and finite.

    Examples
    --------
    >>> FrenetParams(law='nonlinear', k1=4.0, k2=4.0).law
    'nonlinear'

    """

    law: str = 'linear'  # 'linear' (9.93) or 'nonlinear' (9.99)
    k1: float = 1.0  # [1/m²], book (9.93)/(9.99): b² of (9.98)
    k2: float = 2.0  # [1/m], book (9.93); k(v) = k2 |v| in (9.99): 2 δ b of (9.98)
    desired_linear_velocity: float = 0.5  # v [m/s], not controlled by the law
    max_angular_velocity: float = 1.5  # [rad/s]; the speed is lowered to respect it
    goal_tolerance: float = 0.05  # [m] of remaining arc length at which the path is done
    search_window: float = 2.0  # [m] half-width of the closest-point search around the progress
    curvature_window: float = 0.25  # [m] half-width of the arc over which c(s) is averaged

    def __post_init__(self) -> None:
        if self.law not in FRENET_LAWS:
            raise ValueError(f'law must be one of {FRENET_LAWS}, got {self.law!r}')
        for field in fields(self):
            if field.name == 'law':
                continue
            value = getattr(self, field.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f'{field.name} must be positive and finite, got {value!r}')


def path_following_input(lateral_error: float, heading_error: float, linear: float,
                         params: FrenetParams) -> float:
    """
    Return the auxiliary input u = θ̃' [rad/s] of the chosen law, book (9.93) or (9.99).

    ``'linear'``: u = -k1 v d - k2 |v| θ̃; ``'nonlinear'``: u = -k1 v d sin θ̃ / θ̃ - k2 |v| θ̃.

    Parameters
    ----------
    lateral_error : float
        d [m], > 0 left of the path.
    heading_error : float
        θ̃ [rad], wrapped to (-π, π].
    linear : float
        Speed v [m/s] (any sign).
    params : FrenetParams
        Law and gains.

    Raises
    ------
    ValueError
        If a value is not finite.

    >>> path_following_input(0.5, 0.0, 2.0, FrenetParams(k1=1.0, k2=2.0))
    -1.0

    """
    d = finite_real('lateral_error', lateral_error)
    heading = finite_real('heading_error', heading_error)
    v = finite_real('linear', linear)
    sinc = 1.0 if params.law == 'linear' else math.sin(heading) / heading if heading else 1.0
    return -params.k1 * v * d * sinc - params.k2 * abs(v) * heading


def frenet_angular_velocity(errors: FrenetErrors | ArrayLike, linear: float,
                            params: FrenetParams) -> float:
    """
    Return the yaw rate ω [rad/s] of the path-following law, book (9.90) with (9.93)/(9.99).

    ω = u + v c cos θ̃ / max(1 - c d, :data:`MIN_FRENET_SCALE`), u from
    :func:`path_following_input`. The curvature command is γ = ω / v.

    Parameters
    ----------
    errors : FrenetErrors or array_like, shape (3,)
        The errors, or (d [m], θ̃ [rad], c [1/m]).
    linear : float
        Speed v [m/s].
    params : FrenetParams
        Law and gains.

    Raises
    ------
    ValueError
        If a value is not finite or ``errors`` has a wrong size.

    >>> frenet_angular_velocity([0.0, 0.0, 0.5], 2.0, FrenetParams())  # on a circle, R = 2 m
    1.0

    """
    d, heading, c = _error_triple(errors)
    v = finite_real('linear', linear)
    u = path_following_input(d, heading, v, params)
    return u + v * c * math.cos(heading) / max(1.0 - c * d, MIN_FRENET_SCALE)


def in_convergence_region(lateral_error: float, heading_error: float, k1: float,
                          max_path_curvature: float) -> bool:
    """
    Return whether the nonlinear law (9.99) provably converges from (d, θ̃), book (9.101).

    Condition d² + θ̃²/k1 < 1 / limsup c² (printed without the square on d); always true on a
    straight path (c = 0). The guarantee also needs lim v(t) != 0 (9.100).

    Parameters
    ----------
    lateral_error : float
        d(0) [m].
    heading_error : float
        θ̃(0) [rad].
    k1 : float
        Gain k1 [1/m²], > 0.
    max_path_curvature : float
        limsup |c(s)| [1/m] over the path, >= 0.

    Raises
    ------
    ValueError
        If a value is not finite, ``k1 <= 0`` or ``max_path_curvature < 0``.

    >>> in_convergence_region(0.5, 0.5, 1.0, 1.0), in_convergence_region(0.9, 0.5, 1.0, 1.0)
    (True, False)

    """
    d = finite_real('lateral_error', lateral_error)
    heading = finite_real('heading_error', heading_error)
    gain = _positive('k1', k1)
    c_max = finite_real('max_path_curvature', max_path_curvature)
    if c_max < 0.0:
        raise ValueError(f'max_path_curvature must be >= 0, got {c_max!r}')
    return (d * d + heading * heading / gain) * c_max * c_max < 1.0


class FrenetPathFollower(PathTrackerBase[FrenetParams]):
    """
    Path follower in the Frenet frame of a :class:`PolylinePath` (book §9.4.3).

    Each update projects the vehicle onto the path within ``params.search_window`` of the
    progress s (so, as for pure pursuit, the vehicle should start near the start of the path
    and a closed path is driven once round), computes d, θ̃ and the curvature c(s), applies
    the chosen law at the desired speed, and lowers the speed if needed so that
    |ω| <= ``max_angular_velocity`` with the curvature kept. A polyline has no curvature
    between its vertices and an impulse at each; c(s) is the mean heading rate over
    [s - w, s + w] (w = ``curvature_window``, cut at the ends of an open path) with each
    vertex's turn spread over at most half of each adjacent segment, which gives 1/R on a
    finely sampled circle and the turn / (2 w) near a corner.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses given to :meth:`update` (e.g. ``odom``).
    params : FrenetParams
        Tunables; replace them at run time with :meth:`set_params`.

    Examples
    --------
    >>> follower = FrenetPathFollower(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), FrenetParams())
    >>> out = follower.update([0.0, 0.5, 0.0], 0.0)
    >>> out.linear, out.angular, out.extras['curvature'], out.cross_track  # u = -k1 v d
    (0.5, -0.25, -0.5, 0.5)

    """

    def __init__(self, path: PolylinePath, params: FrenetParams) -> None:
        super().__init__(path, params)
        self._curvature = _CurvatureProfile(path, params.curvature_window)

    def set_params(self, params: FrenetParams) -> None:
        """
        Use ``params`` from the next :meth:`update` on; the progress is kept.

        >>> follower = FrenetPathFollower(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), FrenetParams())
        >>> follower.set_params(FrenetParams(law='nonlinear'))
        >>> follower.params.law
        'nonlinear'

        """
        if params.curvature_window != self._params.curvature_window:
            self._curvature = _CurvatureProfile(self._path, params.curvature_window)
        self._params = params

    def path_curvature(self, s: float) -> float:
        """
        Return the estimated path curvature c(s) [1/m] at arc length ``s`` [m].

        Raises
        ------
        ValueError
            If ``s`` is not finite.

        >>> square = PolylinePath([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]])
        >>> follower = FrenetPathFollower(square, FrenetParams(curvature_window=0.5))
        >>> round(follower.path_curvature(2.0), 12), follower.path_curvature(1.0)
        (1.570796326795, 0.0)

        """
        return self._curvature(finite_real('s', s))

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Return the command for vehicle pose ``pose`` (one control period).

        Steps: (1) project the position onto the path within the search window around the
        progress; (2) d, θ̃ (:func:`frenet_errors`) and c(s); (3) ω at the desired speed v by
        (9.90) with (9.93) or (9.99) (:func:`frenet_angular_velocity`), γ = ω / v; (4) if
        |ω| > ``max_angular_velocity``, v = max_angular_velocity / |γ| and ω = v γ. Once the
        remaining arc length and the distance to the last point are both within
        ``goal_tolerance`` the command is zero and stays so
        until :meth:`reset`; as for :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`,
        a closed path is driven once round from its start.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        time : float
            Time of the pose [s]; not used.
        speed : float, optional
            Measured speed [m/s]; not used (the law runs at the desired speed).

        Returns
        -------
        TrackerOutput
            Velocities; ``cross_track`` and ``heading_error`` are the d and θ̃ of the law,
            ``target_point`` the closest point of the path; ``extras``: ``curvature``
            γ = ω / v [1/m] and ``path_curvature`` c(s) [1/m] of the feed-forward.

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector.

        """
        x, projection = self._locate(pose)
        params = self._params
        errors = frenet_errors(x, projection, self._curvature(projection.s))
        if self._finished:
            v = gamma = 0.0
        else:
            v = params.desired_linear_velocity
            gamma = frenet_angular_velocity(errors, v, params) / v
            if abs(v * gamma) > params.max_angular_velocity:
                v = params.max_angular_velocity / abs(gamma)
        return TrackerOutput(v, v * gamma, errors.lateral_error, errors.heading_error,
                             projection.along_track, projection.point, self._finished,
                             {'curvature': gamma, 'path_curvature': errors.path_curvature})


def steering_state_matrices(linear_velocity: float, steering_time_constant: float,
                            wheelbase: float | None = None
                            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return (A (3, 3), B (3,)) of the linearised path-following model with steering lag.

    Book (9.109)-(9.113) in REP-103, state x = (d [m], θ̃ [rad], γ [1/m]), d > 0 left:
    d' = v θ̃, θ̃' = v γ, γ' = (u - γ)/τ, so A = [[0, v, 0], [0, 0, v], [0, 0, -1/τ]] and
    B = (0, 0, 1/τ) (the book's first row is -v for its right-positive ξ = -d). With a
    ``wheelbase`` l the third state is instead the steering angle α [rad] (γ = tan α / l ≈ α/l,
    §9.4.4) and u the commanded angle: A[1, 2] = v / l.

    Parameters
    ----------
    linear_velocity : float
        v [m/s], held constant.
    steering_time_constant : float
        τ [s] of the first-order steering actuator, > 0.
    wheelbase : float, optional
        l [m], > 0; None keeps the book's curvature state.

    Raises
    ------
    ValueError
        If ``v`` is not finite, or ``τ`` or ``l`` is not positive and finite.

    >>> A, B = steering_state_matrices(2.0, 0.5)
    >>> A
    array([[ 0.,  2.,  0.],
           [ 0.,  0.,  2.],
           [ 0.,  0., -2.]])
    >>> B
    array([0., 0., 2.])

    """
    v = finite_real('linear_velocity', linear_velocity)
    tau = _positive('steering_time_constant', steering_time_constant)
    scale = 1.0 if wheelbase is None else 1.0 / _positive('wheelbase', wheelbase)
    a = np.array([[0.0, v, 0.0], [0.0, 0.0, v * scale], [0.0, 0.0, -1.0 / tau]])
    return a, np.array([0.0, 0.0, 1.0 / tau])


def steering_feedback(lateral_error: float, heading_error: float, steering: float,
                      gains: ArrayLike) -> float:
    """
    Return the steering command u = -k1 d - k2 θ̃ - k3 γ, book (9.114) in REP-103.

    Parameters
    ----------
    lateral_error : float
        d [m], > 0 left of the path (the book's -ξ, hence its k1 is -k1 here).
    heading_error : float
        θ̃ [rad].
    steering : float
        Current steering state γ [1/m] (or α [rad] with a wheelbase).
    gains : array_like, shape (3,)
        (k1, k2, k3).

    Returns
    -------
    float
        Commanded curvature [1/m] (or steering angle [rad]) fed to the actuator.

    Raises
    ------
    ValueError
        If a value is not finite or ``gains`` is not of shape (3,).

    >>> steering_feedback(0.5, 0.1, 0.2, [1.0, 2.0, 0.5])
    -0.8

    """
    k = _gains(gains)
    x = np.array([finite_real('lateral_error', lateral_error),
                  finite_real('heading_error', heading_error),
                  finite_real('steering', steering)])
    return -float(k @ x)


def characteristic_polynomial(gains: ArrayLike, linear_velocity: float,
                              wheelbase: float | None,
                              steering_time_constant: float) -> NDArray[np.float64]:
    """
    Return the coefficients (4,) of the closed-loop characteristic polynomial, book (9.116).

    det(s I - (A - B K)) τ = τ s³ + (1 + k3) s² + (v/l) k2 s + (v²/l) k1, highest power first
    (the order of :func:`numpy.roots`), with l = 1 when ``wheelbase`` is None. The book prints
    ... - v² k1 for its right-positive ξ, i.e. its k1 is -k1 here.

    Parameters
    ----------
    gains : array_like, shape (3,)
        (k1, k2, k3) of :func:`steering_feedback`.
    linear_velocity : float
        v [m/s].
    wheelbase : float or None
        l [m] > 0, or None for the book's curvature state.
    steering_time_constant : float
        τ [s], > 0.

    Raises
    ------
    ValueError
        On a bad gain vector, a non-finite ``v``, or ``τ``, ``l`` not positive and finite.

    >>> characteristic_polynomial([1.0, 2.0, 0.5], 2.0, None, 0.5)
    array([0.5, 1.5, 4. , 4. ])

    """
    k1, k2, k3 = _gains(gains)
    a, _ = steering_state_matrices(linear_velocity, steering_time_constant, wheelbase)
    tau = float(steering_time_constant)
    v, v_over_l = float(linear_velocity), float(a[1, 2])
    return np.array([tau, 1.0 + k3, v_over_l * k2, v * v_over_l * k1])


def routh_table(gains: ArrayLike, linear_velocity: float, wheelbase: float | None,
                steering_time_constant: float) -> NDArray[np.float64]:
    """
    Return the Routh array (4, 2) of the characteristic polynomial (9.116).

    For a3 s³ + a2 s² + a1 s + a0 the rows are s³: (a3, a1), s²: (a2, a0),
    s¹: ((a2 a1 - a3 a0)/a2, 0), s⁰: (a0, 0). With a3 = τ > 0 the system is stable iff the
    first column is positive, which is (9.117): (1 + k3)/τ > 0, v k2/(l τ) > 0, k1 > 0 (the
    book's k1/τ < 0), and (1 + k3) k2/(v τ) > k1 (the book's ... > -k1) for v > 0. When
    a2 = 0 the s¹ entry is NaN (not stable: a zero in the first column).

    Parameters
    ----------
    gains, linear_velocity, wheelbase, steering_time_constant
        As in :func:`characteristic_polynomial`.

    Raises
    ------
    ValueError
        As :func:`characteristic_polynomial`.

    >>> routh_table([1.0, 2.0, 0.5], 2.0, None, 0.5)[:, 0]
    array([0.5       , 1.5       , 2.66666667, 4.        ])

    """
    a3, a2, a1, a0 = characteristic_polynomial(gains, linear_velocity, wheelbase,
                                               steering_time_constant)
    b1 = (a2 * a1 - a3 * a0) / a2 if a2 != 0.0 else math.nan
    return np.array([[a3, a1], [a2, a0], [b1, 0.0], [a0, 0.0]])


def routh_stable(gains: ArrayLike, linear_velocity: float, wheelbase: float | None,
                 steering_time_constant: float) -> bool:
    """
    Return whether the state feedback (9.114) stabilises the model (9.111), book (9.117).

    Routh's criterion: every entry of the first column of :func:`routh_table` is > 0
    (τ > 0), i.e. all roots of (9.116) lie in the open left half plane.

    Parameters
    ----------
    gains, linear_velocity, wheelbase, steering_time_constant
        As in :func:`characteristic_polynomial`.

    Raises
    ------
    ValueError
        As :func:`characteristic_polynomial`.

    >>> routh_stable([1.0, 2.0, 0.5], 2.0, None, 0.5)
    True
    >>> routh_stable([-1.0, 2.0, 0.5], 2.0, None, 0.5)  # the book's k1 > 0: unstable
    False

    """
    column = routh_table(gains, linear_velocity, wheelbase, steering_time_constant)[:, 0]
    return bool(np.all(column > 0.0))


class _CurvatureProfile:
    """
    Mean heading rate of a polyline over a window of arc length: c(s) [1/m].

    The heading Θ(σ) of the polyline, unwrapped, steps by the turn of each vertex; here each
    step is spread linearly over [s_i - r_i, s_i + r_i], r_i = min(w, half of each adjacent
    segment), and c(s) = (Θ(hi) - Θ(lo)) / (hi - lo) with [lo, hi] = [s - w, s + w] (cut at
    the ends of an open path; a closed path's vertices repeat on the laps before and after).
    """

    def __init__(self, path: PolylinePath, window: float) -> None:
        headings, seg_len, s = path.headings, np.diff(path.s), path.s
        length = path.length
        self._closed = path.closed
        self._length = length
        self._window = min(window, 0.5 * length) if path.closed else window
        turn = np.asarray(wrap_to_pi(np.diff(headings)), dtype=np.float64).reshape(-1)
        at = s[1:-1]
        half = 0.5 * np.minimum(seg_len[:-1], seg_len[1:])
        if path.closed:
            turn = np.append(turn, wrap_to_pi(float(headings[0] - headings[-1])))
            at = np.append(at, 0.0)
            half = np.append(half, 0.5 * min(float(seg_len[-1]), float(seg_len[0])))
            order = np.argsort(at, kind='stable')
            turn, at, half = turn[order], at[order], half[order]
            turn = np.concatenate((turn, turn, turn))
            at = np.concatenate((at - length, at, at + length))
            half = np.concatenate((half, half, half))
        self._turn = turn
        self._at = at
        self._radius = np.minimum(half, self._window)

    def __call__(self, s: float) -> float:
        w = self._window
        if self._closed:
            s = s % self._length
            lo, hi = s - w, s + w
        else:
            lo, hi = max(s - w, 0.0), min(s + w, self._length)
            if hi <= lo:
                return 0.0
        first = int(np.searchsorted(self._at, lo - w, side='left'))
        stop = int(np.searchsorted(self._at, hi + w, side='right'))
        at, r = self._at[first:stop], self._radius[first:stop]
        start, width = at - r, 2.0 * r

        def theta(sigma: float) -> float:
            ramp = np.clip((sigma - start) / width, 0.0, 1.0)
            return float(self._turn[first:stop] @ ramp)

        return (theta(hi) - theta(lo)) / (hi - lo)


def _error_triple(errors: FrenetErrors | ArrayLike) -> tuple[float, float, float]:
    """Return (d, θ̃, c) from a :class:`FrenetErrors` or a finite 3-vector."""
    if isinstance(errors, FrenetErrors):
        return errors.lateral_error, errors.heading_error, errors.path_curvature
    e = np.asarray(errors, dtype=np.float64)
    if e.shape != (3,) or not np.all(np.isfinite(e)):
        raise ValueError(f'errors must be a finite (3,) vector (d, heading, c), got {errors!r}')
    return float(e[0]), float(e[1]), float(e[2])


def _gains(gains: ArrayLike) -> NDArray[np.float64]:
    """Return ``gains`` as a finite (3,) float64 vector (k1, k2, k3), or raise ValueError."""
    k = np.asarray(gains, dtype=np.float64)
    if k.shape != (3,) or not np.all(np.isfinite(k)):
        raise ValueError(f'gains must be a finite (3,) vector (k1, k2, k3), got {gains!r}')
    return k


def _positive(name: str, value: float) -> float:
    """Return ``value`` as a float, or raise ValueError if it is not positive and finite."""
    x = finite_real(name, value)
    if not x > 0.0:
        raise ValueError(f'{name} must be positive and finite, got {value!r}')
    return x
