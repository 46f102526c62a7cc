"""
Gyroscope emulator node: ground-truth yaw rate -> ``imu/data`` (sensor_msgs/Imu, rates only).

Each ``ground_truth/odom`` message gives the true body rates (a planar vehicle: yaw rate only,
roll and pitch rates zero); each axis is a :class:`robotica_sim.sensors.gyro.GyroModel` of the
grade ``preset`` (book §7.7.3; white noise, Gauss–Markov bias instability, rate random walk,
turn-on bias, scale factor, saturation, quantisation), reproducible from ``seed``. The sample
period is the time between two truth messages (the first message only starts the clock). The
message carries the angular velocity in ``frame_id`` and, as its covariance, the white-noise
variance per sample (the honest figure of one reading; the slowly wandering bias is not white
and is left to the estimator); orientation and linear acceleration are marked "not provided"
(covariance element 0 = -1, as sensor_msgs/Imu defines).

Every error term of the model is a parameter (``noise_density``, ``bias_instability``,
``bias_correlation_time``, ``random_walk``, ``initial_bias``, ``initial_bias_stddev``,
``scale_factor_error``, ``saturation``, ``resolution``: :data:`GYRO_TERMS`). The node reads
``preset`` first and declares each term with the preset's value as its default, so a value
given explicitly (``-p``, ``--params-file``, a scenario) overrides the preset's and an absent
one keeps it. The terms are checked at start-up (exit 2 with one line) and may be set at run
time: a set is refused with the reason unless the whole :class:`GyroParams` is valid, and an
accepted one applies from the next sample on.
"""
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import StampGate
from robotica_kin.ros.convert import stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import check_on_set, declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_sim.sensors.gyro import (GYRO_PARAMETERS, gyro_params, gyro_term_specs,
                                       GYRO_TERMS, GyroModel)
from sensor_msgs.msg import Imu


class GyroEmulatorNode(GuardedNode):
    """Publish the three gyro axes' readings of the true body rates."""

    def __init__(self) -> None:
        super().__init__('gyro_emulator')
        values = declare_specs(self, {k: GYRO_PARAMETERS[k] for k in ('preset', 'seed')})
        values.update(declare_specs(self, gyro_term_specs(values['preset']), read_only=False))
        params = gyro_params(values)
        self._axes = [GyroModel(params, np.random.default_rng(s))
                      for s in np.random.SeedSequence(values['seed']).spawn(3)]
        self._frame = declare(self, 'frame_id', 'base_link', 'frame_id of the readings',
                              read_only=True)
        self._last_t: float | None = None
        self._stamps = StampGate()
        self._pub = self.create_publisher(Imu, 'imu/data', STREAM_PUB_QOS)
        self.create_subscription(Odometry, 'ground_truth/odom', self._on_truth,
                                 STREAM_REPLAY_SUB_QOS)
        check_on_set(self, {name: values[name] for name in GYRO_TERMS},
                     lambda terms: gyro_params({**values, **terms}), self._set_params)
        self.get_logger().info(f'gyro preset {values["preset"]!r}')

    def _set_params(self, params) -> None:
        for axis in self._axes:
            axis.params = params

    def _on_truth(self, msg: Odometry) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        if self._stamps.check(t) == 'restart':   # refused (raises) when it jumps
            self._last_t = None
        rates = msg.twist.twist.angular
        true_rates = (rates.x, rates.y, rates.z)
        if not np.isfinite(true_rates).all():
            self.get_logger().warn('non-finite ground truth; no reading',
                                   throttle_duration_sec=5.0)
            return
        if self._last_t is None or t <= self._last_t:
            if self._last_t is not None:
                self.get_logger().warn(f'time did not advance ({self._last_t} -> {t} s); '
                                       'reading skipped', throttle_duration_sec=5.0)
            self._last_t = t if self._last_t is None else self._last_t
            return
        dt = t - self._last_t
        self._last_t = t
        measured = [axis.measure(rate, dt) for axis, rate in zip(self._axes, true_rates)]
        out = Imu()
        out.header.stamp = msg.header.stamp
        out.header.frame_id = self._frame
        out.angular_velocity.x, out.angular_velocity.y, out.angular_velocity.z = measured
        covariance = [0.0] * 9
        covariance[0], covariance[4], covariance[8] = (axis.variance(dt) for axis in self._axes)
        out.angular_velocity_covariance = covariance
        out.orientation_covariance[0] = -1.0
        out.linear_acceleration_covariance[0] = -1.0
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the gyro emulator until Ctrl-C."""
    run_node(GyroEmulatorNode, args, executor_factory=EventsExecutor)
