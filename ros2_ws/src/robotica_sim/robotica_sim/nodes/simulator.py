"""
Simulator node: a differential-drive robot integrated at a fixed step; it owns the time.

Subscribes ``cmd_vel`` (geometry_msgs/Twist). Publishes ``/clock``, the ground truth
``ground_truth/odom`` (nav_msgs/Odometry, pose in ``world_frame_id``, twist in ``base_frame_id``),
the wheel angles on ``joint_states`` (for the encoder emulator) and ``~/status``
(robotica_msgs/SimulatorStatus). Service ``~/start`` (std_srvs/Trigger) starts the run when
``autostart`` is false. Pacing (``realtime`` or ``lockstep``) and the end of the run are those of
:class:`~robotica_sim.nodes.stepped_simulator.SteppedSimulatorNode`. A command older than
``cmd_timeout`` brakes the robot.
"""
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from robotica_kin.mobile.differential_drive import DifferentialDriveParams
from robotica_kin.nodes.convert import odometry_message, seconds_to_stamp
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_kin.nodes.qos import COMMAND_QOS, STREAM_PUB_QOS
from robotica_sim.diff_drive_simulation import DiffDriveSimulation, SimulationParams
from robotica_sim.nodes.stepped_simulator import SteppedSimulatorNode
from sensor_msgs.msg import JointState


class SimulatorNode(SteppedSimulatorNode):
    """Thin ROS shell around :class:`DiffDriveSimulation`; run it with :meth:`run`."""

    def __init__(self) -> None:
        super().__init__('simulator', default_step_period=0.02, command_topic='cmd_vel')
        robot = DifferentialDriveParams(
            wheel_radius=declare(self, 'robot.wheel_radius', 0.1,
                                 'Wheel radius c [m], book (4.109)', low=1e-3, high=10.0,
                                 read_only=True),
            wheel_separation=declare(self, 'robot.wheel_separation', 0.4,
                                     'Track b between the drive wheels [m], book (4.110)',
                                     low=1e-3, high=100.0, read_only=True))
        pose = [declare(self, 'initial_pose.' + k, 0.0, d, low=-1e6, high=1e6, read_only=True)
                for k, d in (('x', 'Initial x [m], world frame'),
                             ('y', 'Initial y [m], world frame'),
                             ('theta', 'Initial heading [rad], REP-103 (from the x axis)'))]
        params = SimulationParams(
            step_period=self.step_period,
            rk4_substeps=declare(self, 'rk4_substeps', 1, 'RK4 integration steps per step',
                                 low=1, high=1000, read_only=True),
            cmd_timeout=declare(self, 'cmd_timeout', 0.5,
                                'A command older than this [s, simulated] brakes the robot',
                                low=1e-3, high=60.0, read_only=True))
        self._world_frame = declare(self, 'world_frame_id', 'map',
                                    'Frame of the ground-truth pose', read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link',
                                   'Frame of the robot body', read_only=True)
        self._joint_names = [
            declare(self, 'left_wheel_joint', 'left_wheel_joint', 'Left wheel joint name',
                    read_only=True),
            declare(self, 'right_wheel_joint', 'right_wheel_joint', 'Right wheel joint name',
                    read_only=True)]
        self._sim = DiffDriveSimulation(robot, params, pose)
        self._truth_pub = self.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
        self._joints_pub = self.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS)
        self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, COMMAND_QOS)
        self._was_stale = False

    @property
    def publishers_to_flush(self) -> list:
        """Return the clock, status, ground-truth and joint-state publishers."""
        return super().publishers_to_flush + [self._truth_pub, self._joints_pub]

    # -- callbacks: store and convert only ------------------------------------------------
    def _on_cmd_vel(self, msg: Twist) -> None:
        self.note_answer()
        try:
            self._sim.set_command(msg.linear.x, msg.angular.z, self._sim.t)
        except ValueError as err:
            self._sim.set_command(0.0, 0.0, self._sim.t)
            self.get_logger().warn(f'refused command ({err}); braking',
                                   throttle_duration_sec=1.0)

    # -- the plant ------------------------------------------------------------------------
    def publish_plant(self, t: float) -> None:
        """Publish the ground truth and the wheel angles at time ``t`` [s]."""
        stamp = seconds_to_stamp(t)
        self._truth_pub.publish(odometry_message(t, self._world_frame, self._base_frame,
                                                 self._sim.pose, self._sim.twist))
        joints = JointState(name=self._joint_names,
                            position=[float(a) for a in self._sim.wheel_angles],
                            velocity=[float(w) for w in self._sim.wheel_speeds])
        joints.header.stamp = stamp
        joints.header.frame_id = self._base_frame
        self._joints_pub.publish(joints)

    def step_plant(self) -> None:
        """Advance the robot one step; brake (and log the change) when the command is stale."""
        stale = self._sim.command_is_stale()
        if stale:
            self.stale_steps += 1
        if stale != self._was_stale and self._sim.step_count > 0:
            if stale:
                self.get_logger().warn(f'command stale at t = {self._sim.t:.3f} s: braking')
            else:
                self.get_logger().info(f'commands resumed at t = {self._sim.t:.3f} s')
        self._was_stale = stale
        self._sim.step()


def main(args=None) -> None:
    """Run the simulator node until its end time or Ctrl-C."""
    run_node(SimulatorNode, args, run=SimulatorNode.run)
