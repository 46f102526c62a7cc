"""
The reference of the Cartesian-space control laws of book §8.6: tool pose, twist, acceleration.

Book (8.155)-(8.157) (seed catalogue §6.6): the laws of fig. 8.39-8.41 take the desired motion
of the tool as ``x_d``, ``x_d'`` and ``x_d''`` instead of a joint trajectory. Here ``x_d`` is the
pose ``T_d`` (4×4, the tool frame in the base frame {0}), and the twist ``[v; ω]`` and its
derivative ``[v'; ω']`` are 6-vectors in the axes of {0}, ``v`` the velocity of the tool frame's
origin: the convention of :func:`~robotica_kin.jacobian.jacob0` (``x' = J q'``) and of the pose
error :func:`~robotica_kin.differential_motion.tr2diff`.

:func:`line_references` samples one from the straight line of
:func:`~robotica_ctrl.trajectory.cartesian_line.cartesian_line` (§10.5) timed by a path profile
``s(t)``.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.joint_control.law import _checked_rows, _Immutable
from robotica_ctrl.trajectory.cartesian_line import _check_pose, cartesian_line
from scipy.spatial.transform import Rotation

__all__ = ['CartesianReference', 'line_references']


class CartesianReference(_Immutable):
    """
    The desired tool motion at one instant: pose T_d, twist x_d' and acceleration x_d''.

    Attributes (read-only float64 arrays, base frame {0}):

    - ``T_d`` (4, 4): the tool pose, a homogeneous transform [m];
    - ``xd_d`` (6,): the twist ``[vx vy vz ωx ωy ωz]`` [m/s, rad/s], ``v`` of the tool origin;
    - ``xdd_d`` (6,): its time derivative [m/s², rad/s²].

    ``xd_d`` and ``xdd_d`` default to zero (a set point). ValueError for a ``T_d`` that is not a
    finite homogeneous transform or vectors not of shape (6,) or not finite.

    >>> from robotica_kin.transforms import transl
    >>> CartesianReference(transl(1.0, 0.0, 0.5)).xd_d
    array([0., 0., 0., 0., 0., 0.])
    """

    __slots__ = ('T_d', 'xd_d', 'xdd_d')
    T_d: NDArray[np.float64]
    xd_d: NDArray[np.float64]
    xdd_d: NDArray[np.float64]

    def __init__(self, T_d: ArrayLike, xd_d: ArrayLike | None = None,
                 xdd_d: ArrayLike | None = None) -> None:
        pose = _check_pose(T_d, 'T_d').copy()
        pose.setflags(write=False)
        zeros = np.zeros(6)
        rows = _checked_rows(('xd_d', 'xdd_d'), (zeros if xd_d is None else xd_d,
                                                 zeros if xdd_d is None else xdd_d))
        if rows.shape[1] != 6:
            raise ValueError(f'xd_d and xdd_d must have shape (6,), got ({rows.shape[1]},)')
        object.__setattr__(self, 'T_d', pose)
        object.__setattr__(self, 'xd_d', rows[0])
        object.__setattr__(self, 'xdd_d', rows[1])


def line_references(T0: ArrayLike, T1: ArrayLike, s: ArrayLike, sd: ArrayLike,
                    sdd: ArrayLike) -> list[CartesianReference]:
    """
    Return the references along the straight line from T0 to T1 timed by ``s(t)`` (book §10.5).

    The poses are :func:`~robotica_ctrl.trajectory.cartesian_line.cartesian_line`'s at the path
    parameters ``s``: ``p(s) = p_0 + s (p_1 − p_0)``, ``R(s) = R_0 Rot(k̂, s θ)`` with ``k̂ θ``
    the axis-angle of ``R_0ᵀ R_1``. The axis ``R_0 k̂`` is fixed in {0}, so the twist is the
    constant direction ``D = [p_1 − p_0; R_0 k̂ θ]`` times ``s'`` and the acceleration ``D s''``,
    exactly (no differentiation of samples).

    Parameters
    ----------
    T0, T1 : array_like, shape (4, 4)
        Start and end poses of the tool in {0} [m].
    s, sd, sdd : array_like, shape (m,)
        The path profile at the sample times: ``s`` in [0, 1], ``s'`` [1/s], ``s''`` [1/s²];
        e.g. the ``q_t, qd_t, qdd_t`` of a rest-to-rest ``pol5([0, 1], [0, 0], [0, 0], 0, T, dt)``.

    Returns
    -------
    list of CartesianReference
        One reference per sample.

    Raises
    ------
    ValueError
        For a pose that is not a finite homogeneous transform, ``s`` outside [0, 1], or
        profiles that are not finite vectors of one shape (m,).

    Examples
    --------
    >>> from robotica_kin.transforms import transl
    >>> refs = line_references(transl(0, 0, 0), transl(2, 0, 0), [0.0, 0.5], [0.0, 1.5],
    ...                        [3.0, 0.0])
    >>> refs[1].T_d[:3, 3], refs[1].xd_d, refs[0].xdd_d
    (array([1., 0., 0.]), array([3., 0., 0., 0., 0., 0.]), array([6., 0., 0., 0., 0., 0.]))

    """
    if np.ndim(s) != 1:
        raise ValueError(f's must be a vector (m,) of path parameters, got shape {np.shape(s)}')
    path, rate, acceleration = _checked_rows(('s', 'sd', 'sdd'), (s, sd, sdd))
    poses = cartesian_line(T0, T1, path)   # checks the poses and s in [0, 1]
    start, end = np.asarray(T0, dtype=np.float64), np.asarray(T1, dtype=np.float64)
    R0 = start[:3, :3]
    direction = np.concatenate([end[:3, 3] - start[:3, 3],
                                R0 @ Rotation.from_matrix(R0.T @ end[:3, :3]).as_rotvec()])
    return [CartesianReference(poses[k], direction * rate[k], direction * acceleration[k])
            for k in range(path.size)]
