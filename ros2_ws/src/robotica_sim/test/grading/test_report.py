"""
Tests of ``robotica report`` (robotica_sim.grading.report and robotica_sim.cli.report).

The bags are synthetic, written with rosbags: a mobile run on a circular arc whose heading
crosses ±π, 0.05 m inside a concentric reference path, with sensor readings made of the truth
plus noise drawn from a seeded generator; an arm run with constant joint errors; a run with
only some topics. The figures are checked to be real images (size, coloured pixels), the page
to reference every figure written, the tracking errors to be the ones ``robotica grade``
computes. The numbers in each caption are checked by test_figures.py.
"""
import html
import math
from pathlib import Path
import re

from matplotlib.image import imread
import numpy as np
import pytest
from robotica_kin.geodetic import GeodeticOrigin
from robotica_sim.bags.typestore import ensure_type, jazzy_typestore
from robotica_sim.cli.main import run_verb
from robotica_sim.grading.metrics import compute_metrics
from robotica_sim.grading.report import default_output, ReportError, write_report
from robotica_sim.grading.series import load_run
from rosbags.interfaces import Nodetype
from rosbags.rosbag2 import StoragePlugin, Writer

RATE = 20.0                    # [Hz] of the synthetic streams
DURATION = 10.0                # [s]
RADIUS, V, W = 2.0, 0.5, 0.25  # [m], [m/s], [rad/s] the arc of the truth
THETA0 = 2.0                   # [rad] initial heading: θ crosses π at t = 4.57 s
PATH_OFFSET = 0.05             # [m] the path's radius minus the truth's: the truth is left of it
ODOM_OFFSET = (0.01, -0.02, 0.005)  # [m, m, rad] /odom minus truth
ODOM_VAR = (1e-4, 1e-4, 1e-6)       # [m^2, m^2, rad^2]: 3σ = 0.03 m, 0.03 m, 0.003 rad
GYRO_BIAS, GYRO_SIGMA = 0.01, 0.05  # [rad/s]
COMPASS_SIGMA = 0.02                # [rad]
GPS_SIGMA = 0.5                     # [m] per axis
GPS_EVERY = 4                       # one fix per 4 truth samples (5 Hz)
ORIGIN = (40.0, -3.7, 650.0)        # [deg, deg, m]: not the default origin
MOBILE_SCENARIO = f"""name: arc_test
description: Synthetic arc with every sensor.
seed: 3
pacing: lockstep
robot:
  type: differential
sensors:
  gps:
    enabled: true
    origin: [{ORIGIN[0]}, {ORIGIN[1]}, {ORIGIN[2]}]
"""
ARM_SCENARIO = 'name: arm_test\ndescription: Two joints.\nrobot:\n  type: manipulator\n'
JOINT_ERRORS = (0.01, -0.02)        # [rad] e = q_d - q, constant
MOBILE_FIGURES = {'trajectory', 'tracking_errors', 'commands', 'estimation', 'gyro',
                  'compass', 'gps'}
ARM_FIGURES = {'joint_positions', 'joint_velocities', 'joint_torques', 'joint_errors'}
NUMBER = r'-?\d+(?:\.\d*)?(?:e[-+]?\d+)?'
PRINTED = 5.1e-3                    # relative precision of a value printed with 3 digits


# --- writing bags -------------------------------------------------------------------------

def _default(store, node):
    kind, spec = node
    if kind == Nodetype.NAME:
        return _message(store, spec)
    if kind == Nodetype.BASE:
        name = spec[0]
        return '' if name == 'string' else False if name == 'bool' else \
            0.0 if name.startswith('float') else 0
    inner, length = spec
    if inner[0] == Nodetype.BASE and inner[1][0] not in ('string', 'bool'):
        return np.zeros(length if kind == Nodetype.ARRAY else 0, dtype=inner[1][0])
    return [_default(store, inner) for _ in range(length if kind == Nodetype.ARRAY else 0)]


def _message(store, msgtype, **values):
    """Return a rosbags message of ``msgtype``: ``values`` and defaults for the rest."""
    fields = {name: values[name] if name in values else _default(store, node)
              for name, node in store.fielddefs[msgtype][1]}
    return store.types[msgtype](**fields)


def _time(store, t):
    nanoseconds = round(t * 1e9)
    return _message(store, 'builtin_interfaces/msg/Time', sec=nanoseconds // 10**9,
                    nanosec=nanoseconds % 10**9)


