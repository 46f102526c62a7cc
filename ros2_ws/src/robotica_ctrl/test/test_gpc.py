"""
Tests of robotica_ctrl.mobile.gpc: generalised predictive control (book §9.5).

References are independent of the code under test: the Diophantine identity is checked by
polynomial multiplication; step and free responses by running the difference equation of the
CARIMA model (9.118) (``scipy.signal.lfilter`` or a loop written here); the control law
against ``numpy.linalg.lstsq`` on the stacked least-squares form of the cost (9.121). The GPC
path tracker is tested in test_gpc_tracker.py.
"""

import math

import numpy as np
import pytest
from robotica_ctrl.mobile.gpc import (check_horizons, diophantine, GpcController,
                                      prediction_polynomials, soften_reference,
                                      step_response_matrix)
from scipy.signal import lfilter


def random_model(rng, na, nb):
    """Return a random stable-ish A (monic, na) and B (nb + 1 coefficients)."""
    poles = rng.uniform(-0.9, 0.9, na)
    a = np.poly(poles)
    b = rng.normal(size=nb + 1)
    return a, b


def simulate_carima(a, b, y_hist, du_hist, du_future):
    """
    Run Δ A y(t) = B Δu(t-1) forward from the histories (newest first); return y(k+1 …).

    ``du_future`` holds Δu(k), Δu(k+1), …; one output per element is returned.
    """
    at = np.convolve(a, [1.0, -1.0])
    y = list(reversed(list(y_hist)))           # oldest first, y[-1] = y(k)
    du = list(reversed(list(du_hist)))         # oldest first, du[-1] = Δu(k-1)
    out = []
    for d in du_future:
        du.append(d)                           # du[-1] = Δu(t) for y(t+1)
        value = sum(b[i] * du[-1 - i] for i in range(len(b)) if len(du) - 1 - i >= 0)
        value -= sum(at[i] * y[-i] for i in range(1, len(at)) if len(y) - i >= 0)
        y.append(value)
        out.append(value)
    return np.array(out)


# --- Diophantine identity (9.132) ---------------------------------------------------------

@pytest.mark.parametrize('seed', range(6))
@pytest.mark.parametrize('na', [0, 1, 2, 3])
def test_diophantine_identity_random_models(seed, na):
    rng = np.random.default_rng(seed)
    a = np.concatenate(([1.0], rng.normal(size=na)))
    a_tilde = np.convolve(a, [1.0, -1.0])
    n2 = 12
    E, F = diophantine(a_tilde, n2)
    assert len(E) == len(F) == n2
    for j in range(1, n2 + 1):
        assert E[j - 1].shape == (j,)            # deg E_j = j - 1
        assert F[j - 1].shape == (na + 1,)       # deg F_j = na
        lhs = np.convolve(E[j - 1], a_tilde)
        shifted = np.concatenate((np.zeros(j), F[j - 1]))
        total = np.zeros(max(lhs.size, shifted.size))
        total[:lhs.size] += lhs
        total[:shifted.size] += shifted
        expected = np.zeros_like(total)
        expected[0] = 1.0
        np.testing.assert_allclose(total, expected, atol=1e-9 * max(1.0, np.abs(lhs).max()))


def test_diophantine_hand_example():
    # A = 1 - 0.8 q^-1, Ã = 1 - 1.8 q^-1 + 0.8 q^-2 (worked by hand): E_j are the partial
    # sums of 1/Ã = 1 + 1.8 q^-1 + 2.44 q^-2 + …, F_1 = [1.8, -0.8], F_2 = [2.44, -1.44],
    # F_3 = [2.952, -1.952].
    E, F = diophantine([1.0, -1.8, 0.8], 3)
    for got, want in zip(E, [[1.0], [1.0, 1.8], [1.0, 1.8, 2.44]]):
        np.testing.assert_allclose(got, want, rtol=1e-14)
    for got, want in zip(F, [[1.8, -0.8], [2.44, -1.44], [2.952, -1.952]]):
        np.testing.assert_allclose(got, want, rtol=1e-14)


# --- Step response and prediction (9.124)-(9.131) ---------------------------------------

@pytest.mark.parametrize('seed', range(4))
def test_step_response_matches_simulation(seed):
    rng = np.random.default_rng(100 + seed)
    a, b = random_model(rng, na=int(rng.integers(1, 4)), nb=int(rng.integers(0, 3)))
    n2 = 15
    g, F, H = prediction_polynomials(a, b, n2)
    # Unit step in u from k = 0, model at rest: y(j) = g_(j-1) (u(k-1) enters with B).
    y = lfilter(np.concatenate(([0.0], b)), a, np.ones(n2 + 1))
    np.testing.assert_allclose(g, y[1:], rtol=1e-10, atol=1e-12)
    assert F.shape == (n2, a.size) and H.shape == (n2, b.size - 1)
    # G1 (9.130): rows N1 … N2, NU columns, Toeplitz of the step response.
    G = step_response_matrix(a, b, 3, n2, 4)
    assert G.shape == (n2 - 2, 4)
    for r, j in enumerate(range(3, n2 + 1)):
        for c in range(4):
            assert G[r, c] == pytest.approx(y[j - c] if j - c >= 1 else 0.0, abs=1e-12)


