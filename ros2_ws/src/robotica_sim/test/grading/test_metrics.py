"""
Tests of robotica_sim.grading.metrics on synthetic runs with closed-form metrics.

Reference values come from the signals' definitions, not from the code: a constant offset of
0.1 m has RMS 0.1 m; A sin over whole periods has RMS A / sqrt(2); an exponential error
e^(-t) enters a 2 % band at ln 50 s; the step response of a second-order system with damping
zeta overshoots by exp(-zeta pi / sqrt(1 - zeta^2)); the integral of |2 sin t| over a period
is 8; a 2R arm (l1 = 3 m, l2 = 1 m) bent by 90 deg at the elbow moves its tip by sqrt(2) m;
a parking run's final pose error is hypot(0.3, 0.4) = 0.5 m and 90 - 80 = 10 deg; its
manoeuvres are counted by hand, or by grouping the signs of the moving samples.
"""
from dataclasses import replace
import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import circle, figure_eight, straight_line
from robotica_sim.grading.metrics import (compute_metrics, contact_events, energy,
                                          MetricParams, METRICS, normal_fit, overshoot,
                                          path_errors, reading_error, rms, settling_time,
                                          total_variation, travel_stretches)
from robotica_sim.grading.rubric import check_metrics, parse_rubric
from robotica_sim.grading.series import RunSeries, Series, TOPICS


def make_run(scenario=None, duration=0.0, path=None, path_times=None, **series):
    """Return a RunSeries with the given series; counts as a bag of them would have."""
    roles = {'truth': 'truth', 'odom': 'odom', 'tracking_error': 'tracking_error',
             'joint_states': 'joint_states', 'controller': 'controller', 'torques': 'torques',
             'bumper': 'bumper'}
    counts = {TOPICS[roles[name]]: len(s) for name, s in series.items() if name in roles}
    cmd = series.get('cmd')
    if cmd is not None:
        counts[TOPICS['cmd_vel' if 'w' in cmd.columns else 'vehicle_command']] = len(cmd)
    if path is not None:
        counts[TOPICS['path']] = 1
    if duration:
        counts[TOPICS['clock']] = 1
    fields = {name: series.get(name) for name in (
        'truth', 'odom', 'cmd', 'tracking_error', 'imu', 'compass', 'gps', 'joint_states',
        'controller', 'torques', 'bumper')}
    return RunSeries(bag=Path('synthetic'), scenario=scenario, duration=duration, counts=counts,
                     path=None if path is None else np.asarray(path, dtype=float),
                     path_times=path_times, status=None, **fields)


def pose_series(t, x, y, theta, **extra):
    n = len(t)
    columns = {'x': np.asarray(x, dtype=float), 'y': np.asarray(y, dtype=float),
               'theta': np.asarray(theta, dtype=float), 'v': np.ones(n), 'vy': np.zeros(n),
               'w': np.zeros(n)}
    columns.update({k: np.asarray(v, dtype=float) for k, v in extra.items()})
    return Series(np.asarray(t, dtype=float), columns)


STRAIGHT = [[0.0, 0.0], [10.0, 0.0]]


def test_constant_offset_from_a_straight_path():
    t = np.linspace(0.0, 4.0, 41)
    truth = pose_series(t, t, np.full(41, 0.1), np.zeros(41))
    m = compute_metrics(make_run(truth=truth, path=STRAIGHT, duration=4.0)).values
    assert m['rms_cross_track'] == pytest.approx(0.1, abs=1e-12)
    assert m['max_cross_track'] == pytest.approx(0.1, abs=1e-12)
    assert m['rms_heading_error'] == 0.0 and m['max_heading_error'] == 0.0
    assert m['completion'] == pytest.approx(0.4)       # 4 m of the 10 m path
    assert m['finished'] is False
    assert m['path_length'] == pytest.approx(4.0)
    assert m['time'] == 4.0
    assert 'collisions' not in m and 'time_in_contact' not in m   # no world: no /bumper


