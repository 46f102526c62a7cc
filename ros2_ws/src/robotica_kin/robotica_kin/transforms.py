"""
Homogeneous transforms of chapter 3 and the HEMERO toolbox (Ollero 2001, §3.2-§3.5, §A.2).

The book follows Craig (1989): ``{}^A P`` is a point P expressed in frame {A}, and the
homogeneous transform ``{}^A_B T = [[{}^A_B R, {}^A P_ORG_B], [0 0 0 1]]`` (3.20) describes
frame {B} in frame {A}: the columns of the rotation block ``{}^A_B R`` are the unit vectors of
the axes of {B} expressed in {A}, the last column is the origin of {B} in {A}, and it maps
augmented points ``{}^A Π = {}^A_B T {}^B Π`` (3.19), with ``Π = [x, y, z, 1]``. In code such
a transform is named ``T_a_b``; transforms compose as ``T_a_c = T_a_b @ T_b_c`` (3.41) and
``trinv(T_a_b)`` is ``T_b_a`` (3.35).

The functions keep the names and semantics of HEMERO (itself derived from Corke's Robotics
Toolbox): rotations are returned as 4×4 homogeneous transforms, angles are in radians unless
``unit='deg'`` is given. RPY angles are roll γ about the fixed X axis, pitch β about the fixed
Y axis, then yaw α about the fixed Z axis, ``R = Rz(α) Ry(β) Rx(γ)`` (3.56); Euler angles are
Z-Y-Z about the moving axes (3.69); quaternions are scalar first, ``[w, x, y, z]`` (fig. 3.20).

Every function checks its input and raises ``ValueError`` naming itself and the problem
(wrong shape, NaN or inf, zero axis, bad unit) instead of returning a wrong number. All
results are float64 arrays, vectors of shape (n,); scalars are Python floats.
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.types import Vector
from scipy.spatial.transform import Rotation

__all__ = [
    'angvec2tr', 'eul2tr', 'ishomog', 'q2tr', 'rotvec', 'rotx', 'roty', 'rotz', 'rpy2tr',
    'tr2angvec', 'tr2eul', 'tr2q', 'tr2rpy', 'transl', 'trinv',
]

HOMOG_TOL = 1e-9
"""Tolerance of :func:`ishomog` and of the last-row check of :func:`trinv`."""

TRINV_ORTHO_TOL = 1e-6
"""Largest |R^T R - I| entry :func:`trinv` accepts (its closed form assumes R^-1 = R^T)."""

SINGULAR_TOL = 1e-12
"""cos β (RPY) or sin β (ZYZ) at or below which the degenerate branch is taken."""

_UNITS = {'rad': 1.0, 'deg': math.pi / 180.0}


def _unit_factor(unit: str, name: str) -> float:
    """Return the factor converting ``unit`` to radians, or raise ValueError."""
    if not isinstance(unit, str) or unit not in _UNITS:
        raise ValueError(f"{name}: unit must be 'rad' or 'deg', got {unit!r}")
    return _UNITS[unit]


def _as_array(
    value: ArrayLike, name: str, what: str, shape: tuple[int, ...]
) -> NDArray[np.float64]:
    """Return ``value`` as a finite float64 array of ``shape``, or raise ValueError."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as error:
        raise ValueError(f'{name}: {what} is not a numeric array ({error})') from None
    if raw.dtype.kind not in 'biuf':
        raise ValueError(f'{name}: {what} must be real numbers, got dtype {raw.dtype}')
    if raw.shape != shape:
        if shape == ():
            raise ValueError(f'{name}: {what} must be a scalar, got shape {raw.shape}')
        raise ValueError(f'{name}: {what} must have shape {shape}, got {raw.shape}')
    array = raw.astype(np.float64)
    if not np.all(np.isfinite(array)):
        raise ValueError(f'{name}: {what} must be finite (it contains NaN or inf)')
    return array


def _as_scalar(value: ArrayLike, name: str, what: str) -> float:
    """Return ``value`` as a finite Python float, or raise ValueError."""
    return float(_as_array(value, name, what, ()))


