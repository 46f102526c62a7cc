"""
Resolved-rate (inverse-Jacobian) Cartesian control, book §8.6, fig. 8.39 (seed catalogue §6.6).

The scheme resolves a Cartesian motion into joint motion, ``δq = J⁻¹ δx`` (8.156), and leaves
the torques to joint controllers. Here, each control period:

1. **Kinematic loop** (closed-loop inverse kinematics, Whitney's resolved rate with feedback):
   the joint reference q_d is integrated from the measured q at the first step (bumpless start),
   ``q_d ← q_d + dt q_d'`` with the rate of the previous step (explicit Euler), and
   ``q_d' = J(q_d)^# (x_d' + K_x x̃)``, ``x̃ = tr2diff(φ(q_d), T_d)`` on the task rows: the
   loop is closed on the forward kinematics of the reference joints (fig. 8.38), so a set point
   or a path is converted into ``(q_d, q_d')`` without inverse kinematics, (8.155)-(8.156).
   ``q_d''`` is the backward difference of ``q_d'`` over ``dt`` ("in practice, finite
   differences", (8.157)); zero at the first step.
2. **Inner joint law**: ``tau = inner(JointReference(q_d, q_d', q_d''), state)``, by default the
   computed torque of §8.3.2 (:class:`~robotica_ctrl.joint_control.ComputedTorque`, its default
   K_p = 25, K_v = 10, with the robot's dynamics and gravity), which closes the loop on the
   measured q; any :class:`~robotica_ctrl.joint_control.law.JointControlLaw` may be given
   (e.g. the decoupled PID of §8.2).

J^# is one of three modes, all through the SVD ``J = U Σ Vᵀ``:

- ``inverse``: ``J⁻¹`` (square J only); ValueError at a singular J;
- ``pseudo_inverse``: the Moore-Penrose ``J⁺`` (any r <= n; Klein & Huang for redundant arms);
  singular values below :data:`~.law.SINGULAR_RCOND` σ_max are dropped, so it stays finite at a
  singularity but grows as ``1/σ_min`` near one;
- ``damped_least_squares`` (Wampler 1986; Nakamura & Hanafusa 1986): ``q'`` solves
  ``(JᵀJ + λ² I) q' = Jᵀ x'``, i.e. ``V diag(σ / (σ² + λ²)) Uᵀ``, bounded by ``|x'| / (2λ)``.
  With ``variable_damping`` (the default) λ grows as the arm nears a singularity and is zero
  away from it (no tracking error there): ``λ² = λ_max² (1 − (σ_min/ε)²)`` for σ_min < ε, else
  0, with ε the law's ``singular_threshold``. Nakamura & Hanafusa vary λ with the
  manipulability, ``λ = λ_0 (1 − w/w_0)²``; the smallest singular value is the distance to the
  singularity along the one direction that is lost (Maciejewski & Klein 1988; Chiaverini,
  Siciliano & Egeland 1994). Without it λ = λ_max always (Wampler). With λ_max = ε (the
  defaults, 0.05) every singular value is resolved with a gain σ / (σ² + λ²) <= 1/ε, so
  ``|q_d'| <= |x_d' + K_x x̃| / ε`` everywhere, singularities included.

The singularity is reported in the telemetry (:class:`~.law.CartesianTelemetry`) at q_d:
``manipulability``, ``min_singular_value``, ``near_singularity`` (σ_min < ε) and ``damping``
(the λ used), with ``joint_reference`` the ``(q_d, q_d', q_d'')`` handed to the inner law.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.joint_control.computed_torque import ComputedTorque
from robotica_ctrl.joint_control.law import (gain_field, JointControlLaw, JointReference,
                                             JointState, per_joint)
from robotica_kin.dh import DHModel
from robotica_kin.finite import finite_real

from .cartesian_reference import CartesianReference
from .law import CartesianControlLaw, check_nonsingular, SINGULAR_RCOND

__all__ = ['MODES', 'ResolvedRate', 'ResolvedRateParams', 'damping_factor', 'joint_rates']

MODES = ('inverse', 'pseudo_inverse', 'damped_least_squares')
"""The ways J^# of :func:`joint_rates` is formed."""


@dataclass(frozen=True, eq=False)
class ResolvedRateParams:
    """
    Tunables of :class:`ResolvedRate`.

    >>> ResolvedRateParams(mode='pseudo_inverse').kx
    array(20.)
    """

    mode: str = 'damped_least_squares'   # one of MODES
    kx: ArrayLike = 20.0         # K_x [1/s] on x̃ (scalar or per task row): x̃' = -K_x x̃
    damping: float = 0.05        # λ (λ_max when variable) [units of J's rows], >= 0
    variable_damping: bool = True   # λ grows only inside σ_min < singular_threshold

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f'mode must be one of {MODES}, got {self.mode!r}')
        gain_field(self, 'kx')
        if finite_real('damping', self.damping) < 0.0:
            raise ValueError(f'damping must be >= 0, got {self.damping!r}')
        if not isinstance(self.variable_damping, bool):
            raise ValueError(f'variable_damping must be a bool, got {self.variable_damping!r}')


