"""
From range readings to what the reactive behaviours need: obstacle points, walls, clearance.

Book §9.6 (seed catalogue Part 7.9): a reactive controller either couples the readings directly
to the commands (the obstacle points of VFF and of the generalised potential) or has a
perception stage that extracts the geometry its manoeuvre follows (the wall beside the robot,
the corridor's walls). Everything is in ``base_link`` (REP-103: x forward, y left, angles
counter-clockwise from x), in metres and radians.

Readings follow REP-117 (``sensor_msgs/LaserScan``, ``sensor_msgs/Range``): a range in
[range_min, range_max] is a return; ``+inf`` (or beyond range_max) is no return, free space up
to the maximum; ``-inf`` (or below range_min) an object too close to measure, taken as a point
at range_min (the conservative reading); NaN an erroneous reading, unknown: dropped and counted.
"""
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['RangePoints', 'WallEstimate', 'clearance_ahead', 'nearest_distance', 'range_points',
           'side_wall']

MIN_WALL_POINTS = 3   # points a wall line is fitted to, at least


@dataclass(frozen=True)
class RangePoints:
    """Obstacle points (N, 2) [m] in ``base_link`` and the readings that were NaN (unknown)."""

    points: NDArray[np.float64]
    readings: int           # readings given
    unknown: int            # of them NaN: erroneous, dropped

    @property
    def unknown_fraction(self) -> float:
        """Return the fraction of the readings that were unknown (0 for no reading)."""
        return self.unknown / self.readings if self.readings else 0.0


def range_points(ranges: ArrayLike, angles: ArrayLike, range_min: float, range_max: float,
                 sensor_pose: ArrayLike = (0.0, 0.0, 0.0)) -> RangePoints:
    """
    Return the obstacle points of range readings taken from ``sensor_pose`` in ``base_link``.

    Parameters
    ----------
    ranges : array_like, shape (k,)
        Ranges [m] along each beam (REP-117 conventions, see the module).
    angles : array_like, shape (k,)
        Each beam's direction [rad] in the sensor's frame.
    range_min, range_max : float
        The sensor's limits [m], 0 <= range_min < range_max.
    sensor_pose : array_like, shape (3,) or (k, 3)
        The sensor's (x [m], y [m], yaw [rad]) in ``base_link``; one per beam for a ring of
        sonars.

    Raises
    ------
    ValueError
        For shapes that disagree, non-finite angles or poses, or limits out of order.

    Examples
    --------
    >>> rp = range_points([1.0, math.inf, math.nan, -math.inf], [0.0, 0.5, 1.0, math.pi / 2],
    ...                   0.1, 5.0)
    >>> rp.points.round(6).tolist(), rp.unknown
    ([[1.0, 0.0], [0.0, 0.1]], 1)

    """
    r = np.asarray(ranges, dtype=np.float64).ravel()
    a = np.asarray(angles, dtype=np.float64).ravel()
    pose = np.asarray(sensor_pose, dtype=np.float64)
    if a.shape != r.shape or not np.all(np.isfinite(a)):
        raise ValueError(f'angles must be {r.size} finite values, got shape {a.shape}')
    if pose.shape not in ((3,), (r.size, 3)) or not np.all(np.isfinite(pose)):
        raise ValueError(f'sensor_pose must be finite, shape (3,) or ({r.size}, 3), '
                         f'got {pose.shape}')
    if not (math.isfinite(range_min) and math.isfinite(range_max)
            and 0.0 <= range_min < range_max):
        raise ValueError(f'need 0 <= range_min < range_max, got {range_min!r}, {range_max!r}')
    unknown = np.isnan(r)
    close = ~unknown & (r < range_min)
    hit = ~unknown & (close | (r <= range_max))
    d = np.where(close, range_min, r)[hit]
    pose = np.broadcast_to(pose, (r.size, 3))[hit]
    direction = pose[:, 2] + a[hit]
    points = np.column_stack((pose[:, 0] + d * np.cos(direction),
                              pose[:, 1] + d * np.sin(direction)))
    return RangePoints(points, int(r.size), int(np.count_nonzero(unknown)))


def nearest_distance(points: NDArray[np.float64]) -> float:
    """
    Return the distance [m] from the ``base_link`` origin to the nearest point; inf if none.

    >>> nearest_distance(np.array([[3.0, 4.0], [0.0, -2.0]]))
    2.0
    """
    return float(np.min(np.hypot(points[:, 0], points[:, 1]))) if len(points) else math.inf


def clearance_ahead(points: NDArray[np.float64], half_width: float) -> float:
    """
    Return the distance [m] to the nearest point ahead in the robot's lane; inf if none.

    The lane is x > 0, |y| <= ``half_width`` [m] (the robot's half width plus a margin).

    >>> clearance_ahead(np.array([[2.0, 0.1], [1.0, 0.9], [-1.0, 0.0]]), 0.3)
    2.0
    """
    ahead = points[(points[:, 0] > 0.0) & (np.abs(points[:, 1]) <= half_width)]
    return float(np.min(ahead[:, 0])) if len(ahead) else math.inf


@dataclass(frozen=True)
class WallEstimate:
    """A straight wall beside the robot: its perpendicular distance and direction."""

    distance: float         # d [m] from the base_link origin to the wall line, > 0
    angle: float            # direction of the wall line [rad], in (-π/2, π/2]: + runs left
    points: int             # points it was fitted to


def side_wall(points: NDArray[np.float64], side: str, max_distance: float,
              reach: float) -> Optional[WallEstimate]:
    """
    Return the wall on ``side`` fitted to the points beside the robot, or None.

    The points on that side (y > 0 left, y < 0 right) within ``max_distance`` [m] sideways and
    ``reach`` [m] ahead and behind (|x| <= reach) are fitted with a line by total least squares
    (the principal direction of their scatter), as the perception stage of §9.6 derives the
    path that wall following tracks. None with fewer than :data:`MIN_WALL_POINTS` points or a
    line through the robot.

    >>> wall = side_wall(np.array([[x, 1.0 + 0.1 * x] for x in (-1.0, 0.0, 1.0)]), 'left',
    ...                  2.0, 2.0)
    >>> round(wall.distance, 6), round(wall.angle, 6)   # y = 1 + 0.1 x
    (0.995037, 0.099669)
    """
    if side not in ('left', 'right'):
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    y = points[:, 1] if side == 'left' else -points[:, 1]
    chosen = points[(y > 0.0) & (y <= max_distance) & (np.abs(points[:, 0]) <= reach)]
    if len(chosen) < MIN_WALL_POINTS:
        return None
    centre = chosen.mean(axis=0)
    _, _, vt = np.linalg.svd(chosen - centre, full_matrices=False)
    direction = vt[0] if vt[0][0] >= 0.0 else -vt[0]    # the one pointing forward
    normal = np.array([-direction[1], direction[0]])
    distance = abs(float(centre @ normal))
    if distance <= 0.0:
        return None
    return WallEstimate(distance, math.atan2(float(direction[1]), float(direction[0])),
                        len(chosen))
