"""Tests of robotica_kin.world.occupancy_grid: cells, frames and thresholds (book §12.4.1)."""

import math

from hypothesis import given
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world import log_odds_update, OccupancyGrid, WorldError


@given(x=st.floats(-5, 5), y=st.floats(-5, 5), yaw=st.floats(-math.pi, math.pi))
def test_cell_centre_round_trip(x, y, yaw):
    grid = OccupancyGrid(np.zeros((20, 30), np.int8), 0.2, (x, y, yaw))
    cells = np.array([[0, 0], [29, 19], [7, 3]])
    np.testing.assert_array_equal(grid.world_to_cell(grid.cell_to_world(cells)), cells)


def test_origin_is_the_lower_left_corner_of_cell_zero():
    grid = OccupancyGrid(np.zeros((2, 2), np.int8), 0.5, (1.0, 2.0, math.pi / 2))
    np.testing.assert_allclose(grid.cell_to_world([[0, 0]]), [[0.75, 2.25]])
    np.testing.assert_allclose(grid.world_to_grid([[1.0, 2.0]]), [[0.0, 0.0]], atol=1e-12)


def test_binary_view_uses_occupied_thresh():
    data = np.array([[-1, 0, 64, 65, 100]], np.int8)
    assert OccupancyGrid(data, 1.0).occupied.tolist() == [[False, False, False, True, True]]
    grid = OccupancyGrid(data, 1.0, occupied_thresh=0.5, free_thresh=0.1)
    assert grid.occupied.tolist() == [[False, False, True, True, True]]


@pytest.mark.parametrize(('kwargs', 'message'), [
    ({'data': np.zeros((2, 2)), 'resolution': 1.0}, 'must be integers'),
    ({'data': np.full((2, 2), 101), 'resolution': 1.0}, 'must be -1'),
    ({'data': np.zeros(3, int), 'resolution': 1.0}, 'non-empty 2-D'),
    ({'data': np.zeros((2, 2), int), 'resolution': 0.0}, 'resolution must be > 0'),
    ({'data': np.zeros((2, 2), int), 'resolution': 1.0, 'origin': (0, math.nan, 0)},
     'origin must be finite'),
    ({'data': np.zeros((2, 2), int), 'resolution': 1.0, 'free_thresh': 0.7},
     'free_thresh < occupied_thresh'),
])
def test_bad_grid(kwargs, message):
    with pytest.raises(WorldError, match=message):
        OccupancyGrid(**kwargs)


def test_log_odds_update_is_bayes_rule():
    prior, p = 0.3, 0.8
    bayes = p * prior / (p * prior + (1 - p) * (1 - prior))
    assert log_odds_update(prior, p) == pytest.approx(bayes)
    assert log_odds_update(0.5, 0.5) == pytest.approx(0.5)
