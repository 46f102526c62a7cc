"""
nav_msgs/OccupancyGrid to and from :class:`~robotica_kin.world.occupancy_grid.OccupancyGrid`.

The nodes' one conversion of a map message: the world publisher sends its world's grid with
:func:`grid_message`; the planner reads ``/map`` with :func:`grid_from_message` (which takes any
object with the message's fields). The grading, which imports no ROS message package, reads a
bag's ``/map`` with its own field access (robotica_sim.grading.series).
"""
from typing import Any

from builtin_interfaces.msg import Time
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
import numpy as np
from robotica_kin.ros.convert import quaternion_to_yaw, yaw_to_quaternion
from robotica_kin.world.occupancy_grid import OccupancyGrid

__all__ = ['grid_from_message', 'grid_message']


def grid_message(grid: OccupancyGrid, frame_id: str, stamp: Time | None = None
                 ) -> OccupancyGridMsg:
    """Return ``grid`` as a nav_msgs/OccupancyGrid in ``frame_id`` (row-major, origin yaw)."""
    msg = OccupancyGridMsg()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
        msg.info.map_load_time = stamp
    msg.info.resolution = grid.resolution
    msg.info.width, msg.info.height = grid.width, grid.height
    msg.info.origin.position.x, msg.info.origin.position.y = grid.origin[:2]
    msg.info.origin.orientation = yaw_to_quaternion(grid.origin[2])
    msg.data = grid.data.ravel().tolist()
    return msg


def grid_from_message(msg: Any) -> OccupancyGrid:
    """
    Return the OccupancyGrid of a nav_msgs/OccupancyGrid (or of an object with its fields).

    Raises
    ------
    ValueError
        For data that is not width x height cells, or cells outside -1..100 (WorldError).

    """
    info = msg.info
    data = np.asarray(msg.data, dtype=np.int8)
    if data.size != info.width * info.height or data.size == 0:
        raise ValueError(f'map data holds {data.size} cells, not width x height = '
                         f'{info.width} x {info.height}')
    origin = (info.origin.position.x, info.origin.position.y,
              quaternion_to_yaw(info.origin.orientation))
    return OccupancyGrid(data.reshape(info.height, info.width), info.resolution, origin)