@pytest.mark.parametrize('seed', range(4))
def test_free_response_and_prediction_match_simulation(seed):
    rng = np.random.default_rng(200 + seed)
    na, nb = int(rng.integers(1, 4)), int(rng.integers(0, 3))
    a, b = random_model(rng, na, nb)
    ctrl = GpcController(a, b, 1, 10, 3, 0.5)
    y_hist = rng.normal(size=na + 1)
    du_hist = rng.normal(size=nb)
    free = ctrl.free_response(y_hist, du_hist)
    np.testing.assert_allclose(free, simulate_carima(a, b, y_hist, du_hist, np.zeros(10)),
                               rtol=1e-9, atol=1e-9)
    # ŷ = G Δu + f (9.125) with Δu = 0 beyond NU (9.128).
    du_plan = ctrl.increments(y_hist, du_hist, rng.normal(size=10))
    future = np.concatenate((du_plan, np.zeros(7)))
    np.testing.assert_allclose(ctrl.prediction, simulate_carima(a, b, y_hist, du_hist, future),
                               rtol=1e-9, atol=1e-9)


# --- The control law (9.127)-(9.130) -----------------------------------------------------

def test_n2_nu_1_hand_computation():
    # y(k) = 0.5 y(k-1) + 2 u(k-1): g0 = 2, F_1 = [1.5, -0.5] (Ã = 1 - 1.5 q^-1 + 0.5 q^-2).
    # y(k) = 1, y(k-1) = 0.5: f1 = 1.5 - 0.25 = 1.25; w = 2, λ = 1:
    # Δu = g0 (w - f1) / (g0² + λ) = 2 · 0.75 / 5 = 0.3.
    ctrl = GpcController([1.0, -0.5], [2.0], 1, 1, 1, 1.0)
    np.testing.assert_allclose(ctrl.free_response([1.0, 0.5], []), [1.25])
    assert ctrl.increments([1.0, 0.5], [], 2.0)[0] == pytest.approx(0.3, rel=1e-14)
    np.testing.assert_allclose(ctrl.gain, [[0.4]])
    np.testing.assert_allclose(ctrl.prediction, [1.25 + 2.0 * 0.3])


def test_nu_1_is_a_scalar_law():
    # NU = 1 (book, after (9.130)): Δu = Σ g_(j-1) (w_j - f_j) / (Σ g_(j-1)² + λ), j = N1 … N2.
    rng = np.random.default_rng(7)
    a, b = random_model(rng, 2, 1)
    n1, n2, lam = 2, 9, 0.7
    ctrl = GpcController(a, b, n1, n2, 1, lam)
    y_hist, du_hist, w = rng.normal(size=3), rng.normal(size=1), rng.normal(size=n2)
    g = lfilter(np.concatenate(([0.0], b)), a, np.ones(n2 + 1))[1:]
    f = simulate_carima(a, b, y_hist, du_hist, np.zeros(n2))
    rows = slice(n1 - 1, n2)
    expected = g[rows] @ (w[rows] - f[rows]) / (g[rows] @ g[rows] + lam)
    assert ctrl.increments(y_hist, du_hist, w)[0] == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize(('n1', 'n2', 'nu', 'lam'), [(1, 10, 10, 0.1), (2, 12, 3, 0.3),
                                                     (1, 6, 2, 0.0), (3, 3, 1, 2.0)])
def test_law_minimises_the_cost(n1, n2, nu, lam):
    # Δu minimises |G1 Δu - (w - f)|² + λ |Δu|² (9.121), solved here as a stacked lstsq.
    rng = np.random.default_rng(n1 * 100 + n2)
    a, b = random_model(rng, 2, 2)
    ctrl = GpcController(a, b, n1, n2, nu, lam)
    y_hist, du_hist, w = rng.normal(size=3), rng.normal(size=2), rng.normal(size=n2)
    g = lfilter(np.concatenate(([0.0], b)), a, np.ones(n2 + 1))[1:]
    G = np.array([[g[j - 1 - c] if j - 1 - c >= 0 else 0.0 for c in range(nu)]
                  for j in range(n1, n2 + 1)])
    f = simulate_carima(a, b, y_hist, du_hist, np.zeros(n2))[n1 - 1:]
    stacked = np.vstack((G, math.sqrt(lam) * np.eye(nu)))
    rhs = np.concatenate((w[n1 - 1:] - f, np.zeros(nu)))
    expected = np.linalg.lstsq(stacked, rhs, rcond=None)[0]
    np.testing.assert_allclose(ctrl.increments(y_hist, du_hist, w), expected, rtol=1e-8,
                               atol=1e-10)
    np.testing.assert_allclose(ctrl.G, G, rtol=1e-10, atol=1e-14)


