"""
Pinocchio models built from Craig's modified DH tables (book §4.3, HEMERO ``dh`` and ``dyn``).

Joint i of the Pinocchio model is placed in its parent (joint i-1, or the universe for i = 1)
at ``Rot(X, alpha_{i-1}) Tras(X, a_{i-1})`` followed by the table's constant part of the joint:
``Tras(Z, d_i)`` for a revolute joint (a ``JointModelRZ`` then turns it by q_i) or
``Rot(Z, theta_i)`` for a prismatic one (a ``JointModelPZ`` then slides it by q_i). The frame of
joint i is therefore Craig's link frame {i}, and the product of placements and joint motions is
exactly the chain of link transforms (4.6). Operational frames ``link_0`` … ``link_n`` name
those frames, and ``tool0`` is the robot's tool frame on link n (``DHModel.tool``, the identity
unless given), the frame of ``fkine`` and of the Jacobians.

Pinocchio's split, kept here: the model is built once and then only read, so one
:class:`PinocchioArm` may serve every thread; the scratch of the algorithms, a
``pinocchio.Data`` (``arm.model.createData()``), belongs to the caller, one per node, thread or
object. The arm builds, on first use, what it derives from its robot once and for all (the
friction law, a copy of the model without gravity, a bound of its torques) and keeps it, with a
scratch of its own per thread for the dynamics (:meth:`PinocchioArm.scratch`); the models are
never changed. A caller that computes often keeps its arm and its data, and passes them to the
functions that take them (``fkine(arm, q, data=data)``). Given a robot instead, ``fkine`` and
the Jacobians take their NumPy route, which needs no model, and the dynamics take the arm
:func:`dyn_arm` keeps for that robot object. A caller that changes a model (its gravity, a
payload) builds its own with :func:`build_model`.
"""

import copy
from dataclasses import dataclass
from functools import cached_property
import threading
from typing import Any
import weakref

import numpy as np
from numpy.typing import ArrayLike
import pinocchio as pin

from robotica_kin.bounds import MAX_JOINT_ACCELERATION, MAX_JOINT_POSITION, MAX_JOINT_VELOCITY
from robotica_kin.dh import as_dh_model, as_dyn_model, dh_model, DHModel
from robotica_kin.joint_friction import JointFriction

__all__ = ['PinocchioArm', 'TOOL_FRAME', 'build_model', 'data_for', 'dyn_arm',
           'pinocchio_arm', 'robot_and_arm']

TOOL_FRAME = 'tool0'
"""Name of the tool frame (``DHModel.tool`` on link n), the frame of fkine and the Jacobians."""

_DEFAULT_GRAVITY = 9.81   # [m/s²] Pinocchio's default |g|, the gravity of every arm's model


