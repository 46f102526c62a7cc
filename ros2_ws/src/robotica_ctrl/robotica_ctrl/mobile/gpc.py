"""
Generalised predictive control (GPC) and the GPC path tracker (book §9.5, (9.118)-(9.140)).

The SISO core follows Clarke, Mohtadi & Tuffs (1987), as summarised in Ollero (2001) §9.5:

* CARIMA model (9.118)-(9.120): ``A(q⁻¹) y(k) = B(q⁻¹) u(k-1) + ζ(k)/Δ`` with Δ = 1 - q⁻¹,
  ``A = 1 + a1 q⁻¹ + … + a_na q^-na`` and ``B = b0 + b1 q⁻¹ + … + b_nb q^-nb`` (C = 1, as
  in the book). Polynomials are coefficient arrays in rising powers of q⁻¹.
* Diophantine identity ``1 = E_j(q⁻¹) Ã(q⁻¹) + q^-j F_j(q⁻¹)`` with Ã = Δ A, solved
  recursively for j = 1 … N2 (:func:`diophantine`; the book's (9.132) is misprinted, see the
  seed catalogue, Part 17). deg E_j = j - 1, deg F_j = na.
* Prediction (9.124)-(9.126): ``ŷ(k+j) = G_j Δu(k+j-1) + F_j y(k)`` with ``G_j = E_j B``
  (9.131); the first j coefficients of G_j are the step response g_0 … g_(j-1), the rest act
  on past increments and go, with ``F_j y(k)``, into the free response f.
* Law (9.127)-(9.130), (9.136)-(9.139): ``Δu = (G1ᵀ G1 + λ I)⁻¹ G1ᵀ (w - f)`` over the rows
  j = N1 … N2 and the first NU columns; only its first element Δu(k) is applied (receding
  horizon) and u(k) = u(k-1) + Δu(k), which gives integral action. λ is constant (the book's
  λ(j) sequence with every weight equal).
* Reference softening (9.140) (Hess & Jung 1989): ``w(k+j) = y_d(k+j) - α^j [y_d(k+j) - y(k)]``
  with α = exp(-τ_e) in [0, 1): α = 0 leaves y_d unchanged (large τ_e), α → 1 asks for little
  action (small τ_e). For a constant y_d it is Clarke's first-order filter
  ``w(k+j) = α w(k+j-1) + (1 - α) y_d``, w(k) = y(k). The book prints y(k+j) in the bracket; the
  measured y(k) is meant (future outputs are not known).

The path tracker (§9.5 with the bicycle model of §9.4.4): the output is the lateral distance
to the path and the input the commanded curvature γ (fig. 9.28). The book linearises
(9.109)-(9.110) ``ξ' = -v φ``, ``φ' = γ v`` with the steering lag ``γ' = (u - γ)/τ``; in
REP-103, with the lateral offset e positive to the left of the path and the heading error
θ̃ = θ - θ_path (θ = φ + π/2, both measured in the same path-attached frame), the same model
reads ``e' = v θ̃``, ``θ̃' = v γ``, i.e. ``e = v²/(s² (τ s + 1)) u``. It is sampled with a
zero-order hold at the control period T (:func:`lateral_carima_model`) and rebuilt whenever the
speed changes (the procedure after (9.139)).

Each period the tracker attaches a frame to the path point closest to the vehicle, tangent to
the path there (the book's local coordinates (9.122)-(9.123), θ_path standing for φ_d(0)), and
works in the small-angle geometry of the model: a point at arc length σ along the path from
there and offset e to its left has the lateral coordinate ``e + Y(σ)``, with the unrolled path
``Y(σ) = ∫₀^σ (θ_path(σ') - θ_path(0)) dσ'`` (the sine of (9.122)-(9.123) replaced by its
angle, the distance along the tangent by the arc length). The output y(k) is the cross-track
error, the past outputs are ``e(k-i) + Y(s(k-i) - s(k))`` from the stored cross-track errors and
progress, and the desired outputs are ``y_d(k+j) = Y(v T j)``: the path the vehicle should
follow, previewed over the horizon, which makes a longer horizon anticipate curves (figs
9.29-9.31). On a circle the model is then exact, so γ settles on the path's curvature with
no steady-state error (the book: the steering command stays close to the path curvature).
"""

from collections import deque
from dataclasses import dataclass
import math
import numbers

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PathProjection, PolylinePath
from robotica_ctrl.mobile.tracker_base import PathTrackerBase
from robotica_kin.angles import wrap_to_pi

__all__ = ['diophantine', 'GpcController', 'GpcPathTracker', 'GpcTrackerCommand',
           'GpcTrackerParams', 'lateral_carima_model', 'prediction_polynomials',
           'soften_reference', 'step_response_matrix']


