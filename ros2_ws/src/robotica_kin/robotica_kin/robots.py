"""
The book's manipulators as ready-made :class:`~robotica_kin.dh.DHModel` objects.

- :func:`puma560`: HEMERO's ``dhp560`` table with Armstrong, Khatib and Burdick's (1986)
  dynamic parameters ``dyn`` (book §A.2-§A.3, fig. A.7).
- :func:`planar_rr`, :func:`planar_rrr`: the planar arms of Ej. 4.1 (frame {n} at the end of the
  last link in the RR; at the last joint in the 3R, as the book's table puts it).
- :func:`cylindrical_rpr`: the R-P-R robot of Ej. 4.2 (Table 4.3).
- :func:`pp_robot`: the planar Cartesian PP robot of Ej. 8.10-8.11 (Lewis et al.), force control.

:func:`robot_by_name` looks them up by the names the nodes and services use.
"""

from collections.abc import Callable
import math

import numpy as np

from robotica_kin.dh import dh_model, DHModel
from robotica_kin.transforms import transl

__all__ = ['ROBOT_NAMES', 'cylindrical_rpr', 'planar_rr', 'planar_rrr', 'pp_robot', 'puma560',
           'robot_by_name', 'two_link_arm']

_DEG = math.pi / 180.0

# HEMERO dhp560 (book §A.2): [alpha_{i-1} a_{i-1} theta_i d_i sigma_i], metres and radians.
_PUMA560_DH = [
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [-math.pi / 2, 0.0, 0.0, 0.2435, 0.0],
    [0.0, 0.4318, 0.0, -0.0934, 0.0],
    [math.pi / 2, -0.0203, 0.0, 0.4331, 0.0],
    [-math.pi / 2, 0.0, 0.0, 0.0, 0.0],
    [math.pi / 2, 0.0, 0.0, 0.0, 0.0],
]

# Book fig. A.7 (Armstrong, Khatib & Burdick 1986), after the five DH columns:
# m [kg], r_x r_y r_z [m], Ixx Iyy Izz Ixy Iyz Ixz [kg m^2], J_m [kg m^2], G, B, Tc+, Tc-.
_PUMA560_DYN_TAIL = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.35, 0.0, 0.0, 0.0, 0.0, 291e-6, -62.6111, 0.0, 0.0, 0.0],
    [17.4, 0.068, 0.006, -0.016, 0.13, 0.524, 0.539, 0.0, 0.0, 0.0, 409e-6, 107.815, 0.0, 0.0,
     0.0],
    [4.8, 0.0, -0.070, 0.014, 0.066, 0.0125, 0.066, 0.0, 0.0, 0.0, 299e-6, -53.7063, 0.0, 0.0,
     0.0],
    [0.82, 0.0, 0.0, -0.019, 1.8e-3, 1.8e-3, 1.3e-3, 0.0, 0.0, 0.0, 35e-6, 76.0364, 0.0, 0.0,
     0.0],
    [0.34, 0.0, 0.0, 0.0, 0.3e-3, 0.3e-3, 0.4e-3, 0.0, 0.0, 0.0, 35e-6, 71.923, 0.0, 0.0, 0.0],
    [0.09, 0.0, 0.0, 0.032, 0.15e-3, 0.15e-3, 0.04e-3, 0.0, 0.0, 0.0, 35e-6, 76.686, 0.0, 0.0,
     0.0],
]

# Joint ranges of the PUMA 560 in Craig's frame assignment [deg] (Craig, "Introduction to
# Robotics", the PUMA 560 of chapter 3), the frames of HEMERO's dhp560. HEMERO has no limits:
# puma560(joint_limits=True) adds them (the appendix's straight line leaves them, see below).
_PUMA560_LIMITS_DEG = [[-160.0, 160.0], [-225.0, 45.0], [-45.0, 225.0],
                       [-110.0, 170.0], [-100.0, 100.0], [-266.0, 266.0]]


def puma560(*, joint_limits: bool = False) -> DHModel:
    """
    Return the PUMA 560 of HEMERO (``dhp560`` and its ``dyn`` table, book §A.2-§A.3).

    Lengths in metres. HEMERO's ``dhp560`` has no joint limits, and neither has this model by
    default: ``qlim`` is ±π, which bounds no revolute joint (``ikine`` wraps angles by 2π).
    ``joint_limits=True`` adds the ranges of Craig's PUMA 560 in the same frames (joint 2 in
    [-225°, 45°], joint 3 in [-45°, 225°], ...), the mechanical stops of the real arm, for a
    plant that stops its joints. With them the appendix's straight line (x = 0.40-0.45 m,
    y = z = 0.1 m, identity orientation) has no solution: each of its eight solutions puts
    θ2 past its 45° stop (46-48°) or θ5 past ±100°.

    Parameters
    ----------
    joint_limits : bool
        Add Craig's joint ranges [rad] as ``qlim`` (default False, as HEMERO).

    Examples
    --------
    >>> robot = puma560()
    >>> robot.n, robot.dyn.shape, robot.joint_names[0]
    (6, (6, 20), 'joint_1')
    >>> puma560(joint_limits=True).qlim[1].round(4).tolist()
    [-3.927, 0.7854]

    """
    dyn = np.hstack([np.array(_PUMA560_DH), np.array(_PUMA560_DYN_TAIL)])
    qlim = np.array(_PUMA560_LIMITS_DEG) * _DEG if joint_limits else None
    return dh_model(_PUMA560_DH, name='puma560', qlim=qlim, dyn=dyn)


