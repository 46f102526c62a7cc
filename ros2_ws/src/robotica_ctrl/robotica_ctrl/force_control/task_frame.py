"""
The task frame of force control and the task kinematics of an arm in it (book §8.7, (8.190)).

The force laws work in task coordinates ``x = Rᵀ (p(q) - o)`` [m]: ``p(q)`` is the position of
the end effector (the robot's tool frame origin) in the base frame {0}, and the task frame {T}
is constant, with origin ``o`` [m] and axes the columns of ``R`` (3, m) in {0}. Its first
``normal_axes`` axes are normal to the surface (force-controlled), the others tangential
(position-controlled). Then ``x' = J q'`` with the task Jacobian ``J = Rᵀ J_v`` (m, n), J_v the
linear rows of ``jacob0``, and ``x'' = J q'' + J' q'`` (8.190). A force or velocity is taken to
{T} by ``Rᵀ``: the force ψ that the end effector exerts on the environment, measured in {0},
is ``Rᵀ ψ_0`` in task coordinates.

Ej. 8.10: the PP robot (``robotica_kin.robots.pp_robot``, end effector at ``[d1, d2, 0]``) and
the surface at 45° have ``R = [[1, 1], [-1, 1], [0, 0]] / √2``, ``o = 0``, one normal axis:
``x = (1/√2) [d1 - d2; d1 + d2]`` (8.185), ``J = (1/√2) [[1, -1], [1, 1]]`` (8.186) in the
book's joint order.

Orientation is not a task coordinate here: only the position of the end effector.
"""

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import DHModel
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.pinocchio_model import pinocchio_arm

__all__ = ['TaskFrame', 'TaskKinematics']

_ORTHONORMAL_TOLERANCE = 1e-9


def _frozen(array: NDArray[np.float64]) -> NDArray[np.float64]:
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class TaskFrame:
    """
    A constant task frame {T}: axes ``rotation`` (3, m) and ``origin`` (3,) [m] in {0}.

    Attributes
    ----------
    rotation : array_like, shape (3, m)
        ``R``: the task axes as orthonormal columns in the base frame {0}, 1 <= m <= 3; stored
        read-only float64.
    origin : array_like, shape (3,)
        ``o`` [m], the origin of {T} in {0}; default the origin of {0}.
    normal_axes : int
        How many of the first axes are normal to the surface (force-controlled), 0 to m;
        the rest are tangential (position-controlled). Default 1.

    Raises
    ------
    ValueError
        For columns that are not orthonormal, a bad origin or a bad ``normal_axes``.

    Examples
    --------
    Ej. 8.10 (8.185): the end effector at d1 = 3√2, d2 = √2 m is at x = (2, 4) m.

    >>> s = 1 / np.sqrt(2)
    >>> frame = TaskFrame([[s, s], [-s, s], [0, 0]])
    >>> frame.position([3 / s, 1 / s, 0]).round(12).tolist(), frame.axis_names
    ([2.0, 4.0], ('normal_1', 'tangential_1'))

    """

    rotation: ArrayLike
    origin: ArrayLike = (0.0, 0.0, 0.0)
    normal_axes: int = 1

    def __post_init__(self) -> None:
        R = np.array(self.rotation, dtype=np.float64)
        if R.ndim == 1 and R.shape == (3,):
            R = R[:, np.newaxis]
        if R.ndim != 2 or R.shape[0] != 3 or not 1 <= R.shape[1] <= 3:
            raise ValueError(f'rotation must have shape (3, m) with 1 <= m <= 3, got shape '
                             f'{R.shape}')
        if not np.isfinite(R).all() or not np.allclose(
                R.T @ R, np.eye(R.shape[1]), rtol=0.0, atol=_ORTHONORMAL_TOLERANCE):
            raise ValueError(f'rotation must have orthonormal columns (the task axes in {{0}}), '
                             f'got {self.rotation!r}')
        o = np.array(self.origin, dtype=np.float64)
        if o.shape != (3,) or not np.isfinite(o).all():
            raise ValueError(f'origin must be 3 finite values [m] in {{0}}, got {self.origin!r}')
        count = self.normal_axes
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not (
                0 <= count <= R.shape[1]):
            raise ValueError(f'normal_axes must be an integer in [0, {R.shape[1]}], got '
                             f'{count!r}')
        object.__setattr__(self, 'rotation', _frozen(R))
        object.__setattr__(self, 'origin', _frozen(o))
        object.__setattr__(self, 'normal_axes', int(count))

    @property
    def m(self) -> int:
        """Return the number of task coordinates."""
        return int(np.shape(self.rotation)[1])

    @property
    def force_controlled(self) -> NDArray[np.bool_]:
        """Return, per task axis (m,), True for a normal (force-controlled) axis."""
        return np.arange(self.m) < self.normal_axes

    @property
    def axis_names(self) -> tuple[str, ...]:
        """Return the axis names: ``normal_1`` … then ``tangential_1`` …."""
        tangential = self.m - self.normal_axes
        return (tuple(f'normal_{i + 1}' for i in range(self.normal_axes))
                + tuple(f'tangential_{i + 1}' for i in range(tangential)))

    def position(self, point: ArrayLike) -> NDArray[np.float64]:
        """Return ``x = Rᵀ (p - o)`` (m,) [m] of a point ``p`` (3,) [m] given in {0}."""
        return self.to_task(np.asarray(point, dtype=np.float64) - np.asarray(self.origin))

    def to_task(self, vector: ArrayLike) -> NDArray[np.float64]:
        """
        Return the components ``Rᵀ v`` (m,) in {T} of a vector ``v`` (3,) given in {0}.

        For forces [N] and velocities [m/s]; ValueError unless ``v`` is 3 finite values.
        """
        v = np.asarray(vector, dtype=np.float64)
        if v.shape != (3,) or not np.isfinite(v).all():
            raise ValueError(f'the vector must be 3 finite values in {{0}}, got {vector!r}')
        out: NDArray[np.float64] = np.asarray(self.rotation).T @ v
        return out

    def to_base(self, vector: ArrayLike) -> NDArray[np.float64]:
        """
        Return the vector ``R v`` (3,) in {0} of task components ``v`` (m,).

        ValueError unless ``v`` is m finite values.
        """
        v = np.asarray(vector, dtype=np.float64)
        if v.shape != (self.m,) or not np.isfinite(v).all():
            raise ValueError(f'the task vector must be {self.m} finite values, got {vector!r}')
        out: NDArray[np.float64] = np.asarray(self.rotation) @ v
        return out


