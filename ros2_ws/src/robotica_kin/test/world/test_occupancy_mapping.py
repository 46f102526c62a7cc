"""
Tests of robotica_kin.world.occupancy_mapping: certainty grids from laser and sonar (§12.4.1).

References: the slides' -1..+1 scale by hand, the log-odds closed form sigmoid(n logit m),
an exact clip of each beam against every cell near it, the cone's geometry recomputed here,
and, for maps built while driving, the World's own geometry (which cells a wall crosses, which
lie clear of every obstacle) against a map built from an ideal laser's ranges (cast_rays).
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world import cast_rays, OccupancyGrid, World
from robotica_kin.world.occupancy_mapping import (
    beam_cells, evidence_to_percent, laser_inverse_model, OccupancyMap, OccupancyMappingParams,
    percent_to_evidence, sonar_inverse_model)
from robotica_kin.world.queries import distance_to_obstacles
from robotica_kin.world.shapes import box_polygon

PARAMS = OccupancyMappingParams()
CORRIDOR = World(walls=[[-2.0, 1.02, 8.0, 1.02], [-2.0, -1.03, 8.0, -1.03]],
                 polygons=(box_polygon([3.02, -0.52], [0.4, 0.4]),))


def clipped_lengths(grid, start, end):
    """Return {(col, row): length in cells of the segment inside the cell's closed square}."""
    (u0, v0), (u1, v1) = grid.world_to_grid([start, end])
    lengths = {}
    for col in range(math.floor(min(u0, u1)) - 1, math.floor(max(u0, u1)) + 2):
        for row in range(math.floor(min(v0, v1)) - 1, math.floor(max(v0, v1)) + 2):
            lo, hi = 0.0, 1.0                        # Liang-Barsky clip, one slab at a time
            for p0, dp, low in ((u0, u1 - u0, col), (v0, v1 - v0, row)):
                if dp == 0.0:
                    lo, hi = (lo, hi) if low <= p0 <= low + 1 else (1.0, 0.0)
                else:
                    a, b = sorted(((low - p0) / dp, (low + 1 - p0) / dp))
                    lo, hi = max(lo, a), min(hi, b)
            if hi >= lo:
                lengths[(col, row)] = (hi - lo) * math.hypot(u1 - u0, v1 - v0)
    return lengths


def cells_crossed_by(grid, wall, samples=20001):
    """Return the set of flat indices of the cells that dense points of a wall fall in."""
    t = np.linspace(0.0, 1.0, samples)
    points = np.asarray(wall[:2]) + t[:, None] * (np.asarray(wall[2:]) - np.asarray(wall[:2]))
    cells = {tuple(c) for c in grid.world_to_cell(points).tolist()}
    return {row * grid.width + col for col, row in cells
            if 0 <= col < grid.width and 0 <= row < grid.height}


def test_evidence_scale_is_the_slides():
    assert evidence_to_percent([-1.0, 0.0, 1.0]).tolist() == [0, 50, 100]
    e = np.linspace(-1.0, 1.0, 201)
    np.testing.assert_allclose(percent_to_evidence(evidence_to_percent(e)), e, atol=0.01)
    assert percent_to_evidence([-1]).tolist() == [0.0]   # unknown: no evidence either way
    with pytest.raises(ValueError, match=r'\[-1, 1\]'):
        evidence_to_percent([1.5])
    with pytest.raises(ValueError, match='unknown'):
        percent_to_evidence([101])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), yaw=st.floats(-math.pi, math.pi))
def test_beam_cells_are_the_cells_the_segment_passes(seed, yaw):
    rng = np.random.default_rng(seed)
    grid = OccupancyGrid(np.zeros((20, 20), np.int8), 0.3, (0.4, -0.7, yaw))
    starts, ends = rng.uniform(-3.0, 3.0, (6, 2)), rng.uniform(-3.0, 3.0, (6, 2))
    beam, col, row, t_out = beam_cells(grid, starts, ends)
    for k in range(6):
        mine = [(c, r) for c, r in zip(col[beam == k].tolist(), row[beam == k].tolist())]
        assert len(mine) == len(set(mine))
        lengths = clipped_lengths(grid, starts[k], ends[k])
        assert {c for c, length in lengths.items() if length > 1e-9} <= set(mine) <= set(lengths)
        assert np.all(np.diff(t_out[beam == k]) > 0.0) and t_out[beam == k][-1] == 1.0
        assert tuple(grid.world_to_cell([ends[k]])[0]) == mine[-1] or math.isclose(
            min(abs(v - round(v)) for v in grid.world_to_grid([ends[k]])[0]), 0.0,
            abs_tol=1e-9)


