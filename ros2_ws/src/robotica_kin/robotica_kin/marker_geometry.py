"""
The geometry a viewer's markers draw: a covariance ellipse and a vehicle's outline.

* The k-sigma ellipse of a planar position estimate with covariance Σ (2x2, [m²]) is the set of
  offsets p with pᵀ Σ⁻¹ p = k². With Σ = V diag(λ1, λ2) Vᵀ (λ1 >= λ2 >= 0, the columns of V
  its unit eigenvectors) its semi-axes are a = k sqrt(λ1) along the first eigenvector and
  b = k sqrt(λ2) along the second: :func:`covariance_ellipse` returns (a, b, angle of the major
  axis), :func:`ellipse_polygon` points on it.
* A vehicle's outline (:func:`vehicle_outline`) is read off the URDF that
  :func:`robotica_kin.urdf.vehicle_urdf` writes for it, so that the footprint a viewer shows is
  the vehicle it draws: each wheel (a ``continuous`` joint, turning about the y axis of its
  frame, drawn as a cylinder of radius r and width w) covers on the ground the rectangle of
  its centre ± r along the wheel frame's x axis and ± w/2 along its y axis, at zero steering;
  the outline is the convex hull of those rectangles and of a nose one wheel radius ahead of
  the front-most wheel, on the x axis of ``base_link``, so that it shows where the vehicle
  heads.

Frames: the ellipse is in the frame of the estimate (x, y of ``odom`` or ``map``), about the
estimated position; the outline is in ``base_link`` (REP-105: x forward, y left).

:data:`MARKERS_PARAMETERS` are the markers node's parameters (``robotica_sim.nodes.markers``):
the vehicle under the simulator's and the state publisher's names, the geodetic origin under the
GPS emulator's and the odometry's, and its own.
"""
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real
from robotica_kin.geodetic import ORIGIN_PARAMETERS
from robotica_kin.mobile.vehicles import VehicleGeometry
from robotica_kin.parameter_specs import ParameterSpec
from robotica_kin.urdf import ROBOT_DESCRIPTION_PARAMETERS, vehicle_urdf
from robotica_kin.urdf_kinematics import URDFKinematics
from scipy.spatial import ConvexHull

__all__ = ['MARKERS_PARAMETERS', 'covariance_ellipse', 'ellipse_polygon', 'vehicle_outline']

_SYMMETRY_TOL = 1e-9   # relative: |Σ12 - Σ21| above tol * max|Σ| is not a covariance

MARKERS_PARAMETERS: dict[str, ParameterSpec] = {
    **{name: spec for name, spec in ROBOT_DESCRIPTION_PARAMETERS.items()
       if name.startswith('vehicle.')},
    **ORIGIN_PARAMETERS,
    'publish_rate': ParameterSpec(10.0, 'Rate of the marker arrays [Hz] (of the node clock: '
                                  'simulated time with use_sim_time)', 0.1, 100.0),
    'marker_lifetime': ParameterSpec(2.0, 'Lifetime of the markers of streamed data [s]: they '
                                     'vanish when their data stops; 0: until replaced',
                                     0.0, 3600.0),
    'covariance_k': ParameterSpec(2.0, 'k of the k-sigma ellipse of the estimate (odom) '
                                  'position covariance [-]', 0.1, 10.0),
    'gps_history': ParameterSpec(100, 'GPS fixes drawn: the newest ones', 1, 10000),
    'line_width': ParameterSpec(0.02, 'Width of the lines [m]; points and the target are '
                                'drawn at a few widths', 1e-4, 10.0),
    'tool_axis_length': ParameterSpec(0.1, "Length of the axes of the arm's reference tool "
                                      'pose [m]', 1e-3, 100.0),
    'world_frame_id': ParameterSpec('map', 'Frame of the GPS fixes: the local ENU frame at '
                                    'origin.*'),
    'arm_frame_id': ParameterSpec('link_0', "Frame of the arm's base, {0} (the URDF's link_0)"),
}
"""The markers node's parameters: the vehicle (its footprint), the GPS origin, its own."""


