"""
Simulator node: a differential-drive robot integrated at a fixed step; it owns the time.

Subscribes ``cmd_vel`` (geometry_msgs/Twist). Publishes ``/clock``, the ground truth
``ground_truth/odom`` (nav_msgs/Odometry, pose in ``world_frame_id``, twist in ``base_frame_id``),
the wheel angles on ``joint_states`` (for the encoder emulator) and ``~/status``
(robotica_msgs/SimulatorStatus). Service ``~/start`` (std_srvs/Trigger) starts the run when
``autostart`` is false.

Pacing (DESIGN.md, time and recording):

* ``realtime``: one step per ``step_period`` of wall-clock time.
* ``lockstep``: as fast as possible; step k+1 starts when a command has answered step k, or after
  ``lockstep.timeout`` wall-clock seconds (counted in ``lockstep_timeouts`` and logged). Until the
  first answer, step 0 is published again every ``lockstep.timeout`` (discovery of the control loop
  may still be going on), for at most ``lockstep.start_timeout``; then the node gives up.

At ``end_time`` the node publishes a final status and exits with code 0.
"""
import math
import time

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.duration import Duration
from rclpy.executors import Executor
from rclpy.node import Node
from robotica_kin.mobile.differential_drive import DifferentialDriveParams
from robotica_kin.nodes.convert import odometry_message, seconds_to_stamp
from robotica_kin.nodes.entry_point import run_node
from robotica_kin.nodes.parameters import declare
from robotica_kin.nodes.qos import COMMAND_QOS, STREAM_PUB_QOS
from robotica_msgs.msg import SimulatorStatus
from robotica_sim.diff_drive_simulation import DiffDriveSimulation, SimulationParams
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger

PACING_MODES = ('realtime', 'lockstep')


