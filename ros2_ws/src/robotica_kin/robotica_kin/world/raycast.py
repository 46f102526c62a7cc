"""
Ray casting on the world model: what a laser, sonar or infrared beam meets first.

:func:`cast_rays` intersects k rays with every surface of a :class:`~robotica_kin.world.shapes.
World` at once (rays × surfaces broadcasting, no Python loop over rays or segments):

* **segments** (walls and polygon edges): exact, the parametric solution of
  o + t d = a + s (b - a), t >= 0, 0 <= s <= 1; a ray parallel to a segment never meets it
  (grazing along a wall is a measure-zero event);
* **circles**: exact, the smaller non-negative root of |o + t d - c|² = r²;
* **grid**: an exact vectorised cell traversal. The cells a ray enters are those behind each
  crossing of a vertical grid line (t = (line - u0) / du) or a horizontal one; every crossing's
  entered cell is looked up at once, and the first occupied one gives the range, which is
  therefore the distance to that cell's boundary (exact up to floating rounding; at an exact
  cell corner either neighbour may be taken). The crossings are taken in chunks of ray
  length, :data:`GRID_CHUNK` cells first and doubling, so that short rays stop early (the
  Amanatides–Woo traversal, done by chunks instead of one cell at a time). Rays start where
  they enter the grid's rectangle; unknown cells and the outside of the grid are free. A ray
  starting in an occupied cell has range 0.

Surfaces have no inside for a ray: one starting inside a polygon or circle meets its boundary
from within. A grown world (``inflation`` r) is cast against the capsules and the enlarged
circles of :meth:`World.surfaces`, exactly.

Angles are in the map frame [rad] (REP-103); the incidence angle (between the ray and the
surface normal, in [0, π/2]) is what a sonar's critical angle needs (book §7.4, Part 5.5 of
the seed catalogue: no echo beyond the critical angle).
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.shapes import World

__all__ = ['BLOCK_ELEMENTS', 'GRID_CHUNK', 'RayHits', 'cast_rays']

GRID_CHUNK = 32   # cells of ray length of the grid traversal's first step (doubles each step)
BLOCK_ELEMENTS = 16384   # rays x surfaces per block: the temporaries stay in the cache


@dataclass(frozen=True)
class RayHits:
    """
    What k rays met: ranges (k,) [m], points (k, 2) [m], normals (k, 2), incidence (k,) [rad].

    ``ranges`` is inf and ``points``, ``normals``, ``incidence`` are NaN where ``hit`` is
    False (nothing within max_range). Normals are unit vectors of the map frame facing the
    ray's origin; incidence is the angle between the ray and the normal, in [0, π/2].
    """

    ranges: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    incidence: NDArray[np.float64]
    hit: NDArray[np.bool_]


def _closest(t: NDArray[np.float64], t_best: NDArray[np.float64], rows: slice,
             ) -> tuple[NDArray[np.bool_], NDArray[np.int64], NDArray[np.float64]]:
    """Return which rays of the block found a nearer surface, its column and its t."""
    j = np.argmin(t, axis=1)
    t_min = t[np.arange(len(t)), j]
    better = t_min < t_best[rows]
    return better, j, t_min


def _cast_segments(segments: NDArray[np.float64], ox: NDArray[np.float64],
                   oy: NDArray[np.float64], dx: NDArray[np.float64], dy: NDArray[np.float64],
                   t_best: NDArray[np.float64], n_best: NDArray[np.float64]) -> None:
    n = len(segments)
    if n == 0:
        return
    ax, ay = segments[:, 0], segments[:, 1]
    ex, ey = segments[:, 2] - ax, segments[:, 3] - ay
    directions = np.column_stack([dx, dy])
    normal_t = np.vstack([ey, -ex])            # d × e = d · (ey, -ex)
    single = len(ox) == 1
    if single:
        wx, wy = ax - ox[0], ay - oy[0]
        w_normal = np.vstack([-wy, wx])          # w × d = d · (-wy, wx)
        t_num = wx * ey - wy * ex
    block = max(1, BLOCK_ELEMENTS // n)
    for start in range(0, len(dx), block):
        rows = slice(start, start + block)
        d = directions[rows]
        with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
            inv = d @ normal_t
            np.divide(1.0, inv, out=inv)       # 1 / (d × e): inf when parallel
            if single:
                s = d @ w_normal
                t = t_num * inv
            else:
                bx, by = ax - ox[rows, None], ay - oy[rows, None]
                s = bx * d[:, 1:2] - by * d[:, 0:1]
                t = (bx * ey - by * ex) * inv
            s *= inv
            bad = s < 0.0
            bad |= s > 1.0
            bad |= t < 0.0
            bad |= np.isnan(t)
        np.putmask(t, bad, np.inf)
        better, j, t_min = _closest(t, t_best, rows)
        if better.any():
            jb = j[better]
            nx, ny = -ey[jb], ex[jb]
            norm = np.hypot(nx, ny)
            t_best[rows][better] = t_min[better]
            n_best[rows][better] = np.column_stack([nx / norm, ny / norm])


def _cast_circles(circles: NDArray[np.float64], ox: NDArray[np.float64],
                  oy: NDArray[np.float64], dx: NDArray[np.float64], dy: NDArray[np.float64],
                  t_best: NDArray[np.float64], n_best: NDArray[np.float64]) -> None:
    m = len(circles)
    if m == 0:
        return
    block = max(1, BLOCK_ELEMENTS // m)
    single = len(ox) == 1
    for start in range(0, len(dx), block):
        rows = slice(start, start + block)
        bx, by = (ox, oy) if single else (ox[rows], oy[rows])
        fx = bx[:, None] - circles[:, 0]
        fy = by[:, None] - circles[:, 1]
        b = fx * dx[rows, None] + fy * dy[rows, None]
        c = fx * fx + fy * fy - circles[:, 2] ** 2
        disc = b * b - c
        root = np.sqrt(np.maximum(disc, 0.0))
        near, far = -b - root, -b + root
        t = np.where(near >= 0.0, near, far)
        t = np.where((disc >= 0.0) & (t >= 0.0), t, np.inf)
        better, j, t_min = _closest(t, t_best, rows)
        if better.any():
            jb = j[better]
            px = np.broadcast_to(bx, better.shape)[better] + t_min[better] * dx[rows][better]
            py = np.broadcast_to(by, better.shape)[better] + t_min[better] * dy[rows][better]
            nx, ny = px - circles[jb, 0], py - circles[jb, 1]
            norm = np.hypot(nx, ny)
            t_best[rows][better] = t_min[better]
            n_best[rows][better] = np.column_stack([nx / norm, ny / norm])


def _slab(u0: NDArray[np.float64], du: NDArray[np.float64],
          size: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the parameter interval where u0 + t du lies in [0, size] (empty: lo > hi)."""
    with np.errstate(divide='ignore', invalid='ignore'):
        t1 = -u0 / du
        t2 = (size - u0) / du
    lo, hi = np.minimum(t1, t2), np.maximum(t1, t2)
    parallel = du == 0.0
    inside = (u0 >= 0.0) & (u0 <= size)
    lo = np.where(parallel, np.where(inside, -np.inf, np.inf), lo)
    hi = np.where(parallel, np.where(inside, np.inf, -np.inf), hi)
    return lo, hi


