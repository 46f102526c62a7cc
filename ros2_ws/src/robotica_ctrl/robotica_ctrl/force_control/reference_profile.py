"""
The task reference of a force law as a function of time: the shapes of Ej. 8.10 and 8.11.

Per task axis (normal axes first, as in :class:`~.task_frame.TaskFrame`):

* the position ``x_d(t) = x_0 + A sin(2π t / T + φ)`` [m] with its exact derivatives (A = 0: a
  set point; Ej. 8.10: x_d = (2.3, 2) m; Ej. 8.11: x_d2 = 2 + cos t, i.e. A = 1, T = 2π,
  φ = π/2);
* the force the end effector exerts on the environment ``ψ_d(t) = ψ_f (1 − e^{−t/τ})`` [N] with
  its exact derivatives (τ = 0: a step to ψ_f; Ej. 8.11: ψ_d1 = 1 − e^{−2t}, τ = 0.5 s).

t [s] is the time since the law's first step. A law reads the entries it uses (the stiffness law
positions only, the hybrid law the tangential positions and the normal forces).
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .law import TaskReference

__all__ = ['TaskReferenceProfile']


def _axes(name: str, value: ArrayLike, m: int) -> NDArray[np.float64]:
    """Return ``value`` (1 or m finite numbers) as an (m,) float64 array, or raise ValueError."""
    array = np.array(value, dtype=np.float64).reshape(-1)
    if array.size == 1:
        array = np.full(m, array[0])
    if array.shape != (m,) or not np.isfinite(array).all():
        raise ValueError(f'{name} must be 1 or {m} finite values (one per task axis), got '
                         f'{value!r}')
    return array


@dataclass(frozen=True, eq=False)
class TaskReferenceProfile:
    """
    x_d(t) = x_0 + A sin(2π t/T + φ) and ψ_d(t) = ψ_f (1 − e^{−t/τ}) per task axis.

    Each field takes 1 value (all axes) or one per axis; ``axes`` is the number m of task axes.

    Raises
    ------
    ValueError
        For values that are not finite, of the wrong size, a period <= 0 or a time constant < 0.

    Examples
    --------
    Ej. 8.11 at t = 0: x_d2 = 3 m, moving at 0 m/s; ψ_d1 = 0 N rising at 2 N/s.

    >>> profile = TaskReferenceProfile(2, offset=[0.0, 2.0], amplitude=[0.0, 1.0],
    ...                                phase=math.pi / 2, force=[1.0, 0.0], time_constant=0.5)
    >>> ref = profile.at(0.0)
    >>> ref.x_d.tolist(), ref.xd_d.round(12).tolist(), ref.psid_d.tolist()
    ([0.0, 3.0], [0.0, 0.0], [2.0, 0.0])

    """

    axes: int
    offset: ArrayLike = 0.0            # x_0 [m]
    amplitude: ArrayLike = 0.0         # A [m]
    period: ArrayLike = 2.0 * math.pi  # T [s] > 0
    phase: ArrayLike = 0.0             # φ [rad]
    force: ArrayLike = 0.0             # ψ_f [N], the final force on the environment
    time_constant: ArrayLike = 0.0     # τ [s] >= 0 of the force's rise; 0: a step

    def __post_init__(self) -> None:
        if not (isinstance(self.axes, int) and 1 <= self.axes <= 3):
            raise ValueError(f'axes must be 1 to 3, got {self.axes!r}')
        for name in ('offset', 'amplitude', 'period', 'phase', 'force', 'time_constant'):
            object.__setattr__(self, name, _axes(name, getattr(self, name), self.axes))
        if not (np.asarray(self.period) > 0.0).all():
            raise ValueError(f'period must be > 0 s, got {np.asarray(self.period).tolist()}')
        if not (np.asarray(self.time_constant) >= 0.0).all():
            raise ValueError('time_constant must be >= 0 s, got '
                             f'{np.asarray(self.time_constant).tolist()}')

    def at(self, t: float) -> TaskReference:
        """Return the reference at ``t`` [s] >= 0 since the start, with exact derivatives."""
        w = 2.0 * math.pi / np.asarray(self.period)
        angle = w * t + np.asarray(self.phase)
        a = np.asarray(self.amplitude)
        sin, cos = np.sin(angle), np.cos(angle)
        tau = np.asarray(self.time_constant)
        psi_f = np.asarray(self.force)
        stepped = tau == 0.0
        rate = np.where(stepped, 0.0, 1.0 / np.where(stepped, 1.0, tau))
        decay = np.where(stepped, 0.0, np.exp(-t * rate))
        return TaskReference(np.asarray(self.offset) + a * sin, a * w * cos, -a * w * w * sin,
                             psi_f * (1.0 - decay), psi_f * rate * decay,
                             -psi_f * rate * rate * decay)
