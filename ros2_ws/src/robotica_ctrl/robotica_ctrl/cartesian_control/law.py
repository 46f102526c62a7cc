"""
The interface shared by the Cartesian-space control laws of book §8.6 (seed catalogue §6.6).

A Cartesian law maps a :class:`~.cartesian_reference.CartesianReference` (tool pose T_d,
twist x_d', acceleration x_d'' in the base frame {0}) and the measured
:class:`~robotica_ctrl.joint_control.law.JointState` ``(q, q')`` to joint torques ``tau`` (n,)
[N m]: the simulator takes torques, so every scheme ends in one. The loop is closed through the
forward kinematics, ``x = φ(q)`` (fig. 8.38), and as the joint laws do, a law with memory keeps it
in the object: :meth:`CartesianControlLaw.reset` clears it and :meth:`CartesianControlLaw.update`
advances it by the sample period ``dt`` [s].

Task rows: the Cartesian error has the six rows ``[x y z rx ry rz]`` of {0} (position of the tool
origin, then rotation), and a ``mask`` of six 0/1 values (HEMERO's M, as ``ikine`` takes) keeps
some of them. By default an arm of six or more joints keeps all six; an arm of 3 to 5 joints
controls the position only (``[1 1 1 0 0 0]``); a 2-joint arm the position in the XY plane of
{0} (``[1 1 0 0 0 0]``), where the book's planar arms move (Ej. 4.5, Ej. 5.1). The pose error is
:func:`~robotica_kin.differential_motion.tr2diff` ``(T, T_d)``, ``[p_d − p; sin(ε) k̂]`` for
``R_d = Rot(k̂, ε) R``, and the Jacobian :func:`~robotica_kin.jacobian.jacob0`, both in {0},
restricted to those rows.

After each :meth:`~CartesianControlLaw.update` the law's :attr:`~CartesianControlLaw.telemetry`
holds a :class:`CartesianTelemetry` of that step (None before the first and after
:meth:`~CartesianControlLaw.reset`).

Timing (``timeit``, PUMA 560, one ``update`` on a shared 2-core machine under load): resolved
rate and transpose Jacobian 145-165 µs, operational space 185-200 µs; the input checks of
``tr2diff`` take about 50 µs of it, ``fkine`` 6, ``jacob0`` 4 and the SVD 8.
"""

from abc import ABC, abstractmethod
from dataclasses import dataclass
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_ctrl.joint_control.law import check_dt, gain_field, JointReference, JointState
from robotica_kin.dh import as_dh_model, as_dyn_model, DHModel
from robotica_kin.differential_motion import tr2diff
from robotica_kin.dynamics import set_gravity
from robotica_kin.finite import finite_real
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.pinocchio_model import pinocchio_arm

from .cartesian_reference import CartesianReference

__all__ = ['CartesianControlLaw', 'CartesianGains', 'CartesianTelemetry', 'SINGULAR_RCOND',
           'check_nonsingular', 'task_mask']

SINGULAR_RCOND = 1e-12
"""J counts as singular when its smallest singular value is below this times its largest."""


def task_mask(mask: ArrayLike | None, n: int) -> NDArray[np.bool_]:
    """
    Return the task rows of ``[x y z rx ry rz]`` (bool (6,)) kept for an ``n``-joint arm.

    ``mask`` is six 0/1 values; None takes the default of the module docstring (six rows for
    n >= 6, the position for 3 to 5 joints, x and y for 2). At most ``n`` rows may be kept.

    Raises
    ------
    ValueError
        For a mask that is not six 0/1 values with at least one 1, that keeps more rows than
        the arm has joints, or no mask for a 1-joint arm.

    Examples
    --------
    >>> task_mask(None, 2).astype(int).tolist()
    [1, 1, 0, 0, 0, 0]

    """
    if mask is None:
        if n < 2:
            raise ValueError(f'a {n}-joint arm has no default task rows: give a mask of six 0/1 '
                             'values [x y z rx ry rz]')
        return np.array([True] * 6 if n >= 6 else [True, True, n >= 3, False, False, False])
    values = np.asarray(mask)
    if values.shape != (6,) or not np.isin(values, (0, 1)).all() or not values.any():
        raise ValueError(f'mask must be six 0/1 values [x y z rx ry rz] with at least one 1, '
                         f'got {mask!r}')
    rows = values.astype(bool)
    if rows.sum() > n:
        raise ValueError(f'mask keeps {int(rows.sum())} task rows but the arm has {n} joints: '
                         f'keep at most {n}')
    return rows


