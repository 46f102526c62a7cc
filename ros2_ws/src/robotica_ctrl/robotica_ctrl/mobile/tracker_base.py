"""
What every tracking law of book ch. 9 shares: its output, its interface, the path state.

:class:`TrackerOutput` is the one answer of every law to :meth:`TrackingLaw.update`: the
velocity command (v [m/s], ω [rad/s]), the tracking errors the ``path_tracker`` node publishes
as ``robotica_msgs/TrackingError``, the end flag and the law's own telemetry (``extras``: its
curvature, quintic, GPC prediction, ...). :class:`TrackingLaw` is the interface the node and
the tracking benchmark drive, whatever the law.

:class:`PathTrackerBase` holds what pure pursuit (§9.3.1), the quintic tracker (§9.3.2), the
Frenet path follower (§9.4.3) and the GPC tracker (§9.5) have in common: a
:class:`~robotica_ctrl.mobile.path.PolylinePath`, tunables replaceable at run time, the
progress s [m] along the path (each update searches the closest point only within
``search_window`` of it, so a closed path is driven lap by lap from its start), and the
finished flag (set once both the remaining arc length and the distance to the last point are
within ``goal_tolerance``, kept until :meth:`PathTrackerBase.reset`). Each law subclasses it and
adds its own :meth:`update`.
"""

from dataclasses import fields, replace
import math
from types import MappingProxyType
from typing import (Any, ClassVar, Generic, Mapping, NamedTuple, Protocol, TYPE_CHECKING,
                    TypeVar)

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_kin.finite import all_finite

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = ['PathTrackerBase', 'TrackerOutput', 'TrackerParams', 'TrackingLaw', 'angle_error',
           'check_pose', 'replace_gains']

_NO_EXTRAS: Mapping[str, Any] = MappingProxyType({})


class TrackerOutput(NamedTuple):
    """
    One step of any law: the command, the errors the node reports as ``TrackingError``, extras.

    Attributes
    ----------
    linear : float
        Forward velocity v [m/s] in ``base_link``.
    angular : float
        Yaw rate ω [rad/s], > 0 counter-clockwise.
    cross_track : float
        Lateral offset from the path (or the reference) [m], > 0 left of it; NaN for a law
        that follows no path (the open-loop profile).
    heading_error : float
        θ - θ_path (or θ - θ_ref) [rad], wrapped to (-π, π]; NaN without a path.
    along_track : float
        Offset along the path beyond its ends (path laws), or behind the reference
        (trajectory tracking, > 0 when the robot lags) [m]; NaN without a path.
    target_point : ndarray, shape (2,)
        The point the law steers to: goal point, closest point or reference position [m],
        read-only; NaN without a path.
    finished : bool
        Whether the end of the path (or trajectory) was reached; the command is then zero.
    extras : mapping
        The law's own telemetry by name, e.g. ``curvature`` γ [1/m] of the geometric laws
        (ω = v γ), the quintic's ``coefficients``, GPC's ``reference`` and ``prediction``;
        each law's docstring lists its keys.

    Examples
    --------
    >>> out = TrackerOutput(0.5, 0.0, 0.1, 0.0, 0.0, np.zeros(2), False, {'curvature': 0.0})
    >>> out.linear, out.extras['curvature']
    (0.5, 0.0)

    """

    linear: float
    angular: float
    cross_track: float
    heading_error: float
    along_track: float
    target_point: NDArray[np.float64]
    finished: bool
    extras: Mapping[str, Any] = _NO_EXTRAS


