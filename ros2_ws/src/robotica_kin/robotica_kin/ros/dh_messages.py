"""
Conversions between the manipulator messages and the kinematics core (book §4.3).

``robotica_msgs/DHTable`` ⇄ :class:`~robotica_kin.dh.DHModel` (Craig's modified DH, HEMERO rows
``[alpha_{i-1} a_{i-1} theta_i d_i sigma_i]``), ``geometry_msgs/Pose`` ⇄ 4×4 homogeneous
transform, and how the kinematics nodes choose their robot: a built-in name, a flattened table
from a parameter, or the robot of a service request. A ``DHTable`` has no tool frame: a model's
``tool`` does not travel in it.
"""
import math
from typing import Optional, Sequence

from geometry_msgs.msg import Point, Pose, Quaternion
import numpy as np
from numpy.typing import ArrayLike, NDArray
from rclpy.node import Node
from rclpy.parameter import Parameter
from robotica_kin.bounds import MAX_JOINTS
from robotica_kin.dh import dh_model, DHModel
from robotica_kin.robots import robot_by_name, ROBOT_NAMES
from robotica_kin.ros.parameters import declare
from robotica_kin.transforms import ishomog, q2tr, tr2q
from robotica_msgs.msg import DHParameter, DHTable

QUATERNION_NORM_TOLERANCE = 1e-3   # |‖q‖ - 1| accepted (and normalised away) in a Pose


def dh_table_message(robot: DHModel, frame_id: str = '') -> DHTable:
    """
    Return ``robot`` as a ``robotica_msgs/DHTable`` (its tool, if any, is not carried).

    >>> from robotica_kin.robots import planar_rrr
    >>> msg = dh_table_message(planar_rrr(4.0, 3.0), 'link_0')
    >>> [link.a for link in msg.links], msg.joint_names[2], msg.header.frame_id
    ([0.0, 4.0, 3.0], 'joint_3', 'link_0')
    """
    msg = DHTable(name=robot.name, joint_names=list(robot.joint_names))
    msg.header.frame_id = frame_id
    for alpha, a, theta, d, prismatic in zip(robot.alpha, robot.a, robot.theta, robot.d,
                                             robot.prismatic):
        msg.links.append(DHParameter(
            alpha=float(alpha), a=float(a), theta=float(theta), d=float(d),
            sigma=DHParameter.PRISMATIC if prismatic else DHParameter.REVOLUTE))
    return msg


def dh_model_from_message(msg: DHTable) -> DHModel:
    """
    Return the :class:`DHModel` of a ``DHTable`` (default limits; empty names: ``joint_i``).

    Raises
    ------
    ValueError
        For a table without rows or with more than ``MAX_JOINTS`` (robotica_kin.bounds), a sigma
        other than REVOLUTE (0) or PRISMATIC (1), non-finite values, or joint names that are not
        one distinct name per row.

    Examples
    --------
    >>> msg = dh_table_message(dh_model([[0, 0, 0, 0], [0, 1.0, 0, 0]], name='rr'))
    >>> dh_model_from_message(msg).a.tolist()
    [0.0, 1.0]

    """
    if not 0 < len(msg.links) <= MAX_JOINTS:
        raise ValueError(f'the DH table must have 1 to {MAX_JOINTS} links, got {len(msg.links)}')
    sigmas = [link.sigma for link in msg.links]
    if any(s not in (DHParameter.REVOLUTE, DHParameter.PRISMATIC) for s in sigmas):
        raise ValueError(f'sigma must be 0 (revolute) or 1 (prismatic), got {sigmas}')
    table = [[link.alpha, link.a, link.theta, link.d, float(link.sigma)] for link in msg.links]
    names = list(msg.joint_names) or None
    return dh_model(table, name=msg.name or 'dh_table', joint_names=names)


def pose_message(T: ArrayLike) -> Pose:
    """
    Return a homogeneous transform ``T`` (4, 4) [m] as a ``geometry_msgs/Pose``.

    >>> from robotica_kin.transforms import rotz, transl
    >>> p = pose_message(transl(1.0, 2.0, 3.0) @ rotz(math.pi))
    >>> p.position.x, p.position.z, round(p.orientation.z, 12), round(p.orientation.w, 12)
    (1.0, 3.0, 1.0, 0.0)
    """
    M = np.asarray(T, dtype=np.float64)
    w, x, y, z = (float(v) for v in tr2q(M))
    return Pose(position=Point(x=float(M[0, 3]), y=float(M[1, 3]), z=float(M[2, 3])),
                orientation=Quaternion(x=x, y=y, z=z, w=w))


