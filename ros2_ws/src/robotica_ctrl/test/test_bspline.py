"""
Tests of robotica_ctrl.trajectory.bspline: B-splines and Bézier curves (book §10.3.2).

References from the seed catalogue Part 8.4: the clamped uniform knots (10.73)-(10.75) written
with the book's indices, the Cox–de Boor recursion (10.70)-(10.72) with the corrected second
denominator λ_{i+k} − λ_{i+1} (Part 17), derivatives by differenced control points
(10.77)-(10.79), and Bernstein weights with binomial coefficients; all evaluated here, plus a
linear program for convex-hull membership.
"""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest
from robotica_ctrl.trajectory.bspline import bezier, bspline, bspline_knots
from scipy.optimize import linprog


def book_knots(N, k):
    """Return (10.73)-(10.75) for vertices V_0 .. V_N: N + k + 1 knots."""
    knots = []
    for i in range(N + k + 1):
        if i < k:
            knots.append(0.0)
        elif i <= N:
            knots.append(float(i - k + 1))
        else:
            knots.append(float(N - k + 2))
    return np.array(knots)


def cox_de_boor(i, k, lam, knots):
    """Return B_{i,k}(lam) by (10.70)-(10.72), 0/0 = 0, the last interval closed on the right."""
    if k == 1:
        if knots[i] <= lam < knots[i + 1]:
            return 1.0
        if lam == knots[-1] and knots[i] < knots[i + 1] == knots[-1]:
            return 1.0
        return 0.0
    left = right = 0.0
    if knots[i + k - 1] != knots[i]:
        left = (lam - knots[i]) / (knots[i + k - 1] - knots[i]) * cox_de_boor(
            i, k - 1, lam, knots)
    if knots[i + k] != knots[i + 1]:
        right = (knots[i + k] - lam) / (knots[i + k] - knots[i + 1]) * cox_de_boor(
            i + 1, k - 1, lam, knots)
    return left + right


def reference_curve(V, k, knots, lam):
    """Return sum_i V_i B_{i,k}(lam) (10.69) for each lam."""
    V = np.asarray(V, float)
    return np.array([sum(V[i] * cox_de_boor(i, k, x, knots) for i in range(len(V)))
                     for x in lam])


def differenced(V, k, knots):
    """Return the control points and knots of the derivative curve (10.77)-(10.79)."""
    V = np.asarray(V, float)
    Q = np.array([(k - 1) * (V[i + 1] - V[i]) / (knots[i + k] - knots[i + 1])
                  for i in range(len(V) - 1)])
    return Q, knots[1:-1]


def in_convex_hull(point, vertices):
    """Return whether point = sum w_i V_i with w >= 0, sum w = 1 (a feasibility LP)."""
    V = np.atleast_2d(np.asarray(vertices, float).T).T
    A_eq = np.vstack([V.T, np.ones(len(V))])
    b_eq = np.append(np.atleast_1d(point), 1.0)
    res = linprog(np.zeros(len(V)), A_eq=A_eq, b_eq=b_eq, bounds=(0, None), method='highs')
    return res.status == 0


def bernstein_reference(V, s, deriv=0):
    """Return the Bézier curve (or its derivative by the hodograph) at s with math.comb."""
    V = np.asarray(V, float)
    for _ in range(deriv):
        V = (len(V) - 1) * np.diff(V, axis=0)
    n = len(V) - 1
    if n < 0:
        return np.zeros_like(np.asarray(s, float))
    return np.array([sum(math.comb(n, i) * x**i * (1 - x)**(n - i) * V[i] for i in range(n + 1))
                     for x in s])


@pytest.mark.parametrize('n_points, order', [(2, 2), (5, 2), (4, 4), (6, 4), (9, 4), (7, 3),
                                             (8, 5)])
def test_knots_are_book_10_73_to_10_75(n_points, order):
    knots = bspline_knots(n_points, order)
    np.testing.assert_array_equal(knots, book_knots(n_points - 1, order))
    # λ_max = N - k + 2 with N = n_points - 1; each end has multiplicity k.
    assert knots[-1] == n_points - order + 1
    assert np.count_nonzero(knots == 0.0) == order
    assert np.count_nonzero(knots == knots[-1]) == order


def test_order_2_is_the_control_polygon():
    V = [[0.0, 0.0], [2.0, 1.0], [3.0, -1.0]]
    knots, lam, p, dp, ddp = bspline(V, order=2, samples=5)
    np.testing.assert_allclose(lam, [0, 0.5, 1, 1.5, 2])
    np.testing.assert_allclose(p, [[0, 0], [1, 0.5], [2, 1], [2.5, 0], [3, -1]], atol=1e-12)
    np.testing.assert_allclose(dp[0], [2, 1])
    np.testing.assert_allclose(ddp, 0.0)


