"""
Node tests of odometry: dead reckoning from ticks, the turn from a gyro, a GPS correction.

Expected values are worked out here: a wheel of c = 0.1 m on a 1000-count encoder moves
2π c / 1000 = 0.6283 mm per count; the odometry's distance variance grows by k_distance per metre
travelled; a Kalman update of a position with variance P by a fix with variance R moves it by
P / (P + R) of the innovation.
"""
import math

from nav_msgs.msg import Odometry
import pytest
from rclpy.qos import DurabilityPolicy, qos_profile_sensor_data, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.qos import LATCHED_QOS, STREAM_PUB_QOS
from robotica_msgs.msg import WheelEncoders
from sensor_msgs.msg import Imu, NavSatFix
from tf2_msgs.msg import TFMessage

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
METRES_PER_TICK = 2.0 * math.pi * 0.1 / 1000


def ticks(t, left, right):
    msg = WheelEncoders(left_ticks=left, right_ticks=right, ticks_per_revolution=1000)
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t - int(t)) * 1e9)
    return msg


def ready(node, executor, spin, *publishers):
    assert spin(executor, lambda: all(p.get_subscription_count() > 0 for p in publishers)
                and node.count_publishers('odom') > 0)
    spin(executor, lambda: False, timeout=1.0)


def started(start_node, ros_node, spin, *arguments):
    """Start an odometry; return its received odom messages and an encoder publisher."""
    node, executor = ros_node
    start_node('robotica_sim', 'odometry', *arguments)
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    pub = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    ready(node, executor, spin, pub)
    return odom, pub


def test_straight_line_dead_reckoning_and_its_covariance(start_node, ros_node, spin):
    node, executor = ros_node
    odom, pub = started(start_node, ros_node, spin, '-p', 'odometry_noise.k_distance:=0.002')
    for k in range(11):
        pub.publish(ticks(0.1 * k, 100 * k, 100 * k))
        spin(executor, lambda: False, timeout=0.02)
    assert spin(executor, lambda: len(odom) >= 11)
    last = odom[-1]
    distance = 1000 * METRES_PER_TICK
    assert last.pose.pose.position.x == pytest.approx(distance, abs=1e-9)
    assert last.pose.pose.position.y == pytest.approx(0.0, abs=1e-9)
    assert last.pose.covariance[0] == pytest.approx(0.002 * distance, rel=1e-6)
    assert last.twist.twist.linear.x == pytest.approx(100 * METRES_PER_TICK / 0.1, rel=1e-6)


def test_heading_from_the_gyro(start_node, ros_node, spin):
    node, executor = ros_node
    start_node('robotica_sim', 'odometry', '-p', 'heading_source:=gyro')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    imu = node.create_publisher(Imu, 'imu/data', STREAM_PUB_QOS)
    ready(node, executor, spin, enc, imu)
    for k in range(11):
        gyro = Imu()
        gyro.header.stamp = ticks(0.1 * k, 0, 0).header.stamp
        gyro.angular_velocity.z = 0.5
        imu.publish(gyro)
        spin(executor, lambda: False, timeout=0.05)
        enc.publish(ticks(0.1 * k, 0, 0))        # spinning in place: the wheels do not roll
        spin(executor, lambda: False, timeout=0.05)
    assert spin(executor, lambda: len(odom) >= 11)
    q = odom[-1].pose.pose.orientation
    assert 2.0 * math.atan2(q.z, q.w) == pytest.approx(0.5 * 1.0, abs=1e-9)


