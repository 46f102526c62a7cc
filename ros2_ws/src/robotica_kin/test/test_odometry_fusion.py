"""
Tests of robotica_kin.mobile.odometry_fusion (catalog §13.6; book (4.93), (4.109)-(4.110), §7.7).

References are closed forms worked out here, in the manner of ros2_controllers' odometry tests:
the slides' conversion factor C_m = π D / (n C_e); a straight line, a spin in place and the exact
arc x = R sin θ, y = R (1 - cos θ) with R = v / ω; a Kalman update of a scalar with variance P by
a measurement with variance R moving it by P / (P + R) of the innovation; and the heading
variance of an integrated gyro, Σ σ_k² Δt_k² (each sample's rate held over its interval) plus
the scale-factor and bias terms, summed here sample by sample.
"""

import math

import numpy as np
import pytest
from robotica_kin.bounds import MAX_TIME_JUMP
from robotica_kin.mobile.ekf_localization import OdometryNoise
from robotica_kin.mobile.odometry import ODOMETRY_METHODS
from robotica_kin.mobile.odometry_fusion import (GYRO_WAIT_READINGS, metres_per_tick,
                                                 OdometryFusion, OdometryFusionParams,
                                                 PENDING_LIMIT)

RADIUS, TRACK, TICKS = 0.1, 0.4, 1000
# Slides' C_m = π D / (n C_e) [m/tick]: D = 2c, gear ratio n = 1, C_e = 1000 counts.
C_M = math.pi * (2.0 * RADIUS) / (1 * TICKS)
ZERO = np.zeros((3, 3))


def fusion(pose=(0.0, 0.0, 0.0), covariance=ZERO, **params) -> OdometryFusion:
    return OdometryFusion(OdometryFusionParams(wheel_radius=RADIUS, wheel_separation=TRACK,
                                               **params), pose, covariance)


def feed(odom, readings):
    """Add encoder readings (left, right, t) one by one; return every estimate answered."""
    estimates = []
    for left, right, t in readings:
        odom.add_encoders(left, right, TICKS, t)
        estimates += odom.update()[0]
    return estimates


def kinds(events):
    return [event.kind for event in events]


# -- the conversion factor ----------------------------------------------------------------------

def test_metres_per_tick_is_the_slides_conversion_factor():
    assert metres_per_tick(RADIUS, TICKS) == pytest.approx(C_M, rel=1e-15)
    # A 500-line encoder with x4 decoding on a 0.25 m wheel: π 0.5 / 2000 m per count.
    assert metres_per_tick(0.25, 500 * 4) == pytest.approx(math.pi * 0.5 / 2000, rel=1e-15)


@pytest.mark.parametrize(('radius', 'ticks', 'match'), [
    (0.1, 0, 'ticks_per_revolution'), (0.1, -5, 'ticks_per_revolution'),
    (0.1, 2.5, 'ticks_per_revolution'), (0.1, True, 'ticks_per_revolution'),
    (0.0, 1000, 'wheel_radius'), (math.nan, 1000, 'wheel_radius'),
])
def test_metres_per_tick_rejects_bad_input(radius, ticks, match):
    with pytest.raises(ValueError, match=match):
        metres_per_tick(radius, ticks)


# -- closed-form motions ------------------------------------------------------------------------

@pytest.mark.parametrize('method', ODOMETRY_METHODS)
def test_straight_line(method):
    odom = fusion((1.0, 2.0, 0.5), integration_method=method)
    estimates = feed(odom, [(100, 100, 1.0), (400, 400, 1.5)])
    distance = 300 * C_M
    assert [e.t for e in estimates] == [1.0, 1.5]
    np.testing.assert_allclose(estimates[0].pose, [1.0, 2.0, 0.5])   # the first one latches
    assert estimates[0].twist == (0.0, 0.0)
    np.testing.assert_allclose(
        odom.pose, [1.0 + distance * math.cos(0.5), 2.0 + distance * math.sin(0.5), 0.5])
    assert odom.twist == pytest.approx((distance / 0.5, 0.0))
    assert odom.time == 1.5


