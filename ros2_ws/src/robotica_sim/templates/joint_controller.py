#!/usr/bin/env python3
"""
A joint controller of your own for robotica: PD control of every joint (book §8.2).

The contract of a joint controller (docs/your_node.md): read the reference once from
``~/joint_trajectory`` (trajectory_msgs/JointTrajectory, transient local) and answer every
``joint_states`` (sensor_msgs/JointState) with exactly one ``joint_torques``
(std_msgs/Float64MultiArray: one torque [N m] per joint, in the order of the state's names): in
a lockstep run the simulator takes its next step only when that answer has come. Until the
reference has come, answer nothing: the simulator repeats step 0 meanwhile.

The law: τ_i = K_p,i (q_d,i − q_i) + K_v,i (q'_d,i − q'_i), with the reference interpolated
linearly between the trajectory's points; its time starts at the first state answered.
"""
import bisect

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
# A command: reliable, volatile; a history of 500, so that the run's recorder, when it falls
# behind for a moment, still gets every command (with 10 a loaded machine lost 50 of 4000).
COMMAND = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)


class PdController(Node):
    """Decoupled PD control of each joint towards a sampled reference."""

    def __init__(self) -> None:
        super().__init__('my_joint_controller')
        self.kp = self.declare_parameter('kp', [1600.0, 160.0]).value   # K_p per joint [N m/rad]
        self.kv = self.declare_parameter('kv', [160.0, 16.0]).value     # K_v [N m s/rad]
        self.times: list[float] = []          # [s] from the start of the reference
        self.positions: list[list[float]] = []
        self.velocities: list[list[float]] = []
        self.joints: list[str] = []
        self.start = None                     # [s] time of the first state answered
        self.create_subscription(JointTrajectory, '~/joint_trajectory', self.on_trajectory,
                                 LATCHED)
        self.create_subscription(JointState, 'joint_states', self.on_state, 10)
        self.torque_pub = self.create_publisher(Float64MultiArray, 'joint_torques', COMMAND)

    def on_trajectory(self, msg: JointTrajectory) -> None:
        """Keep the reference's samples."""
        self.joints = list(msg.joint_names)
        self.times = [p.time_from_start.sec + p.time_from_start.nanosec * 1e-9
                      for p in msg.points]
        self.positions = [list(p.positions) for p in msg.points]
        self.velocities = [list(p.velocities) or [0.0] * len(self.joints) for p in msg.points]
        self.get_logger().info(f'reference of {len(self.times)} points for {self.joints}')

    def reference(self, t: float) -> tuple[list[float], list[float]]:
        """Return the reference positions and velocities at ``t`` [s], held after the end."""
        k = bisect.bisect_right(self.times, t)
        if k == 0:
            return self.positions[0], self.velocities[0]
        if k == len(self.times):
            return self.positions[-1], [0.0] * len(self.joints)
        s = (t - self.times[k - 1]) / (self.times[k] - self.times[k - 1])

        def blend(a: list[float], b: list[float]) -> list[float]:
            return [x + s * (y - x) for x, y in zip(a, b)]
        return (blend(self.positions[k - 1], self.positions[k]),
                blend(self.velocities[k - 1], self.velocities[k]))

    def on_state(self, msg: JointState) -> None:
        """Answer the state with one torque per joint (none before the reference)."""
        if not self.times:
            return
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        if self.start is None:
            self.start = t
        q_d, v_d = self.reference(t - self.start)
        torques = []
        for i, name in enumerate(msg.name):
            j = self.joints.index(name)
            velocity = msg.velocity[i] if i < len(msg.velocity) else 0.0
            torques.append(self.kp[j] * (q_d[j] - msg.position[i])
                           + self.kv[j] * (v_d[j] - velocity))
        self.torque_pub.publish(Float64MultiArray(data=torques))


def main() -> None:
    """Run the controller until Ctrl-C (or the run stops it)."""
    rclpy.init()
    node = PdController()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