def test_larger_lambda_gives_smaller_increments():
    rng = np.random.default_rng(3)
    a, b = random_model(rng, 2, 1)
    y_hist, du_hist = np.zeros(3), np.zeros(1)
    steps = []
    for lam in [0.0, 0.01, 0.1, 1.0, 10.0, 100.0, 1e4]:
        ctrl = GpcController(a, b, 1, 10, 3, lam)
        steps.append(abs(ctrl.increments(y_hist, du_hist, 1.0)[0]))
    assert all(x > y for x, y in zip(steps, steps[1:]))
    # λ → ∞: Δu → G1ᵀ (w - f) / λ, f = 0 here.
    g = lfilter(np.concatenate(([0.0], b)), a, np.ones(11))[1:]
    ctrl = GpcController(a, b, 1, 10, 1, 1e8)
    assert ctrl.increments(y_hist, du_hist, 1.0)[0] * 1e8 == pytest.approx(g.sum(), rel=1e-6)


def test_dead_beat_with_minimal_horizons():
    # N1 = N2 = NU = 1, λ = 0 on y(k+1) = 0.9 y(k) + 0.2 u(k): y reaches w in one step.
    ctrl = GpcController([1.0, -0.9], [0.2], 1, 1, 1, 0.0)
    y = 0.0
    for w in [1.0, 1.0, -0.5, -0.5, 2.0]:
        u = ctrl.update(y, w)
        y = 0.9 * y + 0.2 * u
        assert y == pytest.approx(w, abs=1e-12)


def plant_loop(ctrl, steps, w, gain=0.2, pole=0.9, disturbance_at=None, disturbance=0.0):
    """Run y(k+1) = pole y(k) + gain u(k) (+ a load step) under ``ctrl``; return y and u."""
    y, ys, us = 0.0, [], []
    for k in range(steps):
        u = ctrl.update(y, w)
        ys.append(y)
        us.append(u)
        d = disturbance if disturbance_at is not None and k >= disturbance_at else 0.0
        y = pole * y + gain * u + d
    return np.array(ys), np.array(us)


@pytest.mark.parametrize(('model_gain', 'alpha'), [(0.2, 0.0), (0.12, 0.0), (0.3, 0.6)])
def test_closed_loop_first_order_plant_has_no_steady_state_error(model_gain, alpha):
    # Integral action of Δ: a step reference is reached exactly, also with a wrong model
    # gain and a constant load disturbance entering at k = 100.
    ctrl = GpcController([1.0, -0.9], [model_gain], 1, 10, 1, 0.1, alpha)
    ys, us = plant_loop(ctrl, 250, 1.0, disturbance_at=100, disturbance=0.05)
    assert ys[90:100] == pytest.approx(np.ones(10), abs=1e-7)
    assert ys[-10:] == pytest.approx(np.ones(10), abs=1e-9)
    # The control absorbs the load: at steady state 0.1 y = 0.2 u + 0.05 with y = 1.
    assert us[-1] == pytest.approx((0.1 - 0.05) / 0.2, abs=1e-5)


def test_softening_slows_the_first_move():
    first = []
    for alpha in [0.0, 0.3, 0.6, 0.9]:
        ctrl = GpcController([1.0, -0.9], [0.2], 1, 10, 1, 0.1, alpha)
        first.append(ctrl.update(0.0, 1.0))
    assert all(x > y > 0.0 for x, y in zip(first, first[1:]))


def test_reset_restarts_from_rest():
    ctrl = GpcController([1.0, -0.9], [0.2], 1, 5, 2, 0.1)
    fresh = [ctrl.update(y, 1.0) for y in [0.0, 0.3, 0.5]]
    ctrl.reset()
    assert ctrl.u == 0.0
    assert [ctrl.update(y, 1.0) for y in [0.0, 0.3, 0.5]] == fresh
    ctrl.reset(u=2.0)
    assert ctrl.update(0.0, 0.0) == pytest.approx(2.0)  # at rest on target: Δu = 0


# --- Reference softening (9.140) --------------------------------------------------------

