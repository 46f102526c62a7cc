"""
The transforms of a URDF's joints, parent link to child link, by Pinocchio.

The job of robot_state_publisher (C++, not on PyPI). A viewer draws a robot from its URDF
(``/robot_description``) and one transform per joint on ``/tf`` and ``/tf_static``: for joint
J of parent link P and child link C, ``T_P_C`` = J's ``<origin>`` times J's motion at its
position. :class:`URDFKinematics` builds one Pinocchio model from the URDF text
(``pinocchio.buildModelFromXML``, the same for arms and vehicles) and reads the tree off its
frames: each link is a BODY frame whose parent frame is its joint's (JOINT or FIXED_JOINT)
frame, whose parent frame is the parent link's. Fixed joints give the static transforms once
(:attr:`URDFKinematics.fixed`); the moving ones are computed for the joint positions with
``forwardKinematics`` (:meth:`URDFKinematics.moving`) from the joint's local placement
``liMi`` and the links' placements in their joints' frames, so that no transform is the
difference of two world placements.

A ``continuous`` joint (Pinocchio's unbounded revolute: cos and sin in the configuration) takes
its angle as any other; a ``<mimic>`` joint follows its joint, ``q = multiplier q_j + offset``,
as robot_state_publisher computes it; it is not among :attr:`URDFKinematics.joint_names`.
"""
from typing import NamedTuple
import xml.etree.ElementTree as ElementTree

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin

__all__ = ['LinkTransform', 'URDFKinematics']


class LinkTransform(NamedTuple):
    """``T`` (4, 4) [m]: the pose of link ``child`` in link ``parent`` (Craig's parent_T_child)."""

    parent: str
    child: str
    T: NDArray[np.float64]


class _Moving(NamedTuple):
    parent: str
    child: str
    joint: int                 # Pinocchio joint id
    parent_inverse: pin.SE3    # the parent link's placement in its joint's frame, inverted
    child_placement: pin.SE3   # the child link's placement in the joint's frame


def _mimics(urdf: str) -> dict[str, tuple[str, float, float]]:
    """Return ``{mimic joint: (its joint, multiplier, offset)}`` of the URDF text."""
    mimics = {}
    for joint in ElementTree.fromstring(urdf).iter('joint'):
        mimic = joint.find('mimic')
        if mimic is not None:
            mimics[joint.get('name', '')] = (mimic.get('joint', ''),
                                             float(mimic.get('multiplier', '1')),
                                             float(mimic.get('offset', '0')))
    return mimics


class URDFKinematics:
    """
    A URDF's joint transforms for given joint positions (one Pinocchio model and its data).

    Parameters
    ----------
    urdf : str
        The URDF (XML text) with revolute, continuous, prismatic and fixed joints.

    Raises
    ------
    ValueError
        For a URDF that Pinocchio cannot read, a joint of another type (floating, planar) or a
        mimic joint whose joint is not a moving joint of the URDF.

    Examples
    --------
    >>> from robotica_kin.robots import planar_rr
    >>> from robotica_kin.urdf import arm_urdf
    >>> kinematics = URDFKinematics(arm_urdf(planar_rr()))
    >>> kinematics.joint_names
    ('joint_1', 'joint_2')
    >>> [(t.parent, t.child) for t in kinematics.fixed]
    [('link_2', 'tool0')]
    >>> [(t.parent, t.child, float(t.T[0, 3])) for t in kinematics.moving([0.0, 0.5])]
    [('link_0', 'link_1', 0.0), ('link_1', 'link_2', 1.0)]

    """

    def __init__(self, urdf: str) -> None:
        try:
            self.model = pin.buildModelFromXML(urdf)
            mimics = _mimics(urdf)
        except (RuntimeError, ValueError, ElementTree.ParseError) as error:
            raise ValueError(f'the URDF cannot be read: {error}') from None
        self._data = self.model.createData()
        model = self.model
        joints = {model.names[j]: j for j in range(1, model.njoints)}
        for name, j in joints.items():
            nq, nv = model.joints[j].nq, model.joints[j].nv
            if nv != 1 or nq not in (1, 2):
                raise ValueError(f'joint {name!r} ({model.joints[j].shortname()}) is not '
                                 'revolute, continuous, prismatic or fixed')
        for name, (source, _, _) in mimics.items():
            if name not in joints or source not in joints or source in mimics:
                raise ValueError(f'mimic joint {name!r} follows {source!r}, not a moving joint')
        self.joint_names = tuple(name for name in joints if name not in mimics)
        """The joints that positions are given for, in the URDF's order."""
        self.continuous = frozenset(name for name, j in joints.items()
                                    if model.joints[j].nq == 2)
        """The continuous joints (no limits: any angle)."""
        self._mimics = [(joints[name], self.joint_names.index(source), multiplier, offset)
                        for name, (source, multiplier, offset) in mimics.items()]
        self._joints = [joints[name] for name in self.joint_names]
        fixed: list[LinkTransform] = []
        self._moving: list[_Moving] = []
        frames = model.frames
        for child in frames:
            joint = frames[child.parentFrame]
            if child.type != pin.FrameType.BODY or joint.name == 'universe':
                continue
            parent = frames[joint.parentFrame]
            if joint.type == pin.FrameType.FIXED_JOINT:
                T = (parent.placement.inverse() * child.placement).homogeneous
                fixed.append(LinkTransform(parent.name, child.name, T))
            else:
                self._moving.append(_Moving(parent.name, child.name, joint.parentJoint,
                                            parent.placement.inverse(), child.placement))
        self.fixed = tuple(fixed)
        """The fixed joints' transforms (``/tf_static``), in the URDF's order."""

    def moving(self, q: ArrayLike) -> list[LinkTransform]:
        """
        Return the moving joints' transforms at positions ``q`` (``joint_names`` order).

        ``q`` [rad | m], shape (len(joint_names),); mimic joints follow theirs.
        """
        values = np.asarray(q, dtype=np.float64)
        if values.shape != (len(self.joint_names),):
            raise ValueError(f'q must have one value per joint ({len(self.joint_names)},), got '
                             f'shape {values.shape}')
        config = pin.neutral(self.model)
        positions = [(j, value) for j, value in zip(self._joints, values)]
        positions += [(j, multiplier * values[source] + offset)
                      for j, source, multiplier, offset in self._mimics]
        for j, value in positions:
            index = self.model.idx_qs[j]
            if self.model.joints[j].nq == 2:
                config[index:index + 2] = np.cos(value), np.sin(value)
            else:
                config[index] = value
        pin.forwardKinematics(self.model, self._data, config)
        return [LinkTransform(m.parent, m.child,
                              (m.parent_inverse * self._data.liMi[m.joint]
                               * m.child_placement).homogeneous)
                for m in self._moving]
