"""
A robot's footprint moved along a path: where it first meets an obstacle (book §12.5).

Book §12.5 (seed catalogue Part 10.4) names Cameron's practical approach to collision
detection along a motion: sample the motion and test static interference. Here the motion
between samples is not left untested: each step is swept with
:func:`robotica_kin.world.swept_collision` (exact for a circle among walls, polygons and
circles, conservative advancement otherwise), so nothing tunnels between samples. Two motions
are checked, as a path is given:

* a polyline (N, 2) [m] is driven straight along each segment with the heading of that segment
  (:func:`polyline_collision`); what happens at a vertex (a turn on the spot, or the rounded
  turn of :mod:`~robotica_ctrl.planning.continuous_curvature`) is the follower's and is not
  part of it;
* a pose sequence (N, 3) (x [m], y [m], θ [rad]) moves from each pose to the next with x, y
  and θ linear, θ the short way (:func:`pose_collision`), as a vehicle following a sampled
  curve does.

``clearance`` [m] grows the obstacles first (:func:`robotica_kin.world.grow`, §12.4.4): a
motion free in the grown world keeps at least that distance from every obstacle. Everything
is in the map frame; the footprint is a radius [m] or a polygon (v, 2) [m] in ``base_link``.
"""

import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world import footprint_collides, grow, swept_collision, World
from robotica_kin.world.queries import Footprint

__all__ = ['check_clearance', 'check_path_points', 'path_headings', 'polyline_collision',
           'pose_collision']


def check_path_points(points: ArrayLike, name: str = 'points') -> NDArray[np.float64]:
    """
    Return a path's points as a float64 (N, 2) array, N >= 2, finite, or raise ValueError.

    >>> check_path_points([[0, 0], [1, 0]]).shape
    (2, 2)
    """
    p = np.array(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2:
        raise ValueError(f'{name} must have shape (N, 2) with N >= 2, got shape {p.shape}')
    if not np.isfinite(p).all():
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    return p


def check_clearance(clearance: float) -> float:
    """Return ``clearance`` [m] as a float >= 0, or raise ValueError."""
    if isinstance(clearance, bool) or not isinstance(clearance, (int, float)) or not (
            math.isfinite(clearance) and clearance >= 0.0):
        raise ValueError(f'clearance must be finite and >= 0 m, got {clearance!r}')
    return float(clearance)


def path_headings(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the tangent headings θ [rad] (N,) of a sampled path (N, 2) [m].

    The first and last points take the heading of their segment, the others that of the
    chord from the previous point to the next (the central difference of the tangent).

    >>> path_headings(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])).round(4).tolist()
    [0.0, 0.7854, 1.5708]
    """
    chord = np.empty_like(points)
    chord[0] = points[1] - points[0]
    chord[-1] = points[-1] - points[-2]
    chord[1:-1] = points[2:] - points[:-2]
    return np.asarray(np.arctan2(chord[:, 1], chord[:, 0]))


def polyline_collision(world: World, footprint: Footprint, points: ArrayLike,
                       clearance: float = 0.0) -> Optional[tuple[int, float]]:
    """
    Return (segment, fraction) of the first contact along a polyline, or None if it is free.

    The footprint drives each segment i (point i to point i + 1) [m, map frame] straight with
    the segment's heading, in the world grown by ``clearance`` [m]; a segment of zero length
    is skipped (its pose is an end of its neighbours), a path of one repeated point is the
    footprint at heading 0 there.

    >>> wall = World(walls=[[2, -1, 2, 1]])
    >>> polyline_collision(wall, 0.5, [[0, 0], [1, 0], [3, 0]])
    (1, 0.25)
    >>> polyline_collision(wall, 0.5, [[0, 0], [1, 0], [1, 3]]) is None
    True
    >>> polyline_collision(wall, 0.5, [[0, 0], [1, 0], [1, 3]], clearance=0.6)[0]  # 0.9 m in
    0
    """
    p = check_path_points(points)
    margin = check_clearance(clearance)
    grown = grow(world, margin) if margin > 0.0 else world
    steps = np.diff(p, axis=0)
    moving = np.flatnonzero(np.hypot(steps[:, 0], steps[:, 1]) > 0.0)
    if len(moving) == 0:
        return (0, 0.0) if footprint_collides(grown, footprint, [*p[0], 0.0]) else None
    for i in moving.tolist():
        heading = math.atan2(steps[i, 1], steps[i, 0])
        hit = swept_collision(grown, footprint, [*p[i], heading], [*p[i + 1], heading])
        if hit is not None:
            return i, hit
    return None


def pose_collision(world: World, footprint: Footprint, poses: ArrayLike,
                   clearance: float = 0.0) -> Optional[tuple[int, float]]:
    """
    Return (step, fraction) of the first contact along a pose sequence, or None if it is free.

    Step i moves the footprint from pose i to pose i + 1 (x [m], y [m], θ [rad], map frame),
    x, y and θ linearly, θ the short way, in the world grown by ``clearance`` [m]. One pose:
    (0, 0.0) if the footprint there touches an obstacle.

    >>> wall = World(walls=[[2, -1, 2, 1]])
    >>> pose_collision(wall, 0.5, [[0, 0, 0], [1, 0, 0], [3, 0, 0]])
    (1, 0.25)
    """
    q = np.asarray(poses, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != 3 or len(q) < 1 or not np.isfinite(q).all():
        raise ValueError(f'poses must be finite with shape (N, 3), N >= 1, got {q.shape}')
    margin = check_clearance(clearance)
    grown = grow(world, margin) if margin > 0.0 else world
    if len(q) == 1:
        return (0, 0.0) if footprint_collides(grown, footprint, q[0]) else None
    for i in range(len(q) - 1):
        hit = swept_collision(grown, footprint, q[i], q[i + 1])
        if hit is not None:
            return i, hit
    return None