def _polynomial(c: ArrayLike, name: str, monic: bool = False) -> NDArray[np.float64]:
    """Return ``c`` as a finite, non-empty float64 vector (leading 1 if ``monic``)."""
    p = np.array(c, dtype=np.float64)
    if p.ndim != 1 or p.size == 0:
        raise ValueError(f'{name} must be a non-empty 1-D coefficient array, got shape {p.shape}')
    if not np.all(np.isfinite(p)):
        raise ValueError(f'{name} must be finite, got {p!r}')
    if monic and p[0] != 1.0:
        raise ValueError(f'{name}[0] must be 1 (monic polynomial in q^-1), got {p[0]!r}')
    return p


def _count(value: int, name: str, minimum: int) -> int:
    """Return ``value`` as an int >= ``minimum``, rejecting bools and non-integers."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f'{name} must be an integer, got {value!r}')
    if value < minimum:
        raise ValueError(f'{name} must be >= {minimum}, got {value!r}')
    return int(value)


def diophantine(a_tilde: ArrayLike,
                n2: int) -> tuple[list[NDArray[np.float64]], list[NDArray[np.float64]]]:
    """
    Solve ``1 = E_j Ã + q^-j F_j`` for j = 1 … n2 by the recursion of Clarke et al. (1987).

    Book (9.131)-(9.132) (the printed (9.132) is garbled). With Ã of degree n: E_1 = 1,
    F_1 = q (1 - Ã); then, with r = f_(j,0), E_(j+1) = E_j + r q^-j and
    f_(j+1,i) = f_(j,i+1) - r ã_(i+1) for i = 0 … n-1 (f_(j,n) = 0).

    Parameters
    ----------
    a_tilde : array_like, shape (n + 1,)
        Coefficients of Ã(q⁻¹) = Δ A(q⁻¹) in rising powers of q⁻¹, ``a_tilde[0] == 1``, n >= 1.
    n2 : int
        Largest prediction step N2 >= 1.

    Returns
    -------
    E : list of ndarray
        ``E[j - 1]``, shape (j,): coefficients of E_j.
    F : list of ndarray
        ``F[j - 1]``, shape (n,): coefficients of F_j.

    Raises
    ------
    ValueError
        If ``a_tilde`` is not a finite 1-D array of length >= 2 with leading 1, or n2 < 1.

    Examples
    --------
    A = 1 - 0.8 q⁻¹, so Ã = 1 - 1.8 q⁻¹ + 0.8 q⁻²:

    >>> E, F = diophantine([1.0, -1.8, 0.8], 2)
    >>> E[1], F[1]
    (array([1. , 1.8]), array([ 2.44, -1.44]))

    """
    at = _polynomial(a_tilde, 'a_tilde', monic=True)
    if at.size < 2:
        raise ValueError('a_tilde must have degree >= 1 (it holds the factor Δ = 1 - q^-1)')
    n2 = _count(n2, 'n2', 1)
    tail = [float(c) for c in at[1:]]
    n = len(tail)
    e = np.ones(n2)
    F = np.empty((n2, n))
    f = [-c for c in tail]
    F[0] = f
    for j in range(1, n2):
        r = f[0]
        e[j] = r
        f = [(f[i + 1] if i + 1 < n else 0.0) - r * tail[i] for i in range(n)]
        F[j] = f
    e.flags.writeable = False
    F.flags.writeable = False
    return [e[:j] for j in range(1, n2 + 1)], list(F)


def prediction_polynomials(
    a: ArrayLike, b: ArrayLike, n2: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """
    Return the step response and the free-response matrices of the CARIMA model (9.118).

    With ``G_j = E_j B`` (9.131) split as ``g_0 + … + g_(j-1) q^-(j-1)`` plus a tail, the
    prediction j steps ahead is ``ŷ(k+j) = Σ_(i<j) g_i Δu(k+j-1-i) + f(k+j)`` with the free
    response ``f(k+j) = F_j · [y(k), …, y(k-na)] + H_j · [Δu(k-1), …, Δu(k-nb)]``.

    Parameters
    ----------
    a : array_like, shape (na + 1,)
        A(q⁻¹) (9.119), ``a[0] == 1``.
    b : array_like, shape (nb + 1,)
        B(q⁻¹) (9.120) acting on u(k-1).
    n2 : int
        Prediction horizon N2 >= 1.

    Returns
    -------
    g : ndarray, shape (n2,)
        Step-response coefficients g_0 … g_(n2-1): g_(j-1) = y(j) for a unit step in u at 0.
    F : ndarray, shape (n2, na + 1)
        Row j - 1 holds F_j, acting on [y(k), …, y(k-na)].
    H : ndarray, shape (n2, nb)
        Row j - 1 holds the tail of G_j, acting on [Δu(k-1), …, Δu(k-nb)].

    Raises
    ------
    ValueError
        If ``a`` or ``b`` is not a finite 1-D array, ``a[0] != 1`` or n2 < 1.

    Examples
    --------
    >>> g, F, H = prediction_polynomials([1.0, -0.5], [2.0], 3)
    >>> g  # 2 (1 + 0.5 + 0.25)
    array([2. , 3. , 3.5])

    """
    a = _polynomial(a, 'a', monic=True)
    b = _polynomial(b, 'b')
    E, Fs = diophantine(np.convolve(a, [1.0, -1.0]), n2)
    # E_j is the first j terms of the series 1/Ã, so g_i = (E_N2 B)_i for i < N2, and the
    # tail of G_j = E_j B holds (E_j B)_(j+i) = Σ_(m<j) e_m b_(j+i-m), i = 0 … nb-1.
    e = E[-1]
    g = np.convolve(e, b)[:n2]
    nb = b.size - 1
    H = np.zeros((g.size, nb))
    rows = np.arange(1, g.size + 1)
    for i in range(nb):
        for r in range(i + 1, nb + 1):  # m = j + i - r runs over max(0, j + i - nb) … j - 1
            m = rows + i - r
            valid = m >= 0
            H[valid, i] += e[m[valid]] * b[r]
    return g, np.array(Fs), H


def step_response_matrix(a: ArrayLike, b: ArrayLike, n1: int, n2: int,
                         nu: int) -> NDArray[np.float64]:
    """
    Return the step-response matrix G1 (9.130), shape (n2 - n1 + 1, nu).

    Row r is prediction step j = n1 + r and column c the increment Δu(k+c):
    ``G1[r, c] = g_(j-1-c)`` (0 when j - 1 - c < 0); with n1 = 1 and nu = n2 it is the book's
    lower-triangular N × N matrix G of (9.125).

    Raises
    ------
    ValueError
        If the polynomials are invalid, n1 < 1, n2 < n1 or nu is not in 1 … n2.

    Examples
    --------
    >>> step_response_matrix([1.0, -0.5], [2.0], 1, 3, 2)
    array([[2. , 0. ],
           [3. , 2. ],
           [3.5, 3. ]])

    """
    n1, n2, nu = _horizons(n1, n2, nu)
    g = prediction_polynomials(a, b, n2)[0]
    return _g_matrix(g, n1, n2, nu)


def _horizons(n1: int, n2: int, nu: int) -> tuple[int, int, int]:
    """Validate the horizons N1 >= 1, N2 >= N1 and 1 <= NU <= N2."""
    n1 = _count(n1, 'n1', 1)
    n2 = _count(n2, 'n2', n1)
    nu = _count(nu, 'nu', 1)
    if nu > n2:
        raise ValueError(f'nu must be <= n2 = {n2}, got {nu}')
    return n1, n2, nu


def _g_matrix(g: NDArray[np.float64], n1: int, n2: int, nu: int) -> NDArray[np.float64]:
    """Build G1 from the step-response coefficients ``g`` (see :func:`step_response_matrix`)."""
    G = np.zeros((n2 - n1 + 1, nu))
    for r, j in enumerate(range(n1, n2 + 1)):
        for c in range(min(nu, j)):
            G[r, c] = g[j - 1 - c]
    return G


def soften_reference(y_d: ArrayLike, y: float, alpha: float) -> NDArray[np.float64]:
    """
    Return the softened reference (9.140) ``w_j = y_d(k+j) - α^j [y_d(k+j) - y(k)]``.

    Parameters
    ----------
    y_d : array_like, shape (n,)
        Desired outputs y_d(k+1) … y_d(k+n).
    y : float
        Measured output y(k).
    alpha : float
        α = exp(-τ_e) in [0, 1); 0 returns ``y_d`` unchanged.

    Raises
    ------
    ValueError
        If a value is not finite, ``y_d`` is not 1-D or α is outside [0, 1).

    Examples
    --------
    >>> soften_reference([1.0, 1.0, 1.0], 0.0, 0.5)
    array([0.5  , 0.75 , 0.875])

    """
    yd = _polynomial(y_d, 'y_d')
    _check_alpha(alpha)
    if not math.isfinite(y):
        raise ValueError(f'y must be finite, got {y!r}')
    decay = float(alpha) ** np.arange(1, yd.size + 1)
    softened: NDArray[np.float64] = yd - decay * (yd - float(y))
    return softened


def _check_alpha(alpha: float) -> None:
    if not (math.isfinite(alpha) and 0.0 <= alpha < 1.0):
        raise ValueError(f'alpha must be in [0, 1), got {alpha!r}')


class GpcController:
    """
    SISO generalised predictive controller of Clarke et al. (1987), book (9.118)-(9.140).

    Parameters
    ----------
    a : array_like, shape (na + 1,)
        A(q⁻¹) (9.119), ``a[0] == 1``.
    b : array_like, shape (nb + 1,)
        B(q⁻¹) (9.120), acting on u(k-1); not all zero.
    n1, n2 : int
        First and last prediction steps N1 >= 1, N2 >= N1 of the cost (9.121).
    nu : int
        Control horizon NU, 1 … N2 (9.128): Δu(k+j-1) = 0 for j > NU.
    lam : float
        Control weight λ >= 0 on Δu² (9.121), in (output unit / input unit)².
    alpha : float
        Reference softening α = exp(-τ_e) in [0, 1) (9.140); 0 = none.

    Raises
    ------
    ValueError
        On invalid polynomials or horizons, λ < 0 or not finite, α outside [0, 1), an all-zero
        B, or a singular G1ᵀ G1 + λ I (λ = 0 with too few informative rows).

    Notes
    -----
    The controller keeps y(k) … y(k-na), Δu(k-1) … Δu(k-nb) and u(k-1). At the first update
    after construction or :meth:`reset` the past outputs are taken equal to the first
    measurement and the past increments as zero: the model at rest.

    Examples
    --------
    First-order plant y(k) = 0.5 y(k-1) + u(k-1); with N1 = N2 = NU = 1 and λ = 0 the law
    is dead-beat: y(k+1) = w.

    >>> ctrl = GpcController([1.0, -0.5], [1.0], 1, 1, 1, 0.0, 0.0)
    >>> ctrl.update(0.0, 1.0)
    1.0
    >>> ctrl.update(1.0, 1.0)  # 0.5 * 1 + 0.5 = 1: held
    0.5

    """

    def __init__(self, a: ArrayLike, b: ArrayLike, n1: int, n2: int, nu: int, lam: float,
                 alpha: float = 0.0) -> None:
        self._a = _polynomial(a, 'a', monic=True)
        self._b = _polynomial(b, 'b')
        if not np.any(self._b != 0.0):
            raise ValueError('b must not be all zero: the input would not act on the output')
        self._n1, self._n2, self._nu = _horizons(n1, n2, nu)
        if not (math.isfinite(lam) and lam >= 0.0):
            raise ValueError(f'lam must be finite and >= 0, got {lam!r}')
        _check_alpha(alpha)
        self._lam = float(lam)
        self._alpha = float(alpha)
        self._g, self._F, self._H = prediction_polynomials(self._a, self._b, self._n2)
        self._G = _g_matrix(self._g, self._n1, self._n2, self._nu)
        hessian = self._G.T @ self._G + self._lam * np.eye(self._nu)
        eigenvalues = np.linalg.eigvalsh(hessian)
        if not eigenvalues[0] > 1e-12 * eigenvalues[-1]:
            raise ValueError('G1^T G1 + lam I is singular: raise lam, n2 or lower nu, n1')
        self._K: NDArray[np.float64] = np.asarray(np.linalg.solve(hessian, self._G.T),
                                                  dtype=np.float64)
        self._decay = self._alpha ** np.arange(1.0, self._n2 + 1.0)
        for array in (self._a, self._b, self._g, self._F, self._H, self._G, self._K,
                      self._decay):
            array.flags.writeable = False
        self._y_past: NDArray[np.float64] | None = None
        self._du_past = np.zeros(self._b.size - 1)
        self._u = 0.0
        self._prediction = np.zeros(0)

    @property
    def a(self) -> NDArray[np.float64]:
        """Return A(q⁻¹) (na + 1,)."""
        return self._a

    @property
    def b(self) -> NDArray[np.float64]:
        """Return B(q⁻¹) (nb + 1,)."""
        return self._b

    @property
    def horizons(self) -> tuple[int, int, int]:
        """Return (N1, N2, NU)."""
        return self._n1, self._n2, self._nu

    @property
    def lam(self) -> float:
        """Return the control weight λ."""
        return self._lam

    @property
    def alpha(self) -> float:
        """Return the reference-softening factor α."""
        return self._alpha

    @property
    def step_response(self) -> NDArray[np.float64]:
        """Return the step-response coefficients g_0 … g_(N2-1) (N2,)."""
        return self._g

    @property
    def G(self) -> NDArray[np.float64]:  # noqa: N802 (the book's name)
        """Return G1 (9.130), shape (N2 - N1 + 1, NU)."""
        return self._G

    @property
    def gain(self) -> NDArray[np.float64]:
        """Return M1 = (G1ᵀ G1 + λ I)⁻¹ G1ᵀ (9.139), shape (NU, N2 - N1 + 1)."""
        return self._K

    @property
    def u(self) -> float:
        """Return the last control, u at step k - 1 (0 after a reset)."""
        return self._u

    @property
    def prediction(self) -> NDArray[np.float64]:
        """Return ŷ(k+N1) … ŷ(k+N2) (9.125) of the last update with its planned Δu."""
        return self._prediction

    def reset(self, u: float = 0.0) -> None:
        """
        Forget the past: the next update starts from rest with u(k-1) = ``u``.

        Raises
        ------
        ValueError
            If ``u`` is not finite.

        """
        if not math.isfinite(u):
            raise ValueError(f'u must be finite, got {u!r}')
        self._y_past = None
        self._du_past = np.zeros(self._b.size - 1)
        self._u = float(u)
        self._prediction = np.zeros(0)

    def free_response(self, y_past: ArrayLike, du_past: ArrayLike) -> NDArray[np.float64]:
        """
        Return the free response f(k+1) … f(k+N2) (9.126): the prediction with Δu = 0 from k on.

        Parameters
        ----------
        y_past : array_like, shape (na + 1,)
            y(k), y(k-1), …, y(k-na), newest first.
        du_past : array_like, shape (nb,)
            Δu(k-1), …, Δu(k-nb), newest first.

        Raises
        ------
        ValueError
            If a history has the wrong shape or a non-finite value.

        """
        y = _history(y_past, self._a.size, 'y_past')
        du = _history(du_past, self._b.size - 1, 'du_past')
        f: NDArray[np.float64] = self._F @ y + self._H @ du
        return f

    def increments(self, y_past: ArrayLike, du_past: ArrayLike,
                   w: ArrayLike) -> NDArray[np.float64]:
        """
        Return the planned increments Δu(k) … Δu(k+NU-1) (9.129).

        Stateless but for :attr:`prediction`, which it sets: a caller that keeps its own
        histories (e.g. :class:`GpcPathTracker`) uses it instead of :meth:`update`.

        Parameters
        ----------
        y_past, du_past : array_like
            Histories as in :meth:`free_response`.
        w : float or array_like, shape (N2,)
            Desired outputs y_d(k+1) … y_d(k+N2) (only steps N1 … N2 are used), or one value
            for all of them; softened by (9.140) with α.

        Raises
        ------
        ValueError
            If a history or ``w`` has the wrong shape or a non-finite value.

        """
        y = _history(y_past, self._a.size, 'y_past')
        du = _history(du_past, self._b.size - 1, 'du_past')
        wv = np.asarray(w, dtype=np.float64)
        if wv.ndim == 0:
            wv = np.full(self._n2, float(wv))
        if wv.shape != (self._n2,) or not np.all(np.isfinite(wv)):
            raise ValueError(f'w must be finite, a scalar or of shape ({self._n2},), got {w!r}')
        return self._plan(y, du, wv)[0]

    def _plan(self, y: NDArray[np.float64], du: NDArray[np.float64],
              w: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return (Δu (NU,), softened reference (N2 - N1 + 1,)); set :attr:`prediction`."""
        rows = slice(self._n1 - 1, self._n2)
        f = (self._F @ y + self._H @ du)[rows]
        target = (w - self._decay * (w - y[0]))[rows]
        increments: NDArray[np.float64] = self._K @ (target - f)
        self._prediction = self._G @ increments + f
        return increments, target

    def update(self, y: float, w: ArrayLike) -> float:
        """
        Return u(k) = u(k-1) + Δu(k) for measurement y(k) and reference ``w``.

        Parameters
        ----------
        y : float
            Output y(k).
        w : float or array_like, shape (N2,)
            Reference, as in :meth:`increments`.

        Raises
        ------
        ValueError
            If ``y`` or ``w`` is invalid (the state is then unchanged).

        """
        if not math.isfinite(y):
            raise ValueError(f'y must be finite, got {y!r}')
        if self._y_past is None:
            y_past = np.full(self._a.size, float(y))
        else:
            y_past = np.concatenate(([float(y)], self._y_past[:-1]))
        du = float(self.increments(y_past, self._du_past, w)[0])
        self._y_past = y_past
        self._du_past = np.concatenate(([du], self._du_past))[:self._b.size - 1]
        self._u += du
        return self._u