def _as_transform(T: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return ``T`` as a finite float64 (4, 4) array, or raise ValueError."""
    return _as_array(T, name, 'T', (4, 4))


def _check_last_row(T: NDArray[np.float64], name: str) -> None:
    """Raise ValueError unless the last row of ``T`` is [0, 0, 0, 1] within HOMOG_TOL."""
    if np.max(np.abs(T[3] - (0.0, 0.0, 0.0, 1.0))) > HOMOG_TOL:
        raise ValueError(
            f'{name}: T is not a homogeneous transform, its last row is {T[3].tolist()} '
            'instead of [0, 0, 0, 1]')


def _three_angles(
    first: ArrayLike, second: float | None, third: float | None, name: str, what: str,
    factor: float,
) -> tuple[float, float, float]:
    """Return three angles [rad] given as three scalars or as one array of shape (3,)."""
    if second is None and third is None:
        a, b, c = _as_array(first, name, what, (3,)) * factor
        return float(a), float(b), float(c)
    if second is None or third is None:
        raise ValueError(f'{name}: give three angles or one array of shape (3,), not two')
    names = what.strip('[]').split(', ')
    return (_as_scalar(first, name, names[0]) * factor,
            _as_scalar(second, name, names[1]) * factor,
            _as_scalar(third, name, names[2]) * factor)


def _homogeneous(R: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the 4×4 transform with rotation block ``R`` and no translation."""
    T = np.eye(4)
    T[:3, :3] = R
    return T


def _axis_rotation(axis: int, theta: float) -> NDArray[np.float64]:
    """Return the 4×4 rotation by ``theta`` [rad] about coordinate axis 0 (X), 1 (Y) or 2 (Z)."""
    c, s = math.cos(theta), math.sin(theta)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    T = np.eye(4)
    T[i, i] = c
    T[i, j] = -s
    T[j, i] = s
    T[j, j] = c
    return T


def _rodrigues(v: ArrayLike, theta: ArrayLike, unit: str, name: str) -> NDArray[np.float64]:
    """Return Rot(K̂, θ) (3.25) by Rodrigues' formula, checking inputs in the name of ``name``."""
    factor = _unit_factor(unit, name)
    axis = _as_array(v, name, 'the axis', (3,))
    angle = _as_scalar(theta, name, 'theta') * factor
    norm = math.hypot(*axis)
    if norm == 0.0:
        raise ValueError(f'{name}: the rotation axis must be non-zero, got {axis.tolist()}')
    kx, ky, kz = axis / norm
    K = np.array([[0.0, -kz, ky], [kz, 0.0, -kx], [-ky, kx, 0.0]])
    R = np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)
    return _homogeneous(R)


def transl(
    x: ArrayLike, y: float | None = None, z: float | None = None
) -> NDArray[np.float64]:
    """
    Return the pure translation Tras(Q) (3.21)-(3.23), or the translation of a transform.

    ``transl(x, y, z)`` and ``transl([x, y, z])`` give the 4×4 identity with last column
    ``[x, y, z, 1]``. As in HEMERO and Corke's toolbox, ``transl(T)`` with one 4×4
    homogeneous transform ``T_a_b`` gives instead its translation, the origin of {B} in {A},
    as a vector of shape (3,).

    Parameters
    ----------
    x : float or array_like, shape (3,) or (4, 4)
        The x component of Q [length unit], or the whole vector Q, or a transform T.
    y, z : float, optional
        The y and z components of Q; give both or neither.

    Returns
    -------
    ndarray, shape (4, 4) or (3,)
        The translation transform, or the translation of ``T``.

    Raises
    ------
    ValueError
        If the arguments are not three finite scalars, a finite vector of shape (3,) or a
        finite 4×4 array with last row [0, 0, 0, 1].

    Examples
    --------
    >>> transl(8, 4, 0) @ [1.0, 2.0, 3.0, 1.0]
    array([9., 6., 3., 1.])
    >>> transl(transl([1.0, 2.0, 3.0]))
    array([1., 2., 3.])

    """
    if y is None and z is None:
        shape = np.shape(x)
        if shape == (4, 4):
            T = _as_transform(x, 'transl')
            _check_last_row(T, 'transl')
            return T[:3, 3].copy()
        if shape != (3,):
            raise ValueError(
                'transl: give x, y, z, a vector of shape (3,) or a transform of shape (4, 4), '
                f'got one argument of shape {shape}')
        q = _as_array(x, 'transl', 'Q', (3,))
    elif y is None or z is None:
        raise ValueError('transl: give x, y and z, or one vector of shape (3,)')
    else:
        q = np.array([_as_scalar(x, 'transl', 'x'), _as_scalar(y, 'transl', 'y'),
                      _as_scalar(z, 'transl', 'z')])
    T = np.eye(4)
    T[:3, 3] = q
    return T


