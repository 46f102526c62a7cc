"""
Simulator node: any wheeled vehicle of the book integrated at a fixed step; it owns the time.

The configuration is the parameter ``vehicle.type`` (one of
:data:`robotica_kin.mobile.vehicles.VEHICLE_TYPES`). Twist-driven vehicles (differential,
synchronous, skid steer, omnidirectional, mecanum) subscribe ``cmd_vel``: geometry_msgs/Twist,
or with ``enable_stamped_cmd_vel`` (Nav2's name; Jazzy's diff_drive_controller takes only the
stamped one) geometry_msgs/TwistStamped, whose ``header.frame_id`` must be ``base_frame_id``;
steered ones (tricycle, bicycle, Ackermann) subscribe ``vehicle_command``
(robotica_msgs/VehicleCommand: guide-point speed and steering angle). Publishes ``/clock``, the
ground truth ``ground_truth/odom`` (nav_msgs/Odometry, pose in ``world_frame_id``, twist in
``base_frame_id``), the same pose as the transform ``world_frame_id`` -> ``truth_frame_id`` on
``/tf`` (so that a viewer shows the truth beside the estimate's ``base_link``; '': none), the
odometry wheels' angles and rates and the steering angles on ``joint_states`` (for the encoder
emulator and the state publisher: the joint names of the vehicle's URDF,
``VehicleKinematics.odometry_wheel_joints``), each stamped with the sim time of its step, and
``~/status`` (robotica_msgs/SimulatorStatus).

With ``world_file`` (a map_server map, or a YAML file with a ``world:`` section such as the run's
scenario: :func:`robotica_kin.world.world_file.load_world_file`; '' = no world, the behaviour
without obstacles), the vehicle's footprint (``footprint.radius`` or ``footprint.polygon``,
default the outline a viewer draws) stops where it touches an obstacle
(:mod:`robotica_sim.simulation.contact`), and every step is reported on ``bumper``
(robotica_msgs/Contact: in contact or not, the contact point and normal, the contacts so far
and the time in contact). A new type because no standard one carries a contact: common_interfaces
has no bumper message, and Gazebo's ``ros_gz_interfaces/Contacts`` (or ``gazebo_msgs``) is
Gazebo's, lists collision bodies and has no notion of a contact's start; a PointStamped would
not say when the robot is free. ``~/status`` counts the contacts and the time in contact. A
world file that cannot be read, or an initial pose inside an obstacle, ends the node (exit 2)
with one line.
Service ``~/start`` (std_srvs/Trigger) starts the run when ``autostart`` is false. Pacing
(``realtime`` or ``lockstep``) and the end of the run are those of
:class:`~robotica_sim.nodes.stepped_simulator.SteppedSimulatorNode`. A command older than
``cmd_timeout`` stops the vehicle, and the node logs it; a command that is not finite or beyond
the physical bounds (:mod:`robotica_kin.bounds`), or a TwistStamped in another frame, is refused,
logged, and stops it at once.
"""
import math

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.experimental import EventsExecutor
from robotica_kin.mobile.vehicles import STEERED_TYPES
from robotica_kin.ros.convert import odometry_message, planar_transform, seconds_to_stamp
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import COMMAND_QOS, STREAM_PUB_QOS, TF_QOS
from robotica_kin.world.world_file import load_world_file
from robotica_msgs.msg import Contact, VehicleCommand
from robotica_sim.nodes.stepped_simulator import SteppedSimulatorNode
from robotica_sim.simulation.vehicle import SIMULATOR_PARAMETERS, vehicle_simulation
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage


class SimulatorNode(SteppedSimulatorNode):
    """Thin ROS shell around :class:`VehicleSimulation`; run it with :meth:`run`."""

    def __init__(self) -> None:
        super().__init__('simulator', default_step_period=0.02, command_topic='cmd_vel')
        params = declare_specs(self, SIMULATOR_PARAMETERS)
        world_file = declare(self, 'world_file', '',
                             'The obstacles: a map_server map or a YAML file with a world: '
                             "section (a scenario); '': none", read_only=True)
        world = load_world_file(world_file) if world_file else None   # WorldError: exit 2
        self._sim = vehicle_simulation(params, self.step_period, world)
        self.contacts = self._sim.contacts   # 1 when it starts touching
        vehicle_type = params['vehicle.type']
        self._steered = vehicle_type in STEERED_TYPES
        if self._steered:
            self._command_topic = 'vehicle_command'
        self._world_frame = declare(self, 'world_frame_id', 'map',
                                    'Frame of the ground-truth pose', read_only=True)
        self._base_frame = declare(self, 'base_frame_id', 'base_link',
                                   'Frame of the robot body', read_only=True)
        self._truth_frame = declare(self, 'truth_frame_id', 'base_link_truth',
                                    'Frame of the true pose on /tf, child of world_frame_id; '
                                    "'': not published", read_only=True)
        stamped = declare(self, 'enable_stamped_cmd_vel', False,
                          'cmd_vel is geometry_msgs/TwistStamped (in base_frame_id), else Twist',
                          read_only=True)
        self._wheel_joints = list(self._sim.kinematics.odometry_wheel_joints)
        self._truth_pub = self.create_publisher(Odometry, 'ground_truth/odom', STREAM_PUB_QOS)
        self._tf_pub = (self.create_publisher(TFMessage, '/tf', TF_QOS) if self._truth_frame
                        else None)
        self._joints_pub = self.create_publisher(JointState, 'joint_states', STREAM_PUB_QOS,
                                                 allow_nan=('velocity',))
        self._bumper_pub = None if world is None else self.create_publisher(
            Contact, 'bumper', STREAM_PUB_QOS,
            allow_nan=tuple(f'{f}.{a}' for f in ('point', 'normal') for a in 'xyz'))
        if self._steered:
            self.create_subscription(VehicleCommand, 'vehicle_command', self._on_vehicle_command,
                                     COMMAND_QOS)
        elif stamped:
            self.create_subscription(TwistStamped, 'cmd_vel', self._on_cmd_vel_stamped,
                                     COMMAND_QOS)
        else:
            self.create_subscription(Twist, 'cmd_vel', self._on_cmd_vel, COMMAND_QOS)
        self._was_stale = False
        self.get_logger().info(f'vehicle {vehicle_type!r} ({self._sim.kinematics.geometry}), '
                               f'commands on {self._command_topic}')

    # -- callbacks: store and convert only ------------------------------------------------
    def _take(self, command: tuple[float, float, float]) -> None:
        self.note_answer()
        self._sim.set_command(command, self._sim.t)   # a refused one: the guard brakes

    def on_callback_error(self, source: str) -> None:
        """Brake: a refused command (not finite, beyond the bounds) stops the vehicle."""
        self._sim.stop()

    def _on_cmd_vel(self, msg: Twist) -> None:
        self._take((msg.linear.x, msg.linear.y, msg.angular.z))

    def _on_cmd_vel_stamped(self, msg: TwistStamped) -> None:
        if msg.header.frame_id != self._base_frame:   # refused: the guard brakes
            raise ValueError(f'TwistStamped in frame {msg.header.frame_id[:100]!r}, not '
                             f'{self._base_frame!r}')
        self._on_cmd_vel(msg.twist)

    def _on_vehicle_command(self, msg: VehicleCommand) -> None:
        self._take((msg.speed, msg.steering_angle, 0.0))

    # -- the plant ------------------------------------------------------------------------
    def publish_plant(self, t: float) -> None:
        """Publish the ground truth and the wheel and steering angles at time ``t`` [s]."""
        stamp = seconds_to_stamp(t)
        joints = JointState(name=list(self._wheel_joints),
                            position=[float(a) for a in self._sim.wheel_angles],
                            velocity=[float(w) for w in self._sim.wheel_rates])
        for name, angle in self._sim.joint_positions().items():
            joints.name.append(name)
            joints.position.append(angle)
            joints.velocity.append(math.nan)   # not simulated: the steering rate is not known
        joints.header.stamp = stamp
        joints.header.frame_id = self._base_frame
        self._joints_pub.publish(joints)
        self._truth_pub.publish(odometry_message(t, self._world_frame, self._base_frame,
                                                 self._sim.pose, self._sim.twist))
        if self._tf_pub is not None:
            self._tf_pub.publish(TFMessage(transforms=[planar_transform(
                t, self._world_frame, self._truth_frame, self._sim.pose)]))
        if self._bumper_pub is not None:
            self._bumper_pub.publish(self._bumper(stamp))

    def _bumper(self, stamp) -> Contact:
        sim = self._sim
        msg = Contact(in_contact=sim.in_contact, contacts=sim.contacts,
                      time_in_contact=sim.time_in_contact)
        msg.header.stamp = stamp
        msg.header.frame_id = self._world_frame
        z = 0.0 if sim.in_contact else math.nan   # x, y are NaN too when free
        msg.point.x, msg.point.y = (float(v) for v in sim.contact_point)
        msg.normal.x, msg.normal.y = (float(v) for v in sim.contact_normal)
        msg.point.z = msg.normal.z = z
        return msg

    def step_plant(self) -> None:
        """Advance the vehicle one step; stop it (and log the change) when the command is stale."""
        stale = self._sim.command_is_stale()
        if stale:
            self.stale_steps += 1
        if stale != self._was_stale and self._sim.step_count > 0:
            if stale:
                self.get_logger().warn(
                    f'command stale (none newer than {self._sim.params.cmd_timeout} s) at '
                    f't = {self._sim.t:.3f} s: stopping')
            else:
                self.get_logger().info(f'commands resumed at t = {self._sim.t:.3f} s')
        self._was_stale = stale
        was_touching = self._sim.in_contact
        self._sim.step()
        self.contacts, self.time_in_contact = self._sim.contacts, self._sim.time_in_contact
        if self._sim.in_contact and not was_touching:
            x, y = (float(v) for v in self._sim.contact_point)
            self.get_logger().warn(f'contact at t = {self._sim.t:.3f} s, at ({x:.3f}, {y:.3f}) '
                                   f'm: stopped ({self._sim.contacts} so far)')


def main(args=None) -> None:
    """Run the simulator node until its end time or Ctrl-C."""
    run_node(SimulatorNode, args, run=SimulatorNode.run, executor_factory=EventsExecutor)
