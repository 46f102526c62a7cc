"""
Linear segments with parabolic blends through via points (HEMERO ``parab``).

Book §10.6.4 and §10.7 after Craig (seed catalogue Part 8.7): the joint moves at constant
velocity between via points and changes velocity in parabolic blends of constant acceleration
around them. The trajectory starts and ends at rest exactly at the first and last points and
only approaches the interior via points (closer for larger accelerations).
"""

import math
from typing import List, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .polynomial import _check_timing, _check_via, _eval_piecewise, _time_grid

__all__ = ['parab']

BlendTrajectory = Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                        NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]

_TOL = 1e-9


def _check_acc(ac: ArrayLike, shape: Tuple[int, int], single: bool) -> NDArray[np.float64]:
    """Return blend accelerations broadcast to (points, joints), or raise ValueError."""
    arr = np.asarray(ac, dtype=np.float64)
    n_points, n_joints = shape
    if arr.ndim == 0:
        full = np.full(shape, float(arr))
    elif single and arr.shape == (n_points,):
        full = arr.reshape(shape)
    elif not single and arr.shape == (n_joints,):
        full = np.broadcast_to(arr, shape).copy()
    elif not single and arr.shape == shape:
        full = arr.copy()
    else:
        allowed = '() or (points,)' if single else '(), (joints,) or (points, joints)'
        raise ValueError(f'ac must have shape {allowed} for q of shape '
                         f'{(n_points,) if single else shape}, got {arr.shape}')
    if not np.all(np.isfinite(full)) or np.any(full <= 0.0):
        raise ValueError(f'blend accelerations ac must be finite and > 0, got {arr}')
    return full


def _single_segment(q: NDArray[np.float64], acc: NDArray[np.float64], td: float,
                    joint: str) -> Tuple[List[float], List[float]]:
    """Return piece durations and accelerations of a one-segment LSPB (10.103)-(10.107)."""
    dq = q[1] - q[0]
    if dq == 0.0:
        return [0.0, td, 0.0], [0.0, 0.0, 0.0]
    sgn = math.copysign(1.0, dq)
    k = 0.5 / acc[0] + 0.5 / acc[1]
    disc = td**2 - 4.0 * k * abs(dq)
    if disc < -_TOL * td**2:
        raise ValueError(
            f'{joint}acceleration too small for the segment: with equal blend accelerations '
            f'|qdd| >= 4 |q_f - q_0| / t_f^2 = {4.0 * abs(dq) / td**2:.6g} is needed (10.107), '
            f'got {acc[0]:.6g} and {acc[1]:.6g}')
    # Cruise speed v from |dq| = v (t_f - v/(2 a_0) - v/(2 a_f)); for a_0 = a_f = a this gives
    # t_b = t_f/2 - sqrt(a² t_f² - 4 a |dq|)/(2 a), the corrected (10.106).
    speed = (td - math.sqrt(max(disc, 0.0))) / (2.0 * k)
    t_a, t_b = speed / acc[0], speed / acc[1]
    return [t_a, max(td - t_a - t_b, 0.0), t_b], [sgn * acc[0], 0.0, -sgn * acc[1]]


def _via_segments(q: NDArray[np.float64], acc: NDArray[np.float64], td: NDArray[np.float64],
                  joint: str) -> Tuple[List[float], List[float]]:
    """Return piece durations and accelerations of a multi-segment LSPB (10.108)-(10.122)."""
    n = q.size
    dq = np.diff(q)
    vel = dq / td                                           # (10.108) interior slopes
    blend_t = np.zeros(n)
    blend_a = np.zeros(n)
    # First segment: blend starts at t = 0 from rest at q_1.
    if dq[0] != 0.0:
        disc = td[0]**2 - 2.0 * abs(dq[0]) / acc[0]
        if disc < -_TOL * td[0]**2:
            raise ValueError(
                f'{joint}acceleration at the first point too small for the first segment: '
                f'minimum 2 |q_2 - q_1| / t_d12^2 = {2.0 * abs(dq[0]) / td[0]**2:.6g}, '
                f'got {acc[0]:.6g}')
        blend_a[0] = math.copysign(acc[0], dq[0])
        blend_t[0] = td[0] - math.sqrt(max(disc, 0.0))
        vel[0] = dq[0] / (td[0] - 0.5 * blend_t[0])
    else:
        vel[0] = 0.0
    # Last segment: blend ends at rest exactly at q_n.
    if dq[-1] != 0.0:
        disc = td[-1]**2 - 2.0 * abs(dq[-1]) / acc[-1]
        if disc < -_TOL * td[-1]**2:
            raise ValueError(
                f'{joint}acceleration at the last point too small for the last segment: '
                f'minimum 2 |q_n - q_n-1| / t_d^2 = {2.0 * abs(dq[-1]) / td[-1]**2:.6g}, '
                f'got {acc[-1]:.6g}')
        blend_a[-1] = -math.copysign(acc[-1], dq[-1])        # |qdd_n| sgn(q_n-1 - q_n)
        blend_t[-1] = td[-1] - math.sqrt(max(disc, 0.0))
        vel[-1] = dq[-1] / (td[-1] - 0.5 * blend_t[-1])
    else:
        vel[-1] = 0.0
    # Interior blends (10.110)-(10.111).
    for k in range(1, n - 1):
        dv = vel[k] - vel[k - 1]
        if dv != 0.0:
            blend_a[k] = math.copysign(acc[k], dv)
            blend_t[k] = abs(dv) / acc[k]
    # Linear durations (10.112), (10.116), (10.120).
    lin = td - 0.5 * blend_t[:-1] - 0.5 * blend_t[1:]
    lin[0] -= 0.5 * blend_t[0]
    lin[-1] -= 0.5 * blend_t[-1]
    for i in range(n - 1):
        if lin[i] < -_TOL * td[i]:
            dv_sum = blend_t[i] * acc[i] + blend_t[i + 1] * acc[i + 1]
            raise ValueError(
                f'{joint}blends at points {i + 1} and {i + 2} overlap (linear duration '
                f'{lin[i]:.6g} s < 0): accelerations too small for segment {i + 1}; with the '
                f'current slopes a common |qdd| >= {dv_sum / (2.0 * td[i]):.6g} is needed')
    lin = np.maximum(lin, 0.0)
    durations: List[float] = []
    accels: List[float] = []
    for i in range(n - 1):
        durations += [float(blend_t[i]), float(lin[i])]
        accels += [float(blend_a[i]), 0.0]
    return durations + [float(blend_t[-1])], accels + [float(blend_a[-1])]


