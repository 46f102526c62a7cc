"""
Tests of robotica_ctrl.mobile.gpc: generalised predictive control and the GPC path tracker.

References are independent of the code under test: the Diophantine identity is checked by
polynomial multiplication; step and free responses by running the difference equation of the
CARIMA model (9.118) (``scipy.signal.lfilter`` or a loop written here); the control law
against ``numpy.linalg.lstsq`` on the stacked least-squares form of the cost (9.121); the
sampled lateral model against ``scipy.signal.cont2discrete`` and the closed-form continuous
step response. Closed-loop tests drive a bicycle x' = v cos θ, y' = v sin θ, θ' = v γ with
the steering lag γ' = (u - γ)/τ (book (9.113); γ = u when τ = 0), written here and integrated
with ``rk4_step``. The numbers of the NavLab experiment of §9.5 (seed catalogue §7.8: τ = 0.4 s,
v = 3.4 m/s, 18 points, NU = 1, N = 10 vs 25) are used where they apply; the book gives no
worked GPC example with numbers (catalogue §7.10), and the sampling period (0.1 s) is ours.
"""

import dataclasses
import math

import numpy as np
import pytest
from robotica_ctrl.mobile.gpc import (diophantine, GpcController, GpcPathTracker,
                                      GpcTrackerCommand, GpcTrackerParams, lateral_carima_model,
                                      prediction_polynomials, soften_reference,
                                      step_response_matrix)
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import straight_line
from robotica_kin.integrators import rk4_step
from scipy.signal import cont2discrete, lfilter, ss2tf


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


# --- Sampled lateral model (9.109)-(9.113) ----------------------------------------------

def test_lateral_model_without_lag_is_the_sampled_double_integrator():
    # e'' = v² u with ZOH: (v T)²/2 (1 + q^-1) q^-1 / (1 - q^-1)² (worked by hand).
    a, b = lateral_carima_model(2.0, 0.05)
    np.testing.assert_allclose(a, [1.0, -2.0, 1.0])
    np.testing.assert_allclose(b, [0.005, 0.005], rtol=1e-14)


@pytest.mark.parametrize(('v', 't', 'tau'), [(1.0, 0.1, 0.5), (3.4, 0.1, 0.4),
                                             (0.5, 0.02, 2.0)])
def test_lateral_model_with_lag_matches_scipy_and_the_continuous_step(v, t, tau):
    a, b = lateral_carima_model(v, t, tau)
    A = np.array([[0.0, v, 0.0], [0.0, 0.0, v], [0.0, 0.0, -1.0 / tau]])
    B = np.array([[0.0], [0.0], [1.0 / tau]])
    C = np.array([[1.0, 0.0, 0.0]])
    Ad, Bd, Cd, Dd, _ = cont2discrete((A, B, C, np.zeros((1, 1))), t, method='zoh')
    num, den = ss2tf(Ad, Bd, Cd, Dd)
    np.testing.assert_allclose(a, den, rtol=1e-12)
    np.testing.assert_allclose(b, num[0, 1:], rtol=1e-7)  # ss2tf goes through eigenvalues
    p = math.exp(-t / tau)
    np.testing.assert_allclose(a, np.convolve([1.0, -2.0, 1.0], [1.0, -p]), rtol=1e-12)
    # Step response at the samples equals v² (t²/2 - τ t + τ² (1 - e^(-t/τ))).
    times = t * np.arange(1, 30)
    exact = v * v * (times ** 2 / 2 - tau * times + tau ** 2 * (1.0 - np.exp(-times / tau)))
    g = prediction_polynomials(a, b, 29)[0]
    np.testing.assert_allclose(g, exact, rtol=1e-8, atol=1e-14)


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
    for args in [(0.0, 0.1), (-1.0, 0.1), (math.nan, 0.1), (1.0, 0.0), (1.0, 0.1, -0.1),
                 (1.0, 0.1, math.inf)]:
        with pytest.raises(ValueError):
            lateral_carima_model(*args)


@pytest.mark.parametrize('change', [
    {'linear_velocity': 0.0}, {'linear_velocity': math.inf}, {'sample_time': -0.1},
    {'steering_time_constant': -0.1}, {'n1': 0}, {'n1': 5, 'n2': 4}, {'nu': 19},
    {'n2': 2.5}, {'control_weight': -1.0}, {'softening': 1.0}, {'max_curvature': 0.0},
    {'max_curvature': math.nan}, {'goal_tolerance': 0.0}, {'search_window': math.nan},
    {'model_speed_tolerance': -0.1},
])
def test_tracker_params_reject_bad_values(change):
    with pytest.raises(ValueError):
        GpcTrackerParams(**change)