def test_sine_error_has_rms_amplitude_over_sqrt_2():
    amplitude, period, n = 0.3, 2.0, 400           # 4 whole periods, 100 samples each
    t = np.arange(n) * (4 * period / n)
    y = amplitude * np.sin(2 * math.pi * t / period)
    heading = 0.2 * np.cos(2 * math.pi * t / period)
    truth = pose_series(t, 0.5 * t, y, heading)
    m = compute_metrics(make_run(truth=truth, path=STRAIGHT)).values
    assert m['rms_cross_track'] == pytest.approx(amplitude / math.sqrt(2), rel=1e-12)
    assert m['max_cross_track'] == pytest.approx(amplitude, rel=1e-12)
    assert m['rms_heading_error'] == pytest.approx(0.2 / math.sqrt(2), rel=1e-12)
    assert 'time' not in m                         # no /clock: absent, not zero


def test_a_closed_path_is_followed_lap_by_lap():
    square = [[0, 0], [2, 0], [2, 2], [0, 2], [0, 0]]
    # One lap on the square, 0.05 m inside (left of travel), back at the start.
    s = np.linspace(0.0, 8.0, 161)
    corners = np.array(square, dtype=float)
    x = np.interp(s, [0, 2, 4, 6, 8], corners[:, 0])
    y = np.interp(s, [0, 2, 4, 6, 8], corners[:, 1])
    x_in = np.clip(x, 0.05, 1.95)
    y_in = np.clip(y, 0.05, 1.95)
    lap = compute_metrics(make_run(truth=pose_series(s, x_in, y_in, np.zeros(161)),
                                   path=square)).values
    # The last pose (0.05, 0.05) projects onto the last segment at s = 8 - 0.05; a search
    # over the whole path would find the first segment (s = 0.05) instead.
    assert lap['completion'] == pytest.approx(7.95 / 8) and lap['finished'] is True
    assert lap['rms_cross_track'] == pytest.approx(0.05)   # 0.05 m inside everywhere
    half = compute_metrics(make_run(truth=pose_series(s[:81], x[:81], y[:81],
                                                      np.zeros(81)), path=square)).values
    assert half['completion'] == pytest.approx(0.5) and half['finished'] is False


def test_finished_needs_both_the_arc_length_and_the_distance():
    t = np.linspace(0.0, 1.0, 11)
    near = pose_series(t, 9.0 + t * 0.95, np.zeros(11), np.zeros(11))
    assert compute_metrics(make_run(truth=near, path=STRAIGHT)).values['finished'] is True
    params = MetricParams(goal_tolerance=0.01)
    assert compute_metrics(make_run(truth=near, path=STRAIGHT),
                           params).values['finished'] is False


def test_a_timed_path_gives_the_trajectory_error():
    t = np.linspace(0.0, 2.0, 21)
    path = np.column_stack([t, np.zeros(21)])
    truth = pose_series(t, t - 0.3, np.full(21, 0.4), np.zeros(21))  # 0.3 behind, 0.4 aside
    m = compute_metrics(make_run(truth=truth, path=path, path_times=t)).values
    assert m['rms_trajectory_error'] == pytest.approx(0.5)
    assert m['max_trajectory_error'] == pytest.approx(0.5)


def test_tracking_error_topic_is_used_without_truth():
    t = np.linspace(0.0, 1.0, 5)
    topic = Series(t, {'cross_track': np.array([0.1, -0.1, 0.1, -0.1, 0.1]),
                       'heading': np.full(5, -0.3), 'along_track': np.zeros(5),
                       'target_x': t, 'target_y': np.zeros(5)})
    m = compute_metrics(make_run(tracking_error=topic))
    assert m.values['rms_cross_track'] == pytest.approx(0.1)
    assert m.values['max_heading_error'] == pytest.approx(0.3)
    assert 'path_tracker/tracking_error' in m.notes['rms_cross_track']
    assert m.absent['completion'] == ('needs topics /ground_truth/odom and /path, which the '
                                      'bag lacks')