def pose_matrix(pose: Pose) -> NDArray[np.float64]:
    """
    Return a ``geometry_msgs/Pose`` as a 4×4 homogeneous transform [m].

    The quaternion must have unit norm within ``QUATERNION_NORM_TOLERANCE`` (it is then
    normalised).

    Raises
    ------
    ValueError
        For a non-finite position or orientation, or a quaternion that is not a unit one.

    Examples
    --------
    >>> pose_matrix(Pose(position=Point(x=1.0))).tolist()[0]
    [1.0, 0.0, 0.0, 1.0]

    """
    p, o = pose.position, pose.orientation
    position = [p.x, p.y, p.z]
    quaternion = [o.w, o.x, o.y, o.z]
    if not all(math.isfinite(v) for v in position + quaternion):
        raise ValueError(f'pose must be finite, got position {position}, orientation '
                         f'[w x y z] = {quaternion}')
    norm = math.sqrt(sum(v * v for v in quaternion))
    if abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE:
        raise ValueError(f'pose orientation must be a unit quaternion, got norm {norm:.6g}')
    T = q2tr(quaternion)
    T[:3, 3] = position
    if not ishomog(T):
        raise ValueError(f'pose is not a homogeneous transform: {T!r}')
    return T


def _named_robot_or_rows(robot: str, table: Optional[Sequence[float]], parameter: str,
                         width: int, columns: str) -> DHModel | np.ndarray:
    """
    Return the built-in ``robot``, or the flattened ``table`` parameter as rows (n, width).

    Exactly one of them must be given; ``parameter`` and ``columns`` name the table in errors.
    """
    values = list(table or [])
    if robot and values:
        raise ValueError(f"robot {robot!r} and {parameter} both given: set robot to '' to use "
                         f'{parameter}')
    if robot:
        return robot_by_name(robot)
    if not values or len(values) % width:
        raise ValueError(f'{parameter} must hold n rows of {width} values {columns}, got '
                         f'{len(values)} values')
    return np.reshape(np.asarray(values, dtype=np.float64), (-1, width))


def robot_from_parameters(robot: str, dh_table: Optional[Sequence[float]],
                          joint_names: Optional[Sequence[str]] = None) -> DHModel:
    """
    Return a node's robot: the built-in ``robot`` or, when it is '', the flattened ``dh_table``.

    Parameters
    ----------
    robot : str
        A name of :data:`robotica_kin.robots.ROBOT_NAMES`, or '' to use ``dh_table``.
    dh_table : sequence of float or None
        HEMERO table (n, 5) flattened row-major ``[alpha a theta d sigma] * n`` [rad, m];
        must be empty or None when ``robot`` is given.
    joint_names : sequence of str or None
        One name per joint; empty or None keeps the model's names.

    Raises
    ------
    ValueError
        For an unknown robot, both or neither of ``robot`` and ``dh_table``, a table whose
        length is not a positive multiple of 5 or with NaN, or a wrong number of joint names.

    Examples
    --------
    >>> robot_from_parameters('', [0, 0, 0, 0, 0, 0, 1.0, 0, 0, 0], ['a', 'b']).joint_names
    ('a', 'b')
    >>> robot_from_parameters('', [0.0, 1.0])
    Traceback (most recent call last):
    ...
    ValueError: dh_table must hold n rows of 5 values [alpha a theta d sigma], got 2 values
    >>> robot_from_parameters('puma560', [0.0, 0.0, 0.0, 0.0, 0.0])
    Traceback (most recent call last):
    ...
    ValueError: robot 'puma560' and dh_table both given: set robot to '' to use dh_table

    """
    chosen = _named_robot_or_rows(robot, dh_table, 'dh_table', 5, '[alpha a theta d sigma]')
    model = chosen if isinstance(chosen, DHModel) else dh_model(chosen, name='dh_table')
    if not joint_names:
        return model
    return dh_model(model.table, name=model.name, qlim=model.qlim, joint_names=list(joint_names),
                    dyn=model.dyn, tool=model.tool)


