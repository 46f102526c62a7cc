"""
Tests of robotica_sim.grading.figures: each figure drawn from a run built in memory.

The runs are synthetic signals whose statistics are known from their definitions: a constant
offset has RMS and peak equal to itself, 0.1 sin(2π t / 5) sampled 201 times over two whole
periods has mean square 0.01 * 100 / 201, and the sensor readings are the truth plus noise
drawn here from a seeded generator, so that the bias and σ each caption prints can be checked
against the noise itself. The images themselves are checked by test_report.py, through
``robotica report``.
"""
from dataclasses import replace
import math
from pathlib import Path
import re

from matplotlib.figure import Figure
import numpy as np
import pytest
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_sim.grading import figures
from robotica_sim.grading.series import RunSeries, Series

NUMBER = r'-?\d+(?:\.\d*)?(?:e[-+]?\d+)?'
PRINTED = 5.1e-3            # relative precision of a value printed with 3 digits
T = np.arange(201) * 0.05   # [s] 0 ... 10 s at 20 Hz
ORIGIN = (40.0, -3.7, 650.0)   # [deg, deg, m]


def numbers_after(text, label):
    """Return the numbers that follow ``label`` in ``text`` (up to the next ';')."""
    match = re.search(re.escape(label) + r'[^;]*', text)
    assert match, f'{label!r} not in {text!r}'
    return [float(v) for v in re.findall(NUMBER, match.group(0)[len(label):])]


def series(t, **columns):
    return Series(np.asarray(t, dtype=float),
                  {name: np.asarray(v, dtype=float) for name, v in columns.items()})


def poses(t, x, y, theta, w=0.0, **extra):
    """Return an odometry-like series (x, y [m], θ [rad], v, vy [m/s], w [rad/s])."""
    n = len(t)
    return series(t, x=x, y=y, theta=theta, v=np.ones(n), vy=np.zeros(n),
                  w=np.full(n, w) if np.ndim(w) == 0 else w, **extra)


def make_run(path=None, path_times=None, scenario=None, **topics):
    fields = {name: topics.get(name) for name in (
        'truth', 'odom', 'cmd', 'tracking_error', 'imu', 'compass', 'gps', 'joint_states',
        'controller', 'torques')}
    return RunSeries(bag=Path('synthetic'), scenario=scenario, duration=float(T[-1]),
                     counts={}, path=None if path is None else np.asarray(path, dtype=float),
                     path_times=path_times, status=None, **fields)


def draw(function, *args):
    """Draw one figure; return its caption (and check that it drew into axes)."""
    fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
    text = function(fig, *args)
    assert fig.axes
    return text


# --- the robot on the trajectory ----------------------------------------------------------

def test_robot_poses_every_interval():
    t = np.arange(1001) / 100.0                     # 0 ... 10 s
    sampled = figures.robot_poses(t, t, -t, 0.1 * t, 2.0)
    np.testing.assert_allclose(sampled[:, 0], [0.0, 2.0, 4.0, 6.0, 8.0, 10.0])
    np.testing.assert_allclose(sampled[:, 2], 0.1 * sampled[:, 0])
    with pytest.raises(ValueError, match='every'):
        figures.robot_poses(t, t, t, t, 0.0)


def test_auto_robot_every_draws_at_most_15_intervals():
    for duration, expected in ((5.0, 0.5), (7.5, 0.5), (7.6, 1.0), (30.0, 2.0), (60.0, 5.0),
                               (600.0, 60.0)):
        assert figures.auto_robot_every(duration) == expected
        assert duration / expected <= 15


def test_trajectory_caption_names_the_robot_interval_and_the_final_error():
    truth = poses(T, T, np.zeros_like(T), np.zeros_like(T))
    odom = poses(T, T + 0.03, np.full_like(T, -0.04), np.zeros_like(T))
    text = draw(figures.trajectory, make_run(path=[[0.0, 0.0], [10.0, 0.0]], truth=truth,
                                             odom=odom), 2.0)
    assert 'every 2 s' in text and 'true pose' in text
    assert numbers_after(text, 'Final position error of /odom:')[0] == pytest.approx(0.05)


