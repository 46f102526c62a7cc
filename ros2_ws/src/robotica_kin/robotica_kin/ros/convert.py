"""
Conversions between ROS 2 messages and the NumPy values of the robotica cores.

Planar poses are ``(x, y, theta)`` arrays [m, m, rad] in REP-103 (heading from the x axis,
counter-clockwise); times are float seconds. Used by the nodes of every robotica package.
"""
from collections import Counter
import math
import struct
from typing import Sequence

from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import PoseStamped, Quaternion, TransformStamped
from nav_msgs.msg import Odometry, Path
import numpy as np
from numpy.typing import ArrayLike, NDArray
from sensor_msgs.msg import JointState


NANOSECONDS_PER_SECOND = 1_000_000_000
_PLURALS = {'position': 'positions', 'velocity': 'velocities', 'effort': 'efforts'}


def seconds(sec: int, nanosec: int) -> float:
    """
    Return the float seconds of a stamp's ``sec`` and ``nanosec``, or raise ValueError.

    ``nanosec`` must lie in [0, 1e9) (builtin_interfaces/Time and Duration): a stamp with more is
    malformed, not a later time (``nanosec = 2**32 - 1`` would move it 4.3 s on).

    >>> seconds(12, 500_000_000)
    12.5
    >>> seconds(12, 1_000_000_000)
    Traceback (most recent call last):
    ...
    ValueError: stamp nanosec must be in [0, 1e9), got 1000000000 (sec 12)
    """
    if not 0 <= nanosec < NANOSECONDS_PER_SECOND:
        raise ValueError(f'stamp nanosec must be in [0, 1e9), got {nanosec} (sec {sec})')
    return sec + nanosec * 1e-9


def header_stamp(data: bytes) -> float:
    """
    Return the stamp [s] that opens a serialized message, or raise ValueError.

    The message's first field is a std_msgs/Header (its stamp first) or a
    builtin_interfaces/Time (rosgraph_msgs/Clock). ``data`` is CDR with its 4-byte encapsulation
    header (byte 1: 1 little-, 0 big-endian); the stamp's ``int32 sec`` and ``uint32 nanosec``
    follow it. Reading it costs about a microsecond, against some 20 for deserializing.
    """
    sec, nanosec = struct.unpack_from('<iI' if data[1] == 1 else '>iI', data, 4)
    return seconds(sec, nanosec)


def stamp_to_seconds(stamp: Time | Duration) -> float:
    """Return a ``builtin_interfaces/Time`` (or ``Duration``) as float seconds (see seconds)."""
    return seconds(stamp.sec, stamp.nanosec)


def seconds_to_stamp(t: float, kind: type = Time) -> Time:
    """
    Return float seconds ``t`` >= 0 as a ``builtin_interfaces/Time`` (rounded to 1 ns).

    ``kind=Duration`` gives a ``builtin_interfaces/Duration`` (e.g. ``time_from_start``).

    >>> seconds_to_stamp(1.5)
    builtin_interfaces.msg.Time(sec=1, nanosec=500000000)
    """
    ns = round(t * 1e9)
    return kind(sec=ns // NANOSECONDS_PER_SECOND, nanosec=ns % NANOSECONDS_PER_SECOND)


def joint_state_values(msg: JointState, joints: Sequence[str],
                       fields: Sequence[str] = ('position',)) -> NDArray[np.float64]:
    """
    Return the ``fields`` of ``joints`` in a ``sensor_msgs/JointState``, shape (fields, joints).

    The joints may come in any order, among others (ignored). A JointState names each joint once
    and gives each field one value per name: a message that names a joint twice (which value
    would be meant?), whose asked-for field has not one value per name, that lacks one of
    ``joints`` or holds a non-finite value there is refused with ValueError.

    >>> msg = JointState(name=['b', 'a', 'c'], position=[2.0, 1.0, 3.0])
    >>> joint_state_values(msg, ['a', 'b']).tolist()
    [[1.0, 2.0]]
    >>> joint_state_values(JointState(name=['a', 'b', 'a'], position=[1.0, 2.0, 9.0]), ['a'])
    Traceback (most recent call last):
    ...
    ValueError: JointState names ['a'] more than once
    """
    names = list(msg.name)
    index = {name: i for i, name in enumerate(names)}
    if len(index) != len(names):
        twice = sorted(name for name, count in Counter(names).items() if count > 1)
        raise ValueError(f'JointState names {twice[:10]} more than once')
    for field in fields:
        if len(getattr(msg, field)) != len(names):
            raise ValueError(f'JointState has {len(names)} names but '
                             f'{len(getattr(msg, field))} {field} values')
    missing = [joint for joint in joints if joint not in index]
    if missing:
        raise ValueError(f'JointState lacks {" and ".join(map(_PLURALS.get, fields))} of '
                         f'{missing}')
    rows = [index[joint] for joint in joints]
    values = np.array([[getattr(msg, field)[i] for i in rows] for field in fields],
                      dtype=np.float64).reshape(len(fields), len(rows))
    for field, row in zip(fields, values):
        if not np.isfinite(row).all():
            raise ValueError(f'non-finite joint {field} in {row}')
    return values


def yaw_to_quaternion(yaw: float) -> Quaternion:
    """Return the quaternion of a rotation by ``yaw`` [rad] about z."""
    return Quaternion(z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def quaternion_to_yaw(q: Quaternion) -> float:
    """
    Return the rotation about z [rad] of quaternion ``q`` (roll and pitch ignored).

    >>> round(quaternion_to_yaw(yaw_to_quaternion(2.0)), 12)
    2.0
    """
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def pose2d_from_odometry(msg: Odometry) -> NDArray[np.float64]:
    """Return the planar pose ``(x, y, theta)`` of an ``Odometry`` in its header frame."""
    p = msg.pose.pose
    return np.array([p.position.x, p.position.y, quaternion_to_yaw(p.orientation)])


def odometry_message(t: float, frame_id: str, child_frame_id: str, pose: ArrayLike,
                     twist: tuple[float, ...]) -> Odometry:
    """
    Build an ``Odometry``: pose ``(x, y, theta)`` in ``frame_id``, twist in the child frame.

    Parameters
    ----------
    t : float
        Stamp [s].
    frame_id : str
        Frame of the pose (REP-105), e.g. ``odom``.
    child_frame_id : str
        Frame of the twist, e.g. ``base_link``.
    pose : array_like, shape (3,)
        Planar pose [m, m, rad].
    twist : tuple of float
        (v, ω): forward speed [m/s] and yaw rate [rad/s], or (vx, vy, ω) with the lateral
        speed [m/s] of a holonomic base, in ``child_frame_id``.

    """
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=float))
    msg = Odometry()
    msg.header.stamp = seconds_to_stamp(t)
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    msg.pose.pose.position.x = x
    msg.pose.pose.position.y = y
    msg.pose.pose.orientation = yaw_to_quaternion(theta)
    if len(twist) not in (2, 3):
        raise ValueError(f'twist must be (v, w) or (vx, vy, w), got {twist!r}')
    msg.twist.twist.linear.x = float(twist[0])
    msg.twist.twist.linear.y = float(twist[1]) if len(twist) == 3 else 0.0
    msg.twist.twist.angular.z = float(twist[-1])
    return msg


