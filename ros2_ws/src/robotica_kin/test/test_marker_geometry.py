"""
Tests of robotica_kin.marker_geometry: covariance ellipses and vehicle outlines.

References are independent: a covariance is built from chosen semi-axes and angle
(Σ = R diag(σ1², σ2²) Rᵀ), so the ellipse must give back k σ1, k σ2 and the angle; outlines are
worked out by hand from the geometry (wheel rectangles of ± c along, ± 0.2 c across each wheel,
the nose c ahead of the front-most wheel's edge).
"""
import math

import numpy as np
import pytest
from robotica_kin.marker_geometry import covariance_ellipse, ellipse_polygon, vehicle_outline
from robotica_kin.mobile.vehicles import VEHICLE_TYPES, VehicleGeometry


def _covariance(sigma1, sigma2, angle):
    c, s = math.cos(angle), math.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return R @ np.diag([sigma1 ** 2, sigma2 ** 2]) @ R.T


@pytest.mark.parametrize('sigma1, sigma2, angle, k', [
    (2.0, 0.5, 0.3, 2.0), (1.0, 0.1, -1.2, 1.0), (0.3, 0.2, 1.5, 3.0),
    (3.0, 1.0, 2.0, 1.0),          # the same axis as 2 - pi
    (1.0, 0.5, -2.5, 2.0),         # the same axis as -2.5 + pi
    (1e-3, 1e-4, 0.7, 2.0),        # millimetres
])
def test_ellipse_of_a_covariance_built_from_its_axes(sigma1, sigma2, angle, k):
    a, b, theta = covariance_ellipse(_covariance(sigma1, sigma2, angle), k)
    expected = (angle + math.pi / 2.0) % math.pi - math.pi / 2.0   # the axis in (-pi/2, pi/2]
    assert (a, b) == pytest.approx((k * sigma1, k * sigma2), rel=1e-12)
    assert theta == pytest.approx(expected, abs=1e-9)
    assert -math.pi / 2.0 < theta <= math.pi / 2.0


def test_ellipse_points_are_at_k_sigma():
    sigma = _covariance(2.0, 0.5, 0.3)
    k = 2.0
    points = ellipse_polygon(*covariance_ellipse(sigma, k), n=32)
    assert points.shape == (33, 2)
    assert np.array_equal(points[0], points[-1])
    mahalanobis = np.einsum('ij,jk,ik->i', points, np.linalg.inv(sigma), points)
    np.testing.assert_allclose(mahalanobis, k ** 2, rtol=1e-12)


def test_circle_and_zero_covariance():
    assert covariance_ellipse(np.eye(2) * 0.25, 2.0) == (1.0, 1.0, 0.0)
    assert covariance_ellipse(np.zeros((2, 2))) == (0.0, 0.0, 0.0)   # dead reckoning at start
    a, b, theta = covariance_ellipse([[1.0, 0.0], [0.0, 0.0]])   # degenerate: a segment
    assert (a, b, theta) == (1.0, 0.0, 0.0)


@pytest.mark.parametrize('covariance, k, message', [
    ([[1.0, 0.0], [0.0, -1.0]], 1.0, 'positive semi-definite'),
    ([[1.0, 0.5], [0.0, 1.0]], 1.0, 'symmetric'),
    ([[1.0, 0.0], [0.0, math.nan]], 1.0, 'finite 2x2'),
    ([[1.0, 0.0, 0.0]], 1.0, 'finite 2x2'),
    (np.full((2, 2), 1e308), 10.0, 'overflows'),
    (np.eye(2), 0.0, 'k must be > 0'),
    (np.eye(2), math.inf, 'k must be finite'),
])
def test_bad_covariances_are_refused(covariance, k, message):
    with pytest.raises(ValueError, match=message):
        covariance_ellipse(covariance, k)


def _vertices(polygon):
    """Return the polygon's vertices (closure dropped) as a set of rounded tuples."""
    assert np.array_equal(polygon[0], polygon[-1])
    return {(round(x, 12), round(y, 12)) for x, y in polygon[:-1]}


def _signed_area(polygon):
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))


def test_outline_of_a_differential_vehicle():
    # Ejemplo 4.9's robot: c = 0.25 m, b = 1 m. Wheels at (0, ±0.5) cover x in [-0.25, 0.25]
    # and |y| in [0.45, 0.55]; the nose is c ahead of the wheels' front edge: (0.5, 0).
    outline = vehicle_outline('differential', VehicleGeometry(wheel_radius=0.25, track=1.0))
    assert _vertices(outline) == {(-0.25, -0.55), (0.25, -0.55), (0.5, 0.0), (0.25, 0.55),
                                  (-0.25, 0.55)}
    assert _signed_area(outline) == pytest.approx(0.5 * 1.1 + 0.25 * 1.1 / 2.0)   # CCW


def test_outline_of_a_tricycle():
    # c = 0.1, b = 0.6, l = 1: rear wheels at (0, ±0.3) cover x in [-0.1, 0.1], |y| in
    # [0.28, 0.32]; the front wheel at (1, 0) covers x in [0.9, 1.1], |y| <= 0.02; nose (1.2, 0).
    # The front wheel's outer corners (1.1, ±0.02) lie inside the segment (0.1, ±0.32)-(1.2, 0):
    # at x = 1.1 it is at |y| = 0.32 (1 - 1/1.1) = 0.029 > 0.02.
    geometry = VehicleGeometry(wheel_radius=0.1, track=0.6, wheelbase=1.0)
    outline = vehicle_outline('tricycle', geometry)
    assert _vertices(outline) == {(-0.1, -0.32), (0.1, -0.32), (1.2, 0.0), (0.1, 0.32),
                                  (-0.1, 0.32)}
    assert _signed_area(outline) > 0.0


def test_outline_of_an_ackermann_vehicle():
    # Front wheels at (l, ±b/2) = (0.5, ±0.2) with c = 0.1: their outer corners (0.6, ±0.22).
    outline = vehicle_outline('ackermann')
    assert _vertices(outline) == {(-0.1, -0.22), (0.6, -0.22), (0.7, 0.0), (0.6, 0.22),
                                  (-0.1, 0.22)}


@pytest.mark.parametrize('vehicle_type', VEHICLE_TYPES)
def test_every_outline_is_convex_counter_clockwise_and_holds_its_wheel_centres(vehicle_type):
    geometry = VehicleGeometry()
    outline = vehicle_outline(vehicle_type, geometry)
    edges = np.diff(outline, axis=0)
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    assert np.all(turns > 0.0)   # every corner turns left: convex, counter-clockwise
    assert outline[:, 0].max() > 0.0 and outline[:, 0].min() < 0.0
    centre = (0.0, 0.0) if vehicle_type not in ('tricycle', 'bicycle', 'ackermann') else (
        0.5 * geometry.wheelbase, 0.0)
    inward = (outline[1:] - outline[:-1])[:, ::-1] * [-1.0, 1.0]   # left normals
    assert np.all(np.sum(inward * (np.array(centre) - outline[:-1]), axis=1) > 0.0)


def test_unknown_vehicle_is_refused():
    with pytest.raises(ValueError, match='unknown vehicle type'):
        vehicle_outline('hovercraft')
