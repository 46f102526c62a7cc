"""
Mapper node: a probabilistic occupancy map built while driving (book §12.4.1).

Each laser scan (``scan``, sensor_msgs/LaserScan, REP-117 readings) is fused into an
:class:`~robotica_kin.world.occupancy_mapping.OccupancyMap` from the robot's pose at the scan's
stamp (``odom``, nav_msgs/Odometry: remap it to ``ground_truth/odom`` to map from the true pose)
and the laser's ``laser.mount`` on the robot: cells along each beam lose evidence, the cell of
its return gains it (log-odds, clamped). The map (the slides' −1…+1 evidence as 0…100 %, −1
where nothing was observed) goes out on ``map`` (nav_msgs/OccupancyGrid, transient local, in
``frame_id``) every ``publish_period`` seconds of the scans' time: the planner reads it.

A scan whose pose is not known (no pose stamped within ``pose_tolerance`` of it) is skipped and
said so once; a scan or pose with non-finite or absurd values is refused by the guard.
"""
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg, Odometry
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.convert import pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.grid_messages import grid_message
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS, STREAM_SUB_QOS
from robotica_kin.world.occupancy_mapping import OccupancyMap
from sensor_msgs.msg import LaserScan

MAX_MAP_CELLS = 25_000_000
"""At most this many cells (5000 x 5000): a map of 250 x 250 m at 5 cm."""
POSES_KEPT = 200
"""Poses kept to match scans' stamps (4 s of 50 Hz odometry)."""


class MapperNode(GuardedNode):
    """Fuse laser scans into an occupancy grid and publish it."""

    def __init__(self) -> None:
        super().__init__('mapper')
        size = declare(self, 'size', [10.0, 10.0], 'Width and height of the map [m]',
                       read_only=True)
        origin = declare(self, 'origin', [0.0, 0.0], 'Lower-left corner (x, y) [m] of the map',
                         read_only=True)
        resolution = declare(self, 'resolution', 0.05, 'Cell size [m]', low=0.001, high=10.0,
                             read_only=True)
        self._mount = np.asarray(declare(
            self, 'laser.mount', [0.0, 0.0, 0.0], 'The laser (x [m], y [m], yaw [rad]) in '
            'base_link, as the laser emulator has it', read_only=True), dtype=np.float64)
        self._frame = declare(self, 'frame_id', 'map', 'Frame of the map and the poses',
                              read_only=True)
        self._period = declare(self, 'publish_period', 1.0, 'Time between two maps [s] (of the '
                               "scans' stamps)", low=0.0, high=3600.0, read_only=True)
        self._tolerance = declare(self, 'pose_tolerance', 0.05, 'Largest gap between a scan '
                                  'and the pose it is fused from [s]', low=0.0, high=10.0,
                                  read_only=True)
        if len(size) != 2 or len(origin) != 2 or self._mount.shape != (3,) \
                or not all(np.isfinite([*size, *origin, *self._mount])) or min(size) <= 0.0:
            raise ValueError('size must be 2 values > 0 m, origin 2 finite values and '
                             'laser.mount 3 finite values')
        shape = (int(np.ceil(size[1] / resolution)), int(np.ceil(size[0] / resolution)))
        if shape[0] * shape[1] > MAX_MAP_CELLS:
            raise ValueError(f'a map of {shape[1]} x {shape[0]} cells is more than '
                             f'{MAX_MAP_CELLS}: grow resolution or shrink size')
        self._map = OccupancyMap(shape, resolution, (origin[0], origin[1], 0.0))
        self._poses: list[tuple[float, np.ndarray]] = []
        self._last_publish = -np.inf
        self._scans = 0
        self._pub = self.create_publisher(OccupancyGridMsg, 'map', LATCHED_QOS)
        self.create_subscription(Odometry, 'odom', self._on_odom, STREAM_SUB_QOS)
        self.create_subscription(LaserScan, 'scan', self._on_scan, STREAM_SUB_QOS)
        self.get_logger().info(f'mapping {size[0]:g} x {size[1]:g} m at {resolution:g} m from '
                               f'({origin[0]:g}, {origin[1]:g}) m')

    def _on_odom(self, msg: Odometry) -> None:
        pose = pose2d_from_odometry(msg)
        if not np.isfinite(pose).all():
            raise ValueError(f'pose not finite: {pose.tolist()}')
        self._poses.append((stamp_to_seconds(msg.header.stamp), pose))
        del self._poses[:-POSES_KEPT]

    def _on_scan(self, msg: LaserScan) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        if not self._poses:
            self.get_logger().warn('a scan before any pose: skipped', throttle_duration_sec=5.0)
            return
        gap, pose = min(((abs(s - t), p) for s, p in self._poses), key=lambda g: g[0])
        if gap > self._tolerance:
            self.get_logger().warn(f'no pose within {self._tolerance} s of the scan at '
                                   f'{t:.3f} s: skipped', throttle_duration_sec=5.0)
            return
        self._map.update_scan(pose, np.asarray(msg.ranges, dtype=np.float64), msg.angle_min,
                              msg.angle_increment, msg.range_min, msg.range_max, self._mount)
        self._scans += 1
        if t - self._last_publish >= self._period:
            self._last_publish = t
            self._pub.publish(grid_message(self._map.to_grid(), self._frame, msg.header.stamp))


def main(args=None) -> None:
    """Run the mapper until Ctrl-C."""
    run_node(MapperNode, args, executor_factory=EventsExecutor)
