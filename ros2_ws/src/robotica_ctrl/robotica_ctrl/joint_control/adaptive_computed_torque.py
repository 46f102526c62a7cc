"""
Adaptive computed torque (Lewis et al. 1993), book §8.4.2 (catalogue §6.4, Ej. 8.7).

Control as (8.27)-(8.31) with the model of the current estimates φ̂:
``tau = M̂(q)(q_d'' + K_v e' + K_p e) + V̂ + Ĝ``, ``e = q_d - q``. With the regressor (8.79)
``W(q, q', q'') φ = M q'' + V + G`` the error obeys ``e'' + K_v e' + K_p e = M̂⁻¹ W φ̃`` (8.83),
in state form ``ε' = A ε + B M̂⁻¹ W φ̃`` with ``ε = [e; e']``, ``A = [[0, I], [-K_p, -K_v]]``,
``B = [0; I]`` (8.84)-(8.85). The Lyapunov function ``V = εᵀ P ε + φ̃ᵀ Γ⁻¹ φ̃`` (8.86), with P
solving ``Aᵀ P + P A = -Q`` (8.92), gives the adaptation law (8.95)
``φ̂' = Γ Wᵀ M̂⁻¹ Bᵀ P ε``. The default Q is (8.103), ``diag(½ K_p, K_v - ½ I)``, whose P is
(8.102) ``½[[(K_p + ½ K_v), ½ I], [½ I, I]]`` for scalar gains, so ``Bᵀ P ε = ¼ e + ½ e'``
(8.104); it needs K_v > ½ (Q positive definite).

The discrete algorithm, per :meth:`AdaptiveComputedTorque.update`:

1. ``tau = W(q, q', tau_r) φ̂ + known`` with ``tau_r = q_d'' + K_v e' + K_p e`` (the regressor
   at the acceleration tau_r is M̂ tau_r + V̂ + Ĝ; the known torque is the regressor's motor
   inertia, friction and links of zero mass, :mod:`.regressor`);
2. q'' estimated from the measured velocities (:class:`~.acceleration_estimate.
   AccelerationEstimate`: difference over dt, optional low-pass, zero on the first step): the
   method's drawback, named by the book, is that it needs the accelerations;
3. ``φ̂ <- Π(φ̂ + dt Γ Wᵀ(q, q', q''_est) M̂(q, φ̂)⁻¹ Bᵀ P ε)``, Π the projection onto the optional
   bounds ``[lower, upper]`` (per parameter). M̂ must be invertible: when the Cholesky factor of
   M̂(q, φ̂) does not exist (not positive definite), the step is refused, φ̂ returns to the last
   estimate whose M̂ was positive definite, and :attr:`~AdaptiveComputedTorque.refusals` counts
   it. Bounds that keep the masses positive make M̂ positive definite and the refusal moot.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import cho_solve, solve_continuous_lyapunov

from .acceleration_estimate import AccelerationEstimate
from .adaptive_law import AdaptiveLaw
from .law import gain_field, JointReference, JointState, per_joint
from .regressor import ParameterRegressor

__all__ = ['AdaptiveComputedTorque', 'AdaptiveComputedTorqueGains', 'lyapunov_p']


@dataclass(frozen=True, eq=False)
class AdaptiveComputedTorqueGains:
    """
    Gains of :class:`AdaptiveComputedTorque` (scalars or vectors); K_p, K_v as Ej. 8.1's.

    >>> AdaptiveComputedTorqueGains(gamma=5.0).kv
    array(10.)
    """

    kp: ArrayLike = 25.0              # K_p [1/s²] per joint, > 0, book (8.30)
    kv: ArrayLike = 10.0              # K_v [1/s] per joint, > 0 (> ½ with the default Q)
    gamma: ArrayLike = 1.0            # Γ per parameter, > 0, adaptation law (8.95)
    acceleration_time_constant: ArrayLike = 0.0   # T [s] of the q'' estimate's low-pass; 0: none
    lyapunov_q: ArrayLike | None = None   # diag of Q (2n,) of (8.92), > 0; None: (8.103)

    def __post_init__(self) -> None:
        for name in ('kp', 'kv', 'gamma'):
            gain_field(self, name, positive=True)
        gain_field(self, 'acceleration_time_constant')
        if self.lyapunov_q is not None:
            gain_field(self, 'lyapunov_q', positive=True)


def lyapunov_p(kp: ArrayLike, kv: ArrayLike, q_diagonal: ArrayLike) -> NDArray[np.float64]:
    """
    Return P (2n, 2n) solving ``Aᵀ P + P A = -Q`` (8.92) for ``A = [[0, I], [-K_p, -K_v]]``.

    ``kp``, ``kv`` (n,) are the diagonals of K_p [1/s²] and K_v [1/s], ``q_diagonal`` (2n,)
    that of Q. SciPy's ``solve_continuous_lyapunov`` (Bartels-Stewart).

    Examples
    --------
    (8.102)-(8.103): k_p = 25, k_v = 10, Q = diag(½ k_p, k_v - ½) gives
    ``P = ½[[k_p + ½ k_v, ½], [½, 1]]``.

    >>> lyapunov_p([25.0], [10.0], [12.5, 9.5])
    array([[15.  ,  0.25],
           [ 0.25,  0.5 ]])

    """
    kp_, kv_ = np.asarray(kp, dtype=np.float64), np.asarray(kv, dtype=np.float64)
    n = kp_.size
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(kp_), -np.diag(kv_)]])
    p = solve_continuous_lyapunov(a.T, -np.diag(np.asarray(q_diagonal, dtype=np.float64)))
    return 0.5 * (p + p.T)


class AdaptiveComputedTorque(AdaptiveLaw):
    """
    Adaptive computed torque, book (8.79)-(8.95): the model's parameters φ̂ adapt on line.

    Parameters
    ----------
    regressor : ParameterRegressor
        The dynamics as ``W φ`` and M̂(q, φ): :class:`~.regressor.LinkMassRegressor` or
        :class:`~.regressor.TwoLinkRegressor` (the closed form (8.100)).
    initial_estimates : array_like, shape (p,)
        φ̂(0).
    gains : AdaptiveComputedTorqueGains, optional
        K_p, K_v (per joint), Γ (per parameter), the q'' filter and Q.
    bounds : tuple of two array_like, shape (p,) or scalars, optional
        ``(lower, upper)`` of φ̂ (±inf allowed): the projection of step 3 (module docstring).

    Raises
    ------
    ValueError
        For gains of the wrong size, K_v <= ½ with the default Q, bounds not lower <= upper or
        initial estimates outside them.

    Examples
    --------
    At rest, e = [0.1, 0]: M̂ (K_p e) + Ĝ of the 2R (5.77) with m̂ = [1, 2] kg.

    >>> from robotica_ctrl.joint_control.law import JointReference, JointState
    >>> from robotica_ctrl.joint_control.regressor import TwoLinkRegressor
    >>> law = AdaptiveComputedTorque(TwoLinkRegressor(1.0, 1.0, 9.8), [1.0, 2.0])
    >>> law.update(JointReference([0.1, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    array([71.5, 29.6])
    >>> law.adaptation_error      # Bᵀ P ε = ¼ e + ½ e' (8.104)
    array([0.025, 0.   ])

    """

    def __init__(self, regressor: ParameterRegressor, initial_estimates: ArrayLike,
                 gains: AdaptiveComputedTorqueGains | None = None, *,
                 bounds: tuple[ArrayLike, ArrayLike] | None = None) -> None:
        if gains is not None and not isinstance(gains, AdaptiveComputedTorqueGains):
            raise ValueError('gains must be AdaptiveComputedTorqueGains, got '
                             f'{type(gains).__name__}')
        super().__init__(regressor, initial_estimates)
        self.gains = g = AdaptiveComputedTorqueGains() if gains is None else gains
        n = self.n
        self._kp, self._kv = per_joint('kp', g.kp, n), per_joint('kv', g.kv, n)
        self._gamma = per_joint('gamma', g.gamma, self.p)
        if g.lyapunov_q is None:
            if (self._kv <= 0.5).any():
                raise ValueError(f'kv must be > 0.5 1/s for the default Q of (8.103), got {g.kv}')
            q_diagonal = np.concatenate([0.5 * self._kp, self._kv - 0.5])
        else:
            q_diagonal = per_joint('lyapunov_q', g.lyapunov_q, 2 * n)
        self._p = lyapunov_p(self._kp, self._kv, q_diagonal)
        self._lower, self._upper = self._bounds(bounds)
        self._acceleration = AccelerationEstimate(
            per_joint('acceleration_time_constant', g.acceleration_time_constant, n))
        self.reset()

    def _bounds(self, bounds: tuple[ArrayLike, ArrayLike] | None
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the checked (lower, upper) of φ̂, each (p,), or raise ValueError."""
        if bounds is None:
            return np.full(self.p, -np.inf), np.full(self.p, np.inf)
        try:
            lower, upper = (per_joint(name, value, self.p)
                            for name, value in zip(('lower bound', 'upper bound'), bounds))
        except (TypeError, ValueError) as err:
            raise ValueError(f'bounds must be (lower, upper), each a scalar or ({self.p},), got '
                             f'{bounds!r}') from err
        if np.isnan(lower).any() or np.isnan(upper).any() or not (lower <= upper).all():
            raise ValueError(f'bounds must have lower <= upper, got {bounds!r}')
        if ((self.initial_estimates < lower) | (self.initial_estimates > upper)).any():
            raise ValueError(f'initial_estimates {self.initial_estimates} lie outside the bounds '
                             f'{bounds!r}')
        return lower, upper

    @property
    def lyapunov_p(self) -> NDArray[np.float64]:
        """Return a copy of P (2n, 2n) of (8.92) (with the default Q: (8.102))."""
        return self._p.copy()

    @property
    def adaptation_error(self) -> NDArray[np.float64]:
        """Return a copy of Bᵀ P ε (n,) of the last update, the error the estimates adapt on."""
        return self._adaptation_error.copy()

    @property
    def refusals(self) -> int:
        """Return how many adaptation steps were refused for a singular M̂ since the reset."""
        return self._refusals

    def reset(self) -> None:
        """Return the estimates to the initial ones; forget the acceleration estimate."""
        super().reset()
        self._last_good = self.initial_estimates.copy()
        self._acceleration.reset()
        self._adaptation_error = np.zeros(self.n)
        self._refusals = 0

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau = M̂ tau_r + V̂ + Ĝ (+ known torque) (n,) [N m]; adapt φ̂ over ``dt`` (8.95).

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or a number of joints other than the regressor's.

        """
        self.check_joints(reference, state, dt)
        q, qd, n = state.q, state.qd, self.n
        e = reference.q_d - q
        ed = reference.qd_d - qd
        tau_r = reference.qdd_d + self._kv * ed + self._kp * e
        w_r, known = self.regressor.computed_torque_terms(q, qd, tau_r)
        tau = w_r @ self._phi + known
        w, _ = self.regressor.computed_torque_terms(q, qd, self._acceleration.update(qd, dt))
        self._adaptation_error = self._p[n:, :n] @ e + self._p[n:, n:] @ ed
        try:
            factor = np.linalg.cholesky(self.regressor.inertia(q, self._phi))
        except np.linalg.LinAlgError:
            self._phi = self._last_good.copy()
            self._refusals += 1
            return tau
        rate = self._gamma * (w.T @ cho_solve((factor, True), self._adaptation_error,
                                              check_finite=False))
        self._last_good = self._phi
        self._phi = np.clip(self._phi + dt * rate, self._lower, self._upper)
        return tau
