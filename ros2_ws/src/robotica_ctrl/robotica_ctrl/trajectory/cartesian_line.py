"""
Straight-line Cartesian paths of a manipulator's tool between two poses (book §10.5).

Book (10.86)-(10.88) (seed catalogue Part 8.6): a pose is described by the origin ``P`` and the
scaled axis ``K = k̂ θ`` of its orientation, and both are interpolated linearly, never the entries
of the rotation matrix. Here the orientation moves by the relative rotation ``R_0ᵀ R_1`` written
as axis-angle and scaled by the path parameter: the shortest rotation between the two
orientations about one fixed axis at a constant rate, which settles the ``(k̂, θ + n·2π)``
ambiguity of (10.88). When the robot is given, every point is solved by inverse kinematics and
the first unreachable one is refused (Craig's problem (1), e.g. the hole of a 2R arm).
"""

from typing import Optional, overload, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.ik import ikine_solve
from robotica_kin.transforms import ishomog
from scipy.spatial.transform import Rotation

__all__ = ['cartesian_line']

LineWithJoints = Tuple[NDArray[np.float64], NDArray[np.float64]]

_S_TOL = 1e-12


def _check_pose(T: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return a 4×4 homogeneous transform as float64, or raise ValueError."""
    arr = np.asarray(T, dtype=np.float64)
    if arr.shape != (4, 4):
        raise ValueError(f'{name} must be a 4x4 homogeneous transform, got shape {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    if not ishomog(arr):
        raise ValueError(f'{name} is not a homogeneous transform (rotation block orthonormal '
                         'with det +1, last row [0 0 0 1])')
    return arr


def _check_path_parameter(s: Union[int, ArrayLike]) -> NDArray[np.float64]:
    """Return the path parameters (m,) in [0, 1] from a count m >= 2 or the values."""
    if np.ndim(s) == 0:
        if isinstance(s, (bool, np.bool_)) or not isinstance(s, (int, np.integer)) or s < 2:
            raise ValueError(f's must be a number of points >= 2 or an array of path '
                             f'parameters in [0, 1], got {s!r}')
        return np.linspace(0.0, 1.0, int(s))
    arr = np.asarray(s, dtype=np.float64)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f's must be a non-empty 1-D array of path parameters, got shape '
                         f'{arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError('s must be finite (no NaN or inf)')
    if np.any(arr < -_S_TOL) or np.any(arr > 1.0 + _S_TOL):
        raise ValueError(f's must lie in [0, 1], got values in [{arr.min():g}, {arr.max():g}]')
    return np.clip(arr, 0.0, 1.0)


def _line_poses(T0: NDArray[np.float64], T1: NDArray[np.float64],
                s: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the poses (m, 4, 4) at path parameters s of the line from T0 to T1."""
    R0 = T0[:3, :3]
    relative = Rotation.from_matrix(R0.T @ T1[:3, :3]).as_rotvec()   # k̂ θ, θ in [0, π]
    poses = np.zeros((s.size, 4, 4))
    poses[:, :3, :3] = R0 @ Rotation.from_rotvec(s[:, np.newaxis] * relative).as_matrix()
    poses[:, :3, 3] = T0[:3, 3] + s[:, np.newaxis] * (T1[:3, 3] - T0[:3, 3])
    poses[:, 3, 3] = 1.0
    return poses


@overload
def cartesian_line(T0: ArrayLike, T1: ArrayLike, s: Union[int, ArrayLike] = ...,
                   dh: None = ..., q0: None = ..., mask: None = ...,
                   stol: float = ...) -> NDArray[np.float64]: ...


@overload
def cartesian_line(T0: ArrayLike, T1: ArrayLike, s: Union[int, ArrayLike] = ..., *,
                   dh: Union[DHModel, ArrayLike], q0: Optional[ArrayLike] = ...,
                   mask: Optional[ArrayLike] = ..., stol: float = ...
                   ) -> LineWithJoints: ...


@overload
def cartesian_line(T0: ArrayLike, T1: ArrayLike, s: Union[int, ArrayLike],
                   dh: Union[DHModel, ArrayLike], q0: Optional[ArrayLike] = ...,
                   mask: Optional[ArrayLike] = ..., stol: float = ...
                   ) -> LineWithJoints: ...


def cartesian_line(T0: ArrayLike, T1: ArrayLike, s: Union[int, ArrayLike] = 11,
                   dh: Optional[Union[DHModel, ArrayLike]] = None,
                   q0: Optional[ArrayLike] = None, mask: Optional[ArrayLike] = None,
                   stol: float = 1e-6) -> Union[NDArray[np.float64], LineWithJoints]:
    """
    Return tool poses on the straight line from T0 to T1, and joint values if a robot is given.

    Book §10.5, eqs. (10.86)-(10.88) (catalogue Part 8.6): at path parameter s ∈ [0, 1] the
    origin is ``p(s) = p_0 + s (p_1 − p_0)`` and the orientation ``R(s) = R_0 Rot(k̂, s θ)``,
    where ``k̂ θ`` (θ ∈ [0, π]) is the axis-angle of ``R_0ᵀ R_1``: the shortest rotation, about
    an axis fixed in the tool frame, at a constant rate. When ``k̂`` is the same for both
    orientations this is the book's linear interpolation of ``K = k̂ θ``; in general it is the
    geodesic, and it turns the short way round (no ``θ + n·2π`` ambiguity, (10.88)). At
    θ = π both senses are shortest and either may be taken.

    With ``dh`` the points are solved in order by :func:`robotica_kin.ik.ikine_solve`, each
    starting from the previous solution (the first from ``q0``), and a point not reached within
    ``stol`` is refused: a straight line may leave the workspace between two reachable ends
    (problem (1) of §10.5, e.g. the hole of radius ``l1 − l2`` of a 2R arm). Speeds near
    singularities (problem (2)) are not checked: time the path, then check the joint rates.

    Parameters
    ----------
    T0, T1 : array_like, shape (4, 4)
        Start and end poses of the tool in {0} [m].
    s : int or array_like, shape (m,)
        Number m >= 2 of equally spaced points, ends included, or the path parameters in [0, 1]
        (time them with a profile, e.g. ``s = q_t`` of a rest-to-rest ``pol3`` from 0 to 1).
    dh : DHModel or array_like, shape (n, 4) or (n, 5), optional
        The robot; without it only the poses are returned.
    q0 : array_like, shape (n,), optional
        Joint values [rad | m] to start the first point's search from (``dh`` only).
    mask : array_like, shape (6,), optional
        HEMERO's M, 0/1 weights of [x y z rx ry rz] of {0} passed to the inverse kinematics;
        a robot with fewer than six joints needs one, e.g. ``[1, 1, 0, 0, 0, 0]`` for a planar
        2R (``dh`` only).
    stol : float
        Largest admissible norm of the masked pose error [m, rad] (``dh`` only).

    Returns
    -------
    poses : ndarray, shape (m, 4, 4)
        The tool poses along the line.
    q : ndarray, shape (m, n)
        Joint values reaching them [rad | m], only when ``dh`` is given (returned as
        ``(poses, q)``).

    Raises
    ------
    ValueError
        If a pose is not a finite homogeneous transform, ``s`` is not a count >= 2 or values in
        [0, 1], ``q0``/``mask`` come without ``dh``, the robot input is bad, or a point of the
        line cannot be reached: the message names the first such point's index and residual.

    Examples
    --------
    >>> from robotica_kin.transforms import rotz, transl
    >>> poses = cartesian_line(transl(0, 0, 0), transl(1, 2, 0) @ rotz(0.5), 3)
    >>> poses[1].round(4)
    array([[ 0.9689, -0.2474,  0.    ,  0.5   ],
           [ 0.2474,  0.9689,  0.    ,  1.    ],
           [ 0.    ,  0.    ,  1.    ,  0.    ],
           [ 0.    ,  0.    ,  0.    ,  1.    ]])

    """
    start = _check_pose(T0, 'T0')
    end = _check_pose(T1, 'T1')
    params = _check_path_parameter(s)
    poses = _line_poses(start, end, params)
    if dh is None:
        if q0 is not None or mask is not None:
            raise ValueError('q0 and mask are inverse-kinematics options: they need dh')
        return poses
    robot = as_dh_model(dh)
    result = ikine_solve(robot, poses, stol=stol, q0=q0, mask=mask)
    reached = np.atleast_1d(result.success)
    if not np.all(reached):
        k = int(np.flatnonzero(~reached.astype(bool))[0])
        residual = float(np.atleast_1d(result.residual)[k])
        raise ValueError(
            f'point {k} of the line (s = {params[k]:.6g}, position '
            f'{np.round(poses[k, :3, 3], 6).tolist()} m) is unreachable: inverse kinematics '
            f'residual {residual:.3g} > stol {stol:g} (outside the workspace, or no '
            'solution within the joint limits)')
    return poses, np.atleast_2d(result.q)
