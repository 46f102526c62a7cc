"""
Tests of robotica_sim.benchmarks.tracking: its metrics, one closed loop per pose source, the CLI.

The metrics are checked on hand-made error histories against hand-computed values (the path
projection is the project's one, tested with grading.metrics.path_errors); the closed loops
against geometry computed here from the true trajectory (the distance to the x axis, to a
circle's centre), independently of the path projection the benchmark uses.
"""
import json
import math

import numpy as np
import pytest
from robotica_sim.benchmarks.tracking import (benchmark_path, control_effort,
                                              format_tracking_table, plot_tracking,
                                              run_tracking, settling_distance,
                                              tracking_benchmark)
from robotica_sim.cli.main import main


def rms(values):
    """Root mean square, written here for the reference values."""
    return math.sqrt(sum(v * v for v in np.ravel(values)) / np.size(values))


@pytest.fixture(scope='module')
def line_run():
    """Pure pursuit, differential drive, 0.5 m left of the 10 m line, on the true pose."""
    return run_tracking('pure_pursuit', 'differential', 'line_offset', 'ground_truth')


def test_settling_distance_of_a_constructed_error_history():
    travelled = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    # Enters the 0.1 m band at 2 m, leaves it at 3 m, back in for good at 4 m.
    assert settling_distance([0.5, -0.3, 0.05, -0.12, 0.02, 0.01], travelled) == 4.0
    assert settling_distance([0.05, -0.02, 0.0, 0.01, 0.0, 0.03], travelled) == 0.0
    assert settling_distance([0.5, 0.3, 0.0, 0.0, 0.0, 0.2], travelled) == math.inf
    assert settling_distance([0.5, 0.3, 0.0, 0.0, 0.0, 0.0], travelled, threshold=0.35) == 1.0


def test_control_effort_is_the_integral_of_the_squared_yaw_rate():
    # 0.5 rad/s for 2 s, then -1 rad/s for 1 s: 0.25 * 2 + 1 * 1 = 1.5 rad^2/s
    assert control_effort([0.5] * 100 + [-1.0] * 50, step=0.02) == pytest.approx(1.5)


@pytest.mark.parametrize('name, length, start', [
    ('line_offset', 10.0, [0.0, 0.5, 0.0]),
    ('circle', 4.0 * math.pi, [0.0, 0.0, 0.0]),
    ('figure_eight', 8.0 * math.pi, [0.0, 0.0, 0.0]),
    ('sharp_turn', 8.0, [0.0, 0.0, 0.0]),
])
def test_benchmark_paths_have_their_lengths_and_start_poses(name, length, start):
    path, pose = benchmark_path(name)
    assert path.length == pytest.approx(length, rel=1e-4)   # chords of the arcs
    np.testing.assert_array_equal(pose, start)


def test_sharp_turn_has_a_square_corner_without_cusp():
    path, _ = benchmark_path('sharp_turn')
    turns = np.diff(path.headings)
    np.testing.assert_allclose(turns[np.abs(turns) > 1e-9], [math.pi / 2])


def test_pure_pursuit_converges_from_the_offset(line_run):
    trajectory = line_run.trajectory
    assert line_run.completed
    assert abs(trajectory[-1, 1]) < 0.05              # final cross-track below 5 cm
    assert trajectory[-1, 0] == pytest.approx(10.0, abs=0.1)
    # The line is the x axis: cross-track = y and heading error = theta, computed here.
    assert line_run.rms_cross_track == pytest.approx(rms(trajectory[:, 1]), rel=1e-9)
    assert line_run.max_cross_track == pytest.approx(0.5)
    assert line_run.rms_heading_error == pytest.approx(rms(trajectory[:, 2]), rel=1e-9)
    inside = np.abs(trajectory[:, 1]) < 0.1
    first = int(np.flatnonzero(~inside)[-1]) + 1
    steps = np.hypot(*np.diff(trajectory[:, :2], axis=0).T)
    assert line_run.settling_distance == pytest.approx(float(np.sum(steps[:first])))
    assert 0.5 < line_run.settling_distance < 3.0
    assert line_run.distance == pytest.approx(float(np.sum(steps)))
    assert line_run.control_effort > 0.0
    assert 0.0 < line_run.median_update_us <= line_run.p99_update_us