def rotx(theta: float, unit: str = 'rad') -> NDArray[np.float64]:
    """
    Return the 4×4 homogeneous rotation Rot(X̂, θ) about the x axis (3.26).

    HEMERO returns a 4×4 homogeneous transform (spatialmath's ``rotx`` returns a 3×3
    rotation matrix). Rows of the rotation block: [1, 0, 0], [0, c, -s], [0, s, c].

    Parameters
    ----------
    theta : float
        Rotation angle θ, counter-clockwise looking down the axis towards the origin.
    unit : {'rad', 'deg'}
        Unit of ``theta``.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``theta`` is not a finite scalar or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> rotx(90, 'deg') @ [0.0, 1.0, 0.0, 1.0]
    array([0., 0., 1., 1.])

    """
    factor = _unit_factor(unit, 'rotx')
    return _axis_rotation(0, _as_scalar(theta, 'rotx', 'theta') * factor)


def roty(theta: float, unit: str = 'rad') -> NDArray[np.float64]:
    """
    Return the 4×4 homogeneous rotation Rot(Ŷ, θ) about the y axis (3.26).

    HEMERO returns a 4×4 homogeneous transform (spatialmath's ``roty`` returns a 3×3
    rotation matrix). Rows of the rotation block: [c, 0, s], [0, 1, 0], [-s, 0, c].

    Parameters
    ----------
    theta : float
        Rotation angle θ, counter-clockwise looking down the axis towards the origin.
    unit : {'rad', 'deg'}
        Unit of ``theta``.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``theta`` is not a finite scalar or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> roty(90, 'deg') @ [0.0, 0.0, 1.0, 1.0]
    array([1., 0., 0., 1.])

    """
    factor = _unit_factor(unit, 'roty')
    return _axis_rotation(1, _as_scalar(theta, 'roty', 'theta') * factor)


def rotz(theta: float, unit: str = 'rad') -> NDArray[np.float64]:
    """
    Return the 4×4 homogeneous rotation Rot(Ẑ, θ) about the z axis (3.26).

    HEMERO returns a 4×4 homogeneous transform (spatialmath's ``rotz`` returns a 3×3
    rotation matrix). Rows of the rotation block: [c, -s, 0], [s, c, 0], [0, 0, 1].

    Parameters
    ----------
    theta : float
        Rotation angle θ, counter-clockwise looking down the axis towards the origin.
    unit : {'rad', 'deg'}
        Unit of ``theta``.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``theta`` is not a finite scalar or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    Ejemplo 3.3: the point [0, 2, 0] rotated 20° about Z (3.29).

    >>> rotz(math.pi / 9) @ [0, 2, 0, 1]
    array([-0.684,  1.879,  0.   ,  1.   ])

    """
    factor = _unit_factor(unit, 'rotz')
    return _axis_rotation(2, _as_scalar(theta, 'rotz', 'theta') * factor)


def rotvec(v: ArrayLike, theta: float, unit: str = 'rad') -> NDArray[np.float64]:
    """
    Return the 4×4 rotation Rot(K̂, θ) by θ about the axis v through the origin (3.25).

    Computed with Rodrigues' formula ``R = I + sin θ K + (1 - cos θ) K²``, K the
    cross-product matrix of the unit axis ``K̂ = v / |v|``.

    Parameters
    ----------
    v : array_like, shape (3,)
        Rotation axis, any non-zero length (it is normalised).
    theta : float
        Rotation angle θ, right-handed about ``v``.
    unit : {'rad', 'deg'}
        Unit of ``theta``.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``v`` is not a finite non-zero vector of shape (3,), ``theta`` is not a finite
        scalar, or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> rotvec([1, 1, 1], 120, 'deg') @ [1.0, 0.0, 0.0, 1.0]  # cycles x -> y -> z
    array([0., 1., 0., 1.])

    """
    return _rodrigues(v, theta, unit, 'rotvec')