def test_tracker_rejects_bad_poses_and_speeds():
    tracker = GpcPathTracker(PolylinePath([[0.0, 0.0], [10.0, 0.0]]), GpcTrackerParams())
    for pose in [[0.0, 0.0], [0.0, 0.0, math.nan], [0.0, 0.0, 0.0, 0.0]]:
        with pytest.raises(ValueError):
            tracker.update(pose)
    for speed in [0.0, -1.0, math.nan]:
        with pytest.raises(ValueError):
            tracker.update([0.0, 0.0, 0.0], speed=speed)
    with pytest.raises(ValueError):  # λ = 0 with NU > rows: singular
        tracker.set_params(GpcTrackerParams(n1=18, nu=2, control_weight=0.0))
    assert tracker.params == GpcTrackerParams()  # the old params are kept


# --- Path tracker -----------------------------------------------------------------------

def bicycle(_t, state, v, u, tau):
    """Bicycle with first-order steering (9.113): state (x, y, θ, γ)."""
    x, y, theta, gamma = state
    curvature = gamma if tau > 0.0 else u
    return [v * math.cos(theta), v * math.sin(theta), v * curvature,
            (u - gamma) / tau if tau > 0.0 else 0.0]


def drive(tracker, pose, duration, tau=0.0, substeps=10):
    """Close the loop for ``duration`` [s]: commands every T, the bicycle held in between."""
    params = tracker.params
    period = params.sample_time
    state = np.array([*pose, 0.0])
    rows, commands = [], []
    for k in range(round(duration / period)):
        command = tracker.update(state[:3])
        rows.append((k * period, *state))
        commands.append(command)
        if command.finished:
            break
        for i in range(substeps):
            state = rk4_step(bicycle, 0.0, state, period / substeps, command.linear,
                             command.curvature, tau)
    return np.array(rows), commands


@pytest.mark.parametrize(('v', 'tau', 'n2'), [(1.0, 0.0, 18), (3.4, 0.4, 18), (3.4, 0.4, 10)])
def test_converges_to_a_straight_line_from_a_1_m_offset(v, tau, n2):
    path = PolylinePath(straight_line([0.0, 0.0], [150.0, 0.0], spacing=1.0))
    params = GpcTrackerParams(linear_velocity=v, steering_time_constant=tau, n2=n2)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 1.0, 0.0], 20.0, tau)
    error = rows[:, 2]   # lateral error: the path is the x axis
    cross_track = np.array([c.cross_track for c in commands])
    np.testing.assert_allclose(cross_track, error, atol=1e-12)
    assert commands[0].curvature < 0.0              # turns right, towards the path
    assert error.min() > -0.1                       # overshoot below 10 % of the offset
    late = rows[:, 0] > 15.0
    assert np.abs(error[late]).max() < 1e-3
    assert np.abs(rows[late, 3]).max() < 1e-3       # heading along the path
    assert np.abs([c.curvature for c in commands[-20:]]).max() < 1e-3
    for c in commands:
        assert c.angular == pytest.approx(c.linear * c.curvature, rel=1e-12)


def arc_path(radius, start_straight, sweep, spacing=0.05):
    """Straight of ``start_straight`` [m] (may be 0) along +x from the origin, then a left arc."""
    straight = np.arange(0.0, start_straight, spacing)
    points = [np.column_stack((straight, np.zeros_like(straight)))]
    angles = np.linspace(-math.pi / 2, -math.pi / 2 + sweep, math.ceil(radius * sweep / spacing))
    points.append(np.column_stack((start_straight + radius * np.cos(angles),
                                   radius + radius * np.sin(angles))))
    return PolylinePath(np.vstack(points))


@pytest.mark.parametrize('tau', [0.0, 0.4])
def test_steering_settles_on_the_path_curvature_on_an_arc(tau):
    # Book §9.5 (NavLab, fig. 9.30): the steering command stays close to the path
    # curvature. On a circle of radius 5 m the lateral model is exact in the unrolled frame,
    # so γ → 1/R with no steady-state error (up to the polyline's chords).
    radius = 5.0
    path = arc_path(radius, 0.0, 4.0 * math.pi, spacing=0.03)
    params = GpcTrackerParams(linear_velocity=3.4, steering_time_constant=tau)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 0.5, 0.0], 15.0, tau)
    late = rows[:, 0] > 10.0
    curvature = np.array([c.curvature for c in commands])[late]
    cross_track = np.array([c.cross_track for c in commands])[late]
    np.testing.assert_allclose(curvature, 1.0 / radius, rtol=0.01)
    assert np.abs(cross_track).max() < 5e-3
    # Independently of the tracker's own errors: distance of the robot to the circle.
    distance = np.hypot(rows[late, 1], rows[late, 2] - radius) - radius
    assert np.abs(distance).max() < 5e-3