@pytest.mark.parametrize('method', ODOMETRY_METHODS)
def test_spin_in_place(method):
    odom = fusion(integration_method=method)
    feed(odom, [(0, 0, 0.0), (-100, 100, 0.25)])
    turn = 200 * C_M / TRACK
    np.testing.assert_allclose(odom.pose, [0.0, 0.0, turn], atol=1e-15)
    assert odom.twist == pytest.approx((0.0, turn / 0.25))


@pytest.mark.parametrize('updates', [1, 7, 60, 333])
def test_constant_wheel_speeds_drive_the_exact_arc(updates):
    """
    10 left and 20 right counts per 0.1 s drive a circle of R = (b/2)(N_l + N_r)/(N_r - N_l).

    R = 0.2 * 30 / 10 = 0.6 m, v = 15 C_M / 0.1 s, ω = v / R; after t = n 0.1 s the pose is
    ((v/ω) sin ωt, (v/ω)(1 - cos ωt), ωt). 'exact_arc' reproduces it to 1e-9; the midpoint
    rule errs more, the slides' Euler update most.
    """
    v, radius = 15 * C_M / 0.1, 0.6
    omega, t = v / radius, 0.1 * updates
    expected = [radius * math.sin(omega * t), radius * (1.0 - math.cos(omega * t))]
    errors = {}
    for method in ODOMETRY_METHODS:
        odom = fusion(integration_method=method)
        feed(odom, [(10 * k, 20 * k, 0.1 * k) for k in range(updates + 1)])
        errors[method] = math.hypot(*(odom.pose[:2] - expected))
        assert math.remainder(odom.pose[2] - omega * t, math.tau) == pytest.approx(0.0,
                                                                                   abs=1e-12)
        assert odom.twist == pytest.approx((v, omega))
    assert errors['exact_arc'] < 1e-9
    assert 1e-9 < errors['midpoint'] < errors['euler']


def test_distance_variance_grows_by_k_distance_per_metre():
    # Straight along x: var(x) gains k_distance |Δs| at each step, nothing else reaches it.
    odom = fusion(odometry_noise=OdometryNoise(k_distance=0.002, k_heading=1e-4, k_turn=1e-3))
    feed(odom, [(100 * k, 100 * k, 0.1 * k) for k in range(11)])
    assert odom.covariance[0, 0] == pytest.approx(0.002 * 1000 * C_M, rel=1e-12)


def test_a_repeated_reading_is_answered_again_and_its_travel_counts_at_the_next():
    odom = fusion()
    estimates = feed(odom, [(0, 0, 0.0), (100, 100, 0.5), (150, 150, 0.5), (200, 200, 1.0)])
    assert [e.t for e in estimates] == [0.0, 0.5, 0.5, 1.0]
    assert estimates[2].pose[0] == pytest.approx(100 * C_M)
    assert odom.pose[0] == pytest.approx(200 * C_M)
    assert odom.twist[0] == pytest.approx(100 * C_M / 0.5)


def test_a_reading_older_than_the_estimate_is_ignored():
    odom = fusion()
    feed(odom, [(0, 0, 0.0), (100, 100, 1.0)])
    pose = odom.pose
    odom.add_encoders(500, 500, TICKS, 0.5)
    estimates, events = odom.update()
    assert estimates == []
    assert kinds(events) == ['time_went_back']
    assert (events[0].t, events[0].t_previous) == (0.5, 1.0)
    np.testing.assert_array_equal(odom.pose, pose)


def test_a_reading_sent_again_before_update_is_answered_once():
    odom = fusion()
    odom.add_encoders(0, 0, TICKS, 0.0)
    odom.add_encoders(0, 0, TICKS, 0.0)
    assert [e.t for e in odom.update()[0]] == [0.0]


@pytest.mark.parametrize(('left', 'right', 'ticks', 't', 'match'), [
    (0.5, 0, TICKS, 0.0, 'left_ticks'), (0, True, TICKS, 0.0, 'right_ticks'),
    (0, 0, 0, 0.0, 'ticks_per_revolution'), (0, 0, TICKS, math.nan, 't'),
])
def test_bad_encoder_reading_is_refused_and_not_queued(left, right, ticks, t, match):
    odom = fusion()
    with pytest.raises(ValueError, match=match):
        odom.add_encoders(left, right, ticks, t)
    assert odom.update() == ([], [])


