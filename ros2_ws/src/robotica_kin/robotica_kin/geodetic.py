"""
WGS-84 geodetic, ECEF and local ENU coordinates, for GPS fixes (book §7.7.5, seed catalog §5.7).

The book's GPS solves the pseudorange equations (7.15) for the receiver's Cartesian position
(U_X, U_Y, U_Z) in an Earth-centred, Earth-fixed (ECEF) frame; a receiver reports it as
geodetic latitude φ, longitude λ and height h above the WGS-84 ellipsoid, as
``sensor_msgs/NavSatFix`` does. A robot works in a local east-north-up (ENU) frame (REP-103,
REP-105 ``map``) tangent to the ellipsoid at an origin. The conversions:

* geodetic -> ECEF (closed form): with the prime-vertical radius
  N(φ) = a / sqrt(1 - e² sin² φ),
  X = (N + h) cos φ cos λ, Y = (N + h) cos φ sin λ, Z = (N (1 - e²) + h) sin φ.
* ECEF -> geodetic: Bowring's (1976) iteration on the parametric latitude β,
  tan φ = (Z + e'² b sin³ β) / (p - e² a cos³ β), tan β = (1 - f) tan φ, p = sqrt(X² + Y²),
  then h = p cos φ + Z sin φ - a² / N(φ), well conditioned at the poles and the equator. It
  converges to < 1e-14 rad in two or three passes for any point outside the Earth's central
  ~50 km (inside it, where several ellipsoid normals pass through a point, it still returns
  one of them).
* ECEF <-> ENU at an origin (φ0, λ0, h0): rows of R are the unit vectors east
  (-sin λ0, cos λ0, 0), north (-sin φ0 cos λ0, -sin φ0 sin λ0, cos φ0) and up
  (cos φ0 cos λ0, cos φ0 sin λ0, sin φ0); enu = R (ecef - ecef0).

Latitude and longitude are in **degrees at the API boundary** (as in NavSatFix; ``unit='rad'``
switches to radians) and radians inside; heights and coordinates are in metres. Every function
broadcasts over arrays of points; scalar input gives Python floats (geodetic) or a (3,) vector
(ECEF, ENU), array input of shape S gives arrays of shape S or S + (3,).
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real
from robotica_kin.parameter_specs import ParameterSpec

__all__ = [
    'ORIGIN_PARAMETERS', 'WGS84_A', 'WGS84_B', 'WGS84_E2', 'WGS84_F', 'GeodeticOrigin',
    'ecef_to_geodetic', 'geodetic_to_ecef',
]

WGS84_A = 6378137.0
"""Semi-major (equatorial) axis a of the WGS-84 ellipsoid [m] (defining constant)."""

WGS84_F = 1.0 / 298.257223563
"""Flattening f = (a - b) / a of the WGS-84 ellipsoid [-] (defining constant)."""

WGS84_B = WGS84_A * (1.0 - WGS84_F)
"""Semi-minor (polar) axis b = a (1 - f) of the WGS-84 ellipsoid [m], about 6356752.3142 m."""

WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
"""First eccentricity squared e² = f (2 - f) = (a² - b²) / a² [-]."""

_EP2 = WGS84_E2 / (1.0 - WGS84_E2)  # second eccentricity squared e'² = (a² - b²) / b²
_UNITS = ('deg', 'rad')
_MAX_ITERATIONS = 10  # Bowring passes; two or three suffice outside the Earth's centre
_LATITUDE_TOL = 1e-14  # [rad] change of φ between passes at which the iteration stops

FloatOrArray = float | NDArray[np.float64]


def _check_unit(unit: str) -> None:
    if not isinstance(unit, str) or unit not in _UNITS:
        raise ValueError(f"unit must be 'deg' or 'rad', got {unit!r}")


def _broadcast(names: tuple[str, str, str], *values: ArrayLike) -> tuple[
        NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Return the three inputs as broadcast finite float64 arrays, or raise ValueError."""
    arrays = []
    for name, value in zip(names, values):
        try:
            array = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError) as error:
            raise ValueError(f'{name} must be a real number or array, got {value!r}') from error
        if not np.all(np.isfinite(array)):
            raise ValueError(f'{name} must be finite, got {value!r}')
        arrays.append(array)
    try:
        first, second, third = np.broadcast_arrays(*arrays)
    except ValueError as error:
        shapes = ', '.join(f'{n} {a.shape}' for n, a in zip(names, arrays))
        raise ValueError(f'shapes do not broadcast: {shapes}') from error
    return first, second, third


