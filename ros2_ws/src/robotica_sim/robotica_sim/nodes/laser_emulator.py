"""
Laser scanner emulator node: the true pose in the world -> ``scan`` (sensor_msgs/LaserScan).

Core: :class:`robotica_sim.sensors.laser.LaserModel` (book §7.4, §12.3): a fan of beams cast on
the world of ``world_file`` from the scanner at ``mount`` (x, y, yaw) in ``base_link``, range
noise σ0 + k r, dropouts, REP-117 readings (+inf no return, -inf nearer than ``range_min``,
NaN a dropout). One scan at ``scan_rate`` on the truth's stamps, in ``frame_id``
(:mod:`robotica_sim.nodes.range_sensor_node`). The node reads ``preset`` first and declares
each term with the preset's value as its default, so that a term given explicitly overrides
it; the terms are read-only. The scan is published by a plain rclpy publisher: REP-117's
infinities are meaningful there, and a guarded publisher refuses any infinity; every other
field comes from the checked parameters and the truth's checked stamp.
"""
from builtin_interfaces.msg import Time
import numpy as np
from numpy.typing import NDArray
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import STREAM_PUB_QOS
from robotica_sim.nodes.range_sensor_node import RangeSensorNode
from robotica_sim.sensors.laser import (LASER_PARAMETERS, laser_params, laser_term_specs,
                                        LaserModel)
from sensor_msgs.msg import LaserScan


class LaserEmulatorNode(RangeSensorNode):
    """Publish the scans of a laser scanner moving with the true pose."""

    def __init__(self) -> None:
        super().__init__('laser_emulator')
        values = self.declare_terms(LASER_PARAMETERS, laser_term_specs)
        self._params = laser_params(values)
        mount = declare(self, 'mount', [0.0, 0.0, 0.0], 'The laser (x [m], y [m], yaw [rad]) '
                        'in base_link', read_only=True)
        self._frame = declare(self, 'frame_id', 'laser_link', 'frame_id of the scans',
                              read_only=True)
        self._laser = LaserModel(self._params, np.random.default_rng(values['seed']), mount)
        self._pub = self.create_publisher(LaserScan, 'scan', STREAM_PUB_QOS, allow_nan=('ranges',),
                                          allow_inf=('ranges',))   # REP-117
        self.start(self._params.scan_rate)
        self.get_logger().info(f'laser preset {values["preset"]!r}, {self._params.beams} beams')

    def sample(self, pose: NDArray[np.float64], stamp: Time) -> None:
        """Publish one scan from ``pose`` at ``stamp``."""
        p = self._params
        out = LaserScan()
        out.header.stamp = stamp
        out.header.frame_id = self._frame
        out.angle_min = p.angle_min
        out.angle_max = float(p.angles[-1])
        out.angle_increment = p.angle_increment
        out.scan_time = 1.0 / p.scan_rate
        out.time_increment = out.scan_time * p.angle_increment / (2.0 * np.pi)
        out.range_min, out.range_max = p.range_min, p.range_max
        out.ranges = self._laser.scan(self.world, pose).tolist()
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the laser emulator until Ctrl-C."""
    run_node(LaserEmulatorNode, args, executor_factory=EventsExecutor)
