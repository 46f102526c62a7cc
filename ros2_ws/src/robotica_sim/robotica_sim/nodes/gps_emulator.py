"""
GPS emulator node: ground truth -> ``gps/fix`` (sensor_msgs/NavSatFix) with an honest covariance.

Each ``ground_truth/odom`` message gives the true position in the world frame, taken as the
local ENU frame of the geodetic origin ``origin.*`` (REP-103/105: x east, y north). The error
model is :class:`robotica_sim.sensors.gps.GpsModel` with the receiver ``preset`` (``sa_standalone``
~100 m 2DRMS as in the book's SA era, ``standalone`` a few metres, ``dgps`` ~1 m, ``rtk`` ~2 cm):
time-correlated (Gauss–Markov) plus white error, fixes at the update rate, latency and dropouts,
reproducible from ``seed``. A fix is published when its latency has elapsed in simulated time,
stamped with the time of the position it reports; latitude and longitude come from
:class:`robotica_kin.geodetic.GeodeticOrigin` (WGS-84). The covariance is the model's total
error covariance in ENU (``COVARIANCE_TYPE_KNOWN``); the status is the preset's solution type.

Every term of the receiver is a parameter (``horizontal_stddev``, ``vertical_stddev``,
``correlation_time``, ``white_stddev``, ``update_rate``, ``latency``, ``dropout.probability``,
``dropout.mean_duration``, ``status``: :data:`GPS_TERMS`). The node reads ``preset`` first and
declares each term with the preset's value as its default, so a value given explicitly (``-p``,
``--params-file``, a scenario) overrides the preset's and an absent one keeps it. The terms are
checked at start-up (exit 2 with one line) and may be set at run time: a set is refused with the
reason unless the whole :class:`GpsParams` is valid (``white_stddev`` within both stddevs, an
outage of at least one fix period), and an accepted one applies from the next fix on.
"""
from collections import deque
import math

from nav_msgs.msg import Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import StampGate
from robotica_kin.ros.convert import seconds_to_stamp, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import check_on_set, declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_sim.sensors.gps import (gps_configuration, GPS_PARAMETERS, gps_params,
                                      gps_term_specs, GPS_TERMS, GpsFix, GpsModel)
from sensor_msgs.msg import NavSatFix, NavSatStatus


class GpsEmulatorNode(GuardedNode):
    """Publish GPS fixes of the ground-truth position."""

    def __init__(self) -> None:
        super().__init__('gps_emulator')
        values = declare_specs(self, {k: v for k, v in GPS_PARAMETERS.items()
                                      if k not in GPS_TERMS})
        values.update(declare_specs(self, gps_term_specs(values['preset']), read_only=False))
        self._params, self._origin = gps_configuration(values)
        self._model = GpsModel(self._params, values['seed'])
        self._antenna_height = values['antenna_height']
        self._frame = declare(self, 'frame_id', 'gps_link', 'frame_id of the fixes',
                              read_only=True)
        self._pending: deque[GpsFix] = deque()
        self._stamps = StampGate()
        self._pub = self.create_publisher(NavSatFix, 'gps/fix', STREAM_PUB_QOS)
        self.create_subscription(Odometry, 'ground_truth/odom', self._on_truth,
                                 STREAM_REPLAY_SUB_QOS)
        self.get_logger().info(
            f'preset {values["preset"]!r}: sigma {self._params.horizontal_stddev:.3g} m per '
            f'horizontal axis, {self._params.update_rate:g} Hz, latency '
            f'{self._params.latency:g} s')
        check_on_set(self, {name: values[name] for name in GPS_TERMS},
                     lambda terms: gps_params({**values, **terms}), self._set_params)

    def _set_params(self, params) -> None:
        self._params = self._model.params = params

    def _on_truth(self, msg: Odometry) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        if self._stamps.check(t) == 'restart':   # refused (raises) when it jumps
            self._model.reset()
            self._pending.clear()
        position = msg.pose.pose.position
        enu = (position.x, position.y, position.z + self._antenna_height)
        if not all(math.isfinite(v) for v in enu):
            self.get_logger().warn('non-finite ground truth; no fix', throttle_duration_sec=5.0)
            return
        try:
            fix = self._model.measure(t, enu)
        except ValueError as err:
            self.get_logger().warn(f'ground truth refused ({err})', throttle_duration_sec=5.0)
            return
        if fix is not None:
            self._pending.append(fix)
        while self._pending and self._pending[0].available_at <= t + 1e-9:
            self._publish(self._pending.popleft())

    def _publish(self, fix: GpsFix) -> None:
        lat, lon, alt = self._origin.enu_to_geodetic(*fix.enu)
        out = NavSatFix(latitude=float(lat), longitude=float(lon), altitude=float(alt),
                        position_covariance=[float(v) for v in np.ravel(fix.covariance)],
                        position_covariance_type=NavSatFix.COVARIANCE_TYPE_KNOWN)
        out.status.status = fix.navsat_status
        out.status.service = NavSatStatus.SERVICE_GPS
        out.header.stamp = seconds_to_stamp(fix.stamp)
        out.header.frame_id = self._frame
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the GPS emulator until Ctrl-C."""
    run_node(GpsEmulatorNode, args, executor_factory=EventsExecutor)
