"""
Model-reference adaptive control (MRAC) per joint, book §8.4.1, fig. 8.27 (catalogue §6.4).

Each joint i has a reference model (8.75) ``a_i y'' + b_i y' + y = v_i`` with
``a_i = 1/ω_ni²`` and ``b_i = 2 δ_i/ω_ni`` (8.76): the response the closed loop
``α_i q'' + β_i q' + q = r_i`` (8.77) should have. The gains are adapted by the gradient of
``J_i = ½ (w2 ε'' + w1 ε' + w0 ε)²`` (8.78), ``ε = y - q`` (the MIT rule). The book gives this
structure only; the discrete algorithm below adds these assumptions:

1. The adapted law is a decoupled PD on the command: ``tau_i = K_pi (v_i - q_i) - K_vi q_i'``
   with ``v = q_d`` (the reference's q_d' and q_d'' are not used: the reference model makes the
   desired response). For a joint of inertia J alone, the closed loop is (8.77) with
   ``α = J/K_p``, ``β = K_v/K_p``: it matches the model for ``K_p = J ω_n²``,
   ``K_v = 2 δ ω_n J``.
2. MIT rule, ``θ' = -γ ∂J/∂θ = γ s (w2 D² + w1 D + w0) ∂q/∂θ`` with
   ``s = w2 ε'' + w1 ε' + w0 ε`` and θ = (K_p, K_v). The sensitivities of that closed loop,
   ``∂q/∂K_p = (v - q)/(J s² + K_v s + K_p)`` and ``∂q/∂K_v = -s q/(J s² + K_v s + K_p)``,
   use the unknown J; near the match ``J s² + K_v s + K_p = K_p (a s² + b s + 1)``, so they are
   taken as the reference model's filter of ``v - q`` and of ``-q'``, and the factor ``1/K_p``
   is absorbed into the adaptation rates γ_p, γ_v (Åström and Wittenmark's usual approximation).
3. Every filter (the reference model and the two sensitivities) is the model's state-space form
   ``x = [y, y']``, discretised exactly for an input held over the period (zero-order hold,
   matrix exponential, recomputed when dt changes); its second derivative is read from the
   model equation, ``y'' = ω_n² (u - y) - 2 δ ω_n y'``.
4. ε'' needs q'': estimated from the velocities (:class:`~.acceleration_estimate.
   AccelerationEstimate`); with the default weights (w0 = 1, w1 = w2 = 0) it is not used.
5. Each :meth:`~ModelReferenceAdaptive.update` returns tau with the current gains, then steps
   the gains (explicit, ``θ <- θ + dt θ'``, kept >= 0) and the filters. On its first call the
   reference model starts at the measured state (y = q, y' = q': no initial model error) and the
   sensitivities at zero.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm

from .acceleration_estimate import AccelerationEstimate
from .law import gain_field, JointControlLaw, JointReference, JointState, per_joint

__all__ = ['ModelReferenceAdaptive', 'ModelReferenceGains', 'ReferenceModel']


class ReferenceModel:
    """
    The per-joint reference model ``a y'' + b y' + y = u`` (8.75)-(8.76), discretised exactly.

    Parameters
    ----------
    natural_frequency, damping : array_like, shape (n,)
        ω_n [rad/s] > 0 and δ > 0 of each joint: ``a = 1/ω_n²``, ``b = 2 δ/ω_n``.

    Examples
    --------
    A step held for one time constant of a critically damped model (ω_n = 1):
    y = 1 - (1 + t) e^(-t).

    >>> model = ReferenceModel([1.0], [1.0])
    >>> state = model.step(np.zeros((1, 2)), np.array([1.0]), 1.0)
    >>> bool(abs(state[0, 0] - (1.0 - 2.0 * np.exp(-1.0))) < 1e-12)
    True

    """

    def __init__(self, natural_frequency: ArrayLike, damping: ArrayLike) -> None:
        self.natural_frequency = np.array(natural_frequency, dtype=np.float64).reshape(-1)
        self.damping = np.array(damping, dtype=np.float64).reshape(-1)
        self._dt: float | None = None
        self._transition = np.empty((0, 2, 2))
        self._input = np.empty((0, 2))

    def _matrices(self, dt: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return Φ (n, 2, 2) and Γ (n, 2) of the zero-order-hold discretisation for ``dt``."""
        if dt != self._dt:
            transition, gain = [], []
            for w, d in zip(self.natural_frequency, self.damping):
                augmented = np.array([[0.0, 1.0, 0.0], [-w * w, -2.0 * d * w, w * w],
                                      [0.0, 0.0, 0.0]])
                exponential = expm(augmented * dt)
                transition.append(exponential[:2, :2])
                gain.append(exponential[:2, 2])
            self._transition, self._input, self._dt = np.array(transition), np.array(gain), dt
        return self._transition, self._input

    def step(self, state: NDArray[np.float64], u: NDArray[np.float64],
             dt: float) -> NDArray[np.float64]:
        """
        Return the states [y, y'] (..., n, 2) after ``dt`` [s] with the inputs ``u`` (..., n) held.

        ``state`` and ``u`` may stack several signals filtered by the same models (leading axis).
        """
        transition, gain = self._matrices(dt)
        return np.einsum('nij,...nj->...ni', transition, state) + gain * u[..., None]

    def acceleration(self, state: NDArray[np.float64],
                     u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return y'' (..., n) of the states (..., n, 2) with inputs u: ω²(u - y) - 2δω y'."""
        w, d = self.natural_frequency, self.damping
        return w * w * (u - state[..., 0]) - 2.0 * d * w * state[..., 1]


@dataclass(frozen=True, eq=False)
class ModelReferenceGains:
    """
    Reference model, initial gains and adaptation of :class:`ModelReferenceAdaptive`.

    Each a scalar (all joints) or a vector (n,).

    >>> ModelReferenceGains().natural_frequency
    array(5.)
    """

    natural_frequency: ArrayLike = 5.0   # ω_n [rad/s] of the reference model (8.76), > 0
    damping: ArrayLike = 1.0             # δ of the reference model (8.76), > 0
    kp: ArrayLike = 25.0                 # initial K_p [N m/rad], >= 0
    kv: ArrayLike = 10.0                 # initial K_v [N m s/rad], >= 0
    gamma_p: ArrayLike = 1.0             # MIT-rule rate of K_p [N m/rad³ per s], >= 0
    gamma_v: ArrayLike = 1.0             # MIT-rule rate of K_v [N m s/rad³ per s], >= 0
    w0: ArrayLike = 1.0                  # weight of ε in J (8.78), >= 0
    w1: ArrayLike = 0.0                  # weight of ε' [s]
    w2: ArrayLike = 0.0                  # weight of ε'' [s²] (uses the q'' estimate)
    acceleration_time_constant: ArrayLike = 0.0   # T [s] of the q'' estimate's low-pass

    def __post_init__(self) -> None:
        for name in ('natural_frequency', 'damping'):
            gain_field(self, name, positive=True)
        for name in ('kp', 'kv', 'gamma_p', 'gamma_v', 'w0', 'w1', 'w2',
                     'acceleration_time_constant'):
            gain_field(self, name)


class ModelReferenceAdaptive(JointControlLaw):
    """
    MRAC per joint, book (8.75)-(8.78): PD gains adapted so each joint follows its model.

    The number of joints is fixed by the first :meth:`update` until :meth:`reset` (as
    :class:`~.pid.DecoupledPID`). Assumptions of the discrete algorithm: module docstring.

    Examples
    --------
    >>> from robotica_ctrl.joint_control.law import JointReference, JointState
    >>> law = ModelReferenceAdaptive(ModelReferenceGains(kp=4.0, kv=1.0))
    >>> law.update(JointReference([0.5]), JointState([0.0], [0.2]), 0.01)   # 4·0.5 - 1·0.2
    array([1.8])
    >>> law.model_output          # the model started at the measured state
    array([0.])

    """

    def __init__(self, gains: ModelReferenceGains | None = None) -> None:
        if gains is not None and not isinstance(gains, ModelReferenceGains):
            raise ValueError(f'gains must be ModelReferenceGains, got {type(gains).__name__}')
        self.gains = ModelReferenceGains() if gains is None else gains
        self._model: ReferenceModel | None = None
        self._acceleration = AccelerationEstimate(0.0)
        self.reset()

    def reset(self) -> None:
        """Forget the model state, the adapted gains and the number of joints."""
        self._model = None
        self._acceleration.reset()
        empty = np.zeros(0)
        self._kp, self._kv, self._model_error = empty, empty, empty
        self._states = np.zeros((3, 0, 2))

    def _start(self, state: JointState) -> None:
        """Size the law for the state's n joints; start the reference model at the state."""
        n, g = state.n, self.gains
        self._model = ReferenceModel(per_joint('natural_frequency', g.natural_frequency, n),
                                     per_joint('damping', g.damping, n))
        self._kp, self._kv = per_joint('kp', g.kp, n), per_joint('kv', g.kv, n)
        self._rates = np.array([per_joint('gamma_p', g.gamma_p, n),
                                per_joint('gamma_v', g.gamma_v, n)])
        self._weights = [per_joint(name, getattr(g, name), n) for name in ('w0', 'w1', 'w2')]
        self._acceleration = AccelerationEstimate(
            per_joint('acceleration_time_constant', g.acceleration_time_constant, n))
        self._states = np.zeros((3, n, 2))
        self._states[0] = np.column_stack([state.q, state.qd])
        self._model_error = np.zeros(n)

    @property
    def proportional_gain(self) -> NDArray[np.float64]:
        """Return a copy of the adapted K_p (n,) [N m/rad] (empty before the first update)."""
        return self._kp.copy()

    @property
    def derivative_gain(self) -> NDArray[np.float64]:
        """Return a copy of the adapted K_v (n,) [N m s/rad] (empty before the first update)."""
        return self._kv.copy()

    @property
    def model_output(self) -> NDArray[np.float64]:
        """Return a copy of the reference model's output y (n,) [rad | m] for the next update."""
        return self._states[0, :, 0].copy()

    @property
    def model_error(self) -> NDArray[np.float64]:
        """Return a copy of ε = y - q (n,) of the last update (8.78)."""
        return self._model_error.copy()

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Return the names of :attr:`estimates`: ``joint_<i>.kp`` then ``joint_<i>.kv``."""
        n = self._kp.size
        return tuple(f'joint_{i + 1}.{gain}' for gain in ('kp', 'kv') for i in range(n))

    @property
    def estimates(self) -> NDArray[np.float64]:
        """Return the adapted gains [K_p; K_v] (2n,), the law's adapted parameters."""
        return np.concatenate([self._kp, self._kv])

    @property
    def adaptation_error(self) -> NDArray[np.float64]:
        """Return ε = y - q (n,), the error the adaptation minimises (8.78)."""
        return self.model_error

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau = K_p (q_d - q) - K_v q' (n,) [N m]; adapt the gains and step the models by dt.

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or a number of joints other than the first call's.

        """
        n = self.check_inputs(reference, state, dt)
        if self._model is None:
            self._start(state)
        if n != self._kp.size:
            raise ValueError(f'this law runs {self._kp.size} joints, got {n} (call reset() to '
                             'change)')
        assert self._model is not None
        q, qd, v = state.q, state.qd, reference.q_d
        qdd = self._acceleration.update(qd, dt)
        inputs = np.array([v, v - q, -qd])    # the model, the sensitivities to K_p and K_v
        states = self._states
        accelerations = self._model.acceleration(states, inputs)
        w0, w1, w2 = self._weights
        self._model_error = states[0, :, 0] - q
        criterion = (w2 * (accelerations[0] - qdd) + w1 * (states[0, :, 1] - qd)
                     + w0 * self._model_error)
        sensitivity = w2 * accelerations[1:] + w1 * states[1:, :, 1] + w0 * states[1:, :, 0]
        tau = self._kp * (v - q) - self._kv * qd
        step = dt * self._rates * criterion * sensitivity
        self._kp = np.maximum(self._kp + step[0], 0.0)
        self._kv = np.maximum(self._kv + step[1], 0.0)
        self._states = self._model.step(states, inputs, dt)
        return tau
