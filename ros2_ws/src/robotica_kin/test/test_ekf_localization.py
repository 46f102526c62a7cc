"""
Tests of robotica_kin.mobile.ekf_localization (book §4.7.2, §4.7.5, §7.7; catalog §2.9, §5.7).

References are independent of the code under test: closed-form circles and figure eights for
the ground truth, noise drawn here with fixed seeds, central finite differences for the
Jacobians, the information form of the Kalman update, scipy's chi-square quantiles, and
:func:`robotica_kin.mobile.odometry.odometry_increment` for the exact arc.
"""

import math

from hypothesis import given, settings
import hypothesis.strategies as st
import numpy as np
import pytest
from robotica_kin.mobile.ekf_localization import (
    chi_square_threshold,
    EkfLocalization,
    increment_between_poses,
    motion_jacobians,
    motion_model,
    OdometryNoise,
    WHITE_VARIANCE_FLOOR_RATIO,
)
from robotica_kin.mobile.odometry import odometry_increment
from scipy.stats import chi2, norm

# Odometry errors of the drives (variances per metre and per radian), also told to the filter.
NOISE = OdometryNoise(k_distance=1e-3, k_heading=4e-4, k_turn=1e-3)
LENGTH = 200.0  # [m] figure eight: two circles of 100 m, left then right
RADIUS = LENGTH / (4.0 * math.pi)  # [m] ≈ 15.9
P0 = np.diag([0.1 ** 2, 0.1 ** 2, 0.02 ** 2])  # initial covariance [m², m², rad²]
GPS_SIGMA = 1.0  # [m] DGPS, book §7.7.5: 1-5 m

POSES = st.tuples(st.floats(-10.0, 10.0), st.floats(-10.0, 10.0), st.floats(-math.pi, math.pi))
DISTANCES = st.floats(-5.0, 5.0)
TURNS = st.one_of(st.floats(-3.0, 3.0), st.floats(-1e-6, 1e-6), st.just(0.0))


def angle_error(a, b):
    """Return a - b reduced to [-π, π] with math.remainder (independent of wrap_to_pi)."""
    return math.remainder(a - b, 2.0 * math.pi)


def pose_error(pose, truth):
    return np.array([pose[0] - truth[0], pose[1] - truth[1], angle_error(pose[2], truth[2])])


def circle_pose(start, radius, s):
    """Pose after an arc length s on the circle of signed radius R (> 0 turns left)."""
    x0, y0, theta0 = start
    cx, cy = x0 - radius * math.sin(theta0), y0 + radius * math.cos(theta0)
    theta = theta0 + s / radius
    return np.array([cx + radius * math.sin(theta), cy - radius * math.cos(theta), theta])


def figure_eight(s):
    """Ground truth at arc length s [m]: a left circle from the origin, then a right one."""
    if s <= 0.5 * LENGTH:
        return circle_pose((0.0, 0.0, 0.0), RADIUS, s)
    return circle_pose((0.0, 0.0, 0.0), -RADIUS, s - 0.5 * LENGTH)


