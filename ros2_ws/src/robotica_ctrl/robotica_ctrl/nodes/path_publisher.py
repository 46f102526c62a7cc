"""
Path publisher node: a reference path from parameters -> latched ``path`` (nav_msgs/Path).

The path is the polyline through ``x``/``y`` [m] in ``frame_id``; each pose faces the next point.
With ``t`` (one time [s] per point, strictly increasing) it is a trajectory: each pose is
stamped with its time, which trajectory tracking (book §9.4.2) follows.
Published once with a reliable, transient-local QoS, so a tracker that starts later still gets it.
"""
from nav_msgs.msg import Path
import numpy as np
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.exceptions import ParameterUninitializedException
from rclpy.parameter import Parameter
from robotica_kin.ros.convert import path_message
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS


class PathPublisherNode(GuardedNode):
    """Publish one path given as parameters."""

    def __init__(self) -> None:
        super().__init__('path_publisher')
        # Every parameter is declared before any is checked (robotica params lists them all).
        for axis in ('x', 'y'):
            self.declare_parameter(axis, Parameter.Type.DOUBLE_ARRAY, ParameterDescriptor(
                description=f'{axis} coordinates of the path points [m]', read_only=True))
        self.declare_parameter('t', Parameter.Type.DOUBLE_ARRAY, ParameterDescriptor(
            description='Optional time of each path point [s], strictly increasing: the path '
            'is then a trajectory', read_only=True))
        frame = declare(self, 'frame_id', 'odom', 'Frame of the path', read_only=True)
        coords = []
        for axis in ('x', 'y'):
            try:
                coords.append(np.asarray(self.get_parameter(axis).value, dtype=float))
            except ParameterUninitializedException:
                raise ValueError(f'parameter {axis!r} (path points) is required') from None
        try:
            times = np.asarray(self.get_parameter('t').value, dtype=float)
        except ParameterUninitializedException:
            times = None
        x, y = coords
        if x.shape != y.shape or x.size < 2:
            raise ValueError(f'x and y need the same length >= 2, got {x.size} and {y.size}')
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise ValueError('path coordinates must be finite')
        if times is not None and (times.shape != x.shape or not np.all(np.isfinite(times))
                                  or np.any(np.diff(times) <= 0.0)):
            raise ValueError(f't needs {x.size} finite, strictly increasing times [s]')
        self._pub = self.create_publisher(Path, 'path', LATCHED_QOS)
        self._pub.publish(path_message(np.column_stack([x, y]), frame, times=times))
        timing = '' if times is None else f', timed {times[0]:g}-{times[-1]:g} s'
        self.get_logger().info(f'published a path of {x.size} points in frame {frame!r}'
                               f'{timing}')


def main(args=None) -> None:
    """Run the path publisher until Ctrl-C."""
    run_node(PathPublisherNode, args)
