"""
Wrist force/torque sensor emulator node: true contact wrench -> recovered ``ft_sensor/wrench``.

Each ``contact_wrench`` message (geometry_msgs/WrenchStamped: the wrench the environment
applies at the end effector, in the sensor frame) is read by a
:class:`robotica_sim.sensors.force_torque.FtSensorModel` (book §7.6, fig. 7.25): gauge volts
V = H F (7.10) with white noise, quantised and clipped by the ADC, and the wrench recovered by
least squares, F̂ = H^S V (7.11). F̂ is published on ``ft_sensor/wrench`` (WrenchStamped, the
input's stamp, ``frame_id``) and, with ``publish_gauges``, the n gauge volts on
``ft_sensor/gauges`` (std_msgs/Float64MultiArray, [V]). A saturated gauge (its recovered wrench
is wrong) is logged as a warning, the reading still published, as a real sensor's would be.

Every term of the model is a parameter (``spoke_radius``, ``strain_per_newton``,
``gauge_factor``, ``bridge_voltage``, ``amplifier_gain``, ``noise_stddev``, ``adc_bits``,
``adc_range``: :data:`FT_TERMS`), declared with the value of ``preset`` as its default, so that
a value given explicitly overrides the preset's; they are checked at start-up (exit 2 with one
line) and may be set at run time (a set is refused with the reason unless the whole sensor is
valid). ``calibration_matrix`` (read-only; n x 6 numbers, row-major, [V/N, V/(N m)]) replaces
the Maltese-cross geometry's H when given. A non-finite or absurd wrench (beyond
:data:`~robotica_kin.bounds.MAX_FORCE_TORQUE`) or a malformed or jumping stamp is logged and
dropped by the guard.
"""
from geometry_msgs.msg import WrenchStamped
import numpy as np
from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter
from robotica_kin.bounds import bounded_array, MAX_FORCE_TORQUE, StampGate
from robotica_kin.ros.convert import stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import check_on_set, declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_sim.sensors.force_torque import (FT_PARAMETERS, ft_sensor_params, ft_term_specs,
                                               FT_TERMS, FtSensorModel)
from std_msgs.msg import Float64MultiArray, MultiArrayDimension


def _matrix(values) -> np.ndarray | None:
    """Return the row-major numbers of ``calibration_matrix`` as H (n, 6); None if unset."""
    if values is None:
        return None
    if len(values) % 6:
        raise ValueError(f'calibration_matrix must hold n x 6 numbers (row-major), got '
                         f'{len(values)}')
    return np.reshape(np.asarray(values, dtype=np.float64), (-1, 6))


class FtSensorEmulatorNode(GuardedNode):
    """Publish the wrench a wrist F/T sensor recovers from its strain gauges."""

    def __init__(self) -> None:
        super().__init__('ft_sensor_emulator')
        values = declare_specs(self, {k: FT_PARAMETERS[k] for k in ('preset', 'seed')})
        values.update(declare_specs(self, ft_term_specs(values['preset']), read_only=False))
        matrix = _matrix(declare(
            self, 'calibration_matrix', Parameter.Type.DOUBLE_ARRAY,
            'Calibration matrix H [V/N, V/(N m)], n x 6 row-major, n >= 6 gauges, (7.10); '
            "unset: the Maltese-cross geometry's", read_only=True))
        rng = np.random.default_rng(values['seed'])
        self._model = FtSensorModel(ft_sensor_params(values), rng, matrix)
        self._frame = declare(self, 'frame_id', 'ft_sensor_link',
                              'frame_id of the recovered wrench', read_only=True)
        gauges = declare(self, 'publish_gauges', True,
                         'Publish the gauge volts on ft_sensor/gauges', read_only=True)
        self._stamps = StampGate()
        self._pub = self.create_publisher(WrenchStamped, 'ft_sensor/wrench', STREAM_PUB_QOS)
        self._gauges_pub = self.create_publisher(Float64MultiArray, 'ft_sensor/gauges',
                                                 STREAM_PUB_QOS) if gauges else None
        self.create_subscription(WrenchStamped, 'contact_wrench', self._on_wrench,
                                 STREAM_REPLAY_SUB_QOS)
        check_on_set(self, {name: values[name] for name in FT_TERMS},
                     lambda terms: ft_sensor_params({**values, **terms}), self._set_params)
        self.get_logger().info(f'F/T sensor preset {values["preset"]!r}, '
                               f'{self._model.gauges} gauges')

    def _set_params(self, params) -> None:
        self._model.params = params

    def _on_wrench(self, msg: WrenchStamped) -> None:
        self._stamps.check(stamp_to_seconds(msg.header.stamp))   # refused (raises) if it jumps
        f, m = msg.wrench.force, msg.wrench.torque
        wrench = bounded_array('contact_wrench', (f.x, f.y, f.z, m.x, m.y, m.z),
                               MAX_FORCE_TORQUE)
        reading = self._model.measure(wrench)
        if reading.saturated.any():
            self.get_logger().warn(f'gauges {np.flatnonzero(reading.saturated).tolist()} '
                                   'saturated: the recovered wrench is wrong',
                                   throttle_duration_sec=5.0)
        out = WrenchStamped()
        out.header.stamp = msg.header.stamp
        out.header.frame_id = self._frame
        out.wrench.force.x, out.wrench.force.y, out.wrench.force.z = reading.wrench[:3].tolist()
        out.wrench.torque.x, out.wrench.torque.y, out.wrench.torque.z = \
            reading.wrench[3:].tolist()
        self._pub.publish(out)
        if self._gauges_pub is not None:
            volts = Float64MultiArray(data=reading.volts.tolist())
            volts.layout.dim = [MultiArrayDimension(label='gauges', size=self._model.gauges,
                                                    stride=self._model.gauges)]
            self._gauges_pub.publish(volts)


def main(args=None) -> None:
    """Run the F/T sensor emulator until Ctrl-C."""
    run_node(FtSensorEmulatorNode, args, executor_factory=EventsExecutor)