def test_cubic_by_hand():
    # Five vertices 0, 0, 6, 0, 0 (1-D), k = 4: knots 0 0 0 0 1 2 2 2 2. At λ = 1 only
    # B_{1,4}, B_{2,4}, B_{3,4} are non-zero: by Cox-de Boor 1/4, 1/2, 1/4 -> p(1) = 3.
    knots, lam, p, dp, ddp = bspline([0, 0, 6, 0, 0], order=4, samples=[1.0])
    np.testing.assert_array_equal(knots, [0, 0, 0, 0, 1, 2, 2, 2, 2])
    assert p[0] == pytest.approx(3.0)
    assert dp[0] == pytest.approx(0.0, abs=1e-12)


vertex = st.tuples(st.floats(-5, 5), st.floats(-5, 5))


@settings(max_examples=30, deadline=None)
@given(st.integers(2, 5), st.lists(vertex, min_size=5, max_size=8), st.data())
def test_matches_cox_de_boor(order, polygon, data):
    V = np.array(polygon)
    knots, lam, p, dp, ddp = bspline(V, order, samples=17)
    ref_knots = book_knots(len(V) - 1, order)
    np.testing.assert_allclose(lam, np.linspace(0, ref_knots[-1], 17))
    np.testing.assert_allclose(p, reference_curve(V, order, ref_knots, lam), atol=1e-9)
    Q, q_knots = differenced(V, order, ref_knots)
    np.testing.assert_allclose(dp, reference_curve(Q, order - 1, q_knots, lam), atol=1e-8)
    if order >= 3:
        R, r_knots = differenced(Q, order - 1, q_knots)
        np.testing.assert_allclose(ddp, reference_curve(R, order - 2, r_knots, lam), atol=1e-7)
    else:
        np.testing.assert_allclose(ddp, 0.0)
    # Ends: interpolates V_0 and V_last, tangents (k-1)(V_1 - V_0) / (λ_k - λ_1).
    np.testing.assert_allclose(p[0], V[0], atol=1e-12)
    np.testing.assert_allclose(p[-1], V[-1], atol=1e-12)
    np.testing.assert_allclose(dp[0], (order - 1) * (V[1] - V[0]) / ref_knots[order], atol=1e-9)
    # Affine invariance (partition of unity): translating the polygon translates the curve.
    shift = np.array(data.draw(vertex))
    np.testing.assert_allclose(bspline(V + shift, order, samples=17)[2], p + shift, atol=1e-9)


@settings(max_examples=30, deadline=None)
@given(st.integers(2, 5), st.lists(st.floats(-5, 5), min_size=6, max_size=9))
def test_local_convex_hull(order, values):
    # For λ in [λ_j, λ_{j+1}) only V_{j-k+1} .. V_j weigh: p lies between their min and max.
    V = np.array(values)
    knots, lam, p, dp, ddp = bspline(V, order, samples=41)
    for x, y in zip(lam, p):
        j = min(int(np.searchsorted(knots, x, side='right')) - 1, len(V) - 1)
        local = V[j - order + 1:j + 1]
        assert local.min() - 1e-9 <= y <= local.max() + 1e-9


def test_global_convex_hull_and_local_control():
    V = np.array([[0.0, 0.0], [1.0, 3.0], [3.0, 3.5], [4.0, 0.5], [6.0, 1.0], [7.0, 4.0]])
    knots, lam, p, dp, ddp = bspline(V, 4, samples=25)
    assert all(in_convex_hull(x, V) for x in p)
    # Moving V_1 changes the curve only for λ < λ_{1+k} = 2.
    W = V.copy()
    W[1] += [0.5, -1.0]
    changed = np.any(np.abs(bspline(W, 4, samples=25)[2] - p) > 1e-12, axis=1)
    assert changed.any()
    assert not changed[lam >= 2.0].any()


def test_cubic_is_c2_at_interior_knots():
    V = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [4.0, 3.0], [5.0, 0.0], [6.0, 1.0]])
    eps = 1e-7
    for knot in (1.0, 2.0):
        _, _, p, dp, ddp = bspline(V, 4, samples=[knot - eps, knot + eps])
        np.testing.assert_allclose(p[0], p[1], atol=1e-5)
        np.testing.assert_allclose(dp[0], dp[1], atol=1e-5)
        np.testing.assert_allclose(ddp[0], ddp[1], atol=1e-5)
    # Order 3 (quadratic) is only C1: its second derivative jumps at an interior knot.
    _, _, p, dp, ddp = bspline(V, 3, samples=[2.0 - eps, 2.0 + eps])
    np.testing.assert_allclose(dp[0], dp[1], atol=1e-5)
    assert np.abs(ddp[0] - ddp[1]).max() > 1.0


