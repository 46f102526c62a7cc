"""
Pure-pursuit path tracking (book §9.3.1, (9.1)-(9.7), fig. 9.4).

Each control period the tracker of Ollero (2001) finds the path point closest to the vehicle,
takes the goal point a fixed arc length L (the look-ahead) further along the path, and steers
along the circular arc through the vehicle and the goal point that is tangent to the vehicle's
heading. In the vehicle frame that arc has curvature γ = 2 y / L², with y the goal point's
lateral offset and L its distance (9.5), (9.7): a proportional law on the lateral offset with
gain 2/L². The book's safeguards are kept: the goal point is clamped at the end of the path,
and a goal point behind the vehicle (heading roughly opposite to the path) gets a larger
curvature. The speed law (slow-down near the end, curvature-preserving limit on the angular
velocity) follows the approach and curvature regulations of Nav2's Regulated Pure Pursuit.

The book writes the law with the forward axis along y and the offset Δx positive to the right,
γ = -2 Δx / L² (9.5)-(9.6); here frames are REP-103 (``base_link`` x forward, y left, θ from
the x axis) and γ = 2 y / L², positive to the left.
"""

from dataclasses import dataclass, fields
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.tracker_base import PathTrackerBase, TrackerOutput

__all__ = ['PurePursuit', 'PurePursuitParams', 'curvature_to_point']


def curvature_to_point(p: ArrayLike) -> float:
    """
    Return the pure-pursuit curvature [1/m] towards goal point ``p`` [m] in ``base_link``.

    Book (9.5) with (9.7), REP-103 form: γ = 2 y / L² with L = |p|. The circle of this
    curvature tangent to the x axis at the origin passes through ``p``; γ > 0 turns left.

    Parameters
    ----------
    p : array_like, shape (2,)
        Goal point (x, y) [m] in the vehicle frame ``base_link`` (x forward, y left).

    Returns
    -------
    float
        Curvature γ [1/m] (the inverse of the signed turning radius).

    Raises
    ------
    ValueError
        If ``p`` is not a finite (2,) vector or is the origin (L = 0).

    >>> curvature_to_point([1.0, 1.0])
    1.0

    """
    q = np.asarray(p, dtype=np.float64)
    if q.shape != (2,):
        raise ValueError(f'p must be a finite (2,) vector, got {p!r}')
    x, y = q.tolist()
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f'p must be a finite (2,) vector, got {p!r}')
    return _curvature_xy(x, y)


def _curvature_xy(x: float, y: float) -> float:
    """Return γ = 2 y / (x² + y²) [1/m], book (9.5), for a finite goal (x, y) [m] in base_link."""
    lookahead_sq = x * x + y * y
    if lookahead_sq == 0.0:
        raise ValueError('the goal point is at the vehicle (L = 0): curvature undefined')
    return 2.0 * y / lookahead_sq


@dataclass(frozen=True)
class PurePursuitParams:
    """
    Tunables of :class:`PurePursuit`; all must be positive and finite.

    Raises
    ------
    ValueError
        If a value is not positive and finite, or
        ``min_approach_velocity > desired_linear_velocity``.

    Examples
    --------
    >>> PurePursuitParams(lookahead_distance=1.0).lookahead_distance
    1.0

    """

    lookahead_distance: float = 0.5  # L [m], book (9.7): arc length from closest to goal point
    desired_linear_velocity: float = 0.5  # [m/s]
    max_angular_velocity: float = 1.5  # [rad/s]
    goal_tolerance: float = 0.05  # [m]
    approach_distance: float = 0.5  # [m], slow down linearly within this distance of the end
    min_approach_velocity: float = 0.05  # [m/s]
    search_window: float = 2.0  # [m] window of the closest-point search around the progress

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{field.name} must be positive and finite, got {value!r}')
        if self.min_approach_velocity > self.desired_linear_velocity:
            raise ValueError(
                f'min_approach_velocity ({self.min_approach_velocity!r} m/s) must not exceed '
                f'desired_linear_velocity ({self.desired_linear_velocity!r} m/s)')