def test_sensor_data_gyro_is_read_with_qos_overrides(start_node, ros_node, spin):
    # A driver publishing sensor-data QoS (best effort, volatile) is matched once the reader's
    # reliability and durability are overridden by parameter (rclpy's qos_overrides).
    node, executor = ros_node
    prefix = 'qos_overrides./imu/data.subscription.'
    start_node('robotica_sim', 'odometry', '-p', 'heading_source:=gyro',
               '-p', f'{prefix}reliability:=best_effort', '-p', f'{prefix}durability:=volatile')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    imu = node.create_publisher(Imu, 'imu/data', qos_profile_sensor_data)
    ready(node, executor, spin, enc, imu)
    [reader] = node.get_subscriptions_info_by_topic('/imu/data')
    assert reader.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
    assert reader.qos_profile.durability == DurabilityPolicy.VOLATILE
    for k in range(11):
        imu.publish(gyro_sample(0.1 * k, 0.5))
        spin(executor, lambda: False, timeout=0.05)
        enc.publish(ticks(0.1 * k, 0, 0))
        spin(executor, lambda: False, timeout=0.05)
    assert spin(executor, lambda: len(odom) >= 11)
    q = odom[-1].pose.pose.orientation
    assert 2.0 * math.atan2(q.z, q.w) == pytest.approx(0.5, abs=1e-9)


def gyro_sample(t, rate):
    msg = Imu()
    msg.header.stamp = ticks(t, 0, 0).header.stamp
    msg.angular_velocity.z = rate
    return msg


def test_gyro_samples_published_before_the_odometry_started_are_used(start_node, ros_node,
                                                                     spin):
    # A gyro whose samples went out before the odometry's subscription was matched (a loaded
    # machine, discovery late): its history is replayed, and each reading waits for the sample
    # of its time. 0.5 rad/s over (0, 1] s: 0.5 rad; with the samples lost, 0.
    node, executor = ros_node
    imu = node.create_publisher(Imu, 'imu/data', STREAM_PUB_QOS)
    for k in range(1, 11):
        imu.publish(gyro_sample(0.1 * k, 0.5))
    start_node('robotica_sim', 'odometry', '-p', 'heading_source:=gyro')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    ready(node, executor, spin, enc, imu)
    for k in range(11):
        enc.publish(ticks(0.1 * k, 0, 0))
    assert spin(executor, lambda: len(odom) >= 11)
    q = odom[-1].pose.pose.orientation
    assert 2.0 * math.atan2(q.z, q.w) == pytest.approx(0.5, abs=1e-9)


def test_replayed_history_older_than_the_first_reading_is_dropped(start_node, ros_node, spin):
    # A restarted odometry gets the compass's history (1 rad, from t = 0 to 0.5 s); it starts at
    # its first encoder reading (t = 1 s) and applies only what comes after: one reading of
    # 1 rad with R = 1 rad² against P = 1 rad² moves the heading by P / (P + R) = 1/2 of it.
    node, executor = ros_node
    compass = node.create_publisher(Imu, 'compass/heading', STREAM_PUB_QOS)
    heading = Imu()
    heading.orientation.z, heading.orientation.w = math.sin(0.5), math.cos(0.5)
    heading.orientation_covariance[8] = 1.0
    for k in range(6):
        heading.header.stamp = ticks(0.1 * k, 0, 0).header.stamp
        compass.publish(heading)
    start_node('robotica_sim', 'odometry', '-p', 'fuse_compass:=true',
               '-p', 'initial_stddev.heading:=1.0')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    ready(node, executor, spin, enc, compass)
    enc.publish(ticks(1.0, 0, 0))
    assert spin(executor, lambda: odom)
    assert odom[-1].pose.covariance[35] == pytest.approx(1.0, abs=1e-12)   # nothing applied
    heading.header.stamp = ticks(1.1, 0, 0).header.stamp
    compass.publish(heading)
    enc.publish(ticks(1.1, 0, 0))            # it waits for the compass reading of its time
    assert spin(executor, lambda: len(odom) >= 2)
    q = odom[-1].pose.pose.orientation
    assert 2.0 * math.atan2(q.z, q.w) == pytest.approx(0.5, abs=1e-9)