def _header(store, t, frame='odom'):
    return _message(store, 'std_msgs/msg/Header', stamp=_time(store, t), frame_id=frame)


def _quaternion(store, yaw):
    return _message(store, 'geometry_msgs/msg/Quaternion', z=math.sin(yaw / 2.0),
                    w=math.cos(yaw / 2.0))


def _odometry(store, t, x, y, theta, v, w, variances=(0.0, 0.0, 0.0)):
    covariance = np.zeros(36)
    covariance[[0, 7, 35]] = variances
    pose = _message(store, 'geometry_msgs/msg/Pose',
                    position=_message(store, 'geometry_msgs/msg/Point', x=x, y=y),
                    orientation=_quaternion(store, theta))
    twist = _message(store, 'geometry_msgs/msg/Twist',
                     linear=_message(store, 'geometry_msgs/msg/Vector3', x=v),
                     angular=_message(store, 'geometry_msgs/msg/Vector3', z=w))
    return _message(store, 'nav_msgs/msg/Odometry', header=_header(store, t),
                    child_frame_id='base_link',
                    pose=_message(store, 'geometry_msgs/msg/PoseWithCovariance', pose=pose,
                                  covariance=covariance),
                    twist=_message(store, 'geometry_msgs/msg/TwistWithCovariance',
                                   twist=twist))


class BagBuilder:
    """Write messages into a new rosbag2 directory, one connection per topic."""

    def __init__(self, path, scenario=None):
        self.store = jazzy_typestore()
        for msgtype in ('robotica_msgs/msg/TrackingError', 'robotica_msgs/msg/SimulatorStatus',
                        'robotica_msgs/msg/JointControllerState'):
            ensure_type(self.store, msgtype)
        self.writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
        self.writer.open()
        if scenario is not None:
            self.writer.set_custom_data('robotica.scenario.yaml', scenario)
        self.connections = {}

    def write(self, topic, msgtype, t, msg):
        if topic not in self.connections:
            self.connections[topic] = self.writer.add_connection(topic, msgtype,
                                                                 typestore=self.store)
        self.writer.write(self.connections[topic], round(t * 1e9),
                          self.store.serialize_cdr(msg, msgtype))

    def clock(self, t):
        self.write('/clock', 'rosgraph_msgs/msg/Clock', t,
                   _message(self.store, 'rosgraph_msgs/msg/Clock', clock=_time(self.store, t)))

    def close(self):
        self.writer.close()


def truth_arc(t, radius=RADIUS):
    """Return x, y [m], θ [rad] of the arc at times ``t`` (θ not wrapped), or a concentric one."""
    theta = THETA0 + W * t
    centre = (-RADIUS * math.sin(THETA0), RADIUS * math.cos(THETA0))
    return centre[0] + radius * np.sin(theta), centre[1] - radius * np.cos(theta), theta


