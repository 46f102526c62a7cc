#!/usr/bin/env python3
"""
An estimator of your own for robotica: dead reckoning from wheel-encoder ticks.

The contract of an estimator (docs/your_node.md): answer every reading on ``wheel_encoders``
(robotica_msgs/WheelEncoders: cumulative ticks of the left and right wheels) with exactly one
``odom`` (nav_msgs/Odometry, pose in ``odom``, twist in ``base_link``, REP-105) stamped with the
reading's stamp: the tracker answers that pose, and a lockstep simulator steps on.

The model (book §4.7.5, differential drive): each wheel travels ΔU = 2π c Δticks / N (N ticks
per revolution), the robot ΔU_c = (ΔU_l + ΔU_r) / 2 and turns Δθ = (ΔU_r − ΔU_l) / b; the pose
moves by ΔU_c along the mean heading θ + Δθ/2 (the midpoint rule). ``wheel_radius`` c [m],
``wheel_separation`` b [m] and the initial pose come from the run's scenario.
"""
import math

from nav_msgs.msg import Odometry
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_msgs.msg import WheelEncoders

# odom is a stream: published reliable and transient local (a late subscriber, such as the
# lockstep simulator that waits for each estimate, gets the history), keep last 500.
STREAM = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE,
                    durability=DurabilityPolicy.TRANSIENT_LOCAL)


class DeadReckoning(Node):
    """Integrate the wheels' travel into a planar pose (x, y, θ)."""

    def __init__(self) -> None:
        super().__init__('my_estimator')
        self.radius = self.declare_parameter('wheel_radius', 0.1).value          # c [m]
        self.separation = self.declare_parameter('wheel_separation', 0.4).value  # b [m]
        self.x = self.declare_parameter('initial_pose.x', 0.0).value             # [m]
        self.y = self.declare_parameter('initial_pose.y', 0.0).value             # [m]
        self.theta = self.declare_parameter('initial_pose.theta', 0.0).value     # [rad]
        self.previous = None   # (left ticks, right ticks, time [s]) of the last reading
        self.create_subscription(WheelEncoders, 'wheel_encoders', self.on_ticks, 10)
        self.odom_pub = self.create_publisher(Odometry, 'odom', STREAM)

    def on_ticks(self, msg: WheelEncoders) -> None:
        """Answer the reading with one pose estimate."""
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        v = omega = 0.0
        if self.previous is not None and msg.ticks_per_revolution > 0:
            left, right, t0 = self.previous
            metres_per_tick = 2.0 * math.pi * self.radius / msg.ticks_per_revolution
            d_left = (msg.left_ticks - left) * metres_per_tick
            d_right = (msg.right_ticks - right) * metres_per_tick
            distance = (d_left + d_right) / 2.0
            turn = (d_right - d_left) / self.separation
            self.x += distance * math.cos(self.theta + turn / 2.0)
            self.y += distance * math.sin(self.theta + turn / 2.0)
            self.theta = math.atan2(math.sin(self.theta + turn), math.cos(self.theta + turn))
            if t > t0:
                v, omega = distance / (t - t0), turn / (t - t0)
        self.previous = (msg.left_ticks, msg.right_ticks, t)
        odom = Odometry()
        odom.header.stamp = msg.header.stamp
        odom.header.frame_id = 'odom'
        odom.child_frame_id = 'base_link'
        odom.pose.pose.position.x = self.x
        odom.pose.pose.position.y = self.y
        odom.pose.pose.orientation.z = math.sin(self.theta / 2.0)
        odom.pose.pose.orientation.w = math.cos(self.theta / 2.0)
        odom.twist.twist.linear.x = v
        odom.twist.twist.angular.z = omega
        self.odom_pub.publish(odom)


def main() -> None:
    """Run the estimator until Ctrl-C (or the run stops it)."""
    rclpy.init()
    node = DeadReckoning()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
