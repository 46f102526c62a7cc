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
controller holds the first measured position. With ``trial_period`` T > 0 the run is a series of
trials (iterative learning, §8.5): the reference restarts every T seconds (the simulator puts the
arm back at its initial state then), and a learning law ends a trial, learns from it and
publishes its mean squared error (8.153) on ``~/learning_trials`` (robotica_msgs/LearningTrial,
transient local); ``learning_file`` keeps the learned feed-forward between runs (a trial can also
be a run). An adaptive law publishes its estimates every step on ``~/adaptation``
(robotica_msgs/AdaptationState).

The task-space laws (:mod:`robotica_ctrl.joint_control.task_laws`) take no joint trajectory:

* ``stiffness``, ``hybrid``, ``impedance`` (force control, §8.7) follow the ``task.*`` reference
  in the task frame ``task.axes`` and read the contact wrench from ``contact_wrench``
  (geometry_msgs/WrenchStamped, what a wrist F/T sensor aligned with the tool reads; remap it to
  ``ft_sensor/wrench`` to close the loop through the sensor emulator). Each state is answered
  when the wrench of its stamp has arrived (lockstep-safe); ``~/force_control``
  (robotica_msgs/ForceControlState) shows positions and forces in the task frame;
* ``resolved_rate``, ``transpose_jacobian``, ``operational_space`` (Cartesian control, §8.6)
  drive the end effector along a straight line from its pose at the first state to
  ``cartesian.goal`` in ``cartesian.duration``; ``~/cartesian_control``
  (robotica_msgs/CartesianControlState) shows the poses, the error and how near a singularity.