def write_mobile_bag(path):
    """Write the mobile run: the truth on the arc, the path PATH_OFFSET outside it."""
    rng = np.random.default_rng(42)
    t = np.arange(round(DURATION * RATE) + 1) / RATE
    x, y, theta = truth_arc(t)
    path_x, path_y, _ = truth_arc(t, RADIUS + PATH_OFFSET)
    noise = {'gyro': rng.normal(GYRO_BIAS, GYRO_SIGMA, t.size),
             'compass': rng.normal(0.0, COMPASS_SIGMA, t.size),
             'gps': rng.normal(0.0, GPS_SIGMA, (t.size, 2))}
    origin = GeodeticOrigin(*ORIGIN)
    bag = BagBuilder(path, MOBILE_SCENARIO)
    store = bag.store
    poses = [_message(store, 'geometry_msgs/msg/PoseStamped', header=_header(store, 0.0),
                      pose=_message(store, 'geometry_msgs/msg/Pose',
                                    position=_message(store, 'geometry_msgs/msg/Point',
                                                      x=float(px), y=float(py)),
                                    orientation=_quaternion(store, 0.0)))
             for px, py in zip(path_x, path_y)]
    bag.write('/path', 'nav_msgs/msg/Path', 0.0,
              _message(store, 'nav_msgs/msg/Path', header=_header(store, 0.0), poses=poses))
    for k, tk in enumerate(t):
        tk = float(tk)
        bag.clock(tk)
        bag.write('/ground_truth/odom', 'nav_msgs/msg/Odometry', tk,
                  _odometry(store, tk, x[k], y[k], theta[k], V, W))
        bag.write('/odom', 'nav_msgs/msg/Odometry', tk,
                  _odometry(store, tk, x[k] + ODOM_OFFSET[0], y[k] + ODOM_OFFSET[1],
                            theta[k] + ODOM_OFFSET[2], V, W, ODOM_VAR))
        twist = _message(store, 'geometry_msgs/msg/Twist',
                         linear=_message(store, 'geometry_msgs/msg/Vector3', x=V),
                         angular=_message(store, 'geometry_msgs/msg/Vector3', z=W))
        bag.write('/cmd_vel', 'geometry_msgs/msg/Twist', tk, twist)
        bag.write('/path_tracker/tracking_error', 'robotica_msgs/msg/TrackingError', tk,
                  _message(store, 'robotica_msgs/msg/TrackingError', header=_header(store, tk),
                           cross_track=0.1 * math.sin(2.0 * math.pi * tk / 5.0), heading=0.05))
        imu = _message(store, 'sensor_msgs/msg/Imu', header=_header(store, tk, 'imu_link'),
                       angular_velocity=_message(store, 'geometry_msgs/msg/Vector3',
                                                 z=W + noise['gyro'][k]))
        bag.write('/imu/data', 'sensor_msgs/msg/Imu', tk, imu)
        heading = _message(store, 'sensor_msgs/msg/Imu', header=_header(store, tk),
                           orientation=_quaternion(store, theta[k] + noise['compass'][k]))
        bag.write('/compass/heading', 'sensor_msgs/msg/Imu', tk, heading)
        if k % GPS_EVERY == 0:
            lat, lon, alt = origin.enu_to_geodetic(x[k] + noise['gps'][k, 0],
                                                   y[k] + noise['gps'][k, 1], 0.0)
            covariance = np.diag([GPS_SIGMA**2, GPS_SIGMA**2, 1.0]).ravel()
            bag.write('/gps/fix', 'sensor_msgs/msg/NavSatFix', tk,
                      _message(store, 'sensor_msgs/msg/NavSatFix',
                               header=_header(store, tk, 'gps_link'), latitude=lat,
                               longitude=lon, altitude=alt, position_covariance=covariance))
    bag.write('/simulator/status', 'robotica_msgs/msg/SimulatorStatus', DURATION,
              _message(store, 'robotica_msgs/msg/SimulatorStatus',
                       header=_header(store, DURATION), step=200, real_time_factor=12.5,
                       finished=True))
    bag.close()


def write_arm_bag(path):
    """Write a two-joint arm run at 100 Hz for 2 s with constant errors JOINT_ERRORS."""
    bag = BagBuilder(path, ARM_SCENARIO)
    store = bag.store
    names = ['shoulder', 'elbow']
    errors = np.array(JOINT_ERRORS)
    for k in range(201):
        t = k / 100.0
        q = np.array([0.5 * math.sin(t), -0.3 * math.sin(t)])
        dq = np.array([0.5 * math.cos(t), -0.3 * math.cos(t)])
        tau = np.array([3.0 + math.sin(t), -1.0])
        bag.clock(t)
        bag.write('/joint_states', 'sensor_msgs/msg/JointState', t,
                  _message(store, 'sensor_msgs/msg/JointState', header=_header(store, t),
                           name=names, position=q, velocity=dq, effort=tau))
        bag.write('/joint_controller/controller_state', 'robotica_msgs/msg/JointControllerState',
                  t, _message(store, 'robotica_msgs/msg/JointControllerState',
                              header=_header(store, t), law='pid', joint_names=names,
                              reference_position=q + errors, reference_velocity=dq,
                              reference_acceleration=np.zeros(2), position_error=errors,
                              velocity_error=np.zeros(2), effort=tau))
        command = _message(store, 'std_msgs/msg/Float64MultiArray', data=tau)
        bag.write('/joint_torques', 'std_msgs/msg/Float64MultiArray', t, command)
    bag.close()


# --- fixtures -----------------------------------------------------------------------------

