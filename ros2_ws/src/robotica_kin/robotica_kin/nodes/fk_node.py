"""
Forward-kinematics node: ``joint_states`` -> end-effector pose and link frames (book §4.3).

For every ``sensor_msgs/JointState`` the node picks its robot's joints by name (in any order;
other joints are ignored) and publishes, with the same stamp and in ``base_frame_id``:
``~/end_effector_pose`` (geometry_msgs/PoseStamped, the tool frame ``T_0_tool``, book (4.6)) and
``~/link_poses`` (geometry_msgs/PoseArray: Craig's frames {0} … {n}, then the tool). The DH
table goes out once on the latched ``~/robot_description_dh`` (robotica_msgs/DHTable; no tool
in it). The ``~/forward_kinematics`` service (robotica_msgs/ForwardKinematics) computes the pose
of any built-in robot or DH table, or of the node's own robot when the request names none.

The robot is the built-in ``robot`` or, when that is '', the flattened HEMERO table
``dh_table``; an unknown robot or a malformed table stops the node at start-up (exit code 2).
A joint-state message lacking a joint, naming one twice, with not one position per name or a
NaN position is refused (``robotica_kin.ros.convert.joint_state_values``; the guard logs it).
"""
from geometry_msgs.msg import PoseArray, PoseStamped
from robotica_kin.forward_kinematics import fkine, link_frames
from robotica_kin.ros.convert import joint_state_values
from robotica_kin.ros.dh_messages import (declare_robot, dh_table_message, pose_message,
                                          request_robot)
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import error_text, GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS, STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_msgs.msg import DHTable
from robotica_msgs.srv import ForwardKinematics
from sensor_msgs.msg import JointState


class ForwardKinematicsNode(GuardedNode):
    """ROS shell around :func:`robotica_kin.forward_kinematics.fkine` and ``link_frames``."""

    def __init__(self) -> None:
        super().__init__('fk_node')
        self._robot = declare_robot(self, 'Built-in robot',
                                    joint_names='one per DH row, as in joint_states')
        self._frame = declare(self, 'base_frame_id', 'link_0',
                              'Frame {0} of the robot: frame_id of every pose', read_only=True)

        self._pose_pub = self.create_publisher(PoseStamped, '~/end_effector_pose',
                                               STREAM_PUB_QOS)
        self._links_pub = self.create_publisher(PoseArray, '~/link_poses', STREAM_PUB_QOS)
        description = self.create_publisher(DHTable, '~/robot_description_dh', LATCHED_QOS)
        table = dh_table_message(self._robot, self._frame)
        table.header.stamp = self.get_clock().now().to_msg()
        description.publish(table)
        self.create_subscription(JointState, 'joint_states', self._on_joint_states,
                                 STREAM_SUB_QOS)
        self.create_service(ForwardKinematics, '~/forward_kinematics', self._on_fk_request)
        self.get_logger().info(f'robot {self._robot.name!r}, {self._robot.n} joints '
                               f'{list(self._robot.joint_names)}')

    def _on_joint_states(self, msg: JointState) -> None:
        (q,) = joint_state_values(msg, self._robot.joint_names)   # refused: the guard logs it
        frames = link_frames(self._robot, q)
        tool = fkine(self._robot, q)
        pose = PoseStamped(pose=pose_message(tool))
        pose.header.stamp = msg.header.stamp
        pose.header.frame_id = self._frame
        links = PoseArray(header=pose.header,
                          poses=[pose_message(T) for T in frames] + [pose.pose])
        self._pose_pub.publish(pose)
        self._links_pub.publish(links)

    def _on_fk_request(self, request: ForwardKinematics.Request,
                       response: ForwardKinematics.Response) -> ForwardKinematics.Response:
        try:
            robot = request_robot(request.robot, request.dh, self._robot)
            response.pose = pose_message(fkine(robot, list(request.q)))
        except ValueError as err:
            response.success = False
            response.message = error_text(err)
            self.get_logger().warn(f'forward_kinematics refused: {response.message}')
            return response
        response.success = True
        return response


def main(args=None) -> None:
    """Run the forward-kinematics node until Ctrl-C."""
    run_node(ForwardKinematicsNode, args)
