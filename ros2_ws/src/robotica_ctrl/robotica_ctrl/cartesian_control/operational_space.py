"""
Operational-space control (Khatib 1985), book §8.6, fig. 8.41, (8.163) (seed catalogue §6.6).

The dynamics are written in the task coordinates x and the tool force ψ that decouples them is
applied through ``tau = Jᵀ ψ`` (8.158), with no joint trajectory generator:

``ψ = M_x(q) x'' + V_x(q, q') + G_x(q)`` (8.163), where
``M_x = J⁻ᵀ M J⁻¹``, ``V_x = J⁻ᵀ V − M_x J' q'``, ``G_x = J⁻ᵀ G`` and the commanded acceleration
``x'' = x_d'' + K_v x̃' + K_p x̃``, ``x̃ = tr2diff(φ(q), T_d)``, ``x̃' = x_d' − J q'`` (task rows,
frame {0}). ``M`` is Pinocchio's CRBA (with the motor inertias), ``V + G`` its non-linear effects
with the law's gravity, and ``J' q'`` the classical acceleration of the tool frame at ``q'' = 0``
(``getFrameClassicalAcceleration`` in {0}-aligned axes: ``[p''; ω']`` minus ``J q''``), no
finite differences. No friction term (F̂ is not in (8.163)).

With an exact model the closed loop is ``x'' = J q'' + J' q'`` = the commanded acceleration,
so each position row obeys ``x̃'' + K_v x̃' + K_p x̃ = 0``, decoupled. The rotation rows are
decoupled too, but the error ``sin(ε) k̂`` of tr2diff is linear in ε only to first order: from
rest about a set point, with the same gains on the three rotation rows, the tool turns about
the fixed axis k̂ and ``ε'' + K_v ε' + K_p sin ε = 0``.

J must be square (one task row per joint, as (8.163) inverts it) and non-singular: a singular J
raises ValueError, and the telemetry (:class:`~.law.CartesianTelemetry`) reports how near the
arm is (``manipulability``, ``min_singular_value``, ``near_singularity``), with ``pose_error``,
``twist_error`` and ``cartesian_force`` ψ.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_ctrl.joint_control.law import JointState, per_joint
from robotica_kin.dh import DHModel

from .cartesian_reference import CartesianReference
from .law import CartesianControlLaw, CartesianGains, check_nonsingular

__all__ = ['OperationalSpace']


class OperationalSpace(CartesianControlLaw):
    """
    Khatib's operational-space control ``tau = Jᵀ (M_x x'' + V_x + G_x)``, book (8.163).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 20)
        The controller's model of the robot, with dynamics (M̂, V̂, Ĝ).
    gains : CartesianGains, optional
        K_p [1/s²], K_v [1/s] per task row; default 25 and 10 (ω_n = 5, critically damped).
    grav : array_like, shape (3,), optional
        Gravity [m/s²] in {0} for Ĝ; default ``[0, 0, −9.81]``.
    mask : array_like, shape (6,), optional
        Task rows ``[x y z rx ry rz]`` (default: :func:`~.law.task_mask`); n of them.
    singular_threshold : float
        σ_min of J below which ``telemetry.near_singularity`` is raised.

    Raises
    ------
    ValueError
        For a robot without dynamics, a mask that does not keep one row per joint, a bad
        ``grav`` or threshold, or gains of the wrong type or size.

    Examples
    --------
    At rest on the set point the law holds the weight, ``Jᵀ G_x = G`` (Ej. 5.1 arm, tool at
    the tip; (5.77): G = (9.81 (3 · 3 c1 + c12), 9.81 c12)):

    >>> from robotica_kin.dh import dh_model
    >>> from robotica_kin.forward_kinematics import fkine
    >>> from robotica_kin.robots import two_link_arm
    >>> from robotica_kin.transforms import transl
    >>> dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> arm = dh_model(dh, dyn=dyn, tool=transl(1.0, 0.0, 0.0))
    >>> law = OperationalSpace(arm, grav=[0.0, -9.81, 0.0])
    >>> q = [0.0, 0.5]
    >>> law.update(CartesianReference(fkine(arm, q)), JointState(q, [0.0, 0.0]), 1e-3).round(4)
    array([96.8991,  8.6091])

    """

    def __init__(self, model: DHModel | ArrayLike, gains: CartesianGains | None = None,
                 grav: ArrayLike | None = None, *, mask: ArrayLike | None = None,
                 singular_threshold: float = 0.05) -> None:
        if gains is not None and not isinstance(gains, CartesianGains):
            raise ValueError(f'gains must be CartesianGains, got {type(gains).__name__}')
        super().__init__(model, mask, singular_threshold, needs_dynamics=True)
        if self.rows != self.n:
            raise ValueError(f'operational-space control inverts J: the mask must keep one task '
                             f'row per joint, {self.n}, got {self.rows}')
        self.gains = CartesianGains() if gains is None else gains
        self._kp = per_joint('kp', self.gains.kp, self.rows)
        self._kv = per_joint('kv', self.gains.kv, self.rows)
        self._model, self._dynamics = self.gravity_model(grav)
        self._zero = np.zeros(self.n)

    def reset(self) -> None:
        """Clear the telemetry (the law has no memory)."""
        self.telemetry = None

    def bias_acceleration(self, q: NDArray[np.float64],
                          qd: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return ``J'(q, q') q'`` (r,) [m/s², rad/s²] of the task rows, in {0}."""
        arm = self._arm
        pin.forwardKinematics(arm.model, self._data, q, qd, self._zero)
        acceleration = pin.getFrameClassicalAcceleration(arm.model, self._data, arm.tool_frame,
                                                         pin.LOCAL_WORLD_ALIGNED)
        bias: NDArray[np.float64] = acceleration.vector[self.mask]
        return bias

    def update(self, reference: CartesianReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return ``tau = Jᵀ ψ`` (n,) [N m]; stateless, so an ODE solver may call it anywhere.

        Raises
        ------
        ValueError
            For bad inputs (see :meth:`~.law.CartesianControlLaw.update`) or a singular J(q).

        """
        self.check_inputs(reference, state, dt)
        q, qd = state.q, state.qd
        pose_error, jacobian = self.task_kinematics(q, reference.T_d)
        U, sigma, Vt = np.linalg.svd(jacobian)
        check_nonsingular(sigma, q)
        inverse = (Vt.T / sigma) @ U.T                                   # J⁻¹
        twist_error = reference.xd_d[self.mask] - jacobian @ qd
        command = reference.xdd_d[self.mask] + self._kv * twist_error + self._kp * pose_error
        mass = inverse.T @ pin.crba(self._model, self._dynamics, q) @ inverse     # M_x
        bias = pin.nonLinearEffects(self._model, self._dynamics, q, qd)          # V + G
        force = mass @ (command - self.bias_acceleration(q, qd)) + inverse.T @ bias  # ψ (8.163)
        self.telemetry = self.step_telemetry(pose_error, twist_error, sigma,
                                             cartesian_force=force)
        tau: NDArray[np.float64] = jacobian.T @ force
        return tau
