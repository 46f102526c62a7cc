"""
Node tests of markers: the MarkerArray of a path, an estimate, the truth, GPS, a target, an arm.

References are computed here by other routes: the differential footprint by hand (wheels of
c = 0.1 m at y = ±0.2 m, 0.04 m wide, a nose at 0.2 m); the ellipse by its defining property
(every point p satisfies pᵀ Σ⁻¹ p = k²); a GPS fix's local position from the WGS-84 radii of
curvature to first order (north = Δφ (M + h), as in test_gps_emulator); the PUMA 560's tool
pose from the DH model's ``fkine`` and its quaternion read by SciPy.
"""
import math
import signal

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point
from nav_msgs.msg import Odometry, Path
import numpy as np
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.forward_kinematics import fkine
from robotica_kin.robots import puma560
from robotica_kin.ros.convert import path_message
from robotica_kin.ros.qos import LATCHED_QOS
from robotica_msgs.msg import JointControllerState, TrackingError
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import NavSatFix
from visualization_msgs.msg import Marker, MarkerArray

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
A, F = 6378137.0, 1.0 / 298.257223563       # WGS-84
E2 = F * (2.0 - F)
LAT0, LON0, H0 = 37.41, -6.0, 10.0
SIGMA = np.array([[0.09, 0.02], [0.02, 0.04]])   # x-y covariance of the estimate [m²]
K = 2.0
ALL = {('path', 0), ('target', 0), ('footprint', 0), ('footprint', 1), ('covariance', 0),
       ('gps', 0), ('tool', 0)}


def _odometry(frame, x, y, yaw, sec):
    msg = Odometry()
    msg.header.stamp, msg.header.frame_id = Time(sec=sec, nanosec=5), frame
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    covariance = np.zeros((6, 6))
    covariance[:2, :2] = SIGMA
    covariance[5, 5] = 0.01
    msg.pose.covariance = [float(v) for v in covariance.ravel()]
    return msg


def _fix(north, sec):
    phi = math.radians(LAT0)
    m = A * (1.0 - E2) / (1.0 - E2 * math.sin(phi) ** 2) ** 1.5
    msg = NavSatFix(latitude=LAT0 + math.degrees(north / (m + H0)), longitude=LON0, altitude=H0)
    msg.header.stamp = Time(sec=sec)
    return msg


def _yaw(q):
    return 2.0 * math.atan2(q.z, q.w)


def _xy(points):
    return np.array([[p.x, p.y] for p in points])


