"""
Overlapping Allan deviation of a rate signal sampled at a constant period.

The standard tool to read gyro noise terms from a recording (IEEE Std 952-1997, annex C;
Riley, NIST SP 1065, 2008): on a log-log plot of σ(τ) white rate noise (angle random walk,
noise density N) falls as N/√τ (slope -1/2), a rate random walk K rises as K √(τ/3)
(slope +1/2), and bias instability shows as the flat floor in between. The book names the
gyro drift types without numbers (§7.7.3, seed catalogue §5.7 and Part 15); this module is the
check that the emulated gyro (:mod:`robotica_sim.sensors.gyro`) has the noise it claims.

With the angle θ_0 = 0, θ_j = dt Σ_{i<j} y_i (j = 0..n) of n rate samples y_i and τ = m dt,
the overlapping estimator is

    σ²(τ) = Σ_{k=0}^{n-2m} (θ_{k+2m} - 2 θ_{k+m} + θ_k)² / (2 τ² (n + 1 - 2m)).
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['allan_deviation', 'default_cluster_sizes']

_POINTS_PER_DECADE = 10  # default density of the log-spaced τ grid
_TAU_TOLERANCE = 1e-9    # relative mismatch allowed between a requested τ and m dt


def default_cluster_sizes(n: int) -> NDArray[np.int64]:
    """
    Return log-spaced cluster sizes m = 1 .. n // 2 (about ten per decade) for ``n`` samples.

    Raises ValueError for n < 2 (no τ has a second difference).

    >>> default_cluster_sizes(40)
    array([ 1,  2,  3,  4,  6,  7,  8, 11, 13, 16, 20])
    """
    if n < 2:
        raise ValueError(f'the Allan deviation needs at least 2 samples, got {n}')
    m_max = n // 2
    count = max(2, int(math.ceil(_POINTS_PER_DECADE * math.log10(m_max))) + 1)
    sizes = np.unique(np.rint(np.logspace(0.0, math.log10(m_max), count)).astype(np.int64))
    return sizes


def allan_deviation(
    samples: ArrayLike,
    dt: float,
    taus: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the overlapping Allan deviation of a rate signal.

    Parameters
    ----------
    samples : array_like, shape (n,)
        Rate samples y_i [unit] at the constant period ``dt`` (e.g. gyro readings [rad/s]),
        each the mean rate over its period; n >= 2, finite.
    dt : float
        Sample period [s], finite and > 0.
    taus : array_like, shape (k,), optional
        Averaging times τ [s], each a multiple m dt with 1 <= m <= n // 2 (within a relative
        1e-9). Default: :func:`default_cluster_sizes` times ``dt``.

    Returns
    -------
    taus : ndarray, shape (k,)
        The averaging times m dt [s], ascending when the default is used, else in the given
        order.
    adev : ndarray, shape (k,)
        Allan deviation σ(τ) [unit], the square root of the estimator in the module docstring.

    Raises
    ------
    ValueError
        On non-finite or too few samples, dt <= 0, or a τ that is not a multiple of dt or is
        outside [dt, (n // 2) dt].

    Examples
    --------
    A linear rate ramp y = R t has σ(τ) = R τ / √2 exactly:

    >>> t = 0.1 * np.arange(100)
    >>> allan_deviation(2.0 * t, 0.1, taus=[0.1, 1.0])[1] * math.sqrt(2.0) / 2.0
    array([0.1, 1. ])

    """
    y = np.asarray(samples, dtype=np.float64)
    if y.ndim != 1:
        raise ValueError(f'samples must have shape (n,), got shape {y.shape}')
    n = y.size
    if n < 2:
        raise ValueError(f'the Allan deviation needs at least 2 samples, got {n}')
    if not np.all(np.isfinite(y)):
        raise ValueError('samples must be finite')
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f'dt must be finite and > 0 s, got {dt!r}')
    if taus is None:
        sizes = default_cluster_sizes(n)
    else:
        requested = np.asarray(taus, dtype=np.float64)
        if requested.ndim != 1 or requested.size == 0 or not np.all(np.isfinite(requested)):
            raise ValueError(f'taus must be a non-empty finite vector of seconds, got {taus!r}')
        ratio = requested / dt
        sizes = np.rint(ratio).astype(np.int64)
        if np.any(np.abs(ratio - sizes) > _TAU_TOLERANCE * np.maximum(1.0, ratio)):
            raise ValueError(f'every tau must be a multiple of dt = {dt!r} s, got {taus!r}')
        if np.any(sizes < 1) or np.any(sizes > n // 2):
            raise ValueError(f'taus must lie in [dt, {n // 2} dt] for {n} samples, got {taus!r}')
    # The mean rate adds a line to θ, which second differences cancel: drop it for precision.
    theta = np.concatenate(([0.0], np.cumsum(y - y.mean()) * dt))
    adev = np.empty(sizes.size)
    for index, m in enumerate(sizes):
        m = int(m)
        tau = m * dt
        second = theta[2 * m:] - 2.0 * theta[m:-m] + theta[:-2 * m]
        adev[index] = math.sqrt(np.dot(second, second) / (2.0 * tau * tau * second.size))
    return sizes.astype(np.float64) * dt, adev
