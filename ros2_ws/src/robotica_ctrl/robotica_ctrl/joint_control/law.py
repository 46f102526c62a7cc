"""
The interface shared by the joint control laws of book ch. 8 (seed catalogue Part 6).

A control law maps a joint reference ``(q_d, q_d', q_d'')`` and the measured joint state
``(q, q')`` to joint torques ``tau`` (n,) [N m] (forces [N] for prismatic joints). The error is
``e = q_d - q`` and ``e' = q_d' - q'`` (book (8.30)-(8.31)). Laws with memory (an integral term,
an adaptation or learning state) keep it in the object: :meth:`JointControlLaw.reset` clears it
and :meth:`JointControlLaw.update` advances it by the sample period ``dt`` [s]. The core reads no
clock and draws no random numbers.
"""

from abc import ABC, abstractmethod
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import all_finite

__all__ = ['JointControlLaw', 'JointReference', 'JointState', 'check_dt', 'gain_field',
           'per_joint']


def _vector(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float64 vector (n,), or raise ValueError (finiteness apart)."""
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be a vector of numbers, got {value!r}') from err
    if array.ndim != 1 or array.size == 0:
        raise ValueError(f'{name} must have shape (n,) with n >= 1, got shape {array.shape}')
    return array


def _checked_rows(names: tuple[str, ...], values: tuple[ArrayLike, ...]) -> NDArray[np.float64]:
    """
    Return ``values`` as the rows of one read-only (len(values), n) float64 array, all finite.

    One allocation and one finiteness test (the squared norm of all of them is finite unless an
    element is not, or the sum overflows) per call, which runs on every control step; only a
    failure looks at each value, to name it in the ValueError.
    """
    try:
        rows = np.array(values, dtype=np.float64)
    except (TypeError, ValueError):
        rows = None   # not numbers, or of different shapes: found and named below
    if rows is None or rows.ndim != 2 or rows.shape[1] == 0:
        shapes = [_vector(name, value).shape for name, value in zip(names, values)]
        raise ValueError(f'{", ".join(names)} must have the same shape, got {shapes}')
    flat = rows.ravel()
    if not math.isfinite(flat.dot(flat)):
        for name, value, row in zip(names, values, rows):
            if not all_finite(row):
                raise ValueError(f'{name} must be finite, got {value!r}')
    rows.setflags(write=False)
    return rows


class _Immutable:
    """Base of the per-step value objects: attributes are set once, in ``__init__``."""

    __slots__ = ()

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f'{type(self).__name__} is immutable')

    def __repr__(self) -> str:
        names: tuple[str, ...] = self.__slots__
        fields = ', '.join(f'{name}={getattr(self, name).tolist()}' for name in names)
        return f'{type(self).__name__}({fields})'


class JointReference(_Immutable):
    """
    A joint-space reference at one instant: q_d [rad | m], q_d' [/s] and q_d'' [/s²], each (n,).

    ``qd_d`` and ``qdd_d`` default to zero (a set point). The attributes are read-only float64
    vectors of one shape; ValueError for any other shape or a value that is not finite.

    >>> JointReference([0.1, 0.2]).qdd_d
    array([0., 0.])
    """

    __slots__ = ('q_d', 'qd_d', 'qdd_d')
    q_d: NDArray[np.float64]
    qd_d: NDArray[np.float64]
    qdd_d: NDArray[np.float64]

    def __init__(self, q_d: ArrayLike, qd_d: ArrayLike | None = None,
                 qdd_d: ArrayLike | None = None) -> None:
        if qd_d is None or qdd_d is None:
            zeros = np.zeros(_vector('q_d', q_d).shape)
            qd_d = zeros if qd_d is None else qd_d
            qdd_d = zeros if qdd_d is None else qdd_d
        rows = _checked_rows(('q_d', 'qd_d', 'qdd_d'), (q_d, qd_d, qdd_d))
        set_field = object.__setattr__
        set_field(self, 'q_d', rows[0])
        set_field(self, 'qd_d', rows[1])
        set_field(self, 'qdd_d', rows[2])

    @property
    def n(self) -> int:
        """Return the number of joints."""
        return len(self.q_d)


class JointState(_Immutable):
    """
    Measured joint positions q [rad | m] and velocities q' [rad/s | m/s], each (n,).

    The attributes are read-only float64 vectors of one shape (ValueError otherwise, or for a
    value that is not finite).

    >>> JointState([0.0, 1.0], [0.0, 0.0]).n
    2
    """

    __slots__ = ('q', 'qd')
    q: NDArray[np.float64]
    qd: NDArray[np.float64]

    def __init__(self, q: ArrayLike, qd: ArrayLike) -> None:
        rows = _checked_rows(('q', 'qd'), (q, qd))
        object.__setattr__(self, 'q', rows[0])
        object.__setattr__(self, 'qd', rows[1])

    @property
    def n(self) -> int:
        """Return the number of joints."""
        return len(self.q)


def check_dt(dt: float) -> float:
    """
    Return the sample period ``dt`` [s] as a float, or raise ValueError unless finite and > 0.

    >>> check_dt(0.001)
    0.001
    """
    try:
        value = float(dt)
    except (TypeError, ValueError) as err:
        raise ValueError(f'dt must be a number of seconds, got {dt!r}') from err
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f'dt must be finite and > 0 s, got {dt!r}')
    return value


def per_joint(name: str, value: ArrayLike, n: int) -> NDArray[np.float64]:
    """
    Return a gain or limit ``value`` (scalar or (n,)) broadcast to shape (n,), float64.

    Raises ValueError for any other size.

    >>> per_joint('kp', 25.0, 2)
    array([25., 25.])
    """
    array = np.asarray(value, dtype=np.float64)
    if array.ndim == 0 or array.shape == (1,):
        return np.full(n, float(array.reshape(-1)[0]))
    if array.shape != (n,):
        raise ValueError(f'{name} must be a scalar or have shape ({n},), got shape {array.shape}')
    return array.copy()


def gain_field(owner: Any, name: str, *, positive: bool = False, allow_inf: bool = False) -> None:
    """
    Validate and freeze the gain field ``name`` of the frozen dataclass ``owner`` (in place).

    The value must be a scalar or a vector of numbers >= 0 (> 0 when ``positive``), finite unless
    ``allow_inf``; it is stored as a read-only float64 array of shape () or (n,).

    Raises
    ------
    ValueError
        For NaN, negative (or zero when ``positive``) or infinite values, or a matrix.

    """
    value = getattr(owner, name)
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be a scalar or a vector, got {value!r}') from err
    if array.ndim > 1 or array.size == 0:
        raise ValueError(f'{name} must be a scalar or a vector (n,), got shape {array.shape}')
    if np.isnan(array).any() or (not allow_inf and not np.isfinite(array).all()):
        raise ValueError(f'{name} must be {"" if allow_inf else "finite and "}not NaN, '
                         f'got {value!r}')
    if (array <= 0.0).any() if positive else (array < 0.0).any():
        raise ValueError(f'{name} must be {">" if positive else ">="} 0, got {value!r}')
    array.setflags(write=False)
    object.__setattr__(owner, name, array)


class JointControlLaw(ABC):
    """
    A joint control law ``tau = law(reference, state)`` with optional memory (book ch. 8).

    Subclasses implement :meth:`reset` and :meth:`update`. ``update`` is called once per control
    period; ``dt`` [s] is the time since the previous call (the integration step of any state).
    """

    @abstractmethod
    def reset(self) -> None:
        """Clear the law's memory (integral, adaptation, learning state)."""

    @abstractmethod
    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return the joint torques tau (n,) [N m] for ``reference`` and ``state``; advance by ``dt``.

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or sizes that do not match each other or the law.

        """

    @staticmethod
    def check_inputs(reference: JointReference, state: JointState, dt: float) -> int:
        """
        Return the number of joints n after checking the inputs of :meth:`update`.

        Raises ValueError for the wrong types, a size mismatch or a bad ``dt``.
        """
        if not isinstance(reference, JointReference) or not isinstance(state, JointState):
            raise ValueError('reference must be a JointReference and state a JointState, got '
                             f'{type(reference).__name__} and {type(state).__name__}')
        check_dt(dt)
        if reference.n != state.n:
            raise ValueError(f'reference has {reference.n} joints but state has {state.n}')
        return state.n
