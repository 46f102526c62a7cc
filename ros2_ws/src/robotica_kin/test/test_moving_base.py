"""
Tests of robotica_kin.moving_base (catalog Part 3.5 Craig's RNE, §3.8 Ej. 5.1, §12.6 PUMA).

References: the fixed-base ``rne`` (zero base motion; the equivalence principle for a base
that accelerates without turning), closed forms for the point masses of Ej. 5.1 on a
turntable, Newton-Euler by hand for those point masses under any base motion (5.21), and
finite differences of a planar vehicle's motion.
"""
import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest

from reference_models import closed_form_2r
from robotica_kin.dynamics import rne
from robotica_kin.moving_base import base_motion_from_planar, rne_moving_base
from robotica_kin.robots import puma560, two_link_arm

G = 9.81
M1, M2, L1, L2 = 2.0, 1.0, 3.0, 1.0     # Ej. 5.1 numbers used throughout the book's §3.8


def _puma_with_friction():
    """PUMA dyn table with viscous and Coulomb friction, so that F(q') is exercised too."""
    table = np.array(puma560().dyn)
    table[:, 17] = 1e-3 * np.arange(1, 7)
    table[:, 18] = 0.02
    table[:, 19] = -0.03
    return table


def _rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _point_mass_2r(q, qd, qdd, omega, alpha, accel, grav, m1=M1, m2=M2, l1=L1, l2=L2):
    """
    Newton-Euler by hand for the point masses of Ej. 5.1 on a moving base.

    Acceleration of a point moving in {0} (5.21): a_P = a_0 + p'' + 2 ω × p' + α × p
    + ω × (ω × p), all in {0}. Each mass needs F = m (a_P - g); joint i (axis Z_0, through
    the origin for joint 1 and through p1 for joint 2) carries the Z moment of the forces on
    the masses beyond it.
    """
    t1, t12 = q[0], q[0] + q[1]
    w1, w12 = qd[0], qd[0] + qd[1]
    d1, d12 = qdd[0], qdd[0] + qdd[1]
    u1 = np.array([math.cos(t1), math.sin(t1), 0.0])
    n1 = np.array([-math.sin(t1), math.cos(t1), 0.0])
    u12 = np.array([math.cos(t12), math.sin(t12), 0.0])
    n12 = np.array([-math.sin(t12), math.cos(t12), 0.0])
    p1 = l1 * u1
    p2 = p1 + l2 * u12
    v1 = l1 * w1 * n1
    v2 = v1 + l2 * w12 * n12
    a1 = l1 * (d1 * n1 - w1 ** 2 * u1)
    a2 = a1 + l2 * (d12 * n12 - w12 ** 2 * u12)

    def absolute(p, v, a):
        return (accel + a + 2 * np.cross(omega, v) + np.cross(alpha, p)
                + np.cross(omega, np.cross(omega, p)))

    f1 = m1 * (absolute(p1, v1, a1) - grav)
    f2 = m2 * (absolute(p2, v2, a2) - grav)
    tau1 = np.cross(p1, f1)[2] + np.cross(p2, f2)[2]
    tau2 = np.cross(p2 - p1, f2)[2]
    return np.array([tau1, tau2])


# ---------------------------------------------------------------------------------------------
# Reduction to the fixed base


def test_zero_base_motion_equals_rne_for_the_puma():
    dyn = _puma_with_friction()
    rng = np.random.default_rng(1)
    q, qd, qdd = rng.uniform(-2, 2, (3, 5, 6))
    qd[0, 2] = 0.0      # one joint at rest: Coulomb friction 0 there
    zero = np.zeros(6)
    for grav in (None, [0.0, -9.81, 0.0], [1.0, 2.0, -3.0]):
        expected = rne(dyn, q, qd, qdd, grav)
        np.testing.assert_allclose(rne_moving_base(dyn, q, qd, qdd, zero, zero, grav),
                                   expected, atol=1e-10)
        np.testing.assert_allclose(rne_moving_base(dyn, q[2], qd[2], qdd[2], zero, zero, grav),
                                   expected[2], atol=1e-10)