def ishomog(T: ArrayLike) -> bool:
    """
    Return whether T is a 4×4 homogeneous transform (3.20).

    True iff ``T`` is a finite real 4×4 array whose rotation block is orthonormal with
    determinant +1 and whose last row is [0, 0, 0, 1], each within :data:`HOMOG_TOL` (1e-9).
    Never raises: anything else (other shapes, NaN, non-numeric input) gives False.

    Parameters
    ----------
    T : array_like
        The candidate transform.

    Returns
    -------
    bool
        Whether ``T`` is a homogeneous transform.

    Examples
    --------
    >>> ishomog(transl(1, 2, 3) @ rotx(0.3))
    True
    >>> ishomog(np.eye(3)), ishomog(np.diag([1.0, 1.0, -1.0, 1.0]))
    (False, False)

    """
    try:
        raw = np.asarray(T)
    except (TypeError, ValueError):
        return False
    if raw.shape != (4, 4) or raw.dtype.kind not in 'biuf':
        return False
    a = raw.astype(np.float64)
    if not np.all(np.isfinite(a)):
        return False
    R = a[:3, :3]
    return bool(
        np.max(np.abs(a[3] - (0.0, 0.0, 0.0, 1.0))) <= HOMOG_TOL
        and np.max(np.abs(R.T @ R - np.eye(3))) <= HOMOG_TOL
        and abs(np.linalg.det(R) - 1.0) <= HOMOG_TOL)


def trinv(T: ArrayLike) -> NDArray[np.float64]:
    """
    Return the inverse of a homogeneous transform by the closed form (3.35).

    ``{}^B_A T = [[{}^A_B R^T, -{}^A_B R^T {}^A P_ORG_B], [0 0 0 1]]``: no general matrix
    inversion. The closed form is the inverse only of a homogeneous transform, so ``T`` must
    have last row [0, 0, 0, 1] (within :data:`HOMOG_TOL`, 1e-9) and an orthonormal rotation
    block (|R^T R - I| entries within :data:`TRINV_ORTHO_TOL`, 1e-6); a matrix typed from
    3-digit printed values is not one, build it with :func:`rotz` etc. instead.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        The transform ``T_a_b``.

    Returns
    -------
    ndarray, shape (4, 4)
        ``T_b_a``.

    Raises
    ------
    ValueError
        If ``T`` is not a finite 4×4 array, its last row is not [0, 0, 0, 1] or its rotation
        block is not orthonormal.

    Examples
    --------
    Ejemplo 3.4: the inverse (3.36) of the robot's transform (3.30).

    >>> trinv(transl(8, 4, 0) @ rotz(math.pi / 9))
    array([[ 0.940,  0.342,  0.   , -8.886],
           [-0.342,  0.940,  0.   , -1.023],
           [ 0.   ,  0.   ,  1.   ,  0.   ],
           [ 0.   ,  0.   ,  0.   ,  1.   ]])

    """
    T = _as_transform(T, 'trinv')
    _check_last_row(T, 'trinv')
    R = T[:3, :3]
    if np.max(np.abs(R.T @ R - np.eye(3))) > TRINV_ORTHO_TOL:
        raise ValueError(
            'trinv: the rotation block of T is not orthonormal (R^T R != I), so the closed '
            'form (3.35) is not its inverse')
    inverse = np.eye(4)
    inverse[:3, :3] = R.T
    inverse[:3, 3] = -R.T @ T[:3, 3]
    return inverse


