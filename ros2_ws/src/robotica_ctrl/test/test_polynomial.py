"""
Tests of robotica_ctrl.trajectory.polynomial: HEMERO pol3 / pol5 (book §10.3.1, §10.6).

Book values from the seed catalogue Part 8.8 (Ejemplos 10.1-10.4, with the Part 17 corrections:
Ej. 10.1 a3 = -2,5; Ej. 10.2 qd = [2 4 1], tij = [2 4]). Other references are computed here
independently by solving the boundary-condition linear systems.
"""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest

from robotica_ctrl.trajectory import pol3, pol5


def boundary_solve(p0, pf, v0, vf, T, a0=None, af=None):
    """Return polynomial coefficients (lowest first) solving the end conditions directly."""
    order = 3 if a0 is None else 5

    def row(t, deriv):
        r = np.zeros(order + 1)
        for k in range(deriv, order + 1):
            r[k] = math.factorial(k) / math.factorial(k - deriv) * t ** (k - deriv)
        return r

    rows = [row(0.0, 0), row(T, 0), row(0.0, 1), row(T, 1)]
    rhs = [p0, pf, v0, vf]
    if a0 is not None:
        rows += [row(0.0, 2), row(T, 2)]
        rhs += [a0, af]
    return np.linalg.solve(np.array(rows), np.array(rhs))


def poly_at(c, t, deriv=0):
    """Evaluate derivative ``deriv`` of the polynomial with coefficients c (lowest first)."""
    return np.polyval(np.polyder(np.asarray(c)[::-1], deriv), t) if deriv else \
        np.polyval(np.asarray(c)[::-1], t)


def test_ejemplo_10_1():
    # Catalogue §8.8 Ej. 10.1 (printed a3 = 2,5 has lost its sign: -2,5, Part 17).
    coef, time, q_t, qd_t, qdd_t = pol3([10, 90], [0, 0], 0, 4, 0.001)
    assert coef.shape == (1, 4)
    np.testing.assert_allclose(coef[0], [10.0, 0.0, 15.0, -2.5], atol=1e-12)
    assert time.shape == (4001,)
    np.testing.assert_allclose(q_t, 10 + 15 * time**2 - 2.5 * time**3, atol=1e-9)
    np.testing.assert_allclose(qd_t, 30 * time - 7.5 * time**2, atol=1e-9)
    np.testing.assert_allclose(qdd_t, 30 - 15 * time, atol=1e-9)
    i2 = 2000
    assert time[i2] == pytest.approx(2.0)
    assert q_t[i2] == pytest.approx(50.0)
    assert qd_t[i2] == pytest.approx(30.0)
    assert qd_t.max() == pytest.approx(30.0)
    assert qdd_t[0] == pytest.approx(30.0)
    assert qdd_t[-1] == pytest.approx(-30.0)


def test_ejemplo_10_2():
    # Catalogue §8.8 Ej. 10.2, with the MATLAB call's qd = [2 4 1], tij = [2 4].
    coef, time, q_t, qd_t, qdd_t = pol3([10, 5, 20], [2, 4, 1], 0, [2, 4], 0.001)
    np.testing.assert_allclose(coef, [[10, 2, -7.75, 2.75], [5, 4, 0.5625, -0.15625]],
                               atol=1e-12)
    assert time[-1] == pytest.approx(6.0)
    i_via = 2000
    assert q_t[i_via] == pytest.approx(5.0)
    assert qd_t[i_via] == pytest.approx(4.0)
    # Acceleration discontinuous at the via point (fig. 10.11): 2 a12 + 6 a13 T vs 2 a22.
    left = poly_at(coef[0], 2.0, 2)
    assert left == pytest.approx(2 * -7.75 + 6 * 2.75 * 2)
    assert qdd_t[i_via] == pytest.approx(2 * 0.5625)
    assert abs(left - qdd_t[i_via]) > 1.0


def test_ejemplo_10_3():
    # Catalogue §8.8 Ej. 10.3.
    coef, time, q_t, qd_t, qdd_t = pol5([10, 90], [0, 0], [10, 30], 0, 4, 0.001)
    np.testing.assert_allclose(coef[0], [10, 0, 5, 12.5, -5.625, 0.625], atol=1e-12)
    assert q_t[0] == pytest.approx(10.0)
    assert q_t[-1] == pytest.approx(90.0)
    assert qd_t[-1] == pytest.approx(0.0, abs=1e-9)
    assert qdd_t[0] == pytest.approx(10.0)
    assert qdd_t[-1] == pytest.approx(30.0)