# -- the gyro -----------------------------------------------------------------------------------

def test_gyro_turn_and_heading_variance_are_summed_sample_by_sample():
    """
    Spinning in place on the gyro: Δθ = Σ ω_k Δt_k, and var(Δθ) per reading.

    Two samples per encoder reading, each rate held over the 0.05 s since the previous sample:
    var(Δθ) = Σ σ_k² Δt_k² + k_turn |Δθ| + (σ_bias Δt)² with Δt = 0.1 s; the wheels do not
    roll, so the heading variance of the filter is the sum over the readings.
    """
    k_turn, bias = 2e-3, 0.01
    odom = fusion(heading_source='gyro', gyro_bias_stddev=bias,
                  odometry_noise=OdometryNoise(k_distance=1e-3, k_heading=1e-4, k_turn=k_turn))
    rates = [0.5, 0.7, -0.2, 0.4, 0.9, 0.1]                # [rad/s] at t = 0.05, 0.10, ...
    variances = [1e-4, 4e-4, 9e-4, 1e-4, 2e-4, 3e-4]        # [rad²/s²]
    feed(odom, [(0, 0, 0.0)])
    heading = variance = 0.0
    for k in range(3):
        for j in (2 * k, 2 * k + 1):
            assert odom.add_gyro(0.05 * (j + 1), rates[j], variances[j])
        odom.add_encoders(0, 0, TICKS, 0.1 * (k + 1))
        odom.update()
        turn = 0.05 * (rates[2 * k] + rates[2 * k + 1])
        heading += turn
        variance += (0.05 ** 2 * (variances[2 * k] + variances[2 * k + 1])
                     + k_turn * abs(turn) + (bias * 0.1) ** 2)
    np.testing.assert_allclose(odom.pose, [0.0, 0.0, heading], atol=1e-12)
    assert odom.covariance[2, 2] == pytest.approx(variance, rel=1e-12)
    assert odom.covariance[0, 0] == 0.0


def test_gyro_keeps_the_wheels_distance_and_takes_their_turn():
    # The wheels say a straight 1 m; the gyro a turn of 0.5 rad: an exact arc of R = 2 m.
    odom = fusion(heading_source='gyro')
    feed(odom, [(0, 0, 0.0)])
    odom.add_gyro(1.0, 0.5, 0.0)
    ticks = round(1.0 / C_M)
    odom.add_encoders(ticks, ticks, TICKS, 1.0)
    odom.update()
    distance = ticks * C_M
    radius = distance / 0.5
    np.testing.assert_allclose(odom.pose, [radius * math.sin(0.5),
                                           radius * (1.0 - math.cos(0.5)), 0.5], atol=1e-12)
    assert odom.twist == pytest.approx((distance, 0.5))


def test_reading_waits_for_the_gyro_sample_of_its_time():
    odom = fusion(heading_source='gyro')
    assert [e.t for e in feed(odom, [(0, 0, 0.0)])] == [0.0]
    odom.add_encoders(0, 0, TICKS, 0.1)
    assert odom.update() == ([], [])                     # no gyro sample of t = 0.1 s yet
    assert odom.add_gyro(0.1, 1.0, 0.0)
    estimates, events = odom.update()
    assert [e.t for e in estimates] == [0.1] and events == []
    assert odom.pose[2] == pytest.approx(0.1)


def test_first_reading_waits_for_a_gyro_to_be_connected():
    odom = fusion(heading_source='gyro')
    odom.add_encoders(0, 0, TICKS, 0.0)
    estimates, events = odom.update(gyro_connected=False)
    assert estimates == [] and kinds(events) == ['waiting_for_gyro']
    assert [e.t for e in odom.update(gyro_connected=True)[0]] == [0.0]


