"""
Mapper node: a probabilistic occupancy map built while driving (book §12.4.1).

Each laser scan (``scan``, sensor_msgs/LaserScan, REP-117 readings) and each sonar reading
(``sonar_<i>``, sensor_msgs/Range) is fused into an
:class:`~robotica_kin.world.occupancy_mapping.OccupancyMap` from the robot's pose at the
reading's stamp (``odom``, nav_msgs/Odometry: remap it to ``ground_truth/odom`` to map from the
true pose) and the sensor's mount on the robot. A laser beam (``laser.mount``) takes evidence
from the cells it crosses and gives it to the cell of its return; a sonar reading of transducer
i (``sonar.mounts``' i-th (x, y, yaw) triple, as the sonar emulator's ``mounts``) updates the
cells of its cone with Elfes' model (half-angle ``field_of_view`` / 2, ``min_range`` and
``max_range`` of the message; a reading >= ``max_range`` or +inf is no echo, NaN and -inf are
skipped; the message's ``frame_id``, the emulator's ``sonar_<i>_link``, is not read: the topic
names the mount). Both are log-odds updates, clamped. The map (the slides' −1…+1 evidence as
0…100 %, −1 where nothing was observed) goes out on ``map`` (nav_msgs/OccupancyGrid, transient
local, in ``frame_id``) every ``publish_period`` seconds of the readings' time: the planner
reads it.

The sources: the laser unless ``laser.enabled`` is false (the default maps from it, as before
the sonar came), the sonar when ``sonar.mounts`` is given (one topic per triple). A Range whose
``radiation_type`` is not ULTRASOUND is refused (choice: the cone model is the sonar's, and an
infrared reading on a ``sonar_<i>`` topic is a wiring mistake to show, not to map). A reading
whose pose is not known (no pose stamped within ``pose_tolerance`` of it) is skipped and said so
(at most once every 5 s); a reading or pose with non-finite or absurd values is refused by the
guard.
"""
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry
import numpy as np
from numpy.typing import NDArray
from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter
from robotica_kin.mobile.pose_history import PoseHistory
from robotica_kin.ros.convert import pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.grid_messages import grid_message
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS, STREAM_SUB_QOS
from robotica_kin.world.occupancy_mapping import OccupancyMap
from sensor_msgs.msg import LaserScan, Range

MAX_MAP_CELLS = 25_000_000
"""At most this many cells (5000 x 5000): a map of 250 x 250 m at 5 cm."""
POSES_KEPT = 200
"""Poses kept to match readings' stamps (4 s of 50 Hz odometry)."""
MAX_SONARS = 64
"""At most this many sonar transducers (topics ``sonar_0`` ... ``sonar_63``)."""