def dynamic_robot_from_parameters(robot: str, dyn_table: Optional[Sequence[float]],
                                  joint_names: Optional[Sequence[str]] = None,
                                  joint_limits: Optional[Sequence[float]] = None) -> DHModel:
    """
    Return a node's robot with dynamics: the built-in ``robot`` or the flattened ``dyn_table``.

    Parameters
    ----------
    robot : str
        A name of :data:`robotica_kin.robots.ROBOT_NAMES` whose model has a ``dyn`` table, or ''
        to use ``dyn_table``.
    dyn_table : sequence of float or None
        HEMERO ``dyn`` table (n, 20) flattened row-major (book §A.3: DH row, mass, centre of
        mass, inertia tensor, motor inertia, gear ratio, viscous and Coulomb friction).
    joint_names : sequence of str or None
        One name per joint; empty or None keeps the model's names.
    joint_limits : sequence of float or None
        ``[low_1, high_1, ..., low_n, high_n]`` [rad | m]; empty or None keeps the model's.

    Raises
    ------
    ValueError
        As :func:`robot_from_parameters`, and for a robot without dynamic parameters, a table
        whose length is not a multiple of 20, or limits that are not n finite (low < high) pairs.

    Examples
    --------
    >>> robot = dynamic_robot_from_parameters('', [0.0] * 5 + [1.0] + [0.0] * 14)
    >>> robot.n, float(robot.dyn[0, 5])
    (1, 1.0)
    >>> dynamic_robot_from_parameters('planar_rr', None)
    Traceback (most recent call last):
    ...
    ValueError: robot 'planar_rr' has no dynamic parameters: give a dyn_table instead

    """
    chosen = _named_robot_or_rows(robot, dyn_table, 'dyn_table', 20, '(HEMERO dyn)')
    if isinstance(chosen, DHModel):
        model = chosen
        if model.dyn is None:
            raise ValueError(f'robot {robot!r} has no dynamic parameters: give a dyn_table '
                             'instead')
    else:
        model = dh_model(chosen[:, :5], name='dyn_table', dyn=chosen)
    qlim = model.qlim
    if joint_limits:
        qlim = np.reshape(np.asarray(joint_limits, dtype=np.float64), (-1, 2)) \
            if len(joint_limits) == 2 * model.n else None
        if qlim is None or not np.isfinite(qlim).all() or np.any(qlim[:, 0] >= qlim[:, 1]):
            raise ValueError(f'joint_limits must be {model.n} pairs [low, high] with low < high, '
                             f'got {list(joint_limits)}')
    return dh_model(model.table, name=model.name, qlim=qlim,
                    joint_names=list(joint_names) if joint_names else model.joint_names,
                    dyn=model.dyn, tool=model.tool)


def request_robot(robot: str, dh: DHTable, default: DHModel) -> DHModel:
    """
    Return the robot a service request asks for: ``robot`` by name, else ``dh``, else ``default``.

    Raises
    ------
    ValueError
        For an unknown robot name or a malformed table.

    Examples
    --------
    >>> request_robot('', DHTable(), robot_by_name('planar_rr')).name
    'planar_rr'

    """
    if robot:
        return default if robot == default.name and robot in ROBOT_NAMES else robot_by_name(robot)
    if dh.links:
        return dh_model_from_message(dh)
    return default


_DH_TABLE = ('HEMERO DH table [alpha_{i-1} a_{i-1} theta_i d_i sigma_i] * n [rad, m], book '
             "Table 4.2, flattened row-major; used when robot is ''")
_DYN_TABLE = ('HEMERO dyn table (n x 20: DH row, mass, centre of mass, inertia, Jm, G, B, Tc+, '
              "Tc-), flattened row-major; used when robot is ''")


def declare_robot(node: Node, role: str, *, dynamics: bool = False,
                  joint_names: str | None = None, joint_limits: bool = False) -> DHModel:
    """
    Declare a node's robot parameters (all read-only) and return its robot.

    ``robot`` (a built-in name, default ``puma560``) and ``dh_table`` or, with ``dynamics``,
    ``dyn_table``; ``joint_names`` when a description of their order is given;
    ``joint_limits`` [rad | m] if asked. ``role`` says what the robot is to the node
    ("Built-in robot", "The controller's model"). Raises ValueError as
    :func:`robot_from_parameters` and :func:`dynamic_robot_from_parameters`, which
    :func:`~robotica_kin.ros.entry_point.run_node` reports as invalid configuration.
    """
    table_name = 'dyn_table' if dynamics else 'dh_table'
    robot = declare(node, 'robot', 'puma560',
                    f'{role}, one of {ROBOT_NAMES}{" with dynamics" if dynamics else ""}; '
                    f'empty: use {table_name}', read_only=True)
    table = declare(node, table_name, Parameter.Type.DOUBLE_ARRAY,
                    _DYN_TABLE if dynamics else _DH_TABLE, read_only=True)
    names = None if joint_names is None else declare(
        node, 'joint_names', Parameter.Type.STRING_ARRAY,
        f"Joint names, {joint_names}; default the model's (joint_1 … joint_n)", read_only=True)
    if not dynamics:
        return robot_from_parameters(robot, table, names)
    limits = None if not joint_limits else declare(
        node, 'joint_limits', Parameter.Type.DOUBLE_ARRAY,
        "[low_1, high_1, …] [rad | m]; default the model's", read_only=True)
    return dynamic_robot_from_parameters(robot, table, names, limits)