def parab(q: ArrayLike, ac: ArrayLike, t0: float, tij: ArrayLike, dt: float) -> BlendTrajectory:
    """
    Return linear segments with parabolic blends through via points, sampled every ``dt``.

    HEMERO ``[Qcoef, time, q_t, qd_t, qdd_t, interv] = parab(q, ac, t0, tij, dt)`` (book
    §10.6.4, §10.7, eqs. (10.103)-(10.128); Ejemplos 10.5 and 10.6). With two points it is the
    rest-to-rest LSPB (10.103)-(10.107) (symmetric blends ``t_b = t_f/2 − sqrt(a² t_f² −
    4 a Δq)/(2a)`` when both accelerations are equal, the corrected (10.106)). With more points
    it is Craig's multi-segment LSPB (10.108)-(10.122): the first blend starts at ``t0`` from
    rest at ``q[0]``, the last ends at rest at ``q[-1]`` at ``t0 + sum(tij)``, interior blends
    are centred on the via-point times; interior via points are only approached. Sampling uses
    the continuous form of (10.123)-(10.128) (the printed (10.126) drops a term).

    Parameters
    ----------
    q : array_like, shape (points,) or (points, joints)
        Via points [rad or m], points >= 2.
    ac : float or array_like
        Blend acceleration magnitudes |qdd_k| > 0 [rad/s²]: a scalar, one per via point
        (points,) as in HEMERO for one joint, or for several joints one per joint (joints,)
        or per point and joint (points, joints).
    t0 : float
        Start time [s].
    tij : array_like, shape (points - 1,)
        Durations between the via points t_djk [s], each > 0.
    dt : float
        Sampling period [s] > 0.

    Returns
    -------
    coef : ndarray, shape (2 points - 1, 3) or (joints, 2 points - 1, 3)
        Pieces in time order (blend 1, linear 1-2, blend 2, ..., blend n), each
        ``[c0, c1, c2]`` of ``q(τ) = c0 + c1 τ + c2 τ²`` in its local time, c2 = qdd_k/2 in a
        blend and 0 in a linear piece.
    time : ndarray, shape (samples,)
        ``t0`` to ``t0 + sum(tij)`` inclusive, step ``dt``.
    q_t, qd_t, qdd_t : ndarray, shape (samples,) or (samples, joints)
        Sampled position, velocity and acceleration.
    interv : ndarray, shape (2 points - 1,) or (joints, 2 points - 1)
        Piece durations [s] ``[t_1, t_12, t_2, t_23, ..., t_n]`` (blends and linear parts).

    Raises
    ------
    ValueError
        On NaN/inf, mismatched shapes, fewer than 2 points, non-positive durations, ``dt`` or
        ``ac``, or an acceleration too small for a segment (the message gives the minimum).

    Examples
    --------
    Ejemplo 10.5: 10 → 90 in 4 s with |qdd| = 30 gives blends of 0.845 s.

    >>> coef, time, q_t, qd_t, qdd_t, interv = parab([10, 90], [30, 30], 0, 4, 0.001)
    >>> interv.round(4)
    array([0.8453, 2.3094, 0.8453])
    >>> float(q_t[-1]), float(qd_t[-1])
    (90.0, 0.0)

    """
    qa = _check_via(q)
    single = qa.ndim == 1
    q2 = qa.reshape(qa.shape[0], -1)
    acc = _check_acc(ac, q2.shape, single)
    t0, dur, dt = _check_timing(t0, tij, dt, qa.shape[0] - 1)
    n_points, n_joints = q2.shape
    n_pieces = 2 * n_points - 1
    coef = np.zeros((n_joints, n_pieces, 3))
    interv = np.zeros((n_joints, n_pieces))
    breaks = np.zeros((n_joints, n_pieces + 1))
    for j in range(n_joints):
        joint = '' if single else f'joint {j}: '
        if n_points == 2:
            pieces, accels = _single_segment(q2[:, j], acc[:, j], float(dur[0]), joint)
        else:
            pieces, accels = _via_segments(q2[:, j], acc[:, j], dur, joint)
        pos, vel = float(q2[0, j]), 0.0
        for i, (d, a) in enumerate(zip(pieces, accels)):
            coef[j, i] = [pos, vel, 0.5 * a]
            pos += vel * d + 0.5 * a * d * d
            vel += a * d
        interv[j] = pieces
        breaks[j] = t0 + np.concatenate(([0.0], np.cumsum(pieces)))
    time = _time_grid(t0, float(np.sum(dur)), dt)
    q_t, qd_t, qdd_t = _eval_piecewise(coef, breaks, time)
    if single:
        return coef[0], time, q_t[:, 0], qd_t[:, 0], qdd_t[:, 0], interv[0]
    return coef, time, q_t, qd_t, qdd_t, interv