def test_reference_on_an_arc_is_the_unrolled_circle():
    # On the circle, heading along it: Y(σ) = ∫ σ'/R dσ' = σ² / (2 R) at σ = v T j.
    radius = 4.0
    # The polyline's first chord is turned by half its angle, spacing / (2 R), from the
    # circle's tangent: an error up to σ spacing / (2 R) < 3e-4 m here.
    path = arc_path(radius, 0.0, math.pi, spacing=0.001)
    params = GpcTrackerParams(linear_velocity=2.0, n2=10)
    command = GpcPathTracker(path, params).update([0.0, 0.0, 0.0])
    sigma = 2.0 * 0.1 * np.arange(1, 11)
    np.testing.assert_allclose(command.reference, sigma ** 2 / (2.0 * radius), atol=3e-4)
    assert command.reference.shape == command.prediction.shape == (10,)


def test_navlab_horizon_effect():
    # Book §9.5, fig. 9.31 (NavLab: τ = 0.4 s, v = 3.4 m/s, NU = 1): a longer horizon
    # anticipates a curve (turns earlier, cuts the corner), a shorter one reacts late.
    # Straight of 20 m, then a left arc of radius 5 m (near the vehicle's limit).
    path = arc_path(5.0, 20.0, math.pi, spacing=0.1)
    starts, cuts = [], []
    for n2 in [10, 18, 25]:
        params = GpcTrackerParams(linear_velocity=3.4, steering_time_constant=0.4, n2=n2)
        rows, commands = drive(GpcPathTracker(path, params), [0.0, 0.0, 0.0], 9.0, 0.4)
        s = np.array([c.projection.s for c in commands])
        curvature = np.array([c.curvature for c in commands])
        starts.append(s[np.argmax(curvature > 0.02)])  # 10 % of the arc's curvature
        cuts.append(max(c.cross_track for c in commands))  # > 0: inside the left turn
    assert starts[0] > starts[1] > starts[2]
    assert starts[0] < 20.0                                # even N = 10 previews the arc
    assert 20.0 - starts[2] > 2.0 * (20.0 - starts[0])     # N = 25 turns much earlier
    assert cuts[0] < cuts[1] < cuts[2]


def test_model_is_rebuilt_when_the_speed_changes():
    path = PolylinePath([[0.0, 0.0], [50.0, 0.0]])
    tracker = GpcPathTracker(path, GpcTrackerParams(steering_time_constant=0.4))
    first = tracker.controller
    tracker.update([0.0, 0.2, 0.0])
    assert tracker.controller is first
    tracker.update([0.1, 0.2, 0.0], speed=2.0)
    assert tracker.controller is not first
    np.testing.assert_allclose(tracker.controller.b, lateral_carima_model(2.0, 0.1, 0.4)[1])
    # With a tolerance, small speed changes keep the model.
    tracker.set_params(GpcTrackerParams(steering_time_constant=0.4,
                                        model_speed_tolerance=0.05))
    kept = tracker.controller
    tracker.update([0.2, 0.2, 0.0], speed=1.04)
    assert tracker.controller is kept
    tracker.update([0.3, 0.2, 0.0], speed=1.1)
    assert tracker.controller is not kept


def test_softening_and_curvature_limit_in_the_tracker():
    path = PolylinePath(straight_line([0.0, 0.0], [60.0, 0.0], spacing=1.0))
    first = [GpcPathTracker(path, GpcTrackerParams(softening=alpha)).update(
        [0.0, 1.0, 0.0]).curvature for alpha in [0.0, 0.5, 0.9]]
    assert first[0] < first[1] < first[2] < 0.0
    params = GpcTrackerParams(max_curvature=0.2)
    rows, commands = drive(GpcPathTracker(path, params), [0.0, 1.0, 0.0], 30.0)
    curvature = np.array([c.curvature for c in commands])
    assert np.abs(curvature).max() == pytest.approx(0.2)  # the limit is reached, not passed
    assert abs(rows[-1, 2]) < 1e-3                         # and the path is still reached


def test_finishes_at_the_end_and_stays_finished_until_reset():
    path = PolylinePath([[0.0, 0.0], [3.0, 0.0]])
    tracker = GpcPathTracker(path, GpcTrackerParams())
    rows, commands = drive(tracker, [0.0, 0.0, 0.0], 10.0)
    assert commands[-1].finished and not commands[0].finished
    assert (commands[-1].linear, commands[-1].angular, commands[-1].curvature) == (0, 0, 0)
    assert rows[-1, 1] == pytest.approx(3.0, abs=0.1)
    assert tracker.update([1.0, 0.3, 0.0]).finished
    tracker.reset()
    assert tracker.progress == 0.0
    assert not tracker.update([0.0, 0.0, 0.0]).finished


def test_command_is_immutable_and_defaults_follow_navlab():
    params = GpcTrackerParams()
    assert (params.n1, params.n2, params.nu) == (1, 18, 1)
    assert dataclasses.replace(params, n2=25).n2 == 25
    command = GpcPathTracker(PolylinePath([[0.0, 0.0], [5.0, 0.0]]), params).update(
        [0.0, 0.0, 0.0])
    assert isinstance(command, GpcTrackerCommand)
    with pytest.raises(ValueError):
        command.reference[0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        command.linear = 2.0  # type: ignore[misc]