@pytest.fixture(scope='module')
def mobile(tmp_path_factory):
    """Write the mobile bag and its report; return the run, the report, the progress."""
    root = tmp_path_factory.mktemp('mobile')
    write_mobile_bag(root / 'bag')
    progress = []
    run = load_run(root / 'bag')
    report = write_report(run, root / 'out', robot_every=2.0, progress=progress.append)
    return run, report, progress


@pytest.fixture(scope='module')
def arm(tmp_path_factory):
    root = tmp_path_factory.mktemp('arm')
    write_arm_bag(root / 'bag')
    return write_report(load_run(root / 'bag'), root / 'out')


def run_cli(*argv):
    """Run ``robotica report`` as the command does (errors mapped to exit codes by cli.main)."""
    return run_verb(['report', *(str(a) for a in argv)])


def caption(report, name):
    return next(f.caption for f in report.figures if f.path.stem == name)


def numbers_after(text, label):
    """Return the numbers that follow ``label`` in ``text`` (up to the next ';' or '.  ')."""
    match = re.search(re.escape(label) + r'[^;]*', text)
    assert match, f'{label!r} not in {text!r}'
    return [float(v) for v in re.findall(NUMBER, match.group(0)[len(label):])]


def assert_real_image(path, height, width=800):
    """Check that the PNG has the expected size, many colours and coloured (data) pixels."""
    image = imread(path)
    assert image.shape == (height, width, 4)
    rgb = image[..., :3]
    levels = (rgb * 255.0).round().astype(np.int64)
    colours = np.unique(levels[..., 0] << 16 | levels[..., 1] << 8 | levels[..., 2])
    assert colours.size > 100
    assert rgb.std() > 0.05
    saturation = rgb.max(axis=2) - rgb.min(axis=2)
    assert np.mean(saturation > 0.2) > 0.003   # lines and patches in colour, not only text


# --- the report --------------------------------------------------------------------------

def test_default_output_beside_the_bag():
    assert default_output(Path('runs/demo/bag')) == Path('runs/demo/report')
    assert default_output(Path('/data/run7')) == Path('/data/run7_report')


# --- mobile report ------------------------------------------------------------------------

def test_mobile_report_writes_every_figure_as_a_real_image(mobile):
    _, report, progress = mobile
    assert {f.path.stem for f in report.figures} == MOBILE_FIGURES
    for figure in report.figures:
        assert_real_image(figure.path, 500)
    assert progress[0] == 'figure 1/7: trajectory'
    assert len(progress) == 7


def test_html_references_every_png_and_the_scenario(mobile):
    _, report, _ = mobile
    page = report.index.read_text()
    written = {p.name for p in report.index.parent.glob('*.png')}
    assert set(re.findall(r'<img src="([^"]+)"', page)) == written
    assert 'arc_test' in page and 'Synthetic arc with every sensor.' in page
    # A bag without run settings: the scenario file's, said to be so.
    assert '<td>seed 3, pacing lockstep (from the scenario file' in page
    assert '<td>/gps/fix</td><td>sensor_msgs/msg/NavSatFix</td><td class="n">51</td>' in page
    assert 'real time factor 12.5' in page
    for figure in report.figures:
        assert html.escape(figure.caption) in page


def test_tracking_errors_are_those_robotica_grade_computes(mobile):
    # One projection (grading.metrics.path_errors): the true errors the report prints are
    # the grade's metrics, here a cross-track error of PATH_OFFSET up to the chords of the
    # path (sagitta (0.0256 m)^2 / (8 * 2.05 m) = 4e-5 m). The tracker's own errors are the
    # 0.1 sin(2π t / 5) m it published: mean square 0.01 * 100 / 201 over 201 samples.
    run, report, _ = mobile
    true, tracker = caption(report, 'tracking_errors').split('As the tracker')
    metrics = compute_metrics(run).values
    rms, peak = numbers_after(true, 'cross-track RMS')[:2]
    assert (rms, peak) == pytest.approx((metrics['rms_cross_track'],
                                         metrics['max_cross_track']), rel=PRINTED)
    assert rms == pytest.approx(PATH_OFFSET, abs=1e-4)
    assert numbers_after(true, 'heading RMS')[:2] == pytest.approx(
        [metrics['rms_heading_error'], metrics['max_heading_error']], rel=PRINTED)
    assert numbers_after(tracker, 'cross-track RMS')[0] == pytest.approx(
        0.1 * math.sqrt(100.0 / 201.0), rel=PRINTED)


