"""
Tests of robotica_kin.world.solids: primitives of §12.4.3, distances and intersection.

References: configurations with a distance known by hand (rim to rim, edge to edge, crossed
axes, ...), and brute-force sampling written here: points on the surface of each solid on
grids of known covering radius δ, so that the least sampled distance D satisfies
D - δ_A - δ_B <= distance <= D, and inside-tests of each solid written here for intersection.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest

from robotica_kin.world.solids import (
    Box, closest_point, Cylinder, Cylsphere, distance, intersect, point_distance,
    segment_segment_distance_3d, Sphere, support)
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

SQRT2 = math.sqrt(2.0)


def ring_frame(axis):
    """Return two unit vectors normal to ``axis`` and to each other."""
    u = axis / np.linalg.norm(axis)
    e1 = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return u, e1, np.cross(u, e1)


def sphere_points(center, r, step):
    """Return points on a sphere's surface and their covering radius."""
    n_lat = int(math.ceil(math.pi * r / step))
    n_lon = int(math.ceil(2.0 * math.pi * r / step))
    lat = np.linspace(-0.5 * math.pi, 0.5 * math.pi, n_lat + 1)
    lon = np.linspace(-math.pi, math.pi, n_lon, endpoint=False)
    la, lo = np.meshgrid(lat, lon)
    p = np.column_stack([np.cos(la.ravel()) * np.cos(lo.ravel()),
                         np.cos(la.ravel()) * np.sin(lo.ravel()), np.sin(la.ravel())])
    spacing = math.hypot(math.pi * r / n_lat, 2.0 * math.pi * r / n_lon)
    return center + r * p, 0.5 * spacing


def samples(solid, step=0.02):
    """Return points of the solid covering its surface, and the covering radius."""
    if isinstance(solid, Sphere):
        return sphere_points(solid.center, solid.radius, step)
    if isinstance(solid, Box):
        faces = []
        h = solid.half_extents
        for axis in range(3):
            a, b = [k for k in range(3) if k != axis]
            na, nb = (int(math.ceil(2 * h[k] / step)) + 1 for k in (a, b))
            ga, gb = np.meshgrid(np.linspace(-h[a], h[a], na), np.linspace(-h[b], h[b], nb))
            for sign in (-1.0, 1.0):
                f = np.zeros((ga.size, 3))
                f[:, axis], f[:, a], f[:, b] = sign * h[axis], ga.ravel(), gb.ravel()
                faces.append(f)
        local = np.vstack(faces)
        return solid.center + local @ solid.rotation.T, step * SQRT2 / 2
    u, e1, e2 = ring_frame(solid.end - solid.start)
    length = np.linalg.norm(solid.end - solid.start)
    r = solid.radius
    n_ax = int(math.ceil(length / step)) + 1
    n_ang = int(math.ceil(2 * math.pi * r / step))
    turns = np.linspace(-math.pi, math.pi, n_ang, endpoint=False)
    t, ang = np.meshgrid(np.linspace(0.0, 1.0, n_ax), turns)
    side = (solid.start + np.outer(t.ravel(), solid.end - solid.start)
            + r * (np.outer(np.cos(ang.ravel()), e1) + np.outer(np.sin(ang.ravel()), e2)))
    delta = 0.5 * math.hypot(length / (n_ax - 1), 2 * math.pi * r / n_ang)
    if isinstance(solid, Cylsphere):
        ends = [sphere_points(p, r, step) for p in (solid.start, solid.end)]
        return np.vstack([side, ends[0][0], ends[1][0]]), max(delta, ends[0][1])
    n_rad = int(math.ceil(r / step)) + 1
    rho, ang = np.meshgrid(np.linspace(0.0, r, n_rad), turns)
    disc = np.outer(rho.ravel() * np.cos(ang.ravel()), e1) + np.outer(
        rho.ravel() * np.sin(ang.ravel()), e2)
    caps = np.vstack([solid.start + disc, solid.end + disc])
    cap_delta = 0.5 * math.hypot(r / (n_rad - 1), 2 * math.pi * r / n_ang)
    return np.vstack([side, caps]), max(delta, cap_delta)


def inside(solid, p):
    """Return whether points (k, 3) lie in the solid: written here, one formula per kind."""
    if isinstance(solid, Sphere):
        return np.linalg.norm(p - solid.center, axis=1) <= solid.radius
    if isinstance(solid, Box):
        return (np.abs((p - solid.center) @ solid.rotation) <= solid.half_extents).all(axis=1)
    axis = solid.end - solid.start
    t = (p - solid.start) @ axis / (axis @ axis)
    if isinstance(solid, Cylinder):
        radial = np.linalg.norm(p - solid.start - np.outer(t, axis), axis=1)
        return (t >= 0.0) & (t <= 1.0) & (radial <= solid.radius)
    nearest = solid.start + np.outer(np.clip(t, 0.0, 1.0), axis)
    return np.linalg.norm(p - nearest, axis=1) <= solid.radius


