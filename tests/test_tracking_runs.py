"""
End-to-end: the path- and trajectory-tracking examples of book ch. 9, run and recorded.

* Ejemplos 9.3 and 9.4 (§9.4.2): the posture errors (9.63) of the recorded ground truth against
  the reference (9.59), which this file integrates itself in closed form, equal the catalog's
  values (Part 7.10, computed from the continuous-time (9.67)) at the printed instants; the
  nodes sample the law every 10 ms (zero-order hold), so positions are checked to 1.5 mm and
  headings to 2.5 mrad.
* Ejemplo 9.5 (§9.4.3): under the linear law (9.93) with k1 = 1, k2 = 2 and no initial heading
  error, the lateral error in travelled distance ρ is (9.97)'s critically damped
  η(ρ) = η0 (1 + ρ) e^(-ρ) (η0 = -0.5 m); on the straight path and on the parabola.
* Ejemplos 9.1, 9.2 and the appendix's tricycle (§9.3.1, pure pursuit): the steered vehicles
  reach the path and stay on it; the Romeo 4R's short look-ahead overshoots the path first, as
  the book reports.
"""
import json
import math
import subprocess

import numpy as np
import pytest
from test_mobile_runs import angle_difference, pose, run, run_directory, stamp

pytestmark = [pytest.mark.slow, pytest.mark.ros]


def reference_posture(t: float) -> tuple[float, float, float]:
    """Return Ejemplo 9.3's reference posture at ``t`` [s], REP-103, by exact arcs."""
    x, y, theta, t0 = 0.0, 0.0, math.pi / 2.0, 0.0
    for v, w, duration in ((0.2, 0.3, 10.0), (0.2, 0.2, 10.0), (0.1, 0.2, 10.0)):
        tau = min(max(t - t0, 0.0), duration)
        x += v / w * (math.sin(theta + w * tau) - math.sin(theta))
        y -= v / w * (math.cos(theta + w * tau) - math.cos(theta))
        theta += w * tau
        t0 += duration
    return x, y, theta


def truth_at(messages, t: float) -> tuple[float, float, float]:
    """
    Return the recorded true pose at ``t`` [s], interpolated between its neighbours.

    The loop runs faster than the recorder here (the law reads the truth, so the odometry is
    off the lockstep chain): a message can be missing, and its neighbours 10 ms away give it
    to second order.
    """
    times = np.array([stamp(m) for m in messages])
    after = int(np.searchsorted(times, t - 1e-6))
    assert after < len(times) and times[after] - t < 0.025, f'no true pose near {t} s'
    if abs(times[after] - t) < 1e-6:
        return pose(messages[after])
    before = after - 1
    assert before >= 0 and t - times[before] < 0.025, f'no true pose before {t} s'
    w = (t - times[before]) / (times[after] - times[before])
    a, b = np.array(pose(messages[before])), np.array(pose(messages[after]))
    b[2] = a[2] + angle_difference(b[2], a[2])
    x, y, theta = (1.0 - w) * a + w * b
    return float(x), float(y), float(theta)


def posture_error(robot, reference) -> tuple[float, float, float]:
    """Return (e1, e2, e3) of book (9.63) in REP-103 (e2 > 0: the reference is to the left)."""
    x, y, theta = robot
    x_r, y_r, theta_r = reference
    c, s = math.cos(theta), math.sin(theta)
    return (c * (x_r - x) + s * (y_r - y), -s * (x_r - x) + c * (y_r - y),
            angle_difference(theta_r, theta))


@pytest.mark.parametrize('name, expected', [
    ('ej9_3a', {10.0: (0.066, 0.195, -0.102), 30.0: (0.0037, 0.0168, -0.0086)}),
    ('ej9_3b', {5.0: (0.010, 0.076, -0.241), 10.0: (0.0005, 0.0006, -0.0049)}),
    ('ej9_4', {5.0: (0.0045, 0.034, -0.203), 10.0: (-0.0004, -0.0011, 0.0047)}),
])
def test_trajectory_tracking_errors_match_the_catalog(tmp_path, name, expected):
    messages, summary = run(tmp_path, name)
    assert summary['exit_code'] == 0 and summary['lockstep_timeouts'] == 0
    truth = messages['/ground_truth/odom']
    for t, (e1, e2, e3) in expected.items():
        error = posture_error(truth_at(truth, t), reference_posture(t))
        assert error[0] == pytest.approx(e1, abs=1.5e-3), (t, error)
        assert error[1] == pytest.approx(e2, abs=1.5e-3), (t, error)
        assert error[2] == pytest.approx(e3, abs=2.5e-3), (t, error)
    assert len(messages['/path_tracker/tracking_error']) == summary['steps'] + 1


@pytest.mark.parametrize('name', ['ej9_5a', 'ej9_5b'])
def test_linear_path_following_is_critically_damped_in_distance(tmp_path, name):
    messages, summary = run(tmp_path, name)
    truth = [pose(m) for m in messages['/ground_truth/odom']]
    distance = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(np.array(truth)[:, :2],
                                                                      axis=0).T))))
    errors = {round(stamp(m), 3): m.cross_track for m in messages['/path_tracker/tracking_error']}
    times = [round(stamp(m), 3) for m in messages['/ground_truth/odom']]
    checked = 0
    for rho, t in zip(distance, times):
        if t in errors and rho <= 8.0:
            assert errors[t] == pytest.approx(-0.5 * (1.0 + rho) * math.exp(-rho), abs=0.01), t
            checked += 1
    assert checked > 700


@pytest.mark.parametrize('name, overshoots', [
    ('ej9_1', False), ('ej9_2', True), ('appendix_tricycle_pure_pursuit', False)])
def test_steered_vehicles_reach_the_path_under_pure_pursuit(tmp_path, name, overshoots):
    messages, summary = run(tmp_path, name)
    assert messages['/vehicle_command']                       # steered: speed and steering angle
    errors = np.array([m.cross_track for m in messages['/path_tracker/tracking_error']])
    assert abs(errors[0]) >= 0.5
    assert np.abs(errors[-len(errors) // 4:]).max() < 0.01    # on the path for the last quarter
    opposite = np.sign(errors) == -np.sign(errors[0])
    assert bool((errors[opposite] ** 2).max(initial=0.0) > 0.05 ** 2) is overshoots


def test_a_good_run_passes_its_rubric_and_a_cut_short_one_fails(tmp_path):
    """Ej. 9.1 graded by its shipped rubric: the full run passes; 3 s of it complete 0.2 < 0.6."""
    grades = {}
    for name, options in (('good', ()), ('bad', ('--duration', '3'))):
        run(tmp_path, 'ej9_1', *options)   # the full run is the pure-pursuit test's, if it ran
        run_dir = run_directory('ej9_1', *options)
        graded = subprocess.run(['robotica', 'grade', str(run_dir / 'bag'), '--rubric', 'ej9_1',
                                 '--json', str(tmp_path / f'{name}.json')],
                                capture_output=True, text=True, timeout=300)
        grades[name] = (graded.returncode, json.loads((tmp_path / f'{name}.json').read_text()))
    assert grades['good'][0] == 0 and grades['bad'][0] == 1
    assert 'Traceback' not in json.dumps(grades)
    good, bad = json.dumps(grades['good'][1]), json.dumps(grades['bad'][1])
    assert '"completion"' in good and '"completion"' in bad