def drive(seed, step, gps_every=None):
    """
    Drive the figure eight with noisy odometry (and GPS every ``gps_every`` steps).

    The odometry noise has the variances of the error model the filter uses, drawn here. The
    start pose is drawn from P0 around the true origin. Returns, per step, the true pose, the
    dead-reckoning filter (predictions only) and the GPS-aided filter: poses and covariances.
    """
    rng = np.random.default_rng(seed)
    n = round(LENGTH / step)
    start = rng.multivariate_normal(np.zeros(3), P0)
    dead_reckoning = EkfLocalization(start, P0, NOISE)
    fused = EkfLocalization(start, P0, NOISE)
    out = {key: [] for key in ('truth', 'dr_pose', 'dr_cov', 'pose', 'cov')}
    for k in range(1, n + 1):
        turn = (step if k <= n // 2 else -step) / RADIUS
        sigma_s = math.sqrt(NOISE.k_distance * step)
        sigma_theta = math.sqrt(NOISE.k_heading * step + NOISE.k_turn * abs(turn))
        delta_s = step + sigma_s * rng.standard_normal()
        delta_theta = turn + sigma_theta * rng.standard_normal()
        dead_reckoning.predict(delta_s, delta_theta)
        fused.predict(delta_s, delta_theta)
        truth = figure_eight(k * step)
        if gps_every is not None and k % gps_every == 0:
            fix = truth[:2] + GPS_SIGMA * rng.standard_normal(2)
            fused.update_position(fix, GPS_SIGMA ** 2 * np.eye(2))
        out['truth'].append(truth)
        out['dr_pose'].append(dead_reckoning.pose)
        out['dr_cov'].append(dead_reckoning.covariance)
        out['pose'].append(fused.pose)
        out['cov'].append(fused.covariance)
    result = {key: np.array(value) for key, value in out.items()}
    result['rejected'] = fused.rejected_updates
    return result


def errors_and_nees(poses, covariances, truths):
    errors = np.array([pose_error(p, t) for p, t in zip(poses, truths)])
    nees = np.array([e @ np.linalg.solve(c, e) for e, c in zip(errors, covariances)])
    return errors, nees


# --- 1. motion model and Jacobians --------------------------------------------------------


def numerical_jacobians(pose, delta_s, delta_theta, h=1e-6):
    def diff(plus, minus):
        return np.array([(plus[0] - minus[0]) / (2 * h), (plus[1] - minus[1]) / (2 * h),
                         angle_error(plus[2], minus[2]) / (2 * h)])

    jac_state = np.empty((3, 3))
    for i in range(3):
        dp = np.zeros(3)
        dp[i] = h
        jac_state[:, i] = diff(motion_model(pose + dp, delta_s, delta_theta),
                               motion_model(pose - dp, delta_s, delta_theta))
    jac_increment = np.column_stack([
        diff(motion_model(pose, delta_s + h, delta_theta),
             motion_model(pose, delta_s - h, delta_theta)),
        diff(motion_model(pose, delta_s, delta_theta + h),
             motion_model(pose, delta_s, delta_theta - h)),
    ])
    return jac_state, jac_increment


@settings(max_examples=80, deadline=None)
@given(POSES, DISTANCES, TURNS)
def test_jacobians_match_central_differences(pose, delta_s, delta_theta):
    pose = np.array(pose)
    jac_state, jac_increment = motion_jacobians(pose, delta_s, delta_theta)
    ref_state, ref_increment = numerical_jacobians(pose, delta_s, delta_theta)
    np.testing.assert_allclose(jac_state, ref_state, atol=1e-7)
    np.testing.assert_allclose(jac_increment, ref_increment, atol=1e-7)


@pytest.mark.parametrize('delta_theta', [0.0, -1e-12, 1e-4, 0.2 - 1e-9, 0.2 + 1e-9, -0.2, 1.0])
def test_jacobians_are_smooth_across_the_series_switch(delta_theta):
    """d/dh (sin h / h) switches to its series at |h| = 0.1 rad: no jump there, none at 0."""
    pose = np.array([1.0, -2.0, 0.8])
    jac_state, jac_increment = motion_jacobians(pose, 3.0, delta_theta)
    ref_state, ref_increment = numerical_jacobians(pose, 3.0, delta_theta, h=1e-5)
    np.testing.assert_allclose(jac_state, ref_state, atol=1e-8)
    np.testing.assert_allclose(jac_increment, ref_increment, atol=1e-8)


def test_jacobians_of_a_straight_step_in_closed_form():
    """Δθ = 0: x' = x + Δs cos θ, y' = y + Δs sin θ; ∂/∂Δθ of (x', y') is (Δs/2)(-sin, cos)."""
    theta, delta_s = 0.7, 2.0
    jac_state, jac_increment = motion_jacobians([3.0, 4.0, theta], delta_s, 0.0)
    c, s = math.cos(theta), math.sin(theta)
    np.testing.assert_allclose(jac_state, [[1, 0, -delta_s * s], [0, 1, delta_s * c], [0, 0, 1]],
                               atol=1e-15)
    np.testing.assert_allclose(jac_increment,
                               [[c, -0.5 * delta_s * s], [s, 0.5 * delta_s * c], [0, 1]],
                               atol=1e-15)


@settings(max_examples=60, deadline=None)
@given(POSES, DISTANCES, TURNS)
def test_motion_model_is_the_exact_arc_of_odometry_increment(pose, delta_s, delta_theta):
    """
    Book (4.93) as implemented by odometry_increment('exact_arc'), track b = 1 m.

    The (Δs/Δθ)(sin(θ+Δθ) - sin θ) form of odometry_increment loses about Δs eps/|Δθ| to
    cancellation for small |Δθ| (above its 1e-9 rad guard); the tolerance allows for it.
    """
    expected = odometry_increment(pose, delta_s - 0.5 * delta_theta, delta_s + 0.5 * delta_theta,
                                  1.0, 'exact_arc')
    result = motion_model(pose, delta_s, delta_theta)
    assert -math.pi < result[2] <= math.pi
    cancellation = 8.0 * np.finfo(float).eps * abs(delta_s) / max(abs(delta_theta), 1e-9)
    np.testing.assert_allclose(pose_error(result, expected), 0.0, atol=1e-9 + cancellation)


@pytest.mark.parametrize('delta_theta', [1e-6, 2e-8, 1e-9, 1e-12])
def test_motion_model_is_accurate_for_tiny_turns(delta_theta):
    """From θ = 0: y = Δs (1 - cos Δθ)/Δθ = Δs (Δθ/2 - Δθ³/24 + ...), x = Δs sin Δθ/Δθ."""
    delta_s = 3.0
    pose = motion_model([0.0, 0.0, 0.0], delta_s, delta_theta)
    assert pose[1] == pytest.approx(delta_s * (0.5 * delta_theta - delta_theta ** 3 / 24.0),
                                    rel=1e-14)
    assert pose[0] == pytest.approx(delta_s * (1.0 - delta_theta ** 2 / 6.0), rel=1e-15)


@settings(max_examples=60, deadline=None)
@given(POSES, DISTANCES, st.floats(-3.0, 3.0))
def test_increment_between_poses_inverts_the_motion_model(pose, delta_s, delta_theta):
    after = motion_model(pose, delta_s, delta_theta)
    ds, dth = increment_between_poses(pose, after)
    assert ds == pytest.approx(delta_s, abs=1e-9)
    assert dth == pytest.approx(delta_theta, abs=1e-12)


# --- 2. noise-free prediction -------------------------------------------------------------


@pytest.mark.parametrize(('start', 'radius', 'step'), [
    ((0.0, 0.0, 0.0), 5.0, 0.1),
    ((2.0, -1.0, 3.0), -3.0, 0.25),
    ((-4.0, 7.0, -2.5), 1e6, 0.5),
    ((1.0, 1.0, 1.0), 2.0, -0.05),  # reversing
])
def test_exact_increments_follow_the_true_circle(start, radius, step):
    """Δs = step and Δθ = step/R each time put the pose on the closed-form circle, P stays 0."""
    ekf = EkfLocalization(start, np.zeros((3, 3)), OdometryNoise(0.0, 0.0, 0.0))
    for k in range(1, 401):
        pose = ekf.predict(step, step / radius)
        expected = circle_pose(start, radius, k * step)
        np.testing.assert_allclose(pose_error(pose, expected), 0.0, atol=1e-9)
        assert -math.pi < pose[2] <= math.pi
    np.testing.assert_array_equal(ekf.covariance, np.zeros((3, 3)))


def test_predicted_covariance_of_a_straight_step_in_closed_form():
    """From P = 0 at θ = 0: P = G Q Gᵀ with G = [[1, 0], [0, Δs/2], [0, 1]]."""
    delta_s = 2.0
    ekf = EkfLocalization([0.0, 0.0, 0.0], np.zeros((3, 3)), NOISE)
    ekf.predict(delta_s, 0.0)
    var_s, var_theta = NOISE.k_distance * delta_s, NOISE.k_heading * delta_s
    half = 0.5 * delta_s
    expected = [[var_s, 0.0, 0.0],
                [0.0, half ** 2 * var_theta, half * var_theta],
                [0.0, half * var_theta, var_theta]]
    np.testing.assert_allclose(ekf.covariance, expected, atol=1e-18)
    # A gyro's heading variance replaces the odometry one.
    ekf.reset([0.0, 0.0, 0.0], np.zeros((3, 3)))
    ekf.predict(delta_s, 0.0, heading_variance=1e-6)
    assert ekf.covariance[2, 2] == pytest.approx(1e-6)
    assert ekf.covariance[1, 1] == pytest.approx(half ** 2 * 1e-6)
    assert ekf.covariance[0, 0] == pytest.approx(var_s)


def test_odometry_noise_covariance_is_proportional():
    q = NOISE.covariance(-2.0, -0.5)  # reversing and turning right count by magnitude
    np.testing.assert_allclose(q, np.diag([2e-3, 4e-4 * 2.0 + 1e-3 * 0.5]))
    np.testing.assert_allclose(NOISE.covariance(2.0, 0.5, heading_variance=0.0),
                               np.diag([2e-3, 0.0]))
    np.testing.assert_array_equal(NOISE.covariance(0.0, 0.0), np.zeros((2, 2)))


# --- 3. drift of dead reckoning, bounded error with GPS -----------------------------------


@pytest.fixture(scope='module')
def run_10hz():
    """One 200-m figure eight at 1 m/s: odometry at 10 Hz (0.1 m), GPS every 1 s (σ = 1 m)."""
    return drive(seed=20240501, step=0.1, gps_every=10)


def test_dead_reckoning_drifts(run_10hz):
    truth = run_10hz['truth']
    n = len(truth)
    position_error = np.hypot(*(run_10hz['dr_pose'][:, :2] - truth[:, :2]).T)
    assert position_error[-1] > position_error[n // 4 - 1]
    # Without fixes det P never decreases (det F = 1 and G Q Gᵀ >= 0), nor does var θ. The
    # position variance itself may shrink for a while: closing a loop undoes the lateral
    # effect of earlier heading errors, but overall it grows.
    covariance = run_10hz['dr_cov']
    assert np.all(np.diff(np.linalg.det(covariance)) >= 0.0)
    assert np.all(np.diff(covariance[:, 2, 2]) >= 0.0)
    position_variance = np.trace(covariance[:, :2, :2], axis1=1, axis2=2)
    assert position_variance[-1] > 2.0 * position_variance[n // 4 - 1]


def test_gps_bounds_the_error_and_the_filter_is_consistent(run_10hz):
    truth = run_10hz['truth']
    errors, nees = errors_and_nees(run_10hz['pose'], run_10hz['cov'], truth)
    rms = math.sqrt(np.mean(errors[:, 0] ** 2 + errors[:, 1] ** 2))
    dead_reckoning_end = math.hypot(*(run_10hz['dr_pose'][-1, :2] - truth[-1, :2]))
    assert rms < 2.0
    assert rms < dead_reckoning_end
    assert run_10hz['rejected'] <= 2  # 0.1 % of 200 good fixes expected beyond the gate
    # Each axis within its own 3σ at >= 95 % of the steps (99.7 % for a Gaussian).
    sigmas = np.sqrt(np.diagonal(run_10hz['cov'], axis1=1, axis2=2))
    assert np.mean(np.all(np.abs(errors) <= 3.0 * sigmas, axis=1)) >= 0.95
    # Single-run NEES within the two-sided 95 % chi-square bounds (3 dof) most of the time;
    # successive steps are correlated, so the fraction of one run scatters below 95 %.
    low, high = chi2.ppf([0.025, 0.975], 3)
    assert np.mean((nees > low) & (nees < high)) >= 0.85


def test_monte_carlo_nees_of_dead_reckoning_and_of_the_gps_filter():
    """
    Average NEES over N runs at each step lies within the χ²(3N)/N 95 % bounds (Bar-Shalom).

    At 2 m/s with odometry and GPS at 1 Hz (2 m steps). A filter with too small a Q (or a
    wrong Jacobian) gives NEES well above 3, one with too large a Q well below.
    """
    runs = 24
    results = [drive(seed=1000 + r, step=2.0, gps_every=1) for r in range(runs)]
    n = len(results[0]['truth'])
    dr_nees = np.array([errors_and_nees(r['dr_pose'], r['dr_cov'], r['truth'])[1]
                        for r in results]).mean(axis=0)
    gps_nees = np.array([errors_and_nees(r['pose'], r['cov'], r['truth'])[1]
                         for r in results]).mean(axis=0)
    low, high = chi2.ppf([0.025, 0.975], 3 * runs) / runs
    assert np.mean((gps_nees > low) & (gps_nees < high)) >= 0.9
    assert np.mean((dr_nees > low) & (dr_nees < high)) >= 0.9
    assert 2.7 < gps_nees.mean() < 3.3
    # Dead reckoning drifts: RMS position error at the end well above that at 1/4 of the way.
    dr_rms = np.sqrt(np.mean([np.sum((r['dr_pose'][:, :2] - r['truth'][:, :2]) ** 2, axis=1)
                              for r in results], axis=0))
    assert dr_rms[-1] > 1.5 * dr_rms[n // 4 - 1]


# --- 4. the innovation gate ---------------------------------------------------------------


def test_outlier_fix_is_rejected_and_changes_nothing():
    ekf = EkfLocalization([10.0, 5.0, 0.3], np.diag([1.0, 1.0, 0.01]), NOISE)
    ekf.predict(1.0, 0.05)
    assert ekf.update_position(ekf.pose[:2] + [0.5, -0.3], np.eye(2))
    pose, covariance = ekf.pose, ekf.covariance
    assert not ekf.update_position(pose[:2] + [100.0, 0.0], np.eye(2))
    np.testing.assert_array_equal(ekf.pose, pose)
    np.testing.assert_array_equal(ekf.covariance, covariance)
    assert ekf.rejected_updates == 1
    assert ekf.last_nis > -2.0 * math.log(1.0 - 0.999)
    # Without a gate the same fix is fused and drags the estimate.
    open_gate = EkfLocalization(pose, covariance, NOISE, gate_probability=1.0)
    assert open_gate.update_position(pose[:2] + [100.0, 0.0], np.eye(2))
    assert open_gate.pose[0] > pose[0] + 10.0
    assert open_gate.rejected_updates == 0


@pytest.mark.parametrize(('probability', 'dof'), [(0.999, 2), (0.95, 2), (0.999, 1), (0.9, 1)])
def test_gate_threshold_is_the_chi_square_quantile(probability, dof):
    """2 dof: -2 ln(1 - p); 1 dof: the two-sided normal quantile squared."""
    if dof == 2:
        expected = -2.0 * math.log(1.0 - probability)
    else:
        expected = norm.ppf(0.5 * (1.0 + probability)) ** 2
    assert chi_square_threshold(probability, dof) == pytest.approx(expected, rel=1e-12)
    assert chi_square_threshold(probability, 3) == pytest.approx(chi2.ppf(probability, 3))
    assert chi_square_threshold(1.0, dof) == math.inf


@pytest.mark.parametrize(('nis', 'accepted'), [(13.7, True), (13.9, False)])
def test_position_gate_boundary(nis, accepted):
    """P_xy = a I and R = r I give S = (a + r) I, so a fix at distance d has NIS d²/(a + r)."""
    a, r = 0.5, 1.5
    ekf = EkfLocalization([1.0, 2.0, 0.0], np.diag([a, a, 0.01]), NOISE)
    d = math.sqrt(nis * (a + r))
    assert ekf.update_position([1.0 + d * 0.6, 2.0 + d * 0.8], r * np.eye(2)) is accepted
    assert ekf.last_nis == pytest.approx(nis)
    assert ekf.rejected_updates == (0 if accepted else 1)


@pytest.mark.parametrize(('nis', 'accepted'), [(10.7, True), (10.9, False)])
def test_heading_gate_boundary(nis, accepted):
    """χ²₁(0.999) = 10.83."""
    ekf = EkfLocalization([0.0, 0.0, 0.5], np.diag([1.0, 1.0, 0.02]), NOISE)
    z = 0.5 - math.sqrt(nis * (0.02 + 0.03))
    assert ekf.update_heading(z, 0.03) is accepted
    assert ekf.last_nis == pytest.approx(nis)


# --- the Kalman update against the information form ---------------------------------------


def random_spd(rng, size, scale):
    a = rng.standard_normal((size, size))
    return scale * (a @ a.T + 0.1 * np.eye(size))


@pytest.mark.parametrize('seed', range(5))
def test_updates_match_the_information_form(seed):
    """P⁺ = (P⁻¹ + Hᵀ R⁻¹ H)⁻¹, x⁺ = x + P⁺ Hᵀ R⁻¹ y: a different algebra from K and Joseph."""
    rng = np.random.default_rng(seed)
    prior = random_spd(rng, 3, 0.3)
    pose = np.array([3.0, -2.0, 1.0])
    noise_xy = random_spd(rng, 2, 0.5)
    z = pose[:2] + 0.3 * rng.standard_normal(2)
    ekf = EkfLocalization(pose, prior, NOISE, gate_probability=1.0)
    assert ekf.update_position(z, noise_xy)
    h = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    info = np.linalg.inv(prior) + h.T @ np.linalg.solve(noise_xy, h)
    posterior = np.linalg.inv(info)
    np.testing.assert_allclose(ekf.covariance, posterior, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(
        ekf.pose, pose + posterior @ h.T @ np.linalg.solve(noise_xy, z - pose[:2]), atol=1e-12)
    np.testing.assert_array_equal(ekf.covariance, ekf.covariance.T)
    # Then a compass heading.
    pose, prior = ekf.pose, ekf.covariance
    z_theta, var_theta = pose[2] + 0.1, 0.02
    assert ekf.update_heading(z_theta, var_theta)
    h = np.array([[0.0, 0.0, 1.0]])
    posterior = np.linalg.inv(np.linalg.inv(prior) + h.T @ h / var_theta)
    np.testing.assert_allclose(ekf.covariance, posterior, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ekf.pose, pose + posterior[:, 2] * 0.1 / var_theta, atol=1e-12)


def test_scalar_position_update_is_the_weighted_mean():
    """Independent axes: x⁺ = (x/P + z/R)/(1/P + 1/R), P⁺ = P R/(P + R)."""
    ekf = EkfLocalization([0.0, 0.0, 0.0], np.diag([4.0, 1.0, 0.1]), NOISE)
    assert ekf.update_position([2.0, 1.0], np.diag([1.0, 3.0]))
    np.testing.assert_allclose(ekf.pose, [(0 / 4 + 2 / 1) / (1 / 4 + 1), (1 / 3) / (1 + 1 / 3),
                                          0.0], atol=1e-15)
    np.testing.assert_allclose(ekf.covariance, np.diag([4 / 5, 3 / 4, 0.1]), atol=1e-15)


def test_exact_fix_with_zero_measurement_noise():
    """R = 0 is allowed (PSD): the position becomes the fix and its variance zero."""
    ekf = EkfLocalization([0.0, 0.0, 0.0], np.diag([1.0, 1.0, 0.1]), NOISE)
    assert ekf.update_position([1.0, -1.0], np.zeros((2, 2)))
    np.testing.assert_allclose(ekf.pose, [1.0, -1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(ekf.covariance, np.diag([0.0, 0.0, 0.1]), atol=1e-15)


# --- 5. compass heading across ±π ---------------------------------------------------------


@pytest.mark.parametrize(('estimate', 'measured', 'expected'), [
    (math.pi - 0.01, -math.pi + 0.01, math.pi),  # +0.02 across the cut, halfway: π
    (-math.pi + 0.01, math.pi - 0.03, math.pi - 0.01),  # -0.04 across, halfway: π - 0.01
    (-math.pi + 0.05, -math.pi + 0.01, -math.pi + 0.03),  # no crossing
])
def test_compass_update_wraps_the_innovation(estimate, measured, expected):
    """Equal prior and measurement variances: the estimate moves halfway along the short arc."""
    ekf = EkfLocalization([1.0, 2.0, estimate], np.diag([0.1, 0.1, 0.01]), NOISE)
    assert ekf.update_heading(measured, 0.01)
    theta = ekf.pose[2]
    assert -math.pi < theta <= math.pi
    assert abs(angle_error(theta, expected)) < 1e-12
    np.testing.assert_array_equal(ekf.pose[:2], [1.0, 2.0])
    assert ekf.covariance[2, 2] == pytest.approx(0.005)


def test_reset_and_copies():
    ekf = EkfLocalization([0.0, 0.0, 7.0], np.eye(3), NOISE)
    assert ekf.pose[2] == pytest.approx(7.0 - 2.0 * math.pi)
    ekf.pose[0] = 99.0
    ekf.covariance[0, 0] = 99.0
    np.testing.assert_array_equal(ekf.pose[:2], [0.0, 0.0])
    np.testing.assert_array_equal(ekf.covariance, np.eye(3))
    ekf.update_position([50.0, 0.0], 0.01 * np.eye(2))
    assert ekf.rejected_updates == 1
    ekf.reset([1.0, 2.0, 0.5], 0.5 * np.eye(3))
    assert ekf.rejected_updates == 0 and ekf.last_nis is None
    np.testing.assert_array_equal(ekf.pose, [1.0, 2.0, 0.5])
    assert ekf.odometry_noise is NOISE and ekf.gate_probability == 0.999


# --- 6. bad input -------------------------------------------------------------------------


@pytest.mark.parametrize('kwargs', [
    {'k_distance': -1e-3}, {'k_heading': math.nan}, {'k_turn': math.inf}, {'k_distance': '1'},
    {'k_turn': True},
])
def test_odometry_noise_rejects_bad_coefficients(kwargs):
    with pytest.raises(ValueError, match=next(iter(kwargs))):
        OdometryNoise(**kwargs)


@pytest.mark.parametrize(('args', 'match'), [
    (([0.0, 0.0], np.eye(3), NOISE), 'initial_pose'),
    (([0.0, math.nan, 0.0], np.eye(3), NOISE), 'initial_pose'),
    (([0.0, 0.0, 0.0], np.eye(2), NOISE), 'initial_covariance'),
    (([0.0, 0.0, 0.0], np.full((3, 3), math.nan), NOISE), 'initial_covariance'),
    (([0.0, 0.0, 0.0], [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], NOISE), 'symmetric'),
    (([0.0, 0.0, 0.0], np.diag([1.0, -1.0, 1.0]), NOISE), 'positive semi-definite'),
    (([0.0, 0.0, 0.0], np.eye(3), (1e-3, 1e-4, 1e-3)), 'OdometryNoise'),
    (([0.0, 0.0, 0.0], np.eye(3), NOISE, 0.0), 'gate_probability'),
    (([0.0, 0.0, 0.0], np.eye(3), NOISE, 1.5), 'gate_probability'),
    (([0.0, 0.0, 0.0], np.eye(3), NOISE, math.nan), 'gate_probability'),
])
def test_constructor_rejects_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        EkfLocalization(*args)


def assert_rejected_and_unchanged(ekf, call, match):
    pose, covariance = ekf.pose, ekf.covariance
    with pytest.raises(ValueError, match=match):
        call()
    np.testing.assert_array_equal(ekf.pose, pose)
    np.testing.assert_array_equal(ekf.covariance, covariance)


@pytest.mark.parametrize(('method', 'args', 'match'), [
    ('predict', (math.nan, 0.0), 'delta_distance'),
    ('predict', (1.0, math.inf), 'delta_heading'),
    ('predict', (1.0, 0.1, -1e-3), 'heading_variance'),
    ('predict', (1.0, 0.1, math.nan), 'heading_variance'),
    ('update_position', ([1.0, 2.0, 3.0], np.eye(2)), 'z_enu_xy'),
    ('update_position', ([1.0, math.nan], np.eye(2)), 'z_enu_xy'),
    ('update_position', ('here', np.eye(2)), 'z_enu_xy'),
    ('update_position', ([1.0, 2.0], np.eye(3)), 'R'),
    ('update_position', ([1.0, 2.0], 1.0), 'R'),
    ('update_position', ([1.0, 2.0], [[1.0, math.nan], [math.nan, 1.0]]), 'R'),
    ('update_position', ([1.0, 2.0], [[1.0, 0.5], [0.0, 1.0]]), 'symmetric'),
    ('update_position', ([1.0, 2.0], [[1.0, 2.0], [2.0, 1.0]]), 'positive semi-definite'),
    ('update_heading', (math.nan, 0.01), 'z_theta'),
    ('update_heading', ('0.1', 0.01), 'z_theta'),
    ('predict', (True, 0.0), 'delta_distance'),
    ('update_heading', (0.1, -0.01), 'variance'),
    ('update_heading', (0.1, math.inf), 'variance'),
])
def test_methods_reject_bad_input_and_keep_the_state(method, args, match):
    ekf = EkfLocalization([1.0, 2.0, 0.3], np.diag([1.0, 1.0, 0.1]), NOISE)
    assert_rejected_and_unchanged(ekf, lambda: getattr(ekf, method)(*args), match)
    assert ekf.rejected_updates == 0


def test_singular_innovation_covariance_is_refused():
    """Zero prior and zero measurement variance leave S = 0: refuse rather than divide by 0."""
    ekf = EkfLocalization([1.0, 2.0, 0.3], np.zeros((3, 3)), NOISE)
    assert_rejected_and_unchanged(
        ekf, lambda: ekf.update_position([1.0, 2.0], np.zeros((2, 2))), 'positive definite')
    assert_rejected_and_unchanged(ekf, lambda: ekf.update_heading(0.3, 0.0), 'positive definite')


@pytest.mark.parametrize(('function', 'args', 'match'), [
    (motion_model, ([0.0, 0.0], 1.0, 0.0), 'pose'),
    (motion_model, ([0.0, 0.0, 0.0], math.nan, 0.0), 'delta_distance'),
    (motion_jacobians, ([0.0, 0.0, math.inf], 1.0, 0.0), 'pose'),
    (motion_jacobians, ([0.0, 0.0, 0.0], 1.0, math.nan), 'delta_heading'),
    (increment_between_poses, ([0.0, 0.0, 0.0], [0.0, 0.0]), 'pose_after'),
    (increment_between_poses, ([0.0, math.nan, 0.0], [0.0, 0.0, 0.0]), 'pose_before'),
    (chi_square_threshold, (0.0, 2), 'gate_probability'),
    (chi_square_threshold, (0.9, 0), 'dof'),
    (chi_square_threshold, (0.9, 1.5), 'dof'),
])
def test_functions_reject_bad_input(function, args, match):
    with pytest.raises(ValueError, match=match):
        function(*args)


# --- 7. time-correlated GPS error: the Gauss–Markov bias augmentation ----------------------

GM_TAU = 30.0  # [s] correlation time of the GPS error (the 'dgps' preset of the simulator)
GM_SIGMA = 0.35  # [m] its stationary 1σ per axis
WHITE_SIGMA = 0.1  # [m] white receiver noise per axis
GM_RATE = 5.0  # [Hz] odometry increments and fixes
GM_SPEED = 2.0  # [m/s] the 200-m figure eight in 100 s
GM_RUNS = 16
GM_FIX_COVARIANCE = (GM_SIGMA ** 2 + WHITE_SIGMA ** 2) * np.eye(2)  # the honest total [m²]


def augmented(pose=(0.0, 0.0, 0.0), covariance=P0, **kwargs):
    kwargs.setdefault('position_bias_stddev', GM_SIGMA)
    kwargs.setdefault('position_bias_correlation_time', GM_TAU)
    return EkfLocalization(pose, covariance, NOISE, **kwargs)


def drive_with_correlated_gps(seed):
    """
    Drive the figure eight at 2 m/s with odometry and a GPS fix at 5 Hz.

    The fix error is e_k = b_k + w_k per axis: b a first-order Gauss–Markov process started in
    its stationary law N(0, σ²) and stepped exactly, b_k = a b_(k-1) + σ sqrt(1 - a²) n_k with
    a = exp(-Δt/τ); w white N(0, σ_w²). Both filters are told the total covariance
    (σ² + σ_w²) I of a fix, as the GPS emulator reports it; the augmented one derives the
    white part from it.
    """
    rng = np.random.default_rng(seed)
    dt = 1.0 / GM_RATE
    step = GM_SPEED * dt
    n = round(LENGTH / step)
    a = math.exp(-dt / GM_TAU)
    start = rng.multivariate_normal(np.zeros(3), P0)
    plain = EkfLocalization(start, P0, NOISE)
    aug = augmented(start)
    bias = GM_SIGMA * rng.standard_normal(2)
    out = {key: [] for key in ('truth', 'bias', 'pose', 'cov', 'aug_state', 'aug_cov')}
    for k in range(1, n + 1):
        turn = (step if k <= n // 2 else -step) / RADIUS
        sigma_s = math.sqrt(NOISE.k_distance * step)
        sigma_theta = math.sqrt(NOISE.k_heading * step + NOISE.k_turn * abs(turn))
        delta_s = step + sigma_s * rng.standard_normal()
        delta_theta = turn + sigma_theta * rng.standard_normal()
        plain.predict(delta_s, delta_theta)
        aug.predict(delta_s, delta_theta, dt=dt)
        truth = figure_eight(k * step)
        bias = a * bias + GM_SIGMA * math.sqrt(1.0 - a * a) * rng.standard_normal(2)
        fix = truth[:2] + bias + WHITE_SIGMA * rng.standard_normal(2)
        plain.update_position(fix, GM_FIX_COVARIANCE)
        aug.update_position(fix, GM_FIX_COVARIANCE)
        out['truth'].append(truth)
        out['bias'].append(bias)
        out['pose'].append(plain.pose)
        out['cov'].append(plain.covariance)
        out['aug_state'].append(aug.state)
        out['aug_cov'].append(aug.full_covariance)
    return {key: np.array(value) for key, value in out.items()}


def state_errors(estimates, truth):
    """Estimate minus truth per step, the heading difference reduced to [-π, π)."""
    errors = estimates - truth
    errors[:, 2] = np.mod(errors[:, 2] + math.pi, 2.0 * math.pi) - math.pi
    return errors


def nees(errors, covariances):
    return np.einsum('ni,ni->n', errors, np.linalg.solve(covariances, errors[..., None])[..., 0])


@pytest.fixture(scope='module')
def gm_runs():
    runs = [drive_with_correlated_gps(5000 + r) for r in range(GM_RUNS)]
    for run in runs:
        run['errors'] = state_errors(run['pose'], run['truth'])
        run['aug_errors'] = state_errors(run['aug_state'][:, :3], run['truth'])
        run['aug_full_errors'] = np.column_stack(
            [run['aug_errors'], run['aug_state'][:, 3:] - run['bias']])
    return runs


def fraction_inside_3_sigma(runs, errors_key, cov_key):
    """Per axis, the fraction of all steps of all runs whose error is within ±3σ."""
    errors = np.concatenate([run[errors_key] for run in runs])
    covariances = np.concatenate([run[cov_key] for run in runs])
    size = errors.shape[1]
    sigmas = np.sqrt(np.diagonal(covariances[:, :size, :size], axis1=1, axis2=2))
    return np.mean(np.abs(errors) <= 3.0 * sigmas, axis=0)


def test_plain_filter_is_overconfident_with_correlated_fixes(gm_runs):
    """
    Fixes at 5 Hz treated as independent average an error that lives 30 s: P shrinks far below it.

    A consistent filter holds 99.7 % of the errors of each axis within 3σ and has a mean NEES
    of 3 (3 dof); this one misses both by far (60-80 % and ≈ 27 with these seeds).
    """
    inside = fraction_inside_3_sigma(gm_runs, 'errors', 'cov')
    assert np.all(inside[:2] < 0.85)
    mean_nees = np.mean([nees(run['errors'], run['cov']) for run in gm_runs], axis=0)
    assert mean_nees.mean() > 10.0
    high = chi2.ppf(0.975, 3 * GM_RUNS) / GM_RUNS
    assert np.mean(mean_nees > high) > 0.9


def test_augmented_filter_is_consistent(gm_runs):
    """
    With the GPS error as a Gauss–Markov state the pose errors match P (Bar-Shalom's NEES test).

    Each axis within 3σ at >= 95 % of the steps; the average over 16 runs of the pose NEES
    (3 dof) and of the full-state NEES (pose and GPS error, 5 dof) within the two-sided 95 %
    χ²(dof·N)/N bounds at >= 90 % of the steps, and the time average of the pose NEES near 3.
    """
    inside = fraction_inside_3_sigma(gm_runs, 'aug_errors', 'aug_cov')
    assert np.all(inside >= 0.95)
    for errors_key, dof in (('aug_errors', 3), ('aug_full_errors', 5)):
        mean_nees = np.mean([nees(run[errors_key], run['aug_cov'][:, :dof, :dof])
                             for run in gm_runs], axis=0)
        low, high = chi2.ppf([0.025, 0.975], dof * GM_RUNS) / GM_RUNS
        assert np.mean((mean_nees > low) & (mean_nees < high)) >= 0.9
        assert 0.8 * dof < mean_nees.mean() < 1.2 * dof


def test_augmented_filter_is_not_less_accurate(gm_runs):
    """The RMS position error over all runs is no worse than the plain filter's (+5 %)."""
    def rms(key):
        return math.sqrt(np.mean([np.mean(np.sum(run[key][:, :2] ** 2, axis=1))
                                  for run in gm_runs]))

    assert rms('aug_errors') <= 1.05 * rms('errors')


@pytest.mark.parametrize(('dt', 'tau'), [(0.2, 30.0), (5.0, 30.0), (100.0, 2.0), (1.0, math.inf)])
def test_bias_prediction_is_the_exact_gauss_markov_step(dt, tau):
    """
    One predict: b ← φ b, var ← φ² var + σ² (1 - φ²), cov(pose, b) ← F cov φ, φ = exp(-dt/τ).

    Started from the stationary σ² the variance stays σ²; from another value it relaxes
    towards σ². With a motion the pose block is the 3-state filter's.
    """
    sigma = 0.4
    phi = math.exp(-dt / tau)
    ekf = augmented(covariance=np.diag([0.01, 0.02, 0.001]), position_bias_stddev=sigma,
                    position_bias_correlation_time=tau)
    np.testing.assert_array_equal(ekf.full_covariance[3:, 3:], sigma ** 2 * np.eye(2))
    ekf.predict(0.0, 0.0, dt=dt)
    np.testing.assert_allclose(ekf.full_covariance[3:, 3:],
                               (sigma ** 2 * phi ** 2 + sigma ** 2 * (1.0 - phi ** 2))
                               * np.eye(2), rtol=1e-12)
    np.testing.assert_allclose(ekf.full_covariance[3:, 3:], sigma ** 2 * np.eye(2), rtol=1e-12)
    # From a non-stationary, correlated start, with a motion.
    start_state = np.array([1.0, -2.0, 0.4, 0.3, -0.2])
    start_cov = np.diag([0.05, 0.04, 0.003, 0.01, 0.02])
    start_cov[0, 3] = start_cov[3, 0] = 0.005
    start_cov[2, 4] = start_cov[4, 2] = -0.001
    ekf.reset(start_state, start_cov)
    ekf.predict(1.5, 0.2, dt=dt)
    jac_pose, jac_increment = motion_jacobians(start_state[:3], 1.5, 0.2)
    q = NOISE.covariance(1.5, 0.2)
    np.testing.assert_allclose(ekf.state[:3], motion_model(start_state[:3], 1.5, 0.2),
                               atol=1e-15)
    np.testing.assert_allclose(ekf.position_bias, phi * start_state[3:], rtol=1e-15)
    cov = ekf.full_covariance
    np.testing.assert_allclose(
        cov[:3, :3],
        jac_pose @ start_cov[:3, :3] @ jac_pose.T + jac_increment @ q @ jac_increment.T,
        rtol=1e-12)
    np.testing.assert_allclose(cov[:3, 3:], phi * jac_pose @ start_cov[:3, 3:], atol=1e-15)
    relaxed = [phi ** 2 * v + sigma ** 2 * (1.0 - phi ** 2) for v in (0.01, 0.02)]
    np.testing.assert_allclose(cov[3:, 3:], np.diag(relaxed), rtol=1e-12, atol=1e-18)


def test_bias_prediction_composes_over_time():
    """Ten predicts of 0.3 s equal one of 3 s (the discretisation is exact); pose as 3-state."""
    start = ([0.0, 0.0, 0.1, 0.2, -0.1], np.diag([0.01, 0.01, 0.001, 0.02, 0.05]))
    steps, once = augmented(*start), augmented(*start)
    plain = EkfLocalization(start[0][:3], start[1][:3, :3], NOISE)
    for _ in range(10):
        steps.predict(0.0, 0.0, dt=0.3)
        plain.predict(0.2, -0.01)
    once.predict(0.0, 0.0, dt=3.0)
    np.testing.assert_allclose(steps.full_covariance[3:, 3:], once.full_covariance[3:, 3:],
                               rtol=1e-12)
    np.testing.assert_allclose(steps.position_bias, once.position_bias, rtol=1e-12)
    # Motion with uncorrelated bias: the pose block is the plain filter's, bit for bit.
    moving = augmented(*start)
    for _ in range(10):
        moving.predict(0.2, -0.01, dt=0.3)
    np.testing.assert_array_equal(moving.pose, plain.pose)
    np.testing.assert_array_equal(moving.covariance, plain.covariance)
    np.testing.assert_array_equal(moving.full_covariance[:3, 3:], np.zeros((3, 2)))


@pytest.mark.parametrize('seed', range(4))
def test_augmented_updates_match_the_information_form(seed):
    """H = [I₂ 0 I₂] for a fix, [0 0 1 0 0] for a heading; NIS yᵀ S⁻¹ y with S = H P Hᵀ + R."""
    rng = np.random.default_rng(seed)
    prior = random_spd(rng, 5, 0.2)
    state = np.array([3.0, -2.0, 1.0, 0.2, -0.1])
    white = 0.02
    z = state[:2] + state[3:] + 0.2 * rng.standard_normal(2)
    ekf = augmented(state, prior, position_bias_stddev=0.3, gate_probability=1.0)
    assert ekf.update_position(z, np.eye(2), white_variance=white)
    h = np.array([[1.0, 0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0, 1.0]])
    innovation = z - state[:2] - state[3:]
    info = np.linalg.inv(prior) + h.T @ h / white
    posterior = np.linalg.inv(info)
    np.testing.assert_allclose(ekf.full_covariance, posterior, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(ekf.state, state + posterior @ h.T @ innovation / white,
                               atol=1e-10)
    s = h @ prior @ h.T + white * np.eye(2)
    assert ekf.last_nis == pytest.approx(innovation @ np.linalg.solve(s, innovation))
    np.testing.assert_array_equal(ekf.pose, ekf.state[:3])
    np.testing.assert_array_equal(ekf.covariance, ekf.full_covariance[:3, :3])
    np.testing.assert_array_equal(ekf.position_bias, ekf.state[3:])
    # A compass heading.
    state, prior = ekf.state, ekf.full_covariance
    assert ekf.update_heading(state[2] + 0.05, 0.01)
    posterior = np.linalg.inv(np.linalg.inv(prior) + np.outer(np.eye(5)[2], np.eye(5)[2]) / 0.01)
    np.testing.assert_allclose(ekf.full_covariance, posterior, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(ekf.state, state + posterior[:, 2] * 0.05 / 0.01, atol=1e-10)


@pytest.mark.parametrize(('total', 'white'), [
    (np.diag([0.3 ** 2 + 0.01, 0.3 ** 2 + 0.01]), np.diag([0.01, 0.01])),  # R - σ² I
    (np.diag([0.3 ** 2 + 0.04, 0.3 ** 2 + 0.01]), np.diag([0.04, 0.01])),
    (0.5 * 0.3 ** 2 * np.eye(2), 0.01 * 0.3 ** 2 * np.eye(2)),  # below σ²: the floor 0.01 σ²
    (np.diag([0.3 ** 2 + 0.02, 0.0]), np.diag([0.02, 0.01 * 0.3 ** 2])),
])
def test_white_part_of_a_total_fix_covariance(total, white):
    """R_white = R - σ_b² I, eigenvalues clipped at 0.01 σ_b²; also for a rotated R."""
    state = np.array([1.0, 2.0, 0.3, 0.1, 0.05])
    prior = np.diag([0.2, 0.3, 0.01, 0.09, 0.09])
    rotation = np.array([[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]])
    for r in (np.eye(2), rotation):
        from_total = augmented(state, prior, position_bias_stddev=0.3)
        assert from_total.update_position([1.4, 2.2], r @ total @ r.T)
        h = np.array([[1.0, 0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0, 1.0]])
        noise = r @ white @ r.T
        posterior = np.linalg.inv(np.linalg.inv(prior) + h.T @ np.linalg.solve(noise, h))
        np.testing.assert_allclose(from_total.full_covariance, posterior, rtol=1e-8,
                                   atol=1e-12)
    assert WHITE_VARIANCE_FLOOR_RATIO == 0.01
    # The explicit white variance wins over R.
    given = augmented(state, prior, position_bias_stddev=0.3)
    assert given.update_position([1.4, 2.2], 100.0 * np.eye(2), white_variance=0.01)
    reference = augmented(state, prior, position_bias_stddev=0.3)
    assert reference.update_position([1.4, 2.2], (0.09 + 0.01) * np.eye(2))
    np.testing.assert_allclose(given.full_covariance, reference.full_covariance, rtol=1e-9)
    np.testing.assert_allclose(given.state, reference.state, rtol=1e-12)


def test_without_augmentation_nothing_changes():
    """σ_b = 0: 3 states, dt and white_variance are checked but unused, no bias."""
    plain = EkfLocalization([1.0, 2.0, 0.3], np.diag([1.0, 1.0, 0.1]), NOISE)
    timed = EkfLocalization([1.0, 2.0, 0.3], np.diag([1.0, 1.0, 0.1]), NOISE,
                            position_bias_stddev=0.0, position_bias_correlation_time=10.0)
    plain.predict(1.0, 0.1)
    timed.predict(1.0, 0.1, dt=0.5)
    assert plain.update_position([2.0, 2.5], 0.5 * np.eye(2))
    assert timed.update_position([2.0, 2.5], 0.5 * np.eye(2), white_variance=1e-6)
    for ekf in (plain, timed):
        assert ekf.state.shape == (3,) and ekf.full_covariance.shape == (3, 3)
        np.testing.assert_array_equal(ekf.position_bias, [0.0, 0.0])
        assert ekf.position_bias_stddev == 0.0
    np.testing.assert_array_equal(timed.state, plain.state)
    np.testing.assert_array_equal(timed.full_covariance, plain.full_covariance)
    assert plain.position_bias_correlation_time == math.inf


def test_augmented_reset_and_copies():
    ekf = augmented([0.0, 0.0, 7.0], np.eye(3))
    assert ekf.state[2] == pytest.approx(7.0 - 2.0 * math.pi)
    np.testing.assert_array_equal(ekf.position_bias, [0.0, 0.0])
    ekf.state[3] = 5.0
    ekf.full_covariance[4, 4] = 5.0
    ekf.position_bias[0] = 5.0
    np.testing.assert_array_equal(ekf.state[3:], [0.0, 0.0])
    np.testing.assert_array_equal(ekf.full_covariance,
                                  np.diag([1.0, 1.0, 1.0, GM_SIGMA ** 2, GM_SIGMA ** 2]))
    ekf.reset([1.0, 2.0, 0.5, 0.3, -0.3], np.diag([1.0, 1.0, 0.1, 0.2, 0.3]))
    np.testing.assert_array_equal(ekf.position_bias, [0.3, -0.3])
    np.testing.assert_array_equal(ekf.full_covariance.diagonal(), [1.0, 1.0, 0.1, 0.2, 0.3])
    ekf.reset([1.0, 2.0, 0.5], np.diag([1.0, 1.0, 0.1]))
    np.testing.assert_array_equal(ekf.position_bias, [0.0, 0.0])


@pytest.mark.parametrize('dt', [0.0, -0.1, math.nan, math.inf, '0.1', True, [0.1]])
def test_predict_rejects_a_bad_interval(dt):
    for ekf in (augmented(), EkfLocalization([0.0, 0.0, 0.0], P0, NOISE)):
        state, covariance = ekf.state, ekf.full_covariance
        with pytest.raises(ValueError, match='dt'):
            ekf.predict(1.0, 0.1, dt=dt)
        np.testing.assert_array_equal(ekf.state, state)
        np.testing.assert_array_equal(ekf.full_covariance, covariance)


def test_augmented_predict_requires_the_interval():
    ekf = augmented()
    state, covariance = ekf.state, ekf.full_covariance
    with pytest.raises(ValueError, match='dt .*required'):
        ekf.predict(1.0, 0.1)
    np.testing.assert_array_equal(ekf.state, state)
    np.testing.assert_array_equal(ekf.full_covariance, covariance)


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'position_bias_stddev': -0.1}, 'position_bias_stddev'),
    ({'position_bias_stddev': math.nan}, 'position_bias_stddev'),
    ({'position_bias_stddev': math.inf}, 'position_bias_stddev'),
    ({'position_bias_correlation_time': 0.0}, 'position_bias_correlation_time'),
    ({'position_bias_correlation_time': -30.0}, 'position_bias_correlation_time'),
    ({'position_bias_correlation_time': math.nan}, 'position_bias_correlation_time'),
    ({'pose': [0.0, 0.0, 0.0, 0.0]}, 'initial_pose'),
    ({'pose': [0.0, 0.0, 0.0, math.nan, 0.0]}, 'initial_pose'),
    ({'covariance': np.eye(4)}, 'initial_covariance'),
    ({'covariance': -np.eye(5)}, 'positive semi-definite'),
])
def test_augmented_constructor_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        augmented(**kwargs)


@pytest.mark.parametrize('white_variance', [-1e-3, math.nan, math.inf, '0.01'])
def test_update_position_rejects_a_bad_white_variance(white_variance):
    ekf = augmented()
    state, covariance = ekf.state, ekf.full_covariance
    with pytest.raises(ValueError, match='white_variance'):
        ekf.update_position([0.0, 0.0], np.eye(2), white_variance=white_variance)
    np.testing.assert_array_equal(ekf.state, state)
    np.testing.assert_array_equal(ekf.full_covariance, covariance)
