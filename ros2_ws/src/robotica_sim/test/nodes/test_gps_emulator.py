"""
Node tests of gps_emulator: fixes from a ground-truth stream, in WGS-84, with their covariance.

The reference latitude and longitude of an ENU offset are computed here with the local radii of
curvature of the WGS-84 ellipsoid (meridian M and prime vertical N), an independent first-order
formula good to millimetres over a few hundred metres: Δφ = north / (M + h),
Δλ = east / ((N + h) cos φ).
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import STREAM_PUB_QOS
from sensor_msgs.msg import NavSatFix, NavSatStatus

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)
A, F = 6378137.0, 1.0 / 298.257223563       # WGS-84
E2 = F * (2.0 - F)


def expected_lat_lon(lat0_deg, lon0_deg, h, east, north):
    phi = math.radians(lat0_deg)
    w = math.sqrt(1.0 - E2 * math.sin(phi) ** 2)
    m, n = A * (1.0 - E2) / w ** 3, A / w
    return (lat0_deg + math.degrees(north / (m + h)),
            lon0_deg + math.degrees(east / ((n + h) * math.cos(phi))))


def truth(t, x, y):
    msg = Odometry()
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    msg.header.frame_id = 'map'
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.w = 1.0
    return msg


def test_rtk_fixes_at_the_rate_with_latency(start_node, ros_node, spin):
    node, executor = ros_node
    proc = start_node('robotica_sim', 'gps_emulator', '-p', 'preset:=rtk', '-p', 'seed:=3',
                      '-p', 'origin.latitude:=37.41', '-p', 'origin.longitude:=-6.0',
                      '-p', 'origin.altitude:=10.0')
    fixes = []
    node.create_subscription(NavSatFix, 'gps/fix', fixes.append, QOS)
    pub = node.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
    assert spin(executor, lambda: pub.get_subscription_count() > 0
                and node.count_publishers('gps/fix') > 0)
    spin(executor, lambda: False, timeout=1.0)   # let the node's writer match this reader
    east, north = 120.0, -250.0
    for k in range(101):                          # 2 s at 50 Hz
        pub.publish(truth(0.02 * k, east, north))
        spin(executor, lambda: False, timeout=0.005)
    assert spin(executor, lambda: len(fixes) >= 20, timeout=10.0)
    stamps = [f.header.stamp.sec + f.header.stamp.nanosec * 1e-9 for f in fixes]
    # 10 Hz; the fix of t = 1.95 s is not out yet (latency 0.05 s, last truth at 2.0 s).
    assert len(fixes) == 20 or len(fixes) == 21
    assert stamps[:3] == pytest.approx([0.0, 0.1, 0.2], abs=1e-6)
    lat, lon = expected_lat_lon(37.41, -6.0, 10.0, east, north)
    for fix in fixes:
        assert fix.status.status == NavSatStatus.STATUS_GBAS_FIX
        assert fix.position_covariance_type == NavSatFix.COVARIANCE_TYPE_KNOWN
        sigma = math.sqrt(fix.position_covariance[0])
        assert 0.005 < sigma < 0.01                                # 2DRMS 2 cm
        assert (fix.latitude - lat) * 111e3 == pytest.approx(0.0, abs=6 * sigma + 0.01)
        assert (fix.longitude - lon) * 88e3 == pytest.approx(0.0, abs=6 * sigma + 0.01)
    assert proc.poll() is None


def test_unknown_preset_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'gps_emulator', '-p', 'preset:=galileo')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert "preset must be one of ('sa_standalone', 'standalone', 'dgps', 'rtk')" in text
    assert 'Traceback' not in text


def test_origin_beyond_its_range_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'gps_emulator', '-p', 'origin.altitude:=200000.0')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'origin.altitude' in text and 'Traceback' not in text


def test_terms_checked_together_at_start_up(start_node, read_output):
    # Each within its range, but the white part exceeds the DGPS preset's total 0.35 m.
    proc = start_node('robotica_sim', 'gps_emulator', '-p', 'preset:=dgps',
                      '-p', 'white_stddev:=1.0')
    assert proc.wait(timeout=30) == 2
    assert 'white_stddev must be in [0, min(horizontal_stddev' in read_output(proc)
