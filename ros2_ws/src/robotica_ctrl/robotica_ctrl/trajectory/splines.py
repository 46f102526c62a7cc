"""
Interpolating cubic splines through via points and Craig's via-velocity heuristic.

Book §10.3.2 (seed catalogue Part 8.4): a cubic spline passes through every via point with
continuous position, velocity and acceleration; the second derivatives at the points solve a
tridiagonal system (10.68) (Mortenson) closed by natural (zero end accelerations) or clamped
(given end velocities) conditions. SciPy's ``CubicSpline`` solves that system here. Book §10.6.1
(catalogue Part 8.7, fig. 10.12): for ``pol3`` the via velocities may be chosen by a heuristic,
:func:`via_velocities`. Units are those of ``q`` (rad or m) and seconds.
"""

import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from .polynomial import _check_timing, _check_via, _time_grid, PolyTrajectory

__all__ = ['cubic_spline', 'via_velocities']


def _check_times(t: ArrayLike, n_points: int) -> NDArray[np.float64]:
    """Return knot times (points,) as float64, finite and strictly increasing, or raise."""
    arr = np.asarray(t, dtype=np.float64)
    if arr.shape != (n_points,):
        raise ValueError(
            f't must hold one time per via point, shape ({n_points},), got {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError('t must be finite (no NaN or inf)')
    steps = np.diff(arr)
    if np.any(steps <= 0.0):
        k = int(np.flatnonzero(steps <= 0.0)[0])
        raise ValueError(f't must be strictly increasing: t[{k + 1}] = {arr[k + 1]!r} <= '
                         f't[{k}] = {arr[k]!r}')
    return arr


def _check_end_velocity(v: Optional[ArrayLike], n_joints: int, single: bool,
                        name: str) -> NDArray[np.float64]:
    """Return an end velocity as (joints,) (0 when None), from a scalar or (joints,)."""
    if v is None:
        return np.zeros(n_joints)
    arr = np.asarray(v, dtype=np.float64)
    if arr.ndim == 0:
        arr = np.full(n_joints, float(arr))
    elif single or arr.shape != (n_joints,):
        allowed = 'a scalar' if single else f'a scalar or shape ({n_joints},)'
        raise ValueError(f'{name} must be {allowed}, got shape {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    return arr


def cubic_spline(t: ArrayLike, q: ArrayLike, bc: str = 'natural',
                 qd0: Optional[ArrayLike] = None, qdf: Optional[ArrayLike] = None,
                 dt: float = 0.001) -> PolyTrajectory:
    """
    Return the interpolating cubic spline through via points, sampled every ``dt``.

    Book §10.3.2, eqs. (10.67)-(10.68) (catalogue Part 8.4): one cubic per interval
    ``[t_i, t_{i+1}]``, through every via point, with position, velocity and acceleration
    continuous at the interior points; the accelerations at the points solve the tridiagonal
    system (10.68), here by :class:`scipy.interpolate.CubicSpline`. End conditions: ``'natural'``
    (``qdd = 0`` at both ends) or ``'clamped'`` (given end velocities ``qd0``, ``qdf``; rest
    when omitted). All joints share the knot times. With two points, natural gives the straight
    line and clamped gives the cubic of ``pol3`` (10.25)-(10.39).

    Parameters
    ----------
    t : array_like, shape (points,)
        Absolute times of the via points [s], finite and strictly increasing.
    q : array_like, shape (points,) or (points, joints)
        Via points [rad or m], points >= 2.
    bc : {'natural', 'clamped'}
        End conditions.
    qd0, qdf : float or array_like, shape (joints,), optional
        Velocities at ``t[0]`` and ``t[-1]`` [rad/s or m/s], ``'clamped'`` only (default 0).
    dt : float
        Sampling period [s] > 0 (HEMERO's examples use 0.001).

    Returns
    -------
    coef : ndarray, shape (segments, 4) or (joints, segments, 4)
        ``[a0, a1, a2, a3]`` of each interval in its local time ``τ = t − t_i``, lowest power
        first: the layout of ``pol3``'s coefficients.
    time : ndarray, shape (samples,)
        ``t[0], t[0] + dt, ...`` up to ``t[-1]`` inclusive.
    q_t, qd_t, qdd_t : ndarray, shape (samples,) or (samples, joints)
        Sampled position, velocity and acceleration.

    Raises
    ------
    ValueError
        If an input is NaN/inf, the shapes disagree, fewer than 2 points are given, ``t`` is
        not strictly increasing, ``dt`` is not > 0, ``bc`` is unknown, or end velocities are
        given with ``bc='natural'``.

    Examples
    --------
    Clamped at rest through Ej. 10.1's points it is Ej. 10.1's cubic:

    >>> coef, time, q_t, qd_t, qdd_t = cubic_spline([0, 4], [10, 90], bc='clamped')
    >>> coef
    array([[10. ,  0. , 15. , -2.5]])
    >>> coef, time, q_t, qd_t, qdd_t = cubic_spline([0, 1, 2], [0, 1, 0], dt=0.5)
    >>> q_t, qdd_t
    (array([0. , 0.6875, 1. , 0.6875, 0. ]), array([ 0. , -1.5, -3. , -1.5,  0. ]))

    """
    qa = _check_via(q)
    times = _check_times(t, qa.shape[0])
    single = qa.ndim == 1
    q2 = qa.reshape(qa.shape[0], -1)
    n_joints = q2.shape[1]
    if bc == 'natural':
        if qd0 is not None or qdf is not None:
            raise ValueError("end velocities qd0/qdf need bc='clamped' (natural ends have "
                             'zero acceleration and free velocity)')
        bc_type: object = 'natural'
    elif bc == 'clamped':
        v0 = _check_end_velocity(qd0, n_joints, single, 'qd0')
        vf = _check_end_velocity(qdf, n_joints, single, 'qdf')
        bc_type = ((1, v0[0] if single else v0), (1, vf[0] if single else vf))
    else:
        raise ValueError(f"bc must be 'natural' or 'clamped', got {bc!r}")
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f'sampling period dt must be finite and > 0 s, got {dt!r}')
    spline = CubicSpline(times, qa, axis=0, bc_type=bc_type)
    # spline.c: (4, segments[, joints]), highest power first, local time t - t_i.
    coef = np.moveaxis(spline.c[::-1].reshape(4, -1, n_joints), 0, -1).transpose(1, 0, 2)
    time = _time_grid(float(times[0]), float(times[-1] - times[0]), dt)
    q_t = spline(time)
    qd_t = spline(time, 1)
    qdd_t = spline(time, 2)
    if single:
        return np.ascontiguousarray(coef[0]), time, q_t, qd_t, qdd_t
    return np.ascontiguousarray(coef), time, q_t, qd_t, qdd_t


def via_velocities(q: ArrayLike, tij: ArrayLike) -> NDArray[np.float64]:
    """
    Return via-point velocities for ``pol3`` by Craig's heuristic.

    Book §10.6.1 after (10.92), fig. 10.12 (catalogue Part 8.7, option (2)): with the segment
    slopes ``m_k = (q_{k+1} − q_k) / t_k``, the velocity at an interior via point is 0 when the
    slopes on its two sides change sign, else their average ``(m_{k−1} + m_k) / 2``; the first
    and last points are at rest. A flat neighbouring segment (slope 0) also gives 0, so the
    cubic of that segment does not overshoot its level.

    Parameters
    ----------
    q : array_like, shape (points,) or (points, joints)
        Via points [rad or m], points >= 2.
    tij : array_like, shape (points - 1,)
        Segment durations [s], each > 0 (a scalar is accepted for a single segment).

    Returns
    -------
    ndarray, shape of ``q``
        Velocities at the via points [rad/s or m/s], joint by joint.

    Raises
    ------
    ValueError
        If an input is NaN/inf, the shapes disagree, fewer than 2 points are given or a
        duration is not > 0.

    Examples
    --------
    Ej. 10.2's points and durations:

    >>> via_velocities([10, 5, 20], [2, 4])
    array([0., 0., 0.])
    >>> via_velocities([0, 10, 30, 0], [1, 2, 1])
    array([ 0., 10.,  0.,  0.])

    """
    qa = _check_via(q)
    dur = _check_timing(0.0, tij, 1.0, qa.shape[0] - 1)[1]
    q2 = qa.reshape(qa.shape[0], -1)
    slope = np.diff(q2, axis=0) / dur[:, np.newaxis]
    before, after = slope[:-1], slope[1:]
    inner = np.where(before * after > 0.0, 0.5 * (before + after), 0.0)
    zero = np.zeros((1, q2.shape[1]))
    return np.concatenate((zero, inner, zero)).reshape(qa.shape)
