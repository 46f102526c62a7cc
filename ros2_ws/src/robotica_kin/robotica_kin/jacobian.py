"""
Manipulator Jacobians in the tool and base frames (book §4.6; HEMERO ``jacobn``, ``jacob0``).

The Jacobian maps joint rates to the velocity ``[v; ω]`` of the tool frame (frame {n} unless
the model has a ``tool``), ``v = J(q) q'`` (4.59)-(4.60): ``v`` is the linear velocity of the
tool frame's origin and ``ω`` the angular velocity, both in the tool's axes for
:func:`jacobn` and in the base frame {0} for :func:`jacob0`; rows ``[vx vy vz ωx ωy ωz]``,
one column per joint.

Two routes, which agree to 1e-12 (tested):

- one configuration of a :class:`~robotica_kin.pinocchio_model.PinocchioArm` (the robot's
  Pinocchio model, built once and kept by the caller, passed in place of the robot):
  Pinocchio's ``computeFrameJacobian`` of the ``tool0`` frame, with reference frame ``LOCAL``
  (velocity of the frame origin, frame axes: exactly HEMERO's ``jacobn``) or
  ``LOCAL_WORLD_ALIGNED`` (the same velocity in world = {0} axes: ``jacob0``), in the caller's
  ``data``. It fuses ``computeJointJacobians``, ``updateFramePlacements`` and
  ``getFrameJacobian`` into one call and was the faster of the two (PUMA 560: about 1.2 us
  against 2.2 us);
- a robot (``DHModel`` or table), or a batch of m configurations: Paul's method ([H]
  (3.13)-(3.22), catalogue §12.2) vectorised over the batch with NumPy, which needs no model
  built. For ``U = {}^i_tool T = [n o a p]`` the column of joint i is
  ``[(z × p)·n, (z × p)·o, (z × p)·a, n_z, o_z, a_z]`` for a revolute joint and
  ``[n_z, o_z, a_z, 0, 0, 0]`` for a prismatic one; ``jacob0 = blkdiag(R, R) jacobn`` with R
  the rotation of ``fkine``.

Timing with ``timeit`` on the PUMA 560 (a shared 2-core machine, per public call including
the input checks): one configuration, Pinocchio 9-13 us against NumPy 190-310 us; 1000
configurations in one (m, n) array, NumPy 1.7-2.5 ms against 10-13 ms for a loop of Pinocchio
calls (break-even near 15-20 configurations). Hence Pinocchio for q of shape (n,) when the
caller keeps an arm, NumPy for (m, n).
"""

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin

from robotica_kin.dh import DHModel
from robotica_kin.pinocchio_model import data_for, PinocchioArm, robot_and_arm

__all__ = ['jacob0', 'jacobn', 'manipulability']


def _frame_jacobian(arm: PinocchioArm, data: Any, q: NDArray[np.float64], reference: object
                    ) -> NDArray[np.float64]:
    """Return Pinocchio's 6×n Jacobian of the tool frame at one configuration ``q``."""
    J: NDArray[np.float64] = pin.computeFrameJacobian(
        arm.model, data_for(arm, data), q, arm.tool_frame, reference)
    return J if J.ndim == 2 else J.reshape(6, 1)    # eigenpy returns a 6×1 matrix as (6,)