@dataclass(frozen=True, eq=False)
class CartesianGains:
    """
    Diagonal Cartesian gains K_p, K_v: scalars or one value per task row (r,).

    Their units are the law's: for :class:`~.operational_space.OperationalSpace` accelerations,
    ``x'' = x_d'' + K_v x̃' + K_p x̃`` (K_p [1/s²], K_v [1/s], default ω_n = 5, critically
    damped, as Ej. 8.1); for :class:`~.transpose_jacobian.TransposeJacobian` the force
    ``ψ = K_p x̃ + K_v x̃'`` (K_p [N/m | N m/rad], K_v [N s/m | N m s/rad]).

    >>> CartesianGains(kp=[25.0, 100.0]).kp
    array([ 25., 100.])
    """

    kp: ArrayLike = 25.0
    kv: ArrayLike = 10.0

    def __post_init__(self) -> None:
        gain_field(self, 'kp')
        gain_field(self, 'kv')


@dataclass(frozen=True, eq=False)
class CartesianTelemetry:
    """
    What one :meth:`CartesianControlLaw.update` saw and decided (task rows r, frame {0}).

    Attributes
    ----------
    pose_error : ndarray, shape (r,)
        x̃ = tr2diff(T, T_d) [m | rad] at the configuration the law linearises about (the
        measured q, or q_d for :class:`~.resolved_rate.ResolvedRate`).
    twist_error : ndarray, shape (r,)
        x̃' = x_d' − J q' [m/s | rad/s] (q_d' for the resolved rate).
    manipulability : float
        Yoshikawa's ``w = sqrt(det(J Jᵀ))`` of the task rows, the product of the singular
        values of J (as :func:`robotica_kin.jacobian.manipulability`).
    min_singular_value : float
        σ_min of J (units of J's rows per joint unit).
    near_singularity : bool
        σ_min < the law's ``singular_threshold``.
    damping : float
        λ of the damped least squares used at this step; 0 for the other schemes and modes.
    cartesian_force : ndarray, shape (r,), or None
        ψ [N | N m] with ``tau = Jᵀ ψ`` (transpose-Jacobian and operational-space laws).
    joint_reference : JointReference or None
        ``(q_d, q_d', q_d'')`` handed to the inner joint law (resolved rate only).

    """

    pose_error: NDArray[np.float64]
    twist_error: NDArray[np.float64]
    manipulability: float
    min_singular_value: float
    near_singularity: bool
    damping: float = 0.0
    cartesian_force: NDArray[np.float64] | None = None
    joint_reference: JointReference | None = None


def check_nonsingular(sigma: NDArray[np.float64], q: NDArray[np.float64] | None = None) -> None:
    """
    Raise ValueError where J of singular values ``sigma`` is singular, naming σ_min and ``q``.

    Singular means σ_min <= :data:`SINGULAR_RCOND` σ_max (``sigma`` in decreasing order, as
    ``numpy.linalg.svd`` returns it): J⁻¹ does not exist there.

    >>> check_nonsingular(np.array([2.0, 0.0]), np.array([0.0, 0.0]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: the Jacobian is singular at q = [0.0, 0.0] (smallest singular value 0): ...
    """
    if not sigma[-1] > SINGULAR_RCOND * sigma[0]:
        where = '' if q is None else f' at q = {np.round(q, 6).tolist()}'
        raise ValueError(f'the Jacobian is singular{where} (smallest singular value '
                         f'{sigma[-1]:.3g}): J⁻¹ does not exist')


