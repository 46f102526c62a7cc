"""
Configuration space (book §12.4.5, §12.6.3): C-obstacles of polygons, φ-slices, a 2R arm's grid.

**Translating convex robot** (Lozano-Pérez and Wesley 1979; Schilling 1990; figs. 12.5-12.7).
A convex robot A, given by its vertices in its own frame whose origin is the reference point
r, collides with a convex obstacle B exactly when r lies in the C-obstacle

    B_A = B ⊕ (-A) = {b - a : b in B, a in A},

the Minkowski sum of B and A reflected through r (:func:`cspace_obstacle`). With n_A, n_B and
n_BA vertices, n_B <= n_BA <= n_A + n_B; B_A is convex; r in A implies B ⊆ B_A (the book's
three properties). The sum is built by the classic merge of the two polygons' edges by
direction (linear time); edges of equal direction are joined, so collinear vertices never
count. A non-convex robot is a union of convex parts sharing r: its C-obstacle is the union of
the parts' (:func:`cspace_obstacles`). A wall (a segment) is a degenerate convex obstacle.

**Rotating robot, φ-slices** (figs. 12.10, 12.13-12.15). For orientations φ in [φ0, φ1] the
robot sweeps a region; each vertex v runs along an arc of radius |v|, which lies inside the
triangle of the arc's ends and the crossing of its end tangents (at radius |v| / cos(Δφ / 2)
on the bisector, Δφ = φ1 - φ0 < π). So the convex hull of those points encloses every turned
copy of A: the circumscribed polygon of fig. 12.10 (:func:`swept_polygon`), conservative and
exact for Δφ = 0. The slice's C-obstacles are B ⊕ (-swept) (:func:`phi_slice`). A slice's
free space is drawn on a grid by :func:`cspace_grid`: a cell is occupied when its closed
square meets a C-obstacle (exact separating-axis test), so 4-connected free cells are joined
by free straight segments (a path found on the grid is a real one).

**Planar 2R arm, joint-space grid** (the n-torus of §12.4.5, Lumelsky and Sun 1987).
:func:`arm_2r_cspace` marks each cell (θ1, θ2) of a grid over [-π, π)² in collision when
either link, at the cell's centre, meets a polygon: an exact segment-polygon test (the link
crosses an edge or lies inside). Links: base -> elbow = base + l1 (cos θ1, sin θ1), elbow ->
tip = elbow + l2 (cos(θ1 + θ2), sin(θ1 + θ2)) (θ2 relative to link 1, radians, REP-103).
With ``conservative`` the test asks for a clearance of the most any point of the link can move
within the cell (l1 Δθ1 / 2 for link 1, (l1 + l2) Δθ1 / 2 + l2 Δθ2 / 2 for link 2), so that a
free cell is free for every configuration in it.

A circular robot needs none of this: grow the obstacles by its radius
(:func:`~robotica_kin.world.queries.grow`, §12.4.4).
"""

from dataclasses import dataclass
import math
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.segment_geometry import (
    points_in_polygon, segment_segment_distance, segments_intersect)
from robotica_kin.world.shapes import polygon_edges, validate_polygon

__all__ = ['ArmCSpace', 'MAX_GRID_CELLS', 'arm_2r_cspace', 'convex_polygon', 'cspace_grid',
           'cspace_obstacle', 'cspace_obstacles', 'minkowski_sum', 'phi_slice',
           'swept_polygon']

MAX_GRID_CELLS = 4_000_000   # cells of a C-space grid (as the world's drawn grids)
_COLLINEAR = 1e-12           # relative cross product below which three vertices are in line