class TaskKinematics:
    """
    The task kinematics of one robot in one :class:`TaskFrame`, with its Pinocchio scratch.

    ``evaluate(q, qd)`` returns ``x``, ``x'`` and ``J`` through ``robotica_kin``'s ``fkine``
    and ``jacob0`` (Pinocchio route); ``bias_acceleration(q, qd)`` returns ``J' q'``, the task
    acceleration at ``q'' = 0`` (Pinocchio's classical acceleration of the tool frame's origin,
    the term of (8.190)-(8.191)). One object per law: the scratch is its own.

    Examples
    --------
    >>> from robotica_kin.robots import pp_robot
    >>> s = 1 / np.sqrt(2)
    >>> kinematics = TaskKinematics(pp_robot(), TaskFrame([[s, s], [-s, s], [0, 0]]))
    >>> x, x_dot, J = kinematics.evaluate(np.array([1 / s, 3 / s]), np.zeros(2))
    >>> x.round(12).tolist(), (J * np.sqrt(2)).round(12).tolist()    # chain order [d2, d1]
    ([2.0, 4.0], [[-1.0, 1.0], [1.0, 1.0]])

    """

    def __init__(self, robot: DHModel, frame: TaskFrame) -> None:
        if not isinstance(frame, TaskFrame):
            raise ValueError(f'frame must be a TaskFrame, got {type(frame).__name__}')
        self.robot = robot
        self.frame = frame
        self._arm = pinocchio_arm(robot)
        self._data = self._arm.model.createData()
        self._R_T = np.ascontiguousarray(np.asarray(frame.rotation).T)   # Rᵀ (m, 3)
        self._zeros = np.zeros(robot.n)

    def evaluate(self, q: NDArray[np.float64], qd: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """
        Return ``x`` (m,) [m], ``x'`` (m,) [m/s] and ``J`` (m, n) at the joint state (q, q').

        ``q``, ``qd`` are checked float64 vectors (n,) (a ``JointState``'s).
        """
        p = fkine(self._arm, q, data=self._data)[:3, 3]
        J: NDArray[np.float64] = self._R_T @ jacob0(self._arm, q, data=self._data)[:3]
        x: NDArray[np.float64] = self._R_T @ (p - np.asarray(self.frame.origin))
        return x, J @ qd, J

    def bias_acceleration(self, q: NDArray[np.float64],
                          qd: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return ``J' q'`` (m,) [m/s²]: the task acceleration at (q, q') with q'' = 0."""
        model, data = self._arm.model, self._data
        pin.forwardKinematics(model, data, q, qd, self._zeros)
        acceleration: Any = pin.getFrameClassicalAcceleration(
            model, data, self._arm.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        out: NDArray[np.float64] = self._R_T @ acceleration.linear
        return out