def test_tracking_errors_need_the_truth_and_path_or_the_tracker(tmp_path):
    # No /path_tracker/tracking_error: the figure still shows the truth against /path.
    bag = BagBuilder(tmp_path / 'bag')
    store = bag.store
    x, y, theta = truth_arc(np.arange(50) / 10.0)
    poses = [_message(store, 'geometry_msgs/msg/PoseStamped', header=_header(store, 0.0),
                      pose=_message(store, 'geometry_msgs/msg/Pose',
                                    position=_message(store, 'geometry_msgs/msg/Point',
                                                      x=float(px), y=float(py))))
             for px, py in zip(x, y)]
    bag.write('/path', 'nav_msgs/msg/Path', 0.0,
              _message(store, 'nav_msgs/msg/Path', header=_header(store, 0.0), poses=poses))
    for k in range(50):
        bag.write('/ground_truth/odom', 'nav_msgs/msg/Odometry', k / 10.0,
                  _odometry(store, k / 10.0, x[k], y[k], theta[k], V, W))
    bag.close()
    report = write_report(load_run(tmp_path / 'bag'), tmp_path / 'out')
    assert [f.path.stem for f in report.figures] == ['trajectory', 'tracking_errors']
    text = caption(report, 'tracking_errors')
    assert 'True errors' in text and 'As the tracker' not in text


# --- arm and partial reports --------------------------------------------------------------

def test_arm_report_draws_the_joint_figures(arm):
    assert {f.path.stem for f in arm.figures} == ARM_FIGURES
    for figure in arm.figures:
        assert_real_image(figure.path, 500)
    # The joints' names and errors come through from the bag.
    text = caption(arm, 'joint_errors')
    for name, error in zip(('shoulder', 'elbow'), JOINT_ERRORS):
        assert numbers_after(text, f'{name} RMS')[0] == pytest.approx(abs(error))


def test_missing_topics_skip_their_figures(tmp_path):
    # A mobile run with wheel joint states but no scenario: not taken for an arm.
    bag = BagBuilder(tmp_path / 'bag')
    store = bag.store
    for k in range(50):
        t = k / 10.0
        x, y, theta = (float(v) for v in truth_arc(np.array(t)))
        bag.write('/ground_truth/odom', 'nav_msgs/msg/Odometry', t,
                  _odometry(store, t, x, y, theta, V, W))
        bag.write('/joint_states', 'sensor_msgs/msg/JointState', t,
                  _message(store, 'sensor_msgs/msg/JointState', header=_header(store, t),
                           name=['left', 'right'], position=np.array([t, t]),
                           velocity=np.zeros(2), effort=np.zeros(2)))
    bag.close()
    report = write_report(load_run(tmp_path / 'bag'), tmp_path / 'out')
    assert [f.path.stem for f in report.figures] == ['trajectory']
    assert [p.name for p in (tmp_path / 'out').glob('*.png')] == ['trajectory.png']
    assert_real_image(report.figures[0].path, 500)


# --- the command --------------------------------------------------------------------------

def test_cli_writes_to_the_default_directory(tmp_path, capsys):
    write_arm_bag(tmp_path / 'bag')
    assert run_cli(tmp_path / 'bag', '--quiet') == 0
    assert (tmp_path / 'report' / 'index.html').is_file()
    assert str(tmp_path / 'report' / 'index.html') in capsys.readouterr().out


def one_line_error(capsys):
    err = capsys.readouterr().err
    assert 'Traceback' not in err
    assert err.count('\n') == 1 and err.startswith('robotica report: ')
    return err


