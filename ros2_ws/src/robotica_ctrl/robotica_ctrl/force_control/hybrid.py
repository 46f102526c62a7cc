"""
Hybrid force/position control (Raibert & Craig 1981, as Lewis et al.), book §8.7.3, Ej. 8.11.

The linearising law (8.193) ``τ = M̂ Ĵ⁻¹ [p - Ĵ' q'] + V̂_m q' + Ĝ + F̂ + Ĵᵀ ψ`` gives
``x'' = p`` (8.194) with an exact model (the book prints ``p - Ĵ q'`` in (8.193) and ``Ĵ' ψ``
in (8.210); the terms are ``Ĵ' q'`` and ``Ĵᵀ ψ``). The task axes are split by the task frame:

- tangential (position) axes (8.197)-(8.200): ``p_T = x_Td'' + K_Tv x̃_T' + K_Tp x̃_T``,
  ``x̃_T = x_Td - x_T``, so that ``x̃_T'' + K_Tv x̃_T' + K_Tp x̃_T = 0``;
- normal (force) axes (8.201)-(8.207): with ``ψ_N = K_e (x_N - x_e)``, ``x_N'' = ψ_N'' / K_e``
  and ``p_N = (ψ_Nd'' + K_Nv ψ̃_N' + K_Np ψ̃_N) / K_e``, ``ψ̃_N = ψ_Nd - ψ_N`` (8.204), so that
  ``ψ̃_N'' + K_Nv ψ̃_N' + K_Np ψ̃_N = 0``.

ψ_N is the measured force. Its derivative is estimated from the model (8.201) as
``ψ_N' = K_e x_N'`` (the velocity of the model's kinematics), exactly as the book's closed loop
(8.214) writes it: no differentiation of a noisy force signal. Out of contact (ψ_N = 0) the
same estimate makes the approach a damped motion, ``x_N'' = -K_Nv x_N' + (ψ_Nd'' + K_Nv ψ_Nd'
+ K_Np ψ_Nd) / K_e``: the end effector nears the surface at the speed
``K_Np ψ_Nd / (K_Nv K_e)`` for a constant ψ_Nd, instead of accelerating into it.

The law inverts Ĵ: the task frame has one axis per joint.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import DHModel

from .law import ForceControlLaw, ForceControlTelemetry, TaskReference
from .task_frame import TaskFrame
from ..joint_control.law import gain_field, JointState, per_joint

__all__ = ['HybridForcePosition', 'HybridGains']


@dataclass(frozen=True, eq=False)
class HybridGains:
    """
    Gains of :class:`HybridForcePosition`, > 0, scalar or one per axis of their kind.

    Defaults: Ej. 8.11's 15 for all four (8.213).

    >>> HybridGains().kp_normal
    array(15.)
    """

    kp_tangential: ArrayLike = 15.0   # K_Tp [1/s²], position loop (8.197)
    kv_tangential: ArrayLike = 15.0   # K_Tv [1/s]
    kp_normal: ArrayLike = 15.0       # K_Np [1/s²], force loop (8.205)
    kv_normal: ArrayLike = 15.0       # K_Nv [1/s]

    def __post_init__(self) -> None:
        for name in ('kp_tangential', 'kv_tangential', 'kp_normal', 'kv_normal'):
            gain_field(self, name, positive=True)


class HybridForcePosition(ForceControlLaw):
    """
    Hybrid force/position control in a task frame, book (8.193)-(8.207).

    Parameters
    ----------
    model, task_frame, grav, use_friction
        As :class:`ForceControlLaw`; the task frame must have one axis per joint.
    environment_stiffness : array_like, scalar or (k,)
        K_e [N/m] > 0 of the environment along each of the k normal axes (8.201).
    gains : HybridGains, optional
        Default Ej. 8.11's.

    Attributes
    ----------
    force_rate : ndarray, shape (k,)
        The last estimate of ψ_N' = K_e x_N' [N/s] on the normal axes.

    Raises
    ------
    ValueError
        For a task frame without one axis per joint, a K_e that is not finite and > 0 per
        normal axis, or bad gains.

    Examples
    --------
    Ej. 8.11 at t = 0: x = (2, 4) m at rest, ψ = 0, ψ_d = 1 - e^{-2t} (ψ_d' = 2, ψ_d'' = -4).

    >>> from robotica_kin.robots import pp_robot
    >>> from robotica_ctrl.joint_control import JointState
    >>> s = 1 / np.sqrt(2)
    >>> frame = TaskFrame([[s, s], [-s, s], [0, 0]])
    >>> law = HybridForcePosition(pp_robot(), frame, 1200.0, grav=[0.0, -9.81, 0.0])
    >>> reference = TaskReference([2.0, 3.0], psi_d=[0.0, 0.0], psid_d=[2.0, 0.0],
    ...                           psidd_d=[-4.0, 0.0])
    >>> tau = law.update(reference, JointState([1 / s, 3 / s], [0.0, 0.0]), [0.0, 0.0], 1e-3)
    >>> law.telemetry.acceleration_command.round(6).tolist()    # p_N = 26/1200, p_T = -15
    [0.021667, -15.0]

    """

    law_name = 'hybrid'

    def __init__(self, model: DHModel | ArrayLike, task_frame: TaskFrame,
                 environment_stiffness: ArrayLike, gains: HybridGains | None = None,
                 grav: ArrayLike | None = None, *, use_friction: bool = True) -> None:
        if gains is not None and not isinstance(gains, HybridGains):
            raise ValueError(f'gains must be HybridGains, got {type(gains).__name__}')
        super().__init__(model, task_frame, grav, use_friction=use_friction)
        self._square_task()
        k = task_frame.normal_axes
        self._k = k
        stiffness = per_joint('environment_stiffness', environment_stiffness, k)
        if not (np.isfinite(stiffness).all() and (stiffness > 0.0).all()):
            raise ValueError(f'environment_stiffness must be finite and > 0 N/m, got '
                             f'{environment_stiffness!r}')
        self.environment_stiffness = stiffness
        self.gains = HybridGains() if gains is None else gains
        tangential = self.m - k
        self._kp_t = per_joint('kp_tangential', self.gains.kp_tangential, tangential)
        self._kv_t = per_joint('kv_tangential', self.gains.kv_tangential, tangential)
        self._kp_n = per_joint('kp_normal', self.gains.kp_normal, k)
        self._kv_n = per_joint('kv_normal', self.gains.kv_normal, k)
        self.force_rate = np.zeros(k)

    def update(self, reference: TaskReference, state: JointState, force: ArrayLike,
               dt: float) -> NDArray[np.float64]:
        """Return τ of (8.193) (n,) [N m | N] and set the telemetry; see the base class."""
        psi = self._check(reference, state, force, dt)
        x, x_dot, J = self._kinematics.evaluate(state.q, state.qd)
        k, ke = self._k, self.environment_stiffness
        p = np.empty(self.m)
        p[k:] = (reference.xdd_d[k:] + self._kv_t * (reference.xd_d[k:] - x_dot[k:])
                 + self._kp_t * (reference.x_d[k:] - x[k:]))
        self.force_rate = ke * x_dot[:k]
        p[:k] = (reference.psidd_d[:k] + self._kv_n * (reference.psid_d[:k] - self.force_rate)
                 + self._kp_n * (reference.psi_d[:k] - psi[:k])) / ke
        tau = self._linearising_torque(state, J, p, psi)
        position_reference = reference.x_d.copy()
        position_reference[:k] = np.nan
        force_reference = reference.psi_d.copy()
        force_reference[k:] = np.nan
        self.telemetry = ForceControlTelemetry(
            law=self.law_name, position_reference=position_reference, position=x,
            velocity=x_dot, force_reference=force_reference, force=psi,
            acceleration_command=p, effort=tau)
        return tau
