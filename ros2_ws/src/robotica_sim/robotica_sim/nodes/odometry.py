"""
Odometry node: dead reckoning from wheel-encoder ticks, fused with gyro, compass and GPS.

Every ``wheel_encoders`` reading (robotica_msgs/WheelEncoders) moves the estimate by the wheels'
travel since the previous one, by the slides' equations (catalog §13.6): ΔU = C_m Δticks with
C_m = 2π c / ticks_per_revolution (each wheel with its nominal radius: ``left_wheel_radius``,
``right_wheel_radius``, or ``wheel_radius`` where they are 0), ΔU_c = (ΔU_l + ΔU_r)/2,
Δθ = (ΔU_r − ΔU_l)/b, applied with
``integration_method`` (``euler``, ``midpoint`` or the exact arc (4.93), book §4.7.5). With
``heading_source`` = ``gyro`` the heading increment is instead the integral of the yaw rate of
``imu/data`` (sensor_msgs/Imu) since the previous reading: the encoders then give the distance
only (synchronous drive, skid steer, slipping wheels). A rate beyond ``MAX_ANGULAR_RATE`` of
robotica_kin.bounds, or a variance beyond its square, is ignored like a non-finite one.

The estimate and its covariance are those of
:class:`robotica_kin.mobile.ekf_localization.EkfLocalization`: the prediction propagates the
odometry error model ``odometry_noise.*`` (or the gyro's reported variance), and, when enabled,
``gps/fix`` (sensor_msgs/NavSatFix, converted to the local ENU frame of ``origin.*``) and
``compass/heading`` (sensor_msgs/Imu orientation) correct it, each behind a chi-square gate
(rejections are counted and logged). A GPS error that is correlated in time (every preset's
is) makes a filter that takes each fix as independent overconfident; ``gps_bias.stddev`` > 0
estimates it as two more, Gauss–Markov, states (``gps_bias.correlation_time``). Without fusion
it is pure dead reckoning with a growing covariance. Measurements are applied when they
arrive, except that one newer than the estimate waits until an encoder reading reaches its
time; a fix's latency (0.1 s for DGPS) is not compensated.
The gyro, compass and GPS are subscribed transient-local (a late match replays the
publisher's history, robotica_kin.ros.qos); the encoder readings volatile: the first one the
node receives starts the estimate, and anything older is dropped, so that a restarted node does
not apply stale history. With the heading from the gyro, the first reading is not answered
before a gyro publisher is matched, and each later one waits for the gyro sample (and with
``fuse_compass`` the compass reading) of its time.
Publishes ``odom`` (nav_msgs/Odometry: pose in ``odom_frame_id``, twist in ``base_frame_id``,
REP-105, pose covariance of x, y and yaw) at each encoder reading.

With ``publish_tf`` (as robot_localization and diff_drive_controller name it) it also publishes,
stamped with the reading's time, the REP-105 transforms (docs/nodes.md has the tree):

* without an absolute measurement (no GPS, no compass) ``odom_frame_id`` -> ``base_frame_id``
  is the estimate, and ``map_frame_id`` -> ``odom_frame_id`` the identity, once on
  ``/tf_static``: the estimate starts at the true pose, so odom and map coincide at the start;
* with GPS or compass fusion, as robot_localization's two-filter setup: ``odom`` ->
  ``base_link`` is the dead reckoning alone (the estimate's own increments, continuous, never
  jumping at a fix), and ``map`` -> ``odom`` = (map -> base_link, the fused estimate) x
  inverse(odom -> base_link), on ``/tf`` with each reading; so ``map`` -> ``base_link`` through
  the tree is the fused estimate, while ``odom`` keeps the smooth pose a local planner needs.

No ``map`` -> ``odom`` is published when ``map_frame_id`` equals ``odom_frame_id``.

The estimator is :class:`robotica_kin.mobile.odometry_fusion.OdometryFusion`; this node declares
its parameters, converts the messages to numbers (the fix to ENU), passes them in, logs what it
reports and publishes each estimate.
"""
import math