class MapperNode(GuardedNode):
    """Fuse laser scans and sonar readings into an occupancy grid and publish it."""

    def __init__(self) -> None:
        super().__init__('mapper')
        size = declare(self, 'size', [10.0, 10.0], 'Width and height of the map [m]',
                       read_only=True)
        origin = declare(self, 'origin', [0.0, 0.0], 'Lower-left corner (x, y) [m] of the map',
                         read_only=True)
        resolution = declare(self, 'resolution', 0.05, 'Cell size [m]', low=0.001, high=10.0,
                             read_only=True)
        laser = declare(self, 'laser.enabled', True, 'Fuse the laser scans of scan (false: '
                        'sonar only)', read_only=True)
        self._mount = np.asarray(declare(
            self, 'laser.mount', [0.0, 0.0, 0.0], 'The laser (x [m], y [m], yaw [rad]) in '
            'base_link, as the laser emulator has it', read_only=True), dtype=np.float64)
        sonar = declare(self, 'sonar.mounts', Parameter.Type.DOUBLE_ARRAY, 'The sonar '
                        'transducers (x [m], y [m], yaw [rad]) in base_link, three numbers each, '
                        "as the sonar emulator's mounts: transducer i is read on sonar_<i>; "
                        'default none (no sonar)', read_only=True)
        self._frame = declare(self, 'frame_id', 'map', 'Frame of the map and the poses',
                              read_only=True)
        self._period = declare(self, 'publish_period', 1.0, 'Time between two maps [s] (of the '
                               "readings' stamps)", low=0.0, high=3600.0, read_only=True)
        self._tolerance = declare(self, 'pose_tolerance', 0.05, 'Largest gap between a reading '
                                  'and the pose it is fused from [s]', low=0.0, high=10.0,
                                  read_only=True)
        if len(size) != 2 or len(origin) != 2 or self._mount.shape != (3,) \
                or not all(np.isfinite([*size, *origin, *self._mount])) or min(size) <= 0.0:
            raise ValueError('size must be 2 values > 0 m, origin 2 finite values and '
                             'laser.mount 3 finite values')
        self._sonar_mounts = _sonar_mounts(sonar)
        if not laser and not len(self._sonar_mounts):
            raise ValueError('nothing to map from: laser.enabled is false and sonar.mounts '
                             'is not given')
        shape = (int(np.ceil(size[1] / resolution)), int(np.ceil(size[0] / resolution)))
        if shape[0] * shape[1] > MAX_MAP_CELLS:
            raise ValueError(f'a map of {shape[1]} x {shape[0]} cells is more than '
                             f'{MAX_MAP_CELLS}: grow resolution or shrink size')
        self._map = OccupancyMap(shape, resolution, (origin[0], origin[1], 0.0))
        self._poses = PoseHistory(POSES_KEPT)
        self._last_publish = -np.inf
        self._pub = self.create_publisher(OccupancyGridMsg, 'map', LATCHED_QOS)
        self.create_subscription(Odometry, 'odom', self._on_odom, STREAM_SUB_QOS)
        if laser:
            self.create_subscription(LaserScan, 'scan', self._on_scan, STREAM_SUB_QOS)
        for i, mount in enumerate(self._sonar_mounts):
            self.create_subscription(Range, f'sonar_{i}',
                                     lambda msg, mount=mount: self._on_sonar(msg, mount),
                                     STREAM_SUB_QOS)
        sources = ['laser'] * bool(laser) + [f'{len(self._sonar_mounts)} sonars'] * bool(
            len(self._sonar_mounts))
        self.get_logger().info(f'mapping {size[0]:g} x {size[1]:g} m at {resolution:g} m from '
                               f'({origin[0]:g}, {origin[1]:g}) m with {" and ".join(sources)}')

    def _on_odom(self, msg: Odometry) -> None:
        self._poses.add(stamp_to_seconds(msg.header.stamp), pose2d_from_odometry(msg))

    def _pose_at(self, t: float, what: str) -> NDArray[np.float64] | None:
        """Return the kept pose nearest ``t`` [s], or None (said so) when none is close."""
        if not len(self._poses):
            self.get_logger().warn(f'a {what} before any pose: skipped',
                                   throttle_duration_sec=5.0)
            return None
        pose = self._poses.nearest(t, self._tolerance)
        if pose is None:
            self.get_logger().warn(f'no pose within {self._tolerance} s of the {what} at '
                                   f'{t:.3f} s: skipped', throttle_duration_sec=5.0)
            return None
        return pose

    def _publish_when_due(self, t: float, msg: LaserScan | Range) -> None:
        if t - self._last_publish >= self._period:
            self._last_publish = t
            self._pub.publish(grid_message(self._map.to_grid(), self._frame, msg.header.stamp))

    def _on_scan(self, msg: LaserScan) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        pose = self._pose_at(t, 'scan')
        if pose is None:
            return
        self._map.update_scan(pose, np.asarray(msg.ranges, dtype=np.float64), msg.angle_min,
                              msg.angle_increment, msg.range_min, msg.range_max, self._mount)
        self._publish_when_due(t, msg)

    def _on_sonar(self, msg: Range, mount: NDArray[np.float64]) -> None:
        if msg.radiation_type != Range.ULTRASOUND:
            raise ValueError(f'radiation_type {msg.radiation_type} is not ULTRASOUND '
                             f'({Range.ULTRASOUND}): a sonar_<i> topic takes sonar readings')
        t = stamp_to_seconds(msg.header.stamp)
        pose = self._pose_at(t, 'sonar reading')
        if pose is None:
            return
        # update_sonar refuses a non-finite or absurd cone and ranges (ValueError: the guard).
        self._map.update_sonar(pose, msg.range, 0.5 * msg.field_of_view, msg.min_range,
                               msg.max_range, mount)
        self._publish_when_due(t, msg)


def _sonar_mounts(values: list[float] | None) -> NDArray[np.float64]:
    """
    Return ``sonar.mounts`` as (n, 3) (x, y, yaw) triples; none given (unset or empty): (0, 3).

    ValueError for a count that is not a multiple of 3, more than ``MAX_SONARS`` triples or a
    non-finite value.
    """
    m = np.asarray(values if values is not None else [], dtype=np.float64)
    if m.size % 3 or m.size > 3 * MAX_SONARS or not np.isfinite(m).all():
        raise ValueError(f'sonar.mounts must hold at most {MAX_SONARS} finite (x, y, yaw) '
                         f'triples, got {m.size} numbers')
    return m.reshape(-1, 3)


def main(args=None) -> None:
    """Run the mapper until Ctrl-C."""
    run_node(MapperNode, args, executor_factory=EventsExecutor)
