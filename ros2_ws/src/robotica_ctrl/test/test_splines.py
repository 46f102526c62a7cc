"""
Tests of robotica_ctrl.trajectory.splines: cubic splines (book §10.3.2) and via velocities.

References: the seed catalogue Part 8.4 (second-derivative form (10.67) and the tridiagonal
system (10.68) of the accelerations at the knots, natural or clamped ends), Part 8.7 (Craig's
via-velocity heuristic, fig. 10.12) and Part 8.8 (Ej. 10.1, with the Part 17 sign of a3). The
spline reference below solves the knot accelerations with a dense linear solve written here.
"""

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest

from robotica_ctrl.trajectory.polynomial import pol3
from robotica_ctrl.trajectory.splines import cubic_spline, via_velocities


def reference_spline(t, y, bc='natural', v0=0.0, vf=0.0):
    """
    Return the knot accelerations M of a cubic spline (one joint), by a dense solve.

    Interior rows: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (m_i - m_{i-1})
    with chord slopes m_i (the time form of (10.68)); natural M_0 = M_n = 0, clamped
    2 h_0 M_0 + h_0 M_1 = 6 (m_0 - v0) and h_{n-1} M_{n-1} + 2 h_{n-1} M_n = 6 (vf - m_{n-1}).
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    n = t.size
    h = np.diff(t)
    m = np.diff(y) / h
    A = np.zeros((n, n))
    b = np.zeros(n)
    for i in range(1, n - 1):
        A[i, i - 1:i + 2] = [h[i - 1], 2 * (h[i - 1] + h[i]), h[i]]
        b[i] = 6 * (m[i] - m[i - 1])
    if bc == 'natural':
        A[0, 0] = A[-1, -1] = 1.0
    else:
        A[0, :2] = [2 * h[0], h[0]]
        b[0] = 6 * (m[0] - v0)
        A[-1, -2:] = [h[-1], 2 * h[-1]]
        b[-1] = 6 * (vf - m[-1])
    return np.linalg.solve(A, b)


def reference_eval(t, y, M, time):
    """Evaluate position, velocity, acceleration with the second-derivative form (10.67)."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    i = np.clip(np.searchsorted(t, time, side='right') - 1, 0, t.size - 2)
    h = t[i + 1] - t[i]
    u = (time - t[i]) / h
    y0, y1, M0, M1 = y[i], y[i + 1], M[i], M[i + 1]
    # (10.67) on lambda = u in [0, 1], with p'' scaled by h^2 for time derivatives.
    q = (1 - u) * y0 + u * y1 + h**2 * ((-u**3 + 3 * u**2 - 2 * u) * M0 + (u**3 - u) * M1) / 6
    qd = (y1 - y0) / h + h * ((-3 * u**2 + 6 * u - 2) * M0 + (3 * u**2 - 1) * M1) / 6
    qdd = (1 - u) * M0 + u * M1
    return q, qd, qdd


def test_clamped_two_points_is_ejemplo_10_1():
    # Catalogue §8.8 Ej. 10.1 (a3 = -2,5, Part 17): q(t) = 10 + 15 t^2 - 2,5 t^3.
    coef, time, q_t, qd_t, qdd_t = cubic_spline([0, 4], [10, 90], bc='clamped')
    np.testing.assert_allclose(coef, [[10.0, 0.0, 15.0, -2.5]], atol=1e-12)
    assert time.shape == (4001,)
    np.testing.assert_allclose(q_t, 10 + 15 * time**2 - 2.5 * time**3, atol=1e-9)
    np.testing.assert_allclose(qd_t, 30 * time - 7.5 * time**2, atol=1e-9)
    np.testing.assert_allclose(qdd_t, 30 - 15 * time, atol=1e-9)


