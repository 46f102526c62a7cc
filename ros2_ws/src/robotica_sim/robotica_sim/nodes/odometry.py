"""
Odometry node: dead reckoning from wheel-encoder ticks, fused with gyro, compass and GPS.

Every ``wheel_encoders`` reading (robotica_msgs/WheelEncoders) moves the estimate by the wheels'
travel since the previous one, by the slides' equations (catalog §13.6): ΔU = C_m Δticks with
C_m = 2π c / ticks_per_revolution, ΔU_c = (ΔU_l + ΔU_r)/2, Δθ = (ΔU_r − ΔU_l)/b, applied with
``integration_method`` (``euler``, ``midpoint`` or the exact arc (4.93), book §4.7.5). With
``heading_source`` = ``gyro`` the heading increment is instead the integral of the yaw rate of
``imu/data`` (sensor_msgs/Imu) since the previous reading: the encoders then give the distance
only (synchronous drive, skid steer, slipping wheels).

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
"""
import math

from nav_msgs.msg import Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.mobile.ekf_localization import (EkfLocalization, increment_between_poses,
                                                  OdometryNoise)
from robotica_kin.mobile.odometry import odometry_increment, ODOMETRY_METHODS
from robotica_kin.ros.convert import odometry_message, quaternion_to_yaw, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import (INPUT_QOS_OVERRIDES, STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS,
                                  STREAM_SUB_QOS)
from robotica_msgs.msg import WheelEncoders
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus

HEADING_SOURCES = ('encoders', 'gyro')
PENDING_LIMIT = 1000   # measurements waiting for the estimate to reach their time
GYRO_WAIT_READINGS = 25   # encoder readings that wait for a late gyro/compass (0.5 s at 50 Hz)
STAMP_TOLERANCE = 1e-9    # [s] stamps closer than this are the same time