def test_a_robot_with_a_footprint_polygon_is_drawn_as_its_body_and_at_its_end():
    # A 4.5 x 1.7 m car body about its rear axle, driven 10 m along x: drawn at true scale at
    # 0, 2, ..., 10 s and once more at the end (the last drawn patch), where it stopped.
    from matplotlib.patches import Polygon
    truth = poses(T, T, np.zeros_like(T), np.zeros_like(T))
    body = [-0.9, -0.85, 3.6, -0.85, 3.6, 0.85, -0.9, 0.85]
    fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
    text = figures.trajectory(fig, make_run(path=[[0.0, 0.0], [10.0, 0.0]], truth=truth,
                                            scenario={'robot': {'footprint_polygon': body}}),
                              2.0)
    assert 'as its body (robot.footprint_polygon, true scale)' in text
    patches = [p for p in fig.axes[0].patches if isinstance(p, Polygon)]
    assert len(patches) == 7                         # six every 2 s and the end
    corners = patches[-1].get_xy()[:4]
    np.testing.assert_allclose(corners, [[T[-1] - 0.9, -0.85], [T[-1] + 3.6, -0.85],
                                         [T[-1] + 3.6, 0.85], [T[-1] - 0.9, 0.85]], atol=1e-12)


# --- tracking errors ----------------------------------------------------------------------

def test_tracking_errors_of_the_truth_against_the_path_and_of_the_tracker():
    # The truth weaves 0.1 sin(2π t / 5) m to the left of the x axis with heading 0.05 rad:
    # along a straight path its cross-track error is y itself and its heading error 0.05 rad.
    # The tracker reports its own numbers, 0.02 m and -0.01 rad, from the pose it reads.
    y = 0.1 * np.sin(2.0 * math.pi * T / 5.0)
    run = make_run(path=[[-1.0, 0.0], [20.0, 0.0]],
                   truth=poses(T, T, y, np.full_like(T, 0.05)),
                   tracking_error=series(T, cross_track=np.full_like(T, 0.02),
                                         heading=np.full_like(T, -0.01),
                                         along_track=np.zeros_like(T)))
    text = draw(figures.tracking_errors, run, 2.0)
    true, tracker = text.split('As the tracker')
    rms, peak = numbers_after(true, 'cross-track RMS')[:2]
    assert rms == pytest.approx(0.1 * math.sqrt(100.0 / 201.0), rel=PRINTED)
    assert peak == pytest.approx(0.1, rel=PRINTED)
    assert numbers_after(true, 'heading RMS')[:2] == pytest.approx([0.05, 0.05])
    assert 'within 2 m of the progress' in true
    assert numbers_after(tracker, 'cross-track RMS')[:2] == pytest.approx([0.02, 0.02])
    assert numbers_after(tracker, 'heading RMS')[:2] == pytest.approx([0.01, 0.01])
    assert 'along-track' not in text


def test_tracking_errors_of_the_tracker_alone_with_its_along_track_error():
    run = make_run(tracking_error=series(T, cross_track=np.full_like(T, -0.3),
                                         heading=np.full_like(T, 0.2),
                                         along_track=np.full_like(T, 0.4)))
    text = draw(figures.tracking_errors, run, 2.0)
    assert 'True errors' not in text
    assert numbers_after(text, 'cross-track RMS')[:2] == pytest.approx([0.3, 0.3])
    assert numbers_after(text, 'along-track RMS')[:2] == pytest.approx([0.4, 0.4])


# --- estimation and sensors ---------------------------------------------------------------

def test_estimation_errors_and_their_3_sigma_band():
    # /odom = truth + (0.01 m, -0.02 m, 0.005 rad) with variances 1e-4 m², 1e-4 m², 1e-6 rad²:
    # 3σ = 0.03 m, 0.03 m, 0.003 rad, so x and y lie inside the band and θ outside it. One
    # more /odom sample after the truth ends has no error (NaN) and counts for nothing.
    truth = poses(T, T, np.zeros_like(T), np.full_like(T, 3.0))
    t = np.append(T, T[-1] + 0.05)
    odom = poses(t, t + 0.01, np.full_like(t, -0.02), np.full_like(t, 3.005),
                 var_x=np.full_like(t, 1e-4), var_y=np.full_like(t, 1e-4),
                 var_theta=np.full_like(t, 1e-6))
    text = draw(figures.estimation, odom, truth)
    assert numbers_after(text, 'x RMS')[:2] == pytest.approx([0.01, 100.0])
    assert numbers_after(text, 'y RMS')[:2] == pytest.approx([0.02, 100.0])
    assert numbers_after(text, 'theta RMS')[:2] == pytest.approx([0.005, 0.0])


def test_gyro_bias_and_sigma_are_those_of_the_noise():
    noise = np.random.default_rng(42).normal(0.01, 0.05, T.size)   # bias 0.01, σ 0.05 rad/s
    truth = poses(T, T, np.zeros_like(T), 0.25 * T, w=0.25)
    text = draw(figures.gyro, series(T, wz=0.25 + noise), truth)
    mean, std = numbers_after(text, 'mean (bias)')[:2]
    assert mean == pytest.approx(np.mean(noise), rel=PRINTED)
    assert std == pytest.approx(np.std(noise, ddof=1), rel=PRINTED)