@given(a=st.lists(st.floats(-20, 20), min_size=3, max_size=3),
       v=st.lists(st.floats(-5, 5), min_size=3, max_size=3),
       g=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
       seed=st.integers(0, 2 ** 16))
@settings(max_examples=25, deadline=None)
def test_equivalence_principle_puma_linear_base_acceleration(a, v, g, seed):
    # A base that does not turn and accelerates with a is the fixed base with gravity g - a
    # (Craig: v'_0 = a - g); its velocity v plays no part.
    dyn = _puma_with_friction()
    rng = np.random.default_rng(seed)
    q, qd, qdd = rng.uniform(-2, 2, (3, 6))
    base_v = np.concatenate((v, np.zeros(3)))
    base_a = np.concatenate((a, np.zeros(3)))
    np.testing.assert_allclose(rne_moving_base(dyn, q, qd, qdd, base_v, base_a, g),
                               rne(dyn, q, qd, qdd, np.subtract(g, a)), rtol=1e-9, atol=1e-9)


def test_puma_torques_do_not_depend_on_the_base_linear_velocity():
    # With the classical acceleration a as input only ω, α, a and g enter (Craig's RNE): a
    # wrong spatial/classical conversion (ω × v) would make v matter.
    dyn = puma560()
    rng = np.random.default_rng(7)
    q, qd, qdd = rng.uniform(-2, 2, (3, 6))
    w, a, alpha = rng.uniform(-2, 2, (3, 3))
    reference = rne_moving_base(dyn, q, qd, qdd, np.r_[0, 0, 0, w], np.r_[a, alpha])
    for v in rng.uniform(-5, 5, (4, 3)):
        np.testing.assert_allclose(
            rne_moving_base(dyn, q, qd, qdd, np.r_[v, w], np.r_[a, alpha]), reference,
            atol=1e-9)
    # … while the angular velocity does matter.
    assert not np.allclose(rne_moving_base(dyn, q, qd, qdd, np.zeros(6), np.r_[a, alpha]),
                           reference, atol=1e-3)


# ---------------------------------------------------------------------------------------------
# Ej. 5.1 point masses on a turntable (axis Z_0 = joint-1 axis), q fixed


@pytest.mark.parametrize('theta1, theta2, omega, alpha', [
    (0.0, 0.0, 0.0, 1.0),
    (0.3, 0.7, 2.0, 0.0),
    (-1.0, 2.5, -1.5, 0.4),
    (2.0, -1.2, 0.8, -2.0),
])
def test_ejemplo_5_1_on_a_turntable_closed_form(theta1, theta2, omega, alpha):
    # Rigid rotation about Z_0: m_i moves on a circle of radius r_i, r1 = l1,
    # r2² = l1² + l2² + 2 l1 l2 cos θ2. Joint 1 carries the Z moment of the tangential
    # forces, τ1 = α (m1 r1² + m2 r2²) (zero for constant ω: centripetal forces point at the
    # axis). Joint 2 carries the moment about p1 of m2 (α Ẑ × p2 - ω² p2):
    # τ2 = α m2 l2 (l2 + l1 cos θ2) + ω² m2 l1 l2 sin θ2. Gravity along -Z_0 loads no joint.
    _, dyn = two_link_arm(M1, M2, L1, L2)
    r2_sq = L1 ** 2 + L2 ** 2 + 2 * L1 * L2 * math.cos(theta2)
    expected = [alpha * (M1 * L1 ** 2 + M2 * r2_sq),
                alpha * M2 * L2 * (L2 + L1 * math.cos(theta2))
                + omega ** 2 * M2 * L1 * L2 * math.sin(theta2)]
    tau = rne_moving_base(dyn, [theta1, theta2], [0, 0], [0, 0], [0, 0, 0, 0, 0, omega],
                          [0, 0, 0, 0, 0, alpha])
    np.testing.assert_allclose(tau, expected, atol=1e-10)
    if alpha == 0.0:
        assert abs(tau[0]) < 1e-10


