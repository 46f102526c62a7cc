"""
Pure pursuit that can reverse: a path of postures whose motion changes direction (§9.3.1).

A manoeuvre such as the course's parallel parking (catalogue Part 14) drives forward and in
reverse. Its path is given as postures (x, y, θ) [m, rad] of the vehicle's reference point (the
rear-axle midpoint of a car): where the step from one posture to the next points against the
heading, the vehicle moves in reverse. The path is cut at every change of direction (a cusp)
into pieces, each followed by :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit` (9.1)-(9.7);
a reverse piece is followed as pure pursuit would follow it with the vehicle turned round (its
heading θ + π), and the command is mirrored: the speed negated, the yaw rate kept (the turned
vehicle's yaw rate is the vehicle's own). Each piece's goal point runs on beyond its end along
its last segment (``PurePursuit(..., extend_end=True)``, ext.): the vehicle reaches a cusp
along the path's tangent there, parallel to the street at the ends of the parking arcs. At the
end of each piece the vehicle stops (the geometric mode of the parking planner: the wheels are
re-oriented standing) and the next piece begins; the path is finished at the end of the last.
The errors are measured against the postures' headings (left of the heading is > 0 forward
and reverse alike), so they run on continuously through a cusp.

It is the ``reversing_pure_pursuit`` law of the registry
(:mod:`~robotica_ctrl.mobile.tracking_laws`) and of the ``path_tracker`` node, which reads the
postures from a ``nav_msgs/Path``: each pose's position and the yaw of its orientation.
"""

import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .path import PolylinePath
from .pure_pursuit import PurePursuit, PurePursuitParams
from .tracker_base import check_pose, replace_gains, TrackerOutput

__all__ = ['ReversingPurePursuit', 'motion_directions']


def motion_directions(poses: ArrayLike) -> NDArray[np.int8]:
    """
    Return +1 (forward) or -1 (reverse) for each step between consecutive postures (N - 1,).

    A step against the heading (its displacement · (cos θ, sin θ) < 0) is reverse; a step of no
    length takes the direction of the step before it (forward at the start).

    >>> motion_directions([[0, 0, 0], [1, 0, 0], [0.5, 0, 0]]).tolist()
    [1, -1]
    """
    p = np.asarray(poses, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) < 2 or not np.isfinite(p).all():
        raise ValueError(f'poses must be (N, 3) finite postures, N >= 2, got shape {p.shape}')
    step = np.diff(p[:, :2], axis=0)
    along = step[:, 0] * np.cos(p[:-1, 2]) + step[:, 1] * np.sin(p[:-1, 2])
    directions = np.ones(len(step), dtype=np.int8)
    for k, value in enumerate(along):
        directions[k] = (1 if value > 0.0 else -1) if abs(value) > 1e-12 else \
            (directions[k - 1] if k else 1)
    return directions


class ReversingPurePursuit:
    """
    Follow a path of postures forward and in reverse, stopping at each cusp (module docstring).

    Parameters
    ----------
    poses : array_like, shape (N, 3)
        The postures (x, y, θ) [m, rad] of the path, map frame, N >= 2.
    params : PurePursuitParams, optional
        The tunables of each piece's pure pursuit.

    Raises
    ------
    ValueError
        For poses that are not (N, 3) finite postures, or a piece of fewer than two distinct
        points.

    Examples
    --------
    Two metres forward, then one back: the first command drives forward, and after the cusp the
    vehicle reverses.

    >>> law = ReversingPurePursuit([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 0, 0]])
    >>> law.pieces, law.update([0.0, 0.0, 0.0], 0.0).linear > 0.0
    (2, True)

    """

    def __init__(self, poses: ArrayLike, params: PurePursuitParams | None = None) -> None:
        p = np.asarray(poses, dtype=np.float64)
        directions = motion_directions(p)
        cusps = np.flatnonzero(np.diff(directions)) + 1   # step index where direction changes
        bounds = [0, *cusps.tolist(), len(directions)]
        self.params = PurePursuitParams() if params is None else params
        self._pieces: list[tuple[PurePursuit, int]] = []
        for first, last in zip(bounds[:-1], bounds[1:]):   # steps first..last-1: points ..last
            path = PolylinePath(p[first:last + 1, :2])
            self._pieces.append((PurePursuit(path, self.params, extend_end=True),
                                 int(directions[first])))
        self._index = 0

    @property
    def pieces(self) -> int:
        """Return how many pieces the path has (one more than its cusps)."""
        return len(self._pieces)

    @property
    def piece(self) -> int:
        """Return the index of the piece being followed."""
        return self._index

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace pure pursuit's tunables (names of :class:`PurePursuitParams`) on every piece."""
        self.params = replace_gains(self.params, gains)
        for law, _ in self._pieces:
            law.set_gains(gains)

    def reset(self) -> None:
        """Start again from the first piece."""
        self._index = 0
        for law, _ in self._pieces:
            law.reset()

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Return the command (v [m/s], ω [rad/s]) for the vehicle at ``pose`` (x, y, θ).

        v < 0 on a reverse piece; (0, 0) when a piece ends (a stop at the cusp), the next
        update following the next piece. ``speed`` is the measured forward speed [m/s] (< 0
        reversing). The errors are the piece's, measured against the postures' headings: the
        cross-track error > 0 left of the path as the vehicle faces along it (on a reverse
        piece: left of the heading, not of the travel), the heading error θ - θ_path with
        θ_path the posture's heading, the along-track offset beyond the piece's ends (> 0 past
        its end in the direction of travel). ``extras``: pure pursuit's ``curvature`` γ [1/m]
        (of the turned vehicle, ω = |v| γ), ``piece`` (its index) and ``direction`` (+1, -1).

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector.

        """
        x, y, theta = check_pose(pose).tolist()
        law, direction = self._pieces[self._index]
        turned = [x, y, theta + math.pi] if direction < 0 else [x, y, theta]
        out = law.update(turned, time, None if speed is None else direction * speed)
        extras = {**out.extras, 'piece': self._index, 'direction': direction}
        out = out._replace(cross_track=direction * out.cross_track, extras=extras)
        if out.finished and self._index < len(self._pieces) - 1:
            self._index += 1
            return out._replace(linear=0.0, angular=0.0, finished=False)
        return out._replace(linear=direction * out.linear)
