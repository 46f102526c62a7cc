"""
Speed of ray casting on the world model, against a plain NumPy loop in the same run.

A scan is 360 beams (one per degree, ``max_range`` 30 m) from one origin, as a laser gives:

- against a world of 200 random walls in a 20 m x 20 m square (lengths 0.2..2 m), by
  :func:`robotica_kin.world.cast_rays` and by the baseline, a loop over the beams in which each
  beam meets all the segments at once in NumPy (the straightforward vectorisation);
- against a 1000 x 1000 grid (5 cm cells, 50 m x 50 m) with 1 % of its cells occupied at
  random, by ``cast_rays`` and by a plain-Python Amanatides–Woo traversal, one beam and one
  cell at a time;
- a sonar ring: 16 beams from 16 origins on a 0.2 m circle, against the walls.

Each scan has its own random origin (a free cell for the grid; the same origins for both
routes), times are wall-clock per scan (``time.perf_counter``), the median over ``scans``
scans (fewer for the slow Python traversal); the ranges of both routes are compared. Run it
with ``robotica bench raycast``.
"""

import math
import statistics
import time
from typing import Callable

import numpy as np
from numpy.typing import NDArray
from robotica_kin.world import cast_rays, OccupancyGrid, World
from robotica_sim.benchmarks.measurement_row import MeasurementRow

__all__ = ['baseline_grid', 'baseline_segments', 'raycast_benchmark']

BEAMS = 360
MAX_RANGE = 30.0      # [m]
SEGMENTS = 200
GRID_SIZE = 1000      # cells a side
GRID_RESOLUTION = 0.05   # [m/cell]
GRID_DENSITY = 0.01   # fraction of occupied cells


def baseline_segments(segments: NDArray[np.float64], origin: NDArray[np.float64],
                      angles: NDArray[np.float64], max_range: float) -> NDArray[np.float64]:
    """Return the ranges [m] of the beams, one beam against all segments at a time."""
    ax, ay = segments[:, 0], segments[:, 1]
    ex, ey = segments[:, 2] - ax, segments[:, 3] - ay
    wx, wy = ax - origin[0], ay - origin[1]
    ranges = np.full(len(angles), np.inf)
    for k, angle in enumerate(angles):
        dx, dy = math.cos(angle), math.sin(angle)
        with np.errstate(divide='ignore', invalid='ignore'):
            denom = dx * ey - dy * ex
            t = (wx * ey - wy * ex) / denom
            s = (wx * dy - wy * dx) / denom
        t = t[(t >= 0.0) & (s >= 0.0) & (s <= 1.0)]
        if t.size and t.min() <= max_range:
            ranges[k] = t.min()
    return ranges


def baseline_grid(grid: OccupancyGrid, origin: NDArray[np.float64],
                  angles: NDArray[np.float64], max_range: float) -> NDArray[np.float64]:
    """Return the ranges [m] by Amanatides–Woo in plain Python, one beam, one cell at a time."""
    occupied = grid.occupied
    res = grid.resolution
    (u0, v0), = grid.world_to_grid([origin])
    limit = max_range / res
    ranges = np.full(len(angles), np.inf)
    for k, angle in enumerate(angles):
        du, dv = math.cos(angle), math.sin(angle)   # axis-aligned grid
        col, row = math.floor(u0), math.floor(v0)
        step_u, step_v = (1 if du > 0 else -1), (1 if dv > 0 else -1)
        t_u = ((col + 1 - u0) / du if du > 0 else (u0 - col) / -du) if du else math.inf
        t_v = ((row + 1 - v0) / dv if dv > 0 else (v0 - row) / -dv) if dv else math.inf
        dt_u = abs(1.0 / du) if du else math.inf
        dt_v = abs(1.0 / dv) if dv else math.inf
        t = 0.0
        while t <= limit and 0 <= col < grid.width and 0 <= row < grid.height:
            if occupied[row, col]:
                ranges[k] = t * res
                break
            if t_u < t_v:
                t, col, t_u = t_u, col + step_u, t_u + dt_u
            else:
                t, row, t_v = t_v, row + step_v, t_v + dt_v
    return ranges


def _median_us(times: list[float]) -> float:
    return statistics.median(times) * 1e6


def _time(scan: Callable[[int], NDArray[np.float64]], count: int) -> tuple[list[float], list]:
    times, results = [], []
    for i in range(count):
        start = time.perf_counter()
        results.append(scan(i))
        times.append(time.perf_counter() - start)
    return times, results


