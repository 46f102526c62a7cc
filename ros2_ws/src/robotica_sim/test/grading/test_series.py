"""
Tests of robotica_sim.grading.series on synthetic bags written with rosbags in the test.

The reference values are the numbers written into the bag, so every column is checked against
what went in: stamps, positions, the yaw of quaternions built from known angles, covariance
diagonals, joint arrays (also when a message lists its joints in another order).
"""
from dataclasses import replace
import math
from pathlib import Path

import numpy as np
import pytest
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.world.map_file import write_map
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_sim.bags.info import BagError
from robotica_sim.bags.typestore import ensure_type, jazzy_typestore
from robotica_sim.grading import series as series_module
from robotica_sim.grading.metrics import compute_metrics
from robotica_sim.grading.series import (fixes_to_enu, gps_origin, load_run, run_world,
                                         RunSeries, sensor_mounts, Series)
from robotica_sim.runs.scenario import GpsSpec
from robotica_sim.sensors.infrared import INFRARED_MOUNTS
from robotica_sim.sensors.sonar import SONAR_MOUNTS
from rosbags.rosbag2 import StoragePlugin, Writer

SCENARIO = 'name: synthetic\nseed: 3\narm:\n  model: two_link_arm\n  lengths: [3.0, 1.0]\n'
N = 5                     # samples per topic
DT = 0.1                  # [s]
THETA = [0.1, 0.5, -2.0, 3.0, -3.1]   # [rad] truth headings


def _types(store):
    for msgtype in ('TrackingError', 'JointControllerState', 'SimulatorStatus',
                    'VehicleCommand'):
        ensure_type(store, f'robotica_msgs/msg/{msgtype}')
    return store.types


def _header(types, t, frame='odom'):
    sec = int(math.floor(t))
    return types['std_msgs/msg/Header'](
        stamp=types['builtin_interfaces/msg/Time'](sec=sec, nanosec=round((t - sec) * 1e9)),
        frame_id=frame)


def _quaternion(types, yaw):
    return types['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=math.sin(yaw / 2),
                                                 w=math.cos(yaw / 2))