def test_control_effort_of_commands():
    t = np.arange(201) * 0.01                      # two whole periods of 1 s, both ends
    w = np.sin(2 * math.pi * t)
    twist = Series(t, {'v': np.ones(201), 'w': w})
    m = compute_metrics(make_run(cmd=twist)).values
    # sum of sin^2 over 100 samples of a period is 50: 100 over 201 samples
    assert m['rms_angular_command'] == pytest.approx(math.sqrt(100 / 201), rel=1e-12)
    # sampled at its peaks (t = 0.25 + k/2): 0 -> 1 -> -1 -> 1 -> -1 -> 0, total 8
    assert m['angular_command_variation'] == pytest.approx(8.0, rel=1e-12)
    steering = Series(t[:3], {'v': np.ones(3), 'steering': np.array([0.0, 0.2, -0.1]),
                              'steering_rate': np.zeros(3)})
    m = compute_metrics(make_run(cmd=steering)).values
    assert m['rms_steering'] == pytest.approx(math.sqrt(0.05 / 3))
    assert m['steering_variation'] == pytest.approx(0.5)
    assert 'rms_angular_command' not in m


def test_estimation_errors_against_interpolated_truth():
    t = np.linspace(0.0, 1.0, 11)                   # truth: x = t, heading near pi
    truth = pose_series(t, t, np.zeros(11), np.full(11, 3.1))
    t_odom = np.linspace(0.05, 0.95, 10)            # between the truth samples
    var_x = np.where(np.arange(10) < 5, 0.1 ** 2, 0.05 ** 2)   # 3 sigma: 0.3 m, then 0.15 m
    odom = pose_series(t_odom, t_odom + 0.2, np.zeros(10), np.full(10, -3.1),
                       var_x=var_x, var_y=np.full(10, 1.0), var_theta=np.full(10, 1.0))
    m = compute_metrics(make_run(truth=truth, odom=odom)).values
    assert m['rms_position_error'] == pytest.approx(0.2)
    assert m['max_position_error'] == pytest.approx(0.2)
    assert m['rms_odom_heading_error'] == pytest.approx(2 * math.pi - 6.2)   # wrapped
    assert m['within_3_sigma'] == pytest.approx(0.5)
    no_cov = pose_series(t_odom, t_odom, np.zeros(10), np.full(10, 3.1), var_x=np.zeros(10),
                         var_y=np.zeros(10), var_theta=np.zeros(10))
    result = compute_metrics(make_run(truth=truth, odom=no_cov))
    assert result.values['within_3_sigma'] is None
    assert 'covariance' in result.notes['within_3_sigma']
    assert result.values['rms_position_error'] == pytest.approx(0.0, abs=1e-12)


def controller_series(t, q_d, e):
    z = np.zeros_like(q_d)
    return Series(t, {'reference_position': q_d, 'reference_velocity': z,
                      'position_error': e, 'velocity_error': z, 'effort': z},
                  ('joint_1', 'joint_2'))


def test_arm_errors_settling_and_overshoot():
    t = np.arange(0, 8001) * 0.001                  # 8 s at 1 kHz
    zeta, wn = 0.5, 2.0
    wd = wn * math.sqrt(1 - zeta ** 2)
    ratio = zeta / math.sqrt(1 - zeta ** 2)
    step = 1.0 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + ratio * np.sin(wd * t))
    q_d = np.column_stack([np.ones_like(t), np.ones_like(t)])
    q = np.column_stack([1.0 - np.exp(-t), step])   # joint 1: e = e^-t; joint 2: 2nd order
    m = compute_metrics(make_run(controller=controller_series(t, q_d, q_d - q))).values
    assert m['rms_joint_error'][0] == pytest.approx(math.sqrt((1 - math.exp(-16)) / 16),
                                                    rel=1e-3)
    assert m['max_joint_error'][0] == pytest.approx(1.0)
    assert m['settling_time'][0] == pytest.approx(math.log(50), abs=0.001)
    assert m['overshoot'][1] == pytest.approx(
        100 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2)), rel=1e-4)
    assert m['overshoot'][0] == pytest.approx(0.0)  # e^-t never passes the set point
    assert 'rms_cartesian_error' in compute_metrics(make_run(
        controller=controller_series(t, q_d, q_d - q))).absent