def test_reading_goes_on_without_its_gyro_sample_after_the_wait():
    odom = fusion(heading_source='gyro')
    feed(odom, [(0, 0, 0.0)])
    for k in range(1, GYRO_WAIT_READINGS + 1):
        odom.add_encoders(0, 0, TICKS, 0.1 * k)
        assert odom.update() == ([], [])
    odom.add_encoders(0, 0, TICKS, 0.1 * (GYRO_WAIT_READINGS + 1))
    estimates, events = odom.update()
    assert [e.t for e in estimates] == [pytest.approx(0.1)]
    assert kinds(events) == ['went_on_without_samples']


def test_gyro_samples_repeated_or_not_finite():
    odom = fusion(heading_source='gyro')
    assert odom.add_gyro(0.1, 0.5, 1e-4)
    assert not odom.add_gyro(0.1, 0.5, 1e-4)
    assert not odom.add_gyro(0.05, 0.5, 1e-4)
    with pytest.raises(ValueError, match='finite'):
        odom.add_gyro(0.2, math.nan, 1e-4)


def test_gyro_history_before_the_first_reading_is_dropped():
    odom = fusion(heading_source='gyro')
    odom.add_gyro(0.5, 10.0, 0.0)                         # replayed, before the start
    odom.add_gyro(1.1, 1.0, 0.0)
    feed(odom, [(0, 0, 1.0), (0, 0, 1.1)])
    assert odom.pose[2] == pytest.approx(0.1)


# -- corrections and their time alignment -------------------------------------------------------

def test_a_heading_newer_than_the_estimate_waits_until_a_reading_reaches_its_time():
    # P = 1 rad², R = 1 rad², innovation 1 rad: the heading moves by P / (P + R) = 1/2 of it.
    odom = fusion(covariance=np.diag([0.0, 0.0, 1.0]))
    feed(odom, [(0, 0, 0.0)])
    assert odom.add_heading(0.15, 1.0, 1.0) == []
    feed(odom, [(0, 0, 0.1)])
    assert odom.pose[2] == 0.0 and odom.covariance[2, 2] == pytest.approx(1.0)
    feed(odom, [(0, 0, 0.2)])
    assert odom.pose[2] == pytest.approx(0.5, abs=1e-12)
    assert odom.covariance[2, 2] == pytest.approx(0.5, abs=1e-12)


def test_a_fix_of_the_estimate_time_is_applied_at_once():
    odom = fusion(covariance=np.diag([1.0, 1.0, 0.0]))
    feed(odom, [(0, 0, 0.0)])
    assert odom.add_position(0.0, [2.0, 0.0], np.eye(2)) == []
    assert odom.pose[0] == pytest.approx(1.0, abs=1e-12)        # P / (P + R) = 1/2 of 2 m
    assert odom.covariance[0, 0] == pytest.approx(0.5, abs=1e-12)


def test_measurements_are_applied_in_time_order():
    # Two headings 1 rad apart, the later one added first: the last applied is the later one,
    # so the estimate ends nearer it. P = 1, R = 1 each: 1/2 of 1 rad, then 1/3 of (2 - 0.5).
    odom = fusion(covariance=np.diag([0.0, 0.0, 1.0]))
    feed(odom, [(0, 0, 0.0)])
    odom.add_heading(0.2, 2.0, 1.0)
    odom.add_heading(0.1, 1.0, 1.0)
    feed(odom, [(0, 0, 0.2)])
    assert odom.pose[2] == pytest.approx(0.5 + (2.0 - 0.5) / 3.0, abs=1e-12)


def test_measurements_older_than_the_first_reading_are_dropped():
    odom = fusion(covariance=np.diag([0.0, 0.0, 1.0]))
    odom.add_heading(0.5, 1.0, 1.0)
    odom.add_heading(0.6, 1.0, 1.0)
    odom.add_encoders(0, 0, TICKS, 1.0)
    estimates, events = odom.update()
    assert kinds(events) == ['stale_dropped'] and events[0].count == 2
    assert estimates[0].pose[2] == 0.0 and estimates[0].covariance[2, 2] == 1.0
    assert odom.add_heading(0.9, 1.0, 1.0) == []          # and later ones too
    assert odom.pose[2] == 0.0


