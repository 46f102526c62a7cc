"""
Contact of a simulated vehicle with the world: where a step stops, and the bumper's report.

The vehicle's footprint (a circle of radius r about ``base_link``, or a polygon (v, 2) [m] in
``base_link``) moves over one step from the pose at its start to the pose the integration
gives at its end; :func:`robotica_kin.world.queries.swept_collision` finds the fraction of the
step at first contact (x, y and θ interpolated linearly: the chord of the step's arc, within
v ω dt² / 8 of it, 5e-5 m at 1 m/s, 1 rad/s, 20 ms), exact for a circle and within its
tolerance for a polygon, so that no wall is passed however thin or fast the step
(:data:`~robotica_kin.bounds.MAX_SPEED` at the largest step period included). The vehicle is
put there and its speeds zeroed (:meth:`~robotica_sim.simulation.vehicle.VehicleSimulation.
step`).

A vehicle that touches (clearance <= :data:`CONTACT_DISTANCE`) at the start of a step stays
put unless the step takes it away: the clearance after the first :data:`PROBE_DISTANCE` of the
motion (the farthest point of the footprint moving at most that) must grow. Pushing into the
obstacle, sliding along it or turning against it keeps it where it is (turning in place is
free for a circle, which it does not move); backing away frees it, and the rest of the step is
tested as any other.

The default footprint (:func:`default_footprint`) is the outline a viewer draws
(:func:`robotica_kin.marker_geometry.vehicle_outline`, read off the vehicle's URDF): the
vehicle that stops at a wall is the one shown touching it.
"""

import math
from typing import Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.mobile.vehicles import VehicleGeometry
from robotica_kin.world.queries import Footprint, footprint_distance, swept_collision
from robotica_kin.world.raycast import cast_rays
from robotica_kin.world.shapes import validate_polygon, World

__all__ = ['CONTACT_DISTANCE', 'CONTACT_RAYS', 'PROBE_DISTANCE', 'contact_point',
           'default_footprint', 'footprint_from_parameters', 'step_fraction']

CONTACT_DISTANCE = 1e-3   # [m] a footprint this close to an obstacle touches it (the bumper)
PROBE_DISTANCE = 1e-3     # [m] motion over which a touching vehicle must move away
SWEPT_TOLERANCE = 1e-4    # [m] a polygon's contact is found within this of the obstacle
CONTACT_RAYS = 360        # rays about base_link that locate the contact point


def default_footprint(vehicle_type: str, geometry: VehicleGeometry) -> NDArray[np.float64]:
    """
    Return the vehicle's default footprint (v, 2) [m] in ``base_link``: its viewer outline.

    The convex hull of its wheels and its nose (:func:`robotica_kin.marker_geometry.
    vehicle_outline`), open (the closing vertex dropped).

    >>> default_footprint('differential', VehicleGeometry()).round(12).tolist()[:2]
    [[-0.1, -0.22], [0.1, -0.22]]
    """
    # Imported here: the outline is read off the URDF with Pinocchio, seconds of import that a
    # simulation without a world need not spend.
    from robotica_kin.marker_geometry import vehicle_outline
    return np.asarray(vehicle_outline(vehicle_type, geometry)[:-1])