def rpy2tr(
    roll: ArrayLike, pitch: float | None = None, yaw: float | None = None, unit: str = 'rad'
) -> NDArray[np.float64]:
    """
    Return the rotation of the roll, pitch, yaw angles, ``Rz(α) Ry(β) Rx(γ)`` (3.56).

    Roll γ about the fixed X axis, then pitch β about the fixed Y axis, then yaw α about the
    fixed Z axis (3.54)-(3.55); the same matrix as Z-Y-X Euler angles about the moving axes
    (3.68). The arguments go in HEMERO's order ``rpy2tr(gamma, beta, alpha)``.

    Parameters
    ----------
    roll : float or array_like, shape (3,)
        Roll γ, or the three angles ``[roll, pitch, yaw]``.
    pitch, yaw : float, optional
        Pitch β and yaw α; give both or neither.
    unit : {'rad', 'deg'}
        Unit of the angles.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation ``{}^A_B T`` of the rotated frame {B}, with zero translation.

    Raises
    ------
    ValueError
        If the angles are not three finite scalars or one finite vector of shape (3,), or
        ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> rpy2tr(0.0, 0.0, 90.0, unit='deg') @ [1.0, 0.0, 0.0, 1.0]
    array([0., 1., 0., 1.])

    """
    factor = _unit_factor(unit, 'rpy2tr')
    gamma, beta, alpha = _three_angles(
        roll, pitch, yaw, 'rpy2tr', '[roll, pitch, yaw]', factor)
    return _axis_rotation(2, alpha) @ _axis_rotation(1, beta) @ _axis_rotation(0, gamma)


def tr2rpy(T: ArrayLike, unit: str = 'rad') -> Vector:
    """
    Return the roll, pitch, yaw angles of the rotation of T (3.58)-(3.64).

    With -90° ≤ β ≤ 90° (3.61): ``β = atan2(-r31, sqrt(r11² + r21²))``,
    ``α = atan2(r21, r11)`` (3.62) and γ from (3.58), ``γ = atan2(r32, r33)``, evaluated in
    the equivalent form ``atan2(sα r13 - cα r23, cα r22 - sα r12)`` (the (2,3) and (2,2)
    entries of ``Rz(α)^T R = Ry(β) Rx(γ)``), which stays accurate next to β = ±90°.
    When cos β = sqrt(r11² + r21²) ≤ :data:`SINGULAR_TOL` (1e-12) only α - γ or α + γ is
    defined; the book's choice α = 0 is taken (3.63)-(3.64): β = +90° (r31 < 0) gives
    ``γ = atan2(r12, r22)``, β = -90° gives ``γ = -atan2(r12, r22)``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform whose rotation block is read (translation ignored; orthonormality is
        assumed, not checked).
    unit : {'rad', 'deg'}
        Unit of the returned angles.

    Returns
    -------
    ndarray, shape (3,)
        ``[roll γ, pitch β, yaw α]``, β in [-π/2, π/2], γ and α in [-π, π].

    Raises
    ------
    ValueError
        If ``T`` is not a finite 4×4 array or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> tr2rpy(rpy2tr(10.0, 20.0, 30.0, unit='deg'), unit='deg')
    array([10., 20., 30.])
    >>> tr2rpy(rpy2tr(10.0, 90.0, 30.0, unit='deg'), unit='deg')  # α = 0, γ = 10° - 30°
    array([-20., 90., 0.])

    """
    factor = _unit_factor(unit, 'tr2rpy')
    r = _as_transform(T, 'tr2rpy')[:3, :3]
    cos_beta = math.hypot(r[0, 0], r[1, 0])
    if cos_beta <= SINGULAR_TOL:
        alpha = 0.0
        if r[2, 0] <= 0.0:
            beta = 0.5 * math.pi
            gamma = math.atan2(r[0, 1], r[1, 1])
        else:
            beta = -0.5 * math.pi
            gamma = -math.atan2(r[0, 1], r[1, 1])
    else:
        alpha = math.atan2(r[1, 0], r[0, 0])
        beta = math.atan2(-r[2, 0], cos_beta)
        ca, sa = math.cos(alpha), math.sin(alpha)
        gamma = math.atan2(sa * r[0, 2] - ca * r[1, 2], ca * r[1, 1] - sa * r[0, 1])
    return np.array([gamma, beta, alpha]) / factor


