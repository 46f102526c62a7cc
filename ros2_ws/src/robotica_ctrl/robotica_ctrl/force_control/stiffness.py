"""
Stiffness control (Lewis et al. 1993), book §8.7.2, (8.168)-(8.181) and Ej. 8.10.

The PD law in task coordinates (8.168): ``τ = Ĵᵀ (-K_v x' + K_p x̃) + Ĝ + F̂``, ``x̃ = x_d - x``
(8.169), K_p and K_v diagonal positive definite (per task axis). It regulates to a set point:
the reference's x_d' and x_d'' and the force references are not used. Against an environment
``ψ = K_e (x - x_e)`` (8.164) it is stable (Lyapunov (8.171)-(8.174)) and settles, per axis
(8.175)-(8.178), at ``x(∞) = (K_p x_d + K_e x_e) / (K_p + K_e)`` with
``ψ(∞) = K_e K_p (x_d - x_e) / (K_p + K_e)`` (:func:`stiffness_steady_state`); in free
directions (K_e = 0) at ``x(∞) = x_d`` (8.180). K_p is the arm's stiffness: with ``K_e ≫ K_p``,
``ψ(∞) ≈ K_p (x_d - x_e)`` (8.179, (8.181)), so a force ψ_d asks for the set point
``x_d = ψ_d / K_p + x_e`` (:func:`stiffness_set_point`; Ej. 8.10: 3/10 + 2 = 2.3 m). Without
contact the law is a Cartesian PD with gravity compensation: x → x_d.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import DHModel

from .law import ForceControlLaw, ForceControlTelemetry, TaskReference
from .task_frame import TaskFrame
from ..joint_control.law import gain_field, JointState, per_joint

__all__ = ['StiffnessControl', 'StiffnessGains', 'stiffness_set_point', 'stiffness_steady_state']


def _axis_values(**values: ArrayLike) -> list[NDArray[np.float64]]:
    """Return the values (scalars or (m,)) broadcast to one shape, float64, or ValueError."""
    arrays = []
    for name, value in values.items():
        try:
            array = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError) as err:
            raise ValueError(f'{name} must be a number or a vector, got {value!r}') from err
        if array.ndim > 1 or not np.isfinite(array).all():
            raise ValueError(f'{name} must be a finite scalar or vector (m,), got {value!r}')
        arrays.append(array)
    try:
        return list(np.broadcast_arrays(*arrays))
    except ValueError as err:
        raise ValueError(f'{", ".join(values)} must have the same size, got shapes '
                         f'{[a.shape for a in arrays]}') from err


def stiffness_steady_state(kp: ArrayLike, ke: ArrayLike, x_d: ArrayLike, x_e: ArrayLike
                           ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the steady state ``(x(∞), ψ(∞))`` of stiffness control, per task axis (8.176)-(8.178).

    ``x(∞) = (K_p x_d + K_e x_e) / (K_p + K_e)`` [m] and
    ``ψ(∞) = K_e K_p (x_d - x_e) / (K_p + K_e)`` [N], for the linear environment
    ``ψ = K_e (x - x_e)`` (8.164); with K_e = 0, ``x(∞) = x_d`` and ψ(∞) = 0 (8.180). A
    one-sided surface (that only pushes) gives these only where ψ(∞) >= 0 (x_d beyond x_e);
    elsewhere the arm stays off it at x_d.

    Parameters
    ----------
    kp : array_like, scalar or (m,)
        K_p [N/m] > 0.
    ke : array_like, scalar or (m,)
        K_e [N/m] >= 0, 0 on free axes.
    x_d, x_e : array_like, scalar or (m,)
        Set point and surface position [m] in task coordinates.

    Returns
    -------
    x, psi : ndarray
        In the broadcast shape of the inputs.

    Raises
    ------
    ValueError
        For values that are not finite, K_p <= 0, K_e < 0 or sizes that do not broadcast.

    Examples
    --------
    Ej. 8.10: K_p = 10, K_e1 = 1200 N/m (none along the surface), x_d = (2.3, 2), x_e1 = 2 m.

    >>> x, psi = stiffness_steady_state(10.0, [1200.0, 0.0], [2.3, 2.0], [2.0, 0.0])
    >>> x.round(5).tolist(), psi.round(3).tolist()
    ([2.00248, 2.0], [2.975, 0.0])

    """
    k_p, k_e, xd, xe = _axis_values(kp=kp, ke=ke, x_d=x_d, x_e=x_e)
    if (k_p <= 0.0).any():
        raise ValueError(f'kp must be > 0 N/m, got {kp!r}')
    if (k_e < 0.0).any():
        raise ValueError(f'ke must be >= 0 N/m, got {ke!r}')
    x = (k_p * xd + k_e * xe) / (k_p + k_e)
    return x, k_e * k_p * (xd - xe) / (k_p + k_e)


