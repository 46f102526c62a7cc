"""
Arm simulator node: a manipulator's dynamics integrated at a fixed step; it owns the time.

The plant is :class:`~robotica_sim.simulation.arm.ArmSimulation` (Pinocchio ABA, RK4, book
§5.7): the robot ``robot`` by name or a HEMERO ``dyn_table``, with friction, torque saturation
``tau_max``, joint stops, ``unmodelled_viscous`` friction the controller does not know (App. A)
and a payload grasped at ``payload.time`` (Ej. 8.4). With ``trial_period`` T > 0 the arm is put
back at its initial state every T seconds of simulated time: the trials of iterative learning
(§8.5), each from the same start, in one run. With ``environment.stiffness`` K_e > 0 the end
effector presses on a compliant plane (book §8.7, (8.164)-(8.166): ψ = K_e δ n, τ_e = Jᵀψ;
:mod:`robotica_sim.simulation.compliant_environment`) and ``contact_wrench``
(geometry_msgs/WrenchStamped, frame ``tool0``) carries, every step with the joint states, the
wrench the environment applies to the end effector: what an ideal wrist F/T sensor reads, the
input of ``ft_sensor_emulator``.

Subscribes ``joint_torques`` (std_msgs/Float64MultiArray, one torque [N m] or force [N] per
joint in ``joint_names`` order, as ros2_controllers' effort controllers take them). Publishes
``joint_states`` (sensor_msgs/JointState: position, velocity and the applied effort, stamped
with the simulated time), ``/clock`` and ``~/status``. Pacing and the end of the run:
:class:`~robotica_sim.nodes.stepped_simulator.SteppedSimulatorNode`.

Safe stop: while no valid command newer than ``cmd_timeout`` exists (none yet, a stale one, or
a refused one: wrong size, not finite, beyond ``robotica_kin.bounds.MAX_FORCE_TORQUE``), the
joint brakes hold the arm (velocities zero, positions held); every change of that condition is
logged.
"""
from geometry_msgs.msg import WrenchStamped
import numpy as np
from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter
from robotica_kin.bounds import bounded_array, MAX_FORCE_TORQUE
from robotica_kin.ros.convert import seconds_to_stamp
from robotica_kin.ros.dh_messages import declare_robot
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import COMMAND_QOS, STREAM_PUB_QOS
from robotica_sim.nodes.stepped_simulator import SteppedSimulatorNode
from robotica_sim.simulation.arm import arm_simulation, ARM_SIMULATOR_PARAMETERS
from robotica_sim.simulation.compliant_environment import compliant_plane, ENVIRONMENT_PARAMETERS
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray


class ArmSimulatorNode(SteppedSimulatorNode):
    """Thin ROS shell around :class:`ArmSimulation`; run it with :meth:`run`."""

    def __init__(self) -> None:
        super().__init__('arm_simulator', default_step_period=1e-3,
                         command_topic='joint_torques')
        self._robot = declare_robot(self, 'Built-in robot', dynamics=True,
                                    joint_names='in torque order', joint_limits=True)
        n = self._robot.n
        values = declare_specs(self, ARM_SIMULATOR_PARAMETERS)
        for name, default, description in (
                ('initial_positions', [0.0] * n, 'q(0) [rad | m]'),
                ('initial_velocities', [0.0] * n, "q'(0) [rad/s | m/s]"),
                ('tau_max', Parameter.Type.DOUBLE_ARRAY,
                 'Torque saturation [N m] (1 or n values); default none'),
                ('unmodelled_viscous', Parameter.Type.DOUBLE_ARRAY,
                 'Viscous friction [N m s] per joint unknown to the controller (App. A: 0.1 on '
                 'joint 1); default none')):
            values[name] = declare(self, name, default, description, read_only=True)
        environment = compliant_plane(declare_specs(self, ENVIRONMENT_PARAMETERS))
        self._sim = arm_simulation(self._robot, values, self.step_period, environment)
        self._start = (self._sim.q.copy(), self._sim.qd.copy())
        self._trial_period = declare(
            self, 'trial_period', 0.0, 'Put the arm back at its initial state every trial_period '
            '[s] (trials of iterative learning, §8.5); 0: never', low=0.0, high=1e6,
            read_only=True)
        self._next_trial = self._trial_period
        self._payload_mass = values['payload.mass']
        self._payload_com = values['payload.com']
        self._payload_time = values['payload.time']
        self._cmd_timeout = values['cmd_timeout']
        self._frame = declare(self, 'base_frame_id', 'link_0', 'frame_id of joint_states',
                              read_only=True)
        self._names = list(self._robot.joint_names)
        self._torque: np.ndarray | None = None
        self._torque_time = -np.inf
        self._braking = False
        self._payload_pending = self._payload_mass > 0.0
        self._joints_pub = self.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS)
        self._wrench_pub = None if environment is None else self.create_publisher(
            WrenchStamped, 'contact_wrench', STREAM_PUB_QOS)
        self.create_subscription(Float64MultiArray, 'joint_torques', self._on_torques,
                                 COMMAND_QOS)
        self.get_logger().info(f'robot {self._robot.name!r}, {n} joints {self._names}, '
                               f'step {self.step_period} s')

    @property
    def publishers_to_flush(self) -> list:
        """Return the clock, status and joint-state publishers."""
        return super().publishers_to_flush + [self._joints_pub] + (
            [] if self._wrench_pub is None else [self._wrench_pub])

    # -- callbacks: store and convert only ------------------------------------------------
    def _on_torques(self, msg: Float64MultiArray) -> None:
        self.note_answer()
        torque = bounded_array('torques', msg.data, MAX_FORCE_TORQUE)
        if torque.shape != (self._robot.n,):
            raise ValueError(f'need {self._robot.n} torques, got {torque.size}')
        self._torque = torque
        self._torque_time = self.sim_time

    def on_callback_error(self, source: str) -> None:
        """Brake: a refused command (wrong size, not finite, beyond the bounds) holds the arm."""
        self._torque = None

    # -- the plant ------------------------------------------------------------------------
    def publish_plant(self, t: float) -> None:
        """Publish the joint positions, velocities and applied torques at time ``t`` [s]."""
        msg = JointState(name=self._names, position=self._sim.q.tolist(),
                         velocity=self._sim.qd.tolist(),
                         effort=self._sim.applied_torque.tolist())
        msg.header.stamp = seconds_to_stamp(t)
        msg.header.frame_id = self._frame
        self._joints_pub.publish(msg)
        if self._wrench_pub is not None:
            wrench = WrenchStamped()
            wrench.header.stamp = msg.header.stamp
            wrench.header.frame_id = 'tool0'
            f = self._sim.contact_wrench().on_tool()
            w = wrench.wrench
            w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z = f.tolist()
            self._wrench_pub.publish(wrench)

    def step_plant(self) -> None:
        """Advance the arm one step with the newest torque, or with the brakes on."""
        t = self.sim_time
        if self._payload_pending and t >= self._payload_time - 1e-12:
            self._sim.add_payload(self._payload_mass, self._payload_com)
            self._payload_pending = False
            self.get_logger().info(f'payload of {self._payload_mass} kg grasped at t = {t:.3f} s')
        braking = self._torque is None or t - self._torque_time > self._cmd_timeout + 1e-12
        if braking != self._braking:
            if braking:
                self.get_logger().warn(f'no valid command newer than {self._cmd_timeout} s at '
                                       f't = {t:.3f} s: brakes on')
            else:
                self.get_logger().info(f'commands at t = {t:.3f} s: brakes off')
            self._braking = braking
        if braking:
            self.stale_steps += 1
            self._sim.step_braked()
        else:
            self._sim.step(self._torque)
        if 0.0 < self._next_trial <= t + self.step_period + 1e-9:
            self._sim.reset(*self._start)
            self._next_trial += self._trial_period
            self.get_logger().info(f'trial ends at t = {t + self.step_period:.3f} s: arm back at '
                                   'its initial state')


def main(args=None) -> None:
    """Run the arm simulator until its end time or Ctrl-C."""
    run_node(ArmSimulatorNode, args, run=ArmSimulatorNode.run, executor_factory=EventsExecutor)
