"""
World publisher node: the run's world on ``/map``, as a map server does, and as markers.

Loads ``world_file`` (a map_server map, or a YAML file with a ``world:`` section such as the
run's scenario: :func:`robotica_kin.world.world_file.load_world_file`), draws it as an occupancy
grid of ``resolution`` [m/cell] (:func:`robotica_kin.world.rasterise.world_grid`; a map file's
grid as it is) and publishes it once on ``/map`` (nav_msgs/OccupancyGrid, frame ``frame_id``,
reliable and transient local as nav2_map_server's, so that a viewer, a planner or the recorder
that comes later still gets it), and its geometry on ``~/markers``
(visualization_msgs/MarkerArray, latched: the walls and polygon edges as one LINE_LIST ``walls``,
each circle a CYLINDER ``circles``, 0.5 m high), which a viewer draws exactly, without the
grid's cells. A world file that is missing or malformed ends the node at start-up with one line
naming the file and the field (exit 2).
"""
from pathlib import Path

from geometry_msgs.msg import Point
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.grid_messages import grid_message
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS
from robotica_kin.world.rasterise import world_as_grid
from robotica_kin.world.shapes import World
from robotica_kin.world.world_file import load_world_file
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

WALL_HEIGHT = 0.5   # [m] of the drawn circles (posts); walls are lines on the floor


class WorldPublisherNode(GuardedNode):
    """Publish the world of ``world_file`` on /map, once, latched."""

    def __init__(self) -> None:
        super().__init__('world_publisher')
        path = declare(self, 'world_file', '', 'The world: a map_server map or a YAML file with '
                       'a world: section (a scenario)', read_only=True)
        resolution = declare(self, 'resolution', 0.05, 'Cell size of the grid drawn from the '
                             "world's geometry [m/cell] (a map file keeps its own)",
                             low=0.001, high=10.0, read_only=True)
        frame = declare(self, 'frame_id', 'map', 'Frame of the map', read_only=True)
        if not path:
            raise ValueError('parameter world_file is required')
        world = load_world_file(Path(path))   # WorldError (a ValueError): one line, exit 2
        grid = world_as_grid(world, resolution)
        self.create_publisher(OccupancyGridMsg, '/map', LATCHED_QOS).publish(
            grid_message(grid, frame))
        self.create_publisher(MarkerArray, '~/markers', LATCHED_QOS).publish(
            world_markers(world, frame))
        self.get_logger().info(f'/map: {grid.width} x {grid.height} cells of '
                               f'{grid.resolution} m from {path}')


def world_markers(world: World, frame: str) -> MarkerArray:
    """Return the world's walls (one LINE_LIST) and circles (CYLINDERs) as markers in ``frame``."""
    grey = ColorRGBA(r=0.3, g=0.3, b=0.3, a=1.0)
    markers = MarkerArray()
    if len(world.segments):
        walls = Marker(ns='walls', id=0, type=Marker.LINE_LIST, action=Marker.ADD, color=grey)
        walls.scale.x = 0.03   # [m] line width
        walls.points = [Point(x=float(x), y=float(y)) for x1, y1, x2, y2 in world.segments
                        for x, y in ((x1, y1), (x2, y2))]
        markers.markers.append(walls)
    for k, (cx, cy, r) in enumerate(world.circles):
        post = Marker(ns='circles', id=k, type=Marker.CYLINDER, action=Marker.ADD, color=grey)
        post.pose.position.x, post.pose.position.y = float(cx), float(cy)
        post.pose.position.z = WALL_HEIGHT / 2.0
        post.pose.orientation.w = 1.0
        post.scale.x = post.scale.y = 2.0 * float(r)
        post.scale.z = WALL_HEIGHT
        markers.markers.append(post)
    for marker in markers.markers:
        marker.header.frame_id = frame
        marker.pose.orientation.w = 1.0
    return markers


def main(args=None) -> None:
    """Run the world publisher until Ctrl-C."""
    run_node(WorldPublisherNode, args, executor_factory=EventsExecutor)