def covariance_ellipse(covariance: ArrayLike, k: float = 1.0) -> tuple[float, float, float]:
    """
    Return the k-sigma ellipse (a, b [m], angle [rad]) of a 2x2 position covariance [m²].

    a >= b are the semi-axes k sqrt(λ1), k sqrt(λ2) of the eigenvalues λ1 >= λ2 of Σ; angle
    is the major axis' direction from the x axis, in (-π/2, π/2] (0 for a circle).

    Raises
    ------
    ValueError
        For a matrix that is not 2x2, finite, symmetric and positive semi-definite (within
        rounding), or k not finite and > 0.

    Examples
    --------
    >>> a, b, angle = covariance_ellipse([[4.0, 0.0], [0.0, 1.0]], k=2.0)
    >>> float(a), float(b), float(angle)
    (4.0, 2.0, 0.0)
    >>> covariance_ellipse([[1.0, 2.0], [2.0, 1.0]])
    Traceback (most recent call last):
    ...
    ValueError: the covariance must be positive semi-definite, its eigenvalues are [-1.0, 3.0]

    """
    if not finite_real('k', k) > 0.0:
        raise ValueError(f'k must be > 0, got {k!r}')
    sigma = np.asarray(covariance, dtype=np.float64)
    if sigma.shape != (2, 2) or not np.isfinite(sigma).all():
        raise ValueError(f'the covariance must be a finite 2x2 matrix, got {sigma.tolist()}')
    scale = float(np.abs(sigma).max())
    if abs(sigma[0, 1] - sigma[1, 0]) > _SYMMETRY_TOL * scale:
        raise ValueError(f'the covariance must be symmetric, got {sigma.tolist()}')
    eigenvalues, eigenvectors = np.linalg.eigh(0.5 * sigma + 0.5 * sigma.T)   # ascending
    if eigenvalues[0] < -_SYMMETRY_TOL * scale:
        raise ValueError(f'the covariance must be positive semi-definite, its eigenvalues are '
                         f'{eigenvalues.tolist()}')
    minor, major = np.sqrt(np.maximum(eigenvalues, 0.0)) * k
    if not math.isfinite(major):
        raise ValueError(f'the {k}-sigma ellipse of {sigma.tolist()} overflows')
    angle = math.atan2(eigenvectors[1, 1], eigenvectors[0, 1]) if major > minor else 0.0
    if angle <= -math.pi / 2.0:
        angle += math.pi
    elif angle > math.pi / 2.0:
        angle -= math.pi
    return float(major), float(minor), angle


def ellipse_polygon(a: float, b: float, angle: float, n: int = 64) -> NDArray[np.float64]:
    """
    Return n + 1 points (closed: the last is the first) of an ellipse about the origin [m].

    Semi-axes ``a`` along the direction ``angle`` [rad] from x and ``b`` across it:
    p(t) = R(angle) (a cos t, b sin t), t = 2π i / n; shape (n + 1, 2).

    >>> ellipse_polygon(2.0, 1.0, 0.0, n=4).round(12).tolist()
    [[2.0, 0.0], [0.0, 1.0], [-2.0, 0.0], [-0.0, -1.0], [2.0, 0.0]]
    """
    if n < 3:
        raise ValueError(f'n must be >= 3 points, got {n!r}')
    t = np.linspace(0.0, 2.0 * math.pi, n + 1)
    t[-1] = 0.0   # exactly closed
    c, s = math.cos(angle), math.sin(angle)
    x, y = a * np.cos(t), b * np.sin(t)
    return np.column_stack([c * x - s * y, s * x + c * y])


def vehicle_outline(vehicle_type: str,
                    geometry: VehicleGeometry | None = None) -> NDArray[np.float64]:
    """
    Return the outline of a vehicle in ``base_link`` [m]: a closed counter-clockwise polygon.

    The convex hull of the wheels' ground rectangles and the nose (module docstring), as
    ``(m + 1, 2)`` points, the last equal to the first.

    Raises
    ------
    ValueError
        As :func:`robotica_kin.urdf.vehicle_urdf` (an unknown type, a bad geometry).

    Examples
    --------
    >>> vehicle_outline('differential').round(12).tolist()   # c = 0.1, b = 0.4, wheels 0.04
    [[-0.1, -0.22], [0.1, -0.22], [0.2, 0.0], [0.1, 0.22], [-0.1, 0.22], [-0.1, -0.22]]

    """
    urdf = vehicle_urdf(vehicle_type, geometry)
    kinematics = URDFKinematics(urdf)
    zero = np.zeros(len(kinematics.joint_names))
    parents = {t.child: t for t in (*kinematics.fixed, *kinematics.moving(zero))}
    root = ElementTree.fromstring(urdf)
    corners = []
    radii = []
    for joint in root.iter('joint'):
        if joint.get('type') != 'continuous':
            continue
        link = joint.find('child').get('link')   # type: ignore[union-attr]
        cylinder = root.find(f"link[@name='{link}']/visual/geometry/cylinder")
        radius = float(cylinder.get('radius'))   # type: ignore[union-attr, arg-type]
        width = float(cylinder.get('length'))    # type: ignore[union-attr, arg-type]
        T = np.eye(4)   # the wheel frame in base_link, composed up the tree
        while link in parents:
            T = parents[link].T @ T
            link = parents[link].parent
        for along in (-radius, radius):
            for across in (-0.5 * width, 0.5 * width):
                corners.append(T[:2, 3] + along * T[:2, 0] + across * T[:2, 1])
        radii.append(radius)
    points = np.array(corners)
    nose = [float(points[:, 0].max()) + max(radii), 0.0]
    points = np.vstack([points, nose])
    hull = points[ConvexHull(points).vertices]   # counter-clockwise in 2-D
    start = np.lexsort((hull[:, 0], hull[:, 1]))[0]   # the lowest, then leftmost vertex
    hull = np.roll(hull, -start, axis=0)
    return np.vstack([hull, hull[:1]])