@dataclass(frozen=True, eq=False)
class PinocchioArm:
    """
    A robot with its Pinocchio model, built once by :func:`pinocchio_arm`; read-only, shareable.

    The algorithms of :mod:`robotica_kin.forward_kinematics`, :mod:`robotica_kin.jacobian` and
    :mod:`robotica_kin.dynamics` take it in place of the :class:`~robotica_kin.dh.DHModel` to
    skip the build on every call, and a ``data`` of its model to skip the allocation. Never
    change :attr:`model` (e.g. its gravity): it is shared; copy it (``pinocchio.Model``).

    Attributes
    ----------
    robot : DHModel
        The robot the model was built from.
    model : pinocchio.Model
        :func:`build_model` of ``robot`` (with its dynamics when it has a ``dyn`` table); the
        gravity is Pinocchio's default ``[0, 0, -9.81]`` m/s².
    tool : pinocchio.SE3
        ``robot.tool``, ``T_n_tool``: the tool frame in the last link frame {n}.
    tool_frame : int
        Id of the frame :data:`TOOL_FRAME` in :attr:`model`.

    """

    robot: DHModel
    model: Any
    tool: Any
    tool_frame: int

    @cached_property
    def friction(self) -> JointFriction:
        """
        Return the robot's friction law, built on first use and kept (the robot is frozen).

        Raises ValueError for a robot without a ``dyn`` table.
        """
        return JointFriction(self.robot)

    @cached_property
    def model_without_gravity(self) -> Any:
        """Return a copy of :attr:`model` without gravity (for V = RNEA at q'' = 0); read-only."""
        model = pin.Model(self.model)
        model.gravity = pin.Motion.Zero()
        return model

    @cached_property
    def torque_bound(self) -> float:
        """
        Return an upper bound [N m | N] of the dynamics' values within the joint bounds.

        Over every q, q', q'' within :mod:`robotica_kin.bounds` and the model's gravity (9.81
        m/s²), each element of M, G, V, F and of ``M q'' + G + V + F`` is at most
        ``K X + F_max``: ``K = sum(m_k) (1 + R)² + sum(|I_k|) + sum(J_m G²)`` bounds the inertia
        about any axis, with R the reach (every ``|a|``, ``|d|`` and centre of mass, plus
        ``MAX_JOINT_POSITION`` per prismatic joint), ``X = n q''_max + 3 n² q'_max² + g`` the
        acceleration of any point per unit of arm, and ``F_max`` the friction at ``q'_max``.
        Crude (orders of magnitude above the real torques); inf or NaN for absurd parameters.
        The dynamics check their results only when it is not far below overflow. Raises
        ValueError without a ``dyn`` table.
        """
        robot = as_dyn_model(self.robot)
        assert robot.dyn is not None
        dyn = np.abs(robot.dyn)
        n = robot.n
        reach = float(dyn[:, [1, 3, 6, 7, 8]].sum()) + MAX_JOINT_POSITION * int(
            robot.prismatic.sum())
        acceleration = (n * MAX_JOINT_ACCELERATION + 3.0 * (n * MAX_JOINT_VELOCITY) ** 2
                        + _DEFAULT_GRAVITY)
        with np.errstate(over='ignore', invalid='ignore'):   # absurd masses: inf or NaN
            inertia = (float(dyn[:, 5].sum()) * (1.0 + reach) ** 2 + float(dyn[:, 9:15].sum())
                       + float((dyn[:, 15] * dyn[:, 16] ** 2).sum()))
            friction = float((dyn[:, 16] ** 2 * dyn[:, 17] * MAX_JOINT_VELOCITY
                              + dyn[:, 16] * np.maximum(dyn[:, 18], dyn[:, 19])).sum())
        return inertia * acceleration + friction

    @cached_property
    def _own_data(self) -> '_OwnData':
        """Each thread's own Data of :attr:`model`, built on the thread's first use."""
        return _OwnData(self.model)

    @cached_property
    def _checked_data(self) -> list[Any]:
        """Return a one-element list: the caller's Data checked last (by any thread)."""
        return [None]

    def scratch(self, data: Any = None) -> Any:
        """
        Return ``data`` once it is checked, or for None this thread's own Data of :attr:`model`.

        The dynamics' scratch: a caller's ``data`` is checked as :func:`data_for` does, and
        the last one checked is remembered (the arm keeps a reference to it; a thread that
        alternates two checks each again, 0.3 µs); without one, each thread gets a Data of its
        own, built on its first call and reused (the algorithms only write it, and return new
        arrays).

        Raises
        ------
        ValueError
            When ``data`` is not a Pinocchio ``Data`` of this model.

        """
        if data is None:
            return self._own_data.data
        checked = self._checked_data
        if data is not checked[0]:
            checked[0] = data_for(self, data)
        return data


class _OwnData(threading.local):
    """One Data of a model per thread (``data``), built on the thread's first use."""

    def __init__(self, model: Any) -> None:
        self.data = model.createData()