class PurePursuit(PathTrackerBase[PurePursuitParams]):
    """
    Pure-pursuit tracker of a :class:`PolylinePath` (book §9.3.1, fig. 9.4).

    The state is the progress s [m] along the path: each update searches the closest point
    only within ``params.search_window`` of it, so a closed path is followed lap by lap from
    its start and the progress never falls back by more than the window. Before the first
    update the progress is 0, so the vehicle is expected near the start of the path; the
    search window should be shorter than half a closed path.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses given to :meth:`update` (e.g. ``odom``).
    params : PurePursuitParams
        Tunables; replace them at run time with :meth:`set_params`.
    extend_end : bool
        Take the goal point beyond the end on the line of the last segment instead of at the
        end (ext.): the vehicle then arrives along the end's tangent, not just at the point,
        which a manoeuvre that must end parallel to a line (parking) needs. The end, the
        approach and the finish are the path's own either way.

    Examples
    --------
    >>> from robotica_ctrl.mobile.path import PolylinePath
    >>> tracker = PurePursuit(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), PurePursuitParams())
    >>> out = tracker.update([0.0, 0.0, 0.0], 0.0)
    >>> out.linear, out.extras['curvature'], out.target_point
    (0.5, 0.0, array([0.5, 0. ]))
    >>> ahead = PurePursuit(PolylinePath([[0.0, 0.0], [1.0, 0.0]]), PurePursuitParams(),
    ...                     extend_end=True)
    >>> ahead.update([0.8, 0.1, 0.0], 0.0).target_point   # 0.5 m on from s = 0.8 m
    array([1.3, 0. ])

    """

    def __init__(self, path: PolylinePath, params: PurePursuitParams,
                 extend_end: bool = False) -> None:
        super().__init__(path, params)
        self._extend_end = extend_end

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Return the command for vehicle pose ``pose`` (one period of fig. 9.4).

        Steps: (1) project the position onto the path within the search window around the
        progress; (2) goal point at arc length s + ``lookahead_distance``, clamped at the
        end of the path; (3) curvature (9.5) γ = 2 y / D² to the goal point (x, y) in
        ``base_link``, D = |(x, y)| being the book's L of (9.7); a goal point behind the
        vehicle (x <= 0, heading roughly opposite to the path) gets the larger value
        sign(y) max(|2 y / D²|, 2 / D) = sign(y) 2 / D, turning left when y = 0 (the book's
        safeguard); (4) speed v = desired, reduced linearly within
        ``approach_distance`` of the end (not below ``min_approach_velocity``) and then so
        that |v γ| <= ``max_angular_velocity`` with γ kept; ω = v γ. Once the remaining arc
        length and the distance to the last point are both within ``goal_tolerance`` the
        command is zero and stays so until :meth:`reset`.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        time : float
            Time of the pose [s]; not used (the law has no dynamics).
        speed : float, optional
            Measured speed [m/s]; not used.

        Returns
        -------
        TrackerOutput
            Velocities, errors from the projection, the goal point as ``target_point``;
            ``extras['curvature']`` is γ [1/m].

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector, or the goal point coincides with the
            vehicle position (L = 0).

        >>> from robotica_ctrl.mobile.path import PolylinePath
        >>> tracker = PurePursuit(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), PurePursuitParams())
        >>> tracker.update([0.0, 0.5, 0.0], 0.0).extras['curvature']  # 2 (-0.5) / (0.5² + 0.5²)
        -2.0

        """
        x, projection = self._locate(pose)
        params = self._params
        ahead = projection.s + params.lookahead_distance
        goal = self._path.point_at(ahead)
        if self._extend_end and ahead > self._path.length:   # on along the last segment
            end_heading = self._path.heading_at(self._path.length)
            goal = goal + (ahead - self._path.length) * np.array(
                [math.cos(end_heading), math.sin(end_heading)])
        theta = float(x[2])
        if self._finished:
            return self._output(0.0, 0.0, theta, projection, goal, True, {'curvature': 0.0})
        remaining = self._path.length - projection.s
        gamma = _steering_curvature(goal - x[:2], theta)
        v = params.desired_linear_velocity
        if remaining < params.approach_distance:
            v = max(v * remaining / params.approach_distance, params.min_approach_velocity)
        if abs(v * gamma) > params.max_angular_velocity:
            v = params.max_angular_velocity / abs(gamma)
        return self._output(v, v * gamma, theta, projection, goal, False, {'curvature': gamma})


def _steering_curvature(offset: NDArray[np.float64], theta: float) -> float:
    """
    Return γ [1/m] towards a goal at ``offset`` [m] (path frame) from a vehicle heading θ.

    Book (9.5)-(9.7) with the reversed-heading safeguard of §9.3.1 for a goal behind.
    """
    dx, dy = offset.tolist()
    c, s = math.cos(theta), math.sin(theta)
    x, y = c * dx + s * dy, -s * dx + c * dy  # goal in base_link [m]
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f'the goal point must be finite, got {(x, y)!r}')
    gamma = _curvature_xy(x, y)
    if x > 0.0:
        return gamma
    # Goal behind: sign(y) max(|2 y / D²|, 2 / D), which is sign(y) 2 / D as |y| <= D.
    larger = 2.0 / math.hypot(x, y)
    return larger if y >= 0.0 else -larger