def test_gps_fix_pulls_the_estimate(start_node, ros_node, spin):
    node, executor = ros_node
    start_node('robotica_sim', 'odometry', '-p', 'fuse_gps:=true',
               '-p', 'initial_stddev.position:=1.0', '-p', 'origin.latitude:=0.0',
               '-p', 'origin.longitude:=0.0', '-p', 'origin.altitude:=0.0')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    gps = node.create_publisher(NavSatFix, 'gps/fix', STREAM_PUB_QOS)
    ready(node, executor, spin, enc, gps)
    # 2 m east of the origin on the equator: 2 / a rad of longitude (a = 6378137 m).
    fix = NavSatFix(latitude=0.0, longitude=math.degrees(2.0 / 6378137.0), altitude=0.0,
                    position_covariance=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                    position_covariance_type=NavSatFix.COVARIANCE_TYPE_KNOWN)
    gps.publish(fix)
    spin(executor, lambda: False, timeout=0.5)
    enc.publish(ticks(0.0, 0, 0))
    assert spin(executor, lambda: odom)
    x = odom[-1].pose.pose.position.x
    assert x == pytest.approx(1.0, abs=1e-6)                 # P / (P + R) = 1/2 of 2 m
    assert odom[-1].pose.covariance[0] == pytest.approx(0.5, abs=1e-9)


def transforms(messages):
    """Return {(parent, child): [(stamp [s], x, y, yaw), ...]} of received TF messages."""
    out = {}
    for msg in messages:
        for tf in msg.transforms:
            stamp = tf.header.stamp.sec + tf.header.stamp.nanosec * 1e-9
            q, p = tf.transform.rotation, tf.transform.translation
            out.setdefault((tf.header.frame_id, tf.child_frame_id), []).append(
                (stamp, p.x, p.y, 2.0 * math.atan2(q.z, q.w)))
    return out


def test_dead_reckoning_is_odom_to_base_link_on_tf(start_node, ros_node, spin):
    # REP-105 without an absolute sensor: odom -> base_link is the estimate, stamped with the
    # reading's time; map -> odom is the identity, latched on /tf_static.
    node, executor = ros_node
    tf, static = [], []
    node.create_subscription(TFMessage, '/tf', tf.append, QOS)
    node.create_subscription(TFMessage, '/tf_static', static.append, LATCHED_QOS)
    _, pub = started(start_node, ros_node, spin)
    for k in range(6):
        pub.publish(ticks(0.1 * k, 100 * k, 100 * k))
        spin(executor, lambda: False, timeout=0.02)
    assert spin(executor, lambda: len(transforms(tf).get(('odom', 'base_link'), [])) >= 6
                and static)
    stamp, x, y, yaw = transforms(tf)[('odom', 'base_link')][-1]
    assert stamp == pytest.approx(0.5, abs=1e-9)
    assert (x, y, yaw) == pytest.approx((500 * METRES_PER_TICK, 0.0, 0.0), abs=1e-9)
    assert transforms(static) == {('map', 'odom'): [(0.0, 0.0, 0.0, 0.0)]}
    assert set(transforms(tf)) == {('odom', 'base_link')}