def test_reading_waits_for_the_compass_reading_of_its_time():
    odom = fusion(covariance=np.diag([0.0, 0.0, 1.0]), wait_for_compass=True)
    feed(odom, [(0, 0, 0.0)])
    odom.add_encoders(0, 0, TICKS, 0.1)
    assert odom.update() == ([], [])
    assert odom.add_heading(0.1, 1.0, 1.0) == []          # waits for the reading of t = 0.1
    estimates, _ = odom.update()
    assert estimates[0].pose[2] == pytest.approx(0.5, abs=1e-12)


def test_an_unusable_heading_is_reported_and_still_releases_the_reading():
    odom = fusion(wait_for_compass=True)
    feed(odom, [(0, 0, 0.0)])
    odom.add_encoders(0, 0, TICKS, 0.1)
    events = odom.add_heading(0.1, 1.0, math.nan)
    assert kinds(events) == ['invalid_heading']
    assert [e.t for e in odom.update()[0]] == [0.1]
    assert odom.pose[2] == 0.0


def test_the_queue_drops_its_oldest_measurement_when_full():
    odom = fusion(covariance=np.diag([0.0, 0.0, 1.0]))
    feed(odom, [(0, 0, 0.0)])
    for k in range(PENDING_LIMIT):
        assert odom.add_heading(1.0 + 1e-3 * k, 0.0, 1.0) == []
    assert kinds(odom.add_heading(5.0, 1.0, 1.0)) == ['queue_full']


def test_a_refused_measurement_is_reported():
    odom = fusion(covariance=np.eye(3))
    feed(odom, [(0, 0, 0.0)])
    events = odom.add_position(0.0, [1.0, 0.0], [[1.0, 0.5], [0.0, 1.0]])   # not symmetric
    assert kinds(events) == ['refused'] and events[0].sensor == 'position'
    assert 'symmetric' in events[0].error
    np.testing.assert_array_equal(odom.pose, [0.0, 0.0, 0.0])


def test_filter_that_rejects_every_heading_is_reopened():
    """
    A certain heading of 0 against a compass at 1 rad with R = 1e-6 rad²: gated out.

    After max_rejections = 3 in a row the heading variance grows by the innovation squared,
    1 rad², and the update moves it by 1 / (1 + 1e-6) of the innovation.
    """
    odom = fusion(max_rejections=3)
    feed(odom, [(0, 0, 0.0)])
    events = [e for _ in range(3) for e in odom.add_heading(0.0, 1.0, 1e-6)]
    assert kinds(events) == ['rejected', 'rejected', 'rejected', 'reopened']
    assert [e.count for e in events[:3]] == [1, 2, 3]
    assert events[-1].applied and events[-1].sensor == 'heading'
    assert odom.pose[2] == pytest.approx(1.0 / (1.0 + 1e-6), abs=1e-9)
    assert odom.rejections == 3


def test_fix_with_the_gps_error_as_a_state():
    # σ_b = 0.3 m with a white σ_w = 0.1 m: the fix's white part R = σ_w² I enters the update,
    # and z = x + b: with P_x = 1 m², var(b) = 0.09 m², the position moves by
    # P_x / (P_x + σ_b² + σ_w²) of the 1 m innovation.
    odom = fusion(covariance=np.diag([1.0, 1.0, 0.0]), gps_bias_stddev=0.3,
                  gps_bias_correlation_time=30.0, gps_white_stddev=0.1)
    feed(odom, [(0, 0, 0.0)])
    odom.add_position(0.0, [1.0, 0.0], np.eye(2))
    assert odom.pose[0] == pytest.approx(1.0 / (1.0 + 0.09 + 0.01), abs=1e-12)


def test_reset_forgets_everything():
    odom = fusion(heading_source='gyro')
    feed(odom, [(0, 0, 0.0)])
    odom.add_gyro(0.1, 1.0, 0.0)
    odom.add_encoders(0, 0, TICKS, 0.2)
    odom.reset([1.0, 2.0, 3.0], ZERO)
    assert odom.time is None and odom.twist == (0.0, 0.0)
    np.testing.assert_array_equal(odom.pose, [1.0, 2.0, 3.0])
    assert odom.update() == ([], [])
    assert [e.t for e in feed(odom, [(5, 5, 7.0)])] == [7.0]