def test_ejemplo_10_4():
    # Catalogue §8.8 Ej. 10.4, printed to 4 decimals (exact -0,65625, -0,019531, 0,013672).
    coef, time, q_t, qd_t, qdd_t = pol5([10, 5, 20], [2, 4, 1], [1, 4, 2], 0, [2, 4], 0.001)
    np.testing.assert_allclose(coef[0], [10, 2, 0.5, -13, 9.5625, -1.875], atol=5e-5)
    np.testing.assert_allclose(coef[1], [5, 4, 2, -0.6563, -0.0195, 0.0137], atol=5e-5)
    np.testing.assert_allclose(coef[1, 3:], [-0.65625, -0.019531, 0.013672], atol=5e-7)
    # Continuous acceleration at the via point (fig. 10.14).
    assert poly_at(coef[0], 2.0, 2) == pytest.approx(4.0)
    assert qdd_t[2000] == pytest.approx(4.0)


def test_rest_to_rest_cubic_10_89():
    # Catalogue §8.7 (10.89)-(10.90): a1 = 0, a2 = 3 dq / tf^2, a3 = -2 dq / tf^3.
    q0, qf, tf = -0.4, 1.3, 2.5
    coef = pol3([q0, qf], [0, 0], 1.0, [tf], 0.01)[0]
    np.testing.assert_allclose(
        coef[0], [q0, 0, 3 * (qf - q0) / tf**2, -2 * (qf - q0) / tf**3], atol=1e-12)


def test_two_cubics_continuous_acceleration_10_93():
    # Catalogue §8.7 (10.93)-(10.99): with the via velocity 3 (qf - q0) / (4 tf), two cubics
    # from and to rest have continuous acceleration and the printed coefficients.
    q0, qv, qf, tf = 0.2, 1.1, -0.5, 1.5
    vv = (3 * qf - 3 * q0) / (4 * tf)
    coef = pol3([q0, qv, qf], [0, vv, 0], 0, [tf, tf], 0.01)[0]
    expected = [
        [q0, 0, (12 * qv - 3 * qf - 9 * q0) / (4 * tf**2),
         (-8 * qv + 3 * qf + 5 * q0) / (4 * tf**3)],
        [qv, vv, (-12 * qv + 6 * qf + 6 * q0) / (4 * tf**2),
         (8 * qv - 5 * qf - 3 * q0) / (4 * tf**3)],
    ]
    np.testing.assert_allclose(coef, expected, atol=1e-12)
    assert poly_at(coef[0], tf, 2) == pytest.approx(poly_at(coef[1], 0.0, 2))


vals = st.floats(-3.0, 3.0)
durs = st.floats(0.2, 3.0)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(vals, vals, vals), min_size=2, max_size=5), st.data())
def test_boundary_conditions_and_coefficients(points, data):
    q, qd, qdd = (np.array(c) for c in zip(*points))
    tij = np.array(data.draw(st.lists(durs, min_size=q.size - 1, max_size=q.size - 1)))
    c3 = pol3(q, qd, 0.0, tij, 0.05)[0]
    c5 = pol5(q, qd, qdd, 0.0, tij, 0.05)[0]
    for i, T in enumerate(tij):
        np.testing.assert_allclose(c3[i], boundary_solve(q[i], q[i + 1], qd[i], qd[i + 1], T),
                                   atol=1e-8)
        np.testing.assert_allclose(
            c5[i], boundary_solve(q[i], q[i + 1], qd[i], qd[i + 1], T, qdd[i], qdd[i + 1]),
            atol=1e-7)
        # Each segment meets the via-point conditions at both of its ends.
        for d, target in enumerate((q, qd)):
            assert poly_at(c3[i], T, d) == pytest.approx(target[i + 1], abs=1e-8)
            assert poly_at(c3[i], 0.0, d) == pytest.approx(target[i], abs=1e-12)
        for d, target in enumerate((q, qd, qdd)):
            assert poly_at(c5[i], T, d) == pytest.approx(target[i + 1], abs=1e-7)
            assert poly_at(c5[i], 0.0, d) == pytest.approx(target[i], abs=1e-12)


