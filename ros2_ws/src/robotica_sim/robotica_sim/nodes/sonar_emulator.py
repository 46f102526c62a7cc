"""
Sonar ring emulator node: the true pose in the world -> ``sonar_<i>`` (sensor_msgs/Range).

Core: :class:`robotica_sim.sensors.sonar.SonarRing` (book §7.4, fig. 7.19): transducers at
``mounts`` (x, y, yaw triples in ``base_link``), each a beam cone on the world of
``world_file``, the critical incidence angle (no echo: ``max_range``), specular multipath,
noise σ0 + k r, the speed of sound, fired in ``firing_groups`` groups in turn at
``cycle_rate`` on the truth's stamps (:mod:`robotica_sim.nodes.range_sensor_node`). Each
transducer that fires publishes its reading on ``sonar_<i>`` (ULTRASOUND, frame
``<frame_prefix><i>_link``, field of view twice the cone's half-angle); the others publish
nothing that cycle. The node reads ``preset`` first and declares each term with the preset's
value as its default, so that a term given explicitly overrides it; the terms are read-only.
"""
from builtin_interfaces.msg import Time
import numpy as np
from numpy.typing import NDArray
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.entry_point import run_node
from robotica_sim.nodes.range_sensor_node import RangeSensorNode
from robotica_sim.sensors.sonar import (SONAR_MOUNTS, SONAR_PARAMETERS, sonar_params,
                                        sonar_term_specs, SonarRing)
from sensor_msgs.msg import Range


class SonarEmulatorNode(RangeSensorNode):
    """Publish the readings of a sonar ring moving with the true pose."""

    def __init__(self) -> None:
        super().__init__('sonar_emulator')
        values = self.declare_terms(SONAR_PARAMETERS, sonar_term_specs)
        self._params = sonar_params(values)
        mounts, self._frames, self._pubs = self.declare_sensors('sonar', SONAR_MOUNTS)
        self._ring = SonarRing(self._params, mounts, np.random.default_rng(values['seed']))
        self.start(self._params.cycle_rate)
        self.get_logger().info(f'sonar preset {values["preset"]!r}, {len(self._frames)} '
                               f'transducers in {self._params.firing_groups} groups')

    def sample(self, pose: NDArray[np.float64], stamp: Time) -> None:
        """Fire this cycle's group from ``pose`` and publish its readings at ``stamp``."""
        p = self._params
        for i in self._ring.fire(self.world, pose):
            out = Range(radiation_type=Range.ULTRASOUND, field_of_view=2.0 * p.cone_half_angle,
                        min_range=p.min_range, max_range=p.max_range,
                        range=float(self._ring.readings[i]))
            out.header.stamp = stamp
            out.header.frame_id = self._frames[i]
            self._pubs[i].publish(out)


def main(args=None) -> None:
    """Run the sonar emulator until Ctrl-C."""
    run_node(SonarEmulatorNode, args, executor_factory=EventsExecutor)
