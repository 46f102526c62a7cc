"""
Tests of robotica_ctrl.trajectory.parabolic_blend: HEMERO parab, LSPB (book §10.6.4, §10.7).

Book values from the seed catalogue Part 8.8 (Ejemplos 10.5 and 10.6; Part 17: (10.106) is
t_b = t_f/2 - sqrt(...)/(2 q''), and the t_23 line of Ej. 10.6 uses 0,427, not 0,437). Other
references are computed here from Craig's formulas (catalogue Part 8.7).
"""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest

from robotica_ctrl.trajectory import parab


def piece_starts(interv, t0=0.0):
    return t0 + np.concatenate(([0.0], np.cumsum(interv)[:-1]))


@pytest.mark.parametrize('acc, t_b', [(30.0, 0.845), (80.0, 0.268)])
def test_ejemplo_10_5(acc, t_b):
    # Catalogue §8.8 Ej. 10.5: q0 = 10, qf = 90, tf = 4 s.
    coef, time, q_t, qd_t, qdd_t, interv = parab([10, 90], [acc, acc], 0, 4, 0.001)
    assert interv.shape == (3,) and coef.shape == (3, 3)
    assert interv[0] == pytest.approx(t_b, abs=5e-4)
    assert interv[2] == pytest.approx(t_b, abs=5e-4)
    # Exact (10.106) corrected, computed here: 0,8453 and 0,2679.
    exact = 2.0 - math.sqrt(acc**2 * 16 - 4 * acc * 80) / (2 * acc)
    np.testing.assert_allclose(interv, [exact, 4 - 2 * exact, exact], atol=1e-12)
    if acc == 30.0:
        assert interv[0] + interv[1] == pytest.approx(3.155, abs=5e-4)
    np.testing.assert_allclose(coef[:, 2], [acc / 2, 0, -acc / 2])
    assert q_t[0] == 10.0 and q_t[-1] == pytest.approx(90.0)
    assert qd_t[0] == 0.0 and qd_t[-1] == pytest.approx(0.0, abs=1e-9)
    assert qd_t.max() == pytest.approx(acc * exact)
    # Symmetric about (t_m, q_m) = (2, 50).
    assert q_t[2000] == pytest.approx(50.0)
    np.testing.assert_allclose(q_t + q_t[::-1], 100.0, atol=1e-9)
    assert set(np.unique(qdd_t)) <= {acc, 0.0, -acc}


def test_ejemplo_10_5_minimum_acceleration():
    # (10.107): q'' >= 4 (qf - q0) / tf^2 = 20; equality leaves no linear part.
    interv = parab([10, 90], 20.0, 0, 4, 0.001)[5]
    np.testing.assert_allclose(interv, [2.0, 0.0, 2.0], atol=1e-9)
    with pytest.raises(ValueError, match='20'):
        parab([10, 90], 19.0, 0, 4, 0.001)


