"""
Encoder emulator node: wheel angles (``joint_states``) -> quadrature counts (``wheel_encoders``).

Each ``sensor_msgs/JointState`` from the simulator gives the cumulative angles of the two
odometry wheels; the node publishes one ``robotica_msgs/WheelEncoders`` with the same stamp. Each
wheel's counter is a :class:`robotica_sim.sensors.encoder.EncoderModel` (book §7.3.2, slides
§13.6): ``pulses_per_revolution`` × ``decoding`` (×1/×2/×4 quadrature) × ``gear_ratio`` counts
per wheel revolution, floor quantisation, and edges missed with ``missed_count_probability``
(reproducible from ``seed``). Wheel-radius and track errors are a mismatch between the simulated
vehicle and the odometry's nominal geometry: set them there.
"""
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import bounded_array, MAX_JOINT_POSITION
from robotica_kin.ros.convert import joint_state_values
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_msgs.msg import WheelEncoders
from robotica_sim.sensors.encoder import ENCODER_PARAMETERS, encoder_params, EncoderModel
from sensor_msgs.msg import JointState


class EncoderEmulatorNode(GuardedNode):
    """Publish the encoder counts of the wheels named by parameters."""

    def __init__(self) -> None:
        super().__init__('encoder_emulator')
        values = declare_specs(self, ENCODER_PARAMETERS)
        params = encoder_params(values)
        seed = values['seed']
        left, right = (np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(2))
        self._counters = (EncoderModel(params, left), EncoderModel(params, right))
        self._ticks_per_rev = params.ticks_per_revolution
        self._joints = (
            declare(self, 'left_wheel_joint', 'left_wheel_joint', 'Left wheel joint name',
                    read_only=True),
            declare(self, 'right_wheel_joint', 'right_wheel_joint', 'Right wheel joint name',
                    read_only=True))
        self._frame = declare(self, 'frame_id', 'base_link', 'frame_id of the readings',
                              read_only=True)
        self._pub = self.create_publisher(WheelEncoders, 'wheel_encoders', STREAM_PUB_QOS)
        self.create_subscription(JointState, 'joint_states', self._on_joint_states,
                                 STREAM_REPLAY_SUB_QOS)
        self.get_logger().info(f'{self._ticks_per_rev} counts per wheel revolution, missed '
                               f'counts with p = {params.missed_count_probability}')

    def _on_joint_states(self, msg: JointState) -> None:
        (angles,) = joint_state_values(msg, self._joints)   # refused: the guard logs it
        bounded_array('wheel angles', angles, MAX_JOINT_POSITION)
        left, right = (counter.ticks(a) for counter, a in zip(self._counters, angles))
        out = WheelEncoders(left_ticks=left, right_ticks=right,
                            ticks_per_revolution=self._ticks_per_rev)
        out.header.stamp = msg.header.stamp
        out.header.frame_id = self._frame
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the encoder emulator until Ctrl-C."""
    run_node(EncoderEmulatorNode, args, executor_factory=EventsExecutor)
