#!/usr/bin/env python3
"""
A path tracker of your own for robotica: steer the heading towards a look-ahead point.

The contract of a tracker (docs/your_node.md): read the path once from ``path``
(nav_msgs/Path, transient local) and answer every pose on ``odom`` (nav_msgs/Odometry) with
exactly one velocity command on ``cmd_vel`` (geometry_msgs/Twist): in a lockstep run the
simulator takes its next step only when that answer has come. Answer with a stop when there is
nothing to follow yet or the path is done.

The law: the goal is the first path point at least ``lookahead_distance`` ahead of the robot;
the angular velocity is ``heading_gain`` times the heading error towards it (REP-103: θ from the
x axis, counter-clockwise), at a constant ``speed``. Run it with ``robotica run`` and the
scenario ``robotica new`` wrote beside it; change ``on_odom`` to try your own law.
"""
import math

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry, Path
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
# A command: reliable, volatile; a history of 500, so that the run's recorder, when it falls
# behind for a moment, still gets every command (with 10 a loaded machine lost some).
COMMAND = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)
SEARCH_WINDOW = 40   # path points searched ahead of the previous closest one


class HeadingTracker(Node):
    """Proportional heading control towards a look-ahead point of the path."""

    def __init__(self) -> None:
        super().__init__('my_tracker')
        self.speed = self.declare_parameter('speed', 0.5).value                  # [m/s]
        self.lookahead = self.declare_parameter('lookahead_distance', 0.5).value  # [m]
        self.gain = self.declare_parameter('heading_gain', 2.0).value            # [1/s]
        self.max_rate = self.declare_parameter('max_angular_velocity', 1.5).value  # [rad/s]
        self.goal_tolerance = self.declare_parameter('goal_tolerance', 0.1).value  # [m]
        self.path: list[tuple[float, float]] = []
        self.closest = 0
        self.create_subscription(Path, 'path', self.on_path, LATCHED)
        self.create_subscription(Odometry, 'odom', self.on_odom, 10)
        self.cmd_pub = self.create_publisher(Twist, 'cmd_vel', COMMAND)

    def on_path(self, msg: Path) -> None:
        """Keep the path's points [m] (in its frame, odom)."""
        self.path = [(p.pose.position.x, p.pose.position.y) for p in msg.poses]
        self.closest = 0
        self.get_logger().info(f'path of {len(self.path)} points')

    def on_odom(self, msg: Odometry) -> None:
        """Answer the pose with one command."""
        cmd = Twist()   # zero: a stop
        if len(self.path) >= 2:
            x, y = msg.pose.pose.position.x, msg.pose.pose.position.y
            q = msg.pose.pose.orientation
            theta = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y ** 2 + q.z ** 2))
            window = range(self.closest, min(len(self.path), self.closest + SEARCH_WINDOW))
            self.closest = min(window, key=lambda i: math.dist((x, y), self.path[i]))
            goal = next((p for p in self.path[self.closest:]
                         if math.dist((x, y), p) >= self.lookahead), self.path[-1])
            if math.dist((x, y), self.path[-1]) > self.goal_tolerance \
                    or self.closest < len(self.path) - 1:
                error = math.atan2(goal[1] - y, goal[0] - x) - theta
                error = math.atan2(math.sin(error), math.cos(error))   # to (-pi, pi]
                cmd.linear.x = self.speed
                cmd.angular.z = max(-self.max_rate, min(self.max_rate, self.gain * error))
        self.cmd_pub.publish(cmd)


def main() -> None:
    """Run the tracker until Ctrl-C (or the run stops it)."""
    rclpy.init()
    node = HeadingTracker()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