def _cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def _drop_collinear(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return a CCW polygon without the vertices whose two edges run in one direction."""
    while len(v) > 2:
        e_in = v - np.roll(v, 1, axis=0)
        e_out = np.roll(v, -1, axis=0) - v
        scale = np.hypot(*e_in.T) * np.hypot(*e_out.T)
        straight = np.abs(_cross(e_in, e_out)) <= _COLLINEAR * scale
        straight &= (e_in * e_out).sum(axis=1) > 0.0
        if not straight.any():
            break
        v = v[~straight]
    return v


def convex_polygon(vertices: ArrayLike, where: str = 'polygon',
                   allow_segment: bool = False) -> NDArray[np.float64]:
    """
    Return a convex polygon's vertices (v, 2) [m] CCW from the lowest, collinear ones dropped.

    ``allow_segment`` accepts two distinct points (a wall) as a degenerate convex set.
    ValueError names ``where`` for a polygon that is not simple, not convex, or degenerate.

    >>> convex_polygon([[0, 0], [0, 1], [1, 1], [1, 0.5], [1, 0]]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    """
    v = np.asarray(vertices, dtype=np.float64)
    if allow_segment and v.shape == (2, 2):
        if not np.isfinite(v).all() or np.array_equal(v[0], v[1]):
            raise ValueError(f'{where}: a segment needs two distinct finite points')
        return v.copy()
    v = np.array(validate_polygon(v, where))
    area2 = float(_cross(v, np.roll(v, -1, axis=0)).sum())
    if area2 < 0.0:
        v = v[::-1]
    e_in = v - np.roll(v, 1, axis=0)
    e_out = np.roll(v, -1, axis=0) - v
    scale = np.hypot(*e_in.T) * np.hypot(*e_out.T)
    if (_cross(e_in, e_out) < -_COLLINEAR * scale).any():
        raise ValueError(f'{where}: the polygon is not convex')
    v = _drop_collinear(v)
    if len(v) < 3:
        raise ValueError(f'{where}: a polygon of zero area')
    return _from_lowest(v)


def _from_lowest(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the CCW vertices rolled to start at the lowest (then leftmost) one."""
    k = int(np.lexsort((v[:, 0], v[:, 1]))[0])
    return np.roll(v, -k, axis=0)


def minkowski_sum(p: ArrayLike, q: ArrayLike) -> NDArray[np.float64]:
    """
    Return P ⊕ Q of two convex polygons (or segments) (v, 2) [m], counter-clockwise.

    The edges of both, each started at its lowest vertex, are merged by direction (their
    angles rise from 0 to 2π round a convex polygon) and chained from the sum of the two
    lowest vertices; parallel edges join into one. O(n_P + n_Q).

    >>> minkowski_sum([[0, 0], [2, 0], [2, 1], [0, 1]], [[0, 0], [1, 0], [0, 1]]).tolist()
    [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [2.0, 2.0], [0.0, 2.0]]
    """
    a = _from_lowest(convex_polygon(p, 'p', allow_segment=True))
    b = _from_lowest(convex_polygon(q, 'q', allow_segment=True))
    edges = np.vstack([np.roll(a, -1, axis=0) - a, np.roll(b, -1, axis=0) - b])
    angle = np.mod(np.arctan2(edges[:, 1], edges[:, 0]), 2.0 * math.pi)
    # An edge of angle ~2π is the last one of its polygon; keep it last, not first.
    angle = np.where(angle >= 2.0 * math.pi - 1e-15, 2.0 * math.pi, angle)
    ordered = edges[np.argsort(angle, kind='stable')]
    vertices = a[0] + b[0] + np.vstack([[0.0, 0.0], np.cumsum(ordered[:-1], axis=0)])
    return _drop_collinear(vertices)


def _turn(v: NDArray[np.float64], theta: float) -> NDArray[np.float64]:
    c, s = math.cos(theta), math.sin(theta)
    return np.asarray(v @ np.array([[c, s], [-s, c]]))


def cspace_obstacle(obstacle: ArrayLike, robot: ArrayLike,
                    theta: float = 0.0) -> NDArray[np.float64]:
    """
    Return the C-obstacle B ⊕ (-A) (v, 2) [m] of a convex obstacle for a translating robot.

    ``robot`` (v, 2) [m]: a convex polygon in its own frame, whose origin is the reference
    point r; it is turned by ``theta`` [rad] first. ``obstacle``: a convex polygon or a wall
    (2, 2) in the map frame. The robot at reference position t collides iff t is in the result.

    A square obstacle and a triangular robot give a C-obstacle of five vertices, as in fig.
    12.6 (4 <= 5 <= 3 + 4):

    >>> cspace_obstacle([[2, 0], [3, 0], [3, 1], [2, 1]], [[0, 0], [1, 0], [0, 1]]).tolist()
    [[2.0, -1.0], [3.0, -1.0], [3.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
    """
    a = convex_polygon(robot, 'robot')
    return minkowski_sum(obstacle, -_turn(a, float(theta)))


def cspace_obstacles(obstacles: Sequence[ArrayLike], robot_parts: Sequence[ArrayLike],
                     theta: float = 0.0) -> list[NDArray[np.float64]]:
    """
    Return the C-obstacles of every (obstacle, robot part) pair: their union is the C-obstacle.

    A non-convex robot is given as convex parts in one frame (sharing the reference point, fig.
    12.8-12.9); each part and each convex obstacle or wall gives one convex C-obstacle.
    """
    return [cspace_obstacle(b, part, theta) for b in obstacles for part in robot_parts]


def swept_polygon(robot: ArrayLike, phi_low: float, phi_high: float) -> NDArray[np.float64]:
    """
    Return a convex polygon (v, 2) [m] enclosing the robot turned by every φ in [φ0, φ1].

    The circumscribed polygon of fig. 12.10 (module docstring): the hull of each vertex turned
    to φ0 and φ1 and of the crossing of its arc's end tangents. 0 <= φ1 - φ0 < π [rad].

    >>> swept_polygon([[1, -0.1], [1, 0.1], [-1, 0.1], [-1, -0.1]], 0.0, 0.0).shape
    (4, 2)
    """
    from scipy.spatial import ConvexHull
    a = convex_polygon(robot, 'robot')
    span = float(phi_high) - float(phi_low)
    if not (math.isfinite(span) and 0.0 <= span < math.pi):
        raise ValueError(f'the slice must satisfy 0 <= phi_high - phi_low < pi rad, got {span!r}')
    if span == 0.0:
        return _turn(a, float(phi_low))
    points = [_turn(a, float(phi_low)), _turn(a, float(phi_high)),
              _turn(a, float(phi_low) + 0.5 * span) / math.cos(0.5 * span)]
    cloud = np.vstack(points)
    hull = cloud[ConvexHull(cloud).vertices]
    return convex_polygon(hull, 'swept robot')


def phi_slice(obstacles: Sequence[ArrayLike], robot: ArrayLike, phi_low: float,
              phi_high: float) -> list[NDArray[np.float64]]:
    """
    Return the convex C-obstacles of the slice φ in [φ0, φ1] [rad] of a rotating robot.

    Each is B ⊕ (-swept) with the swept polygon of :func:`swept_polygon`: a reference position
    free of all of them is free for every orientation of the slice (conservative).
    """
    swept = swept_polygon(robot, phi_low, phi_high)
    return [minkowski_sum(b, -swept) for b in obstacles]


def cspace_grid(cobstacles: Sequence[ArrayLike], bounds: ArrayLike,
                resolution: float) -> OccupancyGrid:
    """
    Return an OccupancyGrid (100 occupied, 0 free) of the C-obstacles over ``bounds``.

    ``bounds`` = [xmin, ymin, xmax, ymax] [m] of the reference point, ``resolution``
    [m/cell]; a cell is occupied when its closed square meets a convex C-obstacle (separating
    axes: x, y and the polygon's edge normals). ValueError beyond :data:`MAX_GRID_CELLS`.

    >>> grid = cspace_grid([[[0.6, 0.6], [1.4, 0.6], [1.0, 1.4]]], [0, 0, 2, 2], 0.5)
    >>> (grid.data // 100).tolist()
    [[0, 0, 0, 0], [0, 1, 1, 0], [0, 1, 1, 0], [0, 0, 0, 0]]
    """
    b = np.asarray(bounds, dtype=np.float64)
    if b.shape != (4,) or not np.isfinite(b).all() or not (b[2:] > b[:2]).all():
        raise ValueError(f'bounds must be finite [xmin, ymin, xmax, ymax], got {bounds!r}')
    if not (math.isfinite(resolution) and resolution > 0.0):
        raise ValueError(f'resolution must be > 0 m/cell, got {resolution!r}')
    cols, rows = (int(math.ceil(v - 1e-9)) for v in (b[2:] - b[:2]) / resolution)
    if rows * cols > MAX_GRID_CELLS:
        raise ValueError(f'a grid of {rows} x {cols} cells is more than {MAX_GRID_CELLS}')
    occupied = np.zeros((rows, cols), dtype=bool)
    for k, polygon in enumerate(cobstacles):
        v = convex_polygon(polygon, f'cobstacles[{k}]', allow_segment=True)
        low = np.ceil((v.min(axis=0) - b[:2]) / resolution).astype(int) - 1   # touching too
        high = np.floor((v.max(axis=0) - b[:2]) / resolution).astype(int)
        c0, r0 = np.maximum(low, 0)
        c1, r1 = np.minimum(high, [cols - 1, rows - 1])
        if c1 < c0 or r1 < r0:
            continue
        j, i = np.meshgrid(np.arange(c0, c1 + 1), np.arange(r0, r1 + 1))
        x0 = b[0] + j * resolution
        y0 = b[1] + i * resolution
        meets = ((x0 <= v[:, 0].max()) & (x0 + resolution >= v[:, 0].min())
                 & (y0 <= v[:, 1].max()) & (y0 + resolution >= v[:, 1].min()))
        edges = np.roll(v, -1, axis=0) - v
        normals = np.column_stack([edges[:, 1], -edges[:, 0]])     # outward (CCW)
        projections = normals @ v.T
        for n, p_max, p_min in zip(normals, projections.max(axis=1), projections.min(axis=1)):
            near = n[0] * x0 + n[1] * y0 + resolution * (min(n[0], 0.0) + min(n[1], 0.0))
            far = n[0] * x0 + n[1] * y0 + resolution * (max(n[0], 0.0) + max(n[1], 0.0))
            meets &= (near <= p_max) & (far >= p_min)
        occupied[i, j] |= meets
    data = np.where(occupied, 100, 0).astype(np.int8)
    return OccupancyGrid(data, float(resolution), (float(b[0]), float(b[1]), 0.0))


@dataclass(frozen=True)
class ArmCSpace:
    """
    The joint-space grid of a planar 2R arm: ``collision`` (n1, n2) at angles (θ1_i, θ2_j).

    ``theta1`` (n1,) and ``theta2`` (n2,) [rad] are the cells' centres over [-π, π); the
    space is a torus (the first and last cells of each axis are neighbours).
    """

    theta1: NDArray[np.float64]
    theta2: NDArray[np.float64]
    collision: NDArray[np.bool_]


def _links_hit(links: NDArray[np.float64], polygons: Sequence[NDArray[np.float64]],
               clearance: float) -> NDArray[np.bool_]:
    """Return whether each segment (k, 4) comes within ``clearance`` of a polygon (or meets it)."""
    hit = np.zeros(len(links), dtype=bool)
    block = max(1, 2_000_000 // max(1, max((len(p) for p in polygons), default=1)))
    for start in range(0, len(links), block):
        seg = links[start:start + block]
        found = np.zeros(len(seg), dtype=bool)
        for polygon in polygons:
            edges = polygon_edges(polygon)
            if clearance > 0.0:
                found |= (segment_segment_distance(seg, edges) <= clearance).any(axis=1)
            else:
                found |= segments_intersect(seg, edges).any(axis=1)
            found |= points_in_polygon(seg[:, 0:2], polygon)
        hit[start:start + block] = found
    return hit


def arm_2r_cspace(link_lengths: ArrayLike, obstacles: Sequence[ArrayLike],
                  cells: tuple[int, int] = (180, 180), base: ArrayLike = (0.0, 0.0),
                  conservative: bool = False) -> ArmCSpace:
    """
    Return the joint-space grid C-space of a planar 2R arm among polygons (module docstring).

    Parameters
    ----------
    link_lengths : array_like
        (l1, l2) [m], > 0.
    obstacles : sequence of array_like
        Simple polygons (v, 2) [m] in the arm's base frame.
    cells : (int, int)
        Cells (n1, n2) over [-π, π) for θ1 and θ2.
    base : array_like
        The first joint's position (x, y) [m].
    conservative : bool
        Mark a cell when the links come within the cell's motion bound of an obstacle.

    Examples
    --------
    A post at x = 1.5 m: of the cells at 0 and ±120°, only the arm stretched along +x meets it:

    >>> post = [[1.4, -0.1], [1.6, -0.1], [1.6, 0.1], [1.4, 0.1]]
    >>> space = arm_2r_cspace([1.0, 1.0], [post], cells=(3, 3))
    >>> np.degrees(space.theta1).round(6).tolist(), space.collision.astype(int).tolist()
    ([-120.0, 0.0, 120.0], [[0, 0, 0], [0, 1, 0], [0, 0, 0]])

    """
    lengths = np.asarray(link_lengths, dtype=np.float64)
    if lengths.shape != (2,) or not (np.isfinite(lengths).all() and (lengths > 0).all()):
        raise ValueError(f'link_lengths must be two lengths > 0 m, got {link_lengths!r}')
    n1, n2 = (int(n) for n in cells)
    if n1 < 1 or n2 < 1 or n1 * n2 > MAX_GRID_CELLS:
        raise ValueError(f'cells must be >= 1 each and at most {MAX_GRID_CELLS} in all, '
                         f'got {cells!r}')
    origin = np.asarray(base, dtype=np.float64)
    if origin.shape != (2,) or not np.isfinite(origin).all():
        raise ValueError(f'base must be a finite (x, y), got {base!r}')
    polygons = [validate_polygon(p, f'obstacles[{k}]') for k, p in enumerate(obstacles)]
    l1, l2 = float(lengths[0]), float(lengths[1])
    step1, step2 = 2.0 * math.pi / n1, 2.0 * math.pi / n2
    theta1 = np.asarray(-math.pi + (np.arange(n1) + 0.5) * step1, dtype=np.float64)
    theta2 = np.asarray(-math.pi + (np.arange(n2) + 0.5) * step2, dtype=np.float64)
    elbow = origin + l1 * np.column_stack([np.cos(theta1), np.sin(theta1)])
    reach1 = 0.5 * l1 * step1 if conservative else 0.0
    reach2 = (0.5 * (l1 + l2) * step1 + 0.5 * l2 * step2) if conservative else 0.0
    link1 = _links_hit(np.hstack([np.broadcast_to(origin, elbow.shape), elbow]), polygons,
                       reach1)
    total = theta1[:, None] + theta2[None, :]
    tip = elbow[:, None, :] + l2 * np.stack([np.cos(total), np.sin(total)], axis=-1)
    link2 = _links_hit(np.concatenate([np.broadcast_to(elbow[:, None, :], tip.shape), tip],
                                      axis=-1).reshape(-1, 4), polygons, reach2)
    collision = link1[:, None] | link2.reshape(n1, n2)
    return ArmCSpace(theta1, theta2, collision)