def _check_lengths(**lengths: float) -> None:
    for name, value in lengths.items():
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f'{name} must be a finite length > 0 m, got {value!r}')


def planar_rr(l1: float = 1.0, l2: float = 1.0) -> DHModel:
    """
    Return a planar 2R arm with links ``l1``, ``l2`` [m] (book §4.4, Ej. 4.4-4.5).

    Craig's table ``[[0 0 θ1 0], [0 l1 θ2 0]]`` puts frame {2} at the elbow; the tip, at
    ``l2`` along X_2, is the model's tool frame (``transl(l2, 0, 0)``), so ``fkine`` gives the
    tip: ``x = l1 c1 + l2 c12``, ``y = l1 s1 + l2 s12``. Limits ±π.

    Examples
    --------
    >>> from robotica_kin.forward_kinematics import fkine
    >>> fkine(planar_rr(4.0, 3.0), [0.0, 0.0])[:3, 3].tolist()
    [7.0, 0.0, 0.0]

    """
    _check_lengths(l1=l1, l2=l2)
    return dh_model([[0.0, 0.0, 0.0, 0.0, 0.0], [0.0, l1, 0.0, 0.0, 0.0]], name='planar_rr',
                    qlim=[[-math.pi, math.pi]] * 2, tool=transl(l2, 0.0, 0.0))


def planar_rrr(l1: float = 1.0, l2: float = 1.0, l3: float = 0.0) -> DHModel:
    """
    Return the planar 3R arm of Ej. 4.1 with links ``l1``, ``l2`` [m] and tool length ``l3`` [m].

    Table 4.2: ``[[0 0 θ1 0], [0 l1 θ2 0], [0 l2 θ3 0]]``; frame {3} is at the end of link 2
    and turns with θ3, so with ``l3 = 0`` (the book's model and Ej. H.3.1, with l1 = 4, l2 = 3)
    ``fkine`` is (4.10). A positive ``l3`` adds a tool at ``l3`` along X_3. Limits ±π.

    Examples
    --------
    >>> planar_rrr(4.0, 3.0).a.tolist()
    [0.0, 4.0, 3.0]

    """
    _check_lengths(l1=l1, l2=l2)
    if not (math.isfinite(l3) and l3 >= 0.0):
        raise ValueError(f'l3 must be a finite length >= 0 m, got {l3!r}')
    return dh_model([[0.0, 0.0, 0.0, 0.0, 0.0], [0.0, l1, 0.0, 0.0, 0.0],
                     [0.0, l2, 0.0, 0.0, 0.0]], name='planar_rrr',
                    qlim=[[-math.pi, math.pi]] * 3, tool=transl(l3, 0.0, 0.0))


def cylindrical_rpr(l2: float = 0.2, d2_max: float = 1.0) -> DHModel:
    """
    Return the R-P-R "cylindrical" robot of Ej. 4.2 (book Table 4.3, Craig fig. 4.4).

    Table ``[[0 0 θ1 0 0], [π/2 0 0 d2 1], [0 0 θ3 l2 0]]``: joint 2 is prismatic, with
    ``d2 = 0`` the minimum extension, so its limits are ``[0, d2_max]`` [m]; θ1 and θ3 have ±π.

    Examples
    --------
    >>> cylindrical_rpr(0.3).prismatic.tolist()
    [False, True, False]

    """
    _check_lengths(l2=l2, d2_max=d2_max)
    return dh_model([[0.0, 0.0, 0.0, 0.0, 0.0], [math.pi / 2, 0.0, 0.0, 0.0, 1.0],
                     [0.0, 0.0, 0.0, l2, 0.0]], name='cylindrical_rpr',
                    qlim=[[-math.pi, math.pi], [0.0, d2_max], [-math.pi, math.pi]])