def test_a_moving_reference_has_no_overshoot_and_may_not_settle():
    t = np.linspace(0.0, 4.0, 401)
    q_d = np.column_stack([0.15 * np.sin(t), 0.15 * np.sin(t)])
    e = np.column_stack([0.1 * np.sin(3 * t), np.zeros_like(t)])
    result = compute_metrics(make_run(controller=controller_series(t, q_d, e)))
    assert result.values['overshoot'] == [None, None]
    assert result.values['settling_time'] == [None, 0.0]
    assert 'band' in result.notes['settling_time']


def test_cartesian_error_of_the_two_link_arm():
    scenario = {'arm': {'model': 'two_link_arm', 'masses': [2.0, 1.0], 'lengths': [3.0, 1.0]}}
    t = np.linspace(0.0, 1.0, 3)
    q_d = np.zeros((3, 2))                           # tip at (4, 0)
    e = np.tile([0.0, math.pi / 2], (3, 1))          # q = [0, -pi/2]: tip at (3, -1)
    m = compute_metrics(make_run(scenario=scenario,
                                 controller=controller_series(t, q_d, e))).values
    assert m['rms_cartesian_error'] == pytest.approx(math.sqrt(2))
    assert m['max_cartesian_error'] == pytest.approx(math.sqrt(2))


def test_peak_torque_and_energy():
    t = np.linspace(0.0, 2 * math.pi, 20001)
    torques = Series(t, {'effort': np.column_stack([np.full_like(t, 2.0), -np.full_like(t, 3.0)])})
    joints = Series(t, {'position': np.zeros((len(t), 2)),
                        'velocity': np.column_stack([np.sin(t), np.zeros_like(t)]),
                        'effort': np.zeros((len(t), 0))}, ('joint_1', 'joint_2'))
    m = compute_metrics(make_run(torques=torques, joint_states=joints)).values
    assert m['peak_torque'] == [2.0, 3.0]
    assert m['energy'] == pytest.approx(8.0, rel=1e-6)
    result = compute_metrics(make_run(torques=torques))
    assert result.absent['energy'] == 'needs topic /joint_states, which the bag lacks'


def test_absent_metrics_name_the_missing_topic():
    t = np.linspace(0.0, 1.0, 3)
    result = compute_metrics(make_run(truth=pose_series(t, t, 0 * t, 0 * t)))
    assert result.absent['max_position_error'] == 'needs topic /odom, which the bag lacks'
    assert result.absent['rms_cross_track'].startswith('needs topic /path, which the bag lacks')
    assert result.absent['peak_torque'] == 'needs topic /joint_torques, which the bag lacks'
    assert set(result.values) | set(result.absent) == set(METRICS)


def test_helpers_against_hand_values():
    assert total_variation([0.0, 2.0, 1.0, 1.0]) == 3.0
    assert settling_time([0.0, 0.5, 1.0], [0.5, 0.01, 0.0], 0.02) == 0.5
    assert overshoot([2.0, 0.5, 0.8, 1.0], 1.0) == pytest.approx(50.0)   # downward move
    assert overshoot([1.0, 1.0], 1.0) is None
    assert energy([0.0, 2.0], [[1.0, 1.0], [1.0, 1.0]], [[1.0, -2.0], [1.0, -2.0]]) == 6.0


@pytest.mark.parametrize('field, value', [('goal_tolerance', 0.0), ('search_window', -1.0),
                                          ('settling_band', 1.0), ('sigma_bound', math.nan),
                                          ('stop_speed', 0.0), ('stop_speed', True)])