def eul2tr(
    alpha: ArrayLike, beta: float | None = None, gamma: float | None = None, unit: str = 'rad'
) -> NDArray[np.float64]:
    """
    Return the rotation of the Z-Y-Z Euler angles, ``Rz(α) Ry(β) Rz(γ)`` (3.69).

    Rotation α about Z, then β about the new Y, then γ about the new Z (moving axes).

    Parameters
    ----------
    alpha : float or array_like, shape (3,)
        α, or the three angles ``[alpha, beta, gamma]``.
    beta, gamma : float, optional
        β and γ; give both or neither.
    unit : {'rad', 'deg'}
        Unit of the angles.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation ``{}^A_B T`` of the rotated frame {B}, with zero translation.

    Raises
    ------
    ValueError
        If the angles are not three finite scalars or one finite vector of shape (3,), or
        ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> eul2tr(90.0, 90.0, 0.0, unit='deg') @ [0.0, 0.0, 1.0, 1.0]
    array([0., 1., 0., 1.])

    """
    factor = _unit_factor(unit, 'eul2tr')
    a, b, c = _three_angles(alpha, beta, gamma, 'eul2tr', '[alpha, beta, gamma]', factor)
    return _axis_rotation(2, a) @ _axis_rotation(1, b) @ _axis_rotation(2, c)


def tr2eul(T: ArrayLike, unit: str = 'rad') -> Vector:
    """
    Return the Z-Y-Z Euler angles of the rotation of T (3.70)-(3.72).

    With 0 ≤ β ≤ 180° (3.70): ``β = atan2(sqrt(r31² + r32²), r33)``, ``α = atan2(r23, r13)``
    and γ from ``γ = atan2(r32, -r31)``, evaluated in the equivalent form
    ``atan2(cα r21 - sα r11, cα r22 - sα r12)`` (the (2,1) and (2,2) entries of
    ``Rz(α)^T R = Ry(β) Rz(γ)``), which stays accurate next to β = 0 and β = 180°.
    When sin β = sqrt(r31² + r32²) ≤ :data:`SINGULAR_TOL` (1e-12) only α ± γ is defined; the
    book's choice α = 0 is taken (3.71)-(3.72): β = 0 (r33 > 0) gives
    ``γ = atan2(-r12, r11)``, β = 180° gives ``γ = atan2(r12, -r11)``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform whose rotation block is read (translation ignored; orthonormality is
        assumed, not checked).
    unit : {'rad', 'deg'}
        Unit of the returned angles.

    Returns
    -------
    ndarray, shape (3,)
        ``[alpha, beta, gamma]``, β in [0, π], α and γ in [-π, π].

    Raises
    ------
    ValueError
        If ``T`` is not a finite 4×4 array or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> tr2eul(eul2tr(10.0, 20.0, 30.0, unit='deg'), unit='deg')
    array([10., 20., 30.])
    >>> tr2eul(eul2tr(10.0, 0.0, 30.0, unit='deg'), unit='deg')  # α = 0, γ = 10° + 30°
    array([ 0.,  0., 40.])

    """
    factor = _unit_factor(unit, 'tr2eul')
    r = _as_transform(T, 'tr2eul')[:3, :3]
    sin_beta = math.hypot(r[2, 0], r[2, 1])
    if sin_beta <= SINGULAR_TOL:
        alpha = 0.0
        if r[2, 2] >= 0.0:
            beta = 0.0
            gamma = math.atan2(-r[0, 1], r[0, 0])
        else:
            beta = math.pi
            gamma = math.atan2(r[0, 1], -r[0, 0])
    else:
        alpha = math.atan2(r[1, 2], r[0, 2])
        beta = math.atan2(sin_beta, r[2, 2])
        ca, sa = math.cos(alpha), math.sin(alpha)
        gamma = math.atan2(ca * r[1, 0] - sa * r[0, 0], ca * r[1, 1] - sa * r[0, 1])
    return np.array([alpha, beta, gamma]) / factor


def tr2q(T: ArrayLike) -> Vector:
    """
    Return the unit quaternion of the rotation of T, ``[cos(θ/2), k̂ sin(θ/2)]`` (fig. 3.20).

    Scalar first, ``[w, x, y, z]``, for the rotation by θ about the unit axis k̂. Of the two
    quaternions ±q of a rotation the one with w ≥ 0 is returned (when w = 0, the one whose
    first non-zero vector component is positive). Computed by SciPy's ``Rotation``; a
    rotation block that is not quite orthonormal is replaced by the nearest rotation.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform whose rotation block is read (translation ignored).

    Returns
    -------
    ndarray, shape (4,)
        ``[w, x, y, z]``, unit norm, w ≥ 0.

    Raises
    ------
    ValueError
        If ``T`` is not a finite 4×4 array.

    Examples
    --------
    >>> tr2q(rotz(math.pi / 2))  # [cos 45°, 0, 0, sin 45°]
    array([0.70710678, 0.        , 0.        , 0.70710678])

    """
    R = _as_transform(T, 'tr2q')[:3, :3]
    q = Rotation.from_matrix(R).as_quat(canonical=True, scalar_first=True)
    return np.asarray(q, dtype=np.float64)


