"""
Joint accelerations estimated from measured velocities, for the laws that need q'' (book §8.4).

The adaptive computed torque of §8.4.2 (its regressor W(q, q', q''), (8.79)-(8.95)) and the MRAC
criterion of (8.78) (ε'') use the joint accelerations, which a joint controller does not measure:
the book names it as the drawback of the method (measured accelerations are noisy). Here
``q''_k ≈ (q'_k - q'_{k-1}) / dt``, optionally low-pass filtered by ``1 / (T s + 1)`` discretised
by backward Euler, ``f_k = f_{k-1} + dt / (T + dt) (raw_k - f_{k-1})`` (``T`` =
``time_constant``; 0: unfiltered), as the derivative filter of
:class:`~robotica_ctrl.joint_control.pid.DecoupledPID`. The first estimate, with no previous
velocity, is zero. The difference is the mean acceleration over the last period: half a period
late, plus the filter's lag.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .law import check_dt, per_joint

__all__ = ['AccelerationEstimate']


class AccelerationEstimate:
    """
    q'' [rad/s² | m/s²] from successive measured velocities q' (n,), by differencing.

    Parameters
    ----------
    time_constant : float or array_like, shape (n,)
        T [s] of the first-order low-pass filter, >= 0 (0: the raw difference).

    Examples
    --------
    >>> estimate = AccelerationEstimate()
    >>> estimate.update(np.array([0.0, 1.0]), 0.01)      # first call: zero
    array([0., 0.])
    >>> estimate.update(np.array([0.1, 1.0]), 0.01)
    array([10.,  0.])

    """

    def __init__(self, time_constant: ArrayLike = 0.0) -> None:
        constant = np.asarray(time_constant, dtype=np.float64)
        if constant.ndim > 1 or not (np.isfinite(constant).all() and (constant >= 0.0).all()):
            raise ValueError('time_constant must be a scalar or a vector of finite values >= 0 s, '
                             f'got {time_constant!r}')
        self.time_constant = constant
        self._velocity: NDArray[np.float64] | None = None
        self._estimate: NDArray[np.float64] | None = None

    def reset(self) -> None:
        """Forget the previous velocity and the filter state."""
        self._velocity = None
        self._estimate = None

    def update(self, qd: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
        """
        Return the estimate of q'' (n,) from the velocity ``qd`` (n,) measured ``dt`` [s] later.

        ``qd`` is a checked float64 vector (a :class:`~.law.JointState`'s). Raises ValueError for
        ``dt <= 0``, or a size other than the previous call's.
        """
        check_dt(dt)
        previous = self._velocity
        if previous is not None and previous.shape != qd.shape:
            raise ValueError(f'qd has shape {qd.shape}, the previous one {previous.shape}')
        self._velocity = qd.copy()
        if previous is None or self._estimate is None:
            self._estimate = np.zeros(qd.shape)
            return self._estimate.copy()
        raw = (qd - previous) / dt
        weight = dt / (per_joint('time_constant', self.time_constant, qd.size) + dt)
        self._estimate = self._estimate + weight * (raw - self._estimate)
        return self._estimate.copy()
