"""
Sinusoidal joint references: Ej. 8.1 (8.47) and the appendix's PUMA example (A.2).

``q_d(t) = offset + A sin(2π t / T + φ)`` per joint, with its exact first and second
derivatives. Ej. 8.1 uses ``θ1d = A sin(2πt/T)``, ``θ2d = A cos(2πt/T)`` (φ2 = π/2) with
A = 0.15 rad and T = 4 s; the PUMA example ``θ_i = sin t`` (A = 1 rad, T = 2π s).
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['sinusoid']


def sinusoid(t: ArrayLike, amplitude: ArrayLike, period: ArrayLike, phase: ArrayLike = 0.0,
             offset: ArrayLike = 0.0) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                               NDArray[np.float64]]:
    """
    Return ``(q, qd, qdd)`` of ``offset + amplitude sin(2π t / period + phase)`` at times ``t``.

    Parameters
    ----------
    t : array_like, shape (m,)
        Times [s].
    amplitude, period, phase, offset : array_like, scalar or shape (n,)
        A [rad | m], T [s] (> 0), φ [rad] and the offset [rad | m] per joint; scalars apply
        to every joint. n is the longest of them (1 if all are scalars).

    Returns
    -------
    q, qd, qdd : ndarray, shape (m, n)
        Positions [rad | m], velocities [/s] and accelerations [/s²].

    Raises
    ------
    ValueError
        For a non-positive period, non-finite values or per-joint sizes that disagree.

    Examples
    --------
    Ej. 8.1 (8.47) at t = 1 s (a quarter period): θ1d = 0.15, θ2d = 0.

    >>> q, qd, qdd = sinusoid([1.0], 0.15, 4.0, [0.0, np.pi / 2])
    >>> np.round(q, 12).tolist()
    [[0.15, 0.0]]

    """
    times = np.asarray(t, dtype=np.float64)
    if times.ndim != 1 or not np.isfinite(times).all():
        raise ValueError(f't must be a finite vector of times [s], got shape {times.shape}')
    values = {name: np.atleast_1d(np.asarray(v, dtype=np.float64)) for name, v in
              (('amplitude', amplitude), ('period', period), ('phase', phase),
               ('offset', offset))}
    for name, v in values.items():
        if v.ndim != 1 or not np.isfinite(v).all():
            raise ValueError(f'{name} must be a finite scalar or vector (n,), got {v!r}')
    n = max(v.size for v in values.values())
    for name, v in values.items():
        if v.size not in (1, n):
            raise ValueError(f'{name} has {v.size} values, expected 1 or {n}')
    if np.any(values['period'] <= 0.0):
        raise ValueError(f'period must be > 0 s, got {period!r}')
    omega = 2.0 * np.pi / values['period']
    angle = np.outer(times, omega) + values['phase']
    a = values['amplitude'] * np.ones(n)
    q = values['offset'] + a * np.sin(angle)
    qd = a * omega * np.cos(angle)
    qdd = -a * omega ** 2 * np.sin(angle)
    return q, qd, qdd
