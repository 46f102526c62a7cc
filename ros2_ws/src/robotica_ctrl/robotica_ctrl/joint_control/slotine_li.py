"""
Slotine and Li's adaptive inertia-related controller, book §8.4.3 (catalogue §6.4, Ej. 8.8).

Filtered error ``r = Λ e + e'`` (8.111), ``e = q_d - q``; with ``v = q_d' + Λ e`` and
``a = q_d'' + Λ e'`` the regressor (8.119) gives ``Y(q, q', v, a) φ = M a + V_m(q, q') v + G``
(V_m the Christoffel matrix, ``M' - 2 V_m`` skew-symmetric). Control (8.123)
``tau = Y φ̂ + K_v r`` and adaptation (8.125), corrected as the catalogue says
(printed ``Γ Y r``), ``φ̂' = Γ Yᵀ r``; then ``V = ½ rᵀ M r + ½ φ̃ᵀ Γ⁻¹ φ̃`` has
``V' = -rᵀ K_v r`` (8.126): r → 0, so e, e' → 0, and φ̃ stays bounded (φ̂ → φ only with a
persistently exciting reference). No joint acceleration is needed.

Discrete form: each :meth:`SlotineLi.update` returns tau with the current φ̂, then advances φ̂ by
the explicit step ``φ̂ <- φ̂ + dt Γ Yᵀ r``. The regressor's known torque (motor inertia,
friction, links of zero mass; :mod:`.regressor`) is added to ``Y φ̂``.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .adaptive_law import AdaptiveLaw
from .law import gain_field, JointReference, JointState, per_joint
from .regressor import ParameterRegressor

__all__ = ['SlotineLi', 'SlotineLiGains']


@dataclass(frozen=True, eq=False)
class SlotineLiGains:
    """
    Gains of :class:`SlotineLi`, each > 0 (scalar or vector); defaults are Ej. 8.8's (8.137).

    >>> SlotineLiGains().lam
    array(2.5)
    """

    kv: ArrayLike = 10.0      # K_v [N m s/rad] per joint, book (8.123)
    lam: ArrayLike = 2.5      # Λ [1/s] per joint, r = Λ e + e' (8.111)
    gamma: ArrayLike = 20.0   # Γ per parameter, φ̂' = Γ Yᵀ r (8.125) [kg²/(N m) for masses]

    def __post_init__(self) -> None:
        for name in ('kv', 'lam', 'gamma'):
            gain_field(self, name, positive=True)


class SlotineLi(AdaptiveLaw):
    """
    Slotine and Li's adaptive controller, book (8.111)-(8.136): ``tau = Y φ̂ + K_v r``.

    Parameters
    ----------
    regressor : ParameterRegressor
        The dynamics as ``Y φ``: :class:`~.regressor.LinkMassRegressor` (any arm, φ the link
        masses) or :class:`~.regressor.TwoLinkRegressor` (the closed form (8.134)).
    initial_estimates : array_like, shape (p,)
        φ̂(0) (Ej. 8.8: ``[30, 100]`` kg).
    gains : SlotineLiGains, optional
        K_v, Λ (one per joint) and Γ (one per parameter); default Ej. 8.8's.

    Raises
    ------
    ValueError
        For gains or initial estimates of the wrong size.

    Examples
    --------
    At rest on the reference, the torque is the model's gravity with the estimates.

    >>> from robotica_ctrl.joint_control.law import JointReference, JointState
    >>> from robotica_ctrl.joint_control.regressor import TwoLinkRegressor
    >>> law = SlotineLi(TwoLinkRegressor(1.0, 1.0, 9.8), [30.0, 100.0])
    >>> law.update(JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    array([2254.,  980.])

    """

    def __init__(self, regressor: ParameterRegressor, initial_estimates: ArrayLike,
                 gains: SlotineLiGains | None = None) -> None:
        if gains is not None and not isinstance(gains, SlotineLiGains):
            raise ValueError(f'gains must be SlotineLiGains, got {type(gains).__name__}')
        super().__init__(regressor, initial_estimates)
        self.gains = SlotineLiGains() if gains is None else gains
        self._kv = per_joint('kv', self.gains.kv, self.n)
        self._lam = per_joint('lam', self.gains.lam, self.n)
        self._gamma = per_joint('gamma', self.gains.gamma, self.p)
        self._filtered_error = np.zeros(self.n)

    @property
    def filtered_error(self) -> NDArray[np.float64]:
        """Return a copy of r = Λ e + e' (n,) [rad/s] of the last update (8.111)."""
        return self._filtered_error.copy()

    def reset(self) -> None:
        """Return the estimates to the initial ones and clear r."""
        super().reset()
        self._filtered_error = np.zeros(self.n)

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau = Y φ̂ + K_v r (+ known torque) (n,) [N m]; advance φ̂ by ``dt`` (8.125).

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or a number of joints other than the regressor's.

        """
        self.check_joints(reference, state, dt)
        e = reference.q_d - state.q
        ed = reference.qd_d - state.qd
        lam_e = self._lam * e
        r = lam_e + ed
        y, known = self.regressor.slotine_li_terms(
            state.q, state.qd, reference.qd_d + lam_e, reference.qdd_d + self._lam * ed)
        tau = y @ self._phi + known + self._kv * r
        self._phi = self._phi + dt * self._gamma * (y.T @ r)
        self._filtered_error = r
        return tau