def test_markers_of_a_run(start_node, ros_node, spin):
    node, executor = ros_node
    proc = start_node(
        'robotica_sim', 'markers', '-p', 'vehicle.type:=differential', '-p', f'covariance_k:={K}',
        '-p', 'publish_rate:=20.0', '-p', 'robot:=puma560', '-p', f'origin.latitude:={LAT0}',
        '-p', f'origin.longitude:={LON0}', '-p', f'origin.altitude:={H0}', '-p', 'gps_history:=2')
    markers, stamps = {}, []

    def received(msg):
        for marker in msg.markers:
            markers[(marker.ns, marker.id)] = marker
            stamps.append((marker.ns, marker.header.stamp.sec))
    node.create_subscription(MarkerArray, 'markers', received, QOS)
    path_pub = node.create_publisher(Path, 'path', LATCHED_QOS)
    path = [[0.0, 0.0], [1.0, 0.5], [2.0, 2.0]]
    path_msg = path_message(path, 'map', t=1.0)
    path_pub.publish(path_msg)
    pubs = {topic: node.create_publisher(msg_type, topic, QOS) for topic, msg_type in (
        ('odom', Odometry), ('ground_truth/odom', Odometry), ('gps/fix', NavSatFix),
        ('path_tracker/tracking_error', TrackingError),
        ('joint_controller/controller_state', JointControllerState))}
    assert spin(executor, lambda: all(p.get_subscription_count() > 0 for p in pubs.values())
                and node.count_publishers('markers') > 0)
    error = TrackingError(target_point=Point(x=3.0, y=4.0))
    error.header.stamp, error.header.frame_id = Time(sec=7), 'odom'
    q = np.array([0.1, -0.4, 0.3, 0.2, 0.5, -0.6])
    names = [f'joint_{i}' for i in range(6, 0, -1)]   # reversed: the node maps by name
    state = JointControllerState(joint_names=names, reference_position=q[::-1].tolist())
    state.header.stamp = Time(sec=8)
    fixes = [_fix(0.0, 5), _fix(100.0, 6)]   # gps_history 2: the newest two are these
    sent = {'odom': _odometry('odom', 1.0, 2.0, 0.5, 3),
            'ground_truth/odom': _odometry('map', 1.1, 2.1, 0.4, 4),
            'path_tracker/tracking_error': error, 'joint_controller/controller_state': state}

    def send_all_and_check():   # resent until answered: a first message may find no reader
        for topic, msg in sent.items():
            pubs[topic].publish(msg)
        for fix in fixes:
            pubs['gps/fix'].publish(fix)
        spin(executor, lambda: ALL <= set(markers), 0.2)
        return ALL <= set(markers)

    assert spin(executor, send_all_and_check, timeout=20.0)
    path_marker = markers[('path', 0)]
    assert path_marker.type == Marker.LINE_STRIP and path_marker.header.frame_id == 'map'
    np.testing.assert_array_equal(_xy(path_marker.points), path)
    assert path_marker.lifetime.sec == path_marker.lifetime.nanosec == 0   # until replaced
    assert path_marker.header.stamp == path_msg.header.stamp

    target = markers[('target', 0)]
    assert target.type == Marker.SPHERE and target.header.frame_id == 'odom'
    assert (target.pose.position.x, target.pose.position.y) == (3.0, 4.0)
    assert target.header.stamp == Time(sec=7) and target.lifetime.sec == 2

    pentagon = [[-0.1, -0.22], [0.1, -0.22], [0.2, 0.0], [0.1, 0.22], [-0.1, 0.22],
                [-0.1, -0.22]]
    for marker_id, frame, x, y, yaw, sec in ((0, 'odom', 1.0, 2.0, 0.5, 3),
                                             (1, 'map', 1.1, 2.1, 0.4, 4)):
        footprint = markers[('footprint', marker_id)]
        assert footprint.type == Marker.LINE_STRIP and footprint.header.frame_id == frame
        assert footprint.header.stamp == Time(sec=sec, nanosec=5)
        assert (footprint.pose.position.x, footprint.pose.position.y) == (x, y)
        assert _yaw(footprint.pose.orientation) == pytest.approx(yaw, abs=1e-12)
        np.testing.assert_allclose(_xy(footprint.points), pentagon, atol=1e-12)
    assert markers[('footprint', 0)].color != markers[('footprint', 1)].color

    ellipse = markers[('covariance', 0)]
    assert ellipse.type == Marker.LINE_STRIP and ellipse.header.frame_id == 'odom'
    assert (ellipse.pose.position.x, ellipse.pose.position.y) == (1.0, 2.0)
    offsets = _xy(ellipse.points)
    assert len(offsets) > 16 and np.array_equal(offsets[0], offsets[-1])
    np.testing.assert_allclose(np.einsum('ij,jk,ik->i', offsets, np.linalg.inv(SIGMA), offsets),
                               K ** 2, rtol=1e-9)

    gps = markers[('gps', 0)]
    assert gps.type == Marker.POINTS and gps.header.frame_id == 'map'
    assert gps.header.stamp == Time(sec=6)   # the newest fix
    np.testing.assert_allclose(_xy(gps.points), [[0.0, 0.0], [0.0, 100.0]], atol=0.01)

    tool = markers[('tool', 0)]
    T = fkine(puma560(), q)
    assert tool.type == Marker.LINE_LIST and tool.header.frame_id == 'link_0'
    assert tool.header.stamp == Time(sec=8)
    p, o = tool.pose.position, tool.pose.orientation
    np.testing.assert_allclose([p.x, p.y, p.z], T[:3, 3], atol=1e-12)
    np.testing.assert_allclose(Rotation.from_quat([o.x, o.y, o.z, o.w]).as_matrix(), T[:3, :3],
                               atol=1e-9)
    assert [(c.r, c.g, c.b) for c in tool.colors[::2]] == [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                                                           (0.0, 0.0, 1.0)]

    # A covariance that is not one drops its message: no marker of t = 50 s; t = 51 s is drawn.
    bad, good = _odometry('odom', 1.0, 2.0, 0.5, 50), _odometry('odom', 1.5, 2.0, 0.5, 51)
    bad.pose.covariance[1] = 5.0   # x-y entry without its y-x twin
    pubs['odom'].publish(bad)
    assert spin(executor, lambda: (pubs['odom'].publish(good),
                                   markers[('covariance', 0)].header.stamp.sec == 51)[-1], 10.0)
    assert ('footprint', 50) not in stamps and ('covariance', 50) not in stamps
    assert markers[('footprint', 0)].pose.position.x == 1.5
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=15) == 0


def test_a_parameter_out_of_range_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'markers', '-p', 'covariance_k:=0.0')
    assert proc.wait(timeout=30) != 0
    assert 'covariance_k' in read_output(proc)
