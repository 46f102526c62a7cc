"""
Serial manipulators described by Craig's modified Denavit-Hartenberg table (book §4.3).

A HEMERO ``dh`` table has one row per joint, ``[alpha_{i-1}, a_{i-1}, theta_i, d_i, sigma_i]``
(book Table 4.2): the twist and length of the previous link, then the joint angle and offset.
``sigma_i = 0`` marks a revolute joint, any other value a prismatic one; a table with four
columns is all revolute. As in HEMERO, the joint variable (theta_i of a revolute joint, d_i of a
prismatic one) always comes from ``q``: the table's entry for it is ignored.

:class:`DHModel` is that table validated once, with joint limits and names: plain, immutable
data (the Pinocchio model built from it is :mod:`robotica_kin.pinocchio_model`'s). Every
kinematic function accepts a ``DHModel`` or a raw table; :func:`as_dh_model` validates a raw
table on every call, so a loop keeps the model it converted once.
"""

from dataclasses import dataclass, field
import math
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.transforms import ishomog
from robotica_kin.types import Vector

__all__ = ['DHModel', 'as_dh_model', 'as_dyn_model', 'dh_model', 'linktrans']

_DEFAULT_REVOLUTE_LIMIT = math.pi
_DEFAULT_PRISMATIC_LIMIT = 1.0


def _readonly(array: NDArray[Any]) -> NDArray[Any]:
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class DHModel:
    """
    A serial manipulator in Craig's modified DH convention, validated (book §4.3, Table 4.2).

    Build it with :func:`dh_model`; the arrays are read-only.

    Attributes
    ----------
    alpha, a, theta, d : ndarray, shape (n,)
        alpha_{i-1} [rad], a_{i-1} [m], theta_i [rad], d_i [m] of each row. theta_i of a
        revolute joint and d_i of a prismatic joint are the table's placeholders, unused.
    prismatic : ndarray of bool, shape (n,)
        True where sigma_i != 0.
    qlim : ndarray, shape (n, 2)
        Lower and upper joint limits [rad or m].
    name : str
        Robot name.
    joint_names : tuple of str
        One name per joint.
    dyn : ndarray, shape (n, 20), or None
        HEMERO's dynamic table (book §A.3) when the robot has one.
    tool : ndarray, shape (4, 4)
        ``T_n_tool``: the tool frame in the last link frame {n} (Craig's {H} in {M}, book
        (4.1)); the identity unless given. ``fkine`` and the Jacobians are of this frame.

    """

    alpha: Vector
    a: Vector
    theta: Vector
    d: Vector
    prismatic: NDArray[np.bool_]
    qlim: NDArray[np.float64]
    name: str
    joint_names: tuple[str, ...]
    dyn: NDArray[np.float64] | None = None
    tool: NDArray[np.float64] = field(default_factory=lambda: _readonly(np.eye(4)))

    @property
    def n(self) -> int:
        """Return the number of joints."""
        return int(self.alpha.shape[0])

    @property
    def table(self) -> NDArray[np.float64]:
        """Return the HEMERO table, shape (n, 5): ``[alpha a theta d sigma]`` per row."""
        return np.column_stack(
            [self.alpha, self.a, self.theta, self.d, self.prismatic.astype(np.float64)])

    def check_q(self, q: ArrayLike, name: str = 'q') -> NDArray[np.float64]:
        """
        Return ``q`` as float64 of shape (n,) or (m, n), or raise ValueError.

        NaN or infinite joint values and wrong sizes are refused with a message that gives
        the expected shape.
        """
        arr = np.asarray(q, dtype=np.float64)
        if arr.ndim == 0 or arr.ndim > 2 or arr.shape[-1] != self.n:
            raise ValueError(
                f'{name} must have shape ({self.n},) or (m, {self.n}) for the {self.n}-joint '
                f'robot {self.name!r}, got shape {arr.shape}')
        if not np.all(np.isfinite(arr)):
            raise ValueError(f'{name} must be finite, got {arr!r}')
        return arr

    def within_limits(self, q: ArrayLike) -> bool:
        """Return True when every joint value of ``q`` (shape (n,)) lies within :attr:`qlim`."""
        arr = self.check_q(q)
        return bool(np.all(arr >= self.qlim[:, 0]) and np.all(arr <= self.qlim[:, 1]))