def test_natural_two_points_is_straight_line():
    coef, time, q_t, qd_t, qdd_t = cubic_spline([1, 3], [2, 6], dt=0.5)
    np.testing.assert_allclose(coef, [[2.0, 2.0, 0.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(time, [1, 1.5, 2, 2.5, 3])
    np.testing.assert_allclose(q_t, [2, 3, 4, 5, 6])
    np.testing.assert_allclose(qd_t, 2.0)
    np.testing.assert_allclose(qdd_t, 0.0, atol=1e-12)


def test_natural_three_points_by_hand():
    # t = [0 1 2], q = [0 1 0]: 4 M1 = 6 (-1 - 1) -> M1 = -3, so per segment
    # a1 = m - h (2 M_i + M_{i+1}) / 6, a2 = M_i / 2, a3 = (M_{i+1} - M_i) / (6 h).
    coef, time, q_t, qd_t, qdd_t = cubic_spline([0, 1, 2], [0, 1, 0], dt=0.5)
    np.testing.assert_allclose(coef, [[0.0, 1.5, 0.0, -0.5], [1.0, 0.0, -1.5, 0.5]],
                               atol=1e-12)
    np.testing.assert_allclose(q_t, [0, 0.6875, 1, 0.6875, 0], atol=1e-12)
    np.testing.assert_allclose(qdd_t, [0, -1.5, -3, -1.5, 0], atol=1e-12)


def test_clamped_three_points_by_hand():
    # t = [0 1 2], q = [0 1 0], rest at both ends: rows [2 1 0; 1 4 1; 0 1 2] M =
    # 6 [1, -2, 1] -> M = [6, -6, 6]; middle velocity 0 by symmetry.
    coef = cubic_spline([0, 1, 2], [0, 1, 0], bc='clamped', dt=0.5)[0]
    np.testing.assert_allclose(coef[:, 2] * 2, [6, -6], atol=1e-12)
    np.testing.assert_allclose(coef[:, 1], [0, 0], atol=1e-12)


def test_reproduces_a_cubic_polynomial():
    # A cubic through its own samples with its own end slopes is the unique clamped spline.
    c = np.array([1.0, -2.0, 0.5, 0.25])
    t = np.array([0.0, 0.7, 1.5, 3.0, 3.2])

    def poly(x, d=0):
        return np.polyval(np.polyder(c[::-1], d), x) if d else np.polyval(c[::-1], x)

    _, time, q_t, qd_t, qdd_t = cubic_spline(t, poly(t), 'clamped', poly(0.0, 1), poly(3.2, 1),
                                             dt=0.01)
    np.testing.assert_allclose(q_t, poly(time), atol=1e-10)
    np.testing.assert_allclose(qd_t, poly(time, 1), atol=1e-9)
    np.testing.assert_allclose(qdd_t, poly(time, 2), atol=1e-8)


knot_steps = st.lists(st.floats(0.2, 3.0), min_size=1, max_size=6)


@settings(max_examples=40, deadline=None)
@given(knot_steps, st.data())
def test_matches_tridiagonal_reference(steps, data):
    t = np.concatenate(([0.5], 0.5 + np.cumsum(steps)))
    n = t.size
    joints = data.draw(st.integers(1, 3))
    y = np.array(data.draw(st.lists(st.lists(st.floats(-5, 5), min_size=joints,
                                             max_size=joints), min_size=n, max_size=n)))
    bc = data.draw(st.sampled_from(['natural', 'clamped']))
    v0 = np.array(data.draw(st.lists(st.floats(-3, 3), min_size=joints, max_size=joints)))
    vf = np.array(data.draw(st.lists(st.floats(-3, 3), min_size=joints, max_size=joints)))
    kwargs = {'qd0': v0, 'qdf': vf} if bc == 'clamped' else {}
    coef, time, q_t, qd_t, qdd_t = cubic_spline(t, y, bc, dt=0.05, **kwargs)
    assert coef.shape == (joints, n - 1, 4)
    assert q_t.shape == (time.size, joints)
    for j in range(joints):
        M = reference_spline(t, y[:, j], bc, v0[j], vf[j])
        q_r, qd_r, qdd_r = reference_eval(t, y[:, j], M, time)
        np.testing.assert_allclose(q_t[:, j], q_r, atol=1e-9)
        np.testing.assert_allclose(qd_t[:, j], qd_r, atol=1e-8)
        np.testing.assert_allclose(qdd_t[:, j], qdd_r, atol=1e-7)
        # Coefficients: through the points, C2 at the interior knots, the end conditions.
        h = np.diff(t)
        a = coef[j]
        end_q = a[:, 0] + a[:, 1] * h + a[:, 2] * h**2 + a[:, 3] * h**3
        end_qd = a[:, 1] + 2 * a[:, 2] * h + 3 * a[:, 3] * h**2
        end_qdd = 2 * a[:, 2] + 6 * a[:, 3] * h
        np.testing.assert_allclose(a[:, 0], y[:-1, j], atol=1e-12)
        np.testing.assert_allclose(end_q, y[1:, j], atol=1e-9)
        np.testing.assert_allclose(end_qd[:-1], a[1:, 1], atol=1e-8)
        np.testing.assert_allclose(end_qdd[:-1], 2 * a[1:, 2], atol=1e-7)
        if bc == 'natural':
            assert abs(a[0, 2]) < 1e-9 and abs(end_qdd[-1]) < 1e-7
        else:
            assert a[0, 1] == pytest.approx(v0[j], abs=1e-9)
            assert end_qd[-1] == pytest.approx(vf[j], abs=1e-8)


def test_time_grid_and_single_joint_shapes():
    coef, time, q_t, qd_t, qdd_t = cubic_spline([0.0, 0.3, 1.0], [0, 2, 1], dt=0.25)
    assert coef.shape == (2, 4)
    np.testing.assert_allclose(time, [0, 0.25, 0.5, 0.75, 1.0])
    assert q_t.shape == qd_t.shape == qdd_t.shape == (5,)
    assert q_t[0] == 0.0 and q_t[-1] == pytest.approx(1.0)


def test_multi_joint_equals_per_joint():
    t = [0.0, 1.0, 2.5, 4.0]
    q = np.array([[0.0, 1.0], [2.0, -1.0], [1.0, 0.5], [3.0, 0.0]])
    full = cubic_spline(t, q, 'clamped', [0.5, -1.0], [0.0, 2.0], dt=0.1)
    for j, (v0, vf) in enumerate([(0.5, 0.0), (-1.0, 2.0)]):
        one = cubic_spline(t, q[:, j], 'clamped', v0, vf, dt=0.1)
        np.testing.assert_allclose(full[0][j], one[0], atol=1e-12)
        for k in range(2, 5):
            np.testing.assert_allclose(full[k][:, j], one[k], atol=1e-12)


def test_clamped_scalar_end_velocity_for_all_joints():
    q = np.array([[0.0, 1.0], [2.0, -1.0]])
    coef = cubic_spline([0, 1], q, 'clamped', 1.5, -0.5)[0]
    np.testing.assert_allclose(coef[:, 0, 1], [1.5, 1.5])


@pytest.mark.parametrize('args, kwargs, match', [
    (([0, 1], [0, np.nan]), {}, 'finite'),
    (([0, np.inf], [0, 1]), {}, 'finite'),
    (([0, 1, 2], [0, 1]), {}, 'one time per via point'),
    (([0], [0]), {}, 'at least 2'),
    (([0, 1, 1], [0, 1, 2]), {}, 'strictly increasing'),
    (([0, 2, 1], [0, 1, 2]), {}, r't\[2\]'),
    (([0, 1], [0, 1]), {'bc': 'periodic'}, 'natural'),
    (([0, 1], [0, 1]), {'qd0': 1.0}, 'clamped'),
    (([0, 1], [0, 1]), {'bc': 'clamped', 'qdf': [1.0, 2.0]}, 'qdf'),
    (([0, 1], [[0, 1], [1, 2]]), {'bc': 'clamped', 'qd0': [1.0, 2.0, 3.0]}, 'qd0'),
    (([0, 1], [0, 1]), {'bc': 'clamped', 'qd0': np.nan}, 'qd0'),
    (([0, 1], [0, 1]), {'dt': 0.0}, 'dt'),
    (([0, 1], [0, 1]), {'dt': np.nan}, 'dt'),
    (([0, 1], np.zeros((2, 2, 2))), {}, 'shape'),
])
def test_cubic_spline_bad_input_raises(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        cubic_spline(*args, **kwargs)


def reference_via_velocities(q, tij):
    """Return Craig's heuristic velocities point by point (one joint)."""
    slopes = [(q[k + 1] - q[k]) / tij[k] for k in range(len(tij))]
    v = [0.0]
    for k in range(1, len(q) - 1):
        before, after = slopes[k - 1], slopes[k]
        same_sign = (before > 0 and after > 0) or (before < 0 and after < 0)
        v.append((before + after) / 2 if same_sign else 0.0)
    return np.array(v + [0.0])


def test_via_velocities_by_hand():
    # Ej. 10.2 points and durations: slopes -2.5 and 3.75 change sign -> 0.
    np.testing.assert_allclose(via_velocities([10, 5, 20], [2, 4]), [0, 0, 0])
    # Slopes 10, 10, -30: same sign at point 1 (average 10), sign change at point 2.
    np.testing.assert_allclose(via_velocities([0, 10, 30, 0], [1, 2, 1]), [0, 10, 0, 0])
    # Slopes 2, 6, 1 (durations 1, 0.5, 2): averages 4 and 3.5.
    np.testing.assert_allclose(via_velocities([0, 2, 5, 7], [1, 0.5, 2]), [0, 4, 3.5, 0])
    # A flat segment (slope 0) gives 0.
    np.testing.assert_allclose(via_velocities([0, 1, 1, 2], [1, 1, 1]), [0, 0, 0, 0])
    # Two points: both ends at rest.
    np.testing.assert_allclose(via_velocities([3, 7], 2.0), [0, 0])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(-10, 10), st.floats(-10, 10)), min_size=2, max_size=7),
       st.data())
def test_via_velocities_property(points, data):
    q = np.array(points)
    tij = np.array(data.draw(st.lists(st.floats(0.1, 3.0), min_size=len(q) - 1,
                                      max_size=len(q) - 1)))
    v = via_velocities(q, tij)
    assert v.shape == q.shape
    for j in range(2):
        np.testing.assert_allclose(v[:, j], reference_via_velocities(q[:, j], tij), atol=1e-12)
    slopes = np.diff(q, axis=0) / tij[:, None]
    lo = np.minimum(slopes[:-1], slopes[1:])
    hi = np.maximum(slopes[:-1], slopes[1:])
    inner = v[1:-1]
    assert np.all((inner == 0) | ((inner >= lo - 1e-12) & (inner <= hi + 1e-12)))
    np.testing.assert_array_equal(v[[0, -1]], 0.0)


def test_via_velocities_feed_pol3():
    q = np.array([0.0, 10.0, 30.0, 0.0])
    tij = [1.0, 2.0, 1.0]
    qd = via_velocities(q, tij)
    coef, time, q_t, qd_t, qdd_t = pol3(q, qd, 0.0, tij, 0.001)
    for k, tk in enumerate([0.0, 1.0, 3.0, 4.0]):
        i = int(round(tk / 0.001))
        assert q_t[i] == pytest.approx(q[k], abs=1e-9)
        assert qd_t[i] == pytest.approx([0.0, 10.0, 0.0, 0.0][k], abs=1e-9)
    # Zero velocity where the slope changes sign: q = 30 is the maximum of the trajectory.
    assert q_t.max() == pytest.approx(30.0, abs=1e-9)


@pytest.mark.parametrize('args, match', [
    (([0, np.nan, 1], [1, 1]), 'finite'),
    (([0, 1, 2], [1]), 'one duration per segment'),
    (([0, 1, 2], [1, 0]), '> 0'),
    (([0, 1, 2], [1, np.nan]), '> 0'),
    (([1], [1]), 'at least 2'),
])
def test_via_velocities_bad_input_raises(args, match):
    with pytest.raises(ValueError, match=match):
        via_velocities(*args)
