"""
State shared by the path trackers of book ch. 9: the path, the tunables, the progress, the end.

:class:`PathTrackerBase` holds what pure pursuit (§9.3.1), the quintic tracker (§9.3.2), the
Frenet path follower (§9.4.3) and the GPC tracker (§9.5) have in common: a
:class:`~robotica_ctrl.mobile.path.PolylinePath`, tunables replaceable at run time, the
progress s [m] along the path (each update searches the closest point only within
``search_window`` of it, so a closed path is driven lap by lap from its start), and the
finished flag (set once both the remaining arc length and the distance to the last point are
within ``goal_tolerance``, kept until :meth:`PathTrackerBase.reset`). Each law subclasses it and
adds its own :meth:`update`.
"""

import math
from typing import Generic, Protocol, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_kin.finite import all_finite

__all__ = ['PathTrackerBase', 'TrackerParams', 'check_pose']


class TrackerParams(Protocol):
    """The tunables every path tracker reads: its finish and search distances [m]."""

    @property
    def goal_tolerance(self) -> float:
        """Distance to the end [m] within which the path is finished."""

    @property
    def search_window(self) -> float:
        """Half-width [m] of the closest-point search around the progress."""


ParamsT = TypeVar('ParamsT', bound=TrackerParams)


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
