"""
The interface shared by the force control laws of book §8.7 (seed catalogue Part 6, §6.7).

A force law maps a task reference (:class:`TaskReference`), the measured joint state (a
``JointState``: q, q') and the measured contact force ψ (m,) [N] in task coordinates (the force
the end effector exerts on the environment, (8.164)) to joint torques τ (n,) [N m | N]; it
works in the task frame of a :class:`~robotica_ctrl.force_control.task_frame.TaskFrame`. After
each :meth:`ForceControlLaw.update` its :attr:`~ForceControlLaw.telemetry` holds what it
computed (a :class:`ForceControlTelemetry`). The model (M̂, V̂, Ĝ, F̂, Ĵ) is a robot with
dynamics, as for ``robotica_ctrl.joint_control.ComputedTorque``; the core reads no clock.

The linearising law (8.193), shared by the hybrid and the impedance laws, is
``τ = M̂ Ĵ⁻¹ [p - Ĵ' q'] + V̂_m q' + Ĝ + F̂ + Ĵᵀ ψ`` (the book prints ``p - Ĵ q'``: the term
is ``Ĵ' q'``, (8.191)); with an exact model it gives ``x'' = p`` (8.194). ``M̂ q''_c + V̂ + Ĝ``
at ``q''_c = Ĵ⁻¹ (p - Ĵ' q')`` is one recursive Newton-Euler pass (Pinocchio's RNEA).
"""

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.dynamics import set_gravity
from robotica_kin.joint_friction import JointFriction
from robotica_kin.pinocchio_model import build_model

from .task_frame import TaskFrame, TaskKinematics
from ..joint_control.law import _checked_rows, _Immutable, check_dt, JointState

__all__ = ['ForceControlLaw', 'ForceControlTelemetry', 'TaskReference']

_REFERENCE_NAMES = ('x_d', 'xd_d', 'xdd_d', 'psi_d', 'psid_d', 'psidd_d')
_SINGULAR = 1e-9   # Ĵ is singular when its condition number exceeds 1e9


class TaskReference(_Immutable):
    """
    A task reference at one instant, each (m,) in the task frame {T}.

    ``x_d`` [m], ``xd_d`` [m/s], ``xdd_d`` [m/s²]: the position reference and its derivatives
    (tangential axes of the hybrid law; every axis of the stiffness and impedance laws).
    ``psi_d`` [N], ``psid_d`` [N/s], ``psidd_d`` [N/s²]: the force reference ψ_d that the end
    effector should exert on the environment and its derivatives (normal axes of the hybrid
    law). All but ``x_d`` default to zero; a law ignores the entries it does not use. The
    attributes are read-only float64 vectors of one shape; ValueError for any other shape or
    a value that is not finite.

    >>> TaskReference([2.3, 2.0]).psi_d
    array([0., 0.])
    """

    __slots__ = _REFERENCE_NAMES
    x_d: NDArray[np.float64]
    xd_d: NDArray[np.float64]
    xdd_d: NDArray[np.float64]
    psi_d: NDArray[np.float64]
    psid_d: NDArray[np.float64]
    psidd_d: NDArray[np.float64]

    def __init__(self, x_d: ArrayLike, xd_d: ArrayLike | None = None,
                 xdd_d: ArrayLike | None = None, psi_d: ArrayLike | None = None,
                 psid_d: ArrayLike | None = None, psidd_d: ArrayLike | None = None) -> None:
        zeros = np.zeros(np.shape(x_d))
        values = tuple(zeros if v is None else v
                       for v in (x_d, xd_d, xdd_d, psi_d, psid_d, psidd_d))
        rows = _checked_rows(_REFERENCE_NAMES, values)
        for name, row in zip(_REFERENCE_NAMES, rows):
            object.__setattr__(self, name, row)

    @property
    def m(self) -> int:
        """Return the number of task coordinates."""
        return len(self.x_d)


@dataclass(frozen=True, eq=False)
class ForceControlTelemetry:
    """
    What a force law computed in one :meth:`ForceControlLaw.update` (task frame {T}).

    Attributes
    ----------
    law : str
        ``stiffness``, ``hybrid`` or ``impedance``.
    position_reference : ndarray, shape (m,)
        x_d [m]; NaN on the axes whose position the law does not control (normal axes of the
        hybrid law).
    position, velocity : ndarray, shape (m,)
        x [m] and x' [m/s] from the model's kinematics.
    force_reference : ndarray, shape (m,)
        ψ_d [N]; NaN on the axes without a force reference (all but the hybrid law's normal).
    force : ndarray, shape (m,)
        ψ [N], the measured force the end effector exerts on the environment.
    acceleration_command : ndarray, shape (m,)
        p [m/s²] of (8.194), the task acceleration commanded; NaN for the stiffness law.
    effort : ndarray, shape (n,)
        τ [N m | N] returned, joint order.

    """

    law: str
    position_reference: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    force_reference: NDArray[np.float64]
    force: NDArray[np.float64]
    acceleration_command: NDArray[np.float64]
    effort: NDArray[np.float64]