def planar_transform(t: float, frame_id: str, child_frame_id: str,
                     pose: ArrayLike) -> TransformStamped:
    """
    Build the ``TransformStamped`` ``frame_id`` -> ``child_frame_id`` of a planar pose.

    ``pose`` is (x [m], y [m], theta [rad]) of the child frame in ``frame_id``; stamp ``t`` [s].

    >>> msg = planar_transform(1.5, 'odom', 'base_link', [1.0, 2.0, math.pi])
    >>> msg.header.stamp.sec, msg.transform.translation.y, msg.transform.rotation.z
    (1, 2.0, 1.0)
    """
    x, y, theta = (float(v) for v in np.asarray(pose, dtype=float))
    msg = TransformStamped(child_frame_id=child_frame_id)
    msg.header.stamp = seconds_to_stamp(t)
    msg.header.frame_id = frame_id
    msg.transform.translation.x = x
    msg.transform.translation.y = y
    msg.transform.rotation = yaw_to_quaternion(theta)
    return msg


def path_points(msg: Path) -> NDArray[np.float64]:
    """Return the positions of a ``nav_msgs/Path`` as an (N, 2) array [m]."""
    return np.array([[p.pose.position.x, p.pose.position.y] for p in msg.poses],
                    dtype=float).reshape(-1, 2)


def path_postures(msg: Path) -> NDArray[np.float64]:
    """
    Return the postures of a ``nav_msgs/Path`` as an (N, 3) array (x [m], y [m], yaw [rad]).

    The yaw is each pose's orientation about z (:func:`quaternion_to_yaw`), in (-π, π]: a
    planner's vehicle heading, which on a reverse segment points against the travel.

    >>> path_postures(path_message([[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]], 'map')).tolist()
    [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    return np.array([[p.pose.position.x, p.pose.position.y,
                      quaternion_to_yaw(p.pose.orientation)] for p in msg.poses],
                    dtype=float).reshape(-1, 3)


def path_message(points: ArrayLike, frame_id: str, t: float = 0.0,
                 times: ArrayLike | None = None) -> Path:
    """
    Build a ``nav_msgs/Path`` through (N, 2) ``points`` or (N, 3) postures [m, m, rad].

    Through points each pose faces the next point (the last faces as the one before it);
    through postures (x, y, yaw) each pose's orientation is its yaw, e.g. a vehicle's heading,
    which points against the travel on a reverse segment (read back by :func:`path_postures`).
    The header is stamped ``t`` [s]; each pose is stamped too, with its time in ``times`` (N,)
    [s] when the path is a trajectory, else ``t``.
    """
    given = np.asarray(points, dtype=float)
    postured = given.ndim == 2 and given.shape[1] == 3
    pts = given[:, :2] if postured else given.reshape(-1, 2)
    stamps = np.full(len(pts), float(t)) if times is None else np.asarray(times, dtype=float)
    if stamps.shape != (len(pts),):
        raise ValueError(f'times must have one value per point ({len(pts)}), got shape '
                         f'{stamps.shape}')
    if postured:
        headings = given[:, 2]
    else:
        steps = np.diff(pts, axis=0)
        headings = np.arctan2(steps[:, 1], steps[:, 0]) if len(steps) else np.zeros(0)
        headings = np.append(headings, headings[-1] if len(headings) else 0.0)
    msg = Path()
    msg.header.stamp = seconds_to_stamp(t)
    msg.header.frame_id = frame_id
    for (x, y), yaw, stamp in zip(pts, headings, stamps):
        pose = PoseStamped()
        pose.header.stamp = seconds_to_stamp(float(stamp))
        pose.header.frame_id = frame_id
        pose.pose.position.x = float(x)
        pose.pose.position.y = float(y)
        pose.pose.orientation = yaw_to_quaternion(float(yaw))
        msg.poses.append(pose)
    return msg