class _Lines:
    """The crossings of one family of grid lines by k rays: per-ray constants of the traversal."""

    def __init__(self, u0: NDArray[np.float64], du: NDArray[np.float64],
                 v0: NDArray[np.float64], dv: NDArray[np.float64]) -> None:
        f = np.floor(u0)
        self.step = np.where(du >= 0.0, 1.0, -1.0)
        with np.errstate(divide='ignore', invalid='ignore'):
            # t between crossings [cells]; finite (1e300) for rays along the lines, whose
            # crossings then all lie beyond any range (no inf * 0 = NaN downstream).
            self.dt = 1.0 / np.maximum(np.abs(du), 1e-300)
            self.first = np.where(du > 0.0, f + 1.0 - u0, u0 - f)   # u to the first line
            self.f = f
            self.v0, self.dv = v0, dv
            self.parallel = du == 0.0

    def first_hit(self, a: NDArray[np.int64], lo: NDArray[np.float64], hi: NDArray[np.float64],
                  count: int, occupied: NDArray[np.bool_], stride: int,
                  by_column: bool) -> NDArray[np.float64]:
        """Return the least t in [lo, hi] of a crossing into an occupied cell (inf: none)."""
        dt, first, step = self.dt[a], self.first[a], self.step[a]
        steps = np.arange(count, dtype=np.float64)
        with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
            j0 = np.maximum(np.ceil(lo / dt - first - 1e-9), 0.0)
            last = np.where(self.parallel[a], -1.0, np.floor(hi / dt - first) - j0)
            t_base = (first + j0) * dt
            entered = (self.f[a] + step * (j0 + 1.0))[:, None] + steps * step[:, None]
            other = np.floor((self.v0[a] + self.dv[a] * t_base)[:, None]
                             + steps * (self.dv[a] * dt)[:, None])
            # Within [lo, hi] the entered cell lies on the grid or its one-cell free border;
            # the steps beyond hi (masked below) may not: take clips their index.
            index = (other if by_column else entered) * stride
            index += entered if by_column else other
            index += stride + 1.0
            ok = np.take(occupied, index.astype(np.int64), mode='clip')
        ok &= steps <= last[:, None]
        j = np.argmax(ok, axis=1)
        found = ok[np.arange(len(j)), j]
        return np.where(found, t_base + j * dt, np.inf)


