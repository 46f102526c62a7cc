"""
Tests of robotica_kin.geodetic (book §7.7.5; seed catalog §5.7 and Part 15).

References are independent of the code under test: the WGS-84 defining constants, the
ellipsoid equation and its normal (a geodetic point is the foot of the ellipsoid normal plus
h along it), the meridian arc length integrated with scipy.integrate.quad from the meridian
radius of curvature M(φ), and the parallel-circle radius N(φ) cos φ.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.geodetic import ecef_to_geodetic, geodetic_to_ecef, GeodeticOrigin
from scipy.integrate import quad

# WGS-84 defining constants, restated here (NIMA TR8350.2).
A = 6378137.0  # a [m]
F = 1.0 / 298.257223563  # f [-]
B = A * (1.0 - F)  # b [m]
E2 = F * (2.0 - F)  # e² [-]

MM = 1e-3  # [m]

latitudes = st.floats(-90.0, 90.0)
longitudes = st.floats(-180.0, 180.0)
heights = st.floats(-1.0e4, 4.0e7)  # from below sea level to beyond GPS orbits [m]


def meridian_radius(phi):
    """M(φ) = a (1 - e²) / (1 - e² sin² φ)^(3/2) [m], φ in rad."""
    return A * (1.0 - E2) / (1.0 - E2 * math.sin(phi) ** 2) ** 1.5


def prime_vertical_radius(phi):
    """N(φ) = a / sqrt(1 - e² sin² φ) [m], φ in rad."""
    return A / math.sqrt(1.0 - E2 * math.sin(phi) ** 2)


def normal(lat_deg, lon_deg):
    """Outward unit normal of the ellipsoid at geodetic latitude/longitude [deg]."""
    phi, lam = math.radians(lat_deg), math.radians(lon_deg)
    return np.array([math.cos(phi) * math.cos(lam), math.cos(phi) * math.sin(lam),
                     math.sin(phi)])


def lon_difference(lon1, lon2):
    """Return the wrapped difference of two longitudes [deg], in [-180, 180)."""
    return (lon1 - lon2 + 180.0) % 360.0 - 180.0


@pytest.mark.parametrize(('lat', 'lon', 'alt', 'expected'), [
    (0.0, 0.0, 0.0, (A, 0.0, 0.0)),
    (0.0, 90.0, 0.0, (0.0, A, 0.0)),
    (0.0, 180.0, 250.0, (-(A + 250.0), 0.0, 0.0)),
    (0.0, -90.0, -40.0, (0.0, -(A - 40.0), 0.0)),
    (90.0, 0.0, 0.0, (0.0, 0.0, B)),
    (90.0, 123.0, 1000.0, (0.0, 0.0, B + 1000.0)),
    (-90.0, 0.0, 100.0, (0.0, 0.0, -(B + 100.0))),
])
def test_known_points(lat, lon, alt, expected):
    np.testing.assert_allclose(geodetic_to_ecef(lat, lon, alt), expected, rtol=0, atol=1e-6)
    lat_back, lon_back, alt_back = ecef_to_geodetic(*expected)
    assert lat_back == pytest.approx(lat, abs=1e-12)
    assert alt_back == pytest.approx(alt, abs=1e-6)
    if abs(lat) < 90.0:
        assert lon_difference(lon_back, lon) == pytest.approx(0.0, abs=1e-12)


def test_semi_minor_axis_value():
    """Check b = 6356752.3142 m, the value printed in WGS-84 tables."""
    assert geodetic_to_ecef(90.0, 0.0, 0.0)[2] == pytest.approx(6356752.3142, abs=1e-4)


@given(latitudes, longitudes, heights)
def test_ecef_is_on_the_normal_of_the_ellipsoid(lat, lon, alt):
    """P - h n lies on the ellipsoid x²/a² + y²/a² + z²/b² = 1, whose normal there is n."""
    point = geodetic_to_ecef(lat, lon, alt)
    n = normal(lat, lon)
    foot = point - alt * n
    assert (foot[0] ** 2 + foot[1] ** 2) / A**2 + foot[2] ** 2 / B**2 == pytest.approx(
        1.0, abs=1e-14)
    gradient = np.array([foot[0] / A**2, foot[1] / A**2, foot[2] / B**2])
    np.testing.assert_allclose(gradient / np.linalg.norm(gradient), n, atol=1e-12)


@given(latitudes, longitudes, heights)
def test_round_trip_geodetic_ecef_geodetic(lat, lon, alt):
    lat_back, lon_back, alt_back = ecef_to_geodetic(*geodetic_to_ecef(lat, lon, alt))
    assert abs(lat_back - lat) < 1e-9
    assert abs(alt_back - alt) < MM
    # the longitude is undefined at the poles: compare the east displacement it causes
    assert abs(lon_difference(lon_back, lon)) * math.cos(math.radians(lat)) < 1e-9


@given(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0),
       st.floats(6.0e6, 4.5e7))
def test_round_trip_ecef_geodetic_ecef(ux, uy, uz, radius):
    direction = np.array([ux, uy, uz])
    if np.linalg.norm(direction) < 1e-3:
        direction = np.array([0.0, 0.0, 1.0])
    point = radius * direction / np.linalg.norm(direction)
    lat, lon, alt = ecef_to_geodetic(*point)
    assert -90.0 <= lat <= 90.0 and -180.0 <= lon <= 180.0
    np.testing.assert_allclose(geodetic_to_ecef(lat, lon, alt), point, rtol=0, atol=MM)


def test_radians_unit():
    point = geodetic_to_ecef(0.5, -1.0, 20.0, unit='rad')
    np.testing.assert_allclose(point, geodetic_to_ecef(math.degrees(0.5), math.degrees(-1.0),
                                                       20.0), rtol=0, atol=1e-8)
    lat, lon, alt = ecef_to_geodetic(*point, unit='rad')
    assert (lat, lon, alt) == pytest.approx((0.5, -1.0, 20.0), abs=1e-12)


def test_vectorised_matches_pointwise():
    rng = np.random.default_rng(7)
    lat = rng.uniform(-90.0, 90.0, (4, 5))
    lon = rng.uniform(-180.0, 180.0, (4, 5))
    alt = rng.uniform(-100.0, 1e4, (4, 5))
    ecef = geodetic_to_ecef(lat, lon, alt)
    assert ecef.shape == (4, 5, 3)
    for index in np.ndindex(lat.shape):
        np.testing.assert_array_equal(ecef[index],
                                      geodetic_to_ecef(lat[index], lon[index], alt[index]))
    lat_back, lon_back, alt_back = ecef_to_geodetic(ecef[..., 0], ecef[..., 1], ecef[..., 2])
    assert lat_back.shape == lon_back.shape == alt_back.shape == (4, 5)
    np.testing.assert_allclose(lat_back, lat, rtol=0, atol=1e-9)
    np.testing.assert_allclose(alt_back, alt, rtol=0, atol=MM)
    # broadcasting a scalar height over arrays of positions
    assert geodetic_to_ecef(lat, lon, 0.0).shape == (4, 5, 3)
    assert isinstance(ecef_to_geodetic(A, 0.0, 0.0)[0], float)


@pytest.mark.parametrize('lat0', [-80.0, -45.0, 0.0, 10.0, 37.41, 60.0, 89.0])
def test_north_offset_is_meridian_arc(lat0):
    """
    Check that 1000 m north in the tangent plane is 1000 m of meridian arc (minus ~1e-5 m).

    The arc from φ0 to φ1 is ∫ M(φ) dφ (quad); the tangent-plane point lies above the
    ellipsoid by d²/(2 M) to first order.
    """
    origin = GeodeticOrigin(lat0, 12.5, 0.0)
    lat1, lon1, alt1 = origin.enu_to_geodetic(0.0, 1000.0, 0.0)
    assert lon1 == pytest.approx(12.5, abs=1e-12)
    arc, _ = quad(meridian_radius, math.radians(lat0), math.radians(lat1), epsabs=1e-9)
    assert arc == pytest.approx(1000.0, abs=0.01)
    assert alt1 == pytest.approx(1000.0**2 / (2.0 * meridian_radius(math.radians(lat0))),
                                 abs=MM)


@given(st.floats(-85.0, 85.0), longitudes, st.floats(-1e-5, 1e-5))
def test_east_offset_is_parallel_arc(lat0, lon0, delta_lon):
    """A point on the same parallel is N(φ) cos φ Δλ east (Δλ <= 1e-5 rad, <= 64 m)."""
    origin = GeodeticOrigin(lat0, lon0, 0.0)
    enu = origin.geodetic_to_enu(lat0, lon0 + math.degrees(delta_lon), 0.0)
    phi = math.radians(lat0)
    expected_east = prime_vertical_radius(phi) * math.cos(phi) * delta_lon
    assert enu[0] == pytest.approx(expected_east, abs=1e-6)


def test_origin_maps_to_zero_and_up_is_the_normal():
    origin = GeodeticOrigin(-33.9, 151.2, 58.0)
    np.testing.assert_allclose(origin.geodetic_to_enu(-33.9, 151.2, 58.0), 0.0, atol=1e-8)
    np.testing.assert_allclose(origin.geodetic_to_enu(-33.9, 151.2, 158.0), [0.0, 0.0, 100.0],
                               atol=1e-8)
    np.testing.assert_allclose(origin.ecef + 100.0 * normal(-33.9, 151.2),
                               geodetic_to_ecef(-33.9, 151.2, 158.0), atol=1e-8)
    rotation = origin.rotation_enu_ecef
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(rotation) == pytest.approx(1.0)  # right-handed: east x north = up


@settings(deadline=None)
@given(st.floats(-89.0, 89.0), longitudes, st.floats(-100.0, 3000.0),
       st.floats(-1e5, 1e5), st.floats(-1e5, 1e5), st.floats(-1e3, 1e4))
def test_enu_round_trip(lat0, lon0, alt0, east, north, up):
    origin = GeodeticOrigin(lat0, lon0, alt0)
    lat, lon, alt = origin.enu_to_geodetic(east, north, up)
    np.testing.assert_allclose(origin.geodetic_to_enu(lat, lon, alt), [east, north, up],
                               rtol=0, atol=MM)


def test_enu_vectorised():
    origin = GeodeticOrigin(52.0, 4.4, -2.0)
    rng = np.random.default_rng(3)
    enu = rng.uniform(-5000.0, 5000.0, (100, 3))
    lat, lon, alt = origin.enu_to_geodetic(enu[:, 0], enu[:, 1], enu[:, 2])
    assert lat.shape == lon.shape == alt.shape == (100,)
    back = origin.geodetic_to_enu(lat, lon, alt)
    assert back.shape == (100, 3)
    np.testing.assert_allclose(back, enu, rtol=0, atol=MM)
    for k in range(0, 100, 17):
        single = origin.enu_to_geodetic(*enu[k])
        assert single == pytest.approx((lat[k], lon[k], alt[k]), abs=1e-12)


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'latitude_deg': 90.5, 'longitude_deg': 0.0}, 'latitude_deg'),
    ({'latitude_deg': -91.0, 'longitude_deg': 0.0}, 'latitude_deg'),
    ({'latitude_deg': math.nan, 'longitude_deg': 0.0}, 'latitude_deg'),
    ({'latitude_deg': 0.0, 'longitude_deg': 180.5}, 'longitude_deg'),
    ({'latitude_deg': 0.0, 'longitude_deg': math.inf}, 'longitude_deg'),
    ({'latitude_deg': 0.0, 'longitude_deg': 0.0, 'altitude': math.nan}, 'altitude'),
    ({'latitude_deg': '37.4', 'longitude_deg': 0.0}, 'latitude_deg'),
    ({'latitude_deg': True, 'longitude_deg': 0.0}, 'latitude_deg'),
])
def test_origin_rejects_bad_fields(kwargs, match):
    with pytest.raises(ValueError, match=match):
        GeodeticOrigin(**kwargs)


def test_origin_is_frozen():
    origin = GeodeticOrigin(1.0, 2.0)
    with pytest.raises(AttributeError):
        origin.latitude_deg = 3.0  # type: ignore[misc]


@pytest.mark.parametrize(('call', 'match'), [
    (lambda: geodetic_to_ecef(90.001, 0.0, 0.0), 'lat'),
    (lambda: geodetic_to_ecef(1.6, 0.0, 0.0, unit='rad'), 'lat'),
    (lambda: geodetic_to_ecef(math.nan, 0.0, 0.0), 'lat'),
    (lambda: geodetic_to_ecef(0.0, math.inf, 0.0), 'lon'),
    (lambda: geodetic_to_ecef(0.0, 0.0, [0.0, math.nan]), 'alt'),
    (lambda: geodetic_to_ecef([0.0, 1.0], [0.0, 1.0, 2.0], 0.0), 'broadcast'),
    (lambda: geodetic_to_ecef(0.0, 0.0, 0.0, unit='grad'), 'unit'),
    (lambda: geodetic_to_ecef('north', 0.0, 0.0), 'lat'),
    (lambda: ecef_to_geodetic(A, math.nan, 0.0), 'y'),
    (lambda: ecef_to_geodetic(A, 0.0, 0.0, unit='degrees'), 'unit'),
    (lambda: GeodeticOrigin(0.0, 0.0).enu_to_geodetic(0.0, [1.0, 2.0], [1.0, 2.0, 3.0]),
     'broadcast'),
    (lambda: GeodeticOrigin(0.0, 0.0).enu_to_geodetic(math.nan, 0.0, 0.0), 'east'),
    (lambda: GeodeticOrigin(0.0, 0.0).geodetic_to_enu(95.0, 0.0, 0.0), 'lat'),
])
def test_rejects_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()