def test_compass_error_is_wrapped_across_pi():
    # The heading turns from 2 rad through π at 0.25 rad/s; readings are stored wrapped.
    noise = np.random.default_rng(7).normal(0.0, 0.02, T.size)
    theta = 2.0 + 0.25 * T
    truth = poses(T, T, np.zeros_like(T), (theta + math.pi) % (2.0 * math.pi) - math.pi)
    reading = (theta + noise + math.pi) % (2.0 * math.pi) - math.pi
    text = draw(figures.compass, series(T, theta=reading), truth)
    mean, std = numbers_after(text, 'mean')[:2]
    assert mean == pytest.approx(np.mean(noise), rel=PRINTED)
    assert std == pytest.approx(np.std(noise, ddof=1), rel=PRINTED)


def test_gps_fixes_in_the_scenario_origin_enu_frame():
    origin = GeodeticOrigin(*ORIGIN)
    noise = np.random.default_rng(3).normal(0.0, 0.5, (T.size, 2))   # σ 0.5 m per axis
    x, y = 2.0 * T, -T
    latitude, longitude, altitude = origin.enu_to_geodetic(x + noise[:, 0], y + noise[:, 1],
                                                           np.zeros_like(T))
    fixes = series(T, latitude=latitude, longitude=longitude, altitude=altitude,
                   var_e=np.full_like(T, 0.25), var_n=np.full_like(T, 0.25))
    text = draw(figures.gps, fixes, poses(T, x, y, np.zeros_like(T)), origin)
    assert '40° N, 3.7° W, 650 m' in text
    east_mean, east_std = numbers_after(text, 'east mean')[:2]
    north_mean, north_std = numbers_after(text, 'north mean')[:2]
    np.testing.assert_allclose([east_mean, north_mean], np.mean(noise, axis=0), rtol=PRINTED)
    np.testing.assert_allclose([east_std, north_std], np.std(noise, axis=0, ddof=1),
                               rtol=PRINTED)
    assert numbers_after(text, 'claims σ')[0] == pytest.approx(0.5)


# --- manipulator --------------------------------------------------------------------------

def arm_run(errors=(0.01, -0.02)):
    """Two joints over 2 s at 100 Hz with constant errors e = q_d - q; τ1 = 3 + sin t."""
    t = np.arange(201) / 100.0
    q = np.column_stack([0.5 * np.sin(t), -0.3 * np.sin(t)])
    tau = np.column_stack([3.0 + np.sin(t), np.full_like(t, -1.0)])
    names = ('shoulder', 'elbow')
    joints = Series(t, {'position': q, 'velocity': np.gradient(q, t, axis=0), 'effort': tau},
                    names)
    error = np.tile(errors, (t.size, 1))
    controller = Series(t, {'reference_position': q + error, 'reference_velocity': q * 0.0,
                            'position_error': error, 'effort': tau}, names)
    return make_run(joint_states=joints, controller=controller,
                    torques=Series(t, {'effort': tau}))


def test_joint_errors_caption_per_joint():
    run = arm_run()
    text = draw(figures.joint_errors, run, run.controller)
    for name, error in zip(('shoulder', 'elbow'), (0.01, -0.02)):
        rms, peak, final = numbers_after(text, f'{name} RMS')[:3]
        assert (rms, peak, final) == pytest.approx((abs(error), abs(error), error))


def test_joint_torques_peak_per_joint():
    # τ = 3 + sin t on the shoulder, t in [0, 2] s: peak 4 N m at t = π/2; the elbow -1 N m.
    text = draw(figures.joint_torques, arm_run())
    assert numbers_after(text, 'shoulder')[0] == pytest.approx(4.0)
    assert numbers_after(text, 'elbow')[0] == pytest.approx(1.0)
    assert '/joint_torques' in text


@pytest.mark.parametrize('kind, symbol', [('position', 'q [rad]'), ('velocity', "q' [rad/s]")])
def test_joint_figure_names_the_joints(kind, symbol):
    fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
    text = figures.joint_figure(fig, arm_run(), kind)
    assert symbol in text
    assert [ax.get_title() for ax in fig.axes] == ['shoulder', 'elbow']