def pinocchio_arm(dh: DHModel | ArrayLike) -> PinocchioArm:
    """
    Build the Pinocchio model of a robot and return it with the robot and its tool frame.

    Parameters
    ----------
    dh : DHModel or array_like, shape (n, 4) or (n, 5)
        The robot (book Table 4.2 rows ``[alpha a theta d sigma]``); a raw table gets the
        defaults of :func:`~robotica_kin.dh.dh_model` (no dynamics).

    Returns
    -------
    PinocchioArm

    Raises
    ------
    ValueError
        For an invalid table (see :func:`robotica_kin.dh.dh_model`).

    Examples
    --------
    >>> from robotica_kin.forward_kinematics import link_frames
    >>> from robotica_kin.robots import puma560
    >>> arm = pinocchio_arm(puma560())
    >>> data = arm.model.createData()          # the caller's scratch, one per thread
    >>> q = [0.1, -0.5, 0.6, 0.2, 0.4, -0.3]
    >>> pin.forwardKinematics(arm.model, data, np.array(q))
    >>> T_0_6 = link_frames(arm.robot, q)[-1]     # Craig's product (4.6), in NumPy
    >>> bool(np.allclose(data.oMi[6].homogeneous, T_0_6, atol=1e-12))
    True

    """
    robot = as_dh_model(dh)
    model = build_model(robot)
    return PinocchioArm(robot=robot, model=model, tool=pin.SE3(np.array(robot.tool)),
                        tool_frame=int(model.getFrameId(TOOL_FRAME)))


def data_for(arm: PinocchioArm, data: Any) -> Any:
    """
    Return ``data``, or a new ``Data`` of ``arm.model`` when it is None.

    Raises
    ------
    ValueError
        When ``data`` is not a Pinocchio ``Data`` of the arm's model (sizes that differ would
        let Pinocchio write out of bounds).

    """
    if data is None:
        return arm.model.createData()
    if not isinstance(data, pin.Data) or not arm.model.check(data):
        raise ValueError(f'data must be a pinocchio.Data of the model of {arm.robot.name!r} '
                         f'(arm.model.createData()), got {type(data).__name__}')
    return data


def robot_and_arm(dh: DHModel | PinocchioArm | ArrayLike,
                  data: Any) -> tuple[DHModel, PinocchioArm | None]:
    """
    Return the robot of ``dh``, and ``dh`` itself when it is a :class:`PinocchioArm`.

    For the functions with a NumPy route and a Pinocchio route (``fkine``, the Jacobians):
    only an arm has a model for ``data`` to be the scratch of.

    Raises
    ------
    ValueError
        For a bad table, or a ``data`` that comes without an arm.

    """
    if isinstance(dh, PinocchioArm):
        return dh.robot, dh
    if data is not None:
        raise ValueError("data is the scratch of a PinocchioArm's model: pass the arm, not the "
                         'robot, with it')
    return as_dh_model(dh), None


_ARMS: 'weakref.WeakKeyDictionary[DHModel, PinocchioArm]' = weakref.WeakKeyDictionary()


def dyn_arm(dyn: DHModel | PinocchioArm | ArrayLike) -> PinocchioArm:
    """
    Return ``dyn`` when it is the arm of a robot with dynamics, else the arm built from it.

    The arm of a :class:`~robotica_kin.dh.DHModel` (frozen, its arrays read-only) is built on
    its first use and kept while that robot object lives; its ``robot`` is a shallow copy, so
    that the kept arm does not keep the robot alive. A raw table gets a new arm on every call.

    Raises
    ------
    ValueError
        For a robot or an arm without a ``dyn`` table, or a bad table.

    """
    if type(dyn) is PinocchioArm and dyn.robot.dyn is not None:
        return dyn
    if isinstance(dyn, PinocchioArm):
        as_dyn_model(dyn.robot)
        return dyn
    if isinstance(dyn, DHModel):
        arm = _ARMS.get(dyn)
        if arm is None:
            arm = _ARMS[dyn] = pinocchio_arm(copy.copy(as_dyn_model(dyn)))
        return arm
    return pinocchio_arm(as_dyn_model(dyn))