def damping_factor(sigma_min: float, damping: float, threshold: float,
                   variable: bool = True) -> float:
    """
    Return the damping λ of the damped least squares for the smallest singular value σ_min.

    ``variable``: ``λ = damping sqrt(1 − (σ_min/threshold)²)`` for σ_min < threshold, 0 beyond
    (and for threshold 0); otherwise ``λ = damping``.

    >>> damping_factor(0.0, 0.05, 0.1), damping_factor(0.2, 0.05, 0.1)
    (0.05, 0.0)
    >>> round(damping_factor(0.06, 0.05, 0.1), 6)
    0.04
    """
    if not variable:
        return damping
    if sigma_min >= threshold:
        return 0.0
    return damping * math.sqrt(1.0 - (sigma_min / threshold) ** 2)


def _resolved(U: NDArray[np.float64], sigma: NDArray[np.float64], Vt: NDArray[np.float64],
              x_rate: NDArray[np.float64], mode: str, damping: float,
              q: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Return ``J^# x'`` from the thin SVD of J (see :func:`joint_rates`); ``q`` names a fault."""
    if mode == 'inverse':
        check_nonsingular(sigma, q)
        gains = 1.0 / sigma
    elif mode == 'damped_least_squares' and damping > 0.0:
        gains = sigma / (sigma * sigma + damping * damping)
    else:   # pseudo-inverse, also the damped least squares with λ = 0
        kept = sigma > SINGULAR_RCOND * sigma[0]
        gains = np.divide(1.0, sigma, out=np.zeros_like(sigma), where=kept)
    rates: NDArray[np.float64] = Vt.T @ (gains * (U.T @ x_rate))
    return rates


def joint_rates(jacobian: ArrayLike, x_rate: ArrayLike, mode: str = 'damped_least_squares',
                damping: float = 0.0) -> NDArray[np.float64]:
    """
    Return the joint rates ``q' = J^# x'`` resolving a Cartesian rate (book (8.156), fig. 8.39).

    Parameters
    ----------
    jacobian : array_like, shape (r, n)
        The task Jacobian J, r <= n (``inverse``: r = n).
    x_rate : array_like, shape (r,)
        The Cartesian rate (or small displacement δx) in J's rows.
    mode : str
        ``inverse`` (J⁻¹), ``pseudo_inverse`` (J⁺) or ``damped_least_squares``
        (``(JᵀJ + λ²I) q' = Jᵀ x'``); see the module docstring.
    damping : float
        λ >= 0 of the damped least squares (λ = 0: the pseudo-inverse).

    Returns
    -------
    ndarray, shape (n,)

    Raises
    ------
    ValueError
        For an unknown mode, shapes that do not fit, values that are not finite, a negative
        damping, or ``inverse`` with a non-square or singular J.

    Examples
    --------
    The stretched 2R (l1 = 3, l2 = 1, q2 = 0) cannot move its tip along the arm:

    >>> J = np.array([[0.0, 0.0], [4.0, 1.0]])
    >>> joint_rates(J, [0.1, 0.0], damping=0.05).round(6) + 0.0
    array([0., 0.])
    >>> joint_rates(J, [0.0, 1.0], 'pseudo_inverse').round(6)
    array([0.235294, 0.058824])

    """
    if mode not in MODES:
        raise ValueError(f'mode must be one of {MODES}, got {mode!r}')
    J = np.asarray(jacobian, dtype=np.float64)
    x = np.asarray(x_rate, dtype=np.float64)
    if J.ndim != 2 or x.shape != J.shape[:1] or J.shape[0] > J.shape[1] or J.size == 0:
        raise ValueError(f'jacobian must be (r, n) with r <= n and x_rate (r,), got shapes '
                         f'{J.shape} and {x.shape}')
    if mode == 'inverse' and J.shape[0] != J.shape[1]:
        raise ValueError(f"mode 'inverse' needs a square Jacobian, got shape {J.shape}")
    if not (np.isfinite(J).all() and np.isfinite(x).all()):
        raise ValueError('jacobian and x_rate must be finite')
    if finite_real('damping', damping) < 0.0:
        raise ValueError(f'damping must be >= 0, got {damping!r}')
    U, sigma, Vt = np.linalg.svd(J, full_matrices=False)
    return _resolved(U, sigma, Vt, x, mode, damping)


class ResolvedRate(CartesianControlLaw):
    """
    Resolved-rate Cartesian control with an inner joint law, book fig. 8.39 (module docstring).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 4), (n, 5) or (n, 20)
        The robot; with dynamics (a ``dyn`` table) unless ``inner`` is given.
    params : ResolvedRateParams, optional
        Mode, K_x, λ; default damped least squares, K_x = 20 /s, λ_max = 0.05, variable.
    grav : array_like, shape (3,), optional
        Gravity [m/s²] in {0} of the default inner computed torque; default ``[0, 0, −9.81]``.
    mask : array_like, shape (6,), optional
        Task rows ``[x y z rx ry rz]`` (default: :func:`~.law.task_mask`).
    inner : JointControlLaw, optional
        The joint law that turns ``(q_d, q_d', q_d'')`` into torques; default
        ``ComputedTorque(model, grav=grav)``.
    singular_threshold : float
        ε on σ_min(J(q_d)): the ``near_singularity`` flag and the variable damping's region.

    Raises
    ------
    ValueError
        For a bad robot, mask, ``grav`` or threshold, ``params``/``inner`` of the wrong type,
        gains of the wrong size, or ``inverse`` with a non-square task Jacobian.

    Examples
    --------
    A planar 2R (l1 = 3, l2 = 1, kinematics only) with a joint PD as the inner law, at rest at
    q = (0, π/2), tip (3, 1), 0.1 m short of the set point along x: ``q_d' = J⁻¹ K_x x̃`` with
    ``J = [[-1, -1], [3, 0]]`` and ``K_x x̃ = (2, 0)`` m/s, and the PD pushes joint 2:

    >>> from robotica_ctrl.joint_control import DecoupledPID, PIDGains
    >>> from robotica_kin.robots import planar_rr
    >>> from robotica_kin.transforms import transl
    >>> law = ResolvedRate(planar_rr(3.0, 1.0), inner=DecoupledPID(PIDGains(kp=100.0, kv=20.0)))
    >>> law.update(CartesianReference(transl(3.1, 1.0, 0.0)),
    ...            JointState([0.0, np.pi / 2], [0.0, 0.0]), 1e-3).round(9) + 0.0
    array([  0., -40.])
    >>> law.telemetry.joint_reference.qd_d.round(9) + 0.0, law.telemetry.damping
    (array([ 0., -2.]), 0.0)

    """

    def __init__(self, model: DHModel | ArrayLike, params: ResolvedRateParams | None = None,
                 grav: ArrayLike | None = None, *, mask: ArrayLike | None = None,
                 inner: JointControlLaw | None = None,
                 singular_threshold: float = 0.05) -> None:
        if params is not None and not isinstance(params, ResolvedRateParams):
            raise ValueError(f'params must be ResolvedRateParams, got {type(params).__name__}')
        if inner is not None and not isinstance(inner, JointControlLaw):
            raise ValueError(f'inner must be a JointControlLaw, got {type(inner).__name__}')
        super().__init__(model, mask, singular_threshold, needs_dynamics=inner is None)
        self.params = ResolvedRateParams() if params is None else params
        if self.params.mode == 'inverse' and self.rows != self.n:
            raise ValueError(f"mode 'inverse' needs a square Jacobian: the mask keeps {self.rows} "
                             f'task rows for {self.n} joints; use pseudo_inverse or '
                             'damped_least_squares')
        self.inner = ComputedTorque(self.robot, grav=grav) if inner is None else inner
        self._kx = per_joint('kx', self.params.kx, self.rows)
        self._q_d: NDArray[np.float64] | None = None
        self._qd_d = np.zeros(self.n)

    def reset(self) -> None:
        """Forget q_d (the next update restarts from the measured q) and reset the inner law."""
        self._q_d = None
        self._qd_d = np.zeros(self.n)
        self.telemetry = None
        self.inner.reset()

    def update(self, reference: CartesianReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau (n,) [N m] of the inner law tracking q_d; advance q_d by ``dt``.

        Raises
        ------
        ValueError
            For bad inputs (see :meth:`~.law.CartesianControlLaw.update`), ``inverse`` at a
            singular J(q_d), or what the inner law refuses; the state is then unchanged.

        """
        self.check_inputs(reference, state, dt)
        first = self._q_d is None
        q_d = state.q.copy() if self._q_d is None else self._q_d + dt * self._qd_d
        pose_error, jacobian = self.task_kinematics(q_d, reference.T_d)
        U, sigma, Vt = np.linalg.svd(jacobian, full_matrices=False)
        params = self.params
        damping = 0.0
        if params.mode == 'damped_least_squares':
            damping = damping_factor(float(sigma[-1]), params.damping, self.singular_threshold,
                                     params.variable_damping)
        x_rate = reference.xd_d[self.mask]
        qd_d = _resolved(U, sigma, Vt, x_rate + self._kx * pose_error, params.mode, damping,
                         q_d)
        qdd_d = np.zeros(self.n) if first else (qd_d - self._qd_d) / dt
        joint_reference = JointReference(q_d, qd_d, qdd_d)
        tau = self.inner.update(joint_reference, state, dt)
        self._q_d, self._qd_d = q_d, qd_d
        self.telemetry = self.step_telemetry(pose_error, x_rate - jacobian @ qd_d, sigma,
                                             damping=damping, joint_reference=joint_reference)
        return tau