def test_params_are_checked(field, value):
    with pytest.raises(ValueError, match=field):
        MetricParams(**{field: value})


def reference_rms(values):
    """Root mean square, written here for the reference values."""
    return math.sqrt(sum(v * v for v in np.ravel(values)) / np.size(values))


def test_rms_of_hand_values_and_of_nothing():
    assert rms([3.0, 4.0]) == pytest.approx(math.sqrt(12.5))   # sqrt((9 + 16) / 2)
    assert rms([0.1, -0.1, 0.1]) == pytest.approx(0.1)         # the sign does not count
    assert rms(np.full((3, 2), -2.0)) == 2.0                   # every element of any shape
    assert math.isnan(rms([]))
    assert math.isnan(rms([1.0, math.nan]))


def test_path_errors_left_and_right_of_a_line_and_wrapped_heading():
    line = PolylinePath(straight_line([0.0, 0.0], [10.0, 0.0]))
    x = np.linspace(0.5, 9.5, 50)
    s, cross, heading = path_errors(line, x, np.full(50, 0.1), np.zeros(50), 1.0)
    np.testing.assert_allclose(s, x, atol=1e-12)
    np.testing.assert_allclose(cross, 0.1, atol=1e-12)
    np.testing.assert_allclose(heading, 0.0, atol=1e-12)
    _, cross, heading = path_errors(line, [1.0, 2.0], [-0.2, -0.2],
                                    [0.3, 3.0 * math.pi - 0.1], 1.0)
    np.testing.assert_allclose(cross, [-0.2, -0.2])
    np.testing.assert_allclose(heading, [0.3, math.pi - 0.1])


def test_path_errors_outside_a_counter_clockwise_circle_is_right_of_it():
    # 0.1 m outside a circle of radius 2 m, heading along its tangent: e = -0.1 m, psi = 0
    # up to the polyline's chords (sagitta r (1 - cos(0.0125)) = 0.16 mm, half-angle
    # 0.0125 rad of a 0.05 m segment).
    path = PolylinePath(circle([0.0, 0.0], 2.0))
    angles = np.linspace(0.0, 2.0 * math.pi, 200, endpoint=False)
    _, cross, heading = path_errors(path, 2.1 * np.cos(angles), 2.1 * np.sin(angles),
                                    angles + math.pi / 2, 1.0)
    np.testing.assert_allclose(cross, -0.1, atol=2e-4)
    np.testing.assert_allclose(heading, 0.0, atol=0.013)


def figure_eight_offset(radius, offset, start, stop, step=0.01):
    """
    Poses ``offset`` [m] left of the figure eight of ``radius`` [m], arc lengths start..stop.

    Written here from the shape's definition (path_shapes.figure_eight's docstring): from the
    origin heading +x, the upper circle (centre (0, r)) counter-clockwise, then the lower one
    (centre (0, -r)) clockwise; left of the upper circle is inward (radius r - offset), left
    of the lower one outward (radius r + offset). Arc lengths are of the path (0..4 pi r),
    taken modulo its length, so that a start before 0 is behind the crossing.
    """
    length = 4.0 * math.pi * radius
    poses = []
    for s in np.arange(start, stop, step):
        s %= length
        if s < 0.5 * length:   # upper circle, counter-clockwise from the bottom
            a = -0.5 * math.pi + s / radius
            rho = radius - offset
            poses.append((rho * math.cos(a), radius + rho * math.sin(a), a + 0.5 * math.pi))
        else:                  # lower circle, clockwise from the top
            a = 0.5 * math.pi - (s - 0.5 * length) / radius
            rho = radius + offset
            poses.append((rho * math.cos(a), -radius + rho * math.sin(a), a - 0.5 * math.pi))
    return np.array(poses)