def _link_inertia(row: np.ndarray) -> Any:
    """Return the Pinocchio inertia of one ``dyn`` row: mass, CoM and inertia about the CoM."""
    mass = row[5]
    com = row[6:9]
    ixx, iyy, izz, ixy, iyz, ixz = row[9:15]
    inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    return pin.Inertia(mass, com, inertia)


def build_model(dh: DHModel | ArrayLike, dyn: ArrayLike | None = None) -> Any:
    """
    Return a Pinocchio ``Model`` of a manipulator given by a modified-DH table.

    Parameters
    ----------
    dh : DHModel or array_like, shape (n, 4) or (n, 5)
        The robot (book Table 4.2 rows ``[alpha a theta d sigma]``).
    dyn : array_like, shape (n, 20), optional
        HEMERO's dynamic table (book §A.3): columns 6-15 give the link mass [kg], its centre of
        mass in the link frame [m] and its inertia tensor about the centre of mass
        ``Ixx Iyy Izz Ixy Iyz Ixz`` [kg m²]; column 16 the motor inertia J_m [kg m²] and 17 the
        gear ratio G, whose reflected inertia ``J_m G²`` becomes the joint's ``armature``.
        Without it the links are massless.

    Returns
    -------
    pinocchio.Model
        One revolute (RZ) or prismatic (PZ) joint per row, named as the robot's joints, with
        the joint limits, and frames ``link_0`` … ``link_n`` and ``tool0``.

    Raises
    ------
    ValueError
        For an invalid table (see :func:`robotica_kin.dh.dh_model`).

    Examples
    --------
    >>> model = build_model([[0, 0, 0, 0], [0, 1.0, 0, 0]])
    >>> model.nq, [model.names[i] for i in range(1, model.njoints)]
    (2, ['joint_1', 'joint_2'])

    """
    robot = as_dh_model(dh)
    if dyn is not None:
        robot = dh_model(robot.table, name=robot.name, qlim=robot.qlim,
                         joint_names=robot.joint_names, dyn=dyn, tool=robot.tool)
    model = pin.Model()
    model.name = robot.name
    model.addFrame(pin.Frame('link_0', 0, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    parent = 0
    for i in range(robot.n):
        ca, sa = np.cos(robot.alpha[i]), np.sin(robot.alpha[i])
        rot_x = np.array([[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]])
        if robot.prismatic[i]:
            ct, st = np.cos(robot.theta[i]), np.sin(robot.theta[i])
            rot = rot_x @ np.array([[ct, -st, 0.0], [st, ct, 0.0], [0.0, 0.0, 1.0]])
            placement = pin.SE3(rot, np.array([robot.a[i], 0.0, 0.0]))
            joint = pin.JointModelPZ()
        else:
            offset = np.array([robot.a[i], -sa * robot.d[i], ca * robot.d[i]])
            placement = pin.SE3(rot_x, offset)
            joint = pin.JointModelRZ()
        parent = model.addJoint(
            parent, joint, placement, robot.joint_names[i],
            np.array([np.inf]), np.array([np.inf]),
            robot.qlim[i:i + 1, 0].copy(), robot.qlim[i:i + 1, 1].copy())
        if robot.dyn is not None:
            model.appendBodyToJoint(parent, _link_inertia(robot.dyn[i]), pin.SE3.Identity())
            motor_inertia, gear_ratio = robot.dyn[i, 15], robot.dyn[i, 16]
            model.armature[i] = motor_inertia * gear_ratio ** 2
            model.rotorInertia[i] = motor_inertia
            model.rotorGearRatio[i] = gear_ratio
        model.addFrame(pin.Frame(f'link_{i + 1}', parent, model.getFrameId(f'link_{i}'),
                                 pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    model.addFrame(pin.Frame(TOOL_FRAME, parent, model.getFrameId(f'link_{robot.n}'),
                             pin.SE3(np.array(robot.tool)), pin.FrameType.OP_FRAME))
    return model