@pytest.mark.parametrize('kind', ['missing', 'file', 'empty_dir', 'truncated'])
def test_cli_not_a_bag_exits_1(tmp_path, bag, capsys, kind):
    target = tmp_path / 'target'
    if kind == 'file':
        target.write_text('not a bag')
    elif kind == 'empty_dir':
        target.mkdir()
    elif kind == 'truncated':
        target = bag
        mcap = next(bag.glob('*.mcap'))
        mcap.write_bytes(mcap.read_bytes()[:mcap.stat().st_size // 2])
    assert run_cli(target, '-o', tmp_path / 'out') == 1
    one_line_error(capsys)
    assert not (tmp_path / 'out').exists()


def test_cli_bag_without_plottable_topics_exits_1(tmp_path, bag, capsys):
    assert run_cli(bag, '-o', tmp_path / 'out') == 1
    assert 'nothing to plot' in one_line_error(capsys)
    with pytest.raises(ReportError):
        write_report(load_run(bag), tmp_path / 'out')


def test_cli_unwritable_output_exits_2(tmp_path, capsys):
    write_arm_bag(tmp_path / 'bag')
    (tmp_path / 'a_file').write_text('')
    assert run_cli(tmp_path / 'bag', '-o', tmp_path / 'a_file' / 'report') == 2
    assert 'cannot write' in one_line_error(capsys)


def test_cli_robot_every_must_be_positive(tmp_path, capsys):
    assert run_cli(tmp_path / 'bag', '--robot-every', '0') == 2
    assert '--robot-every' in one_line_error(capsys)


# --- a run with a world -------------------------------------------------------------------

WORLD_SCENARIO = """name: world_test
robot:
  type: differential
world:
  walls: [[-3.0, -1.0, 3.0, -1.0], [3.0, -1.0, 3.0, 3.0]]
  circles: [[0.0, 1.0, 0.3]]
sensors:
  laser: {enabled: true, mount: [0.1, 0.0, 0.0]}
"""


def write_world_bag(path):
    """Write a run along y = 0 at 0.2 m/s for 10 s; the laser sees the wall at y = -1."""
    bag = BagBuilder(path, WORLD_SCENARIO)
    store = bag.store
    ensure_type(store, 'robotica_msgs/msg/Contact')
    t = np.arange(round(DURATION * RATE) + 1) / RATE
    x = -2.0 + 0.2 * t
    angles = np.linspace(-math.pi / 2.0, 0.0, 7)
    for k, tk in enumerate(t):
        tk = float(tk)
        bag.clock(tk)
        bag.write('/ground_truth/odom', 'nav_msgs/msg/Odometry', tk,
                  _odometry(store, tk, x[k], 0.0, 0.0, 0.2, 0.0))
        touching = tk >= 9.0
        bag.write('/bumper', 'robotica_msgs/msg/Contact', tk, _message(
            store, 'robotica_msgs/msg/Contact', header=_header(store, tk, 'map'),
            in_contact=touching, point=_message(store, 'geometry_msgs/msg/Point',
                                                x=x[k] if touching else math.nan,
                                                y=-1.0 if touching else math.nan)))
        if k % 2 == 0:   # 10 Hz: beams down to the wall y = -1, 1 m below the laser
            down = np.sin(angles) < -0.2
            ranges = np.full(angles.shape, np.inf)
            ranges[down] = -1.0 / np.sin(angles[down])
            bag.write('/scan', 'sensor_msgs/msg/LaserScan', tk, _message(
                store, 'sensor_msgs/msg/LaserScan', header=_header(store, tk, 'laser_link'),
                angle_min=-math.pi / 2.0, angle_max=0.0, angle_increment=math.pi / 12.0,
                range_min=0.1, range_max=8.0, ranges=ranges.astype(np.float32)))
    bag.close()


def test_world_report_draws_the_world_the_scans_and_the_contact(tmp_path):
    write_world_bag(tmp_path / 'bag')
    run = load_run(tmp_path / 'bag')
    report = write_report(run, tmp_path / 'out', robot_every=2.0)
    (figure,) = [f for f in report.figures if f.path.stem == 'trajectory']
    assert figure.title == 'Trajectory in the world'
    image = imread(figure.path)[..., :3]
    assert image.shape == (500, 800, 3)
    red = np.all(np.abs(image - (0.839, 0.153, 0.157)) < 0.05, axis=2)   # C3: the contact
    assert np.count_nonzero(red) > 20
    assert "The world (the scenario's world: section)" in figure.caption
    assert numbers_after(figure.caption, 'returns of the /scan nearest each time (')[0] == 6
    assert 'Contacts (/bumper from free to in contact): 1, at t = 9.00 s' in figure.caption
    page = (tmp_path / 'out' / 'index.html').read_text(encoding='utf-8')
    assert 'Trajectory in the world' in page and html.escape(figure.caption) in page


def test_a_report_without_a_world_titles_the_trajectory_as_before(mobile):
    _, report, _ = mobile
    (figure,) = [f for f in report.figures if f.path.stem == 'trajectory']
    assert figure.title == 'Trajectory in the x-y plane' and 'world' not in figure.caption
