"""
Odometry node: dead reckoning from wheel-encoder ticks -> ``odom`` (nav_msgs/Odometry).

The maths is :class:`robotica_kin.mobile.odometry.DiffDriveOdometry` (the slides' update, book
§4.7.5; exact arc (4.93) by default). The pose is in ``odom_frame_id``, the twist in
``base_frame_id`` (REP-105); the odometry starts at ``initial_pose``.
"""
from nav_msgs.msg import Odometry
from rclpy.node import Node
from robotica_kin.mobile.differential_drive import DifferentialDriveParams
from robotica_kin.mobile.odometry import DiffDriveOdometry, ODOMETRY_METHODS
from robotica_kin.nodes.convert import odometry_message, stamp_to_seconds
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_kin.nodes.qos import STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_msgs.msg import WheelEncoders


class OdometryNode(Node):
    """Integrate encoder ticks into a pose estimate."""

    def __init__(self) -> None:
        super().__init__('odometry')
        self._robot = DifferentialDriveParams(
            wheel_radius=declare(self, 'wheel_radius', 0.1, 'Wheel radius c [m], book (4.109)',
                                 low=1e-3, high=10.0, read_only=True),
            wheel_separation=declare(self, 'wheel_separation', 0.4,
                                     'Track b between the drive wheels [m], book (4.110)',
                                     low=1e-3, high=100.0, read_only=True))
        self._method = declare(self, 'integration_method', 'exact_arc',
                               f'Pose update: one of {ODOMETRY_METHODS} (slides §13.6, book '
                               '(4.93))', read_only=True)
        if self._method not in ODOMETRY_METHODS:
            raise ValueError(f'integration_method must be one of {ODOMETRY_METHODS}, '
                             f'got {self._method!r}')
        self._initial_pose = [
            declare(self, 'initial_pose.' + k, 0.0, d, low=-1e6, high=1e6, read_only=True)
            for k, d in (('x', 'Initial x [m] in the odom frame'),
                         ('y', 'Initial y [m] in the odom frame'),
                         ('theta', 'Initial heading [rad], REP-103'))]
        self._odom_frame = declare(self, 'odom_frame_id', 'odom', 'Frame of the pose',
                                   read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link', 'Frame of the robot',
                                   read_only=True)
        self._odometry = None
        self._ticks_per_rev = 0
        self._pub = self.create_publisher(Odometry, 'odom', STREAM_PUB_QOS)
        self.create_subscription(WheelEncoders, 'wheel_encoders', self._on_ticks, STREAM_SUB_QOS)

    def _on_ticks(self, msg: WheelEncoders) -> None:
        if msg.ticks_per_revolution < 1:
            self.get_logger().warn('wheel_encoders with ticks_per_revolution 0; ignored',
                                   throttle_duration_sec=5.0)
            return
        if self._odometry is None or self._ticks_per_rev != msg.ticks_per_revolution:
            self._ticks_per_rev = msg.ticks_per_revolution
            self._odometry = DiffDriveOdometry(self._robot, self._ticks_per_rev, self._method)
            self._odometry.reset(self._initial_pose)
        t = stamp_to_seconds(msg.header.stamp)
        try:
            pose = self._odometry.update(msg.left_ticks, msg.right_ticks, t)
        except ValueError as err:
            self.get_logger().warn(f'reading refused: {err}', throttle_duration_sec=5.0)
            return
        out = odometry_message(t, self._odom_frame, self._base_frame, pose,
                               self._odometry.twist)
        self._pub.publish(out)


def main(args=None) -> None:
    """Run the odometry node until Ctrl-C."""
    run_node(OdometryNode, args)