def stiffness_set_point(psi_d: ArrayLike, kp: ArrayLike, x_e: ArrayLike) -> NDArray[np.float64]:
    """
    Return the set point ``x_d = ψ_d / K_p + x_e`` [m] that asks for the force ψ_d (8.179).

    The approximation ``K_e ≫ K_p``: the force reached is ψ_d K_e / (K_p + K_e)
    (:func:`stiffness_steady_state`). ``psi_d`` [N], ``kp`` [N/m] > 0 and ``x_e`` [m], each a
    scalar or (m,); ValueError for values that are not finite, K_p <= 0 or bad sizes.

    Examples
    --------
    Ej. 8.10: ψ_d1 = 3 N, K_p1 = 10 N/m, x_e1 = 2 m.

    >>> float(stiffness_set_point(3.0, 10.0, 2.0))
    2.3

    """
    psi, k_p, xe = _axis_values(psi_d=psi_d, kp=kp, x_e=x_e)
    if (k_p <= 0.0).any():
        raise ValueError(f'kp must be > 0 N/m, got {kp!r}')
    out: NDArray[np.float64] = psi / k_p + xe
    return out


@dataclass(frozen=True, eq=False)
class StiffnessGains:
    """
    Gains of :class:`StiffnessControl`, per task axis (scalar or (m,)); Ej. 8.10's by default.

    >>> StiffnessGains().kp
    array(10.)
    """

    kp: ArrayLike = 10.0     # K_p [N/m] > 0, the arm's stiffness (8.168), (8.179)
    kv: ArrayLike = 10.0     # K_v [N s/m] > 0

    def __post_init__(self) -> None:
        gain_field(self, 'kp', positive=True)
        gain_field(self, 'kv', positive=True)


class StiffnessControl(ForceControlLaw):
    """
    Stiffness (PD) control in a task frame, book (8.168) (8.189 without friction).

    ``τ = Ĵᵀ (-K_v x' + K_p (x_d - x)) + Ĝ [+ F̂]``; see :class:`ForceControlLaw` for the
    parameters, and the module for the steady state. The measured force enters only the
    telemetry.

    Examples
    --------
    Ej. 8.10 at the start, x = (2, 4) m at rest: τ = Ĵᵀ K_p x̃ + Ĝ with K_p x̃ = (3, -20) N and
    Ĝ = ((m1 + m2) g, 0) in the chain's order [d2, d1].

    >>> from robotica_kin.robots import pp_robot
    >>> from robotica_ctrl.joint_control import JointState
    >>> s = 1 / np.sqrt(2)
    >>> frame = TaskFrame([[s, s], [-s, s], [0, 0]])
    >>> law = StiffnessControl(pp_robot(), frame, grav=[0.0, -9.81, 0.0])
    >>> state = JointState([1 / s, 3 / s], [0.0, 0.0])
    >>> law.update(TaskReference([2.3, 2.0]), state, [0.0, 0.0], 1e-3).round(4)
    array([  6.79  , -12.0208])

    """

    law_name = 'stiffness'

    def __init__(self, model: DHModel | ArrayLike, task_frame: TaskFrame,
                 gains: StiffnessGains | None = None, grav: ArrayLike | None = None, *,
                 use_friction: bool = True) -> None:
        if gains is not None and not isinstance(gains, StiffnessGains):
            raise ValueError(f'gains must be StiffnessGains, got {type(gains).__name__}')
        super().__init__(model, task_frame, grav, use_friction=use_friction)
        self.gains = StiffnessGains() if gains is None else gains
        self._kp = per_joint('kp', self.gains.kp, self.m)
        self._kv = per_joint('kv', self.gains.kv, self.m)

    def update(self, reference: TaskReference, state: JointState, force: ArrayLike,
               dt: float) -> NDArray[np.float64]:
        """Return τ of (8.168) (n,) [N m | N] and set the telemetry; see the base class."""
        psi = self._check(reference, state, force, dt)
        x, x_dot, J = self._kinematics.evaluate(state.q, state.qd)
        task_force = self._kp * (reference.x_d - x) - self._kv * x_dot
        tau = J.T @ task_force + self._gravity(state.q) + self._joint_friction(state.qd)
        self.telemetry = ForceControlTelemetry(
            law=self.law_name, position_reference=reference.x_d, position=x, velocity=x_dot,
            force_reference=self._no_values, force=psi,
            acceleration_command=self._no_values, effort=tau)
        return tau