def test_ejemplo_10_6():
    # Catalogue §8.8 Ej. 10.6: 0 -> 10 -> 5 deg, 1 s each, |q''| = 40 at the three blends.
    coef, time, q_t, qd_t, qdd_t, interv = parab([0, 10, 5], [40, 40, 40], 0, [1, 1], 0.001)
    t1, t12, t2, t23, t3 = interv
    assert t1 == pytest.approx(0.293, abs=5e-4)
    assert t3 == pytest.approx(0.134, abs=5e-4)
    assert t2 == pytest.approx(0.427, abs=5e-4)
    assert t12 == pytest.approx(0.4935, abs=5e-4)
    assert t23 == pytest.approx(0.652, abs=1e-3)  # printed truncated (0,6526)
    np.testing.assert_allclose(coef[:, 2] * 2, [40, 0, -40, 0, 40])
    v12, v23 = coef[1, 1], coef[3, 1]
    assert v12 == pytest.approx(11.72, abs=5e-3)
    assert v23 == pytest.approx(-5.36, abs=5e-3)
    # Exact values computed here from the catalogue's formulas.
    e_t1 = 1 - math.sqrt(1 - 20 / 40)
    e_v12 = 10 / (1 - e_t1 / 2)
    e_t3 = 1 - math.sqrt(1 + 2 * (5 - 10) / 40)
    e_v23 = -5 / (1 - e_t3 / 2)
    e_t2 = (e_v23 - e_v12) / -40
    np.testing.assert_allclose(
        interv, [e_t1, 1 - e_t1 - e_t2 / 2, e_t2, 1 - e_t3 - e_t2 / 2, e_t3], atol=1e-12)
    assert time[-1] == pytest.approx(2.0)
    assert q_t[0] == 0.0 and q_t[-1] == pytest.approx(5.0)
    assert qd_t[-1] == pytest.approx(0.0, abs=1e-9)
    # The via point is only approached: deviation = |dv| t2 / 8 at the blend centre t = 1 s.
    assert q_t[1000] == pytest.approx(10.0 - abs(e_v23 - e_v12) * e_t2 / 8)


def check_lspb(q, acc, tij, t0=0.0):
    """Assert Craig's LSPB properties for one joint; return the deviation at interior points."""
    coef, time, q_t, qd_t, qdd_t, interv = parab(q, acc, t0, tij, 0.001)
    n = len(q)
    tv = t0 + np.concatenate(([0.0], np.cumsum(tij)))
    starts = piece_starts(interv, t0)
    assert np.all(interv >= 0.0)
    assert np.sum(interv) == pytest.approx(np.sum(tij))
    # Rest at both ends, exactly at the end points.
    assert q_t[0] == q[0] and qd_t[0] == 0.0
    assert q_t[-1] == pytest.approx(q[-1], abs=1e-9) and qd_t[-1] == pytest.approx(0, abs=1e-9)
    # Position and velocity continuous between pieces.
    for i in range(len(interv) - 1):
        d = interv[i]
        assert coef[i, 0] + coef[i, 1] * d + coef[i, 2] * d * d == pytest.approx(
            coef[i + 1, 0], abs=1e-9)
        assert coef[i, 1] + 2 * coef[i, 2] * d == pytest.approx(coef[i + 1, 1], abs=1e-9)
    # Interior blends are centred on the via-point times; the linear pieces, extended, pass
    # through the interior via points (10.108)-(10.112); interior slopes are dq/t_d.
    for k in range(1, n - 1):
        assert starts[2 * k] + interv[2 * k] / 2 == pytest.approx(tv[k], abs=1e-9)
        for lin in (2 * k - 1, 2 * k + 1):
            assert coef[lin, 2] == 0.0
            assert coef[lin, 0] + coef[lin, 1] * (tv[k] - starts[lin]) == pytest.approx(
                q[k], abs=1e-9)
    for s in range(1, n - 2):
        assert coef[2 * s + 1, 1] == pytest.approx((q[s + 1] - q[s]) / tij[s])
    # Blend accelerations have the given magnitudes.
    for k in range(n):
        if interv[2 * k] > 0:
            assert abs(coef[2 * k, 2]) * 2 == pytest.approx(acc[k])
    dq = np.abs(np.diff(q_t))
    assert np.all(dq <= np.max(np.abs(qd_t)) * 0.001 + 1e-9)
    idx = np.round((tv[1:-1] - t0) / 0.001).astype(int)
    return np.abs(q_t[idx] - np.asarray(q)[1:-1])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=6), st.data())
def test_lspb_properties(q, data):
    tij = data.draw(st.lists(st.floats(0.5, 2.0), min_size=len(q) - 1, max_size=len(q) - 1))
    # Accelerations large enough for every segment (blends of at most ~t_d/4).
    vmax = 3 * 4.0 / 0.5
    acc = [max(4 * vmax / 0.5, 1.0)] * len(q)
    check_lspb(np.array(q), acc, np.array(tij))


