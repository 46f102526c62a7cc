"""
Transpose-Jacobian Cartesian control, book §8.6, fig. 8.40, (8.158)-(8.162) (catalogue §6.6).

A Cartesian PD computes the force ``ψ = K_p x̃ + K_v x̃'`` that the tool should exert, with
``x̃ = tr2diff(φ(q), T_d)`` and ``x̃' = x_d' − J(q) q'`` on the task rows (frame {0}), and the
joints produce it through ``tau = Jᵀ(q) ψ`` (8.158): by the balance of power ``q'ᵀ tau = x'ᵀ ψ``
(8.159)-(8.161) these torques do the work of ψ. No inverse of J is needed, so the law is defined
at singularities (where ψ along a lost direction is simply not felt). For a Cartesian robot, J is
orthonormal and ``Jᵀ = J⁻¹`` (8.162): the law is then the inverse-Jacobian scheme.

Gravity compensation (default on): ``tau = Jᵀ ψ + Ĝ(q)``, with Ĝ of the robot's ``dyn`` table
and ``grav``, so that a set point is reached with x̃ → 0 (Lyapunov, as the PD with gravity
compensation of §8.3). Without it the arm settles where ``Jᵀ(q) ψ = G(q)``: the static balance
of (8.167) with the spring ψ = K_p x̃ holding the weight, a steady error x̃ ≠ 0.

Telemetry (:class:`~.law.CartesianTelemetry`) at the measured q: ``pose_error`` x̃,
``twist_error`` x̃', ``cartesian_force`` ψ, ``manipulability``, ``min_singular_value``,
``near_singularity``; ``damping`` 0.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_ctrl.joint_control.law import JointState, per_joint
from robotica_kin.dh import DHModel

from .cartesian_reference import CartesianReference
from .law import CartesianControlLaw, CartesianGains

__all__ = ['TransposeJacobian']


class TransposeJacobian(CartesianControlLaw):
    """
    ``tau = Jᵀ(q) (K_p x̃ + K_v x̃') [+ Ĝ(q)]``, book (8.158) (module docstring).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 4), (n, 5) or (n, 20)
        The robot; with dynamics (a ``dyn`` table) when ``gravity_compensation``.
    gains : CartesianGains, optional
        K_p [N/m | N m/rad], K_v [N s/m | N m s/rad] per task row; default 25 and 10.
    grav : array_like, shape (3,), optional
        Gravity [m/s²] in {0} for Ĝ; default ``[0, 0, −9.81]``.
    mask : array_like, shape (6,), optional
        Task rows ``[x y z rx ry rz]`` (default: :func:`~.law.task_mask`).
    gravity_compensation : bool
        Add Ĝ(q) (default True).
    singular_threshold : float
        σ_min of J below which ``telemetry.near_singularity`` is raised.

    Raises
    ------
    ValueError
        For a bad robot (or one without dynamics when compensating gravity), mask, ``grav``,
        threshold, or gains of the wrong type or size.

    Examples
    --------
    At rest 0.1 m short of the set point along x, no gravity (planar 2R, l1 = 3, l2 = 1, at
    q = (0, π/2): the tip at (3, 1), J = [[-1, -1], [3, 0]]):

    >>> from robotica_kin.robots import planar_rr
    >>> from robotica_kin.transforms import transl
    >>> law = TransposeJacobian(planar_rr(3.0, 1.0), CartesianGains(kp=100.0),
    ...                         gravity_compensation=False)
    >>> law.update(CartesianReference(transl(3.1, 1.0, 0.0)),
    ...            JointState([0.0, np.pi / 2], [0.0, 0.0]), 1e-3).round(9) + 0.0
    array([-10., -10.])

    """

    def __init__(self, model: DHModel | ArrayLike, gains: CartesianGains | None = None,
                 grav: ArrayLike | None = None, *, mask: ArrayLike | None = None,
                 gravity_compensation: bool = True, singular_threshold: float = 0.05) -> None:
        if gains is not None and not isinstance(gains, CartesianGains):
            raise ValueError(f'gains must be CartesianGains, got {type(gains).__name__}')
        self.gravity_compensation = bool(gravity_compensation)
        super().__init__(model, mask, singular_threshold,
                         needs_dynamics=self.gravity_compensation)
        self.gains = CartesianGains() if gains is None else gains
        self._kp = per_joint('kp', self.gains.kp, self.rows)
        self._kv = per_joint('kv', self.gains.kv, self.rows)
        self._gravity = self.gravity_model(grav) if self.gravity_compensation else None

    def reset(self) -> None:
        """Clear the telemetry (the law has no memory)."""
        self.telemetry = None

    def update(self, reference: CartesianReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return ``tau = Jᵀ ψ [+ Ĝ]`` (n,) [N m]; stateless, so an ODE solver may call it anywhere.

        Raises
        ------
        ValueError
            For bad inputs (see :meth:`~.law.CartesianControlLaw.update`).

        """
        self.check_inputs(reference, state, dt)
        pose_error, jacobian = self.task_kinematics(state.q, reference.T_d)
        twist_error = reference.xd_d[self.mask] - jacobian @ state.qd
        force = self._kp * pose_error + self._kv * twist_error
        tau: NDArray[np.float64] = jacobian.T @ force
        if self._gravity is not None:
            tau += pin.computeGeneralizedGravity(*self._gravity, state.q)
        sigma = np.linalg.svd(jacobian, full_matrices=False)[1]
        self.telemetry = self.step_telemetry(pose_error, twist_error, sigma,
                                             cartesian_force=force)
        return tau