def test_soften_reference_hand_values_and_first_order_filter():
    np.testing.assert_allclose(soften_reference([1.0, 1.0, 1.0], 0.0, 0.5),
                               [0.5, 0.75, 0.875])
    y_d = np.array([0.3, -1.0, 2.0])
    np.testing.assert_array_equal(soften_reference(y_d, 5.0, 0.0), y_d)
    # Constant y_d: Clarke's filter w(k+j) = α w(k+j-1) + (1 - α) y_d, w(k) = y(k).
    alpha, y, target = 0.7, -0.4, 1.3
    w, filtered = y, []
    for _ in range(8):
        w = alpha * w + (1.0 - alpha) * target
        filtered.append(w)
    np.testing.assert_allclose(soften_reference(np.full(8, target), y, alpha), filtered,
                               rtol=1e-14)
    # α = exp(-τ_e): large τ_e → y_d, small τ_e → y(k).
    np.testing.assert_allclose(soften_reference([2.0], 0.0, math.exp(-50.0)), [2.0])
    np.testing.assert_allclose(soften_reference([2.0], 0.0, math.exp(-1e-9)), [0.0],
                               atol=1e-8)


def test_plan_gives_the_increments_and_the_softened_reference():
    # Rows N1 … N2 = 2 … 4 of the reference softened by (9.140), written here.
    ctrl = GpcController([1.0, -0.9], [0.2, 0.1], 2, 4, 2, 0.1, 0.6)
    y_past, du_past, w = [0.4, 0.3], [0.05], [1.0, 1.2, 1.4, 1.6]
    increments, reference = ctrl.plan(y_past, du_past, w)
    np.testing.assert_array_equal(increments, ctrl.increments(y_past, du_past, w))
    expected = [w[j - 1] - 0.6 ** j * (w[j - 1] - 0.4) for j in (2, 3, 4)]
    np.testing.assert_allclose(reference, expected, rtol=1e-15)
    np.testing.assert_allclose(reference, soften_reference(w, 0.4, 0.6)[1:], rtol=1e-15)
    with pytest.raises(ValueError):
        ctrl.plan(y_past, du_past, [1.0, 2.0])


# --- Bad parameters ---------------------------------------------------------------------

GOOD = {'a': [1.0, -0.9], 'b': [0.2], 'n1': 1, 'n2': 5, 'nu': 2, 'lam': 0.1, 'alpha': 0.0}


@pytest.mark.parametrize('change', [
    {'a': [2.0, -0.9]}, {'a': [1.0, math.nan]}, {'a': []}, {'a': [[1.0, 0.5]]},
    {'b': [0.0, 0.0]}, {'b': [math.inf]}, {'n1': 0}, {'n2': 0}, {'n1': 4, 'n2': 3},
    {'nu': 0}, {'nu': 6}, {'nu': 1.5}, {'n2': True}, {'lam': -1.0}, {'lam': math.nan},
    {'alpha': 1.0}, {'alpha': -0.1}, {'alpha': math.nan},
    {'n1': 5, 'n2': 5, 'nu': 2, 'lam': 0.0},   # one row, two unknowns, no weight: singular
])
def test_controller_rejects_bad_parameters(change):
    with pytest.raises(ValueError):
        GpcController(**{**GOOD, **change})


@pytest.mark.parametrize(('horizons', 'valid'), [
    ((1, 18, 1), True), ((3, 3, 3), True), ((0, 5, 1), False), ((4, 3, 1), False),
    ((1, 5, 0), False), ((1, 5, 6), False), ((1.0, 5, 1), False), ((True, 5, 1), False),
])
def test_check_horizons(horizons, valid):
    if valid:
        assert check_horizons(*horizons) == horizons
    else:
        with pytest.raises(ValueError):
            check_horizons(*horizons)


def test_bad_inputs_are_rejected():
    with pytest.raises(ValueError):
        diophantine([1.0], 3)
    with pytest.raises(ValueError):
        diophantine([2.0, -1.0], 3)
    with pytest.raises(ValueError):
        diophantine([1.0, -1.0], 0)
    with pytest.raises(ValueError):
        soften_reference([1.0], 0.0, 1.5)
    with pytest.raises(ValueError):
        soften_reference([1.0], math.nan, 0.5)
    ctrl = GpcController(**GOOD)
    for y_hist, du_hist, w in [([0.0], [], 1.0), ([0.0, 0.0], [0.0], 1.0),
                               ([0.0, 0.0], [], [1.0, 2.0]), ([0.0, math.nan], [], 1.0),
                               ([0.0, 0.0], [], math.inf)]:
        with pytest.raises(ValueError):
            ctrl.increments(y_hist, du_hist, w)
    ctrl.update(0.0, 1.0)
    u = ctrl.u
    with pytest.raises(ValueError):
        ctrl.update(math.nan, 1.0)
    with pytest.raises(ValueError):
        ctrl.update(0.0, [1.0, 2.0])
    assert ctrl.u == u  # state unchanged
    with pytest.raises(ValueError):
        ctrl.reset(math.inf)