def _odometry(types, t, x, y, yaw, v, w, variances):
    cov = np.zeros(36)
    cov[[0, 7, 35]] = variances
    vec = types['geometry_msgs/msg/Vector3']
    pose = types['geometry_msgs/msg/Pose'](
        position=types['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
        orientation=_quaternion(types, yaw))
    twist = types['geometry_msgs/msg/Twist'](linear=vec(x=v, y=0.0, z=0.0),
                                             angular=vec(x=0.0, y=0.0, z=w))
    return types['nav_msgs/msg/Odometry'](
        header=_header(types, t), child_frame_id='base_link',
        pose=types['geometry_msgs/msg/PoseWithCovariance'](pose=pose, covariance=cov),
        twist=types['geometry_msgs/msg/TwistWithCovariance'](twist=twist,
                                                             covariance=np.zeros(36)))


def write_bag(path, topics, scenario=SCENARIO):
    """Write ``topics``: {topic: (msgtype, [(receive time [s], message), ...])}."""
    store = jazzy_typestore()
    _types(store)
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    if scenario is not None:
        writer.set_custom_data('robotica.scenario.yaml', scenario)
    for topic, (msgtype, messages) in topics.items():
        connection = writer.add_connection(topic, msgtype, typestore=store)
        for t, msg in messages:
            writer.write(connection, round(t * 1e9), store.serialize_cdr(msg, msgtype))
    writer.close()
    return path


def mobile_topics(types):
    """Every mobile topic, N samples at DT (odom received out of order), known values."""
    times = [k * DT for k in range(N)]
    vec = types['geometry_msgs/msg/Vector3']
    pose_stamped = types['geometry_msgs/msg/PoseStamped']
    path = types['nav_msgs/msg/Path'](header=_header(types, 0.0), poses=[
        pose_stamped(header=_header(types, 0.0), pose=types['geometry_msgs/msg/Pose'](
            position=types['geometry_msgs/msg/Point'](x=float(x), y=0.0, z=0.0),
            orientation=_quaternion(types, 0.0))) for x in range(4)])
    odom = [(t, _odometry(types, t, 10.0 * t, 0.5, THETA[k], 1.0, 0.2, [0.01, 0.02, 0.03]))
            for k, t in enumerate(times)]
    odom[0], odom[1] = (odom[1][0], odom[0][1]), (odom[0][0], odom[1][1])   # swap arrivals
    imu = types['sensor_msgs/msg/Imu'](   # unstamped (0): its receive time is used
        header=_header(types, 0.0), orientation=_quaternion(types, 0.0),
        orientation_covariance=np.zeros(9), angular_velocity=vec(x=0.0, y=0.0, z=0.7),
        angular_velocity_covariance=np.zeros(9), linear_acceleration=vec(x=0.0, y=0.0, z=0.0),
        linear_acceleration_covariance=np.zeros(9))
    compass_cov = np.zeros(9)
    compass_cov[8] = 0.04
    compass = types['sensor_msgs/msg/Imu'](
        header=_header(types, 0.2), orientation=_quaternion(types, -1.2),
        orientation_covariance=compass_cov, angular_velocity=vec(x=0.0, y=0.0, z=0.0),
        angular_velocity_covariance=np.zeros(9), linear_acceleration=vec(x=0.0, y=0.0, z=0.0),
        linear_acceleration_covariance=np.zeros(9))
    gps_cov = np.zeros(9)
    gps_cov[[0, 4, 8]] = [4.0, 9.0, 16.0]
    gps = types['sensor_msgs/msg/NavSatFix'](
        header=_header(types, 0.4), status=types['sensor_msgs/msg/NavSatStatus'](
            status=0, service=1), latitude=37.4, longitude=-6.0, altitude=12.0,
        position_covariance=gps_cov, position_covariance_type=2)
    point = types['geometry_msgs/msg/Point']
    return {
        '/clock': ('rosgraph_msgs/msg/Clock', [
            (t, types['rosgraph_msgs/msg/Clock'](clock=_header(types, t).stamp))
            for t in times]),
        '/ground_truth/odom': ('nav_msgs/msg/Odometry', [
            (t, _odometry(types, t, float(k), 0.5, THETA[k], 1.0, 0.2, [0.0, 0.0, 0.0]))
            for k, t in enumerate(times)]),
        '/odom': ('nav_msgs/msg/Odometry', odom),
        '/path': ('nav_msgs/msg/Path', [(0.0, path)]),
        '/cmd_vel': ('geometry_msgs/msg/Twist', [
            (t, types['geometry_msgs/msg/Twist'](linear=vec(x=1.0, y=0.0, z=0.0),
                                                 angular=vec(x=0.0, y=0.0, z=-t)))
            for t in times]),
        '/path_tracker/tracking_error': ('robotica_msgs/msg/TrackingError', [
            (t, types['robotica_msgs/msg/TrackingError'](
                header=_header(types, t), cross_track=0.5, heading=-t, along_track=0.0,
                target_point=point(x=t + 1.0, y=0.0, z=0.0))) for t in times]),
        '/imu/data': ('sensor_msgs/msg/Imu', [(0.3, imu)]),
        '/compass/heading': ('sensor_msgs/msg/Imu', [(0.2, compass)]),
        '/gps/fix': ('sensor_msgs/msg/NavSatFix', [(0.4, gps)]),
        '/simulator/status': ('robotica_msgs/msg/SimulatorStatus', [
            (t, types['robotica_msgs/msg/SimulatorStatus'](
                header=_header(types, t), step=k, real_time_factor=2.5, lockstep_timeouts=1,
                stale_command_stops=0, finished=k == N - 1, contacts=0,
                time_in_contact=0.0)) for k, t in enumerate(times)]),
    }


def test_mobile_run_columns_match_what_was_written(tmp_path):
    types = _types(jazzy_typestore())
    run = load_run(write_bag(tmp_path / 'bag', mobile_topics(types)))
    assert run.scenario_name == 'synthetic' and run.scenario['seed'] == 3
    assert run.duration == pytest.approx(0.4)
    assert run.counts['/odom'] == N and run.counts['/path'] == 1
    assert run.msgtypes['/compass/heading'] == 'sensor_msgs/msg/Imu'
    assert not run.is_manipulator
    truth = run.truth
    assert truth.t == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
    assert truth['x'] == pytest.approx([0.0, 1.0, 2.0, 3.0, 4.0])
    assert truth['theta'] == pytest.approx(THETA)   # yaw of the quaternions, in (-pi, pi]
    assert (truth['v'] == pytest.approx(np.ones(N))) and truth['w'] == pytest.approx(
        np.full(N, 0.2))
    # /odom arrived with its first two messages swapped: the series is in stamp order, and
    # the message stamped 0 keeps t = 0 although it was received at 0.1 s.
    assert run.odom.t == pytest.approx(truth.t)
    assert run.odom['x'] == pytest.approx(10.0 * truth.t)
    assert (run.odom['var_x'], run.odom['var_y'], run.odom['var_theta']) == (
        pytest.approx(np.full(N, 0.01)), pytest.approx(np.full(N, 0.02)),
        pytest.approx(np.full(N, 0.03)))
    assert run.path.tolist() == [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]
    assert run.path_end_heading == 0.0       # the yaw of the last pose's orientation
    assert run.path_times is None            # every pose stamped 0: not a trajectory
    assert run.cmd['w'] == pytest.approx(-truth.t) and run.cmd.t == pytest.approx(truth.t)
    assert set(run.cmd.columns) == {'v', 'w'}
    assert run.tracking_error['target_x'] == pytest.approx(truth.t + 1.0)
    assert run.imu['wz'].tolist() == [0.7] and run.imu.t == pytest.approx([0.3])
    assert run.compass['theta'] == pytest.approx([-1.2])
    assert run.compass['var_theta'] == pytest.approx([0.04])
    gps = run.gps
    assert (gps['var_e'][0], gps['var_n'][0], gps['altitude'][0]) == (4.0, 9.0, 12.0)
    assert run.status == {'step': N - 1, 'real_time_factor': 2.5, 'lockstep_timeouts': 1,
                          'stale_command_stops': 0, 'finished': True}
    assert run.joint_states is None and run.controller is None and run.torques is None
    for series in (truth, run.odom, run.cmd, run.tracking_error, run.imu, run.gps):
        assert all(v.dtype == np.float64 for v in (series.t, *series.columns.values()))


def _parking_path(types, postures):
    """Return a nav_msgs/Path of postures (x [m], y [m], heading [rad]), stamped 0."""
    pose_stamped, pose = types['geometry_msgs/msg/PoseStamped'], types['geometry_msgs/msg/Pose']
    return types['nav_msgs/msg/Path'](header=_header(types, 0.0), poses=[
        pose_stamped(header=_header(types, 0.0), pose=pose(
            position=types['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
            orientation=_quaternion(types, heading))) for x, y, heading in postures])


def test_the_last_paths_end_heading_is_read_back(tmp_path):
    # Two /path messages: the first a plain line, the last a parking plan whose reverse
    # segment ends facing 2.5 rad (against the travel); only the last one counts.
    types = _types(jazzy_typestore())
    topics = mobile_topics(types)
    line = _parking_path(types, [(0.0, 0.0, 0.0), (9.0, 0.0, 0.0)])
    plan = _parking_path(types, [(6.0, 1.0, 0.0), (5.0, 0.6, 0.3), (4.0, 0.5, 2.5)])
    topics['/path'] = ('nav_msgs/msg/Path', [(0.0, line), (0.2, plan)])
    run = load_run(write_bag(tmp_path / 'bag', topics))
    assert run.path.tolist() == [[6.0, 1.0], [5.0, 0.6], [4.0, 0.5]]
    assert run.path_end_heading == pytest.approx(2.5, abs=1e-12)
    assert run.path_headings == pytest.approx([0.0, 0.3, 2.5], abs=1e-12)   # every pose's yaw
    # The truth ends at (4, 0.5) heading -3.1 rad: 0 m, and |wrap(-3.1 - 2.5)| = 2 pi - 5.6.
    metrics = compute_metrics(run).values
    assert metrics['final_position_error'] == pytest.approx(0.0, abs=1e-12)
    assert metrics['final_heading_error'] == pytest.approx(2 * math.pi - 5.6, abs=1e-9)
    assert metrics['manoeuvres'] == 1                  # v = 1 m/s throughout
    topics['/path'] = ('nav_msgs/msg/Path', [(0.0, _parking_path(types, []))])
    empty = load_run(write_bag(tmp_path / 'empty', topics))
    assert empty.path.shape == (0, 2) and empty.path_end_heading is None
    assert empty.path_headings.shape == (0,)
    # An orientation that is not finite is NaN among the headings; the end heading is None.
    topics['/path'] = ('nav_msgs/msg/Path', [(0.0, _parking_path(
        types, [(0.0, 0.0, 0.0), (1.0, 0.0, math.nan)]))])
    unoriented = load_run(write_bag(tmp_path / 'nan', topics))
    assert unoriented.path_headings[0] == 0.0 and math.isnan(unoriented.path_headings[1])
    assert unoriented.path_end_heading is None


def test_topic_selection_and_errors(tmp_path):
    types = _types(jazzy_typestore())
    bag = write_bag(tmp_path / 'bag', mobile_topics(types))
    run = load_run(bag, ['/path'])
    assert run.path is not None and run.duration == pytest.approx(0.4)   # /clock always
    assert run.truth is None and run.odom is None and run.status is None
    assert run.counts['/ground_truth/odom'] == N                          # counts: all topics
    with pytest.raises(ValueError, match='unknown topics'):
        load_run(bag, ['/nope'])
    with pytest.raises(BagError, match='not a bag directory'):
        load_run(tmp_path / 'missing')
    data = next(bag.glob('*.mcap'))
    data.write_bytes(data.read_bytes()[:300])
    with pytest.raises(BagError, match='partial bag .*robotica bag repair'):
        load_run(bag)


def test_bag_without_known_topics_gives_empty_series(bag):
    # conftest's bag: only std_msgs/Float64 on /a and /b, a scenario without arm.
    run = load_run(bag)
    assert run.counts == {'/a': 11, '/b': 3}
    assert run.truth is None and run.path is None and run.duration == 0.0
    assert run.scenario_name == 'ej9_3a'


def _controller(types, t, names, q_d, e):
    z = np.zeros(len(names))
    return types['robotica_msgs/msg/JointControllerState'](
        header=_header(types, t, ''), law='pid', joint_names=names,
        reference_position=np.array(q_d), reference_velocity=z, reference_acceleration=z,
        position_error=np.array(e), velocity_error=z, effort=np.array(q_d) * 10.0)


def test_arm_run_keeps_the_first_joint_order(tmp_path):
    types = _types(jazzy_typestore())
    names = ['joint_1', 'joint_2']
    joint_state = types['sensor_msgs/msg/JointState']
    layout = types['std_msgs/msg/MultiArrayLayout'](dim=[], data_offset=0)
    topics = {
        '/joint_states': ('sensor_msgs/msg/JointState', [
            (0.0, joint_state(header=_header(types, 0.0, ''), name=names,
                              position=np.array([1.0, 2.0]), velocity=np.array([0.1, 0.2]),
                              effort=np.array([]))),
            (0.001, joint_state(header=_header(types, 0.001, ''), name=names[::-1],
                                position=np.array([20.0, 10.0]),
                                velocity=np.array([0.4, 0.3]), effort=np.array([])))]),
        '/joint_controller/controller_state': ('robotica_msgs/msg/JointControllerState', [
            (0.0, _controller(types, 0.0, names, [1.0, 2.0], [0.5, -0.5])),
            (0.001, _controller(types, 0.001, names, [3.0, 4.0], [0.25, -0.25]))]),
        '/joint_torques': ('std_msgs/msg/Float64MultiArray', [
            (0.0, types['std_msgs/msg/Float64MultiArray'](layout=layout,
                                                          data=np.array([5.0, 6.0]))),
            (0.001, types['std_msgs/msg/Float64MultiArray'](layout=layout,
                                                            data=np.array([7.0, 8.0])))]),
    }
    run = load_run(write_bag(tmp_path / 'bag', topics))
    assert run.is_manipulator and run.duration == 0.0
    js = run.joint_states
    assert js.names == ('joint_1', 'joint_2')
    assert js['position'].tolist() == [[1.0, 2.0], [10.0, 20.0]]   # second message reordered
    assert js['velocity'].tolist() == [[0.1, 0.2], [0.3, 0.4]]
    assert js['effort'].shape == (2, 0)
    assert run.controller['position_error'].tolist() == [[0.5, -0.5], [0.25, -0.25]]
    assert run.controller['effort'].tolist() == [[10.0, 20.0], [30.0, 40.0]]
    assert run.controller.names == ('joint_1', 'joint_2')
    assert run.torques['effort'].tolist() == [[5.0, 6.0], [7.0, 8.0]]
    assert run.torques.t == pytest.approx([0.0, 0.001])             # receive times
    assert run.scenario['arm'] == {'model': 'two_link_arm', 'lengths': [3.0, 1.0]}


def test_series_lookup_names_the_columns():
    series = Series(np.array([0.0]), {'x': np.array([1.0]), 'y': np.array([2.0])})
    assert len(series) == 1 and series['y'].tolist() == [2.0]
    with pytest.raises(KeyError, match='available: x, y'):
        series['theta']


def test_a_known_topic_of_another_type_is_ignored_with_the_reason(tmp_path):
    types = _types(jazzy_typestore())
    stamped = types['geometry_msgs/msg/TwistStamped']
    vec = types['geometry_msgs/msg/Vector3']
    twist = types['geometry_msgs/msg/Twist'](linear=vec(x=1.0, y=0.0, z=0.0),
                                             angular=vec(x=0.0, y=0.0, z=0.5))
    topics = {'/cmd_vel': ('geometry_msgs/msg/TwistStamped',
                           [(0.0, stamped(header=_header(types, 0.0), twist=twist))])}
    run = load_run(write_bag(tmp_path / 'bag', topics))
    assert run.cmd is None and run.counts == {'/cmd_vel': 1}
    assert run.ignored == {'/cmd_vel': 'it has type geometry_msgs/msg/TwistStamped, not '
                                       'geometry_msgs/msg/Twist'}
    reason = compute_metrics(run).absent['rms_angular_command']
    assert reason == ('cannot use /cmd_vel: it has type geometry_msgs/msg/TwistStamped, not '
                      'geometry_msgs/msg/Twist')


# --- GPS fixes in the world frame ---------------------------------------------------------

ORIGIN = (40.0, -3.7, 650.0)   # [deg, deg, m]: not the default origin


def test_gps_origin_from_scenario_or_default():
    origin = gps_origin({'sensors': {'gps': {'origin': [40.0, -3.7, 650.0]}}})
    assert (origin.latitude_deg, origin.longitude_deg, origin.altitude) == ORIGIN
    default = gps_origin({'name': 'x'})
    assert (default.latitude_deg, default.longitude_deg, default.altitude) == GpsSpec().origin
    assert gps_origin(None) == default
    with pytest.raises(ValueError, match='origin'):
        gps_origin({'sensors': {'gps': {'origin': [1.0, 2.0]}}})


def test_fixes_to_enu_against_the_meridian_radius():
    # 0.001° north and 0.001° east of the origin, 5 m up. Independent reference: the
    # meridian radius of curvature M = a (1 - e²) / (1 - e² sin² φ)^1.5 and the prime-vertical
    # radius N = a / sqrt(1 - e² sin² φ) of WGS-84 (a = 6378137 m, f = 1 / 298.257223563), both
    # plus the height h of the origin: arcs of (M + h) dφ north and (N + h) cos φ dλ east.
    a, f = 6378137.0, 1.0 / 298.257223563
    e2 = f * (2.0 - f)
    phi = math.radians(ORIGIN[0])
    m = a * (1.0 - e2) / (1.0 - e2 * math.sin(phi)**2)**1.5
    n = a / math.sqrt(1.0 - e2 * math.sin(phi)**2)
    step = math.radians(0.001)
    lat, lon, alt = ORIGIN
    enu = fixes_to_enu(GeodeticOrigin(*ORIGIN), [lat + 0.001, lat, float('nan'), 91.0],
                       [lon, lon + 0.001, lon, lon], [alt, alt + 5.0, 0.0, 0.0])
    np.testing.assert_allclose(enu[0, :2], [0.0, (m + ORIGIN[2]) * step], atol=2e-3)
    np.testing.assert_allclose(enu[1], [(n + ORIGIN[2]) * math.cos(phi) * step, 0.0, 5.0],
                               atol=2e-3)
    assert np.isnan(enu[2:]).all()   # no fix, and a latitude beyond the pole


# --- a run with a world: scans, range readings, the map and the contacts -------------------

def _scan(types, t, ranges):
    return types['sensor_msgs/msg/LaserScan'](
        header=_header(types, t, 'laser_link'), angle_min=-1.5, angle_max=1.5,
        angle_increment=1.5, time_increment=0.0, scan_time=0.1, range_min=0.1, range_max=8.0,
        ranges=np.asarray(ranges, dtype=np.float32), intensities=np.zeros(0, np.float32))


def _range(types, t, reading, frame):
    return types['sensor_msgs/msg/Range'](
        header=_header(types, t, frame), radiation_type=0, field_of_view=0.5, min_range=0.15,
        max_range=10.7, range=reading, variance=0.0)


def _contact(types, t, touching, x):
    point, vec = types['geometry_msgs/msg/Point'], types['geometry_msgs/msg/Vector3']
    nan = float('nan')
    return types['robotica_msgs/msg/Contact'](
        header=_header(types, t, 'map'), in_contact=touching,
        point=point(x=x if touching else nan, y=0.5 if touching else nan, z=0.0),
        normal=vec(x=nan, y=nan, z=nan), contacts=int(touching), time_in_contact=0.0)


def world_topics(types, scans=20):
    """Return scans every DT (beam 1: +inf), two sonars, a 2 x 3 map, a bumper from 0.2 s."""
    pose = types['geometry_msgs/msg/Pose'](
        position=types['geometry_msgs/msg/Point'](x=-1.0, y=-2.0, z=0.0),
        orientation=_quaternion(types, 0.5))
    info = types['nav_msgs/msg/MapMetaData'](
        map_load_time=_header(types, 0.0).stamp, resolution=0.25, width=3, height=2,
        origin=pose)
    grid = types['nav_msgs/msg/OccupancyGrid'](
        header=_header(types, 0.0, 'map'), info=info,
        data=np.array([0, 100, -1, 0, 0, 100], dtype=np.int8))
    times = [k * DT for k in range(N)]
    return {
        '/scan': ('sensor_msgs/msg/LaserScan', [
            (k * DT, _scan(types, k * DT, [1.0 + k, np.inf, np.nan])) for k in range(scans)]),
        '/sonar_10': ('sensor_msgs/msg/Range', [(t, _range(types, t, 10.7, 's10'))
                                                for t in times]),
        '/sonar_2': ('sensor_msgs/msg/Range', [(t, _range(types, t, 0.5 + t, 's2'))
                                               for t in times]),
        '/map': ('nav_msgs/msg/OccupancyGrid', [(0.0, grid)]),
        '/bumper': ('robotica_msgs/msg/Contact', [
            (t, _contact(types, t, k >= 2, 3.0 + t)) for k, t in enumerate(times)]),
    }


def world_types():
    store = jazzy_typestore()
    ensure_type(store, 'robotica_msgs/msg/Contact')
    return store, _types(store)


def test_scans_ranges_map_and_contacts_of_a_run_with_a_world(tmp_path):
    store, types = world_types()
    run = load_run(write_bag(tmp_path / 'bag', world_topics(types)))
    scans = run.scans
    assert scans.t == pytest.approx(np.arange(20) * DT)
    assert scans['ranges'].shape == (20, 3) and scans['ranges'][3, 0] == 4.0
    assert np.isposinf(scans['ranges'][:, 1]).all() and np.isnan(scans['ranges'][:, 2]).all()
    assert (scans['angle_min'][0], scans['angle_increment'][0]) == (-1.5, 1.5)
    assert (scans['range_min'][0], scans['range_max'][0]) == pytest.approx((0.1, 8.0))
    assert list(run.ranges) == ['/sonar_2', '/sonar_10']   # by index, not by name
    assert run.ranges['/sonar_2']['range'] == pytest.approx(0.5 + np.arange(N) * DT)
    assert run.ranges['/sonar_10']['max_range'] == pytest.approx(np.full(N, 10.7))
    grid = run.map_grid
    assert grid.data.tolist() == [[0, 100, -1], [0, 0, 100]] and grid.resolution == 0.25
    assert grid.origin == pytest.approx((-1.0, -2.0, 0.5))
    bumper = run.bumper   # NaN contact points while free are not corrupt values
    assert bumper['in_contact'].tolist() == [0.0, 0.0, 1.0, 1.0, 1.0]
    assert bumper['x'][2:] == pytest.approx(3.0 + np.arange(2, N) * DT)
    assert np.isnan(bumper['x'][:2]).all() and bumper['y'][2] == 0.5
    assert compute_metrics(run).values['collisions'] == 1


def test_scans_are_subsampled_evenly_to_at_most_max_scans(tmp_path, monkeypatch):
    # With at most 4 kept, 20 scans leave every 8th: 0, 8, 16 (the stride doubles past 4).
    monkeypatch.setattr(series_module, 'MAX_SCANS', 4)
    store, types = world_types()
    run = load_run(write_bag(tmp_path / 'bag', world_topics(types)))
    assert run.scans.t == pytest.approx([0.0, 0.8, 1.6])
    assert run.scans['ranges'][:, 0].tolist() == [1.0, 9.0, 17.0]
    assert run.counts['/scan'] == 20


def test_range_topics_can_be_selected(tmp_path):
    store, types = world_types()
    bag = write_bag(tmp_path / 'bag', world_topics(types))
    run = load_run(bag, ['/sonar_2', '/scan'])
    assert list(run.ranges) == ['/sonar_2'] and run.scans is not None and run.map_grid is None
    assert load_run(bag, ['/bumper']).ranges == {}
    with pytest.raises(ValueError, match='/sonar'):
        load_run(bag, ['/sonar'])


def test_run_world_from_the_scenario_or_map():
    grid = OccupancyGrid(np.zeros((2, 2), np.int8), 0.5)
    base = RunSeries(Path('runs/x/bag'), None, 0.0, {}, *[None] * 13)
    assert run_world(base) is None and base.path_end_heading is None
    assert run_world(replace(base, map_grid=grid)).world.grid is grid
    walls = run_world(replace(base, scenario={'world': {'walls': [[0, 0, 1, 0]]}}))
    assert walls.world.walls.tolist() == [[0.0, 0.0, 1.0, 0.0]] and walls.note == ''
    assert walls.world.grid is None   # /map is not drawn over a world given by its shapes
    missing = {'world': {'map': 'gone.yaml', 'circles': [[1, 1, 0.5]]}}
    found = run_world(replace(base, scenario=missing, map_grid=grid))
    assert found.world.grid is grid and len(found.world.circles) == 1 and 'gone.yaml' in found.note
    bad = run_world(replace(base, scenario={'world': {'walls': 'nope'}}, map_grid=grid))
    assert bad.world.grid is grid and 'not valid' in bad.note
    assert run_world(replace(base, scenario={'world': {'walls': 'nope'}})) is None


def test_run_world_loads_a_map_file_beside_the_bag(tmp_path):
    write_map(OccupancyGrid(np.full((2, 2), 100, np.int8), 0.5), tmp_path / 'room.yaml')
    run = RunSeries(tmp_path / 'bag', {'world': {'map': 'room.yaml'}}, 0.0, {}, *[None] * 13)
    found = run_world(run)
    assert found.world.grid.occupied.all() and found.note == ''


def test_sensor_mounts_of_the_scenario_or_the_defaults():
    assert sensor_mounts({'sensors': {'laser': {'mount': [0.1, 0.0, 0.2]}}}, 'laser').tolist() \
        == [[0.1, 0.0, 0.2]]
    assert sensor_mounts(None, 'sonar').shape == (len(SONAR_MOUNTS) // 3, 3)
    assert sensor_mounts({}, 'infrared').ravel().tolist() == list(INFRARED_MOUNTS)
    assert sensor_mounts({'sensors': {'sonar': {'mounts': [1.0, 2.0]}}}, 'sonar').shape == (0, 3)
    with pytest.raises(ValueError, match='kind'):
        sensor_mounts(None, 'radar')
