"""
Differential motions of frames (Paul 1981; HEMERO ``tr2diff``, ``diff2tr``, ``tr2jac``).

The HEMERO manual ([H] (3.1)-(3.6), (3.23)-(3.27), seed catalogue §12.2) describes a small
motion of a frame by the 6-vector ``D = [dx dy dz δx δy δz]``: a translation ``d`` and a
rotation ``δ`` (a small angle about each axis, rad), both in the axes of one reference frame.
Its differential matrix is ``Δ = Tras(d) Rot(k, dθ) - I`` (3.1), to first order (3.5)::

    Δ = [[  0, -δz,  δy, dx],
         [ δz,   0, -δx, dy],
         [-δy,  δx,   0, dz],
         [  0,   0,   0,  0]]

(the book prints ``+δx`` at row 2, column 3 in (3.6) and (3.24): a misprint, Δ's rotation
block is skew-symmetric). :func:`diff2tr` builds Δ from D and :func:`tr2diff` reads D back from
Δ, or measures the motion between two poses, the error ``ikine`` drives to zero.
:func:`tr2jac` re-expresses a velocity or a differential motion in another frame.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.transforms import HOMOG_TOL, TRINV_ORTHO_TOL
from robotica_kin.types import Vector

__all__ = ['diff2tr', 'tr2diff', 'tr2jac']


def _finite(value: ArrayLike, shape: tuple[int, ...], name: str, what: str) -> NDArray[np.float64]:
    """Return ``value`` as a finite float64 array of ``shape``, or raise ValueError."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f'{name}: {what} is not a numeric array ({error})') from None
    if array.shape != shape:
        raise ValueError(f'{name}: {what} must have shape {shape}, got {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'{name}: {what} must be finite (it contains NaN or inf)')
    return array


def _homogeneous(T: ArrayLike, name: str, what: str) -> NDArray[np.float64]:
    """Return ``T`` as a (4, 4) homogeneous transform (3.20), or raise ValueError."""
    array = _finite(T, (4, 4), name, what)
    if np.max(np.abs(array[3] - (0.0, 0.0, 0.0, 1.0))) > HOMOG_TOL:
        raise ValueError(f'{name}: {what} is not a homogeneous transform, its last row is '
                         f'{array[3].tolist()} instead of [0, 0, 0, 1]')
    R = array[:3, :3]
    if np.max(np.abs(R.T @ R - np.eye(3))) > TRINV_ORTHO_TOL:
        raise ValueError(f'{name}: the rotation block of {what} is not orthonormal (R^T R != I)')
    return array


def _skew(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the cross-product matrix S(p), ``S(p) x = p × x``."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def diff2tr(D: ArrayLike) -> NDArray[np.float64]:
    """
    Return the differential matrix Δ of a differential motion D ([H] (3.5), HEMERO ``diff2tr``).

    Parameters
    ----------
    D : array_like, shape (6,)
        ``[dx dy dz δx δy δz]``: differential translation [m] and rotation [rad] in the axes of
        a reference frame.

    Returns
    -------
    ndarray, shape (4, 4)
        Δ of (3.5): rotation block ``S(δ)`` (skew-symmetric, ``-δx`` at row 2, column 3, where
        the printed (3.6) and (3.24) have ``+δx``), last column ``[dx dy dz 0]``, last row 0.
        To first order, a frame T moved by D (both in the reference frame) is ``T + Δ T``.

    Raises
    ------
    ValueError
        If ``D`` is not a finite array of shape (6,).

    Examples
    --------
    >>> diff2tr([1, 2, 3, 0.1, 0.2, 0.3])
    array([[ 0. , -0.3,  0.2,  1. ],
           [ 0.3,  0. , -0.1,  2. ],
           [-0.2,  0.1,  0. ,  3. ],
           [ 0. ,  0. ,  0. ,  0. ]])

    """
    d = _finite(D, (6,), 'diff2tr', 'D')
    delta = np.zeros((4, 4))
    delta[:3, :3] = _skew(d[3:])
    delta[:3, 3] = d[:3]
    return delta


def tr2diff(T1: ArrayLike, T2: ArrayLike | None = None) -> Vector:
    """
    Return a differential motion D = ``[dx dy dz δx δy δz]`` (HEMERO ``tr2diff``, [H] §3).

    Two forms, as in HEMERO:

    - ``tr2diff(Delta)``: D read from a differential matrix of the form (3.5): the
      translations from the last column and each rotation as the mean of its two entries,
      ``δx = (Δ[2,1] - Δ[1,2]) / 2``, ``δy = (Δ[0,2] - Δ[2,0]) / 2``,
      ``δz = (Δ[1,0] - Δ[0,1]) / 2``, which also averages out a matrix that is only
      approximately skew-symmetric (such as ``(T2 - T1) T1^-1``); the inverse of :func:`diff2tr`.
    - ``tr2diff(T1, T2)``: the motion from pose T1 to pose T2, (3.25)-(3.26),
      ``D = [p2 - p1; (n1 × n2 + o1 × o2 + a1 × a2) / 2]`` with n, o, a, p the columns of each
      transform. Both parts are in the axes of the frame T1 and T2 are given in (the base frame
      for poses from ``fkine``): ``d`` is the displacement of the origin and, for
      ``R2 = Rot(k, ε) R1``, ``δ = sin(ε) k`` exactly, a rotation about an axis through the
      origin of T1. This is the velocity convention of :func:`~robotica_kin.jacobian.jacob0`
      (v of the tool origin, ω, both in {0}), so ``D ≈ jacob0(dh, q) dq`` for
      ``T2 = fkine(dh, q + dq)``, and ``ikine`` uses D as its error.

    Parameters
    ----------
    T1 : array_like, shape (4, 4)
        A differential matrix (one-argument form) or the start pose (two-argument form).
    T2 : array_like, shape (4, 4), optional
        The end pose, in the same reference frame as T1.

    Returns
    -------
    ndarray, shape (6,)
        ``[dx dy dz]`` [m] and ``[δx δy δz]`` [rad].

    Raises
    ------
    ValueError
        If an argument is not a finite 4×4 array, a differential matrix's last row is not
        zero (a pose passed to the one-argument form), or a pose is not a homogeneous
        transform (last row [0 0 0 1], orthonormal rotation).

    Examples
    --------
    >>> from robotica_kin.transforms import rotz, transl
    >>> tr2diff(diff2tr([1, 2, 3, 0.1, 0.2, 0.3]))
    array([1. , 2. , 3. , 0.1, 0.2, 0.3])
    >>> tr2diff(transl(1, 0, 0), transl(1, 0.5, 0) @ rotz(np.pi / 6))
    array([0. , 0.5, 0. , 0. , 0. , 0.5])

    """
    if T2 is None:
        delta = _finite(T1, (4, 4), 'tr2diff', 'the differential matrix')
        if np.max(np.abs(delta[3])) > HOMOG_TOL:
            raise ValueError(
                'tr2diff: a differential matrix (3.5) has last row [0, 0, 0, 0], got '
                f'{delta[3].tolist()}; for the motion between two poses call tr2diff(T1, T2)')
        rotation = 0.5 * np.array([delta[2, 1] - delta[1, 2], delta[0, 2] - delta[2, 0],
                                   delta[1, 0] - delta[0, 1]])
        return np.concatenate([delta[:3, 3], rotation])
    pose1 = _homogeneous(T1, 'tr2diff', 'T1')
    pose2 = _homogeneous(T2, 'tr2diff', 'T2')
    rotation = 0.5 * np.cross(pose1[:3, :3], pose2[:3, :3], axis=0).sum(axis=1)
    return np.concatenate([pose2[:3, 3] - pose1[:3, 3], rotation])


def tr2jac(T: ArrayLike) -> NDArray[np.float64]:
    """
    Return the 6×6 matrix that carries a velocity from frame {A} to frame {B} ([H] (3.27)).

    For ``T = {}^A_B T`` (frame {B} in {A}, rotation R, origin p), ``{}^B v = J {}^A v`` with
    ``v = [v; ω]``, where ``{}^A v`` is the velocity of the point of a rigid body at the
    origin of {A} and its angular velocity, both in {A} axes, and ``{}^B v`` the same motion
    seen at the origin of {B} in {B} axes: ``v_B = R^T (v_A + ω × p)``, ``ω_B = R^T ω``, so::

        J = [[R^T, -R^T S(p)],
             [0,    R^T     ]]

    with S(p) the cross-product matrix. It maps differential motions alike (Paul): for
    ``D_B = J D_A``, ``diff2tr(D_B) = T^-1 diff2tr(D_A) T``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        ``{}^A_B T``, a homogeneous transform (lengths in m).

    Returns
    -------
    ndarray, shape (6, 6)
        ``{}^B J_A``.

    Raises
    ------
    ValueError
        If ``T`` is not a finite homogeneous transform (last row [0 0 0 1], orthonormal R).

    Examples
    --------
    A turn about Z_A at 1 rad/s moves the origin of {B} = ``transl(1, 0, 0)`` along Y:

    >>> from robotica_kin.transforms import transl
    >>> tr2jac(transl(1, 0, 0)) @ [0, 0, 0, 0, 0, 1]
    array([0., 1., 0., 0., 0., 1.])

    """
    pose = _homogeneous(T, 'tr2jac', 'T')
    Rt = pose[:3, :3].T
    J = np.zeros((6, 6))
    J[:3, :3] = Rt
    J[:3, 3:] = -Rt @ _skew(pose[:3, 3])
    J[3:, 3:] = Rt
    return J