def test_sampled_values_at_via_points():
    q = np.array([0.0, 1.0, -0.5, 0.25])
    qd = np.array([0.0, 0.8, -0.3, 0.0])
    qdd = np.array([0.5, 0.0, 1.0, -2.0])
    tij = np.array([1.0, 0.5, 2.0])
    t0 = 3.0
    via_idx = np.concatenate(([0], np.cumsum(np.round(tij / 0.01)).astype(int)))
    _, time, q_t, qd_t, qdd_t = pol5(q, qd, qdd, t0, tij, 0.01)
    np.testing.assert_allclose(time[via_idx], t0 + np.concatenate(([0], np.cumsum(tij))))
    np.testing.assert_allclose(q_t[via_idx], q, atol=1e-9)
    np.testing.assert_allclose(qd_t[via_idx], qd, atol=1e-9)
    np.testing.assert_allclose(qdd_t[via_idx], qdd, atol=1e-9)
    _, _, q3, qd3, _ = pol3(q, qd, t0, tij, 0.01)
    np.testing.assert_allclose(q3[via_idx], q, atol=1e-9)
    np.testing.assert_allclose(qd3[via_idx], qd, atol=1e-9)


def test_time_spacing():
    time = pol3([0, 1, 2], [0, 0, 0], -1.0, [0.3, 0.7], 0.001)[1]
    assert time[0] == -1.0
    assert time[-1] == pytest.approx(0.0, abs=1e-12)
    assert time.size == 1001
    np.testing.assert_allclose(np.diff(time), 0.001, atol=1e-12)
    # Total not a multiple of dt: the end is still sampled, the last step is shorter.
    time = pol3([0, 1], [0, 0], 0.0, [1.05], 0.1)[1]
    assert time[-1] == pytest.approx(1.05)
    np.testing.assert_allclose(np.diff(time)[:-1], 0.1, atol=1e-12)
    assert np.diff(time)[-1] == pytest.approx(0.05)


def test_multi_joint_equals_per_joint():
    rng = np.random.default_rng(7)
    q, qd, qdd = rng.uniform(-2, 2, (3, 4, 3))
    tij = [0.6, 1.2, 0.9]
    c3, t3, *samples3 = pol3(q, qd, 0.5, tij, 0.01)
    c5, t5, *samples5 = pol5(q, qd, qdd, 0.5, tij, 0.01)
    assert c3.shape == (3, 3, 4) and c5.shape == (3, 3, 6)
    assert samples3[0].shape == (t3.size, 3)
    for j in range(3):
        one3 = pol3(q[:, j], qd[:, j], 0.5, tij, 0.01)
        one5 = pol5(q[:, j], qd[:, j], qdd[:, j], 0.5, tij, 0.01)
        np.testing.assert_array_equal(c3[j], one3[0])
        np.testing.assert_array_equal(c5[j], one5[0])
        for k in range(3):
            np.testing.assert_array_equal(samples3[k][:, j], one3[2 + k])
            np.testing.assert_array_equal(samples5[k][:, j], one5[2 + k])


@pytest.mark.parametrize('args, match', [
    (([0, np.nan], [0, 0], 0, [1], 0.1), 'finite'),
    (([0, 1], [0, np.nan], 0, [1], 0.1), 'finite'),
    (([0, 1], [0, 0, 0], 0, [1], 0.1), 'shape'),
    (([0, 1, 2], [0, 0, 0], 0, [1], 0.1), 'duration'),
    (([0, 1], [0, 0], 0, [0.0], 0.1), '> 0'),
    (([0, 1], [0, 0], 0, [-1.0], 0.1), '> 0'),
    (([0, 1], [0, 0], 0, [1], 0.0), 'dt'),
    (([0, 1], [0, 0], 0, [1], -0.1), 'dt'),
    (([0, 1], [0, 0], np.nan, [1], 0.1), 't0'),
    (([1.0], [0], 0, [], 0.1), '2 via points'),
    (([[[0]]], [[[0]]], 0, [], 0.1), 'shape'),
])
def test_bad_input_raises(args, match):
    with pytest.raises(ValueError, match=match):
        pol3(*args)
    q, qd, t0, tij, dt = args
    with pytest.raises(ValueError, match=match):
        pol5(q, qd, np.zeros(np.shape(q)), t0, tij, dt)


def test_pol5_bad_qdd_raises():
    with pytest.raises(ValueError, match='qdd'):
        pol5([0, 1], [0, 0], [0, 0, 0], 0, [1], 0.1)
    with pytest.raises(ValueError, match='qdd'):
        pol5([0, 1], [0, 0], [0, np.inf], 0, [1], 0.1)