def _cast_grid(grid: OccupancyGrid, ox: NDArray[np.float64], oy: NDArray[np.float64],
               dx: NDArray[np.float64], dy: NDArray[np.float64], max_range: float,
               t_best: NDArray[np.float64], n_best: NDArray[np.float64]) -> None:
    k = len(t_best)
    res = grid.resolution
    x0, y0, yaw = grid.origin
    c, s = math.cos(yaw), math.sin(yaw)
    rx = np.broadcast_to(ox, (k,)) - x0
    ry = np.broadcast_to(oy, (k,)) - y0
    u0, v0 = (c * rx + s * ry) / res, (-s * rx + c * ry) / res
    du, dv = c * dx + s * dy, -s * dx + c * dy
    width, height = grid.width, grid.height
    stride = width + 2
    occupied = grid.occupied_padded
    fu, fv = np.floor(u0), np.floor(v0)
    start = ((np.clip(fv, -1, height) + 1) * stride + np.clip(fu, -1, width) + 1).astype(np.int64)
    t_cells = np.where(occupied[start], 0.0, np.inf)
    axis = np.where(t_cells == 0.0, 2, -1)
    lo_u, hi_u = _slab(u0, du, width)
    lo_v, hi_v = _slab(v0, dv, height)
    t_end = np.minimum(t_best, max_range) / res
    t_lo = np.maximum(np.maximum(lo_u, lo_v), 0.0)
    t_exit = np.minimum(np.minimum(hi_u, hi_v), t_end)
    columns, rows = _Lines(u0, du, v0, dv), _Lines(v0, dv, u0, du)
    active = np.nonzero((axis < 0) & (t_lo <= t_exit))[0]
    chunk = GRID_CHUNK
    while active.size:
        a = active
        lo = t_lo[a]
        hi = np.minimum(lo + chunk, t_exit[a])
        tx = columns.first_hit(a, lo, hi, chunk + 2, occupied, stride, True)
        ty = rows.first_hit(a, lo, hi, chunk + 2, occupied, stride, False)
        best = np.minimum(tx, ty)
        found = np.isfinite(best)
        t_cells[a[found]] = best[found]
        axis[a[found]] = np.where(tx[found] <= ty[found], 0, 1)
        t_lo[a] = hi
        active = a[~found & (hi < t_exit[a])]
        chunk *= 2
    t = t_cells * res
    better = (t < t_best) & (t <= max_range)
    if not better.any():
        return
    gx = np.where(axis == 0, -np.sign(du), 0.0)
    gy = np.where(axis == 1, -np.sign(dv), 0.0)
    nx, ny = c * gx - s * gy, s * gx + c * gy
    nx = np.where(axis == 2, -dx, nx)
    ny = np.where(axis == 2, -dy, ny)
    t_best[better] = t[better]
    n_best[better, 0] = nx[better]
    n_best[better, 1] = ny[better]