@pytest.mark.parametrize('args, kwargs, match', [
    (([0, 1, 2],), {'order': 1}, 'order'),
    (([0, 1, 2],), {'order': 2.5}, 'order'),
    (([0, 1, 2],), {'order': True}, 'order'),
    (([0, 1, 2],), {'order': 4}, 'at least 4 control points'),
    (([0, np.nan, 2, 3],), {}, 'finite'),
    ((np.zeros((4, 2, 2)),), {}, 'shape'),
    (([0, 1, 2, 3],), {'samples': 1}, 'samples'),
    (([0, 1, 2, 3],), {'samples': 2.5}, 'samples'),
    (([0, 1, 2, 3],), {'samples': [0.0, 1.5]}, r'\[0, 1\]'),
    (([0, 1, 2, 3],), {'samples': [np.nan]}, 'finite'),
])
def test_bspline_bad_input_raises(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        bspline(*args, **kwargs)


def test_bspline_knots_bad_input_raises():
    with pytest.raises(ValueError, match='order'):
        bspline_knots(5, 1)
    with pytest.raises(ValueError, match='at least 4'):
        bspline_knots(3, 4)


def test_bezier_by_hand():
    # Cubic: p(1/2) = (V0 + 3 V1 + 3 V2 + V3) / 8; p'(0) = 3 (V1 - V0).
    V = [[0, 0], [1, 2], [3, 2], [4, 0]]
    p, dp, ddp = bezier(V, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(p, [[0, 0], [2, 1.5], [4, 0]], atol=1e-12)
    np.testing.assert_allclose(dp[[0, 2]], [[3, 6], [3, -6]], atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.lists(vertex, min_size=2, max_size=7))
def test_bezier_properties(polygon):
    V = np.array(polygon)
    N = len(V)
    s = np.linspace(0.0, 1.0, 11)
    p, dp, ddp = bezier(V, s)
    np.testing.assert_allclose(p, bernstein_reference(V, s), atol=1e-9)
    np.testing.assert_allclose(dp, bernstein_reference(V, s, 1), atol=1e-8)
    np.testing.assert_allclose(ddp, bernstein_reference(V, s, 2) if N >= 3 else 0.0,
                               atol=1e-7)
    np.testing.assert_allclose(p[0], V[0], atol=1e-12)
    np.testing.assert_allclose(p[-1], V[-1], atol=1e-12)
    np.testing.assert_allclose(dp[0], (N - 1) * (V[1] - V[0]), atol=1e-9)
    np.testing.assert_allclose(dp[-1], (N - 1) * (V[-1] - V[-2]), atol=1e-9)
    assert all(in_convex_hull(x, V) for x in p[::2])
    # The B-spline whose order is the number of vertices (knots 0^N 1^N) is the Bézier curve.
    knots, lam, bp, bdp, bddp = bspline(V, order=N, samples=s)
    np.testing.assert_array_equal(knots, [0.0] * N + [1.0] * N)
    np.testing.assert_allclose(bp, p, atol=1e-9)
    np.testing.assert_allclose(bdp, dp, atol=1e-8)
    np.testing.assert_allclose(bddp, ddp, atol=1e-7)


def test_bezier_one_dimensional_and_scalar_s():
    p, dp, ddp = bezier([1.0, 3.0, 2.0], 0.5)
    # (1 + 2 * 3 + 2) / 4 = 2.25; p' = 2 [(1 - s)(3 - 1) + s (2 - 3)] = 1 at s = 1/2.
    np.testing.assert_allclose(p, [2.25])
    np.testing.assert_allclose(dp, [1.0])
    np.testing.assert_allclose(ddp, [2 * (2 - 6 + 1)])


@pytest.mark.parametrize('args, match', [
    (([[0, 0]], [0.5]), 'at least 2'),
    (([0, np.nan], [0.5]), 'finite'),
    (([0, 1], [np.nan]), 'finite'),
    (([0, 1], [1.5]), r'\[0, 1\]'),
    (([0, 1], [-0.1]), r'\[0, 1\]'),
    (([0, 1], [[0.1, 0.2]]), '1-D'),
    ((np.zeros((3, 2, 2)), [0.5]), 'shape'),
])
def test_bezier_bad_input_raises(args, match):
    with pytest.raises(ValueError, match=match):
        bezier(*args)
