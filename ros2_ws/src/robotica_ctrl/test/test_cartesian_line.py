"""
Tests of robotica_ctrl.trajectory.cartesian_line: straight Cartesian lines (book §10.5).

References from the seed catalogue Part 8.6: (10.86)-(10.87) position and scaled-axis
interpolation (checked where both orientations share the axis, so the book's linear K
interpolation applies directly), the (k̂, θ + n·360°) ambiguity (10.88), and Craig's problem (1):
a 2R arm with l2 < l1 cannot reach the disc of radius l1 − l2 around its base. Rotations are
checked with Rodrigues' formula written here; workspace membership by the distance to the base.
"""

import math
import re

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest
from robotica_ctrl.trajectory.cartesian_line import cartesian_line
from robotica_kin.forward_kinematics import fkine
from robotica_kin.robots import planar_rr, planar_rrr, puma560
from robotica_kin.transforms import rotz, rpy2tr, transl

PLANAR_XY = [1, 1, 0, 0, 0, 0]


def rodrigues(axis, angle):
    """Return the 3×3 rotation by angle about the unit axis."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def rotation_angle(R):
    """Return the angle in [0, π] of a 3×3 rotation, from its trace."""
    return math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))


def test_same_axis_is_books_k_interpolation():
    # (10.86)-(10.87): K_A = 0.2 z, K_B = 1.4 z, so K(s) = (0.2 + 1.2 s) z.
    T0 = transl(1.0, -2.0, 0.5) @ rotz(0.2)
    T1 = transl(3.0, 2.0, -0.5) @ rotz(1.4)
    poses = cartesian_line(T0, T1, 5)
    assert poses.shape == (5, 4, 4)
    for s, T in zip(np.linspace(0, 1, 5), poses):
        np.testing.assert_allclose(T[:3, :3], rodrigues([0, 0, 1], 0.2 + 1.2 * s), atol=1e-12)
        np.testing.assert_allclose(T[:3, 3], [1 + 2 * s, -2 + 4 * s, 0.5 - s], atol=1e-12)
        np.testing.assert_allclose(T[3], [0, 0, 0, 1])


def test_short_way_round_10_88():
    # From 170° to -170° about z the short way is 20° through 180°, not 340° back.
    poses = cartesian_line(rotz(math.radians(170)), rotz(math.radians(-170)), 5)
    np.testing.assert_allclose(poses[2][:3, :3], rodrigues([0, 0, 1], math.pi), atol=1e-12)
    steps = [rotation_angle(a[:3, :3].T @ b[:3, :3]) for a, b in zip(poses[:-1], poses[1:])]
    np.testing.assert_allclose(steps, math.radians(5.0), atol=1e-12)


def test_path_parameter_array():
    T1 = transl(2.0, 0.0, 0.0) @ rotz(1.0)
    poses = cartesian_line(np.eye(4), T1, [0.0, 0.25, 1.0])
    np.testing.assert_allclose(poses[1][:3, 3], [0.5, 0, 0])
    np.testing.assert_allclose(poses[1][:3, :3], rodrigues([0, 0, 1], 0.25), atol=1e-12)


angle = st.floats(-math.pi, math.pi)
coord = st.floats(-2.0, 2.0)


@settings(max_examples=40, deadline=None)
@given(st.tuples(coord, coord, coord, angle, angle, angle),
       st.tuples(coord, coord, coord, angle, angle, angle))
def test_geodesic_properties(a, b):
    T0 = transl(*a[:3]) @ rpy2tr(*a[3:])
    T1 = transl(*b[:3]) @ rpy2tr(*b[3:])
    m = 9
    poses = cartesian_line(T0, T1, m)
    np.testing.assert_allclose(poses[0], T0, atol=1e-9)
    np.testing.assert_allclose(poses[-1], T1, atol=1e-9)
    total = rotation_angle(T0[:3, :3].T @ T1[:3, :3])
    s = np.linspace(0, 1, m)
    for k, T in enumerate(poses):
        R = T[:3, :3]
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        np.testing.assert_allclose(T[:3, 3], T0[:3, 3] + s[k] * (T1[:3, 3] - T0[:3, 3]),
                                   atol=1e-12)
        # Geodesic: the angle travelled is s times the angle between the ends (<= π) ...
        assert rotation_angle(T0[:3, :3].T @ R) == pytest.approx(s[k] * total, abs=1e-6)
    # ... at a constant rate, about one axis fixed in the start frame.
    steps = [rotation_angle(p[:3, :3].T @ q[:3, :3]) for p, q in zip(poses[:-1], poses[1:])]
    np.testing.assert_allclose(steps, total / (m - 1), atol=1e-6)
    if 1e-3 < total < math.pi - 1e-3:
        mid = T0[:3, :3].T @ poses[m // 2][:3, :3]
        end = T0[:3, :3].T @ T1[:3, :3]
        np.testing.assert_allclose(mid @ mid, end, atol=1e-9)


def test_line_through_the_hole_of_a_2r_is_refused():
    # planar 2R l1 = 1, l2 = 0.5: reachable 0.5 <= r <= 1.5 (catalogue §8.6 problem (1)).
    robot = planar_rr(l1=1.0, l2=0.5)
    m = 21
    x = np.linspace(-1.0, 1.0, m)
    radius = np.hypot(x, 0.2)
    first = int(np.flatnonzero(radius < 0.5)[0])
    assert first == 6                     # x = -0.4, r = 0.447 (x = -0.5 has r = 0.539)
    with pytest.raises(ValueError, match=rf'point {first} of the line') as info:
        cartesian_line(transl(-1.0, 0.2, 0.0), transl(1.0, 0.2, 0.0), m, dh=robot,
                       mask=PLANAR_XY)
    residual = float(re.search(r'residual ([0-9.eE+-]+)', str(info.value)).group(1))
    # The nearest reachable point is on the circle r = 0.5: the error is at least 0.5 - r.
    assert residual >= 0.5 - radius[first] - 1e-3


def test_line_avoiding_the_hole_is_accepted():
    robot = planar_rr(l1=1.0, l2=0.5)
    # Distance of the line to the base 1.56 / |(-0.6, 1.6)| = 0.91 > 0.5, ends r < 1.5.
    T0, T1 = transl(1.2, -0.6, 0.0), transl(0.6, 1.0, 0.0)
    poses, q = cartesian_line(T0, T1, 21, dh=robot, mask=PLANAR_XY)
    assert poses.shape == (21, 4, 4) and q.shape == (21, 2)
    np.testing.assert_allclose(poses, cartesian_line(T0, T1, 21))
    np.testing.assert_allclose(fkine(robot, q)[:, :2, 3], poses[:, :2, 3], atol=1e-6)
    # Warm-started along the line: neighbouring solutions stay on one branch.
    assert np.abs(np.diff(q, axis=0)).max() < 0.3


def test_planar_3r_reproduces_full_poses():
    robot = planar_rrr(1.0, 0.8, 0.3)
    T0 = transl(1.2, -0.6, 0.0) @ rotz(-0.5)
    T1 = transl(0.6, 1.0, 0.0) @ rotz(1.5)
    poses, q = cartesian_line(T0, T1, 15, dh=robot, mask=[1, 1, 0, 0, 0, 1])
    np.testing.assert_allclose(fkine(robot, q), poses, atol=1e-5)


def test_puma560_from_a_start_configuration():
    robot = puma560()
    q_a = [0.1, -0.5, 0.6, 0.2, 0.4, -0.3]
    T0 = fkine(robot, q_a)
    T1 = fkine(robot, [0.5, -0.2, 0.3, -0.4, 0.8, 0.3])
    poses, q = cartesian_line(T0, T1, 20, dh=robot, q0=q_a)
    np.testing.assert_allclose(fkine(robot, q), poses, atol=1e-5)
    np.testing.assert_allclose(q[0], q_a, atol=1e-5)


@pytest.mark.parametrize('args, kwargs, match', [
    ((np.eye(3), np.eye(4)), {}, 'T0 must be a 4x4'),
    ((np.eye(4), np.full((4, 4), np.nan)), {}, 'T1 must be finite'),
    ((np.diag([1.0, 1.0, -1.0, 1.0]), np.eye(4)), {}, 'T0 is not a homogeneous'),
    ((np.eye(4), 2 * np.eye(4)), {}, 'T1 is not a homogeneous'),
    ((np.eye(4), np.eye(4), 1), {}, 's must be a number'),
    ((np.eye(4), np.eye(4), 2.0), {}, 's must be a number'),
    ((np.eye(4), np.eye(4), [0.0, 1.2]), {}, r'\[0, 1\]'),
    ((np.eye(4), np.eye(4), [0.0, np.nan]), {}, 'finite'),
    ((np.eye(4), np.eye(4), [[0.0, 1.0]]), {}, '1-D'),
    ((np.eye(4), np.eye(4)), {'q0': [0.0, 0.0]}, 'need dh'),
    ((np.eye(4), np.eye(4)), {'mask': PLANAR_XY}, 'need dh'),
])
def test_bad_input_raises(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        cartesian_line(*args, **kwargs)


def test_bad_robot_options_raise():
    robot = planar_rr(1.0, 0.5)
    with pytest.raises(ValueError, match='mask'):
        cartesian_line(transl(1.2, 0, 0), transl(1.0, 0.5, 0), 3, dh=robot, mask=[1, 1, 0])
    with pytest.raises(ValueError, match='q0'):
        cartesian_line(transl(1.2, 0, 0), transl(1.0, 0.5, 0), 3, dh=robot, q0=[0.0, np.nan],
                       mask=PLANAR_XY)
