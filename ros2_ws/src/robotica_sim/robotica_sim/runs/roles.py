"""
The roles a user's own node can take in a run, and the contract of each (docs/your_node.md).

A role is a part of a run that robotica fills with its own node unless the scenario names a
command instead (``tracker: {external: {command: [python3, my_tracker.py]}}``): the mobile
``tracker``, the ``estimator`` (the odometry) and the arm's ``joint_controller``. The contract
says what the run gives the node and what it expects back: the topics in and out (relative names,
resolved in the run's root namespace; ``~/`` names under the node name the run gives it), their
types and QoS, and which input each step's answer replies to. :func:`role_contract` returns it
for a scenario (a steered vehicle's tracker answers on ``vehicle_command``); ``robotica run``
checks a user's node against it (:mod:`robotica_sim.cli.run`), and ``robotica new`` writes a
template that keeps it.

Pure data: no rclpy here.
"""
from dataclasses import dataclass, replace

__all__ = ['ROLES', 'ROLE_SECTIONS', 'Role', 'Topic', 'role_contract', 'topic_name']

STREAM = 'stream'
"""QoS of a stream: published reliable, transient local, keep last 500 (a reliable, volatile
subscription of any depth matches it)."""
LATCHED = 'latched'
"""QoS of latched data: reliable, transient local, keep last 1; the subscription must ask for
transient local too, else a node that starts after the publisher never gets it."""
COMMAND = 'command'
"""QoS of a command: reliable, volatile (the consumer keeps the newest only)."""


@dataclass(frozen=True)
class Topic:
    """One topic of a contract: its name as the user's node uses it, type, QoS and meaning."""

    name: str                     # relative ('odom'), absolute ('/clock') or private ('~/x')
    type: str   # noqa: A003 (the ROS type name, 'nav_msgs/msg/Odometry')
    qos: str                      # STREAM, LATCHED or COMMAND
    description: str
    required: bool = True         # an input the node must read, or an output it must publish

    def line(self) -> str:
        """
        Return the topic as one line of a contract: name (type, QoS).

        >>> Topic('odom', 'nav_msgs/msg/Odometry', STREAM, 'the pose').line()
        'odom (nav_msgs/msg/Odometry, stream)'
        """
        optional = '' if self.required else ', optional'
        return f'{self.name} ({self.type}, {self.qos}{optional})'


@dataclass(frozen=True)
class Role:
    """A role of a run: the node it replaces and its contract."""

    name: str                     # 'tracker'
    section: str                  # the scenario section that names the command
    node_name: str                # the name the run gives the node (-r __node:=...)
    kind: str                     # 'mobile' or 'manipulator'
    inputs: tuple[Topic, ...]
    outputs: tuple[Topic, ...]
    answers: str                  # the input each lockstep step's answer replies to
    answer: str                   # the output that answers it (first of the required outputs)
    summary: str

    def text(self) -> str:
        """Return the contract on one line, as run messages quote it."""
        ins = ', '.join(t.line() for t in self.inputs)
        outs = ', '.join(t.line() for t in self.outputs)
        return (f'in: {ins}; out: {outs}; in lockstep it answers each {self.answers} message '
                f'with exactly one {self.answer}')

    @property
    def topics(self) -> tuple[Topic, ...]:
        """Return every topic of the contract, inputs first."""
        return self.inputs + self.outputs


def topic_name(name: str, node_name: str) -> str:
    """
    Return the absolute name of a contract topic for a node named ``node_name`` in ``/``.

    >>> topic_name('odom', 'path_tracker'), topic_name('~/tracking_error', 'path_tracker')
    ('/odom', '/path_tracker/tracking_error')
    """
    if name.startswith('~/'):
        return f'/{node_name}/{name[2:]}'
    return name if name.startswith('/') else f'/{name}'


_POSE = Topic('odom', 'nav_msgs/msg/Odometry', STREAM,
              'the estimated pose (pose in odom, twist in base_link; REP-105), once per step')
_PATH = Topic('path', 'nav_msgs/msg/Path', LATCHED,
              'the reference path in odom, published once; poses with increasing stamps are a '
              'trajectory')
