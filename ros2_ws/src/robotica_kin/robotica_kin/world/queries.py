"""
Queries on the world model: point in obstacle, clearance, obstacle growing, footprint contact.

* :func:`distance_to_obstacles` is exact to segments, polygons and circles, and to the squares
  of the occupied cells of a grid (a k-d tree of their centres proposes the candidates, the
  distance to each candidate square is exact); 0 inside an obstacle.
* :func:`grow` is the book's obstacle growing (§12.4.4): a circular robot of radius r is a
  point among obstacles grown by r. For walls, polygons and circles the growth is exact and
  implicit: the World's ``inflation`` rises by r and every query honours it (a wall becomes
  its capsule, a polygon its Minkowski sum with the disc, a circle's radius grows by r). A
  grid is dilated instead: a cell becomes occupied when its square comes within r of an
  occupied one (conservative by up to one cell). So ``point_in_obstacle(grow(world, r), p)``
  answers "is p free for a robot of radius r".
* :func:`footprint_collides` and :func:`swept_collision` test a robot's footprint (a circle of
  radius r, or a polygon (v, 2) in ``base_link``) at a pose (x, y, θ) of the map frame, and
  along a step from one pose to the next (x, y and θ interpolated linearly, θ the short way).
  A circle's step is cast as a ray against the obstacles grown by r: exact, at any speed. A
  polygon's step (and a circle's among grid cells) uses conservative advancement (Mirtich):
  from fraction s the body moves at most |Δp| + ρ|Δθ| per unit of s (ρ its farthest vertex),
  so it advances by clearance / that bound, which can never pass an obstacle; contact is
  declared when the clearance falls to ``tolerance``. Nothing tunnels, however thin the wall
  or long the step.
"""

import functools
import math
from typing import Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.raycast import cast_rays
from robotica_kin.world.segment_geometry import (
    point_segment_distance, points_in_polygon, segment_segment_distance)
from robotica_kin.world.shapes import polygon_edges, validate_polygon, World

__all__ = ['Footprint', 'distance_to_obstacles', 'footprint_collides', 'footprint_distance',
           'grow', 'point_in_obstacle', 'swept_collision']

Footprint = Union[float, ArrayLike]
"""A robot's footprint: a radius [m] (a circle about base_link) or a polygon (v, 2) [m]."""

_HALF_DIAGONAL = math.sqrt(0.5)   # a cell's centre to its corner, in cells
_MAX_ADVANCES = 10000             # conservative-advancement steps before reporting contact


def _points(points: ArrayLike) -> NDArray[np.float64]:
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or not np.isfinite(p).all():
        raise ValueError(f'points must be finite with shape (k, 2), got shape {p.shape}')
    return p


def _square_distance(grid: OccupancyGrid, uv: NDArray[np.float64],
                     cells: NDArray[np.int64]) -> NDArray[np.float64]:
    """Return the distance [m] from points uv (k, 2) [cells] to cells (k, c, 2) squares."""
    gap = np.maximum(np.maximum(cells - uv[:, None, :], uv[:, None, :] - cells - 1.0), 0.0)
    return np.asarray(np.hypot(gap[..., 0], gap[..., 1]) * grid.resolution)