def test_ejemplo_5_1_turntable_equals_the_closed_form_with_the_table_speed_added():
    # About the joint-1 axis the table's ω and α add to θ1' and θ1'' in (5.76)-(5.77).
    qd, qdd = np.array([0.5, -1.0]), np.array([2.0, 0.3])
    omega, alpha = 1.5, -0.7
    w, dw = qd + [omega, 0.0], qdd + [alpha, 0.0]
    _, dyn = two_link_arm(M1, M2, L1, L2)
    tau = rne_moving_base(dyn, [0.4, 1.1], qd, qdd, [0, 0, 0, 0, 0, omega],
                          [0, 0, 0, 0, 0, alpha], grav=[0.0, -G, 0.0])
    np.testing.assert_allclose(tau, closed_form_2r(M1, M2, L1, L2, [0.4, 1.1], w, dw, G)[3],
                               atol=1e-10)


# ---------------------------------------------------------------------------------------------
# Any base motion: Newton-Euler by hand for the point masses


_small = st.floats(-3, 3)
_vec3 = st.lists(_small, min_size=3, max_size=3)


@given(q=st.lists(st.floats(-math.pi, math.pi), min_size=2, max_size=2),
       qd=st.lists(_small, min_size=2, max_size=2), qdd=st.lists(_small, min_size=2, max_size=2),
       v=_vec3, w=_vec3, a=_vec3, alpha=_vec3, g=_vec3)
@settings(max_examples=60, deadline=None)
def test_point_masses_match_newton_euler_by_hand(q, qd, qdd, v, w, a, alpha, g):
    _, dyn = two_link_arm(M1, M2, L1, L2)
    expected = _point_mass_2r(q, qd, qdd, np.array(w), np.array(alpha), np.array(a),
                              np.array(g))
    tau = rne_moving_base(dyn, q, qd, qdd, np.r_[v, w], np.r_[a, alpha], grav=g)
    np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-8)


def test_trajectory_rows_match_single_calls_and_a_single_base_row_broadcasts():
    dyn = puma560()
    rng = np.random.default_rng(3)
    q, qd, qdd = rng.uniform(-2, 2, (3, 4, 6))
    base_v, base_a = rng.uniform(-2, 2, (2, 4, 6))
    stacked = rne_moving_base(dyn, q, qd, qdd, base_v, base_a)
    assert stacked.shape == (4, 6)
    for k in range(4):
        np.testing.assert_allclose(
            stacked[k], rne_moving_base(dyn, q[k], qd[k], qdd[k], base_v[k], base_a[k]),
            atol=1e-12)
    shared = rne_moving_base(dyn, q, qd, qdd, base_v[1], base_a[1])
    np.testing.assert_allclose(
        shared[3], rne_moving_base(dyn, q[3], qd[3], qdd[3], base_v[1], base_a[1]), atol=1e-12)


# ---------------------------------------------------------------------------------------------
# Planar vehicle


def test_planar_vehicle_on_a_circle_has_centripetal_acceleration():
    # Constant v and ω: a circle of radius R = v / ω, acceleration v² / R towards the centre
    # (the +y side for ω > 0).
    velocity, acceleration = base_motion_from_planar(3.0, 0.5, 0.0, 0.0)
    np.testing.assert_allclose(velocity, [3.0, 0, 0, 0, 0, 0.5])
    np.testing.assert_allclose(acceleration, [0.0, 3.0 ** 2 / 6.0, 0, 0, 0, 0])
    velocity, acceleration = base_motion_from_planar(2.0, 0.0, 1.5, 0.0)
    np.testing.assert_allclose(acceleration, [1.5, 0, 0, 0, 0, 0])