class SimulatorNode(Node):
    """Thin ROS shell around :class:`DiffDriveSimulation`; run it with :meth:`run`."""

    def __init__(self) -> None:
        super().__init__('simulator')
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
            step_period=declare(self, 'step_period', 0.02,
                                'Simulated time per step [s] (publishing period)',
                                low=1e-4, high=1.0, read_only=True),
            rk4_substeps=declare(self, 'rk4_substeps', 1, 'RK4 integration steps per step',
                                 low=1, high=1000, read_only=True),
            cmd_timeout=declare(self, 'cmd_timeout', 0.5,
                                'A command older than this [s, simulated] brakes the robot',
                                low=1e-3, high=60.0, read_only=True))
        self._pacing = declare(self, 'pacing', 'realtime',
                               'realtime (wall-clock paced) or lockstep (as fast as the '
                               'controller answers)', read_only=True)
        if self._pacing not in PACING_MODES:
            raise ValueError(f'pacing must be one of {PACING_MODES}, got {self._pacing!r}')
        self._lockstep_timeout = declare(
            self, 'lockstep.timeout', 1.0,
            'Wall-clock seconds to wait for the answer to a step before going on',
            low=1e-3, high=60.0, read_only=True)
        self._start_timeout = declare(
            self, 'lockstep.start_timeout', 30.0,
            'Wall-clock seconds to wait for the first answer (discovery) before giving up',
            low=0.1, high=600.0, read_only=True)
        self._end_time = declare(self, 'end_time', 0.0,
                                 'Simulated time [s] at which the run ends; 0: never',
                                 low=0.0, high=1e7, read_only=True)
        self._autostart = declare(self, 'autostart', True,
                                  'Start stepping at once (else wait for ~/start)',
                                  read_only=True)
        self._status_period = declare(self, 'status_period', 1.0,
                                      'Period of ~/status [s, simulated]', low=1e-3, high=1e3,
                                      read_only=True)
        self._world_frame = declare(self, 'world_frame_id', 'map',
                                    'Frame of the ground-truth pose', read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link',
                                   'Frame of the robot body', read_only=True)
        self._joint_names = [
            declare(self, 'left_wheel_joint', 'left_wheel_joint', 'Left wheel joint name',
                    read_only=True),
            declare(self, 'right_wheel_joint', 'right_wheel_joint', 'Right wheel joint name',
                    read_only=True)]
        self._step_period = params.step_period
        self._sim = DiffDriveSimulation(robot, params, pose)

        self._clock_pub = self.create_publisher(Clock, '/clock', STREAM_PUB_QOS)
        self._truth_pub = self.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
        self._joints_pub = self.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS)
        self._status_pub = self.create_publisher(SimulatorStatus, '~/status', STREAM_PUB_QOS)
        self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, COMMAND_QOS)
        self.create_service(Trigger, '~/start', self._on_start)
        self._started = False
        self._answers = 0
        self._timeouts = 0
        self._stale_steps = 0
        self._was_stale = False
        self._next_status = 0.0
        self._wall_start = 0.0

    # -- callbacks: store and convert only ------------------------------------------------
    def _on_cmd_vel(self, msg: Twist) -> None:
        self._answers += 1
        try:
            self._sim.set_command(msg.linear.x, msg.angular.z, self._sim.t)
        except ValueError as err:
            self._sim.set_command(0.0, 0.0, self._sim.t)
            self.get_logger().warn(f'refused command ({err}); braking',
                                   throttle_duration_sec=1.0)

    def _on_start(self, request: Trigger.Request, response: Trigger.Response
                  ) -> Trigger.Response:
        response.success = not self._started
        response.message = 'started' if not self._started else 'already running'
        self._started = True
        return response

    # -- publishing -----------------------------------------------------------------------
    def _publish_state(self) -> None:
        t = self._sim.t
        stamp = seconds_to_stamp(t)
        self._clock_pub.publish(Clock(clock=stamp))
        self._truth_pub.publish(odometry_message(t, self._world_frame, self._base_frame,
                                                 self._sim.pose, self._sim.twist))
        joints = JointState(name=self._joint_names,
                            position=[float(a) for a in self._sim.wheel_angles],
                            velocity=[float(w) for w in self._sim.wheel_speeds])
        joints.header.stamp = stamp
        joints.header.frame_id = self._base_frame
        self._joints_pub.publish(joints)
        if t >= self._next_status - 1e-9:
            self._publish_status(finished=False)
            self._next_status += self._status_period

    def _publish_status(self, finished: bool) -> None:
        wall = time.monotonic() - self._wall_start
        status = SimulatorStatus(step=self._sim.step_count, lockstep_timeouts=self._timeouts,
                                 stale_command_stops=self._stale_steps, finished=finished,
                                 real_time_factor=self._sim.t / wall if wall > 0 else 0.0)
        status.header.stamp = seconds_to_stamp(self._sim.t)
        self._status_pub.publish(status)

    # -- the stepping loop ------------------------------------------------------------------
    def _spin_until(self, executor: Executor, done, deadline: float) -> bool:
        """Spin until ``done()`` or the wall-clock ``deadline``; return ``done()``."""
        while not done():
            remaining = deadline - time.monotonic()
            if remaining <= 0.0:
                break
            executor.spin_once(timeout_sec=min(remaining, 1.0))
        return done()

    def _wait_for_first_answer(self, executor: Executor) -> bool:
        give_up = time.monotonic() + self._start_timeout
        while time.monotonic() < give_up:
            seen = self._answers
            self._publish_state()
            deadline = min(give_up, time.monotonic() + self._lockstep_timeout)
            if self._spin_until(executor, lambda: self._answers > seen, deadline):
                return True
            self.get_logger().info('waiting for the controller to answer step 0 on cmd_vel',
                                   throttle_duration_sec=5.0)
        return False

    def run(self, executor: Executor) -> int:
        """Step until ``end_time`` (or shutdown); return the process exit code."""
        self._spin_until(executor, lambda: self._started or self._autostart, math.inf)
        self.get_logger().info(f'started: pacing {self._pacing}, step {self._step_period} s, '
                               f'end time {self._end_time or "none"} s')
        self._wall_start = time.monotonic()
        lockstep = self._pacing == 'lockstep'
        if lockstep:
            if not self._wait_for_first_answer(executor):
                self.get_logger().error(
                    f'no command on cmd_vel within {self._start_timeout} s: is a controller '
                    'running and connected? Stopping.')
                return 1
        else:
            self._publish_state()
        while self._end_time == 0.0 or self._sim.t < self._end_time - 1e-9:
            if lockstep:
                seen = self._answers
            else:
                target = self._wall_start + (self._sim.step_count + 1) * self._step_period
                self._spin_until(executor, lambda: False, target)
            self._step_once()
            self._publish_state()
            if lockstep:
                deadline = time.monotonic() + self._lockstep_timeout
                if not self._spin_until(executor, lambda: self._answers > seen, deadline):
                    self._timeouts += 1
                    self.get_logger().warn(
                        f'lockstep: no answer to step {self._sim.step_count} within '
                        f'{self._lockstep_timeout} s ({self._timeouts} so far)',
                        throttle_duration_sec=1.0)
        self._publish_status(finished=True)
        for pub in (self._clock_pub, self._truth_pub, self._joints_pub, self._status_pub):
            pub.wait_for_all_acked(Duration(seconds=2.0))
        wall = time.monotonic() - self._wall_start
        self.get_logger().info(
            f'finished at t = {self._sim.t:.3f} s after {self._sim.step_count} steps in '
            f'{wall:.2f} s wall (real-time factor {self._sim.t / max(wall, 1e-9):.1f}); '
            f'lockstep timeouts {self._timeouts}, stale-command steps {self._stale_steps}')
        return 0

    def _step_once(self) -> None:
        stale = self._sim.command_is_stale()
        if stale:
            self._stale_steps += 1
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
