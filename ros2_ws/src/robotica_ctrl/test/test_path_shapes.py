"""Tests of robotica_ctrl.mobile.path_shapes: sampled reference paths for the ch. 9 trackers."""

import math

import numpy as np
import pytest

from robotica_ctrl.mobile.path_shapes import circle, figure_eight, rounded_rectangle, straight_line


def polyline_length(points):
    return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))


def shoelace_area(points):
    """Return the signed area [m²] enclosed by a closed polyline (> 0 counter-clockwise)."""
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))


def chord_deficit(arc_length, radius, spacing):
    """
    Bound [m] on arc length minus chord length for arcs cut into pieces <= spacing.

    A piece of angle a = spacing / r has chord 2 r sin(a/2) >= r a (1 - a²/24).
    """
    return arc_length * (spacing / radius) ** 2 / 24.0


SHAPES = {
    'line': lambda spacing: straight_line([-1.0, 2.0], [3.0, -1.0], spacing),
    'circle': lambda spacing: circle([1.0, -2.0], 1.5, spacing, start_angle=0.3),
    'rounded_rectangle': lambda spacing: rounded_rectangle(4.0, 3.0, 0.5, spacing),
    'stadium': lambda spacing: rounded_rectangle(4.0, 1.0, 0.5, spacing),
    'figure_eight': lambda spacing: figure_eight(1.0, spacing),
}


@pytest.mark.parametrize('spacing', [0.01, 0.05, 0.3])
@pytest.mark.parametrize('shape', sorted(SHAPES))
def test_spacing_bound_and_no_duplicates(shape, spacing):
    points = SHAPES[shape](spacing)
    assert points.ndim == 2 and points.shape[1] == 2
    assert points.dtype == np.float64
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    assert steps.max() <= spacing * (1.0 + 1e-12)
    assert steps.min() > 0.0


def test_straight_line():
    points = straight_line([-1.0, 2.0], [3.0, -1.0], spacing=0.3)
    np.testing.assert_array_equal(points[0], [-1.0, 2.0])
    np.testing.assert_array_equal(points[-1], [3.0, -1.0])
    assert len(points) == math.ceil(5.0 / 0.3) + 1  # length 5 m (3-4-5 triangle)
    assert polyline_length(points) == pytest.approx(5.0, rel=1e-12)
    # Every point on the line 3 x + 4 y = 5 through both ends.
    np.testing.assert_allclose(points @ [3.0, 4.0], 5.0, atol=1e-12)


@pytest.mark.parametrize('radius', [0.2, 1.0, 3.0])
@pytest.mark.parametrize('start_angle', [0.0, 1.0, -2.5])
def test_circle(radius, start_angle):
    spacing = 0.05
    center = np.array([1.0, -2.0])
    points = circle(center, radius, spacing, start_angle=start_angle)
    np.testing.assert_array_equal(points[0], points[-1])  # closed
    np.testing.assert_allclose(np.linalg.norm(points - center, axis=1), radius, rtol=1e-12)
    np.testing.assert_allclose(points[0], center + radius * np.array(
        [math.cos(start_angle), math.sin(start_angle)]), atol=1e-12)
    length = polyline_length(points)
    assert 2.0 * math.pi * radius - chord_deficit(2.0 * math.pi * radius, radius, spacing) \
        <= length <= 2.0 * math.pi * radius
    assert shoelace_area(points) > 0.0  # counter-clockwise
    # The first chord leaves at start_angle + π/2, up to half the angular step.
    first = points[1] - points[0]
    heading_error = math.atan2(first[1], first[0]) - (start_angle + 0.5 * math.pi)
    assert abs(math.atan2(math.sin(heading_error), math.cos(heading_error))) \
        <= 0.5 * spacing / radius


def test_circle_of_large_spacing_keeps_three_segments():
    points = circle([0.0, 0.0], 1.0, spacing=100.0)
    assert len(points) == 4


@pytest.mark.parametrize(('width', 'height', 'r'), [
    (4.0, 3.0, 0.5), (4.0, 3.0, 1.5), (2.0, 2.0, 1.0), (5.0, 1.0, 0.5), (1.0, 5.0, 0.25)])