def test_sweep_metric_draws_each_run_and_the_mean_per_value():
    fig = Figure()
    points = [(0.5, '', 1.0), (0.5, '', 3.0), (2, '', 5.0), (4, '', math.nan)]
    caption = figures.sweep_metric(fig, 'tracker.lookahead_distance', points,
                                   'rms_cross_track', 'm')
    assert 'Means: 0.5: 2; 2: 5.' in caption   # (1 + 3) / 2 and 5; the NaN run is left out
    (ax,) = fig.axes
    runs, mean = ax.lines
    assert list(runs.get_xdata()) == [0.5, 0.5, 2.0] and list(mean.get_ydata()) == [2.0, 5.0]
    assert ax.get_xlabel() == 'tracker.lookahead_distance'
    assert ax.get_ylabel() == 'rms_cross_track [m]'
    words = figures.sweep_metric(Figure(), 'tracker.law', [('stanley', '', 1.0),
                                                           ('pure_pursuit', '', 2.0)], 'x', '')
    assert 'stanley: 1; pure_pursuit: 2' in words   # categories in their first order


# --- the world, the range readings and the contacts ---------------------------------------

WORLD = {'walls': [[0.0, -1.0, 4.0, -1.0], [4.0, -1.0, 4.0, 3.0]],
         'boxes': [{'center': [2.0, 4.0], 'size': [1.0, 0.5]}],   # axis-aligned
         'circles': [[-1.0, 2.0, 0.3]]}
POSE = (1.0, 2.0, math.pi / 2.0)   # [m, m, rad] the robot stands still, facing +y


def still_truth():
    return poses(T, np.full_like(T, POSE[0]), np.full_like(T, POSE[1]),
                 np.full_like(T, POSE[2]))


def world_run(scenario=None, **fields):
    """Return a run of the still robot; ``scenario`` None: no world."""
    return replace(make_run(path=[[0.0, 0.0], [1.0, 2.0]], scenario=scenario,
                            truth=still_truth()), **fields)


def draw_axes(run, every=2.0):
    fig = Figure(figsize=figures.FIGURE_SIZE, dpi=figures.DPI)
    text = figures.trajectory(fig, run, every)
    (ax,) = fig.axes
    return ax, text


def line(ax, label):
    (found,) = [ln for ln in ax.lines if ln.get_label() == label]
    return np.column_stack([found.get_xdata(), found.get_ydata()]).astype(float)


def pieces(xy):
    """Return the pieces, (k, 2) each, of a polyline whose pieces are separated by NaN."""
    breaks = np.flatnonzero(np.isnan(xy[:, 0]))
    parts = [part[~np.isnan(part[:, 0])] for part in np.split(xy, breaks)]
    return [part for part in parts if len(part)]


def test_the_world_is_drawn_at_its_coordinates_under_the_trajectories():
    ax, text = draw_axes(world_run({'world': WORLD}))
    segments = {tuple(np.round(p.ravel(), 9)) for p in pieces(line(ax, 'walls and obstacles'))}
    box = [(1.5, 3.75), (2.5, 3.75), (2.5, 4.25), (1.5, 4.25)]
    expected = {(0.0, -1.0, 4.0, -1.0), (4.0, -1.0, 4.0, 3.0)} | {
        (*box[k], *box[(k + 1) % 4]) for k in range(4)}
    assert len(segments) == 6
    for segment in expected:   # each edge, in either direction
        reverse = segment[2:] + segment[:2]
        assert segment in segments or reverse in segments
    (circle,) = [p for p in ax.patches if type(p).__name__ == 'Circle']
    assert circle.center == pytest.approx((-1.0, 2.0)) and circle.radius == pytest.approx(0.3)
    world = [ln for ln in ax.lines if ln.get_label() == 'walls and obstacles'][0]
    truth = [ln for ln in ax.lines if ln.get_label() == 'true trajectory'][0]
    assert world.get_zorder() < truth.get_zorder() and circle.get_zorder() < truth.get_zorder()
    assert "The world (the scenario's world: section)" in text
    assert ax.get_title().endswith('in the world')


def test_laser_returns_are_placed_by_the_mount_and_the_true_pose():
    # Sensor at (1, 2) + R(π/2) (0.1, 0) = (1, 2.1), facing +y. Beams at -π/2, -π/4, 0, π/4,
    # π/2 in its frame: 1 m at -π/2 (map angle 0) -> (2, 2.1); 2 m at π/4 (map 3π/4) ->
    # (1 - √2, 2.1 + √2); +inf, NaN and -inf are not returns (REP-117), 9 m exceeds range_max.
    ranges = np.array([[1.0, np.inf, np.nan, 2.0, -np.inf, 9.0]])
    scans = series([5.0], angle_min=[-math.pi / 2.0], angle_increment=[math.pi / 4.0],
                   range_min=[0.1], range_max=[8.0])
    scans.columns['ranges'] = ranges
    scenario = {'world': WORLD, 'sensors': {'laser': {'mount': [0.1, 0.0, 0.0]}}}
    ax, text = draw_axes(world_run(scenario, scans=scans))
    root = math.sqrt(2.0)
    np.testing.assert_allclose(line(ax, 'laser returns every 2 s'),
                               [[2.0, 2.1], [1.0 - root, 2.1 + root]], atol=1e-12)
    assert '1 scans, 2 points' in text