@pytest.mark.parametrize('start', [-0.001, 0.0, 0.75 * 4.0 * math.pi * 2.0, 0.3 * 8.0 * math.pi])
def test_figure_eight_offset_is_measured_on_the_lobe_it_drives(start):
    # 0.1 m left of the 2 m figure eight for one lap from ``start`` [m of arc length]: from
    # 1 mm behind the crossing (where the closest point of the path is on the other lobe's
    # end as much as on this lobe's start), from the crossing, from the far (lower) lobe and
    # from the upper one. RMS cross-track 0.100 m up to the chords (0.16 mm, as above).
    path = PolylinePath(figure_eight(2.0))
    poses = figure_eight_offset(2.0, 0.1, start, start + path.length - 0.01)
    _, cross, heading = path_errors(path, poses[:, 0], poses[:, 1], poses[:, 2], 2.0)
    assert reference_rms(cross) == pytest.approx(0.100, abs=5e-4)
    np.testing.assert_allclose(cross, 0.1, atol=1e-3)
    assert np.max(np.abs(heading)) < 0.03   # the chords' heading steps (0.025 rad)


def test_path_errors_starts_at_the_start_of_a_closed_path_not_its_end():
    # A circle starts and ends at the same point: progress 0, not the end (where it could
    # not advance), so that the lap is followed.
    path = PolylinePath(circle([0.0, 0.0], 1.0, start_angle=-0.5 * math.pi))
    angles = np.linspace(-0.5 * math.pi, 1.0 * math.pi, 100)
    s, cross, _ = path_errors(path, np.cos(angles), np.sin(angles), angles + 0.5 * math.pi, 0.5)
    assert s[0] == pytest.approx(0.0, abs=1e-9)
    assert s[-1] == pytest.approx(1.5 * math.pi, rel=1e-3)
    np.testing.assert_allclose(cross, 0.0, atol=4e-4)   # sagitta 1 (1 - cos(0.025))


@pytest.mark.parametrize('x, y, theta, window', [
    ([], [], [], 1.0), ([0.0, 1.0], [0.0], [0.0, 0.0], 1.0), ([math.nan], [0.0], [0.0], 1.0),
    ([0.0], [0.0], [0.0], 0.0), ([0.0], [0.0], [0.0], math.inf)])
def test_path_errors_refuses_bad_input(x, y, theta, window):
    with pytest.raises(ValueError):
        path_errors(PolylinePath([[0.0, 0.0], [1.0, 0.0]]), x, y, theta, window)


# --- sensor errors (the report's sensor figures) ------------------------------------------

def test_reading_error_of_a_line_and_outside_the_truth():
    t_truth = np.array([0.0, 1.0, 2.0])
    truth = 3.0 * t_truth - 1.0                     # a line: interpolation is exact
    error = reading_error([0.25, 1.5, 2.5, -0.1], [0.0, 4.0, 0.0, 0.0], t_truth, truth)
    np.testing.assert_allclose(error[:2], [0.0 - (-0.25), 4.0 - 3.5])
    assert np.isnan(error[2:]).all()


def test_reading_error_of_angles_across_pi():
    # The truth turns through π at 1 rad/s, 3.0 -> 3.2 rad, stored wrapped (3.2 - 2π); at
    # t = 0.1 s it is 3.1 rad. A reading of π + 0.05 rad, stored as 0.05 - π, is 0.0916 rad
    # ahead; another of 3.0 rad is 0.1 rad behind.
    t_truth = np.array([0.0, 0.2])
    truth = np.array([3.0, 3.2 - 2.0 * math.pi])
    error = reading_error([0.1, 0.1], [0.05 - math.pi, 3.0], t_truth, truth, angle=True)
    np.testing.assert_allclose(error, [math.pi + 0.05 - 3.1, -0.1], atol=1e-12)


def test_normal_fit_of_known_samples():
    mean, std, count = normal_fit([2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0, float('nan')])
    assert (mean, count) == (5.0, 8)
    assert std == pytest.approx(math.sqrt(32.0 / 7.0))
    assert normal_fit([1.0])[0] == 1.0 and math.isnan(normal_fit([1.0])[1])