def test_rounded_rectangle(width, height, r):
    spacing = 0.05
    points = rounded_rectangle(width, height, r, spacing)
    np.testing.assert_array_equal(points[0], [0.0, 0.0])
    np.testing.assert_array_equal(points[-1], [0.0, 0.0])  # closed
    first = points[1] - points[0]  # starts heading +x (on a chord when there is no straight)
    assert first[0] > 0.0 and abs(math.atan2(first[1], first[0])) <= 0.5 * spacing / r
    if 2.0 * r < width:
        assert first[1] == 0.0  # exactly along the bottom straight
    np.testing.assert_allclose(points.min(axis=0), [-r, 0.0], atol=1e-12)
    np.testing.assert_allclose(points.max(axis=0), [width - r, height], atol=1e-12)
    expected_length = 2.0 * (width + height) - 8.0 * r + 2.0 * math.pi * r
    deficit = chord_deficit(2.0 * math.pi * r, r, spacing)
    assert expected_length - deficit <= polyline_length(points) <= expected_length + 1e-12
    # Counter-clockwise, enclosing the rectangle less four corners of (1 - π/4) r² each.
    expected_area = width * height - (4.0 - math.pi) * r ** 2
    assert shoelace_area(points) == pytest.approx(expected_area, rel=1e-3)


@pytest.mark.parametrize('radius', [0.5, 1.0, 2.0])
def test_figure_eight(radius):
    spacing = 0.05
    points = figure_eight(radius, spacing)
    np.testing.assert_array_equal(points[0], [0.0, 0.0])
    np.testing.assert_array_equal(points[-1], [0.0, 0.0])  # closed
    assert np.any(np.all(points[1:-1] == 0.0, axis=1))  # crosses the origin half-way
    first = points[1] - points[0]
    assert abs(math.atan2(first[1], first[0])) <= 0.5 * spacing / radius  # heading +x
    assert first[1] > 0.0  # the first loop is the upper one, counter-clockwise
    # Every point is on one of the two circles tangent at the origin.
    to_upper = np.abs(np.linalg.norm(points - [0.0, radius], axis=1) - radius)
    to_lower = np.abs(np.linalg.norm(points - [0.0, -radius], axis=1) - radius)
    assert np.all(np.minimum(to_upper, to_lower) <= 1e-12)
    expected_length = 4.0 * math.pi * radius
    assert expected_length - chord_deficit(expected_length, radius, spacing) \
        <= polyline_length(points) <= expected_length
    # The loops turn opposite ways, so their signed areas cancel.
    assert shoelace_area(points) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize('make', [
    lambda: straight_line([0.0, 0.0], [0.0, 0.0]),
    lambda: straight_line([0.0, 0.0], [1.0, 0.0], spacing=0.0),
    lambda: straight_line([0.0, 0.0], [1.0, math.nan]),
    lambda: straight_line([0.0, 0.0, 0.0], [1.0, 0.0]),
    lambda: circle([0.0, 0.0], 0.0),
    lambda: circle([0.0, 0.0], -1.0),
    lambda: circle([0.0, 0.0], 1.0, spacing=math.inf),
    lambda: circle([0.0, 0.0], 1.0, start_angle=math.nan),
    lambda: circle([0.0, math.inf], 1.0),
    lambda: rounded_rectangle(4.0, 3.0, 0.0),
    lambda: rounded_rectangle(4.0, 3.0, 1.6),   # 2 r > height
    lambda: rounded_rectangle(2.0, 3.0, 1.01),  # 2 r > width
    lambda: rounded_rectangle(-4.0, 3.0, 0.5),
    lambda: rounded_rectangle(4.0, math.nan, 0.5),
    lambda: rounded_rectangle(4.0, 3.0, 0.5, spacing=-0.1),
    lambda: figure_eight(0.0),
    lambda: figure_eight(1.0, spacing=0.0),
])
def test_invalid_inputs_are_rejected(make):
    with pytest.raises(ValueError):
        make()