def test_gps_fusion_publishes_map_to_odom_as_two_filters_do(start_node, ros_node, spin):
    # A fix 2 m east (R = 1 m², P = 1 m²) pulls the fused estimate to x = 1 m at t = 0; then
    # 5 readings of 100 counts straight ahead. Dead reckoning alone (odom -> base_link) never
    # saw the fix: x = 500 counts; map -> odom carries the correction, 1 m, so that
    # map -> odom -> base_link is the fused estimate (1 m + 500 counts).
    node, executor = ros_node
    start_node('robotica_sim', 'odometry', '-p', 'fuse_gps:=true',
               '-p', 'initial_stddev.position:=1.0', '-p', 'origin.latitude:=0.0',
               '-p', 'origin.longitude:=0.0', '-p', 'origin.altitude:=0.0')
    odom, tf = [], []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    node.create_subscription(TFMessage, '/tf', tf.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    gps = node.create_publisher(NavSatFix, 'gps/fix', STREAM_PUB_QOS)
    ready(node, executor, spin, enc, gps)
    gps.publish(NavSatFix(latitude=0.0, longitude=math.degrees(2.0 / 6378137.0), altitude=0.0,
                          position_covariance=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                          position_covariance_type=NavSatFix.COVARIANCE_TYPE_KNOWN))
    spin(executor, lambda: False, timeout=0.5)
    for k in range(6):
        enc.publish(ticks(0.1 * k, 100 * k, 100 * k))
        spin(executor, lambda: False, timeout=0.02)
    assert spin(executor, lambda: len(transforms(tf).get(('map', 'odom'), [])) >= 6)
    travel = 500 * METRES_PER_TICK
    assert odom[-1].pose.pose.position.x == pytest.approx(1.0 + travel, abs=1e-6)
    frames = transforms(tf)
    assert frames[('odom', 'base_link')][-1] == pytest.approx((0.5, travel, 0.0, 0.0), abs=1e-9)
    assert frames[('map', 'odom')][-1] == pytest.approx((0.5, 1.0, 0.0, 0.0), abs=1e-6)


def test_publish_tf_false_publishes_no_transforms(start_node, ros_node, spin):
    node, executor = ros_node
    odom, pub = started(start_node, ros_node, spin, '-p', 'publish_tf:=false')
    pub.publish(ticks(0.0, 0, 0))
    assert spin(executor, lambda: odom)
    assert node.count_publishers('/tf') == node.count_publishers('/tf_static') == 0


def test_bad_heading_source_is_refused(start_node, read_output):
    proc = start_node('robotica_sim', 'odometry', '-p', 'heading_source:=stars')
    assert proc.wait(timeout=30) == 2
    assert 'heading_source must be one of' in read_output(proc)


def test_a_wheel_beyond_the_planned_range_is_refused(start_node, read_output):
    # The range of robotica_kin.mobile.odometry_fusion.ODOMETRY_PARAMETERS, which the plan
    # checks too (test/runs/test_plan_node_checks.py: a nominal wheel of 10.8 m).
    proc = start_node('robotica_sim', 'odometry', '-p', 'wheel_radius:=10.8')
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'wheel_radius' in text and 'Traceback' not in text


def test_filter_that_rejects_every_heading_is_reopened(start_node, ros_node, spin,
                                                       read_output):
    # A certain heading of 0 (initial std. dev. 0) against a compass reading 1 rad with a
    # variance of 1e-6 rad²: the gate rejects it; after gate.max_rejections = 3 in a row the
    # heading variance grows by 1 rad² and the update gives 1 / (1 + 1e-6) of the innovation.
    node, executor = ros_node
    proc = start_node('robotica_sim', 'odometry', '-p', 'fuse_compass:=true',
                      '-p', 'gate.max_rejections:=3')
    odom = []
    node.create_subscription(Odometry, 'odom', odom.append, QOS)
    enc = node.create_publisher(WheelEncoders, 'wheel_encoders', QOS)
    compass = node.create_publisher(Imu, 'compass/heading', STREAM_PUB_QOS)
    ready(node, executor, spin, enc, compass)
    heading = Imu()
    heading.orientation.z, heading.orientation.w = math.sin(0.5), math.cos(0.5)
    heading.orientation_covariance[8] = 1e-6
    for _ in range(3):
        compass.publish(heading)
        spin(executor, lambda: False, timeout=0.2)
    enc.publish(ticks(0.0, 0, 0))
    assert spin(executor, lambda: odom)
    q = odom[-1].pose.pose.orientation
    assert 2.0 * math.atan2(q.z, q.w) == pytest.approx(1.0 / (1.0 + 1e-6), abs=1e-6)
    assert 'rejected by the innovation gate' in read_output(proc)
    assert 'covariance inflated, compass heading applied' in read_output(proc)