def _grid_distance(grid: OccupancyGrid, points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the exact distance [m] from each point to the nearest occupied cell's square."""
    cells = grid.occupied_cells
    if len(cells) == 0:
        return np.full(len(points), np.inf)
    tree = grid.occupied_tree
    nearest, _ = tree.query(points)
    # A square is never farther than its centre, nor nearer than its centre minus the half
    # diagonal: every square nearer than the nearest centre has its centre within this ball.
    balls = tree.query_ball_point(points, nearest + _HALF_DIAGONAL * grid.resolution * 1.0001)
    uv = grid.world_to_grid(points)
    result = np.empty(len(points))
    for i, candidates in enumerate(balls):
        result[i] = _square_distance(grid, uv[i:i + 1], cells[None, candidates]).min()
    return result


def _geometric_distance(world: World, points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the distance [m] to walls, polygons and circles, ignoring inflation; 0 inside."""
    d = np.full(len(points), np.inf)
    if len(world.segments):
        d = point_segment_distance(points, world.segments).min(axis=1)
    if len(world.circles):
        to_centre = np.hypot(points[:, None, 0] - world.circles[:, 0],
                             points[:, None, 1] - world.circles[:, 1])
        d = np.minimum(d, np.maximum(to_centre - world.circles[:, 2], 0.0).min(axis=1))
    for polygon in world.polygons:
        d[points_in_polygon(points, polygon)] = 0.0
    return d


def distance_to_obstacles(world: World, points: ArrayLike) -> NDArray[np.float64]:
    """
    Return the distance [m] from each point (k, 2) [m, map frame] to the nearest obstacle.

    0 inside an obstacle or within its growth, inf in an empty world. Exact for walls,
    polygons and circles (less the world's inflation) and for the squares of a grid's
    occupied cells (book §12.4).

    >>> world = World(walls=[[0, 0, 2, 0]], circles=[[5, 0, 1]])
    >>> distance_to_obstacles(world, [[1, 1], [5, 3], [5, 0]]).tolist()
    [1.0, 2.0, 0.0]
    >>> distance_to_obstacles(grow(world, 0.25), [[1, 1]]).tolist()
    [0.75]
    """
    p = _points(points)
    d = np.maximum(_geometric_distance(world, p) - world.inflation, 0.0)
    if world.grid is not None:
        d = np.minimum(d, _grid_distance(world.grid, p))
    return d


def point_in_obstacle(world: World, points: ArrayLike) -> NDArray[np.bool_]:
    """
    Return whether each point (k, 2) [m, map frame] lies in an obstacle (boundary included).

    Inside a polygon or circle, on a wall, in an occupied cell, or within the world's growth
    of any of them. With ``grow(world, r)``: is the point taken for a robot of radius r.

    >>> world = World(circles=[[0, 0, 1]])
    >>> point_in_obstacle(world, [[0.5, 0], [1.2, 0]]).tolist()
    [True, False]
    >>> point_in_obstacle(grow(world, 0.3), [[1.2, 0]]).tolist()
    [True]
    """
    return np.asarray(distance_to_obstacles(world, points) <= 0.0)


def _dilate(grid: OccupancyGrid, radius: float) -> OccupancyGrid:
    from scipy.ndimage import binary_dilation
    reach = int(math.ceil(radius / grid.resolution)) + 1
    offsets = np.arange(-reach, reach + 1)
    gap = np.maximum(np.abs(offsets) - 1, 0) * grid.resolution
    structure = np.hypot(gap[:, None], gap[None, :]) <= radius
    grown = binary_dilation(grid.occupied, structure=structure)
    data = np.where(grown & ~grid.occupied, np.int8(100), grid.data).astype(np.int8)
    return OccupancyGrid(data, grid.resolution, grid.origin, grid.occupied_thresh,
                         grid.free_thresh)


def grow(world: World, radius: float) -> World:
    """
    Return the world with its obstacles grown by ``radius`` [m] (book §12.4.4).

    Walls, polygons and circles: exact, through ``inflation`` (see the module's docstring);
    a grid: dilated by cells (conservative). Growing by r1 then r2 is growing by r1 + r2
    for the geometry.

    >>> grow(World(walls=[[0, 0, 1, 0]]), 0.5).inflation
    0.5
    """
    if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius >= 0.0):
        raise ValueError(f'radius must be >= 0 m, got {radius!r}')
    grid = world.grid
    if grid is not None and radius > 0.0:
        grid = _dilate(grid, radius)
    return World(walls=world.walls, circles=world.circles, polygons=world.polygons, grid=grid,
                 inflation=world.inflation + radius)


def _parse_footprint(footprint: Footprint) -> tuple[float, Optional[NDArray[np.float64]]]:
    """Return (radius, None) for a circle, (farthest vertex ρ, polygon) for a polygon."""
    if isinstance(footprint, (int, float)) and not isinstance(footprint, bool):
        if not (math.isfinite(footprint) and footprint > 0.0):
            raise ValueError(f'footprint radius must be > 0 m, got {footprint!r}')
        return float(footprint), None
    try:
        vertices = np.asarray(footprint, dtype=np.float64)
    except (TypeError, ValueError):   # not a table of numbers: validate_polygon names it
        validate_polygon(footprint, 'footprint')
        raise
    return _parse_polygon(vertices.tobytes(), vertices.shape)


@functools.lru_cache(maxsize=64)
def _parse_polygon(data: bytes, shape: tuple[int, ...]
                   ) -> tuple[float, Optional[NDArray[np.float64]]]:
    """Validate a footprint polygon once (read-only): a plan checks one at every pose."""
    polygon = validate_polygon(np.frombuffer(data, dtype=np.float64).reshape(shape), 'footprint')
    return float(np.hypot(polygon[:, 0], polygon[:, 1]).max()), polygon


def _pose(pose: ArrayLike, name: str) -> NDArray[np.float64]:
    p = np.asarray(pose, dtype=np.float64)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f'{name} must be a finite (x, y, theta), got {pose!r}')
    return p


def _place(polygon: NDArray[np.float64], pose: NDArray[np.float64]) -> NDArray[np.float64]:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.asarray(polygon @ np.array([[c, s], [-s, c]]) + pose[:2])


def _grid_polygon_distance(grid: OccupancyGrid, placed: NDArray[np.float64],
                           reach: float) -> float:
    """Return a lower bound [m] of the distance between a polygon and the occupied squares."""
    cells = grid.occupied_cells
    if len(cells) == 0:
        return math.inf
    centre = placed.mean(axis=0)
    radius = float(np.hypot(*(placed - centre).T).max())
    margin = (_HALF_DIAGONAL + 1.0) * grid.resolution
    nearest, _ = grid.occupied_tree.query(centre)
    if nearest > radius + margin:
        return float(nearest - radius - _HALF_DIAGONAL * grid.resolution)
    near = cells[grid.occupied_tree.query_ball_point(centre, radius + margin)]
    if len(near) == 0:
        return grid.resolution
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float64)
    squares = grid.resolution * (near[:, None, :] + corners)          # (c, 4, 2) grid frame
    x0, y0, yaw = grid.origin
    c, s = math.cos(yaw), math.sin(yaw)
    squares = squares @ np.array([[c, s], [-s, c]]) + [x0, y0]         # map frame
    square_edges = np.concatenate([squares, np.roll(squares, -1, axis=1)], axis=2)
    d = segment_segment_distance(square_edges.reshape(-1, 4), polygon_edges(placed))
    d = d.min(axis=1).reshape(-1, 4).min(axis=1)
    inside = points_in_polygon(squares.mean(axis=1), placed)
    uv = grid.world_to_grid(placed)
    holds = ((uv[None, :, :] >= near[:, None, :]) & (uv[None, :, :] <= near[:, None, :] + 1))
    inside |= holds.all(axis=2).any(axis=1)
    return float(min(np.where(inside, 0.0, d).min(), grid.resolution))


def footprint_distance(world: World, footprint: Footprint, pose: ArrayLike) -> float:
    """
    Return the clearance [m] of a footprint at ``pose`` (x, y, θ) [m, rad, map frame].

    0 at contact or overlap. Exact for walls, polygons and circles; for a grid, exact for a
    circle footprint and a lower bound (exact within one cell) for a polygon.

    >>> footprint_distance(World(walls=[[2, -1, 2, 1]]), 0.5, [0, 0, 0])
    1.5
    >>> footprint_distance(World(walls=[[2, -1, 2, 1]]), [[-1, -1], [1, -1], [1, 1], [-1, 1]],
    ...                    [0, 0, math.pi / 4]).__round__(6)
    0.585786
    """
    reach, polygon = _parse_footprint(footprint)
    p = _pose(pose, 'pose')
    if polygon is None:
        return float(max(distance_to_obstacles(world, p[None, :2])[0] - reach, 0.0))
    placed = _place(polygon, p)
    edges = polygon_edges(placed)
    d = math.inf
    if len(world.segments):
        d = float(segment_segment_distance(edges, world.segments).min()) - world.inflation
        if points_in_polygon(world.segments[:, 0:2], placed).any():
            d = 0.0
    for obstacle in world.polygons:
        if points_in_polygon(placed, obstacle).any():
            d = 0.0
    if len(world.circles):
        gap = point_segment_distance(world.circles[:, 0:2], edges).min(axis=1)
        gap = gap - world.circles[:, 2] - world.inflation
        gap[points_in_polygon(world.circles[:, 0:2], placed)] = 0.0
        d = min(d, float(gap.min()))
    if world.grid is not None:
        d = min(d, _grid_polygon_distance(world.grid, placed, reach))
    return max(d, 0.0)


def footprint_collides(world: World, footprint: Footprint, pose: ArrayLike) -> bool:
    """
    Return whether the footprint at ``pose`` (x, y, θ) touches or overlaps an obstacle.

    ``footprint``: a radius [m] or a polygon (v, 2) [m] in base_link.

    >>> footprint_collides(World(walls=[[2, -1, 2, 1]]), 0.5, [1.6, 0, 0])
    True
    """
    return footprint_distance(world, footprint, pose) <= 0.0


def swept_collision(world: World, footprint: Footprint, pose_from: ArrayLike,
                    pose_to: ArrayLike, tolerance: float = 1e-4) -> Optional[float]:
    """
    Return the fraction in [0, 1] of the step at first contact, or None if the step is free.

    The footprint (a radius [m] or a polygon (v, 2) [m] in base_link) moves from ``pose_from``
    to ``pose_to`` (x, y, θ) [m, rad, map frame], x, y and θ linearly (θ the short way). 0.0
    if it already touches at the start. A circle among walls, polygons and circles: the exact
    fraction (a ray cast against the obstacles grown by its radius); otherwise conservative
    advancement stops within ``tolerance`` [m] of contact, never past it.

    >>> thin = World(walls=[[5, -1, 5, 1], [5.01, -1, 5.01, 1]])
    >>> swept_collision(thin, 0.5, [0, 0, 0], [10, 0, 0])
    0.45
    """
    reach, polygon = _parse_footprint(footprint)
    start, end = _pose(pose_from, 'pose_from'), _pose(pose_to, 'pose_to')
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise ValueError(f'tolerance must be > 0 m, got {tolerance!r}')
    if footprint_distance(world, footprint, start) <= 0.0:
        return 0.0
    delta = end - start
    delta[2] = wrap_to_pi(float(delta[2]))
    length = math.hypot(delta[0], delta[1])
    bound = length + (reach * abs(delta[2]) if polygon is not None else 0.0)
    if bound == 0.0:
        return None
    if polygon is None:
        hits = cast_rays(World(walls=world.walls, circles=world.circles,
                               polygons=world.polygons, inflation=world.inflation)
                         if world.grid is not None else world,
                         start[:2], [math.atan2(delta[1], delta[0])], length, grown_by=reach)
        fraction = float(hits.ranges[0] / length) if hits.hit[0] else None
        if world.grid is None:
            return fraction
        grid_only = World(grid=world.grid)
        return _advance(grid_only, footprint, start, delta, bound, tolerance,
                        1.0 if fraction is None else fraction, fraction)
    return _advance(world, footprint, start, delta, bound, tolerance, 1.0, None)


def _advance(world: World, footprint: Footprint, start: NDArray[np.float64],
             delta: NDArray[np.float64], bound: float, tolerance: float, horizon: float,
             otherwise: Optional[float]) -> Optional[float]:
    """Return the conservative-advancement contact fraction before ``horizon``, or otherwise."""
    s = 0.0
    for _ in range(_MAX_ADVANCES):
        clearance = footprint_distance(world, footprint, start + s * delta)
        if clearance <= tolerance:
            return s
        s += (clearance - 0.5 * tolerance) / bound
        if s >= horizon:
            return otherwise
    return s