def _history(values: ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """Return ``values`` as a finite (n,) vector."""
    h = np.asarray(values, dtype=np.float64)
    if h.shape != (n,) or not np.all(np.isfinite(h)):
        raise ValueError(f'{name} must be a finite vector of shape ({n},), got {values!r}')
    return h


def lateral_carima_model(speed: float, sample_time: float, steering_time_constant: float = 0.0
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return A(q⁻¹), B(q⁻¹) of the linearised lateral bicycle model at ``speed``, sampled with ZOH.

    Continuous model (9.109)-(9.113) in REP-103 form: ``e' = v θ̃``, ``θ̃' = v γ`` and, when
    τ > 0, ``γ' = (u - γ)/τ``; output e (lateral offset [m], > 0 left), input u (commanded
    curvature [1/m]), so e = v² / (s² (τ s + 1)) u. With a zero-order hold at T this is
    ``A(q⁻¹) e(k) = B(q⁻¹) u(k-1)``; τ = 0 gives the double integrator
    A = 1 - 2 q⁻¹ + q⁻², B = (v T)²/2 (1 + q⁻¹); τ > 0 gives
    A = (1 - q⁻¹)² (1 - p q⁻¹), p = exp(-T/τ), and three B coefficients.

    Parameters
    ----------
    speed : float
        Forward speed v > 0 [m/s].
    sample_time : float
        Sampling period T > 0 [s].
    steering_time_constant : float
        Steering lag τ >= 0 [s] (0: the curvature follows the command at once).

    Returns
    -------
    a : ndarray, shape (3,) or (4,)
    b : ndarray, shape (2,) or (3,)

    Raises
    ------
    ValueError
        If v or T is not positive and finite, or τ is negative or not finite.

    Examples
    --------
    >>> lateral_carima_model(1.0, 0.1)
    (array([ 1., -2.,  1.]), array([0.005, 0.005]))

    """
    for name, value in (('speed', speed), ('sample_time', sample_time)):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f'{name} must be positive and finite, got {value!r}')
    tau = steering_time_constant
    if not (math.isfinite(tau) and tau >= 0.0):
        raise ValueError(f'steering_time_constant must be finite and >= 0 s, got {tau!r}')
    v, t = float(speed), float(sample_time)
    if tau == 0.0:
        phi = [[1.0, v * t], [0.0, 1.0]]
        gamma = [0.5 * (v * t) ** 2, v * t]
    else:
        # Exact ZOH solution of the states (e, θ̃, γ) over one period (derived by integrating
        # γ(t) = p(t) γ0 + (1 - p(t)) u twice), p = exp(-T/τ).
        p = math.exp(-t / tau)
        lag = tau * (1.0 - p)
        phi = [[1.0, v * t, v * v * tau * (t - lag)],
               [0.0, 1.0, v * lag],
               [0.0, 0.0, p]]
        gamma = [v * v * (0.5 * t * t - tau * t + tau * lag), v * (t - lag), 1.0 - p]
    return _transfer_function(phi, gamma)


def _transfer_function(
    phi: list[list[float]], gamma: list[float]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return A, B of ``e(z)/u(z) = C (zI - Φ)⁻¹ Γ`` with C = [1, 0, …] (Faddeev–LeVerrier).

    det(zI - Φ) = z^n + c_1 z^(n-1) + … + c_n and adj(zI - Φ) = Σ_k M_k z^(n-k) with
    M_1 = I, M_k = Φ M_(k-1) + c_(k-1) I, c_k = -tr(Φ M_k)/k; dividing by z^n gives A in q⁻¹
    and, the numerator being of degree n - 1, a one-step delay times B = [C M_k Γ].
    """
    n = len(phi)
    a = [1.0] + [0.0] * n
    b = [0.0] * n
    m = [[float(i == j) for j in range(n)] for i in range(n)]
    for k in range(1, n + 1):
        if k > 1:
            m = [[sum(phi[i][r] * m[r][j] for r in range(n)) + a[k - 1] * (i == j)
                  for j in range(n)] for i in range(n)]
        a[k] = -sum(phi[i][r] * m[r][i] for i in range(n) for r in range(n)) / k
        b[k - 1] = sum(m[0][r] * gamma[r] for r in range(n))
    return np.array(a), np.array(b)


@dataclass(frozen=True)
class GpcTrackerParams:
    """
    Tunables of :class:`GpcPathTracker`.

    The defaults follow the NavLab experiment of §9.5 where the book gives numbers (18 path
    points, NU = 1, N1 = 1); the other values are ours.

    Raises
    ------
    ValueError
        If a float is not positive and finite (``steering_time_constant`` and ``softening``
        may be 0, ``control_weight`` too when the problem stays well posed, ``max_curvature``
        may be infinite), a horizon is not an integer with 1 <= n1 <= n2 and 1 <= nu <= n2,
        or ``softening`` is not in [0, 1).

    Examples
    --------
    >>> GpcTrackerParams(n2=25).n2
    25

    """

    linear_velocity: float = 1.0  # v [m/s], commanded forward speed (> 0)
    sample_time: float = 0.1  # T [s], control period: call update once per period
    steering_time_constant: float = 0.0  # τ [s], first-order steering lag (0: none), (9.113)
    n1: int = 1  # N1, first predicted step (9.121)
    n2: int = 18  # N2, last predicted step (9.121); NavLab: 18 points
    nu: int = 1  # NU, control horizon (9.128); NavLab: 1
    control_weight: float = 0.1  # λ [m⁴] on Δγ² (9.121): output in m, input in 1/m
    softening: float = 0.0  # α = exp(-τ_e) in [0, 1), reference softening (9.140)
    max_curvature: float = math.inf  # [1/m], |γ| limit of the vehicle
    model_speed_tolerance: float = 0.0  # relative speed change that rebuilds the model (0: any)
    goal_tolerance: float = 0.05  # [m]
    search_window: float = 2.0  # [m], closest-point search around the progress

    def __post_init__(self) -> None:
        _horizons(self.n1, self.n2, self.nu)
        for name in ('linear_velocity', 'sample_time', 'goal_tolerance', 'search_window'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        for name in ('steering_time_constant', 'control_weight', 'model_speed_tolerance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (self.max_curvature > 0.0):
            raise ValueError(f'max_curvature must be > 0 1/m, got {self.max_curvature!r}')
        if not (math.isfinite(self.softening) and 0.0 <= self.softening < 1.0):
            raise ValueError(f'softening must be in [0, 1), got {self.softening!r}')


@dataclass(frozen=True)
class GpcTrackerCommand:
    """
    Output of one :meth:`GpcPathTracker.update`.

    Attributes
    ----------
    linear : float
        Forward velocity v [m/s] in ``base_link`` (0 once finished).
    angular : float
        Yaw rate ω = v γ [rad/s], > 0 counter-clockwise.
    curvature : float
        Commanded curvature γ = u(k) [1/m], > 0 turns left.
    cross_track : float
        Lateral offset from the path [m], > 0 left of it (the output y(k)).
    heading_error : float
        θ - θ_path [rad], wrapped to (-π, π].
    projection : PathProjection
        The vehicle's projection onto the path.
    reference : ndarray, shape (N2 - N1 + 1,)
        Softened desired lateral offsets w(k+N1) … w(k+N2) [m] in the local, unrolled path
        frame (module docstring): the path previewed over the horizon.
    prediction : ndarray, shape (N2 - N1 + 1,)
        Predicted lateral offsets ŷ(k+N1) … ŷ(k+N2) [m] with the planned increments.
    finished : bool
        Whether the end of the path has been reached (then the command is zero).

    """

    linear: float
    angular: float
    curvature: float
    cross_track: float
    heading_error: float
    projection: PathProjection
    reference: NDArray[np.float64]
    prediction: NDArray[np.float64]
    finished: bool

    def __post_init__(self) -> None:
        for name in ('reference', 'prediction'):
            value = np.array(getattr(self, name), dtype=np.float64)
            value.flags.writeable = False
            object.__setattr__(self, name, value)


class GpcPathTracker(PathTrackerBase[GpcTrackerParams]):
    """
    GPC path tracker of a :class:`PolylinePath` (book §9.5, fig. 9.28; Ollero & Amidi 1991).

    Each period: project the position on the path (in a window around the progress, as
    :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`); take the frame tangent to the
    path at the closest point; express the current and past positions and the path an arc
    length v T j ahead (j = 1 … N2) as lateral offsets in it (module docstring); compute
    Δγ(k) by (9.129) and apply γ(k) = γ(k-1) + Δγ(k), limited to ``max_curvature`` (the
    applied increment is the one remembered). The model (9.118) comes from
    :func:`lateral_carima_model` at the current speed and is rebuilt when that speed changes
    by more than ``model_speed_tolerance``.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses (e.g. ``odom``).
    params : GpcTrackerParams
        Tunables; replace them with :meth:`set_params`.

    Raises
    ------
    ValueError
        If ``params`` make the GPC problem singular (λ = 0 with too few rows).

    Notes
    -----
    :meth:`update` must be called once per ``sample_time``: the stored cross-track errors and
    progress give the model's past outputs. After construction or :meth:`reset` the vehicle
    is assumed to have driven straight along its current heading with γ = 0 (the model at
    rest). Beyond the end of the path the reference continues along the last segment. As
    :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`, it stops (zero command) once
    within ``goal_tolerance`` of the end, until :meth:`reset`.

    Examples
    --------
    >>> from robotica_ctrl.mobile.path import PolylinePath
    >>> tracker = GpcPathTracker(PolylinePath([[0.0, 0.0], [20.0, 0.0]]), GpcTrackerParams())
    >>> cmd = tracker.update([0.0, 0.0, 0.0])
    >>> cmd.linear, cmd.curvature, cmd.cross_track
    (1.0, 0.0, 0.0)

    """

    def __init__(self, path: PolylinePath, params: GpcTrackerParams) -> None:
        super().__init__(path, params)
        self._model_speed = params.linear_velocity
        self._controller = _build_controller(params, self._model_speed)
        self.reset()

    @property
    def controller(self) -> GpcController:
        """Return the GPC core built for the current model."""
        return self._controller

    def set_params(self, params: GpcTrackerParams) -> None:
        """
        Use ``params`` from now on; the model is rebuilt, the progress and history kept.

        Raises
        ------
        ValueError
            If the new GPC problem is singular (the old params are then kept).

        """
        self._controller = _build_controller(params, params.linear_velocity)
        self._params = params
        self._model_speed = params.linear_velocity

    def reset(self, curvature: float = 0.0) -> None:
        """
        Restart from the beginning of the path, with γ(k-1) = ``curvature`` [1/m].

        Raises
        ------
        ValueError
            If ``curvature`` is not finite.

        """
        if not math.isfinite(curvature):
            raise ValueError(f'curvature must be finite, got {curvature!r}')
        super().reset()
        self._history: deque[tuple[float, float]] = deque(maxlen=_MAX_HISTORY)
        self._du_past: deque[float] = deque(maxlen=_MAX_HISTORY)
        self._u = float(curvature)

    def update(self, pose: ArrayLike, speed: float | None = None) -> GpcTrackerCommand:
        """
        Return the command for the vehicle pose ``pose`` (one period of fig. 9.28).

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame, θ from the x axis.
        speed : float, optional
            Measured forward speed [m/s] > 0 for the model (book: the model at the current
            speed); defaults to ``params.linear_velocity``. The commanded speed is always
            ``params.linear_velocity``.

        Returns
        -------
        GpcTrackerCommand

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector or ``speed`` is not positive and finite.

        Examples
        --------
        1 m left of a straight path, heading along it: turn right (γ < 0).

        >>> from robotica_ctrl.mobile.path import PolylinePath
        >>> path = PolylinePath([[0.0, 0.0], [20.0, 0.0]])
        >>> cmd = GpcPathTracker(path, GpcTrackerParams()).update([0.0, 1.0, 0.0])
        >>> cmd.cross_track, cmd.curvature < 0.0
        (1.0, True)

        """
        params = self._params
        v = params.linear_velocity if speed is None else speed
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f'speed must be positive and finite, got {speed!r}')
        x, projection = self._locate(pose)
        if abs(v - self._model_speed) > params.model_speed_tolerance * self._model_speed:
            self._controller = _build_controller(params, v)
            self._model_speed = v
        ctrl = self._controller
        path = self._path
        e = projection.cross_track
        heading_error = float(wrap_to_pi(float(x[2]) - projection.tangent_heading))
        if self._finished:
            zeros = np.zeros(params.n2 - params.n1 + 1)
            return GpcTrackerCommand(0.0, 0.0, 0.0, e, heading_error, projection, zeros, zeros,
                                     True)
        na = ctrl.a.size - 1
        nb = ctrl.b.size - 1
        step = v * params.sample_time
        past = list(self._history)[:na]
        ahead = projection.s + step * np.arange(1.0, params.n2 + 1.0)
        offsets = _unrolled_offsets(path, projection,
                                    np.concatenate(([s for _, s in past], ahead)))
        y_past = np.empty(na + 1)
        y_past[0] = e
        for i, (e_i, _) in enumerate(past, start=1):
            y_past[i] = e_i + offsets[i - 1]
        # Missing past outputs (after a reset): driven straight at the current heading, γ = 0.
        for i in range(len(past) + 1, na + 1):
            y_past[i] = y_past[i - 1] - step * heading_error
        du_past = np.zeros(nb)
        recent = list(self._du_past)[:nb]
        du_past[:len(recent)] = recent
        increments, reference = ctrl._plan(y_past, du_past, offsets[len(past):])
        u = min(max(self._u + float(increments[0]), -params.max_curvature),
                params.max_curvature)
        self._du_past.appendleft(u - self._u)
        self._u = u
        self._history.appendleft((e, projection.s))
        linear = params.linear_velocity
        return GpcTrackerCommand(linear, linear * u, u, e, heading_error, projection, reference,
                                 ctrl.prediction, False)


_MAX_HISTORY = 4  # past outputs and increments kept: na + 1 <= 4, nb <= 2


def _unrolled_offsets(path: PolylinePath, projection: PathProjection,
                      s: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return the path's unrolled lateral offsets Y(s) [m] from its point at ``projection.s``.

    Y(σ) = ∫ (θ_path(σ') - θ_path(s0)) dσ' from s0 = ``projection.s`` to σ, the lateral offset
    of the path in the frame tangent to it at s0 with the small-angle geometry of the model
    (sin replaced by its angle, arc length for the longitudinal coordinate). Headings are
    unwrapped along the path; before its start and after its end the path continues straight.
    """
    s0 = projection.s
    lo, hi = min(float(s.min()), s0), max(float(s.max()), s0)
    last = len(path.headings) - 1
    i_lo = min(max(int(np.searchsorted(path.s, lo, side='right')) - 1, 0), projection.segment)
    i_hi = max(min(int(np.searchsorted(path.s, hi, side='right')) - 1, last),
               projection.segment)
    headings = np.unwrap(path.headings[i_lo:i_hi + 1])
    relative = headings - headings[projection.segment - i_lo]
    breaks = np.concatenate(([lo], path.s[i_lo + 1:i_hi + 1], [hi]))
    integral = np.concatenate(([0.0], np.cumsum(np.diff(breaks) * relative)))
    offsets: NDArray[np.float64] = np.interp(s, breaks, integral) - np.interp(s0, breaks,
                                                                              integral)
    return offsets


def _build_controller(params: GpcTrackerParams, speed: float) -> GpcController:
    """Return the GPC core of the lateral model at ``speed`` [m/s] (procedure after (9.139))."""
    a, b = lateral_carima_model(speed, params.sample_time, params.steering_time_constant)
    return GpcController(a, b, params.n1, params.n2, params.nu, params.control_weight,
                         params.softening)
