"""
Generalised predictive control (GPC), the SISO law of book §9.5, (9.118)-(9.140).

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

The lateral path tracker of §9.5 built on it is :mod:`robotica_ctrl.mobile.gpc_tracker`.
"""

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['check_horizons', 'diophantine', 'GpcController', 'prediction_polynomials',
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
    n1, n2, nu = check_horizons(n1, n2, nu)
    g = prediction_polynomials(a, b, n2)[0]
    return _g_matrix(g, n1, n2, nu)


def check_horizons(n1: int, n2: int, nu: int) -> tuple[int, int, int]:
    """
    Return the horizons (N1, N2, NU) as ints, checked: N1 >= 1, N2 >= N1, 1 <= NU <= N2.

    Raises
    ------
    ValueError
        If one is not an integer (bools refused) or out of its range.

    >>> check_horizons(1, 18, 1)
    (1, 18, 1)

    """
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
        self._n1, self._n2, self._nu = check_horizons(n1, n2, nu)
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
        histories uses it (or :meth:`plan`) instead of :meth:`update`.

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
        return self.plan(y_past, du_past, w)[0]

    def plan(self, y_past: ArrayLike, du_past: ArrayLike,
             w: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """
        Return the planned increments (NU,) and the softened reference (N2 - N1 + 1,).

        As :meth:`increments`, which returns the first; the second is w(k+N1) … w(k+N2) of
        (9.140), what the planned outputs :attr:`prediction` are compared with.

        Raises
        ------
        ValueError
            If a history or ``w`` has the wrong shape or a non-finite value.

        >>> ctrl = GpcController([1.0, -0.5], [1.0], 1, 2, 1, 0.0, 0.5)
        >>> ctrl.plan([0.0, 0.0], [], 1.0)[1]   # 1 - 0.5^j (1 - 0)
        array([0.5 , 0.75])

        """
        y = _history(y_past, self._a.size, 'y_past')
        du = _history(du_past, self._b.size - 1, 'du_past')
        wv = np.asarray(w, dtype=np.float64)
        if wv.ndim == 0:
            wv = np.full(self._n2, float(wv))
        if wv.shape != (self._n2,) or not np.all(np.isfinite(wv)):
            raise ValueError(f'w must be finite, a scalar or of shape ({self._n2},), got {w!r}')
        rows = slice(self._n1 - 1, self._n2)
        f = (self._F @ y + self._H @ du)[rows]
        target = (wv - self._decay * (wv - y[0]))[rows]
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