def _output(value: NDArray[np.float64]) -> FloatOrArray:
    """Return a 0-d array as a Python float, any other array unchanged."""
    return float(value) if value.ndim == 0 else value


def _to_ecef(phi: NDArray[np.float64], lam: NDArray[np.float64],
             h: NDArray[np.float64]) -> NDArray[np.float64]:
    """ECEF [m], shape S + (3,), of geodetic φ, λ [rad] and h [m] of shape S."""
    sin_phi, cos_phi = np.sin(phi), np.cos(phi)
    n = WGS84_A / np.sqrt(1.0 - WGS84_E2 * sin_phi**2)
    return np.stack([(n + h) * cos_phi * np.cos(lam),
                     (n + h) * cos_phi * np.sin(lam),
                     (n * (1.0 - WGS84_E2) + h) * sin_phi], axis=-1)


def _to_geodetic(x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Geodetic φ, λ [rad] and h [m] of ECEF points (Bowring's iteration)."""
    p = np.hypot(x, y)
    beta = np.arctan2(z, (1.0 - WGS84_F) * p)
    phi = np.zeros_like(p)
    for _ in range(_MAX_ITERATIONS):
        previous = phi
        phi = np.arctan2(z + _EP2 * WGS84_B * np.sin(beta)**3,
                         p - WGS84_E2 * WGS84_A * np.cos(beta)**3)
        beta = np.arctan2((1.0 - WGS84_F) * np.sin(phi), np.cos(phi))
        if np.all(np.abs(phi - previous) <= _LATITUDE_TOL):
            break
    sin_phi = np.sin(phi)
    h = p * np.cos(phi) + z * sin_phi - WGS84_A * np.sqrt(1.0 - WGS84_E2 * sin_phi**2)
    return phi, np.arctan2(y, x), h


def geodetic_to_ecef(lat: ArrayLike, lon: ArrayLike, alt: ArrayLike,
                     unit: str = 'deg') -> NDArray[np.float64]:
    """
    Return the WGS-84 ECEF position [m] of geodetic latitude, longitude and height.

    X = (N + h) cos φ cos λ, Y = (N + h) cos φ sin λ, Z = (N (1 - e²) + h) sin φ with
    N = a / sqrt(1 - e² sin² φ) (module docstring; book §7.7.5 works in these coordinates).

    Parameters
    ----------
    lat, lon : array_like
        Geodetic latitude φ in [-90, 90] and longitude λ (any finite value), positive north
        and east, in ``unit``; broadcast together with ``alt``.
    alt : array_like
        Height h [m] above the ellipsoid (NavSatFix ``altitude``).
    unit : {'deg', 'rad'}
        Unit of ``lat`` and ``lon``; degrees by default, as NavSatFix.

    Returns
    -------
    ndarray, shape S + (3,)
        (X, Y, Z) [m] in ECEF, S the broadcast shape of the inputs ((3,) for scalars).

    Raises
    ------
    ValueError
        If an input is not finite, |lat| exceeds 90° (π/2), the shapes do not broadcast or
        ``unit`` is unknown.

    Examples
    --------
    >>> geodetic_to_ecef(0.0, 0.0, 0.0)  # the equator on the prime meridian: (a, 0, 0)
    array([6378137.,       0.,       0.])
    >>> geodetic_to_ecef(90.0, 0.0, 0.0).round(6)  # the north pole: (0, 0, b)
    array([      0.      ,       0.      , 6356752.314245])

    """
    _check_unit(unit)
    phi, lam, h = _broadcast(('lat', 'lon', 'alt'), lat, lon, alt)
    if unit == 'deg':
        if np.any(np.abs(phi) > 90.0):
            raise ValueError(f'lat must be in [-90, 90] deg, got {lat!r}')
        phi, lam = np.deg2rad(phi), np.deg2rad(lam)
    elif np.any(np.abs(phi) > 0.5 * math.pi):
        raise ValueError(f'lat must be in [-pi/2, pi/2] rad, got {lat!r}')
    return _to_ecef(phi, lam, h)


def ecef_to_geodetic(x: ArrayLike, y: ArrayLike, z: ArrayLike,
                     unit: str = 'deg') -> tuple[FloatOrArray, FloatOrArray, FloatOrArray]:
    """
    Return the WGS-84 geodetic latitude, longitude and height of an ECEF position.

    Bowring's iteration (module docstring), accurate to < 1e-14 rad in latitude and < 1e-8 m
    in height for points outside the Earth's central ~50 km. On the polar axis the longitude
    is undefined and returned as 0 (atan2(0, 0)).

    Parameters
    ----------
    x, y, z : array_like
        ECEF coordinates [m], broadcast together.
    unit : {'deg', 'rad'}
        Unit of the returned latitude and longitude; degrees by default, as NavSatFix.

    Returns
    -------
    lat, lon, alt : float or ndarray
        Latitude φ in [-90, 90], longitude λ in [-180, 180] (in ``unit``) and height h [m]
        above the ellipsoid; Python floats for scalar input, arrays of the broadcast shape
        otherwise.

    Raises
    ------
    ValueError
        If an input is not finite, the shapes do not broadcast or ``unit`` is unknown.

    Examples
    --------
    >>> ecef_to_geodetic(6378237.0, 0.0, 0.0)  # 100 m above the equator on the meridian
    (0.0, 0.0, 100.0)

    """
    _check_unit(unit)
    phi, lam, h = _to_geodetic(*_broadcast(('x', 'y', 'z'), x, y, z))
    if unit == 'deg':
        phi, lam = np.rad2deg(phi), np.rad2deg(lam)
    return _output(phi), _output(lam), _output(h)


@dataclass(frozen=True)
class GeodeticOrigin:
    """
    Origin of a local ENU frame on the WGS-84 ellipsoid (e.g. REP-105 ``map`` with GPS).

    x = east, y = north, z = up (REP-103), tangent to the ellipsoid at the origin: the
    east-north plane is perpendicular to the ellipsoid normal there.

    Raises
    ------
    ValueError
        If a field is not a finite real number, the latitude is outside [-90, 90] or the
        longitude outside [-180, 180].

    Examples
    --------
    >>> origin = GeodeticOrigin(latitude_deg=37.41, longitude_deg=-6.0, altitude=10.0)
    >>> origin.geodetic_to_enu(37.41, -6.0, 12.5).round(9)  # 2.5 m straight up
    array([0. , 0. , 2.5])
    >>> lat, lon, alt = origin.enu_to_geodetic(0.0, 0.0, -10.0)  # on the ellipsoid
    >>> round(lat, 9), round(lon, 9), round(alt, 6)
    (37.41, -6.0, 0.0)

    """

    latitude_deg: float  # φ0 [deg], geodetic, positive north
    longitude_deg: float  # λ0 [deg], positive east
    altitude: float = 0.0  # h0 [m] above the WGS-84 ellipsoid (NavSatFix altitude)

    def __post_init__(self) -> None:
        latitude = finite_real('latitude_deg', self.latitude_deg)
        longitude = finite_real('longitude_deg', self.longitude_deg)
        finite_real('altitude', self.altitude)
        if not -90.0 <= latitude <= 90.0:
            raise ValueError(f'latitude_deg must be in [-90, 90], got {self.latitude_deg!r}')
        if not -180.0 <= longitude <= 180.0:
            raise ValueError(
                f'longitude_deg must be in [-180, 180], got {self.longitude_deg!r}')

    @property
    def ecef(self) -> NDArray[np.float64]:
        """ECEF position [m] of the origin, shape (3,)."""
        return geodetic_to_ecef(self.latitude_deg, self.longitude_deg, self.altitude)

    @property
    def rotation_enu_ecef(self) -> NDArray[np.float64]:
        """
        Rotation R, shape (3, 3), taking ECEF vectors to ENU: v_enu = R v_ecef.

        Its rows are the east, north and up unit vectors at the origin, in ECEF.
        """
        phi, lam = math.radians(self.latitude_deg), math.radians(self.longitude_deg)
        sin_phi, cos_phi, sin_lam, cos_lam = (
            math.sin(phi), math.cos(phi), math.sin(lam), math.cos(lam))
        return np.array([[-sin_lam, cos_lam, 0.0],
                         [-sin_phi * cos_lam, -sin_phi * sin_lam, cos_phi],
                         [cos_phi * cos_lam, cos_phi * sin_lam, sin_phi]])

    def geodetic_to_enu(self, lat_deg: ArrayLike, lon_deg: ArrayLike,
                        alt: ArrayLike) -> NDArray[np.float64]:
        """
        Return the ENU position [m] of geodetic points, relative to this origin.

        enu = R (ecef(φ, λ, h) - ecef0) (module docstring).

        Parameters
        ----------
        lat_deg, lon_deg : array_like
            Latitude in [-90, 90] and longitude [deg], broadcast together with ``alt``.
        alt : array_like
            Height [m] above the ellipsoid.

        Returns
        -------
        ndarray, shape S + (3,)
            (east, north, up) [m], S the broadcast shape of the inputs ((3,) for scalars).

        Raises
        ------
        ValueError
            As :func:`geodetic_to_ecef`.

        """
        offset = geodetic_to_ecef(lat_deg, lon_deg, alt) - self.ecef
        return offset @ self.rotation_enu_ecef.T

    def enu_to_geodetic(self, east: ArrayLike, north: ArrayLike,
                        up: ArrayLike) -> tuple[FloatOrArray, FloatOrArray, FloatOrArray]:
        """
        Return the geodetic latitude, longitude [deg] and height [m] of ENU points.

        ecef = ecef0 + Rᵀ enu, then :func:`ecef_to_geodetic`.

        Parameters
        ----------
        east, north, up : array_like
            Position [m] in the ENU frame of this origin, broadcast together.

        Returns
        -------
        lat_deg, lon_deg, alt : float or ndarray
            Latitude, longitude [deg] and height [m] above the ellipsoid; Python floats for
            scalar input, arrays of the broadcast shape otherwise.

        Raises
        ------
        ValueError
            If an input is not finite or the shapes do not broadcast.

        """
        e, n, u = _broadcast(('east', 'north', 'up'), east, north, up)
        ecef = self.ecef + np.stack([e, n, u], axis=-1) @ self.rotation_enu_ecef
        return ecef_to_geodetic(ecef[..., 0], ecef[..., 1], ecef[..., 2])


ORIGIN_PARAMETERS: dict[str, ParameterSpec] = {
    'origin.latitude': ParameterSpec(37.41, 'Latitude of the world origin [deg] (default: '
                                     'Seville)', -90.0, 90.0),
    'origin.longitude': ParameterSpec(-6.0, 'Longitude of the world origin [deg]',
                                      -180.0, 180.0),
    'origin.altitude': ParameterSpec(10.0, 'Height of the origin above the WGS-84 ellipsoid '
                                     '[m]', -1e4, 1e5),
}
"""A node's :class:`GeodeticOrigin` as parameters (the GPS emulator's, the odometry's)."""