def dh_model(dh: ArrayLike, *, name: str = 'robot', qlim: ArrayLike | None = None,
             joint_names: tuple[str, ...] | list[str] | None = None,
             dyn: ArrayLike | None = None, tool: ArrayLike | None = None) -> DHModel:
    """
    Validate a HEMERO DH table and return it as a :class:`DHModel` (book §4.3, Table 4.2).

    Parameters
    ----------
    dh : array_like, shape (n, 4) or (n, 5)
        Rows ``[alpha_{i-1} [rad], a_{i-1} [m], theta_i [rad], d_i [m], sigma_i]``; sigma
        != 0 is prismatic, a missing fifth column means all revolute.
    name : str
        Robot name used in messages.
    qlim : array_like, shape (n, 2), optional
        Joint limits [rad or m]; default ±π for revolute joints and ±1 m for prismatic ones.
    joint_names : sequence of str, optional
        Default ``joint_1`` … ``joint_n``.
    dyn : array_like, shape (n, 20), optional
        HEMERO's dynamic table (book §A.3); its first five columns must equal ``dh``.
    tool : array_like, shape (4, 4), optional
        Homogeneous transform of the tool frame in frame {n}; default the identity.

    Returns
    -------
    DHModel

    Raises
    ------
    ValueError
        For a table of the wrong shape, non-finite values, limits with lower > upper, or a
        name count that does not match.

    Examples
    --------
    >>> robot = dh_model([[0, 0, 0, 0], [0, 1.0, 0, 0]], name='rr')
    >>> robot.n, robot.prismatic.tolist()
    (2, [False, False])
    >>> dh_model([[0, 0, 0]])
    Traceback (most recent call last):
    ...
    ValueError: DH table must have shape (n, 4) or (n, 5), got (1, 3)

    """
    table = np.array(dh, dtype=np.float64)
    if table.ndim == 1 and table.shape[0] in (4, 5):
        table = table[np.newaxis, :]
    if table.ndim != 2 or table.shape[1] not in (4, 5) or table.shape[0] == 0:
        raise ValueError(f'DH table must have shape (n, 4) or (n, 5), got {table.shape}')
    if not np.all(np.isfinite(table)):
        raise ValueError('DH table must be finite (no NaN or inf entries)')
    n = table.shape[0]
    prismatic = (table[:, 4] != 0.0) if table.shape[1] == 5 else np.zeros(n, dtype=bool)
    if qlim is None:
        limit = np.where(prismatic, _DEFAULT_PRISMATIC_LIMIT, _DEFAULT_REVOLUTE_LIMIT)
        limits = np.column_stack([-limit, limit])
    else:
        limits = np.array(qlim, dtype=np.float64)
        if limits.shape != (n, 2):
            raise ValueError(f'qlim must have shape ({n}, 2), got {limits.shape}')
        if np.any(np.isnan(limits)) or np.any(limits[:, 0] > limits[:, 1]):
            raise ValueError(f'qlim rows must be [lower, upper] with lower <= upper, got {limits}')
    names = tuple(joint_names) if joint_names is not None else tuple(
        f'joint_{i + 1}' for i in range(n))
    if len(names) != n or len(set(names)) != n:
        raise ValueError(f'joint_names must be {n} distinct names, got {names}')
    dyn_table = None
    if dyn is not None:
        dyn_table = np.array(dyn, dtype=np.float64)
        if dyn_table.shape != (n, 20):
            raise ValueError(f'dyn table must have shape ({n}, 20), got {dyn_table.shape}')
        if not np.all(np.isfinite(dyn_table)):
            raise ValueError('dyn table must be finite')
        if not np.array_equal(dyn_table[:, :table.shape[1]], table):
            raise ValueError('the first columns of the dyn table must equal the DH table')
        dyn_table = _readonly(dyn_table)
    tool_pose = np.eye(4) if tool is None else np.array(tool, dtype=np.float64)
    if not ishomog(tool_pose):
        raise ValueError(f'tool must be a 4x4 homogeneous transform, got {tool_pose!r}')
    return DHModel(
        alpha=_readonly(table[:, 0].copy()), a=_readonly(table[:, 1].copy()),
        theta=_readonly(table[:, 2].copy()), d=_readonly(table[:, 3].copy()),
        prismatic=_readonly(prismatic), qlim=_readonly(limits), name=name,
        joint_names=names, dyn=dyn_table, tool=_readonly(tool_pose))


