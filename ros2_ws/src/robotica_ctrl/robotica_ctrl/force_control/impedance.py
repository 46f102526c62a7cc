"""
Impedance control with a measured force, in a task frame (outside book §8.7).

Book §8.7 gives stiffness and hybrid control only; the impedance relation
``M_x Δx'' + D_x Δx' + K_x Δx = ψ`` appears in the book in teleoperation (§13, (13.12)). The law
here is the inverse-dynamics impedance control with force measurement of Siciliano, Sciavicco,
Villani & Oriolo, "Robotics: Modelling, Planning and Control" (Springer 2009), §9.3 (after
Hogan 1985), in this package's notation. The target impedance, per task axis (diagonal
M_d > 0, B_d >= 0, K_d >= 0), is

    M_d x̃'' + B_d x̃' + K_d x̃ = ψ,     x̃ = x_d - x,

with ψ the measured force the end effector exerts on the environment: pushed by the surface
the arm gives way from x_d like a mass-spring-damper. It is obtained with the linearising law
(8.193) ``τ = M̂ Ĵ⁻¹ [p - Ĵ' q'] + V̂_m q' + Ĝ + F̂ + Ĵᵀ ψ`` (``x'' = p`` with an exact model) and

    p = x_d'' + M_d⁻¹ (B_d x̃' + K_d x̃ - ψ).

Against ``ψ = K_e (x - x_e)`` it settles at ``x = (K_d x_d + K_e x_e) / (K_d + K_e)``, the
stiffness law's steady state (8.176) with K_d for K_p; free of contact it tracks x_d with the
dynamics ``x̃'' + (B_d/M_d) x̃' + (K_d/M_d) x̃ = 0``. The law inverts Ĵ: one task axis per joint.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import DHModel

from .law import ForceControlLaw, ForceControlTelemetry, TaskReference
from .task_frame import TaskFrame
from ..joint_control.law import gain_field, JointState, per_joint

__all__ = ['ImpedanceControl', 'ImpedanceGains']


@dataclass(frozen=True, eq=False)
class ImpedanceGains:
    """
    The target impedance of :class:`ImpedanceControl`, per task axis (scalar or (m,)).

    Defaults: critically damped with ω_n = sqrt(K_d / M_d) = 10 rad/s.

    >>> ImpedanceGains().damping
    array(20.)
    """

    inertia: ArrayLike = 1.0       # M_d [kg] > 0
    damping: ArrayLike = 20.0      # B_d [N s/m] >= 0
    stiffness: ArrayLike = 100.0   # K_d [N/m] >= 0

    def __post_init__(self) -> None:
        gain_field(self, 'inertia', positive=True)
        gain_field(self, 'damping')
        gain_field(self, 'stiffness')


class ImpedanceControl(ForceControlLaw):
    """
    Impedance control ``M_d x̃'' + B_d x̃' + K_d x̃ = ψ`` through the linearising law (8.193).

    Parameters as :class:`ForceControlLaw`, plus ``gains`` (:class:`ImpedanceGains`). The
    reference's x_d, x_d', x_d'' are used on every axis, its forces not.

    Raises
    ------
    ValueError
        For a task frame without one axis per joint, or bad gains.

    Examples
    --------
    At rest on the reference, pushing with ψ = (3, 0) N on the surface: p = -ψ / M_d.

    >>> from robotica_kin.robots import pp_robot
    >>> from robotica_ctrl.joint_control import JointState
    >>> s = 1 / np.sqrt(2)
    >>> law = ImpedanceControl(pp_robot(), TaskFrame([[s, s], [-s, s], [0, 0]]),
    ...                        grav=[0.0, -9.81, 0.0])
    >>> state = JointState([1 / s, 3 / s], [0.0, 0.0])
    >>> _ = law.update(TaskReference([2.0, 4.0]), state, [3.0, 0.0], 1e-3)
    >>> law.telemetry.acceleration_command.round(12).tolist()
    [-3.0, 0.0]

    """

    law_name = 'impedance'

    def __init__(self, model: DHModel | ArrayLike, task_frame: TaskFrame,
                 gains: ImpedanceGains | None = None, grav: ArrayLike | None = None, *,
                 use_friction: bool = True) -> None:
        if gains is not None and not isinstance(gains, ImpedanceGains):
            raise ValueError(f'gains must be ImpedanceGains, got {type(gains).__name__}')
        super().__init__(model, task_frame, grav, use_friction=use_friction)
        self._square_task()
        self.gains = ImpedanceGains() if gains is None else gains
        self._inertia = per_joint('inertia', self.gains.inertia, self.m)
        self._damping = per_joint('damping', self.gains.damping, self.m)
        self._stiffness = per_joint('stiffness', self.gains.stiffness, self.m)

    def update(self, reference: TaskReference, state: JointState, force: ArrayLike,
               dt: float) -> NDArray[np.float64]:
        """Return τ (n,) [N m | N] for the target impedance and set the telemetry."""
        psi = self._check(reference, state, force, dt)
        x, x_dot, J = self._kinematics.evaluate(state.q, state.qd)
        p = reference.xdd_d + (self._damping * (reference.xd_d - x_dot)
                               + self._stiffness * (reference.x_d - x) - psi) / self._inertia
        tau = self._linearising_torque(state, J, p, psi)
        self.telemetry = ForceControlTelemetry(
            law=self.law_name, position_reference=reference.x_d, position=x, velocity=x_dot,
            force_reference=self._no_values, force=psi, acceleration_command=p, effort=tau)
        return tau