# -- parameters ---------------------------------------------------------------------------------

@pytest.mark.parametrize(('field', 'value'), [
    ('wheel_radius', 0.0), ('wheel_separation', -0.4), ('wheel_radius', math.inf),
    ('integration_method', 'rk4'), ('heading_source', 'stars'),
    ('gyro_bias_stddev', -1.0), ('gps_bias_stddev', math.nan), ('gps_white_stddev', -0.1),
    ('gps_bias_correlation_time', 0.0), ('max_rejections', 0), ('max_rejections', 2.5),
    ('odometry_noise', 1e-3),
])
def test_params_reject_bad_values(field, value):
    with pytest.raises(ValueError, match=field):
        OdometryFusionParams(**{field: value})


def test_constructor_rejects_bad_pose():
    with pytest.raises(ValueError, match='pose'):
        fusion(pose=(0.0, 0.0))


# -- stamps and travels that jump ---------------------------------------------------------------

def _straight(t0, n, dt=0.02, start_ticks=0, step=10):
    """Return readings of a straight drive: ``step`` ticks per wheel each ``dt`` from ``t0``."""
    return [(start_ticks + step * k, start_ticks + step * k, t0 + dt * k) for k in range(n)]


def test_one_absurd_future_stamp_is_refused_and_changes_nothing():
    # The wedge: one reading stamped sec = 2**31 - 1 amid 50 Hz readings.
    odom, reference = fusion(), fusion()
    valid = _straight(1.0, 101)
    feed(odom, valid[:50])
    feed(reference, valid[:50])
    odom.add_encoders(10_000, 10_000, TICKS, float(2 ** 31 - 1))
    estimates, events = odom.update()
    assert estimates == [] and kinds(events) == ['time_jumped']
    answered = feed(odom, valid[50:])
    assert [e.t for e in answered] == [t for _, _, t in valid[50:]]   # none ignored
    feed(reference, valid[50:])
    np.testing.assert_array_equal(odom.pose, reference.pose)
    assert odom.pose[0] == pytest.approx(100 * 10 * C_M, rel=1e-12)


@pytest.mark.parametrize('absurd', [-(2.0 ** 31), 1e15, 1.0 + MAX_TIME_JUMP * 1.01])
def test_an_absurd_gyro_compass_or_fix_stamp_is_refused(absurd):
    odom = fusion(heading_source='gyro', covariance=np.eye(3))
    odom.add_gyro(0.0, 0.0, 0.0)
    feed(odom, [(0, 0, 0.0)])
    with pytest.raises(ValueError, match='from the encoder time'):
        odom.add_gyro(absurd, 1.0, 0.0)
    assert kinds(odom.add_heading(absurd, 0.0, 1.0)) == ['time_jumped']
    assert kinds(odom.add_position(absurd, [0.0, 0.0], np.eye(2))) == ['time_jumped']
    assert odom.add_gyro(0.02, 0.5, 0.0)   # the next valid sample is new and counts
    feed(odom, [(10, 10, 0.02)])
    assert odom.pose[2] == pytest.approx(0.5 * 0.02, rel=1e-12)


def test_a_first_reading_with_an_absurd_stamp_is_left_after_three_agreeing_ones():
    odom = fusion()
    feed(odom, [(0, 0, 1e9)])
    events = []
    for reading in _straight(1.0, 3, start_ticks=0):
        odom.add_encoders(reading[0], reading[1], TICKS, reading[2])
        events += odom.update()[1]
    assert kinds(events) == ['time_jumped', 'time_jumped', 'time_restarted']
    assert odom.time == pytest.approx(1.04)
    # The base is the first agreeing reading (t = 1.0, 0 ticks): 20 ticks by 1.04, 20 more.
    feed(odom, [(40, 40, 1.06)])
    assert odom.pose[0] == pytest.approx(40 * C_M, rel=1e-12)
    assert odom.twist[0] == pytest.approx(20 * C_M / 0.02, rel=1e-9)