def random_solid(kind, rng, spread=1.2):
    center = rng.uniform(-spread, spread, 3)
    if kind == 'sphere':
        return Sphere(center, rng.uniform(0.1, 0.6))
    if kind == 'box':
        return Box(center, rng.uniform(0.1, 0.5, 3),
                   Rotation.random(random_state=int(rng.integers(2**31))).as_matrix())
    axis = rng.normal(size=3)
    axis *= rng.uniform(0.1, 0.6) / np.linalg.norm(axis)
    solid = Cylinder if kind == 'cylinder' else Cylsphere
    return solid(center - axis, center + axis, rng.uniform(0.08, 0.4))


KINDS = ('sphere', 'cylsphere', 'box', 'cylinder')
PAIRS = [(a, b) for i, a in enumerate(KINDS) for b in KINDS[i:]]


@pytest.mark.parametrize('kinds', PAIRS, ids=['-'.join(p) for p in PAIRS])
def test_against_brute_force_sampling(kinds):
    rng = np.random.default_rng(PAIRS.index(kinds))
    apart = together = 0
    for k in range(16):
        spread = 1.2 if k % 2 else 0.4                # every other pair near: most meet
        a, b = random_solid(kinds[0], rng, spread), random_solid(kinds[1], rng, spread)
        pa, da = samples(a)
        pb, db = samples(b)
        sampled = float(cKDTree(pb).query(pa)[0].min())
        d = distance(a, b)
        assert d == pytest.approx(distance(b, a), abs=2e-9)
        meets = inside(b, pa).any() or inside(a, pb).any()
        if meets:
            together += 1
            assert d <= 1e-9 and intersect(a, b) and intersect(b, a)
        else:
            assert d <= sampled + 1e-9
            if sampled > da + db:
                apart += 1
                assert d >= sampled - da - db
                assert not intersect(a, b)
    assert apart >= 4 and together >= 4


def test_known_configurations():
    cube = Box([0, 0, 0], [0.5, 0.5, 0.5])
    turn_z = Rotation.from_euler('z', 45, degrees=True).as_matrix()
    turn_y = Rotation.from_euler('y', 45, degrees=True).as_matrix()
    cases = [
        (Sphere([0, 0, 0], 1.0), Sphere([5, 0, 0], 2.0), 2.0),
        (Cylsphere([0, 0, 0], [2, 0, 0], 0.5), Cylsphere([1, 3, 0], [4, 3, 0], 0.5), 2.0),
        (Cylsphere([-1, 0, 0], [1, 0, 0], 0.2), Cylsphere([0, -1, 2], [0, 1, 2], 0.3), 1.5),
        (Cylsphere([0, 0, 0], [1, 0, 0], 0.1), Cylsphere([3, 0, 0], [5, 0, 0], 0.1), 1.8),
        (cube, Box([3, 0, 0], [0.5, 0.5, 0.5]), 2.0),
        (cube, Box([3, 0, 0], [0.5, 0.5, 0.5], turn_z), 2.5 - 0.5 * SQRT2),   # vertex-face
        (Box([0, 0, 0], [0.5, 0.5, 0.5], turn_z), Box([3, 0, 0], [0.5, 0.5, 0.5], turn_y),
         3.0 - SQRT2),                                                      # edge-edge
        (Sphere([2, 0, 2], 0.1), Cylinder([0, 0, -1], [0, 0, 1], 1.0), SQRT2 - 0.1),  # rim
        (Sphere([0, 0, 3], 0.5), Cylinder([0, 0, -1], [0, 0, 1], 1.0), 1.5),         # cap
        (Sphere([1.2, 1.2, 1.2], 0.1), cube, math.sqrt(3) * 0.7 - 0.1),              # corner
        (Cylsphere([2, -1, 3], [2, 1, 3], 0.25), cube, math.hypot(1.5, 2.5) - 0.25),  # edge
        (Cylsphere([3, 0, -5], [3, 0, 5], 0.5), Cylinder([0, 0, 0], [0, 0, 1], 1.0), 1.5),
        (Cylinder([0, 0, 0], [0, 0, 1], 1.0), Cylinder([3, 0, 2], [3, 0, 3], 1.0), SQRT2),
        (Cylinder([0, 0, 0], [0, 0, 4], 1.0), Cylinder([3.5, 0, 1], [3.5, 0, 2], 0.5), 2.0),
        (Cylinder([-5, 0, 0], [5, 0, 0], 0.5), Cylinder([0, -5, 3], [0, 5, 3], 1.0), 1.5),
        (Cylinder([0, 0, 0], [0, 0, 1], 0.5), Cylinder([0, 0, 2], [0, 0, 3], 2.0), 1.0),
        (Cylinder([0, 0, -1], [0, 0, 1], 1.0), Box([3, 0, 0], [0.5, 0.5, 0.5]), 1.5),
        (Cylinder([0, 0, -1], [0, 0, 1], 1.0), Box([0, 0, 3], [2, 2, 0.5]), 1.5),
        (Cylinder([0, 0, -1], [0, 0, 1], 1.0), Box([3, 0, 0], [0.5, 0.5, 0.5], turn_z),
         2.0 - 0.5 * SQRT2),                                            # box edge to the side
        (Cylinder([0, 0, -1], [0, 0, 1], 1.0), Box([2.5, 0, 2.5], [0.5, 0.5, 0.5], turn_y),
         3.0 / SQRT2 - 0.5),                                            # box face to the rim
        (Cylinder([0, 0, -1], [0, 0, 1], 1.0), Box([2.5, 0, 2.5], [0.5, 0.5, 0.5]),
         SQRT2),                                                        # box edge to the rim
    ]
    for a, b, expected in cases:
        assert distance(a, b) == pytest.approx(expected, abs=2e-9), (a, b)
        assert distance(b, a) == pytest.approx(expected, abs=2e-9), (b, a)
        assert not intersect(a, b)