A state with missing, repeated or non-finite joints, joints beyond the physical bounds of
:mod:`robotica_kin.bounds`, or a stamp more than ``MAX_TIME_JUMP`` from the previous ones (a
StampGate: three agreeing states restart the controller there) is not answered (a simulator
then brakes on its stale command) and the reason is logged; so is a state whose torques come out
non-finite (the guard of :mod:`robotica_kin.ros.guarded` does not publish them).
"""
import os

from geometry_msgs.msg import WrenchStamped
import numpy as np
from rclpy.experimental import EventsExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_ctrl.joint_control import JointReference, JointState
from robotica_ctrl.joint_control.control_laws import (FIRST_PERIOD, JOINT_LAW_PARAMETERS,
                                                      JOINT_LAWS, make_joint_law, MAX_PERIOD,
                                                      TRIAL_PERIOD)
from robotica_ctrl.joint_control.task_laws import (TASK_LAW_PARAMETERS, TASK_LAWS,
                                                   TASK_PARAMETERS, TaskSpaceControl)
from robotica_ctrl.nodes.law_telemetry import (adaptation_message, cartesian_control_message,
                                               force_control_message, is_adaptive, is_learning,
                                               learning_trial_message)
from robotica_ctrl.trajectory.sampled_trajectory import SampledTrajectory, trajectory_from_points
from robotica_kin.bounds import (bounded_array, MAX_FORCE_TORQUE, MAX_JOINT_POSITION,
                                 MAX_JOINT_VELOCITY, StampGate)
from robotica_kin.forward_kinematics import fkine
from robotica_kin.ros.convert import joint_state_values, seconds_to_stamp, stamp_to_seconds
from robotica_kin.ros.dh_messages import declare_robot
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import (COMMAND_PUB_QOS, INPUT_QOS_OVERRIDES, LATCHED_QOS,
                                  STREAM_PUB_QOS, STREAM_SUB_QOS)
from robotica_msgs.msg import (AdaptationState, CartesianControlState, ForceControlState,
                               JointControllerState, LearningTrial)
from sensor_msgs.msg import JointState as JointStateMsg
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory

TRIALS_QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)
"""~/learning_trials: every trial of the run, for a recorder or a plot that joins late."""


class JointControllerNode(GuardedNode):
    """ROS shell around a :class:`~robotica_ctrl.joint_control.JointControlLaw`."""

    def __init__(self) -> None:
        super().__init__('joint_controller')
        self._law_name = declare(self, 'law', 'computed_torque',
                                 f'Control law: one of {JOINT_LAWS + TASK_LAWS}',
                                 read_only=True)
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
        periods = declare_specs(self, {'first_period': FIRST_PERIOD, 'max_period': MAX_PERIOD,
                                       'trial_period': TRIAL_PERIOD})
        self._first_period, self._max_period = periods['first_period'], periods['max_period']
        self._trial_period = periods['trial_period']
        self._learning_file = declare(
            self, 'learning_file', '', 'File (.npz) of the learned feed-forward of law learning: '
            'loaded at the start if it exists, saved after each trial; empty: none',
            read_only=True)
        prefix = f'{self._law_name}.'
        specs = {**JOINT_LAW_PARAMETERS, **TASK_LAW_PARAMETERS}.get(self._law_name, {})
        gains = {name.removeprefix(prefix): value for name, value in declare_specs(
            self, {prefix + k: v for k, v in specs.items()}
        ).items()}   # an unknown law has none: make_joint_law refuses it
        self._task: TaskSpaceControl | None = None
        if self._law_name in TASK_LAWS:
            self._task = TaskSpaceControl(self._law_name, self._robot, gains,
                                          declare_specs(self, TASK_PARAMETERS), grav,
                                          use_friction=use_friction, step=self._first_period)
            self._law = self._task.law
        else:
            self._law = make_joint_law(self._law_name, self._robot, gains, grav,
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
        self._adaptation_pub = self.create_publisher(
            AdaptationState, '~/adaptation', STREAM_PUB_QOS) if is_adaptive(self._law) else None
        self._trials_pub = self.create_publisher(
            LearningTrial, '~/learning_trials', TRIALS_QOS) if is_learning(self._law) else None
        self._trial = 0   # index of the current trial (0: the first)
        self._task_pub = None if self._task is None else self.create_publisher(
            ForceControlState, '~/force_control', STREAM_PUB_QOS,
            allow_nan=('position_reference', 'force_reference')) if self._task.is_force else \
            self.create_publisher(CartesianControlState, '~/cartesian_control', STREAM_PUB_QOS)
        self._wrench: tuple[float, np.ndarray] | None = None   # (stamp [s], wrench on the tool)
        self._pending: tuple[np.ndarray, np.ndarray, float] | None = None   # (q, q', t)
        if self._task is not None and self._task.is_force:
            self.create_subscription(WrenchStamped, 'contact_wrench', self._on_wrench,
                                     STREAM_SUB_QOS)
        if self._trials_pub is not None and self._learning_file:
            self._load_learning()
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
        elapsed = t - self._trajectory_start
        if self._trial_period > 0.0:
            trial = int(elapsed / self._trial_period + 1e-9)
            if trial > self._trial:
                self._end_trial(t, trial)
            elapsed -= trial * self._trial_period
        return self._trajectory.sample(elapsed)

    # -- trials (iterative learning, §8.5) ------------------------------------------------
    def _end_trial(self, t: float, trial: int) -> None:
        """Start trial ``trial`` (from 0) at ``t`` [s]: a learning law learns from the last."""
        self._trial = trial
        if self._trials_pub is None:
            self.get_logger().info(f'trial {trial + 1} starts at t = {t:.3f} s')
            return
        law = self._law
        mse = law.end_trial()
        _, feedforward = law.learned_feedforward
        self._trials_pub.publish(learning_trial_message(
            self._law_name, trial, self._trial_period, self._names, mse,
            float(np.max(np.abs(feedforward))) if np.size(feedforward) else 0.0,
            seconds_to_stamp(t)))
        self.get_logger().info(f'trial {trial} ended at t = {t:.3f} s: mean squared error '
                               f'{np.array2string(np.asarray(mse), precision=6)} (8.153)')
        if self._learning_file:
            self._law.save(self._learning_file)

    def _load_learning(self) -> None:
        """Load the learned feed-forward of ``learning_file`` if there (ValueError: refused)."""
        if not os.path.exists(self._learning_file):
            self.get_logger().info(f'{self._learning_file}: not there yet, learning from zero')
            return
        self._law.load(self._learning_file)
        self.get_logger().info(f'learned feed-forward of trial {self._law.trial - 1} loaded '
                               f'from {self._learning_file}')

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
        if self._task is None and self._trajectory is None and self._wait_for_trajectory:
            self.get_logger().info('waiting for a trajectory: state not answered',
                                   throttle_duration_sec=1.0)
            return
        if self._task is not None and self._task.is_force and (
                self._wrench is None or abs(self._wrench[0] - t) > 1e-9):
            self._pending = (q, qd, t)   # answered when the wrench of its stamp arrives
            return
        self._answer(q, qd, t)

    def _on_wrench(self, msg: WrenchStamped) -> None:
        """Keep the contact wrench (a force law); answer the state of its stamp if waiting."""
        w = msg.wrench
        wrench = bounded_array('contact wrench', [w.force.x, w.force.y, w.force.z, w.torque.x,
                                                  w.torque.y, w.torque.z], MAX_FORCE_TORQUE)
        t = stamp_to_seconds(msg.header.stamp)
        self._wrench = (t, wrench)
        if self._pending is not None and abs(self._pending[2] - t) <= 1e-9:
            pending, self._pending = self._pending, None
            self._answer(*pending)

    def _answer(self, q: np.ndarray, qd: np.ndarray, t: float) -> None:
        """Answer the joint state (q, q') stamped ``t`` [s] with one torque command."""
        reason = self._restart_reason(t)
        if reason:
            self.get_logger().warn(f'{reason}: controller reset')
            (self._task or self._law).reset()   # a task law's reference restarts too
            self._previous_time = None
        dt = self._first_period if self._previous_time is None or t == self._previous_time \
            else t - self._previous_time
        self._previous_time = t
        if self._task is not None:
            self._answer_task(q, qd, t, dt)
            return
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
        if self._adaptation_pub is not None:
            self._adaptation_pub.publish(adaptation_message(self._law_name, self._law,
                                                            self._names, state.header.stamp))

    def _answer_task(self, q: np.ndarray, qd: np.ndarray, t: float, dt: float) -> None:
        """Answer with a task-space law: torques, then its telemetry."""
        task = self._task
        assert task is not None and self._task_pub is not None
        wrench = None if self._wrench is None else self._wrench[1]
        tau = task.update(t, JointState(q, qd), wrench, dt)
        self._torque_pub.publish(Float64MultiArray(data=tau.tolist()))
        stamp = seconds_to_stamp(t)
        if task.is_force:
            frame = task.frame
            self._task_pub.publish(force_control_message(
                self._law.telemetry, frame.axis_names, frame.force_controlled, 'task', stamp))
        else:
            self._task_pub.publish(cartesian_control_message(
                self._law_name, self._law.telemetry, task.reference.T_d,
                fkine(self._robot, q), tau, 'link_0', stamp))


def main(args=None) -> None:
    """Run the joint controller until Ctrl-C."""
    run_node(JointControllerNode, args, executor_factory=EventsExecutor)