def raycast_benchmark(scans: int = 200, seed: int = 0,
                      progress: Callable[[str], None] = lambda message: None
                      ) -> list[MeasurementRow]:
    """Return the rows of the ray-casting benchmark (median time per scan [µs], speed-ups)."""
    rng = np.random.default_rng(seed)
    angles = np.radians(np.arange(BEAMS, dtype=np.float64)) - math.pi
    start = rng.uniform(0.0, 20.0, (SEGMENTS, 2))
    heading = rng.uniform(-math.pi, math.pi, SEGMENTS)
    length = rng.uniform(0.2, 2.0, SEGMENTS)
    segments = np.hstack([start, start + length[:, None]
                          * np.column_stack([np.cos(heading), np.sin(heading)])])
    walls = World(walls=segments)
    origins = rng.uniform(0.0, 20.0, (scans, 2))
    progress(f'raycast: {scans} scans of {BEAMS} beams against {SEGMENTS} segments')
    fast, fast_ranges = _time(lambda i: cast_rays(walls, origins[i], angles, MAX_RANGE).ranges,
                              scans)
    slow, slow_ranges = _time(lambda i: baseline_segments(segments, origins[i], angles,
                                                          MAX_RANGE), scans)
    agree = all(np.allclose(a, b, rtol=1e-9) for a, b in zip(fast_ranges, slow_ranges))
    rows = [
        MeasurementRow(f'{BEAMS} beams vs {SEGMENTS} segments: cast_rays', _median_us(fast),
                       'µs/scan', f'median of {scans} scans, random origins'),
        MeasurementRow(f'{BEAMS} beams vs {SEGMENTS} segments: NumPy loop over beams',
                       _median_us(slow), 'µs/scan',
                       f'one beam vs all segments at a time; same ranges: {agree}'),
        MeasurementRow('speed-up, segments', statistics.median(slow) / statistics.median(fast),
                       '×', 'baseline median / cast_rays median'),
    ]
    ring = np.linspace(0.0, 2.0 * math.pi, 16, endpoint=False)
    ring_offsets = 0.2 * np.column_stack([np.cos(ring), np.sin(ring)])
    sonar, _ = _time(lambda i: cast_rays(walls, origins[i] + ring_offsets, ring, 5.0).ranges,
                     scans)
    rows.append(MeasurementRow(f'sonar ring, 16 beams from 16 origins vs {SEGMENTS} segments',
                               _median_us(sonar), 'µs/scan', f'median of {scans} scans'))
    progress(f'raycast: {BEAMS} beams against a {GRID_SIZE} x {GRID_SIZE} grid')
    data = np.where(rng.random((GRID_SIZE, GRID_SIZE)) < GRID_DENSITY, 100, 0).astype(np.int8)
    grid = OccupancyGrid(data, GRID_RESOLUTION)
    world = World(grid=grid)
    free = np.argwhere(~grid.occupied)
    picks = free[rng.choice(len(free), scans)]
    grid_origins = (picks[:, ::-1] + rng.uniform(0.0, 1.0, (scans, 2))) * GRID_RESOLUTION
    fast, fast_ranges = _time(lambda i: cast_rays(world, grid_origins[i], angles,
                                                  MAX_RANGE).ranges, scans)
    slow_count = max(1, min(scans, 20))
    slow, slow_ranges = _time(lambda i: baseline_grid(grid, grid_origins[i], angles, MAX_RANGE),
                              slow_count)
    agree = all(np.allclose(a, b, rtol=1e-9) for a, b in zip(fast_ranges, slow_ranges))
    hits = np.concatenate(fast_ranges)
    free_path = float(np.median(hits[np.isfinite(hits)]))
    rows += [
        MeasurementRow(f'{BEAMS} beams vs {GRID_SIZE}x{GRID_SIZE} grid: cast_rays',
                       _median_us(fast), 'µs/scan',
                       f'median of {scans} scans; {GRID_DENSITY:.0%} cells occupied, median '
                       f'range {free_path:.2f} m'),
        MeasurementRow(f'{BEAMS} beams vs {GRID_SIZE}x{GRID_SIZE} grid: Python DDA',
                       _median_us(slow), 'µs/scan',
                       f'Amanatides–Woo, one cell at a time; median of {slow_count} scans; '
                       f'same ranges: {agree}'),
        MeasurementRow('speed-up, grid', statistics.median(slow) / statistics.median(fast),
                       '×', 'baseline median / cast_rays median'),
    ]
    return rows