def test_a_travel_faster_than_the_bound_is_refused_until_three_confirm_it():
    odom = fusion()
    feed(odom, _straight(0.0, 3))
    x = odom.pose[0]
    # 2**31 ticks of a 0.1 m wheel in 0.02 s: about 6.7e5 km/s.
    odom.add_encoders(2 ** 31 - 1, 2 ** 31 - 1, TICKS, 0.06)
    assert kinds(odom.update()[1]) == ['travel_refused']
    feed(odom, [(40, 40, 0.08)])   # the next valid reading: 10 ticks per 0.02 s since 0.04
    assert odom.pose[0] == pytest.approx(x + 20 * C_M, rel=1e-12)
    events = []
    for k in range(3):   # an encoder reset to 0: three readings in a row, then the new base
        odom.add_encoders(10 ** 7 + k, 10 ** 7 + k, TICKS, 0.1 + 0.02 * k)
        events += odom.update()[1]
    assert kinds(events) == ['travel_refused', 'travel_refused', 'ticks_rebased']
    assert odom.pose[0] == pytest.approx(x + 20 * C_M, rel=1e-12)


# -- per-wheel radius errors (the systematic errors of a UMBmark test) --------------------------

@pytest.mark.parametrize('e_left, e_right, track_error', [
    (-0.01, 0.01, 0.0), (0.004, -0.002, 0.05), (0.0, 0.003, -0.02)])
def test_unequal_nominal_radii_bend_a_straight_run_into_the_predicted_arc(
        e_left, e_right, track_error):
    """
    A straight true run, read with nominal radii c (1 + e_L) and c (1 + e_R), is an arc.

    Both true wheels (radius c) turn by the same angle φ, so the robot goes straight for
    D = c φ and each encoder counts n = TICKS φ / 2π. The odometry converts the counts with its
    own radii (C_m = 2π c_i / TICKS): U_L = 2π c (1 + e_L) n / TICKS = D (1 + e_L) and
    U_R = D (1 + e_R). With the nominal track b_n = b (1 + e_b), slides §13.6 / book (4.110)
    give the heading change Δθ = (U_R - U_L) / b_n = D (e_R - e_L) / b_n and (4.109) the
    distance s = (U_L + U_R) / 2 = D (1 + (e_L + e_R) / 2). Every reading has the same ratio,
    so the estimate moves on one circle of radius R = s / Δθ = b_n (1 + (e_L + e_R)/2) /
    (e_R - e_L), Δθ = s (e_R - e_L) / (b_n (1 + (e_L + e_R) / 2)) as a function of the
    estimated distance; from (0, 0, 0) its end is x = R sin Δθ, y = R (1 - cos Δθ),
    θ = Δθ, and every intermediate estimate lies on the circle of centre (0, R) (the exact
    arc (4.93) composes exactly).
    """
    c_left, c_right = RADIUS * (1 + e_left), RADIUS * (1 + e_right)
    b_n = TRACK * (1.0 + track_error)
    odom = OdometryFusion(OdometryFusionParams(
        wheel_radius=RADIUS, wheel_separation=b_n, left_wheel_radius=c_left,
        right_wheel_radius=c_right), (0.0, 0.0, 0.0), ZERO)
    step, readings = 250, 80          # counts per reading on both wheels: 20 000 in all
    estimates = feed(odom, [(k * step, k * step, 0.1 * k) for k in range(readings + 1)])
    D = 2.0 * math.pi * RADIUS * step * readings / TICKS          # true straight run [m]
    turn = D * (e_right - e_left) / b_n
    s = D * (1.0 + 0.5 * (e_left + e_right))
    R = s / turn
    assert estimates[-1].pose == pytest.approx(
        [R * math.sin(turn), R * (1.0 - math.cos(turn)), turn], abs=1e-9)
    for estimate in estimates:
        x, y, _ = estimate.pose
        assert math.hypot(x, y - R) == pytest.approx(abs(R), rel=1e-9)


def test_zero_per_wheel_radii_mean_the_common_radius():
    params = OdometryFusionParams(wheel_radius=RADIUS, left_wheel_radius=0.0,
                                  right_wheel_radius=0.12)
    assert params.wheel_radii == (RADIUS, 0.12)
    with pytest.raises(ValueError, match='left_wheel_radius'):
        OdometryFusionParams(left_wheel_radius=-0.1)