def q2tr(q: ArrayLike) -> NDArray[np.float64]:
    """
    Return the 4×4 rotation of the quaternion ``q = [w, x, y, z]`` (fig. 3.20).

    ``q`` is normalised first, so ``[cos(θ/2), k̂ sin(θ/2)]`` times any positive or negative
    factor gives the rotation by θ about k̂. Computed by SciPy's ``Rotation``.

    Parameters
    ----------
    q : array_like, shape (4,)
        Quaternion, scalar first, any non-zero norm.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``q`` is not a finite non-zero vector of shape (4,).

    Examples
    --------
    >>> q2tr([1.0, 0.0, 0.0, 1.0]) @ [1.0, 0.0, 0.0, 1.0]  # 90° about Z, not normalised
    array([0., 1., 0., 1.])

    """
    quaternion = _as_array(q, 'q2tr', 'q', (4,))
    if math.hypot(*quaternion) == 0.0:
        raise ValueError('q2tr: the quaternion must be non-zero, got [0, 0, 0, 0]')
    R = Rotation.from_quat(quaternion, scalar_first=True).as_matrix()
    return _homogeneous(np.asarray(R, dtype=np.float64))


def tr2angvec(T: ArrayLike, unit: str = 'rad') -> tuple[float, Vector]:
    """
    Return the angle θ and unit axis k̂ of the rotation of T (axis-angle, §3.5).

    Computed by SciPy's ``Rotation`` (rotation vector θ k̂ with θ in [0, π]). For θ = 0 the
    axis is undefined and [0, 0, 1] is returned; for θ = π, k̂ and -k̂ describe the same
    rotation and either may be returned.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Transform whose rotation block is read (translation ignored).
    unit : {'rad', 'deg'}
        Unit of the returned angle.

    Returns
    -------
    theta : float
        Rotation angle, in [0, π] (or [0, 180] in degrees).
    k : ndarray, shape (3,)
        Unit rotation axis.

    Raises
    ------
    ValueError
        If ``T`` is not a finite 4×4 array or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> tr2angvec(rotx(-30.0, 'deg'), unit='deg')
    (30.0, array([-1.,  0.,  0.]))

    """
    factor = _unit_factor(unit, 'tr2angvec')
    R = _as_transform(T, 'tr2angvec')[:3, :3]
    vector = np.asarray(Rotation.from_matrix(R).as_rotvec(), dtype=np.float64)
    theta = math.hypot(*vector)
    if theta == 0.0:
        return 0.0, np.array([0.0, 0.0, 1.0])
    # Normalised twice: for a subnormal rotation vector (θ ~ 1e-313) the components carry few
    # significant bits, and one division leaves the axis's norm off 1 by about 1e-11.
    axis = vector / theta
    return theta / factor, axis / np.linalg.norm(axis)


def angvec2tr(theta: float, k: ArrayLike, unit: str = 'rad') -> NDArray[np.float64]:
    """
    Return the 4×4 rotation by θ about the axis k (3.25); :func:`rotvec` in HEMERO's order.

    Parameters
    ----------
    theta : float
        Rotation angle θ, right-handed about ``k``.
    k : array_like, shape (3,)
        Rotation axis, any non-zero length (it is normalised).
    unit : {'rad', 'deg'}
        Unit of ``theta``.

    Returns
    -------
    ndarray, shape (4, 4)
        The rotation, with zero translation.

    Raises
    ------
    ValueError
        If ``k`` is not a finite non-zero vector of shape (3,), ``theta`` is not a finite
        scalar, or ``unit`` is not 'rad' or 'deg'.

    Examples
    --------
    >>> angvec2tr(*tr2angvec(rotx(0.5))) @ [0.0, 1.0, 0.0, 1.0]
    array([0.   , 0.878, 0.479, 1.   ])

    """
    return _rodrigues(k, theta, unit, 'angvec2tr')
