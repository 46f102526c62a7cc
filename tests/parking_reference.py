"""
The parallel-parking scene and an independent swept-body check, shared by the parking tests.

The parked cars and the curb are rectangles written here, and the body swept between two
postures is the convex hull of the two footprints (SciPy's ConvexHull), tested against each
rectangle by the separating-axis theorem: geometry independent of the planner and of the
trackers it is used to check (tests of robotica_ctrl.planning.parking and of
robotica_ctrl.mobile.reversing_pure_pursuit).
"""
import math

import numpy as np
from robotica_ctrl.planning.parking import ParkingSpace, ParkingVehicle
from scipy.spatial import ConvexHull

CAR = ParkingVehicle()                                        # a1 3.6, b1 0.9, h1 2.6, c1 1.7
SLOW_STEERING = ParkingVehicle(theta_dmax=0.5)                # ρ_min 4.76 m: many manoeuvres
ROBOT = ParkingVehicle(a1=0.45, b1=0.1, h1=0.35, c1=0.3, theta_dmax=0.5, d1=0.28, r=0.05)
ORIGIN = (3.0, -1.0, 0.4)                                     # the space frame in the map


def space_for(vehicle, ratio=1.5, side='right', depth=None, margin=None):
    """Return a space with H' = ratio (a1 + b1) and a depth of 1.3 c1 (J = 2.2 m for a car)."""
    margin = 0.2 * vehicle.c1 / CAR.c1 if margin is None else margin
    depth = 2.2 * vehicle.c1 / CAR.c1 if depth is None else depth
    return ParkingSpace(ORIGIN, ratio * vehicle.length + 2 * margin, depth, side, margin)


def on_map(space, points):
    """Return space-frame points (k, 2) of a right- or left-hand space in the map frame."""
    p = np.asarray(points, dtype=float) * [1.0, 1.0 if space.side == 'right' else -1.0]
    x0, y0, heading = ORIGIN
    c, s = math.cos(heading), math.sin(heading)
    return np.column_stack([x0 + c * p[:, 0] - s * p[:, 1], y0 + s * p[:, 0] + c * p[:, 1]])


def obstacles(space, grown):
    """Return the rear car, the front car and the curb as rectangles grown by ``grown``."""
    h, j, g = space.length, space.depth, grown
    boxes = [(-6.0, -j, 0.0, 0.0), (h, -j, h + 6.0, 0.0), (-30.0, -j - 1.0, h + 30.0, -j)]
    return [on_map(space, [[x0 - g, y0 - g], [x1 + g, y0 - g], [x1 + g, y1 + g],
                           [x0 - g, y1 + g]]) for x0, y0, x1, y1 in boxes]


def footprint(vehicle, pose):
    """Return the body's corners (4, 2) at a pose of P_f (x, y, θ)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    half = 0.5 * vehicle.c1
    body = np.array([[-vehicle.b1, -half], [vehicle.a1, -half], [vehicle.a1, half],
                     [-vehicle.b1, half]])
    return pose[:2] + body @ np.array([[c, s], [-s, c]])


def separated(a, b):
    """Return whether the convex polygons a, b (vertices in order) have a separating axis."""
    for polygon in (a, b):
        edges = np.roll(polygon, -1, axis=0) - polygon
        for nx, ny in np.column_stack([-edges[:, 1], edges[:, 0]]):
            pa, pb = a @ (nx, ny), b @ (nx, ny)
            if pa.max() < pb.min() or pb.max() < pa.min():
                return True
    return False


def assert_swept_free(vehicle, path, rectangles):
    """Assert that the hull of each two consecutive footprints misses every rectangle."""
    bodies = [footprint(vehicle, pose) for pose in path]
    for k in range(len(path) - 1):
        points = np.vstack([bodies[k], bodies[k + 1]])
        hull = points[ConvexHull(points).vertices]
        for rectangle in rectangles:
            assert separated(hull, rectangle), f'segment {k} at {path[k]} meets {rectangle}'


def start_for(space, vehicle, dx2=None, behind=5.0, heading=0.0):
    """Return a start pose on the pass, ``behind`` [m] before the space, at offset dx2."""
    dx2 = 0.5 * vehicle.c1 + 0.35 * vehicle.c1 if dx2 is None else dx2
    return space.to_map([[-behind, dx2, heading]])[0]
