"""
Tests of robotica_ctrl.mobile.range_perception: readings to points, walls and clearance.

References are computed by hand: a beam of range r at angle a from a sensor at (x, y, yaw)
hits (x + r cos(yaw + a), y + r sin(yaw + a)); a wall y = c + m x is at distance
|c| / sqrt(1 + m^2) from the origin, with direction atan(m).
"""
import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from robotica_ctrl.mobile.range_perception import (clearance_ahead, nearest_distance,
                                                   range_points, side_wall)


def test_rep117_conventions():
    rp = range_points([2.0, math.inf, 6.0, math.nan, -math.inf, 0.05],
                      [0.0, 0.1, 0.2, 0.3, 0.4, 0.5], 0.1, 5.0)
    # 2.0: a return; +inf and 6.0 (> range_max): no return; NaN: unknown; -inf and 0.05
    # (< range_min): too close, at range_min.
    assert rp.readings == 6 and rp.unknown == 1 and rp.unknown_fraction == pytest.approx(1 / 6)
    expected = [[2.0, 0.0], [0.1 * math.cos(0.4), 0.1 * math.sin(0.4)],
                [0.1 * math.cos(0.5), 0.1 * math.sin(0.5)]]
    assert rp.points == pytest.approx(np.array(expected))


def test_a_ring_of_sensors_each_at_its_pose():
    poses = [[0.2, 0.0, 0.0], [0.0, 0.2, math.pi / 2], [-0.2, 0.0, math.pi]]
    rp = range_points([1.0, 0.5, 2.0], [0.0, 0.0, 0.0], 0.0, 3.0, poses)
    assert rp.points == pytest.approx(np.array([[1.2, 0.0], [0.0, 0.7], [-2.2, 0.0]]))


@pytest.mark.parametrize('kwargs, message', [
    ({'angles': [0.0]}, 'angles must be 2 finite values'),
    ({'sensor_pose': [0.0, 0.0]}, 'sensor_pose must be finite'),
    ({'range_min': 2.0}, 'need 0 <= range_min < range_max'),
])
def test_bad_input(kwargs, message):
    args = {'ranges': [1.0, 1.0], 'angles': [0.0, 0.1], 'range_min': 0.1, 'range_max': 1.5,
            **kwargs}
    with pytest.raises(ValueError, match=message):
        range_points(**args)


@settings(max_examples=50, deadline=None)
@given(c=st.floats(0.3, 2.0), m=st.floats(-0.5, 0.5), side=st.sampled_from(['left', 'right']))
def test_side_wall_of_a_line(c, m, side):
    sign = 1.0 if side == 'left' else -1.0
    x = np.linspace(-0.5, 0.5, 11)
    points = np.column_stack([x, sign * (c + m * x)])
    wall = side_wall(points, side, 3.0, 1.0)
    assert wall.distance == pytest.approx(c / math.sqrt(1 + m * m), rel=1e-9)
    assert wall.angle == pytest.approx(sign * math.atan(m), abs=1e-9)
    assert wall.points == 11


def test_side_wall_needs_points_on_its_side():
    points = np.array([[0.0, 1.0], [0.5, 1.0], [-0.5, 1.0], [0.0, -1.0]])
    assert side_wall(points, 'right', 2.0, 1.0) is None     # one point only
    assert side_wall(points, 'left', 0.5, 1.0) is None      # beyond max_distance
    with pytest.raises(ValueError, match="side must be 'left' or 'right'"):
        side_wall(points, 'up', 2.0, 1.0)


def test_clearance_and_nearest():
    points = np.array([[1.5, 0.2], [0.8, 0.5], [-0.3, 0.0], [3.0, -0.1]])
    assert clearance_ahead(points, 0.25) == 1.5
    assert clearance_ahead(points, 0.6) == 0.8
    assert nearest_distance(points) == pytest.approx(0.3)
    assert math.isinf(clearance_ahead(np.zeros((0, 2)), 1.0))
    assert math.isinf(nearest_distance(np.zeros((0, 2))))