def cast_rays(world: World, origin: ArrayLike, angles: ArrayLike,
              max_range: float = math.inf, grown_by: float = 0.0) -> RayHits:
    """
    Cast k rays in ``world`` and return what each meets first within ``max_range`` [m].

    Parameters
    ----------
    world : World
        The world model (map frame).
    origin : array_like
        One origin (2,) [m] for every ray (a laser), or one per ray (k, 2) (a sonar ring).
    angles : array_like
        Ray directions (k,) [rad] in the map frame, counter-clockwise from its x axis.
    max_range : float
        Longest range reported [m], > 0 (inf allowed).
    grown_by : float
        Extra growth [m] of the geometric obstacles (not the grid) for this cast, as if by
        :func:`~robotica_kin.world.queries.grow`: a circular body of that radius moving
        along the ray meets the obstacles at the range returned.

    Returns
    -------
    RayHits
        ``ranges`` (k,) [m] (inf for no hit), ``points`` (k, 2) [m], ``normals`` (k, 2) facing
        the origin, ``incidence`` (k,) [rad] in [0, π/2], ``hit`` (k,) bool.

    Raises
    ------
    ValueError
        Non-finite origin or angles, wrong shapes, max_range not > 0, grown_by < 0.

    Examples
    --------
    A ray at 45° to the wall x = 2 meets it at range 2√2 with incidence π/4:

    >>> world = World(walls=[[2.0, -5.0, 2.0, 5.0]])
    >>> hits = cast_rays(world, [0.0, 0.0], [math.pi / 4, math.pi])
    >>> hits.ranges.round(6).tolist(), hits.incidence[0].round(6), hits.normals[0].tolist()
    ([2.828427, inf], np.float64(0.785398), [-1.0, -0.0])

    """
    o = np.asarray(origin, dtype=np.float64)
    a = np.asarray(angles, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f'angles must have shape (k,), got {a.shape}')
    if o.shape != (2,) and o.shape != (len(a), 2):
        raise ValueError(f'origin must have shape (2,) or ({len(a)}, 2), got {o.shape}')
    if not (np.isfinite(o).all() and np.isfinite(a).all()):
        raise ValueError('origin and angles must be finite')
    if not max_range > 0.0:
        raise ValueError(f'max_range must be > 0 m, got {max_range!r}')
    if not (math.isfinite(grown_by) and grown_by >= 0.0):
        raise ValueError(f'grown_by must be >= 0 m, got {grown_by!r}')
    k = len(a)
    ox, oy = np.atleast_1d(o[..., 0]), np.atleast_1d(o[..., 1])
    dx, dy = np.cos(a), np.sin(a)
    t_best = np.full(k, np.inf)
    n_best = np.full((k, 2), np.nan)
    segments, circles = world.surfaces(grown_by)
    _cast_segments(segments, ox, oy, dx, dy, t_best, n_best)
    _cast_circles(circles, ox, oy, dx, dy, t_best, n_best)
    if world.grid is not None:
        _cast_grid(world.grid, ox, oy, dx, dy, max_range, t_best, n_best)
    hit = np.isfinite(t_best) & (t_best <= max_range)
    t_best[~hit] = np.inf
    n_best[~hit] = np.nan
    # Face the normal towards the ray's origin: opposite to the direction.
    flip = n_best[:, 0] * dx + n_best[:, 1] * dy > 0.0
    n_best[flip] *= -1.0
    cos_incidence = -(n_best[:, 0] * dx + n_best[:, 1] * dy)
    incidence = np.arccos(np.clip(cos_incidence, 0.0, 1.0))
    t_hit = np.where(hit, t_best, np.nan)
    points = np.column_stack([ox + t_hit * dx, oy + t_hit * dy])
    return RayHits(ranges=t_best, points=points, normals=n_best, incidence=incidence, hit=hit)