def test_collisions_and_time_in_contact_from_the_bumper():
    # 51 steps of 20 ms; touching at samples 10-19 and 30-50 (the end): 2 contacts, and the
    # steps that began in contact are 10 + 20 = 30, 0.6 s.
    t = np.arange(51) * 0.02
    touching = np.zeros(51)
    touching[10:20] = touching[30:] = 1.0
    run = make_run(bumper=Series(t, {'in_contact': touching}), duration=1.0)
    metrics = compute_metrics(run)
    assert metrics.values['collisions'] == 2
    assert metrics.values['time_in_contact'] == pytest.approx(0.6, abs=1e-12)
    (check,) = check_metrics(parse_rubric({'checks': {'collisions': {'max': 0}}}), metrics, None)
    assert not check.passed and check.message == 'collisions = 2, want <= 0'
    free = compute_metrics(make_run(bumper=Series(t, {'in_contact': np.zeros(51)})))
    assert free.values['collisions'] == 0 and free.values['time_in_contact'] == 0.0


def test_collisions_are_absent_without_a_bumper_topic():
    absent = compute_metrics(make_run(duration=1.0)).absent
    assert absent['collisions'] == absent['time_in_contact'] == (
        'needs topic /bumper, which the bag lacks (the simulator publishes it when the run '
        'has a world)')


def test_a_robot_touching_from_the_start_is_one_contact():
    assert contact_events([0.0, 0.02, 0.04], [1, 1, 1]) == (1, 0.04)
    assert contact_events([0.0], [0]) == (0, 0.0)


# --- a parking run: the final pose against the last /path pose, and the manoeuvres ----------

def speed_run(v, dt=0.1):
    """Return a run whose truth has the longitudinal speeds ``v`` [m/s] every ``dt`` [s]."""
    v = np.asarray(v, dtype=float)
    t = np.arange(len(v)) * dt
    return make_run(truth=pose_series(t, np.zeros(len(v)), np.zeros(len(v)), np.zeros(len(v)),
                                      v=v))


def parking_profile(stop=(0.0, 0.0, 0.0)):
    """Forward, stop, reverse, stop, reverse, stop, forward: 3 manoeuvres (by hand)."""
    return np.concatenate([np.full(20, 0.5), stop, np.full(15, -0.4), stop,
                           np.full(10, -0.3), stop, np.full(5, 0.2)])


def test_forward_reverse_reverse_forward_is_three_manoeuvres():
    # The stop between the two reverse arcs (wheels re-oriented) starts no new manoeuvre.
    metrics = compute_metrics(speed_run(parking_profile()))
    assert metrics.values['manoeuvres'] == 3
    checks = parse_rubric({'checks': {'manoeuvres': {'max': 4}}})
    assert [c.passed for c in check_metrics(checks, metrics, None)] == [True]
    (failed,) = check_metrics(parse_rubric({'checks': {'manoeuvres': {'max': 2}}}), metrics,
                              None)
    assert not failed.passed and failed.message == 'manoeuvres = 3, want <= 2'


def test_noise_below_the_stop_speed_adds_no_manoeuvre():
    # The three stops jitter around zero, both signs, |v| < stop_speed 0.01 m/s.
    jitter = parking_profile((-0.005, 0.0099, -0.009))
    assert compute_metrics(speed_run(jitter)).values['manoeuvres'] == 3
    # With a stop speed below the jitter (a rubric's parameter), the jitter's signs count:
    # + | - + - | - | - + - | - | - + - | + collapses to + - + - - - + - - - + - +, whose sign
    # changes are 3 + 2 + 3 = 8: 9 stretches.
    fine = parse_rubric({'parameters': {'stop_speed': 0.001},
                         'checks': {'manoeuvres': {'max': 4}}})
    assert fine.params.stop_speed == 0.001
    assert compute_metrics(speed_run(jitter), fine.params).values['manoeuvres'] == 9


