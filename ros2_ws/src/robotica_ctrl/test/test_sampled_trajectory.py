"""
Tests of robotica_ctrl.trajectory.sampled_trajectory: Hermite interpolation of joint samples.

References: the rest-to-rest cubic (10.89)-(10.90) and the exact sine of Ej. 8.1 (8.47).
"""
import math

import numpy as np
import pytest
from robotica_ctrl.trajectory.sampled_trajectory import SampledTrajectory
from scipy.interpolate import BPoly


def test_cubic_rest_to_rest_matches_10_89():
    q0, qf, tf = 0.2, 1.4, 2.0
    traj = SampledTrajectory([0.0, tf], [[q0], [qf]], [[0.0], [0.0]])
    a2, a3 = 3 * (qf - q0) / tf ** 2, -2 * (qf - q0) / tf ** 3
    for t in np.linspace(0.0, tf, 9):
        ref = traj.sample(t)
        assert ref.q_d[0] == pytest.approx(q0 + a2 * t ** 2 + a3 * t ** 3, abs=1e-12)
        assert ref.qd_d[0] == pytest.approx(2 * a2 * t + 3 * a3 * t ** 2, abs=1e-12)
        assert ref.qdd_d[0] == pytest.approx(2 * a2 + 6 * a3 * t, abs=1e-12)


def test_quintic_samples_of_a_sine_reproduce_it_between_samples():
    # Ej. 8.1: θ1d = 0.15 sin(2πt/4), θ2d = 0.15 cos(2πt/4), sampled every 20 ms.
    w = 2 * math.pi / 4.0
    t = np.arange(0.0, 4.0 + 1e-9, 0.02)
    q = 0.15 * np.column_stack([np.sin(w * t), np.cos(w * t)])
    qd = 0.15 * w * np.column_stack([np.cos(w * t), -np.sin(w * t)])
    traj = SampledTrajectory(t, q, qd, -w * w * q)
    for s in (0.0, 0.013, 1.007, 2.5, 3.999, 4.0):
        ref = traj.sample(s)
        np.testing.assert_allclose(ref.q_d, 0.15 * np.array([math.sin(w * s), math.cos(w * s)]),
                                   atol=1e-11)
        np.testing.assert_allclose(
            ref.qd_d, 0.15 * w * np.array([math.cos(w * s), -math.sin(w * s)]), atol=1e-9)
        np.testing.assert_allclose(ref.qdd_d, -w * w * ref.q_d, atol=1e-6)


def test_linear_with_positions_only_and_holding_outside():
    traj = SampledTrajectory([1.0, 2.0, 4.0], [[0.0, 1.0], [1.0, 1.0], [3.0, 0.0]])
    np.testing.assert_allclose(traj.sample(3.0).q_d, [2.0, 0.5])
    np.testing.assert_allclose(traj.sample(3.0).qd_d, [1.0, -0.5])
    before, after = traj.sample(0.0), traj.sample(9.0)
    np.testing.assert_array_equal(before.q_d, [0.0, 1.0])
    np.testing.assert_array_equal(after.q_d, [3.0, 0.0])
    for ref in (before, after):
        np.testing.assert_array_equal(ref.qd_d, [0.0, 0.0])
        np.testing.assert_array_equal(ref.qdd_d, [0.0, 0.0])
    assert (traj.start_time, traj.end_time) == (1.0, 4.0)


def test_single_point_is_a_set_point():
    traj = SampledTrajectory([0.0], [[0.5, -0.5]])
    np.testing.assert_array_equal(traj.sample(3.0).q_d, [0.5, -0.5])


@pytest.mark.parametrize(('args', 'match'), [
    (([0.0, 0.0], [[0.0], [1.0]]), 'increasing'),
    (([0.0, math.nan], [[0.0], [1.0]]), 'times'),
    (([0.0, 1.0], [[0.0], [math.nan]]), 'positions'),
    (([0.0, 1.0], [[0.0, 1.0]]), 'positions'),
    (([0.0, 1.0], [[0.0], [1.0]], [[0.0]]), 'velocities'),
    (([0.0, 1.0], [[0.0], [1.0]], None, [[0.0], [0.0]]), 'need velocities'),
])
def test_bad_samples_are_refused(args, match):
    with pytest.raises(ValueError, match=match):
        SampledTrajectory(*args)


def test_non_finite_time_is_refused():
    with pytest.raises(ValueError, match='finite'):
        SampledTrajectory([0.0, 1.0], [[0.0], [1.0]]).sample(math.nan)


@pytest.mark.parametrize('orders', [1, 2, 3], ids=['linear', 'cubic', 'quintic'])
def test_every_interval_matches_scipys_hermite_polynomials(orders):
    # Independent: scipy's BPoly.from_derivatives builds the same Hermite interpolant, one
    # interval at a time, on uneven intervals and random derivatives.
    rng = np.random.default_rng(7)
    times = np.cumsum(rng.uniform(0.01, 0.5, 60))
    columns = [rng.normal(size=(60, 3)) for _ in range(orders)]
    trajectory = SampledTrajectory(times, *columns)
    derivatives = np.stack(columns, axis=-1)
    reference = [BPoly.from_derivatives(times, derivatives[:, j]) for j in range(3)]
    for t in rng.uniform(times[0], times[-1], 200):
        sampled = trajectory.sample(t)
        for order, value in enumerate((sampled.q_d, sampled.qd_d, sampled.qdd_d)):
            expected = [poly(t, order) for poly in reference]
            np.testing.assert_allclose(value, expected, rtol=1e-9, atol=1e-9 * 10 ** order)
