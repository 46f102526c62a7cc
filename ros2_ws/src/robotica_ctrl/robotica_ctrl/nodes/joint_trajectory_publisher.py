"""
Joint trajectory publisher node: a reference of book ch. 8/10 as one latched JointTrajectory.

``generator`` selects how the trajectory is made (``sine``, ``pol3``, ``pol5``, ``parab``:
:mod:`robotica_ctrl.trajectory.joint_reference`, which also checks the parameters); it is
sampled every ``sample_period`` (with positions, velocities and accelerations, which a
controller interpolates exactly enough) and published once on ``joint_trajectory``
(trajectory_msgs/JointTrajectory, transient local, so a controller started later still gets it).
The header stamp is ``start_time`` (0: the controller starts it when it receives it).
"""
from builtin_interfaces.msg import Duration
from rclpy.parameter import Parameter
from robotica_ctrl.trajectory.joint_reference import REFERENCE_PARAMETERS, reference_samples
from robotica_kin.ros.convert import seconds_to_stamp
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import LATCHED_QOS
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint


class JointTrajectoryPublisherNode(GuardedNode):
    """Publish one generated trajectory, latched, and keep it available."""

    def __init__(self) -> None:
        super().__init__('joint_trajectory_publisher')
        params = declare_specs(self, REFERENCE_PARAMETERS)
        params['joint_names'] = names = declare(
            self, 'joint_names', Parameter.Type.STRING_ARRAY,
            'Joint names of the trajectory, in column order', read_only=True)
        for key, description in (
                ('positions', 'Via points [rad | m], points x joints, row-major'),
                ('velocities', 'Velocities at the via points (pol3, pol5); default zero'),
                ('accelerations', 'Accelerations at the via points (pol5); default zero'),
                ('segment_durations', 'Duration of each segment [s]')):
            params[f'via.{key}'] = declare(self, f'via.{key}', Parameter.Type.DOUBLE_ARRAY,
                                           description, read_only=True)
        t, q, qd, qdd = reference_samples(params)
        generator, start = params['generator'], params['start_time']
        msg = JointTrajectory(joint_names=list(names))
        msg.header.stamp = seconds_to_stamp(start)
        msg.points = [JointTrajectoryPoint(positions=q[k].tolist(), velocities=qd[k].tolist(),
                                           accelerations=qdd[k].tolist(),
                                           time_from_start=seconds_to_stamp(t[k], Duration))
                      for k in range(t.size)]
        self._pub = self.create_publisher(JointTrajectory, 'joint_trajectory', LATCHED_QOS)
        self._pub.publish(msg)
        self.get_logger().info(f'{generator} trajectory of {t.size} points over {t[-1]:.3f} s '
                               f'for joints {list(names)} published')


def main(args=None) -> None:
    """Publish the trajectory and stay up (it is latched) until Ctrl-C."""
    run_node(JointTrajectoryPublisherNode, args)