def two_link_arm(m1: float, m2: float, l1: float,
                 l2: float) -> tuple[np.ndarray, np.ndarray]:
    """
    Return ``(dh, dyn)`` of the planar 2R of Ej. 5.1: point masses at the link ends.

    ``dh = [[0 0 θ1 0 0], [0 l1 θ2 0 0]]``; in ``dyn`` link i has mass m_i [kg] at
    ``l_i X̂_i`` [m] (5.54), no inertia tensor, gear ratio 1 and no friction. The planar
    arm moves in the XY plane, so use ``grav = [0, -g, 0]`` as the book does (5.58).

    Examples
    --------
    >>> dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> dyn[:, [5, 6, 16]].tolist()
    [[2.0, 3.0, 1.0], [1.0, 1.0, 1.0]]

    """
    _check_lengths(l1=l1, l2=l2)
    for name, mass in (('m1', m1), ('m2', m2)):
        if not (math.isfinite(mass) and mass >= 0.0):
            raise ValueError(f'{name} must be a finite mass >= 0 kg, got {mass!r}')
    dh = np.array([[0.0, 0.0, 0.0, 0.0, 0.0], [0.0, l1, 0.0, 0.0, 0.0]])
    dyn = np.zeros((2, 20))
    dyn[:, :5] = dh
    dyn[:, 5] = [m1, m2]
    dyn[:, 6] = [l1, l2]
    dyn[:, 16] = 1.0
    return dh, dyn


# The PP robot's tool frame: frame {2} turned back parallel to {0} (R_0_2 is its own inverse).
_PP_TOOL = [[0.0, 0.0, 1.0, 0.0], [0.0, -1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 1.0]]
_PP_TRAVEL = 10.0   # [m] joint range ±, wide enough for Ej. 8.10-8.11 (d1 = 3√2 m at the start)


def pp_robot(m1: float = 2.0, m2: float = 0.35) -> DHModel:
    """
    Return the planar Cartesian PP robot of Ej. 8.10-8.11 (Lewis et al.) with masses m1, m2 [kg].

    The book's model (8.182)-(8.183), in its joint order ``[d1, d2]``: ``M = diag(m1, m1 + m2)``,
    ``G = [0; (m1 + m2) g]``. d2 moves both masses, so it is the base joint: no serial chain
    has them in the book's order (the base joint of a Cartesian chain moves every link, so its
    M entry is the larger). The chain's order is therefore ``q = [d2, d1]``, joints named
    ``d2_vertical`` and ``d1_horizontal``: ``q[::-1]`` is the book's ``[d1, d2]``, and in the
    chain's order ``M = diag(m1 + m2, m1)``, ``G = [(m1 + m2) g; 0]``.

    The robot moves in the XY plane of {0}: d1 along X, d2 along Y (up), so the end effector is
    at ``p = [d1, d2, 0]`` [m] and gravity is ``grav = [0, -g, 0]``, as the book's planar arms
    (5.58) and :func:`two_link_arm`. Table ``[[-π/2 0 -π/2 d2 1], [-π/2 0 0 d1 1]]``; link 1
    (moved by d2 only) has mass m2, link 2 (the end effector) m1, as point masses at the frame
    origins, no friction, gear ratio 1. The tool frame is parallel to {0}. Limits ±10 m.

    Raises
    ------
    ValueError
        For m1 not finite and > 0, or m2 not finite and >= 0.

    Examples
    --------
    >>> robot = pp_robot()
    >>> robot.joint_names, robot.dyn[:, 5].tolist()
    (('d2_vertical', 'd1_horizontal'), [0.35, 2.0])

    """
    if not (math.isfinite(m1) and m1 > 0.0):
        raise ValueError(f'm1 must be a finite mass > 0 kg, got {m1!r}')
    if not (math.isfinite(m2) and m2 >= 0.0):
        raise ValueError(f'm2 must be a finite mass >= 0 kg, got {m2!r}')
    dh = np.array([[-math.pi / 2, 0.0, -math.pi / 2, 0.0, 1.0],
                   [-math.pi / 2, 0.0, 0.0, 0.0, 1.0]])
    dyn = np.zeros((2, 20))
    dyn[:, :5] = dh
    dyn[:, 5] = [m2, m1]
    dyn[:, 16] = 1.0
    return dh_model(dh, name='pp_robot', qlim=[[-_PP_TRAVEL, _PP_TRAVEL]] * 2,
                    joint_names=('d2_vertical', 'd1_horizontal'), dyn=dyn, tool=_PP_TOOL)


ROBOT_NAMES = ('puma560', 'planar_rr', 'planar_rrr', 'cylindrical_rpr', 'pp_robot')
"""Names accepted by :func:`robot_by_name` (each with its default dimensions)."""


def robot_by_name(name: str) -> DHModel:
    """
    Return the built-in robot called ``name`` with its default dimensions.

    Raises
    ------
    ValueError
        For an unknown name; the message lists the known ones.

    Examples
    --------
    >>> robot_by_name('puma560').n
    6

    """
    factories: dict[str, Callable[[], DHModel]] = {
        'puma560': puma560, 'planar_rr': planar_rr, 'planar_rrr': planar_rrr,
        'cylindrical_rpr': cylindrical_rpr, 'pp_robot': pp_robot}
    if name not in factories:
        raise ValueError(f'unknown robot {name!r}; known robots: {", ".join(ROBOT_NAMES)}')
    return factories[name]()