def footprint_from_parameters(vehicle_type: str, geometry: VehicleGeometry, radius: float,
                              polygon: Sequence[float]) -> Footprint:
    """
    Return the footprint the simulator's ``footprint.*`` parameters describe.

    ``radius`` > 0 [m]: a circle about ``base_link``. Else ``polygon`` [x1, y1, x2, y2, ...]
    [m] in ``base_link`` when it holds 3 vertices or more; a single number (the parameter's
    default ``[0.0]``): the vehicle's outline (:func:`default_footprint`). Raises ValueError
    naming ``footprint.polygon`` for an odd count, fewer than 3 vertices or a polygon that is
    not simple, and naming ``footprint.radius`` when both are given.

    >>> footprint_from_parameters('differential', VehicleGeometry(), 0.3, [0.0])
    0.3
    >>> footprint_from_parameters('differential', VehicleGeometry(), 0.0,
    ...                           [0, 0, 1, 0, 0, 1]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    values = [float(v) for v in polygon]
    if radius > 0.0:
        if len(values) > 1:
            raise ValueError('footprint.radius and footprint.polygon are both given: set one '
                             f'(radius {radius!r}, polygon {values!r})')
        return float(radius)
    if len(values) <= 1:
        return default_footprint(vehicle_type, geometry)
    if len(values) % 2 or len(values) < 6:
        raise ValueError('footprint.polygon must be [x1, y1, x2, y2, ...] with 3 vertices or '
                         f'more [m, base_link], got {values!r}')
    return validate_polygon(np.reshape(values, (-1, 2)), 'footprint.polygon')


def _along(start: NDArray[np.float64], delta: NDArray[np.float64],
           s: float) -> NDArray[np.float64]:
    return start + s * delta


def step_fraction(world: World, footprint: Footprint, pose_from: ArrayLike,
                  pose_to: ArrayLike) -> Optional[float]:
    """
    Return the fraction in [0, 1] of a step at which the vehicle stops, or None (free step).

    The footprint moves from ``pose_from`` to ``pose_to`` (x, y, θ) [m, rad, map frame] as
    :func:`~robotica_kin.world.queries.swept_collision` moves it. A footprint that touches at
    the start (clearance <= :data:`CONTACT_DISTANCE`) moves only if the step takes it away (the
    module's docstring); else 0.0.

    >>> wall = World(walls=[[1, -1, 1, 1]])
    >>> step_fraction(wall, 0.5, [0, 0, 0], [1, 0, 0])     # contact at x = 0.5
    0.5
    >>> step_fraction(wall, 0.5, [0.5, 0, 0], [0.6, 0, 0]), step_fraction(
    ...     wall, 0.5, [0.5, 0, 0], [0.4, 0, 0])           # pushing stays; backing off frees
    (0.0, None)
    """
    start = np.asarray(pose_from, dtype=np.float64)
    end = np.asarray(pose_to, dtype=np.float64)
    delta = end - start
    delta[2] = wrap_to_pi(float(delta[2]))
    clearance = footprint_distance(world, footprint, start)
    if clearance > CONTACT_DISTANCE:
        return swept_collision(world, footprint, start, end, SWEPT_TOLERANCE)
    circle = np.ndim(footprint) == 0
    reach = 0.0 if circle else float(np.hypot(*np.asarray(footprint, dtype=float).T).max())
    bound = math.hypot(delta[0], delta[1]) + reach * abs(delta[2])
    if bound == 0.0:
        return None
    probe = min(1.0, PROBE_DISTANCE / bound)
    if footprint_distance(world, footprint, _along(start, delta, probe)) <= clearance:
        return 0.0
    if probe >= 1.0:
        return None
    rest = swept_collision(world, footprint, _along(start, delta, probe), end, SWEPT_TOLERANCE)
    return None if rest is None else probe + rest * (1.0 - probe)


def contact_point(world: World, footprint: Footprint, pose: ArrayLike
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the contact point (2,) [m] and normal (2,) (map frame) of a touching footprint.

    :data:`CONTACT_RAYS` rays from ``base_link`` (inside the footprint) meet the obstacles
    and the footprint's own boundary; the ray along which the obstacle lies nearest beyond
    the boundary gives the point (on the obstacle) and the unit normal (the obstacle's,
    facing the robot). Accurate to the rays' spacing (1°); NaN when no ray meets an obstacle.

    >>> point, normal = contact_point(World(walls=[[1, -1, 1, 1]]), 0.5, [0.5, 0, 0])
    >>> point.round(9).tolist(), normal.round(9).tolist()
    ([1.0, 0.0], [-1.0, 0.0])
    """
    p = np.asarray(pose, dtype=np.float64)
    angles = p[2] + np.linspace(-math.pi, math.pi, CONTACT_RAYS, endpoint=False)
    hits = cast_rays(world, p[:2], angles)
    if np.ndim(footprint) == 0:
        boundary = np.full(CONTACT_RAYS, float(footprint))   # type: ignore[arg-type]
    else:
        c, s = math.cos(p[2]), math.sin(p[2])
        placed = np.asarray(footprint, dtype=np.float64) @ np.array([[c, s], [-s, c]]) + p[:2]
        boundary = cast_rays(World(polygons=(placed,)), p[:2], angles).ranges
    gap = np.where(hits.hit, hits.ranges - np.nan_to_num(boundary, posinf=0.0), np.inf)
    if not np.isfinite(gap).any():
        return np.full(2, np.nan), np.full(2, np.nan)
    k = int(np.argmin(gap))
    return hits.points[k].copy(), hits.normals[k].copy()