class TrackingLaw(Protocol):
    """A tracking law with its state, driven once per control period by :meth:`update`."""

    def update(self, pose: ArrayLike, time: float,
               speed: float | None = None) -> TrackerOutput:
        """
        Return the command and errors for ``pose`` (x [m], y [m], θ [rad]) at ``time`` [s].

        ``speed`` is the measured forward speed [m/s] when known (adaptive look-ahead, GPC
        model). A law that reads the pose raises ValueError for one that is not a finite (3,)
        vector.
        """

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace some gains (names of the law's parameters); ValueError keeps the old."""

    def reset(self) -> None:
        """Restart from the beginning of the path (and of the trajectory)."""


class TrackerParams(Protocol):
    """The tunables every path tracker reads: a dataclass with its finish and search distances."""

    __dataclass_fields__: ClassVar[dict[str, Any]]

    @property
    def goal_tolerance(self) -> float:
        """Distance to the end [m] within which the path is finished."""

    @property
    def search_window(self) -> float:
        """Half-width [m] of the closest-point search around the progress."""


ParamsT = TypeVar('ParamsT', bound=TrackerParams)
DataclassT = TypeVar('DataclassT', bound='DataclassInstance')

_FIELD = {'variant': 'law'}   # gain name -> params field, where they differ ('law' is the node's)


def replace_gains(params: DataclassT, gains: Mapping[str, Any]) -> DataclassT:
    """
    Return a copy of the tunables ``params`` (a frozen dataclass) with ``gains`` applied.

    Gains are named as the law's parameters of the ``path_tracker`` node, which are the
    dataclass's fields but for ``variant`` (the field ``law``: the node's ``law`` names the
    tracking law itself). The dataclass checks the new values.

    Raises
    ------
    ValueError
        For a name that is not a field, or a value the dataclass refuses.

    >>> from robotica_ctrl.mobile.pure_pursuit import PurePursuitParams
    >>> replace_gains(PurePursuitParams(), {'lookahead_distance': 1.0}).lookahead_distance
    1.0

    """
    names = {field.name for field in fields(params)}
    changes = {_FIELD.get(name, name): value for name, value in gains.items()}
    unknown = sorted(set(changes) - names)
    if unknown:
        raise ValueError(f'no gain {unknown}; the gains: {sorted(names)}')
    return replace(params, **changes)


def angle_error(theta: float, reference: float) -> float:
    """
    Return θ - θ_ref [rad] wrapped to (-π, π] (scalar, exact: ``math.remainder``).

    >>> angle_error(3.0, -3.0) == 6.0 - 2.0 * math.pi
    True
    """
    error = math.remainder(theta - reference, math.tau)
    return math.pi if error == -math.pi else error


def check_pose(pose: ArrayLike) -> NDArray[np.float64]:
    """
    Return ``pose`` (x [m], y [m], θ [rad]) as a float64 (3,) array, or raise ValueError.

    >>> check_pose([1, 2, 0.5])
    array([1. , 2. , 0.5])
    """
    x = np.asarray(pose, dtype=np.float64)
    if x.shape != (3,) or not all_finite(x):
        raise ValueError(f'pose must be a finite (3,) vector (x, y, theta), got {pose!r}')
    return x


class PathTrackerBase(Generic[ParamsT]):
    """
    Path, tunables, progress and end of a path tracker (the law is the subclass's update).

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses given to ``update`` (e.g. ``odom``).
    params : dataclass with ``goal_tolerance`` and ``search_window`` [m]
        Tunables; replace them at run time with :meth:`set_params`.

    """

    def __init__(self, path: PolylinePath, params: ParamsT) -> None:
        self._path = path
        self._params = params
        self._progress = 0.0
        self._finished = False
        self._projection: PathProjection | None = None

    @property
    def path(self) -> PolylinePath:
        """Return the reference path."""
        return self._path

    @property
    def params(self) -> ParamsT:
        """Return the current tunables."""
        return self._params

    @property
    def progress(self) -> float:
        """Return the arc length [m] of the last projection onto the path (0 after a reset)."""
        return self._progress

    @property
    def finished(self) -> bool:
        """Return whether the end of the path has been reached (until :meth:`reset`)."""
        return self._finished

    @property
    def last_projection(self) -> PathProjection | None:
        """Return the projection of the last pose onto the path (None before any update)."""
        return self._projection

    def set_params(self, params: ParamsT) -> None:
        """Use ``params`` from the next update on; the progress is kept."""
        self._params = params

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace some tunables by name (:func:`replace_gains`); ValueError keeps the old."""
        self.set_params(replace_gains(self._params, gains))

    def reset(self) -> None:
        """Restart from the beginning of the path: progress 0, not finished."""
        self._progress = 0.0
        self._finished = False
        self._projection = None

    def _locate(self, pose: ArrayLike) -> tuple[NDArray[np.float64], PathProjection]:
        """
        Check ``pose``, project it within the search window and update progress and end.

        Return the pose as a (3,) array and its projection onto the path.
        """
        x = check_pose(pose)
        path, params = self._path, self._params
        projection = path.project(x[:2], s_hint=self._progress, window=params.search_window)
        self._progress = projection.s
        self._projection = projection
        (end_x, end_y), (x_0, y_0) = path.points[-1].tolist(), x[:2].tolist()
        end_distance = math.hypot(end_x - x_0, end_y - y_0)
        if max(path.length - projection.s, end_distance) <= params.goal_tolerance:
            self._finished = True
        return x, projection

    @staticmethod
    def _output(linear: float, angular: float, theta: float, projection: PathProjection,
                target: NDArray[np.float64], finished: bool,
                extras: Mapping[str, Any]) -> TrackerOutput:
        """Return the output of a path law at heading θ [rad] with its projection."""
        target.flags.writeable = False
        return TrackerOutput(float(linear), float(angular), projection.cross_track,
                             angle_error(theta, projection.tangent_heading),
                             projection.along_track, target, finished, extras)