def test_repeated_hits_follow_the_log_odds_closed_form():
    grid_map = OccupancyMap((1, 6), 1.0, params=OccupancyMappingParams(0.7, 0.4, 0.01, 0.999))
    logit = math.log(0.7 / 0.3)
    for n in range(1, 6):
        grid_map.update_laser([0.5, 0.5, 0.0], [0.0], [3.5], 0.1, 5.0)
        expected = 1.0 / (1.0 + math.exp(-n * logit))
        assert grid_map.probability[0, 3] == pytest.approx(expected, rel=1e-12)
        assert grid_map.probability[0, 1] == pytest.approx(
            1.0 / (1.0 + math.exp(-n * math.log(0.4 / 0.6))), rel=1e-12)
    for _ in range(40):
        grid_map.update_laser([0.5, 0.5, 0.0], [0.0], [3.5], 0.1, 5.0)
    assert grid_map.probability[0, 3] == 0.999 and grid_map.probability[0, 1] == 0.01


def test_laser_readings_follow_rep_117():
    grid = OccupancyGrid(np.zeros((1, 10), np.int8), 1.0)
    pose = [0.5, 0.5, 0.0]
    cells, m = laser_inverse_model(grid, pose, [0.0], [math.inf], 0.2, 4.0)
    assert cells.tolist() == [0, 1, 2, 3, 4] and np.all(m == PARAMS.p_free)   # free to 4.5 m
    for reading in (math.nan, -math.inf, 0.1, 4.2):      # no reading, too close, out of range
        cells, m = laser_inverse_model(grid, pose, [0.0], [reading], 0.2, 4.0)
        assert cells.size == 0
    cells, m = laser_inverse_model(grid, pose, [0.0], [4.0], 0.2, 4.0)   # range_max: a hit
    assert cells.tolist() == [0, 1, 2, 3, 4] and m[-1] == PARAMS.p_occupied
    with pytest.raises(ValueError, match='range_min'):
        laser_inverse_model(grid, pose, [0.0], [1.0], 4.0, 1.0)
    with pytest.raises(ValueError, match='angles and ranges'):
        laser_inverse_model(grid, pose, [0.0, 0.1], [1.0], 0.1, 4.0)


def test_a_cell_hit_in_a_scan_is_occupied_though_other_beams_cross_it():
    grid = OccupancyGrid(np.zeros((3, 6), np.int8), 1.0)
    # Beam 0 ends in cell (3, 1); beam 1 crosses it on the way to cell (5, 1).
    cells, m = laser_inverse_model(grid, [0.5, 1.5, 0.0], [0.0, 0.0], [3.0, 5.0], 0.1, 9.0)
    assert dict(zip(cells.tolist(), m.tolist()))[1 * 6 + 3] == PARAMS.p_occupied


def drive(world, xs, grid_map, max_range=3.5, beams=360):
    """Drive along y = 0 heading +x, fusing an ideal laser's scan at every x."""
    angles = np.linspace(-math.pi, math.pi, beams, endpoint=False)
    for x in xs:
        pose = np.array([x, 0.0, 0.0])
        ranges = cast_rays(world, pose[:2], angles, max_range).ranges   # inf: no return
        grid_map.update_laser(pose, angles, ranges, 0.05, max_range)