class ForceControlLaw(ABC):
    """
    A force control law ``τ = law(reference, state, ψ)`` in a task frame (book §8.7).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 20)
        The controller's estimate of the robot (M̂, V̂, Ĝ, F̂ and, from its kinematics, Ĵ).
    task_frame : TaskFrame
        The task frame {T} with m task coordinates.
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²] for Ĝ; default ``[0, 0, -9.81]`` (the book's planar
        robots, ``pp_robot`` included, use ``[0, -9.81, 0]``).
    use_friction : bool
        Add F̂(q') of the model's ``dyn`` table (default True).

    Attributes
    ----------
    telemetry : ForceControlTelemetry or None
        The last update's values; None before the first update and after :meth:`reset`.

    """

    law_name = ''

    def __init__(self, model: DHModel | ArrayLike, task_frame: TaskFrame,
                 grav: ArrayLike | None = None, *, use_friction: bool = True) -> None:
        robot = as_dyn_model(model)
        if not isinstance(task_frame, TaskFrame):
            raise ValueError(f'task_frame must be a TaskFrame, got {type(task_frame).__name__}')
        self.model = model
        self.robot = robot
        self.n = robot.n
        self.task_frame = task_frame
        self.m = task_frame.m
        self.use_friction = bool(use_friction)
        self._kinematics = TaskKinematics(robot, task_frame)
        # The law's own dynamics model (its gravity is set here) and scratch, made once.
        self._pin_model = build_model(robot)
        set_gravity(self._pin_model, grav)
        self._pin_data = self._pin_model.createData()
        friction = JointFriction(robot)
        self._friction = friction if self.use_friction and not friction.is_zero else None
        self._no_values = np.full(self.m, np.nan)   # telemetry of what a law does not use
        self._no_values.setflags(write=False)
        self.telemetry: ForceControlTelemetry | None = None

    def reset(self) -> None:
        """Forget the last telemetry (the laws of this package have no other memory)."""
        self.telemetry = None

    @abstractmethod
    def update(self, reference: TaskReference, state: JointState, force: ArrayLike,
               dt: float) -> NDArray[np.float64]:
        """
        Return the joint torques τ (n,) [N m | N] and set :attr:`telemetry`.

        Parameters
        ----------
        reference : TaskReference
            x_d, x_d', x_d'' and ψ_d, ψ_d', ψ_d'' in {T}, each (m,).
        state : JointState
            Measured q, q' (n,).
        force : array_like, shape (m,)
            Measured ψ [N] in {T}: the force the end effector exerts on the environment.
        dt : float
            Time since the previous call [s], > 0.

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, sizes that do not match the model or the task frame, or a
            singular task Jacobian where the law inverts it.

        """

    def _check(self, reference: TaskReference, state: JointState, force: ArrayLike,
               dt: float) -> NDArray[np.float64]:
        """Return ψ as a float64 vector (m,) after checking every input of :meth:`update`."""
        if not isinstance(reference, TaskReference) or not isinstance(state, JointState):
            raise ValueError('reference must be a TaskReference and state a JointState, got '
                             f'{type(reference).__name__} and {type(state).__name__}')
        check_dt(dt)
        if state.n != self.n:
            raise ValueError(f'the model has {self.n} joints, got a state of {state.n}')
        if reference.m != self.m:
            raise ValueError(f'the task frame has {self.m} axes, got a reference of '
                             f'{reference.m}')
        try:
            psi = np.array(force, dtype=np.float64)     # a copy: the telemetry keeps it
        except (TypeError, ValueError):
            psi = np.full(0, np.nan)                     # refused just below, by name
        if psi.shape != (self.m,) or not np.isfinite(psi).all():
            raise ValueError(f'force must be {self.m} finite values [N] in the task frame, '
                             f'got {force!r}')
        return psi

    def _joint_friction(self, qd: NDArray[np.float64]) -> NDArray[np.float64] | float:
        """Return F̂(q') when the law adds friction, else 0."""
        return 0.0 if self._friction is None else self._friction(qd)

    def _gravity(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return Ĝ(q) (n,) for the law's gravity."""
        out: NDArray[np.float64] = pin.computeGeneralizedGravity(self._pin_model, self._pin_data,
                                                                 q)
        return out.copy()

    def _linearising_torque(self, state: JointState, J: NDArray[np.float64],
                            p: NDArray[np.float64], psi: NDArray[np.float64]
                            ) -> NDArray[np.float64]:
        """
        Return (8.193): ``M̂ Ĵ⁻¹ [p - Ĵ' q'] + V̂_m q' + Ĝ + F̂ + Ĵᵀ ψ`` (n,).

        Raises ValueError when Ĵ is singular at q (condition number above 1e9).
        """
        q, qd = state.q, state.qd
        singular_values = np.linalg.svd(J, compute_uv=False)
        if not singular_values[-1] > _SINGULAR * singular_values[0]:
            raise ValueError(f'the task Jacobian is singular at q = {q.tolist()} (singular '
                             f'values {singular_values.tolist()})')
        qdd: NDArray[Any] = np.linalg.solve(J, p - self._kinematics.bias_acceleration(q, qd))
        tau: NDArray[np.float64] = pin.rnea(self._pin_model, self._pin_data, q, qd, qdd)
        return tau + self._joint_friction(qd) + J.T @ psi

    def _square_task(self) -> None:
        """Raise ValueError unless there are as many task coordinates as joints (Ĵ⁻¹)."""
        if self.m != self.n:
            raise ValueError(f'{self.law_name} control inverts the task Jacobian: the task frame '
                             f'needs {self.n} axes (one per joint), got {self.m}')