def test_touching_and_overlapping():
    cube = Box([0, 0, 0], [0.5, 0.5, 0.5])
    assert intersect(cube, Box([1.0, 0.2, 0.0], [0.5, 0.5, 0.5]))        # face to face
    assert not intersect(cube, Box([1.0 + 1e-6, 0.2, 0.0], [0.5, 0.5, 0.5]))
    assert intersect(cube, Cylinder([0, 0, 0.5], [0, 0, 2], 0.2))          # cap on the face
    assert intersect(Cylinder([0, 0, 0], [0, 0, 1], 1.0), Cylinder([2, 0, 0], [2, 0, 1], 1.0))
    rod = Box([0, 0, 0], [3.0, 0.1, 0.1])                                  # pierces the cube
    assert intersect(cube, rod) and distance(cube, rod) == 0.0
    tube = Cylinder([0, 0, -3], [0, 0, 3], 0.05)                           # through a cylinder
    assert intersect(Cylinder([-1, 0, 0], [1, 0, 0], 0.3), tube)
    assert distance(Cylinder([-1, 0, 0], [1, 0, 0], 0.3), tube) <= 1e-9


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), parallel=st.booleans())
def test_segment_segment_distance_against_a_fine_search(seed, parallel):
    rng = np.random.default_rng(seed)
    p0, p1, q0 = rng.uniform(-1, 1, (3, 3))
    q1 = q0 + rng.uniform(-2, 2) * (p1 - p0) if parallel else rng.uniform(-1, 1, 3)
    d = float(segment_segment_distance_3d(p0, p1, q0, q1)[0])
    s = np.linspace(0.0, 1.0, 4001)[:, None]
    points = p0 + s * (p1 - p0)
    e = q1 - q0
    t = np.clip((points - q0) @ e / (e @ e), 0.0, 1.0)[:, None]   # exact inner minimum
    searched = np.linalg.norm(points - q0 - t * e, axis=1).min()
    assert d <= searched + 1e-12
    assert d >= searched - np.linalg.norm(p1 - p0) / 8000 - 1e-12


def test_projection_and_support_are_consistent():
    rng = np.random.default_rng(5)
    for kind in KINDS:
        solid = random_solid(kind, rng)
        p = rng.uniform(-3, 3, (200, 3))
        q = closest_point(solid, p)
        assert inside(solid, q + 1e-12 * (solid_centre(solid) - q)).all()
        np.testing.assert_allclose(np.linalg.norm(p - q, axis=1), point_distance(solid, p),
                                   atol=1e-12)
        pa, _ = samples(solid, 0.05)
        for n in rng.normal(size=(20, 3)):
            point = support(solid, n)
            assert point @ n >= (pa @ n).max() - 1e-12        # no sample lies farther along n
            assert inside(solid, (point + 1e-9 * (solid_centre(solid) - point))[None]).all()


def solid_centre(solid):
    return solid.center if isinstance(solid, (Sphere, Box)) else 0.5 * (solid.start + solid.end)


def test_bad_input():
    with pytest.raises(ValueError, match='radius'):
        Sphere([0, 0, 0], 0.0)
    with pytest.raises(ValueError, match='rotation'):
        Box([0, 0, 0], [1, 1, 1], np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match='half_extents'):
        Box([0, 0, 0], [1, 0, 1])
    with pytest.raises(ValueError, match='start != end'):
        Cylinder([0, 0, 0], [0, 0, 0], 1.0)
    with pytest.raises(ValueError, match='center'):
        Sphere([0, math.nan, 0], 1.0)
    with pytest.raises(ValueError, match='tolerance'):
        distance(Sphere([0, 0, 0], 1.0), Sphere([3, 0, 0], 1.0), tolerance=0.0)
    with pytest.raises(ValueError, match='not a solid'):
        distance(Sphere([0, 0, 0], 1.0), 'box')
    assert distance(Cylsphere([0, 0, 0], [0, 0, 0], 1.0), Sphere([3, 0, 0], 1.0)) == 1.0