def _paul_jacobians(robot: DHModel, q: NDArray[np.float64]
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return ``jacobn`` (m, 6, n) and the tool rotation R (m, 3, 3) by Paul's method, batched.

    ``q`` has shape (m, n). ``U_j = {}^j_tool T = [n o a p]`` is accumulated from the tool
    backwards, ``U_n = T_n_tool`` and ``U_{j-1} = A_j U_j`` with the link transform
    ``A_j = Rot(X, alpha) Tras(X, a) Rot(Z, theta) Tras(Z, d)`` (4.4) applied factor by factor
    to the three rows of ``[R p]`` (cheaper than batched 4×4 products); column j is read from
    ``U_j`` before ``A_j`` is applied, and the last ``U_0`` is ``fkine``.
    """
    m, n = q.shape
    theta = np.where(robot.prismatic, robot.theta, q)
    d = np.where(robot.prismatic, q, robot.d)
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    rows = [np.repeat(robot.tool[k:k + 1, :], m, axis=0) for k in range(3)]   # (m, 4) each
    J = np.zeros((m, 6, n))
    for j in range(n - 1, -1, -1):
        r0, r1, r2 = rows
        if robot.prismatic[j]:
            J[:, :3, j] = r2[:, :3]                  # R^T z = [n_z, o_z, a_z]
        else:
            J[:, :3, j] = r0[:, 3:] * r1[:, :3] - r1[:, 3:] * r0[:, :3]   # R^T (z × p)
            J[:, 3:, j] = r2[:, :3]
        r2[:, 3] += d[:, j]                          # Tras(Z, d); the rows are our own arrays
        c, s = cos_t[:, j:j + 1], sin_t[:, j:j + 1]
        r0, r1 = c * r0 - s * r1, s * r0 + c * r1    # Rot(Z, theta)
        r0[:, 3] += robot.a[j]                       # Tras(X, a)
        if robot.alpha[j] != 0.0:                    # Rot(X, alpha)
            ca, sa = np.cos(robot.alpha[j]), np.sin(robot.alpha[j])
            r1, r2 = ca * r1 - sa * r2, sa * r1 + ca * r2
        rows = [r0, r1, r2]
    R_0_tool = np.stack([row[:, :3] for row in rows], axis=1)
    return J, R_0_tool


def jacobn(dh: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, *,
           data: Any = None) -> NDArray[np.float64]:
    """
    Return the Jacobian in the tool frame (book §4.6, (4.75), (4.80); HEMERO ``jacobn``).

    ``{}^n v = J q'``: the linear velocity of the tool frame's origin and its angular velocity,
    both in the tool frame's axes (frame {n} when the model has no ``tool``), as Paul's method
    computes it ([H] (3.13)-(3.22)).

    Parameters
    ----------
    dh : DHModel, PinocchioArm or array_like, shape (n, 4) or (n, 5)
        The robot (Craig's modified DH, rows ``[alpha a theta d sigma]``); with a
        ``PinocchioArm`` one configuration goes through Pinocchio.
    q : array_like, shape (n,) or (m, n)
        Joint values [rad or m]; one configuration per row.
    data : pinocchio.Data, optional
        Scratch of the arm's model (``arm.model.createData()``), the caller's, for the
        Pinocchio route; a new one per call when omitted.

    Returns
    -------
    ndarray, shape (6, n) or (m, 6, n)
        Rows ``[vx vy vz ωx ωy ωz]`` [m/s, rad/s per unit joint rate], one column per joint.

    Raises
    ------
    ValueError
        For a bad table, a q of the wrong size or with NaN or inf, or a ``data`` without an
        arm or not of the arm's model.

    Examples
    --------
    Ej. 4.6 (4.80), R-P-R robot with l2 = 0.2 at θ1 = 0, d2 = 0.5, θ3 = 0:

    >>> J = jacobn([[0, 0, 0, 0, 0], [np.pi / 2, 0, 0, 0, 1], [0, 0, 0, 0.2, 0]], [0, 0.5, 0])
    >>> J.round(12) + 0.0    # + 0.0 turns -0.0 into 0.0
    array([[0.7, 0. , 0. ],
           [0. , 0. , 0. ],
           [0. , 1. , 0. ],
           [0. , 0. , 0. ],
           [1. , 0. , 0. ],
           [0. , 0. , 1. ]])

    """
    robot, arm = robot_and_arm(dh, data)
    qq = robot.check_q(q)
    if arm is not None and qq.ndim == 1:
        return _frame_jacobian(arm, data, qq, pin.LOCAL)
    J_n = _paul_jacobians(robot, np.atleast_2d(qq))[0]
    return J_n if qq.ndim == 2 else J_n[0]


def jacob0(dh: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, *,
           data: Any = None) -> NDArray[np.float64]:
    """
    Return the Jacobian in the base frame {0} (book (4.59), (4.73), (4.76); HEMERO ``jacob0``).

    ``{}^0 v = J q'``: the linear velocity of the tool frame's origin and its angular velocity,
    both in the axes of {0}; ``jacob0 = blkdiag(R, R) jacobn`` with R the rotation of
    ``fkine(dh, q)``. A zero row means no motion along or about that axis of {0}.

    Parameters
    ----------
    dh : DHModel, PinocchioArm or array_like, shape (n, 4) or (n, 5)
        The robot (Craig's modified DH, rows ``[alpha a theta d sigma]``); with a
        ``PinocchioArm`` one configuration goes through Pinocchio.
    q : array_like, shape (n,) or (m, n)
        Joint values [rad or m]; one configuration per row.
    data : pinocchio.Data, optional
        Scratch of the arm's model (``arm.model.createData()``), the caller's, for the
        Pinocchio route; a new one per call when omitted.

    Returns
    -------
    ndarray, shape (6, n) or (m, 6, n)
        Rows ``[vx vy vz ωx ωy ωz]`` in {0}, one column per joint.

    Raises
    ------
    ValueError
        For a bad table, a q of the wrong size or with NaN or inf, or a ``data`` without an
        arm or not of the arm's model.

    Examples
    --------
    Ej. 4.5 (4.76), planar 3R with l1 = 4, l2 = 3 at q = (0, π/2, 0):

    >>> jacob0([[0, 0, 0, 0], [0, 4, 0, 0], [0, 3, 0, 0]], [0, np.pi / 2, 0]).round(12) + 0.0
    array([[-3., -3.,  0.],
           [ 4.,  0.,  0.],
           [ 0.,  0.,  0.],
           [ 0.,  0.,  0.],
           [ 0.,  0.,  0.],
           [ 1.,  1.,  1.]])

    """
    robot, arm = robot_and_arm(dh, data)
    qq = robot.check_q(q)
    if arm is not None and qq.ndim == 1:
        return _frame_jacobian(arm, data, qq, pin.LOCAL_WORLD_ALIGNED)
    J_n, R = _paul_jacobians(robot, np.atleast_2d(qq))
    J_0 = np.empty_like(J_n)
    for k in range(3):    # blkdiag(R, R) J_n, as broadcast products (faster than stacked @)
        J_0[:, k] = R[:, k, 0:1] * J_n[:, 0] + R[:, k, 1:2] * J_n[:, 1] + R[:, k, 2:3] * J_n[:, 2]
        J_0[:, k + 3] = (R[:, k, 0:1] * J_n[:, 3] + R[:, k, 1:2] * J_n[:, 4]
                         + R[:, k, 2:3] * J_n[:, 5])
    return J_0 if qq.ndim == 2 else J_0[0]


def manipulability(dh: DHModel | PinocchioArm | ArrayLike, q: ArrayLike,
                   mask: ArrayLike | None = None) -> float | NDArray[np.float64]:
    """
    Return Yoshikawa's manipulability ``w = sqrt(det(J J^T))`` of ``jacob0`` (book §4.6).

    ``w`` is zero exactly at a singularity (4.61) and measures how far the arm is from one;
    J is the base-frame Jacobian restricted to the Cartesian rows selected by ``mask``. It is
    computed as the product of the singular values of J, which equals ``sqrt(det(J J^T))``
    but keeps its accuracy near a singularity (the determinant loses half the digits).
    Linear and angular rows have different units, so compare ``w`` only between
    configurations of one robot with one mask.

    Parameters
    ----------
    dh : DHModel, PinocchioArm or array_like, shape (n, 4) or (n, 5)
        The robot (see :func:`jacob0`).
    q : array_like, shape (n,) or (m, n)
        Joint values [rad or m].
    mask : array_like of 0/1, shape (6,), optional
        The rows ``[x y z rot_x rot_y rot_z]`` to keep, as the mask M of ``ikine`` (e.g.
        ``[1, 1, 0, 0, 0, 1]`` for a planar arm); default all six. At most n rows may be
        selected, since ``J J^T`` is singular when there are more rows than joints.

    Returns
    -------
    float or ndarray, shape (m,)
        ``w >= 0`` per configuration.

    Raises
    ------
    ValueError
        For a bad table or q, a mask that is not six 0/1 values with at least one 1, or a
        mask that selects more rows than the robot has joints.

    Examples
    --------
    Planar 2R tip (Ej. 4.5, (4.73)): ``w = l1 l2 |sin θ2|``.

    >>> from robotica_kin.robots import planar_rr
    >>> round(manipulability(planar_rr(4.0, 3.0), [0.3, np.pi / 2], mask=[1, 1, 0, 0, 0, 0]), 12)
    12.0

    """
    robot, arm = robot_and_arm(dh, None)
    rows = np.ones(6, dtype=bool) if mask is None else np.asarray(mask)
    if rows.shape != (6,) or not np.all((rows == 0) | (rows == 1)) or not np.any(rows):
        raise ValueError(f'mask must be six 0/1 values with at least one 1, got {mask!r}')
    rows = rows.astype(bool)
    if np.count_nonzero(rows) > robot.n:
        raise ValueError(
            f'mask selects {np.count_nonzero(rows)} Cartesian rows but {robot.name!r} has '
            f'{robot.n} joints, so J J^T is always singular; select at most {robot.n} rows')
    J = jacob0(robot if arm is None else arm, q)[..., rows, :]
    w = np.linalg.svd(J, compute_uv=False).prod(axis=-1)
    return float(w) if w.ndim == 0 else w
