"""
Piecewise cubic and quintic joint trajectories through via points (HEMERO ``pol3``, ``pol5``).

Book §10.3.1 and §10.6 (seed catalogue Part 8.3 and 8.7): each segment between two via points
is a polynomial in its own local time τ ∈ [0, T] fixed by the positions and velocities (cubic,
(10.25)-(10.39), (10.91)-(10.92)) or positions, velocities and accelerations (quintic,
(10.40)-(10.52), (10.100)-(10.102)) at its two ends. Coefficients are listed lowest power first.
Units are those of ``q`` (rad or m) and seconds.
"""

import math
from typing import Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['pol3', 'pol5']

PolyTrajectory = Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                       NDArray[np.float64], NDArray[np.float64]]


def _check_via(q: ArrayLike, name: str = 'q') -> NDArray[np.float64]:
    """Return via points as float64 (points,) or (points, joints), or raise ValueError."""
    arr = np.asarray(q, dtype=np.float64)
    if arr.ndim not in (1, 2):
        raise ValueError(f'{name} must have shape (points,) or (points, joints), got {arr.shape}')
    if arr.shape[0] < 2 or arr.size == 0:
        raise ValueError(f'{name} needs at least 2 via points, got shape {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    return arr


def _check_like(x: ArrayLike, shape: Tuple[int, ...], name: str) -> NDArray[np.float64]:
    """Return ``x`` as float64 of exactly ``shape`` (same as q), finite, or raise ValueError."""
    arr = np.asarray(x, dtype=np.float64)
    if arr.shape != shape:
        raise ValueError(f'{name} must have the shape of q {shape}, got {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    return arr


def _check_timing(t0: float, tij: ArrayLike, dt: float,
                  n_segments: int) -> Tuple[float, NDArray[np.float64], float]:
    """Validate start time, segment durations (n_segments,) and sampling period."""
    t0 = float(t0)
    if not math.isfinite(t0):
        raise ValueError(f't0 must be finite, got {t0!r}')
    dur = np.atleast_1d(np.asarray(tij, dtype=np.float64))
    if dur.shape != (n_segments,):
        raise ValueError(
            f'tij must hold one duration per segment, shape ({n_segments},), got {dur.shape}')
    if not np.all(np.isfinite(dur)) or np.any(dur <= 0.0):
        raise ValueError(f'segment durations tij must be finite and > 0 s, got {dur}')
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f'sampling period dt must be finite and > 0 s, got {dt!r}')
    return t0, dur, dt


def _time_grid(t0: float, total: float, dt: float) -> NDArray[np.float64]:
    """Return t0, t0 + dt, ... up to t0 + total inclusive (the end is always a sample)."""
    tol = 1e-9 * max(1.0, total)
    n = int(math.floor(total / dt + 1e-9))
    time = t0 + dt * np.arange(n + 1, dtype=np.float64)
    if total - n * dt > tol:
        time = np.append(time, t0 + total)
    else:
        time[-1] = t0 + total
    return time


def _eval_piecewise(coef: NDArray[np.float64], breaks: NDArray[np.float64],
                    time: NDArray[np.float64]) -> Tuple[NDArray[np.float64], ...]:
    """
    Evaluate piecewise polynomials and their first two derivatives.

    ``coef`` (joints, pieces, order+1) lowest power first in local time, ``breaks``
    (joints, pieces+1) absolute piece limits, ``time`` (samples,). Returns three
    (samples, joints) arrays. At a break the later piece is used.
    """
    n_joints, n_pieces, n_coef = coef.shape
    powers = np.arange(n_coef)
    out = np.zeros((3, time.size, n_joints))
    for j in range(n_joints):
        idx = np.clip(np.searchsorted(breaks[j], time, side='right') - 1, 0, n_pieces - 1)
        tau = time - breaks[j, idx]
        c = coef[j, idx, :]
        tau_pow = tau[:, np.newaxis] ** powers
        out[0, :, j] = np.sum(c * tau_pow, axis=1)
        d1 = c[:, 1:] * powers[1:]
        out[1, :, j] = np.sum(d1 * tau_pow[:, :-1], axis=1)
        d2 = c[:, 2:] * (powers[2:] * (powers[2:] - 1))
        out[2, :, j] = np.sum(d2 * tau_pow[:, :-2], axis=1)
    return out[0], out[1], out[2]


def _sample(coef: NDArray[np.float64], t0: float, dur: NDArray[np.float64], dt: float,
            single: bool) -> PolyTrajectory:
    """Sample coefficients (joints, segments, k) with common durations; shape the outputs."""
    breaks = t0 + np.concatenate(([0.0], np.cumsum(dur)))
    time = _time_grid(t0, float(np.sum(dur)), dt)
    all_breaks = np.broadcast_to(breaks, (coef.shape[0], breaks.size))
    q_t, qd_t, qdd_t = _eval_piecewise(coef, all_breaks, time)
    if single:
        return coef[0], time, q_t[:, 0], qd_t[:, 0], qdd_t[:, 0]
    return coef, time, q_t, qd_t, qdd_t


def _polytraj(q: ArrayLike, qd: ArrayLike, qdd: Optional[ArrayLike], t0: float,
              tij: ArrayLike, dt: float) -> PolyTrajectory:
    """Shared body of pol3 (qdd None) and pol5."""
    qa = _check_via(q)
    qda = _check_like(qd, qa.shape, 'qd')
    qdda = None if qdd is None else _check_like(qdd, qa.shape, 'qdd')
    t0, dur, dt = _check_timing(t0, tij, dt, qa.shape[0] - 1)
    single = qa.ndim == 1
    q2 = qa.reshape(qa.shape[0], -1)
    v2 = qda.reshape(q2.shape)
    p0, pf, v0, vf = q2[:-1], q2[1:], v2[:-1], v2[1:]
    T = dur[:, np.newaxis]
    dq = pf - p0
    if qdda is None:
        # Book (10.91)-(10.92) = (10.25)-(10.39) with lambda_f = T.
        cols = [p0, v0,
                3.0 * dq / T**2 - 2.0 * v0 / T - vf / T,
                -2.0 * dq / T**3 + (vf + v0) / T**2]
    else:
        a2 = qdda.reshape(q2.shape)
        a0, af = a2[:-1], a2[1:]
        # Book (10.40)-(10.52) = (10.100)-(10.102) with lambda_f = T.
        cols = [p0, v0, a0 / 2.0,
                (20.0 * dq - (8.0 * vf + 12.0 * v0) * T - (3.0 * a0 - af) * T**2) / (2.0 * T**3),
                (-30.0 * dq + (14.0 * vf + 16.0 * v0) * T + (3.0 * a0 - 2.0 * af) * T**2)
                / (2.0 * T**4),
                (12.0 * dq - (6.0 * vf + 6.0 * v0) * T - (a0 - af) * T**2) / (2.0 * T**5)]
    coef = np.ascontiguousarray(np.transpose(np.stack(cols, axis=-1), (1, 0, 2)))
    return _sample(coef, t0, dur, dt, single)


def pol3(q: ArrayLike, qd: ArrayLike, t0: float, tij: ArrayLike, dt: float) -> PolyTrajectory:
    """
    Return cubic segments through via points with given velocities, sampled every ``dt``.

    HEMERO ``[Qcoef, time, q_t, qd_t, qdd_t] = pol3(q, qd, t0, tij, dt)`` (book §10.3.1 and
    §10.6.1, eqs. (10.25)-(10.39), (10.89)-(10.92); Ejemplos 10.1 and 10.2). Segment i is
    ``q(τ) = a0 + a1 τ + a2 τ² + a3 τ³``, τ ∈ [0, T_i], with ``a0 = q_i``, ``a1 = qd_i``,
    ``a2 = 3 (q_{i+1} − q_i)/T² − 2 qd_i/T − qd_{i+1}/T``,
    ``a3 = −2 (q_{i+1} − q_i)/T³ + (qd_{i+1} + qd_i)/T²``. Position and velocity are continuous;
    acceleration generally jumps at the via points.

    Parameters
    ----------
    q : array_like, shape (points,) or (points, joints)
        Via points [rad or m], points >= 2.
    qd : array_like, same shape as ``q``
        Velocities at the via points [rad/s or m/s].
    t0 : float
        Start time [s].
    tij : array_like, shape (points - 1,)
        Segment durations [s], each > 0 (a scalar is accepted for a single segment).
    dt : float
        Sampling period [s] > 0.

    Returns
    -------
    coef : ndarray, shape (segments, 4) or (joints, segments, 4)
        ``[a0, a1, a2, a3]`` of each segment in its local time, lowest power first.
    time : ndarray, shape (samples,)
        ``t0, t0 + dt, ...`` up to ``t0 + sum(tij)`` inclusive (the last step may be shorter
        if the total is not a multiple of ``dt``).
    q_t, qd_t, qdd_t : ndarray, shape (samples,) or (samples, joints)
        Sampled position, velocity and acceleration (at a via point, the later segment).

    Raises
    ------
    ValueError
        If an input is NaN/inf, the shapes disagree, fewer than 2 points are given, or a
        duration or ``dt`` is not > 0.

    Examples
    --------
    Ejemplo 10.1: 10 → 90 in 4 s from and to rest.

    >>> coef, time, q_t, qd_t, qdd_t = pol3([10, 90], [0, 0], 0, 4, 0.001)
    >>> coef
    array([[10. ,  0. , 15. , -2.5]])
    >>> float(q_t[2000]), float(qd_t[2000]), time.shape
    (50.0, 30.0, (4001,))

    """
    return _polytraj(q, qd, None, t0, tij, dt)


def pol5(q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, t0: float, tij: ArrayLike,
         dt: float) -> PolyTrajectory:
    """
    Return quintic segments through via points with given velocities and accelerations.

    HEMERO ``[Qcoef, time, q_t, qd_t, qdd_t] = pol5(q, qd, qdd, t0, tij, dt)`` (book §10.3.1
    and §10.6.3, eqs. (10.40)-(10.52), (10.100)-(10.102); Ejemplos 10.3 and 10.4). Segment i
    is ``q(τ) = a0 + a1 τ + ... + a5 τ⁵``, τ ∈ [0, T_i], with ``a0 = q_i``, ``a1 = qd_i``,
    ``a2 = qdd_i/2`` and a3..a5 from the end conditions (catalogue Part 8.3 closed form).
    Position, velocity and acceleration are continuous at the via points.

    Parameters
    ----------
    q : array_like, shape (points,) or (points, joints)
        Via points [rad or m], points >= 2.
    qd, qdd : array_like, same shape as ``q``
        Velocities [rad/s] and accelerations [rad/s²] at the via points.
    t0 : float
        Start time [s].
    tij : array_like, shape (points - 1,)
        Segment durations [s], each > 0 (a scalar is accepted for a single segment).
    dt : float
        Sampling period [s] > 0.

    Returns
    -------
    coef : ndarray, shape (segments, 6) or (joints, segments, 6)
        ``[a0, ..., a5]`` of each segment in its local time, lowest power first.
    time : ndarray, shape (samples,)
        ``t0`` to ``t0 + sum(tij)`` inclusive, step ``dt``.
    q_t, qd_t, qdd_t : ndarray, shape (samples,) or (samples, joints)
        Sampled position, velocity and acceleration.

    Raises
    ------
    ValueError
        If an input is NaN/inf, the shapes disagree, fewer than 2 points are given, or a
        duration or ``dt`` is not > 0.

    Examples
    --------
    Ejemplo 10.3: Ejemplo 10.1 with end accelerations 10 and 30.

    >>> coef = pol5([10, 90], [0, 0], [10, 30], 0, 4, 0.001)[0]
    >>> coef
    array([[10.   ,  0.   ,  5.   , 12.5  , -5.625,  0.625]])

    """
    return _polytraj(q, qd, qdd, t0, tij, dt)