def test_higher_acceleration_approaches_via_points():
    q, tij = [0.0, 1.0, -0.5, 0.5], [1.0, 1.0, 1.0]
    dev = [check_lspb(q, [a] * 4, tij, t0=0.5) for a in (10.0, 20.0, 80.0)]
    assert np.all(dev[0] > dev[1]) and np.all(dev[1] > dev[2])


def test_zero_motion_segments():
    coef, time, q_t, qd_t, qdd_t, interv = parab([1.0, 1.0, 2.0, 2.0], 10.0, 0, [1, 1, 1], 0.01)
    check_lspb([1.0, 1.0, 2.0, 2.0], [10.0] * 4, [1, 1, 1])
    assert interv[0] == 0.0 and interv[-1] == 0.0
    assert q_t[-1] == pytest.approx(2.0)
    np.testing.assert_allclose(parab([3.0, 3.0], 1.0, 0, 2, 0.1)[2], 3.0)


def test_time_spacing():
    time = parab([0, 1, 0], 50.0, 2.0, [0.5, 0.5], 0.01)[1]
    assert time[0] == 2.0 and time[-1] == pytest.approx(3.0) and time.size == 101
    np.testing.assert_allclose(np.diff(time), 0.01, atol=1e-12)


def test_multi_joint_equals_per_joint():
    q = np.array([[0.0, 1.0, -1.0], [1.0, 1.5, 0.0], [0.5, -0.5, 1.0], [2.0, 0.0, 1.0]])
    tij = [1.0, 0.8, 1.2]
    acc = np.array([20.0, 30.0, 40.0])
    coef, time, q_t, qd_t, qdd_t, interv = parab(q, acc, 0.0, tij, 0.005)
    assert coef.shape == (3, 7, 3) and interv.shape == (3, 7) and q_t.shape == (time.size, 3)
    full = parab(q, np.tile(acc, (4, 1)), 0.0, tij, 0.005)
    for j in range(3):
        one = parab(q[:, j], acc[j], 0.0, tij, 0.005)
        np.testing.assert_array_equal(coef[j], one[0])
        np.testing.assert_array_equal(interv[j], one[5])
        for k, arr in enumerate((q_t, qd_t, qdd_t)):
            np.testing.assert_array_equal(arr[:, j], one[2 + k])
        np.testing.assert_array_equal(full[0][j], one[0])


@pytest.mark.parametrize('args, match', [
    (([0, np.nan], 10, 0, [1], 0.1), 'finite'),
    (([0, 1], np.nan, 0, [1], 0.1), 'finite'),
    (([0, 1], -5.0, 0, [1], 0.1), '> 0'),
    (([0, 1], [5.0, 5.0, 5.0], 0, [1], 0.1), 'shape'),
    (([[0, 1], [1, 2]], [5.0, 5.0, 5.0], 0, [1], 0.1), 'shape'),
    (([0, 1, 2], 10, 0, [1], 0.1), 'duration'),
    (([0, 1], 10, 0, [0.0], 0.1), '> 0'),
    (([0, 1], 10, 0, [1], 0.0), 'dt'),
    (([0, 1, 0], 1.0, 0, [1, 1], 0.1), 'minimum 2'),
    (([0, 1, 0], [100.0, 100.0, 1.0], 0, [1, 1], 0.1), 'last'),
    (([0, 1, -1, 0], [50.0, 1.0, 50.0, 50.0], 0, [1, 1, 1], 0.1), 'overlap'),
    (([1.0], 10, 0, [], 0.1), '2 via points'),
])
def test_bad_input_raises(args, match):
    with pytest.raises(ValueError, match=match):
        parab(*args)


def test_small_acceleration_message_names_joint():
    with pytest.raises(ValueError, match='joint 1'):
        parab([[0, 0], [1, 10]], [10.0, 10.0], 0, [1], 0.1)
