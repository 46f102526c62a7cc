"""
Joint controller node: a control law of book ch. 8 closing the loop over topics.

Each ``joint_states`` message (sensor_msgs/JointState, matched to ``joint_names`` by name) is
answered with one torque command on ``joint_torques`` (std_msgs/Float64MultiArray, joint order,
[N m | N]) and one ``~/controller_state`` (robotica_msgs/JointControllerState: reference, error,
torque; stamped with the state's time). Answering each state exactly once is what a lockstep
simulation needs.

The law is chosen by ``law`` and lives in :mod:`robotica_ctrl.joint_control`:

* ``pid``: decoupled PID per joint (8.10), anti-windup, saturation, filtered derivative; gains
  ``pid.*``.
* ``computed_torque``: ``tau = M̂(q)(q_d'' + K_v e' + K_p e [+ K_i ∫e]) + V̂ + Ĝ [+ F̂]``
  (8.27)-(8.37) on the model given by ``robot`` or ``dyn_table`` (give a deliberately wrong
  table to study model errors, Ej. 8.2); gains ``computed_torque.*``.

The reference comes from ``~/joint_trajectory`` (trajectory_msgs/JointTrajectory, transient
local): its points are interpolated as ros2_controllers' joint trajectory controller does
(quintic, cubic or linear Hermite,
:class:`~robotica_ctrl.trajectory.sampled_trajectory.SampledTrajectory`).
A trajectory stamped 0 starts at the time of the next joint state. Without a trajectory the
controller holds the first measured position. A state with missing, repeated or non-finite
joints, joints beyond the physical bounds of :mod:`robotica_kin.bounds`, or a stamp more than
``MAX_TIME_JUMP`` from the previous ones (a StampGate: three agreeing states restart the
controller there) is not answered (a simulator then brakes on its stale command) and the reason
is logged; so is a state whose torques come out non-finite (the guard of
:mod:`robotica_kin.ros.guarded` does not publish them).
"""
import numpy as np
from rclpy.experimental import EventsExecutor
from robotica_ctrl.joint_control import JointControlLaw, JointReference, JointState
from robotica_ctrl.joint_control.control_laws import (FIRST_PERIOD, JOINT_LAW_PARAMETERS,
                                                      JOINT_LAWS, make_joint_law, MAX_PERIOD)
from robotica_ctrl.trajectory.sampled_trajectory import SampledTrajectory, trajectory_from_points
from robotica_kin.bounds import bounded_array, MAX_JOINT_POSITION, MAX_JOINT_VELOCITY, StampGate
from robotica_kin.ros.convert import joint_state_values, seconds_to_stamp, stamp_to_seconds
from robotica_kin.ros.dh_messages import declare_robot
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import (COMMAND_PUB_QOS, INPUT_QOS_OVERRIDES, LATCHED_QOS,
                                  STREAM_PUB_QOS, STREAM_SUB_QOS)
from robotica_msgs.msg import JointControllerState
from sensor_msgs.msg import JointState as JointStateMsg
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory


class JointControllerNode(GuardedNode):
    """ROS shell around a :class:`~robotica_ctrl.joint_control.JointControlLaw`."""

    def __init__(self) -> None:
        super().__init__('joint_controller')
        self._law_name = declare(self, 'law', 'computed_torque',
                                 f'Control law: one of {JOINT_LAWS}', read_only=True)
        self._robot = declare_robot(self, "The controller's model", dynamics=True,
                                    joint_names='the order of states and torques')
        grav = declare(self, 'gravity', [0.0, 0.0, -9.81],
                       'Gravity acceleration [m/s^2] in the base frame {0} for the model',
                       read_only=True)
        use_friction = declare(self, 'use_friction', True,
                               "Compensate the model's friction F̂ (computed_torque)",
                               read_only=True)
        self._wait_for_trajectory = declare(
            self, 'wait_for_trajectory', False,
            'Answer no state before a trajectory arrives (a lockstep run: its simulator repeats '
            'step 0 until answered); false: hold the first state meanwhile', read_only=True)
        periods = declare_specs(self, {'first_period': FIRST_PERIOD, 'max_period': MAX_PERIOD})
        self._first_period, self._max_period = periods['first_period'], periods['max_period']
        prefix = f'{self._law_name}.'
        gains = {name.removeprefix(prefix): value for name, value in declare_specs(
            self, {prefix + k: v for k, v in JOINT_LAW_PARAMETERS.get(self._law_name, {}).items()}
        ).items()}   # an unknown law has none: make_joint_law refuses it
        self._law: JointControlLaw = make_joint_law(self._law_name, self._robot, gains, grav,
                                                    use_friction=use_friction)
        self._names = list(self._robot.joint_names)
        self._trajectory: SampledTrajectory | None = None
        self._trajectory_start: float | None = None
        self._hold: np.ndarray | None = None
        self._previous_time: float | None = None
        self._stamps = StampGate()   # of the joint states
        self._torque_pub = self.create_publisher(Float64MultiArray, 'joint_torques',
                                                 COMMAND_PUB_QOS)
        self._state_pub = self.create_publisher(JointControllerState, '~/controller_state',
                                                STREAM_PUB_QOS)
        self.create_subscription(JointTrajectory, '~/joint_trajectory', self._on_trajectory,
                                 LATCHED_QOS)
        self.create_subscription(JointStateMsg, 'joint_states', self._on_joint_states,
                                 STREAM_SUB_QOS, qos_overriding_options=INPUT_QOS_OVERRIDES)
        self.get_logger().info(f'law {self._law_name} on model {self._robot.name!r}, joints '
                               f'{self._names}')

    # -- reference --------------------------------------------------------------------------
    def _on_trajectory(self, msg: JointTrajectory) -> None:
        points = msg.points
        try:
            trajectory = trajectory_from_points(msg.joint_names, points, self._names)
        except ValueError as err:
            self.get_logger().error(f'trajectory refused: {err}; keeping the previous reference')
            return
        self._trajectory = trajectory
        stamp = stamp_to_seconds(msg.header.stamp)
        self._trajectory_start = stamp if stamp > 0.0 else None
        self.get_logger().info(
            f'trajectory of {len(points)} points over {trajectory.end_time:.3f} s received; '
            + (f'starts at t = {stamp:.3f} s' if stamp > 0.0 else 'starts now'))

    def _reference(self, t: float, q: np.ndarray) -> JointReference:
        if self._trajectory is None:
            if self._hold is None:
                self._hold = q.copy()
                self.get_logger().info(f'no trajectory yet: holding q = {np.round(q, 4).tolist()}')
            return JointReference(self._hold)
        if self._trajectory_start is None:
            self._trajectory_start = t
        return self._trajectory.sample(t - self._trajectory_start)

    def _restart_reason(self, t: float) -> str:
        """
        Return why the state stamped ``t`` [s] starts the law anew, '' when it continues it.

        A restart of the time (one stamp of 1e6 s gave 5e5 N m of PID torque), a time that
        goes back, or a gap longer than ``max_period`` (a gap of 1000 s, integrated, gave
        501 N m): the integrals must not span it.
        """
        if self._stamps.check(t) == 'restart':
            return f'joint_states time restarted at {t:.3f} s'
        if self._previous_time is None:
            return ''
        if t < self._previous_time:
            return f'time went back from {self._previous_time:.3f} s to {t:.3f} s'
        if t - self._previous_time > self._max_period:
            return (f'joint_states gap of {t - self._previous_time:.3f} s > max_period '
                    f'{self._max_period:g} s')
        return ''

    # -- the control step -----------------------------------------------------------------
    def _on_joint_states(self, msg: JointStateMsg) -> None:
        # Refused (missing, repeated or non-finite joints, beyond the bounds, a stamp that jumps):
        # the guard logs it and the state is not answered.
        q, qd = joint_state_values(msg, self._names, ('position', 'velocity'))
        bounded_array('joint positions', q, MAX_JOINT_POSITION)
        bounded_array('joint velocities', qd, MAX_JOINT_VELOCITY)
        t = stamp_to_seconds(msg.header.stamp)
        if self._trajectory is None and self._wait_for_trajectory:
            self.get_logger().info('waiting for a trajectory: state not answered',
                                   throttle_duration_sec=1.0)
            return
        reason = self._restart_reason(t)
        if reason:
            self.get_logger().warn(f'{reason}: controller reset')
            self._law.reset()
            self._previous_time = None
        dt = self._first_period if self._previous_time is None or t == self._previous_time \
            else t - self._previous_time
        self._previous_time = t
        reference = self._reference(t, q)
        tau = self._law.update(reference, JointState(q, qd), dt)
        self._torque_pub.publish(Float64MultiArray(data=tau.tolist()))
        state = JointControllerState(
            law=self._law_name, joint_names=self._names,
            reference_position=np.asarray(reference.q_d).tolist(),
            reference_velocity=np.asarray(reference.qd_d).tolist(),
            reference_acceleration=np.asarray(reference.qdd_d).tolist(),
            position_error=(reference.q_d - q).tolist(),
            velocity_error=(reference.qd_d - qd).tolist(), effort=tau.tolist())
        state.header.stamp = seconds_to_stamp(t)
        self._state_pub.publish(state)


def main(args=None) -> None:
    """Run the joint controller until Ctrl-C."""
    run_node(JointControllerNode, args, executor_factory=EventsExecutor)