class OdometryNode(Node):
    """Integrate encoder ticks (and gyro rates) into a pose estimate; fuse GPS and compass."""

    def __init__(self) -> None:
        super().__init__('odometry')
        self._radius = declare(self, 'wheel_radius', 0.1, 'Nominal wheel radius c [m], book '
                               '(4.109)', low=1e-3, high=10.0, read_only=True)
        self._track = declare(self, 'wheel_separation', 0.4,
                              'Nominal track b between the odometry wheels [m], book (4.110)',
                              low=1e-3, high=100.0, read_only=True)
        self._method = declare(self, 'integration_method', 'exact_arc',
                               f'Pose update: one of {ODOMETRY_METHODS} (slides §13.6, book '
                               '(4.93))', read_only=True)
        if self._method not in ODOMETRY_METHODS:
            raise ValueError(f'integration_method must be one of {ODOMETRY_METHODS}, '
                             f'got {self._method!r}')
        self._heading_source = declare(self, 'heading_source', 'encoders',
                                       f'Heading increments from: one of {HEADING_SOURCES}',
                                       read_only=True)
        if self._heading_source not in HEADING_SOURCES:
            raise ValueError(f'heading_source must be one of {HEADING_SOURCES}, got '
                             f'{self._heading_source!r}')
        pose = [declare(self, 'initial_pose.' + k, 0.0, d, low=-1e6, high=1e6, read_only=True)
                for k, d in (('x', 'Initial x [m] in the odom frame'),
                             ('y', 'Initial y [m] in the odom frame'),
                             ('theta', 'Initial heading [rad], REP-103'))]
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
        self._noise = noise
        self._gyro_bias_stddev = declare(
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
        self._white_variance = bias[2] ** 2 if bias[2] > 0.0 else None
        self._ekf = EkfLocalization(pose, np.diag([sigma0[0] ** 2, sigma0[0] ** 2,
                                                   sigma0[1] ** 2]), noise,
                                    position_bias_stddev=bias[0],
                                    position_bias_correlation_time=bias[1])
        self._fuse_gps = declare(self, 'fuse_gps', False, 'Correct with gps/fix (EKF)',
                                 read_only=True)
        self._fuse_compass = declare(self, 'fuse_compass', False,
                                     'Correct with compass/heading (EKF)', read_only=True)
        self._origin = GeodeticOrigin(
            declare(self, 'origin.latitude', 37.41, 'Latitude of the odom origin [deg]',
                    low=-90.0, high=90.0, read_only=True),
            declare(self, 'origin.longitude', -6.0, 'Longitude of the odom origin [deg]',
                    low=-180.0, high=180.0, read_only=True),
            declare(self, 'origin.altitude', 10.0, 'Height of the origin [m], WGS-84',
                    low=-1e4, high=1e5, read_only=True))
        self._odom_frame = declare(self, 'odom_frame_id', 'odom', 'Frame of the pose',
                                   read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link', 'Frame of the robot',
                                   read_only=True)
        self._last_ticks: tuple[int, int, float] | None = None
        self._twist = (0.0, 0.0)
        # (t, rate, variance) of the gyro samples not yet integrated
        self._gyro_samples: list[tuple[float, float, float]] = []
        self._newest_gyro_t: float | None = None   # [s] stamp of the newest gyro sample received
        self._newest_compass_t: float | None = None   # [s] and of the newest compass reading
        self._gyro_t = 0.0                          # [s] the gyro is integrated up to here
        self._first_reading_t: float | None = None
        self._readings: list[tuple[int, int, float, int]] = []   # encoder readings waiting
        self._max_rejections = declare(
            self, 'gate.max_rejections', 10, 'Consecutive rejections of one sensor after which '
            'the covariance is inflated by its innovation and the measurement applied',
            low=1, high=100000, read_only=True)
        self._streaks: dict[str, int] = {}
        self._pending: list[tuple] = []   # (t, update, what, inflation), see _defer
        self._rejections = 0
        self._pub = self.create_publisher(Odometry, 'odom', STREAM_PUB_QOS)
        overrides = INPUT_QOS_OVERRIDES
        self.create_subscription(WheelEncoders, 'wheel_encoders', self._on_ticks, STREAM_SUB_QOS,
                                 qos_overriding_options=overrides)
        self._gyro_sub = None
        if self._heading_source == 'gyro':
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
        self.get_logger().info(f'heading from {self._heading_source}, {self._method} update; '
                               f'fusing {", ".join(fused) or "nothing (dead reckoning)"}')

    # -- inputs ------------------------------------------------------------------------------
    def _on_gyro(self, msg: Imu) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        rate = msg.angular_velocity.z
        variance = msg.angular_velocity_covariance[8]
        if not (math.isfinite(rate) and math.isfinite(variance)):
            self.get_logger().warn('non-finite gyro reading; ignored', throttle_duration_sec=5.0)
            return
        if self._newest_gyro_t is not None and t <= self._newest_gyro_t + STAMP_TOLERANCE:
            return   # a sample again, or one older than the newest: nothing new
        self._newest_gyro_t = t
        self._gyro_samples.append((t, rate, max(variance, 0.0)))
        self._drain_readings()

    def _on_ticks(self, msg: WheelEncoders) -> None:
        if msg.ticks_per_revolution < 1:
            self.get_logger().warn('wheel_encoders with ticks_per_revolution 0; ignored',
                                   throttle_duration_sec=5.0)
            return
        reading = (msg.left_ticks, msg.right_ticks, stamp_to_seconds(msg.header.stamp),
                   msg.ticks_per_revolution)
        if self._readings and abs(self._readings[-1][2] - reading[2]) <= STAMP_TOLERANCE:
            self._readings[-1] = reading   # a waiting state sent again: answered once
        else:
            self._readings.append(reading)
        self._drain_readings()

    def _drain_readings(self) -> None:
        """
        Process the encoder readings in order, each once its heading increment is known.

        With the heading from the gyro, the first reading waits until a gyro publisher is
        matched (in lockstep the loop's answer to step 0 then shows that the gyro is connected;
        the simulator publishes step 0 again until it is answered), and a later reading of time
        t waits for the gyro sample of time t (a separate process may deliver it later, and a
        late match replays it). With ``fuse_compass`` it also waits for the compass reading of
        time t, so that the reading is compared with the estimate of its own time: applied to a
        newer estimate, readings that came late under load pulled the heading back by up to
        0.25 rad and put y outside its 3 sigma for a quarter of a figure eight. After
        ``GYRO_WAIT_READINGS`` readings without them, the oldest goes on with the samples so
        far, and the node says so; a gyro sample that comes later still counts, at the next
        reading.
        """
        while self._readings:
            t = self._readings[0][2]
            if self._last_ticks is None:
                waiting = (self._heading_source == 'gyro'
                           and self._gyro_sub.get_publisher_count() == 0)
            else:
                waiting = any(on and (newest is None or newest < t - STAMP_TOLERANCE)
                              for on, newest in (
                                  (self._heading_source == 'gyro', self._newest_gyro_t),
                                  (self._fuse_compass, self._newest_compass_t)))
            if waiting and len(self._readings) <= GYRO_WAIT_READINGS:
                if self._last_ticks is None:
                    self.get_logger().info('waiting for a gyro publisher on imu/data',
                                           throttle_duration_sec=5.0)
                return
            if waiting:
                self.get_logger().warn(f'no gyro or compass sample up to t = {t:.3f} s: going '
                                       'on with the samples so far', throttle_duration_sec=5.0)
            self._process_reading(*self._readings.pop(0))

    def _process_reading(self, left_ticks: int, right_ticks: int, t: float,
                         ticks_per_revolution: int) -> None:
        if self._last_ticks is None:
            self._last_ticks = (left_ticks, right_ticks, t)
            self._first_reading_t = self._gyro_t = t
            # Replayed history from before the estimate starts (a restarted node): dropped.
            self._gyro_samples = [g for g in self._gyro_samples if g[0] > t + STAMP_TOLERANCE]
            stale = [p for p in self._pending if p[0] < t - STAMP_TOLERANCE]
            if stale:
                self._pending = [p for p in self._pending if p[0] >= t - STAMP_TOLERANCE]
                self.get_logger().info(f'{len(stale)} measurements older than the first encoder '
                                       f'reading (t = {t:.3f} s) dropped')
            self._apply_due(t)
            self._publish(t)
            return
        left0, right0, t0 = self._last_ticks
        if abs(t - t0) <= STAMP_TOLERANCE:   # the same state again (lockstep start-up):
            self._publish(t)                 # answer it again; any travel counts at the next
            return
        if t < t0:
            self.get_logger().warn(f'encoder time went back ({t0} -> {t} s); reading ignored',
                                   throttle_duration_sec=5.0)
            return
        metres_per_tick = 2.0 * math.pi * self._radius / ticks_per_revolution
        left = metres_per_tick * (left_ticks - left0)
        right = metres_per_tick * (right_ticks - right0)
        self._last_ticks = (left_ticks, right_ticks, t)
        heading_variance = None
        if self._heading_source == 'gyro':
            angle, gyro_variance = self._gyro_turn(t)
            # Keep the distance of the wheels, take the turn from the gyro (§7.7.3).
            centre, half_turn = 0.5 * (left + right), 0.5 * angle * self._track
            left, right = centre - half_turn, centre + half_turn
            # The reported white noise, plus what a gyro's covariance leaves out: its scale
            # factor (k_turn per radian turned) and its bias over the interval.
            heading_variance = (gyro_variance + self._noise.k_turn * abs(angle)
                                + (self._gyro_bias_stddev * (t - t0)) ** 2)
        before = self._ekf.pose
        after = odometry_increment(before, left, right, self._track, self._method)
        distance, turn = increment_between_poses(before, after)
        self._ekf.predict(distance, turn, heading_variance=heading_variance, dt=t - t0)
        self._twist = (0.5 * (left + right) / (t - t0), (right - left) / self._track / (t - t0))
        self._apply_due(t)
        self._publish(t)

    def _gyro_turn(self, t: float) -> tuple[float, float]:
        """
        Return the turn [rad] and its variance [rad²] from the gyro samples up to time ``t`` [s].

        Each sample's rate holds over the interval since the previous one (the gyro emulator's
        sample period); the first sample of a run covers the time since the first reading.
        """
        angle = variance = 0.0
        while self._gyro_samples and self._gyro_samples[0][0] <= t + STAMP_TOLERANCE:
            sample_t, rate, rate_variance = self._gyro_samples.pop(0)
            dt = max(sample_t - self._gyro_t, 0.0)
            angle += rate * dt
            variance += rate_variance * dt * dt
            self._gyro_t = max(self._gyro_t, sample_t)
        return angle, variance

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
        east, north, _ = self._origin.geodetic_to_enu(*values)

        def inflation() -> list[float]:
            state = self._ekf.state
            predicted = state[:2] + (state[3:5] if state.size == 5 else 0.0)
            return [(east - predicted[0]) ** 2, (north - predicted[1]) ** 2, 0.0]

        self._defer(stamp_to_seconds(msg.header.stamp),
                    lambda: self._ekf.update_position([east, north], covariance,
                                                      white_variance=self._white_variance),
                    'GPS fix', inflation)

    def _on_heading(self, msg: Imu) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        self._newest_compass_t = max(t, self._newest_compass_t or t)
        yaw = quaternion_to_yaw(msg.orientation)
        variance = msg.orientation_covariance[8]
        if not (math.isfinite(yaw) and math.isfinite(variance) and variance > 0.0):
            self.get_logger().warn('compass heading without a finite, positive variance; '
                                   'ignored', throttle_duration_sec=5.0)
        else:
            self._defer(t, lambda: self._ekf.update_heading(yaw, variance), 'compass heading',
                        lambda: [0.0, 0.0,
                                 math.remainder(yaw - self._ekf.pose[2], math.tau) ** 2])
        self._drain_readings()

    def _defer(self, t: float, update, what: str, inflation) -> None:
        """
        Apply a measurement of time ``t`` [s] once the estimate has reached ``t``.

        The sensors are separate processes: a compass reading of step k may arrive before the
        encoder reading that moves the estimate to step k, and compared with the pose of step
        k - 1 it would carry the turn of one step as an error. It waits in a queue (at most
        ``PENDING_LIMIT``) until then; a reading older than the estimate is applied at once,
        and one older than the first encoder reading (replayed history) is dropped.
        """
        if self._first_reading_t is not None and t < self._first_reading_t - STAMP_TOLERANCE:
            return
        if self._last_ticks is not None and t <= self._last_ticks[2] + STAMP_TOLERANCE:
            self._correct(update, what, inflation)
            return
        if len(self._pending) >= PENDING_LIMIT:
            self._pending.pop(0)
            self.get_logger().warn('no encoder reading reaches the time of the queued '
                                   'measurements: dropping the oldest', throttle_duration_sec=5.0)
        self._pending.append((t, update, what, inflation))

    def _apply_due(self, t: float) -> None:
        """Apply the queued measurements of time <= ``t`` [s], in time order."""
        due = sorted((p for p in self._pending if p[0] <= t + STAMP_TOLERANCE),
                     key=lambda p: p[0])
        self._pending = [p for p in self._pending if p[0] > t + STAMP_TOLERANCE]
        for _, update, what, inflation in due:
            self._correct(update, what, inflation)

    def _correct(self, update, what: str, inflation) -> None:
        """
        Apply ``update``; after ``gate.max_rejections`` rejections in a row, re-open the filter.

        A filter that has drifted (a gyro sample lost at start-up, a wheel that slipped) while
        believing itself accurate rejects every correction from then on. After too many
        consecutive rejections of one sensor, its innovation squared, ``inflation()``, is added
        to the pose variances and the measurement is applied again.
        """
        try:
            accepted = update()
        except ValueError as err:
            self.get_logger().warn(f'{what} refused: {err}', throttle_duration_sec=5.0)
            return
        if accepted:
            self._streaks[what] = 0
            return
        self._streaks[what] = self._streaks.get(what, 0) + 1
        self._rejections += 1
        self.get_logger().warn(f'{what} rejected by the innovation gate ({self._rejections} '
                               'rejections so far)', throttle_duration_sec=5.0)
        if self._streaks[what] >= self._max_rejections:
            covariance = self._ekf.full_covariance
            covariance[np.diag_indices(3)] += inflation()
            self._ekf.reset(self._ekf.state, covariance)
            self._streaks[what] = 0
            self.get_logger().warn(
                f'{self._max_rejections} rejections of the {what} in a row: the estimate has '
                'drifted; '
                f'covariance inflated, {what} {"applied" if update() else "still rejected"}')

    # -- output ------------------------------------------------------------------------------
    def _publish(self, t: float) -> None:
        out = odometry_message(t, self._odom_frame, self._base_frame, self._ekf.pose,
                               self._twist)
        p = self._ekf.covariance
        covariance = np.zeros((6, 6))            # (x, y, z, roll, pitch, yaw)
        index = [0, 1, 5]
        covariance[np.ix_(index, index)] = p
        out.pose.covariance = [float(v) for v in covariance.ravel()]
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the odometry node until Ctrl-C."""
    run_node(OdometryNode, args, executor_factory=EventsExecutor)
