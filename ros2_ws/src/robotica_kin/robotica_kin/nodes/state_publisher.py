"""
State publisher node: the URDF on ``robot_description``, ``joint_states`` -> ``/tf``.

robot_state_publisher's job (it is C++ and not on PyPI) for robotica's arms and vehicles. The
model is an arm chosen as the other arm nodes choose it (``robot``, ``dh_table``,
``joint_names``) or, when ``vehicle.type`` is set, a vehicle of the simulator's geometry
(``vehicle.*``, the simulator's names and ranges) with its sensor frames (``imu_height``,
``antenna_height``); :func:`robotica_kin.urdf.robot_description` writes its URDF. The node
publishes, as robot_state_publisher does:

* the URDF once on ``robot_description`` (std_msgs/String, reliable, transient local);
* the fixed joints once on ``/tf_static`` (tf2_msgs/TFMessage, all in one message, transient
  local, as tf2's static broadcaster);
* for each ``joint_states`` message the moving joints' transforms, parent link -> child link, on
  ``/tf``, stamped with the joint state's stamp (the sim time of the step it describes).

The transforms are Pinocchio's forward kinematics of the URDF the node publishes
(:class:`robotica_kin.urdf_kinematics.URDFKinematics`): one model for arms and vehicles, and
what goes on ``/tf`` is by construction the kinematics of the ``/robot_description`` a viewer
draws it with (the URDF's equality with the DH model's ``fkine`` is tested in test_urdf.py).
Every frame id is ``frame_prefix`` + the link's name.

A joint state names any of the model's joints, in any order; the others keep their last value
(0 until one comes) and every moving joint is published; names that are not the model's are
ignored (one ``joint_states`` may carry several robots), and mimic joints follow theirs. Refused,
logged by the guard and dropped (:mod:`robotica_kin.ros.guarded`): a message naming none of the
model's joints, naming one twice, with not one position per name, a non-finite position or one
beyond ``MAX_JOINT_POSITION`` (a continuous joint's angle may be any finite number), a malformed
stamp, or one more than ``MAX_TIME_JUMP`` from the latest accepted (a
:class:`~robotica_kin.bounds.StampGate`: three agreeing stamps in a row move the time base).
"""
from typing import Iterable

from builtin_interfaces.msg import Time
from geometry_msgs.msg import TransformStamped
import numpy as np
from numpy.typing import NDArray
import pinocchio as pin
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import bounded, MAX_JOINT_POSITION, StampGate
from robotica_kin.ros.convert import joint_state_values, stamp_to_seconds
from robotica_kin.ros.dh_messages import declare_robot
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import INPUT_QOS_OVERRIDES, LATCHED_QOS, STREAM_SUB_QOS, TF_QOS
from robotica_kin.urdf import robot_description, ROBOT_DESCRIPTION_PARAMETERS
from robotica_kin.urdf_kinematics import LinkTransform, URDFKinematics
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage


def _frames(links: Iterable[LinkTransform], prefix: str) -> list[TransformStamped]:
    """Return a TransformStamped per link, with the prefixed frame ids and nothing else set."""
    messages = []
    for link in links:
        msg = TransformStamped(child_frame_id=prefix + link.child)
        msg.header.frame_id = prefix + link.parent
        messages.append(msg)
    return messages


def _set(msg: TransformStamped, T: NDArray[np.float64], stamp: Time) -> None:
    """Write the transform T (4, 4) [m] and ``stamp`` into ``msg``."""
    msg.header.stamp = stamp
    translation, rotation = msg.transform.translation, msg.transform.rotation
    translation.x, translation.y, translation.z = (float(v) for v in T[:3, 3])
    # Pinocchio's quaternion: 7 µs (robotica_kin.transforms.tr2q, by SciPy: 1 ms).
    rotation.x, rotation.y, rotation.z, rotation.w = (
        float(v) for v in pin.Quaternion(T[:3, :3]).coeffs())


class StatePublisherNode(GuardedNode):
    """ROS shell around :class:`~robotica_kin.urdf_kinematics.URDFKinematics`."""

    def __init__(self) -> None:
        super().__init__('state_publisher')
        arm = declare_robot(self, "The arm (when vehicle.type is '')",
                            joint_names='one per DH row, as in joint_states')
        values = declare_specs(self, ROBOT_DESCRIPTION_PARAMETERS)
        self._prefix = declare(self, 'frame_prefix', '',
                               "Prepended to every link's name in the frame ids (e.g. 'robot1/')",
                               read_only=True)
        urdf = robot_description(values, arm)
        self._kinematics = URDFKinematics(urdf)
        names = self._kinematics.joint_names
        self._index = {name: i for i, name in enumerate(names)}
        self._bounded = [name not in self._kinematics.continuous for name in names]
        self._q = np.zeros(len(names))
        self._stamps = StampGate()   # of the joint states
        self._tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        static = self.create_publisher(TFMessage, '/tf_static', LATCHED_QOS)
        description = self.create_publisher(String, 'robot_description', LATCHED_QOS)
        description.publish(String(data=urdf))
        now = self.get_clock().now().to_msg()
        transforms = _frames(self._kinematics.fixed, self._prefix)
        for transform, link in zip(transforms, self._kinematics.fixed):
            _set(transform, link.T, now)
        static.publish(TFMessage(transforms=transforms))
        # Built once and refilled for each state: a message built anew cost 0.4 ms a state.
        self._tf = TFMessage(transforms=_frames(self._kinematics.moving(self._q), self._prefix))
        self.create_subscription(JointState, 'joint_states', self._on_joint_states,
                                 STREAM_SUB_QOS, qos_overriding_options=INPUT_QOS_OVERRIDES)
        model = values['vehicle.type'] or arm.name
        self.get_logger().info(f'{model!r}: joints {list(names)}, {len(transforms)} fixed '
                               f'frames on /tf_static')

    def _on_joint_states(self, msg: JointState) -> None:
        # Refused (the guard logs it): see the module's docstring.
        known = [name for name in msg.name if name in self._index]
        if not known:
            raise ValueError(f'JointState names none of the joints {list(self._index)}')
        (q,) = joint_state_values(msg, known)
        for name, value in zip(known, q):
            if self._bounded[self._index[name]]:
                bounded(f'position of {name}', value, MAX_JOINT_POSITION)
        self._stamps.check(stamp_to_seconds(msg.header.stamp))
        for name, value in zip(known, q):
            self._q[self._index[name]] = value
        for transform, link in zip(self._tf.transforms, self._kinematics.moving(self._q)):
            _set(transform, link.T, msg.header.stamp)
        self._tf_pub.publish(self._tf)


def main(args=None) -> None:
    """Run the state publisher until Ctrl-C."""
    run_node(StatePublisherNode, args, executor_factory=EventsExecutor)