def test_travel_stretches_against_grouping_the_moving_signs():
    # Independent count: group the signs of the moving samples (itertools.groupby).
    rng = np.random.default_rng(21)
    for _ in range(200):
        v = rng.choice([-0.3, -0.02, -0.005, 0.0, 0.004, 0.02, 0.5], size=rng.integers(0, 12))
        signs = [u > 0 for u in v if abs(u) > 0.01]
        assert travel_stretches(v, 0.01) == len([k for k, _ in itertools.groupby(signs)])


def test_a_robot_that_never_moves_makes_no_manoeuvre():
    assert compute_metrics(speed_run(np.zeros(30))).values['manoeuvres'] == 0
    assert compute_metrics(speed_run(np.full(30, -0.01))).values['manoeuvres'] == 0  # <= stop
    assert compute_metrics(speed_run([0.0, 0.3, 0.0])).values['manoeuvres'] == 1
    assert travel_stretches([], 0.01) == 0 and travel_stretches([-1.0], 0.01) == 1


def test_final_pose_error_against_the_last_path_pose():
    # The path ends at (5, 2) facing +90 deg; the truth ends at (5.3, 2.4) heading 80 deg:
    # hypot(0.3, 0.4) = 0.5 m and 10 deg.
    t = np.linspace(0.0, 2.0, 21)
    truth = pose_series(t, np.linspace(0.0, 5.3, 21), np.linspace(0.0, 2.4, 21),
                        np.linspace(0.0, math.radians(80.0), 21))
    run = replace(make_run(truth=truth, path=[[0.0, 0.0], [5.0, 0.0], [5.0, 2.0]]),
                  path_headings=np.array([0.0, math.radians(90.0), math.radians(90.0)]))
    m = compute_metrics(run).values
    assert m['final_position_error'] == pytest.approx(0.5, abs=1e-12)
    assert m['final_heading_error'] == pytest.approx(math.radians(10.0), abs=1e-12)
    checks = parse_rubric({'checks': {'final_position_error': {'max': 0.3}}})
    assert [c.passed for c in check_metrics(checks, compute_metrics(run), None)] == [False]


def test_final_heading_error_wraps_across_pi():
    # Parked in reverse: the last pose's orientation is 180 deg (against the travel), the
    # truth ends at -179 deg, 1 deg away; the truth ends on a one-pose path's only pose.
    truth = pose_series([0.0, 1.0], [1.0, 2.0], [1.0, 1.0], [0.0, math.radians(-179.0)])
    run = replace(make_run(truth=truth, path=[[2.0, 1.0]]), path_headings=np.array([math.pi]))
    m = compute_metrics(run).values
    assert m['final_heading_error'] == pytest.approx(math.radians(1.0), abs=1e-12)
    assert m['final_position_error'] == 0.0


def test_final_pose_errors_absent_with_the_reason():
    t = np.linspace(0.0, 1.0, 3)
    truth = pose_series(t, t, 0 * t, 0 * t)
    absent = compute_metrics(make_run(truth=truth)).absent
    assert absent['final_position_error'] == absent['final_heading_error'] == (
        'needs topic /path, which the bag lacks')
    no_truth = compute_metrics(replace(make_run(path=STRAIGHT),
                                       path_headings=np.zeros(len(STRAIGHT)))).absent
    assert no_truth['final_position_error'] == no_truth['manoeuvres'] == (
        'needs topic /ground_truth/odom, which the bag lacks')
    unoriented = compute_metrics(make_run(truth=truth, path=STRAIGHT))   # heading None
    assert unoriented.values['final_position_error'] == pytest.approx(9.0)
    assert 'finite orientation' in unoriented.absent['final_heading_error']
    empty = compute_metrics(make_run(truth=truth, path=np.zeros((0, 2)))).absent
    assert empty['final_position_error'] == 'needs a /path with poses; the last /path has none'
