"""
Computed-torque (inverse dynamics) control, book §8.3.2 (seed catalogue Part 6, §6.3).

``tau = M̂(q) tau_r + V̂(q, q') + Ĝ(q) + F̂(q')`` (8.27)-(8.29) with
``tau_r = q_d'' + K_v e' + K_p e`` (8.30), ``e = q_d - q``, ``e' = q_d' - q'`` (8.31), or the PID
variant ``tau_r = q_d'' + K_v e' + K_p e + K_i ∫e dt`` (8.36). With an exact model the errors obey
``e'' + K_v e' + K_p e = 0`` per joint (8.35). The model (M̂, V̂, Ĝ, F̂) is a robot with dynamics
for :mod:`robotica_kin.dynamics`: a ``DHModel`` with a ``dyn`` table or a raw (n, 20) HEMERO
table; a deliberately wrong model (Ej. 8.2) is simply another ``dyn`` table.

``M̂ tau_r + V̂ + Ĝ`` is the inverse dynamics at the acceleration ``tau_r``: one recursive
Newton-Euler pass (Pinocchio's RNEA, motor inertia included), not three separate terms.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.dynamics import set_gravity
from robotica_kin.joint_friction import JointFriction
from robotica_kin.pinocchio_model import build_model

from .law import gain_field, JointControlLaw, JointReference, JointState, per_joint

__all__ = ['ComputedTorque', 'ComputedTorqueGains']


@dataclass(frozen=True, eq=False)
class ComputedTorqueGains:
    """
    Gains of :class:`ComputedTorque` (diagonal, scalar or (n,)); defaults are Ej. 8.1's (8.50).

    >>> ComputedTorqueGains().kp
    array(25.)
    """

    kp: ArrayLike = 25.0              # K_p [1/s²], book (8.30); ω_n = sqrt(K_p) (8.22)
    kv: ArrayLike = 10.0              # K_v [1/s]; δ = K_v / (2 sqrt(K_p)) (8.23)
    ki: ArrayLike = 0.0               # K_i [1/s³], PID variant (8.36)
    integral_max: ArrayLike = np.inf  # clamp of ∫e dt [rad s] (anti-windup), > 0

    def __post_init__(self) -> None:
        for name in ('kp', 'kv', 'ki'):
            gain_field(self, name)
        gain_field(self, 'integral_max', positive=True, allow_inf=True)


class ComputedTorque(JointControlLaw):
    """
    Computed-torque control with a model of the robot, book (8.27)-(8.31) and (8.36).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 20)
        The controller's estimate of the robot's dynamics (M̂, V̂, Ĝ, F̂).
    gains : ComputedTorqueGains, optional
        K_p, K_v, K_i; default Ej. 8.1's K_p = 25, K_v = 10, K_i = 0.
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²] for Ĝ; default ``[0, 0, -9.81]`` (the book's planar
        examples use ``[0, -9.81, 0]``).
    use_friction : bool
        Add F̂(q') of the model's ``dyn`` table (default True).

    Raises
    ------
    ValueError
        For a model without dynamics, a bad ``grav`` or gains of the wrong size.

    Examples
    --------
    At rest on the reference, the law returns the gravity torques (Ej. 5.1 arm stretched along x).

    >>> from robotica_kin.robots import two_link_arm
    >>> from robotica_ctrl.joint_control import JointReference, JointState
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> law = ComputedTorque(dyn, grav=[0.0, -9.81, 0.0])
    >>> law.update(JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    array([98.1 ,  9.81])

    """

    def __init__(self, model: DHModel | ArrayLike, gains: ComputedTorqueGains | None = None,
                 grav: ArrayLike | None = None, *, use_friction: bool = True) -> None:
        if gains is not None and not isinstance(gains, ComputedTorqueGains):
            raise ValueError(f'gains must be ComputedTorqueGains, got {type(gains).__name__}')
        robot = as_dyn_model(model)     # checks the model: dynamics present, (n, 20)
        n = robot.n
        # The law's own model (its gravity is set here) and scratch, made once: update() runs
        # at the control rate and allocates neither.
        self._pin_model = build_model(robot)
        set_gravity(self._pin_model, grav)
        self._pin_data = self._pin_model.createData()
        self._friction = JointFriction(robot)
        self.model = model
        self.n = n
        self.gains = ComputedTorqueGains() if gains is None else gains
        self.use_friction = bool(use_friction)
        self._kp, self._kv, self._ki, self._integral_max = (
            per_joint(name, getattr(self.gains, name), n)
            for name in ('kp', 'kv', 'ki', 'integral_max'))
        self._integral = np.zeros(n)
        self._integrates = bool((self._ki > 0.0).any())
        self._adds_friction = self.use_friction and not self._friction.is_zero

    @property
    def integral(self) -> NDArray[np.float64]:
        """Return a copy of the integral of the error ∫e dt (n,) [rad s]."""
        return self._integral.copy()

    def reset(self) -> None:
        """Clear the integral of the error."""
        self._integral = np.zeros(self.n)

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau = M̂(q) tau_r + V̂ + Ĝ [+ F̂] (n,) [N m]; advance ∫e dt by ``dt`` if K_i ≠ 0.

        Without K_i the law has no memory, so an ODE solver may call it at any state.

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or a number of joints other than the model's.

        """
        n = self.check_inputs(reference, state, dt)
        if n != self.n:
            raise ValueError(f'the model has {self.n} joints, got {n}')
        # The fields of JointReference and JointState are checked float64 vectors (n,) already.
        q, qd = state.q, state.qd
        e = reference.q_d - q
        tau_r = self._kv * (reference.qd_d - qd)
        tau_r += self._kp * e
        tau_r += reference.qdd_d
        if self._integrates:
            self._integral = np.clip(self._integral + e * dt, -self._integral_max,
                                     self._integral_max)
            tau_r = tau_r + self._ki * self._integral
        tau = pin.rnea(self._pin_model, self._pin_data, q, qd, tau_r)
        if self._adds_friction:
            return tau + self._friction(qd)
        return tau   # pin.rnea returns a new array (not a view of the data workspace)