def _robot(model: DHModel | ArrayLike, needs_dynamics: bool) -> DHModel:
    """Return the robot of ``model``; one with a ``dyn`` table when ``needs_dynamics``."""
    if needs_dynamics or (not isinstance(model, DHModel) and np.shape(model)[-1:] == (20,)):
        return as_dyn_model(model)
    return as_dh_model(model)


class CartesianControlLaw(ABC):
    """
    A Cartesian-space law ``tau = law(reference, state)`` with optional memory (book §8.6).

    Subclasses implement :meth:`reset` and :meth:`update`; this base holds the robot, its
    kinematics on the task rows and the telemetry.

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 4), (n, 5) or (n, 20)
        The robot (a ``dyn`` table when ``needs_dynamics``).
    mask : array_like, shape (6,), optional
        Task rows of ``[x y z rx ry rz]`` (see :func:`task_mask`).
    singular_threshold : float
        σ_min of J [J's units] below which ``telemetry.near_singularity`` is raised, >= 0.
    needs_dynamics : bool
        The law uses the robot's dynamic parameters.

    """

    def __init__(self, model: DHModel | ArrayLike, mask: ArrayLike | None,
                 singular_threshold: float, needs_dynamics: bool) -> None:
        self.robot = _robot(model, needs_dynamics)
        self.n = self.robot.n
        self.mask = task_mask(mask, self.n)
        self.rows = int(self.mask.sum())
        self.singular_threshold = finite_real('singular_threshold', singular_threshold)
        if self.singular_threshold < 0.0:
            raise ValueError(f'singular_threshold must be >= 0, got {singular_threshold!r}')
        self.telemetry: CartesianTelemetry | None = None
        # The law's Pinocchio arm and scratch, made once: update() runs at the control rate.
        self._arm = pinocchio_arm(self.robot)
        self._data = self._arm.model.createData()

    @abstractmethod
    def reset(self) -> None:
        """Clear the law's memory and its telemetry."""

    @abstractmethod
    def update(self, reference: CartesianReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return the joint torques tau (n,) [N m] for ``reference`` and ``state``; advance by ``dt``.

        Raises
        ------
        ValueError
            For ``dt <= 0``, the wrong types, a number of joints other than the robot's, or
            (schemes that invert J) a singular Jacobian.

        """

    def check_inputs(self, reference: CartesianReference, state: JointState, dt: float) -> None:
        """Raise ValueError for inputs of the wrong type, a bad ``dt`` or the wrong size."""
        if not isinstance(reference, CartesianReference) or not isinstance(state, JointState):
            raise ValueError('reference must be a CartesianReference and state a JointState, '
                             f'got {type(reference).__name__} and {type(state).__name__}')
        check_dt(dt)
        if state.n != self.n:
            raise ValueError(f'the robot {self.robot.name!r} has {self.n} joints, the state has '
                             f'{state.n}')

    def gravity_model(self, grav: ArrayLike | None) -> tuple[Any, Any]:
        """
        Return a Pinocchio model of the robot with gravity ``grav`` [m/s², {0}] and its data.

        A copy of the law's arm model (the arm's own is never changed); ``grav`` None is
        ``[0, 0, −9.81]``. ValueError for a bad ``grav``.
        """
        model = pin.Model(self._arm.model)
        set_gravity(model, grav)
        return model, model.createData()

    def task_kinematics(self, q: NDArray[np.float64], T_d: NDArray[np.float64]
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the pose error x̃ (r,) [m | rad] and the task Jacobian J (r, n) at ``q``."""
        pose = fkine(self._arm, q, data=self._data)
        jacobian = jacob0(self._arm, q, data=self._data)[self.mask]
        return tr2diff(pose, T_d)[self.mask], jacobian

    def step_telemetry(self, pose_error: NDArray[np.float64],
                       twist_error: NDArray[np.float64], sigma: NDArray[np.float64],
                       **extra: Any) -> CartesianTelemetry:
        """Return the :class:`CartesianTelemetry` of a step from its errors and σ of J."""
        return CartesianTelemetry(
            pose_error=pose_error, twist_error=twist_error,
            manipulability=float(math.prod(sigma)), min_singular_value=float(sigma[-1]),
            near_singularity=bool(sigma[-1] < self.singular_threshold), **extra)