def test_driving_along_a_wall_maps_the_world():
    grid_map = OccupancyMap((30, 100), 0.1, (-2.0, -1.5, 0.0))
    drive(CORRIDOR, np.arange(0.0, 6.01, 0.1), grid_map)
    grid = grid_map.to_grid()
    p, seen = grid_map.probability.ravel(), grid_map.observed.ravel()
    centres = grid.cell_to_world(np.column_stack([np.arange(grid.width * grid.height)
                                                  % grid.width,
                                                  np.arange(grid.width * grid.height)
                                                  // grid.width]))
    # The walls' cells (those the walls cross) along the drive are occupied.
    middle = (centres[:, 0] > 0.5) & (centres[:, 0] < 5.5)
    for wall in CORRIDOR.walls:
        crossed = np.array(sorted(cells_crossed_by(grid, wall)))
        crossed = crossed[middle[crossed]]
        assert len(crossed) == 50
        assert grid.occupied.ravel()[crossed].all(), p[crossed].min()
    # The box's face towards the robot (y = -0.32) too.
    face = np.array(sorted(cells_crossed_by(grid, [2.83, -0.32, 3.21, -0.32])))
    assert grid.occupied.ravel()[face].all()
    # No cell clear of every obstacle by a cell's diagonal leans occupied, and the corridor the
    # robot drove through is free (below map_server's free_thresh).
    clear = distance_to_obstacles(CORRIDOR, centres) > math.sqrt(2.0) * 0.1
    assert (p[clear & seen] < 0.5).all()
    lane = middle & (centres[:, 1] > -0.2) & (centres[:, 1] < 0.9)
    assert lane.sum() == 550 and (p[lane] < 0.196).all()
    # Behind the walls nothing was seen.
    behind = (centres[:, 1] > 1.1) | (centres[:, 1] < -1.1)
    assert not seen[behind].any()
    assert (grid.data.ravel()[behind] == -1).all()


def test_sonar_cone_geometry():
    grid = OccupancyGrid(np.zeros((60, 60), np.int8), 0.05, (-0.5, -1.5, 0.0))
    pose = np.array([0.0, 0.0, 0.3])
    beta, reading = math.radians(12.5), 1.6
    cells, m = sonar_inverse_model(grid, pose, reading, beta, 0.15, 4.0)
    centres = grid.cell_to_world(np.column_stack([cells % grid.width, cells // grid.width]))
    rel = centres - pose[:2]
    rho = np.hypot(rel[:, 0], rel[:, 1])
    off_axis = np.abs(np.angle(np.exp(1j * (np.arctan2(rel[:, 1], rel[:, 0]) - pose[2]))))
    eps = max(PARAMS.sonar_arc_half_width, math.sqrt(0.5) * 0.05)
    assert (off_axis <= beta + 1e-12).all() and (rho <= reading + eps + 1e-12).all()
    np.testing.assert_array_equal(m > 0.5, np.abs(rho - reading) <= eps)
    assert ((m >= PARAMS.p_free) & (m <= PARAMS.p_occupied)).all()
    # The strongest evidence lies on the axis: free near the apex, occupied on the arc.
    assert m.min() == pytest.approx(PARAMS.p_free, abs=0.01)
    assert m.max() == pytest.approx(PARAMS.p_occupied, abs=0.01)
    # No echo: free up to max_range, nothing occupied; NaN and -inf: nothing.
    cells, m = sonar_inverse_model(grid, pose, 4.0, beta, 0.15, 4.0)
    assert cells.size > 0 and (m < 0.5).all()
    cells_inf, m_inf = sonar_inverse_model(grid, pose, math.inf, beta, 0.15, 4.0)
    np.testing.assert_array_equal(cells_inf, cells)
    for reading in (math.nan, -math.inf, 0.1):
        assert sonar_inverse_model(grid, pose, reading, beta, 0.15, 4.0)[0].size == 0
    with pytest.raises(ValueError, match='cone_half_angle'):
        sonar_inverse_model(grid, pose, 1.0, 2.0, 0.15, 4.0)


def test_a_sonar_driven_along_a_wall_maps_it():
    world = World(walls=[[-2.0, 1.02, 8.0, 1.02]])
    grid_map = OccupancyMap((40, 100), 0.1, (-2.0, -1.5, 0.0))
    beta = math.radians(12.5)
    for x in np.arange(0.0, 6.01, 0.05):
        pose = np.array([x, 0.0, 0.0])
        for mount in ([0.0, 0.1, 0.5 * math.pi], [0.1, 0.08, 0.25 * math.pi]):
            sensor = pose + mount
            # An ideal sonar: the nearest echo across the cone, no echo reads max_range.
            fan = sensor[2] + np.linspace(-beta, beta, 11)
            reading = min(cast_rays(world, sensor[:2], fan, 4.0).ranges.min(), 4.0)
            grid_map.update_sonar(pose, reading, beta, 0.15, 4.0, mount=mount)
    grid = grid_map.to_grid()
    crossed = np.array(sorted(cells_crossed_by(grid, [1.0, 1.02, 5.0, 1.02])))
    assert grid.occupied.ravel()[crossed].all()
    # A cone's arc also lies on free cells within its width of the echo: so the cells well
    # clear of the wall lean free, and those in the middle of the lane are free.
    p = grid_map.probability[:, 30:70]                       # x in [1, 5)
    centre_y = -1.5 + 0.1 * (np.arange(40) + 0.5)
    clear = (centre_y < 1.02 - 0.25) & grid_map.observed[:, 30:70].all(axis=1)
    assert clear.sum() == 7 and (p[clear] < 0.5).all()
    middle = (centre_y > 0.2) & (centre_y < 0.7)
    assert (p[middle] < 0.3).all()


def test_map_class_contract():
    grid_map = OccupancyMap.like(OccupancyGrid(np.zeros((3, 4), np.int8), 0.5, (1.0, 2.0, 0.1)))
    assert grid_map.probability.shape == (3, 4) and grid_map.frame.origin == (1.0, 2.0, 0.1)
    assert (grid_map.to_grid().data == -1).all() and (grid_map.evidence() == 0.0).all()
    grid_map.update_scan([1.2, 2.3, 0.1], [1.0, math.inf], 0.0, 0.5, 0.1, 1.5)
    assert grid_map.observed.any()
    grid_map.reset()
    assert not grid_map.observed.any() and (grid_map.probability == 0.5).all()
    with pytest.raises(ValueError, match='shape'):
        OccupancyMap((0, 4), 0.5)
    with pytest.raises(ValueError, match='p_min < p_free'):
        OccupancyMappingParams(p_free=0.6)
    with pytest.raises(ValueError, match='pose'):
        grid_map.update_laser([0.0, math.nan, 0.0], [0.0], [1.0], 0.1, 2.0)