from nav_msgs.msg import Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import (bounded, MAX_ANGULAR_RATE, MAX_LATITUDE, MAX_LONGITUDE, MAX_SPEED,
                                 MAX_TIME_JUMP)
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.mobile.ekf_localization import OdometryNoise
from robotica_kin.mobile.odometry import odometry_increment, ODOMETRY_METHODS
from robotica_kin.mobile.odometry_fusion import (FusionEvent, HEADING_SOURCES,
                                                 ODOMETRY_PARAMETERS, OdometryEstimate,
                                                 OdometryFusion, OdometryFusionParams)
from robotica_kin.ros.convert import (odometry_message, planar_transform, quaternion_to_yaw,
                                      stamp_to_seconds)
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import (INPUT_QOS_OVERRIDES, LATCHED_QOS, STREAM_PUB_QOS,
                                  STREAM_REPLAY_SUB_QOS, STREAM_SUB_QOS, TF_QOS)
from robotica_msgs.msg import WheelEncoders
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus
from tf2_msgs.msg import TFMessage

SENSOR_NAMES = {'position': 'GPS fix', 'heading': 'compass heading'}   # in the log


def _se2(pose) -> np.ndarray:
    """Return the homogeneous (3, 3) matrix of a planar pose (x [m], y [m], theta [rad])."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])


def map_to_odom(fused, dead_reckoning) -> tuple[float, float, float]:
    """
    Return map -> odom (x, y, theta) = map -> base_link (fused) x inverse(odom -> base_link).

    >>> [round(v, 12) for v in map_to_odom((1.0, 1.0, math.pi / 2), (1.0, 0.0, 0.0))]
    [1.0, 0.0, 1.570796326795]
    """
    T = _se2(fused) @ np.linalg.inv(_se2(dead_reckoning))
    return float(T[0, 2]), float(T[1, 2]), math.atan2(T[1, 0], T[0, 0])


class OdometryNode(GuardedNode):
    """Integrate encoder ticks (and gyro rates) into a pose estimate; fuse GPS and compass."""

    def __init__(self) -> None:
        super().__init__('odometry')
        values = declare_specs(self, ODOMETRY_PARAMETERS)   # the ranges the plan checks
        radius, track = values['wheel_radius'], values['wheel_separation']
        method = declare(self, 'integration_method', 'exact_arc',
                         f'Pose update: one of {ODOMETRY_METHODS} (slides §13.6, book (4.93))',
                         read_only=True)
        heading_source = declare(self, 'heading_source', 'encoders',
                                 f'Heading increments from: one of {HEADING_SOURCES}',
                                 read_only=True)
        pose = [values[f'initial_pose.{k}'] for k in ('x', 'y', 'theta')]   # odom frame
        sigma0 = [declare(self, 'initial_stddev.' + k, 0.0, d, low=0.0, high=1e6,
                          read_only=True)
                  for k, d in (('position', 'Initial position std. dev. [m] per axis'),
                               ('heading', 'Initial heading std. dev. [rad]'))]
        defaults = OdometryNoise()
        noise = OdometryNoise(**{
            k: declare(self, 'odometry_noise.' + k, getattr(defaults, k), d, low=0.0, high=1.0,
                       read_only=True)
            for k, d in (('k_distance', 'Variance of the travelled distance per metre [m²/m]'),
                         ('k_heading', 'Heading variance per metre travelled [rad²/m]'),
                         ('k_turn', 'Heading variance per radian turned [rad²/rad]'))})
        gyro_bias_stddev = declare(
            self, 'gyro_bias_stddev', 1e-3, 'Uncertainty of the gyro bias [rad/s] (heading_source '
            'gyro): its heading variance grows by (sigma dt)^2 per reading', low=0.0, high=1.0,
            read_only=True)
        bias = [declare(self, 'gps_bias.' + k, default, d, low=low, high=high, read_only=True)
                for k, default, d, low, high in (
                    ('stddev', 0.0, 'Std. dev. of the time-correlated GPS error per axis [m]; '
                     '> 0 estimates it as two Gauss-Markov states', 0.0, 1e3),
                    ('correlation_time', 60.0, 'Its correlation time [s]', 1e-3, 1e6),
                    ('white_stddev', 0.0, 'Std. dev. of the white part of a fix per axis [m]; '
                     '0: the fix covariance minus the bias variance', 0.0, 1e3))]
        self._fuse_gps = declare(self, 'fuse_gps', False, 'Correct with gps/fix (EKF)',
                                 read_only=True)
        self._fuse_compass = declare(self, 'fuse_compass', False,
                                     'Correct with compass/heading (EKF)', read_only=True)
        self._origin = GeodeticOrigin(*(values[f'origin.{k}']
                                        for k in ('latitude', 'longitude', 'altitude')))
        self._odom_frame = declare(self, 'odom_frame_id', 'odom', 'Frame of the pose',
                                   read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link', 'Frame of the robot',
                                   read_only=True)
        self._map_frame = declare(self, 'map_frame_id', 'map',
                                  'Frame of the map (REP-105): parent of odom_frame_id on /tf',
                                  read_only=True)
        self._publish_tf = declare(self, 'publish_tf', True,
                                   'Publish odom -> base_link and map -> odom (REP-105)',
                                   read_only=True)
        self._max_rejections = declare(
            self, 'gate.max_rejections', 10, 'Consecutive rejections of one sensor after which '
            'the covariance is inflated by its innovation and the measurement applied',
            low=1, high=100000, read_only=True)
        self._fusion = OdometryFusion(
            OdometryFusionParams(
                wheel_radius=radius, wheel_separation=track,
                left_wheel_radius=values['left_wheel_radius'],
                right_wheel_radius=values['right_wheel_radius'], integration_method=method,
                heading_source=heading_source, odometry_noise=noise,
                gyro_bias_stddev=gyro_bias_stddev, gps_bias_stddev=bias[0],
                gps_bias_correlation_time=bias[1], gps_white_stddev=bias[2],
                wait_for_compass=self._fuse_compass, max_rejections=self._max_rejections),
            pose, np.diag([sigma0[0] ** 2, sigma0[0] ** 2, sigma0[1] ** 2]))
        self._pub = self.create_publisher(Odometry, 'odom', STREAM_PUB_QOS)
        # Dead reckoning alone (odom -> base_link) when an absolute measurement moves the estimate.
        self._absolute = self._fuse_gps or self._fuse_compass
        self._dead_reckoning = (np.array(pose, dtype=float), None)   # (pose, time [s])
        self._integration = (method, track)
        self._tf_pub = None
        if self._publish_tf:
            self._tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
            if not self._absolute and self._map_frame != self._odom_frame:
                self._tf_static = self.create_publisher(TFMessage, '/tf_static', LATCHED_QOS)
                self._tf_static.publish(TFMessage(transforms=[planar_transform(
                    0.0, self._map_frame, self._odom_frame, (0.0, 0.0, 0.0))]))
        overrides = INPUT_QOS_OVERRIDES
        self.create_subscription(WheelEncoders, 'wheel_encoders', self._on_ticks, STREAM_SUB_QOS,
                                 qos_overriding_options=overrides)
        self._gyro_sub = None
        if heading_source == 'gyro':
            self._gyro_sub = self.create_subscription(Imu, 'imu/data', self._on_gyro,
                                                      STREAM_REPLAY_SUB_QOS,
                                                      qos_overriding_options=overrides)
        if self._fuse_gps:
            self.create_subscription(NavSatFix, 'gps/fix', self._on_fix, STREAM_REPLAY_SUB_QOS,
                                     qos_overriding_options=overrides)
        if self._fuse_compass:
            self.create_subscription(Imu, 'compass/heading', self._on_heading,
                                     STREAM_REPLAY_SUB_QOS, qos_overriding_options=overrides)
        fused = [name for name, on in (('GPS', self._fuse_gps),
                                       ('compass', self._fuse_compass)) if on]
        self.get_logger().info(f'heading from {heading_source}, {method} update; '
                               f'fusing {", ".join(fused) or "nothing (dead reckoning)"}')

    # -- inputs ------------------------------------------------------------------------------
    def _on_gyro(self, msg: Imu) -> None:
        try:   # one absurd rate or variance (1e200) made the covariance inf for good
            new = self._fusion.add_gyro(
                stamp_to_seconds(msg.header.stamp),
                bounded('gyro rate', msg.angular_velocity.z, MAX_ANGULAR_RATE),
                bounded('gyro rate variance', msg.angular_velocity_covariance[8],
                        MAX_ANGULAR_RATE ** 2))
        except ValueError as err:
            self.get_logger().warn(f'gyro reading ignored: {err}', throttle_duration_sec=5.0)
            return
        if new:
            self._update()

    def _on_ticks(self, msg: WheelEncoders) -> None:
        try:
            self._fusion.add_encoders(msg.left_ticks, msg.right_ticks,
                                      msg.ticks_per_revolution,
                                      stamp_to_seconds(msg.header.stamp))
        except ValueError as err:   # counts and stamp are integers: the resolution is 0
            self.get_logger().warn(f'wheel_encoders ignored: {err}', throttle_duration_sec=5.0)
            return
        self._update()

    def _on_fix(self, msg: NavSatFix) -> None:
        if msg.status.status == NavSatStatus.STATUS_NO_FIX:
            return
        covariance = np.reshape(msg.position_covariance, (3, 3))[:2, :2]
        values = (msg.latitude, msg.longitude, msg.altitude)
        if not (all(math.isfinite(v) for v in values) and np.isfinite(covariance).all()):
            self.get_logger().warn('non-finite GPS fix; ignored', throttle_duration_sec=5.0)
            return
        if msg.position_covariance_type == NavSatFix.COVARIANCE_TYPE_UNKNOWN:
            self.get_logger().warn('GPS fix without covariance; ignored',
                                   throttle_duration_sec=5.0)
            return
        bounded('latitude', msg.latitude, MAX_LATITUDE)   # refused: the guard logs it
        bounded('longitude', msg.longitude, MAX_LONGITUDE)
        east, north, _ = self._origin.geodetic_to_enu(*values)
        self._report(self._fusion.add_position(stamp_to_seconds(msg.header.stamp),
                                               [east, north], covariance))

    def _on_heading(self, msg: Imu) -> None:
        self._report(self._fusion.add_heading(stamp_to_seconds(msg.header.stamp),
                                              quaternion_to_yaw(msg.orientation),
                                              msg.orientation_covariance[8]))
        self._update()

    # -- the estimator and its output --------------------------------------------------------
    def _update(self) -> None:
        """Apply the encoder readings whose gyro/compass samples are in; publish each."""
        connected = self._gyro_sub is None or self._gyro_sub.get_publisher_count() > 0
        estimates, events = self._fusion.update(gyro_connected=connected)
        self._report(events)
        for estimate in estimates:
            self._publish(estimate)

    def _report(self, events: list[FusionEvent]) -> None:
        """Log what the fusion did; one call per kind, so that each throttles on its own."""
        log = self.get_logger()
        for event in events:
            name = SENSOR_NAMES.get(event.sensor, event.sensor)
            match event.kind:
                case 'waiting_for_gyro':
                    log.info('waiting for a gyro publisher on imu/data',
                             throttle_duration_sec=5.0)
                case 'went_on_without_samples':
                    log.warn(f'no gyro or compass sample up to t = {event.t:.3f} s: going on '
                             'with the samples so far', throttle_duration_sec=5.0)
                case 'stale_dropped':
                    log.info(f'{event.count} measurements older than the first encoder reading '
                             f'(t = {event.t:.3f} s) dropped')
                case 'time_went_back':
                    log.warn(f'encoder time went back ({event.t_previous} -> {event.t} s); '
                             'reading ignored', throttle_duration_sec=5.0)
                case 'queue_full':
                    log.warn('no encoder reading reaches the time of the queued measurements: '
                             'dropping the oldest', throttle_duration_sec=5.0)
                case 'invalid_heading':
                    log.warn('compass heading without a finite, positive variance; ignored',
                             throttle_duration_sec=5.0)
                case 'time_jumped':
                    log.warn(f'{name or "encoder reading"} of t = {event.t} s refused: more than '
                             f'{MAX_TIME_JUMP} s from the encoder time {event.t_previous} s',
                             throttle_duration_sec=5.0)
                case 'time_restarted':
                    log.warn(f'encoder time jumped from {event.t_previous} s to {event.t} s in '
                             'agreeing readings: time base restarted there')
                case 'travel_refused':
                    log.warn(f'encoder reading of t = {event.t} s refused: travel faster than '
                             f'{MAX_SPEED} m/s', throttle_duration_sec=5.0)
                case 'ticks_rebased':
                    log.warn(f'encoder counts jumped at t = {event.t} s in readings in a row: '
                             'taken as the new tick base')
                case 'refused':
                    log.warn(f'{name} refused: {event.error}', throttle_duration_sec=5.0)
                case 'rejected':
                    log.warn(f'{name} rejected by the innovation gate ({event.count} '
                             'rejections so far)', throttle_duration_sec=5.0)
                case 'reopened':
                    log.warn(f'{self._max_rejections} rejections of the {name} in a row: the '
                             'estimate has drifted; covariance inflated, '
                             f'{name} {"applied" if event.applied else "still rejected"}')

    def _publish(self, estimate: OdometryEstimate) -> None:
        out = odometry_message(estimate.t, self._odom_frame, self._base_frame, estimate.pose,
                               estimate.twist)
        covariance = np.zeros((6, 6))            # (x, y, z, roll, pitch, yaw)
        index = [0, 1, 5]
        covariance[np.ix_(index, index)] = estimate.covariance
        out.pose.covariance = [float(v) for v in covariance.ravel()]
        self._pub.publish(out)
        if self._tf_pub is not None:
            self._publish_tf_frames(estimate)

    def _publish_tf_frames(self, estimate: OdometryEstimate) -> None:
        """Publish odom -> base_link (and map -> odom when fusing) at the estimate's time."""
        if not self._absolute:
            self._tf_pub.publish(TFMessage(transforms=[planar_transform(
                estimate.t, self._odom_frame, self._base_frame, estimate.pose)]))
            return
        pose, t = self._dead_reckoning
        if t is not None and estimate.t > t:   # the estimate's increment, without corrections
            method, track = self._integration
            dt = estimate.t - t
            v, omega = estimate.twist
            pose = odometry_increment(pose, (v - 0.5 * omega * track) * dt,
                                      (v + 0.5 * omega * track) * dt, track, method)
        self._dead_reckoning = (pose, estimate.t if t is None else max(t, estimate.t))
        transforms = [planar_transform(estimate.t, self._odom_frame, self._base_frame, pose)]
        if self._map_frame != self._odom_frame:
            transforms.append(planar_transform(estimate.t, self._map_frame, self._odom_frame,
                                               map_to_odom(estimate.pose, pose)))
        self._tf_pub.publish(TFMessage(transforms=transforms))


def main(args=None) -> None:
    """Run the odometry node until Ctrl-C."""
    run_node(OdometryNode, args, executor_factory=EventsExecutor)
