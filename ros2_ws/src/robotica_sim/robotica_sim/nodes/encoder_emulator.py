"""
Encoder emulator node: wheel angles (``joint_states``) -> quantised ticks (``wheel_encoders``).

Each ``sensor_msgs/JointState`` from the simulator gives the cumulative angles of the two drive
wheels; the node publishes one ``robotica_msgs/WheelEncoders`` with the same stamp, counts
quantised by :func:`robotica_sim.encoder_model.quantize_ticks`.
"""
import math

from rclpy.node import Node
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_kin.nodes.qos import STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_msgs.msg import WheelEncoders
from robotica_sim.encoder_model import quantize_ticks
from sensor_msgs.msg import JointState


class EncoderEmulatorNode(Node):
    """Publish the encoder counts of the wheels named by parameters."""

    def __init__(self) -> None:
        super().__init__('encoder_emulator')
        self._ticks_per_rev = declare(
            self, 'ticks_per_revolution', 4096,
            'Counts per wheel revolution [ticks/rev] (PPR x decoding x gear ratio), book §7.3.2',
            low=1, high=10_000_000, read_only=True)
        self._joints = (
            declare(self, 'left_wheel_joint', 'left_wheel_joint', 'Left wheel joint name',
                    read_only=True),
            declare(self, 'right_wheel_joint', 'right_wheel_joint', 'Right wheel joint name',
                    read_only=True))
        self._frame = declare(self, 'frame_id', 'base_link', 'frame_id of the readings',
                              read_only=True)
        self._pub = self.create_publisher(WheelEncoders, 'wheel_encoders', STREAM_PUB_QOS)
        self.create_subscription(JointState, 'joint_states', self._on_joint_states,
                                 STREAM_SUB_QOS)

    def _on_joint_states(self, msg: JointState) -> None:
        try:
            angles = [msg.position[list(msg.name).index(j)] for j in self._joints]
        except (ValueError, IndexError):
            self.get_logger().warn(f'joint_states lacks positions of {self._joints}; ignored',
                                   throttle_duration_sec=5.0)
            return
        if not all(math.isfinite(a) for a in angles):
            self.get_logger().warn('non-finite wheel angle; reading skipped',
                                   throttle_duration_sec=5.0)
            return
        out = WheelEncoders(left_ticks=quantize_ticks(angles[0], self._ticks_per_rev),
                            right_ticks=quantize_ticks(angles[1], self._ticks_per_rev),
                            ticks_per_revolution=self._ticks_per_rev)
        out.header.stamp = msg.header.stamp
        out.header.frame_id = self._frame
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the encoder emulator until Ctrl-C."""
    run_node(EncoderEmulatorNode, args)