def test_ackermann_follows_the_circle_through_the_steering_angle():
    result = run_tracking('pure_pursuit', 'ackermann', 'circle', 'ground_truth')
    radius = np.hypot(result.trajectory[:, 0], result.trajectory[:, 1] - 2.0)
    assert result.completed
    assert np.max(np.abs(radius - 2.0)) < 0.02
    # the benchmark's projection against the distance to the centre (chords: 0.16 mm)
    assert result.max_cross_track == pytest.approx(np.max(np.abs(radius - 2.0)), abs=2e-4)
    assert result.trajectory[len(result.trajectory) // 2, 1] == pytest.approx(4.0, abs=0.05)


def test_ekf_pose_tracks_with_the_estimate_error(line_run):
    result = run_tracking('pure_pursuit', 'differential', 'line_offset', 'ekf_dgps')
    assert result.completed
    assert abs(result.trajectory[-1, 1]) < 0.1          # DGPS-fused estimate: cm level
    # the law saw the estimate, not the truth: the true trajectories differ
    assert not np.allclose(result.trajectory[-50:], line_run.trajectory[-50:], atol=1e-6)
    again = run_tracking('pure_pursuit', 'differential', 'line_offset', 'ekf_dgps')
    np.testing.assert_array_equal(again.trajectory, result.trajectory)   # seeded


def test_benchmark_has_one_row_per_combination_and_a_table_row_each():
    messages = []
    results = tracking_benchmark(laws=('pure_pursuit', 'frenet'), vehicles=('tricycle',),
                                 paths=('sharp_turn',), poses=('ground_truth', 'ekf_dgps'),
                                 progress=messages.append)
    assert [(r.law, r.pose_source) for r in results] == [
        ('pure_pursuit', 'ground_truth'), ('pure_pursuit', 'ekf_dgps'),
        ('frenet', 'ground_truth'), ('frenet', 'ekf_dgps')]
    assert all(r.vehicle == 'tricycle' and r.path == 'sharp_turn' for r in results)
    assert len(messages) == 2
    lines = format_tracking_table(results).splitlines()
    assert len(lines) == 2 + len(results)
    assert lines[3].startswith('| pure_pursuit | tricycle | sharp_turn | ekf_dgps | yes |')


def test_plots_are_written(tmp_path, line_run):
    written = plot_tracking([line_run], tmp_path / 'plots')
    names = sorted(path.name for path in written)
    assert names == ['compute_time.png', 'rms_cross_track_ground_truth.png',
                     'trajectories_line_offset_ground_truth.png']
    for path in written:
        assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'


@pytest.mark.parametrize('args', [('unknown', 'differential', 'circle', 'ground_truth'),
                                  ('gpc', 'omni_three', 'circle', 'ground_truth'),
                                  ('gpc', 'differential', 'spiral', 'ground_truth'),
                                  ('gpc', 'differential', 'circle', 'odometry')])
def test_unknown_names_are_refused(args):
    with pytest.raises(ValueError):
        run_tracking(*args)


def test_cli_prints_json_rows(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(['bench', 'tracking', '--laws', 'gpc', '--vehicles', 'ackermann', '--paths',
              'sharp_turn', '--poses', 'ground_truth', '--json', '--quiet'])
    assert exit_info.value.code == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == 1
    assert rows[0]['law'] == 'gpc' and rows[0]['completed'] is True
    assert 'trajectory' not in rows[0]
    with pytest.raises(SystemExit) as exit_info:
        main(['bench', 'tracking', '--paths', 'spiral'])
    assert exit_info.value.code == 2