def as_dh_model(dh: DHModel | ArrayLike) -> DHModel:
    """
    Return ``dh`` as a :class:`DHModel`: a model unchanged, a raw table validated.

    A raw table gets the defaults of :func:`dh_model` (limits and names) and is validated on
    every call: a caller that converts the same table repeatedly keeps the model instead.
    """
    if isinstance(dh, DHModel):
        return dh
    return dh_model(dh)


def as_dyn_model(dyn: DHModel | ArrayLike) -> DHModel:
    """
    Return ``dyn`` as a :class:`DHModel` that has dynamic parameters, or raise ValueError.

    A :class:`DHModel` must carry a ``dyn`` table; a raw HEMERO ``dyn`` table (n, 20) (book
    §A.3, its first five columns the DH table) is validated on every call, like
    :func:`as_dh_model`'s tables.
    """
    if isinstance(dyn, DHModel):
        if dyn.dyn is None:
            raise ValueError(f'robot {dyn.name!r} has no dyn table (dynamic parameters)')
        return dyn
    table = np.asarray(dyn, dtype=np.float64)
    if table.ndim != 2 or table.shape[1] != 20 or table.shape[0] == 0:
        raise ValueError(f'dyn must be a DHModel with dynamics or an (n, 20) HEMERO table, got '
                         f'shape {table.shape}')
    return dh_model(table[:, :5], dyn=table)


@overload
def linktrans(alpha: ArrayLike, a: float) -> NDArray[np.float64]: ...


@overload
def linktrans(alpha: float, a: float, theta: float, d: float) -> NDArray[np.float64]: ...


def linktrans(alpha: Any, a: float, theta: float | None = None,
              d: float | None = None) -> NDArray[np.float64]:
    """
    Return Craig's link transform ``T_{i-1}_i`` (book (4.4)-(4.5), HEMERO ``linktrans``).

    Two forms, as in HEMERO: ``linktrans(alpha, a, theta, d)`` with the four DH values, and
    ``linktrans(dh_row, q)`` with one table row ``[alpha a theta d (sigma)]`` and the joint
    value ``q`` that replaces theta (revolute, sigma = 0 or absent) or d (prismatic).

    The transform is ``Rot(X, alpha) Tras(X, a) Rot(Z, theta) Tras(Z, d)``: frame {i} in
    frame {i-1}; angles in rad, lengths in m.

    Raises
    ------
    ValueError
        For a row that is not 4 or 5 long, or non-finite values.

    Examples
    --------
    >>> linktrans(math.pi / 2, 0.0, 0.0, 0.5).round(3)    # Ej. 4.2 (4.16) with d2 = 0.5
    array([[ 1. ,  0. ,  0. ,  0. ],
           [ 0. ,  0. , -1. , -0.5],
           [ 0. ,  1. ,  0. ,  0. ],
           [ 0. ,  0. ,  0. ,  1. ]])
    >>> np.allclose(linktrans([math.pi / 2, 0, 0, 426, 1], 0.5), linktrans(math.pi / 2, 0, 0, 0.5))
    True

    """
    if theta is None and d is None:
        row = np.asarray(alpha, dtype=np.float64)
        if row.shape not in ((4,), (5,)):
            raise ValueError(f'linktrans(dh_row, q): dh_row must have 4 or 5 entries, got '
                             f'shape {row.shape}')
        q = float(a)
        prismatic = row.shape[0] == 5 and row[4] != 0.0
        values = (row[0], row[1], row[2] if prismatic else q, q if prismatic else row[3])
    elif theta is not None and d is not None:
        values = (float(alpha), float(a), float(theta), float(d))
    else:
        raise ValueError('linktrans takes (alpha, a, theta, d) or (dh_row, q)')
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f'linktrans: values must be finite, got {values}')
    al, aa, th, dd = values
    ca, sa, ct, st = math.cos(al), math.sin(al), math.cos(th), math.sin(th)
    return np.array([
        [ct, -st, 0.0, aa],
        [st * ca, ct * ca, -sa, -sa * dd],
        [st * sa, ct * sa, ca, ca * dd],
        [0.0, 0.0, 0.0, 1.0]])