@pytest.mark.parametrize('offset', [(0.0, 0.0, 0.0), (0.4, -0.2, 0.6)])
def test_planar_vehicle_matches_finite_differences(offset):
    # Vehicle with v(t) = v0 + a_t t, θ(t) = ω0 t + α t² / 2: world velocity of the reference
    # point v(t) (cos θ, sin θ); the mount point adds d/dt (R(θ) r), here by differences.
    v0, a_t, w0, alpha, t, h = 1.2, 0.8, -0.6, 0.5, 0.7, 1e-4
    r = np.array(offset)

    def theta(s):
        return w0 * s + 0.5 * alpha * s * s

    def mount(s):
        return _rotation_z(theta(s)) @ r

    def velocity_world(s):
        ref = (v0 + a_t * s) * np.array([math.cos(theta(s)), math.sin(theta(s)), 0.0])
        return ref + (mount(s + h) - mount(s - h)) / (2 * h)

    accel_world = (velocity_world(t + h) - velocity_world(t - h)) / (2 * h)
    to_body = _rotation_z(theta(t)).T
    velocity, acceleration = base_motion_from_planar(v0 + a_t * t, w0 + alpha * t, a_t, alpha,
                                                     offset=offset)
    np.testing.assert_allclose(velocity[:3], to_body @ velocity_world(t), atol=1e-6)
    np.testing.assert_allclose(acceleration[:3], to_body @ accel_world, atol=1e-5)
    np.testing.assert_allclose(velocity[3:], [0, 0, w0 + alpha * t])
    np.testing.assert_allclose(acceleration[3:], [0, 0, alpha])


def test_planar_vehicle_arrays_and_feeding_the_puma():
    v = np.array([0.0, 1.0, 2.0])
    velocity, acceleration = base_motion_from_planar(v, 0.5, [0.1, 0.2, 0.3], 0.0)
    assert velocity.shape == acceleration.shape == (3, 6)
    np.testing.assert_allclose(acceleration[:, 1], 0.5 * v)
    q = np.zeros((3, 6))
    tau = rne_moving_base(puma560(), q, q, q, velocity, acceleration)
    assert tau.shape == (3, 6) and np.isfinite(tau).all()


# ---------------------------------------------------------------------------------------------
# Bad input


@pytest.mark.parametrize('bad, message', [
    ({'base_velocity': [0, 0, 0, np.nan, 0, 0]}, 'base_velocity'),
    ({'base_acceleration': [0, 0, 0, 0, np.inf, 0]}, 'base_acceleration'),
    ({'base_velocity': [0, 0, 0, 0, 0]}, 'base_velocity'),
    ({'base_acceleration': np.zeros((2, 6))}, 'base_acceleration'),
    ({'q': [0, 0, np.nan, 0, 0, 0]}, 'q'),
    ({'qdd': [0, 0, 0]}, 'qdd'),
    ({'grav': [0, 0, np.nan]}, 'grav'),
])
def test_rne_moving_base_rejects_bad_input(bad, message):
    args = {'q': np.zeros(6), 'qd': np.zeros(6), 'qdd': np.zeros(6),
            'base_velocity': np.zeros(6), 'base_acceleration': np.zeros(6), 'grav': None}
    args.update(bad)
    with pytest.raises(ValueError, match=message):
        rne_moving_base(puma560(), **args)


def test_rne_moving_base_rejects_mismatched_rows_and_robots_without_dynamics():
    q = np.zeros((3, 6))
    with pytest.raises(ValueError, match=r'base_velocity.*\(3, 6\)'):
        rne_moving_base(puma560(), q, q, q, np.zeros((4, 6)), np.zeros(6))
    dh, _ = two_link_arm(M1, M2, L1, L2)
    with pytest.raises(ValueError, match='dyn'):
        rne_moving_base(dh, [0, 0], [0, 0], [0, 0], np.zeros(6), np.zeros(6))


@pytest.mark.parametrize('args, message', [
    ((np.nan, 0.0, 0.0, 0.0), 'v'),
    ((0.0, [0.0, np.inf], 0.0, 0.0), 'omega'),
    ((0.0, 0.0, np.zeros((2, 2)), 0.0), 'a_t'),
    (([1.0, 2.0], [1.0, 2.0, 3.0], 0.0, 0.0), 'same length'),
])
def test_base_motion_from_planar_rejects_bad_input(args, message):
    with pytest.raises(ValueError, match=message):
        base_motion_from_planar(*args)
    with pytest.raises(ValueError, match='offset'):
        base_motion_from_planar(1.0, 0.0, 0.0, 0.0, offset=[0.0, np.nan, 0.0])
