"""
Infrared proximity emulator node: the true pose in the world -> ``infrared_<i>`` (Range).

Core: :func:`robotica_sim.sensors.infrared.infrared_ranges` (book §7.4): sensors at ``mounts``
(x, y, yaw triples in ``base_link``), each a narrow cone on the world of ``world_file``, a
reading only when the returned intensity ρ / r² reaches ``intensity_threshold`` (ρ the world's
``default_reflectivity``), else ``max_range``; noise σ0 + k r. All sensors read at ``rate`` on
the truth's stamps (:mod:`robotica_sim.nodes.range_sensor_node`), each on ``infrared_<i>``
(INFRARED, frame ``<frame_prefix><i>_link``). The node reads ``preset`` first and declares
each term with the preset's value as its default, so that a term given explicitly overrides
it; the terms are read-only.
"""
from builtin_interfaces.msg import Time
import numpy as np
from numpy.typing import NDArray
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.entry_point import run_node
from robotica_sim.nodes.range_sensor_node import RangeSensorNode
from robotica_sim.sensors.infrared import (INFRARED_MOUNTS, INFRARED_PARAMETERS,
                                           infrared_params, infrared_ranges,
                                           infrared_term_specs)
from sensor_msgs.msg import Range


class InfraredEmulatorNode(RangeSensorNode):
    """Publish the readings of infrared proximity sensors moving with the true pose."""

    def __init__(self) -> None:
        super().__init__('infrared_emulator')
        values = self.declare_terms(INFRARED_PARAMETERS, infrared_term_specs)
        self._params = infrared_params(values)
        self._mounts, self._frames, self._pubs = self.declare_sensors('infrared', INFRARED_MOUNTS)
        self._rng = np.random.default_rng(values['seed'])
        self.start(self._params.rate)
        self.get_logger().info(f'infrared preset {values["preset"]!r}, '
                               f'{len(self._frames)} sensors')

    def sample(self, pose: NDArray[np.float64], stamp: Time) -> None:
        """Publish every sensor's reading from ``pose`` at ``stamp``."""
        p = self._params
        readings = infrared_ranges(p, self.world, pose, self._mounts, self._rng)
        for pub, frame, reading in zip(self._pubs, self._frames, readings):
            out = Range(radiation_type=Range.INFRARED, field_of_view=2.0 * p.cone_half_angle,
                        min_range=p.min_range, max_range=p.max_range, range=float(reading))
            out.header.stamp = stamp
            out.header.frame_id = frame
            pub.publish(out)


def main(args=None) -> None:
    """Run the infrared emulator until Ctrl-C."""
    run_node(InfraredEmulatorNode, args, executor_factory=EventsExecutor)
