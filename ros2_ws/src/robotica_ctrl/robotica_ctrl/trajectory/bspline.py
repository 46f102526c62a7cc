"""
B-spline and Bézier curves from a control polygon (book §10.3.2, seed catalogue Part 8.4).

A B-spline of order k (degree k − 1, C^{k−2}) is ``p(λ) = Σ V_i B_{i,k}(λ)`` (10.69) with the
Cox–de Boor basis (10.70)-(10.72) on the clamped uniform knots (10.73)-(10.75); it starts at the
first vertex, ends at the last, and stays in the convex hull of the polygon. A Bézier curve
weighs the vertices with Bernstein polynomials: the B-spline whose order is the number of
vertices. SciPy's ``BSpline`` and ``BPoly`` evaluate them. Units are those of the vertices; the
parameter λ (or s) has none, so derivatives are per unit of parameter.
"""

from typing import Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import BPoly, BSpline

__all__ = ['bezier', 'bspline', 'bspline_knots']

BSplineCurve = Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                     NDArray[np.float64], NDArray[np.float64]]
BezierCurve = Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]

_PARAM_TOL = 1e-12


def _check_order(order: int) -> int:
    """Return the B-spline order k as an int >= 2, or raise ValueError."""
    if isinstance(order, (bool, np.bool_)) or not isinstance(order, (int, np.integer)):
        raise ValueError(f'order must be an integer >= 2, got {order!r}')
    if order < 2:
        raise ValueError(f'order must be >= 2 (degree order - 1 >= 1), got {order}')
    return int(order)


def _check_polygon(control_points: ArrayLike, minimum: int, why: str) -> NDArray[np.float64]:
    """Return vertices as float64 (N,) or (N, dim), finite, N >= minimum, or raise."""
    arr = np.asarray(control_points, dtype=np.float64)
    if arr.ndim not in (1, 2) or arr.size == 0:
        raise ValueError('control_points must have shape (N,) or (N, dim), got '
                         f'{arr.shape}')
    if arr.shape[0] < minimum:
        raise ValueError(f'{why}: need at least {minimum} control points, got {arr.shape[0]}')
    if not np.all(np.isfinite(arr)):
        raise ValueError('control_points must be finite (no NaN or inf)')
    return arr


def _check_parameter(values: ArrayLike, upper: float, name: str) -> NDArray[np.float64]:
    """Return parameter values (samples,) in [0, upper], finite, or raise ValueError."""
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f'{name} must be a non-empty 1-D array, got shape {arr.shape}')
    if not np.all(np.isfinite(arr)):
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    tol = _PARAM_TOL * max(1.0, upper)
    if np.any(arr < -tol) or np.any(arr > upper + tol):
        raise ValueError(f'{name} must lie in [0, {upper:g}], got values in '
                         f'[{arr.min():g}, {arr.max():g}]')
    return np.clip(arr, 0.0, upper)


def bspline_knots(n_points: int, order: int = 4) -> NDArray[np.float64]:
    """
    Return the clamped uniform knot vector of a B-spline (book (10.73)-(10.75)).

    For vertices ``V_0 … V_N`` (``n_points = N + 1``) and order k: ``λ_i = 0`` for
    ``0 ≤ i < k``, ``λ_i = i − k + 1`` for ``k ≤ i ≤ N`` and ``λ_i = N − k + 2`` for
    ``N < i ≤ N + k``: each end knot has multiplicity k, so the curve starts at the first vertex
    and ends at the last, and ``λ_max = N − k + 2 = n_points − k + 1``.

    Parameters
    ----------
    n_points : int
        Number of control points, >= ``order``.
    order : int
        Order k >= 2 (degree k − 1).

    Returns
    -------
    ndarray, shape (n_points + order,)
        The knots, non-decreasing.

    Raises
    ------
    ValueError
        If ``order`` < 2 or ``n_points`` < ``order``.

    Examples
    --------
    >>> bspline_knots(6, 4)
    array([0., 0., 0., 0., 1., 2., 3., 3., 3., 3.])

    """
    k = _check_order(order)
    if isinstance(n_points, (bool, np.bool_)) or not isinstance(n_points, (int, np.integer)):
        raise ValueError(f'n_points must be an integer, got {n_points!r}')
    if n_points < k:
        raise ValueError(f'a B-spline of order {k} needs at least {k} control points, got '
                         f'{n_points}')
    i = np.arange(n_points + k, dtype=np.float64)
    return np.clip(i - k + 1, 0.0, float(n_points - k + 1))