_TRUTH = Topic('ground_truth/odom', 'nav_msgs/msg/Odometry', STREAM,
               "the simulator's true pose (in map), for a tracker that is allowed to read it",
               required=False)
_TRACKING_ERROR = Topic('~/tracking_error', 'robotica_msgs/msg/TrackingError', STREAM,
                        'cross-track and heading errors, stamped with the pose; recorded',
                        required=False)
_TWIST = Topic('cmd_vel', 'geometry_msgs/msg/Twist', COMMAND,
               'the velocity command [m/s, rad/s] in base_link, one per pose')
_STEERING = Topic('vehicle_command', 'robotica_msgs/msg/VehicleCommand', COMMAND,
                  'guide-point speed [m/s] and steering angle [rad], one per pose')

ROLES: dict[str, Role] = {
    'tracker': Role(
        'tracker', 'tracker', 'path_tracker', 'mobile', (_POSE, _PATH, _TRUTH),
        (_TWIST, _TRACKING_ERROR), 'odom', 'cmd_vel',
        'follows the reference path: the pose in, a velocity command out (book ch. 9)'),
    'estimator': Role(
        'estimator', 'odometry', 'odometry', 'mobile', (
            Topic('wheel_encoders', 'robotica_msgs/msg/WheelEncoders', STREAM,
                  'cumulative ticks of the left and right wheels, once per step'),
            Topic('imu/data', 'sensor_msgs/msg/Imu', STREAM,
                  'the gyro (when the scenario enables it)', required=False),
            Topic('compass/heading', 'sensor_msgs/msg/Imu', STREAM,
                  'the compass heading (when enabled)', required=False),
            Topic('gps/fix', 'sensor_msgs/msg/NavSatFix', STREAM,
                  'GPS fixes at a few hertz (when enabled)', required=False)),
        (Topic('odom', 'nav_msgs/msg/Odometry', STREAM,
               'the estimate, stamped with the reading it answers (pose in odom, twist in '
               'base_link)'),),
        'wheel_encoders', 'odom',
        'dead reckoning and fusion: encoder ticks (and gyro, compass, GPS) in, odom out '
        '(book §4.7.5, ch. 7)'),
    'joint_controller': Role(
        'joint_controller', 'controller', 'joint_controller', 'manipulator', (
            Topic('joint_states', 'sensor_msgs/msg/JointState', STREAM,
                  'positions [rad | m], velocities and applied efforts, once per step'),
            Topic('~/joint_trajectory', 'trajectory_msgs/msg/JointTrajectory', LATCHED,
                  'the joint reference, published once')),
        (Topic('joint_torques', 'std_msgs/msg/Float64MultiArray', COMMAND,
               'one torque [N m] or force [N] per joint, in joint_names order, one per state'),
         Topic('~/controller_state', 'robotica_msgs/msg/JointControllerState', STREAM,
               'reference, error and torque, stamped with the state; recorded',
               required=False)),
        'joint_states', 'joint_torques',
        'closes the arm loop: joint states in, joint torques out (book ch. 8)'),
}
"""The roles, by the name ``robotica new`` takes."""

ROLE_SECTIONS = {role.section: role for role in ROLES.values()}
"""The roles by the scenario section whose ``external`` key names a user's command."""


def role_contract(name: str, steered: bool = False) -> Role:
    """
    Return the contract of role ``name`` (a key of :data:`ROLES`).

    ``steered``: the vehicle is steered (tricycle, bicycle, Ackermann); its tracker answers on
    ``vehicle_command`` instead of ``cmd_vel``.

    >>> role_contract('tracker', steered=True).answer
    'vehicle_command'

    Raises
    ------
    ValueError
        If there is no such role; the message lists the roles.

    """
    if name not in ROLES:
        raise ValueError(f'no role {name!r}; the roles: {", ".join(ROLES)}')
    role = ROLES[name]
    if name != 'tracker' or not steered:
        return role
    return replace(role, answer=_STEERING.name,
                   outputs=tuple(_STEERING if t is _TWIST else t for t in role.outputs))