def test_range_readings_are_beams_along_the_sensor_axis():
    # Sonar 0 at (0.2, 0, 0) in base_link: (1, 2.2) facing +y; its 0.5 m echo ends at (1, 2.7).
    # Sonar 1 at (0, 0.2, π/2): (0.8, 2) facing -x; its reading 10.7 m is max_range (no echo),
    # drawn dotted to the edge of what is drawn (the world reaches x = -1.3, plus a margin).
    readings = {f'/sonar_{i}': series([5.0], range=[r], min_range=[0.15], max_range=[10.7])
                for i, r in enumerate((0.5, 10.7))}
    scenario = {'world': WORLD,
                'sensors': {'sonar': {'mounts': [0.2, 0.0, 0.0, 0.0, 0.2, math.pi / 2.0]}}}
    ax, text = draw_axes(world_run(scenario, ranges=readings))
    (echo,) = pieces(line(ax, 'sonar echoes every 2 s'))   # one reading: drawn once
    np.testing.assert_allclose(echo, [[1.0, 2.2], [1.0, 2.7]], atol=1e-12)
    (silent,) = pieces(line(ax, 'sonar: no echo'))
    np.testing.assert_allclose(silent[0], [0.8, 2.0], atol=1e-12)
    assert silent[1, 1] == pytest.approx(2.0) and -2.0 < silent[1, 0] < -1.3
    assert '2 sonar readings' in text


def test_contacts_are_marked_where_the_bumper_starts_touching():
    # Two contacts: at t = 1 s without a contact point (the true position is used), at
    # t = 3 s at the point (3, 4); t = 2 s continues the first.
    t = np.array([0.0, 1.0, 2.0, 2.5, 3.0, 4.0])
    bumper = series(t, in_contact=[0, 1, 1, 0, 1, 0],
                    x=[np.nan, np.nan, 0.0, np.nan, 3.0, np.nan],
                    y=[np.nan, np.nan, 0.0, np.nan, 4.0, np.nan])
    ax, text = draw_axes(world_run({'world': WORLD}, bumper=bumper))
    np.testing.assert_allclose(line(ax, 'contact (2)'), [POSE[:2], [3.0, 4.0]])
    assert 'Contacts (/bumper from free to in contact): 2, at t = 1.00, 3.00 s' in text


def test_a_run_without_a_world_is_drawn_as_before():
    # The scans, readings and contacts of a run are drawn only with its world.
    scans = series([5.0], angle_min=[0.0], angle_increment=[0.1], range_min=[0.1],
                   range_max=[8.0])
    scans.columns['ranges'] = np.array([[1.0, 2.0]])
    run = world_run(None, scans=scans, bumper=series(T, in_contact=np.ones_like(T)))
    ax, text = draw_axes(run)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        'path (reference)', 'true trajectory', 'robot every 2 s', 'start']
    assert len(ax.lines) == 3 and not ax.images and len(ax.patches) == 6   # 6 robots
    assert ax.get_title() == 'Path, true trajectory and /odom estimate'
    assert 'world' not in text and 'Contacts' not in text


def grid_of(cells, resolution=0.5, origin=(-1.0, -1.0, 0.0)):
    return OccupancyGrid(np.asarray(cells, dtype=np.int8), resolution, origin)


def test_an_unloadable_map_file_falls_back_to_map_then_to_the_geometry():
    scenario = {'world': {'map': 'no_such_map.yaml', 'walls': [[0.0, -1.0, 4.0, -1.0]]}}
    grid = grid_of([[0, 100], [-1, 0]])
    ax, text = draw_axes(world_run(scenario, map_grid=grid))
    (image,) = ax.images
    assert image.get_extent() == pytest.approx([0.0, 1.0, 0.0, 1.0])   # in the grid frame
    rgba = image.get_array()
    assert rgba[0, 1, 3] > 0.5 and rgba[0, 0, 3] == 0.0   # occupied drawn, free transparent
    assert "'no_such_map.yaml' could not be loaded" in text and 'published on /map' in text
    assert pieces(line(ax, 'walls and obstacles'))[0].tolist() == [[0.0, -1.0], [4.0, -1.0]]
    ax, text = draw_axes(world_run(scenario))
    assert not ax.images and 'only the walls, polygons and circles are drawn' in text