def bspline(control_points: ArrayLike, order: int = 4,
            samples: Union[int, ArrayLike] = 101) -> BSplineCurve:
    """
    Return a clamped uniform B-spline and its first two derivatives.

    Book §10.3.2, eqs. (10.69)-(10.79) (catalogue Part 8.4): ``p(λ) = Σ_i V_i B_{i,k}(λ)`` with
    the Cox–de Boor basis (10.70)-(10.72) (the printed second denominator of (10.72) should read
    ``λ_{i+k} − λ_{i+1}``, catalogue Part 17) on the knots of :func:`bspline_knots`, evaluated by
    :class:`scipy.interpolate.BSpline`. Order k gives degree k − 1 and continuity C^{k−2}; k = 4
    (cubic) is the lowest with continuous heading and curvature. The curve interpolates only
    the first and last vertices and stays in the convex hull of the polygon.

    Parameters
    ----------
    control_points : array_like, shape (N,) or (N, dim)
        Control polygon ``V_0 …`` [m or rad], N >= ``order``.
    order : int
        Order k >= 2.
    samples : int or array_like, shape (samples,)
        Number (>= 2) of equally spaced parameter values over ``[0, λ_max]``, ends included,
        or the parameter values themselves, each in ``[0, λ_max]``.

    Returns
    -------
    knots : ndarray, shape (N + order,)
        The clamped uniform knots (10.73)-(10.75); ``λ_max = knots[-1] = N − order + 1``.
    lam : ndarray, shape (samples,)
        Parameter values λ.
    p, dp, ddp : ndarray, shape (samples,) or (samples, dim)
        ``p(λ)``, ``dp/dλ`` and ``d²p/dλ²`` (zero for order 2) in the units of the vertices
        per unit of λ.

    Raises
    ------
    ValueError
        If a vertex is NaN/inf, the polygon has the wrong shape or fewer vertices than
        ``order``, ``order`` < 2, or ``samples`` is < 2 or outside ``[0, λ_max]``.

    Examples
    --------
    >>> knots, lam, p, dp, ddp = bspline([[0, 0], [1, 2], [3, 2], [4, 0]], order=3, samples=3)
    >>> knots
    array([0., 0., 0., 1., 2., 2., 2.])
    >>> p
    array([[0., 0.], [2., 2.], [4., 0.]])
    >>> dp[0]
    array([2., 4.])

    """
    k = _check_order(order)
    vertices = _check_polygon(control_points, k, f'a B-spline of order {k}')
    knots = bspline_knots(vertices.shape[0], k)
    lam_max = float(knots[-1])
    if np.ndim(samples) == 0:
        count = samples
        if (isinstance(count, (bool, np.bool_)) or not isinstance(count, (int, np.integer))
                or count < 2):
            raise ValueError(f'samples must be an integer >= 2 or an array of parameter '
                             f'values, got {samples!r}')
        lam = np.linspace(0.0, lam_max, int(count))
    else:
        lam = _check_parameter(samples, lam_max, 'samples')
    curve = BSpline(knots, vertices, k - 1, extrapolate=False, axis=0)
    p = curve(lam)
    dp = curve(lam, 1)
    ddp = curve(lam, 2) if k >= 3 else np.zeros_like(p)
    return knots, lam, p, dp, ddp


def bezier(control_points: ArrayLike, s: ArrayLike) -> BezierCurve:
    """
    Return the Bézier curve of a control polygon and its first two derivatives.

    Book §10.3.2 (catalogue Part 8.4): ``p(s) = Σ_{i=0}^{N−1} C(N−1, i) s^i (1 − s)^{N−1−i} V_i``,
    s ∈ [0, 1] (Bernstein weights; :class:`scipy.interpolate.BPoly`), the B-spline whose order
    is the number of vertices N. It starts at ``V_0`` with tangent ``(N − 1)(V_1 − V_0)``, ends
    at ``V_{N−1}`` with tangent ``(N − 1)(V_{N−1} − V_{N−2})`` and stays in the convex hull of
    the polygon; moving one vertex changes the whole curve.

    Parameters
    ----------
    control_points : array_like, shape (N,) or (N, dim)
        Control polygon [m or rad], N >= 2 (degree N − 1).
    s : float or array_like, shape (samples,)
        Parameter values in [0, 1] (a scalar is one sample).

    Returns
    -------
    p, dp, ddp : ndarray, shape (samples,) or (samples, dim)
        ``p(s)``, ``dp/ds`` and ``d²p/ds²`` (zero for N = 2) in the units of the vertices.

    Raises
    ------
    ValueError
        If a vertex or ``s`` is NaN/inf, the polygon has the wrong shape or fewer than 2
        vertices, or ``s`` is outside [0, 1].

    Examples
    --------
    >>> p, dp, ddp = bezier([[0, 0], [1, 2], [3, 2], [4, 0]], [0.0, 0.5, 1.0])
    >>> p
    array([[0. , 0. ], [2. , 1.5], [4. , 0. ]])
    >>> dp[0], ddp[1]
    (array([3., 6.]), array([ 0., -12.]))

    """
    vertices = _check_polygon(control_points, 2, 'a Bézier curve')
    params = _check_parameter(s, 1.0, 's')
    curve = BPoly(vertices[:, np.newaxis, ...], [0.0, 1.0])
    p = curve(params)
    dp = curve(params, 1)
    ddp = curve(params, 2) if vertices.shape[0] >= 3 else np.zeros_like(p)
    return p, dp, ddp
