"""
Tests of the cubic-spiral posture-to-posture connection (book §10.4, Kelly & Nagy 2003).

References computed here: the spirals that are a line, a circular arc or a clothoid in closed
form (the clothoid's end by scipy's Fresnel integrals); for general postures, a numerical
integration (solve_ivp) of x' = cos θ, y' = sin θ, θ' = κ(s) with κ the cubic spline through the
sampled curvatures (exact for a cubic profile), and the end postures themselves.
"""

import math

import numpy as np
import pytest
from robotica_ctrl.planning.cubic_spiral import cubic_spiral, spiral_coefficients
from robotica_ctrl.planning.plan_result import SearchBudget
from robotica_kin.world import make_world
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline
from scipy.special import fresnel

POSTURES = [
    ([0.0, 0.0, 0.0, 0.0], [4.0, 1.0, 0.0, 0.0]),          # lane change
    ([1.0, 2.0, 0.3, 0.1], [4.0, 5.0, 0.3 + math.pi / 2, 0.5]),
    ([0.0, 0.0, math.pi / 2, 0.0], [-3.0, 3.0, math.pi, -0.2]),
    ([2.0, -1.0, -2.8, 0.0], [-2.0, -3.0, 2.9, 0.0]),        # heading change across ±π
    ([0.0, 0.0, 0.0, 0.3], [10.0, 2.0, 0.0, -0.3]),
    ([0.0, 0.0, 0.0, 0.0], [1.0, 2.0, math.pi, 0.0]),        # a U-turn 2 m wide
]


def wrapped(angle):
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@pytest.mark.parametrize('start, goal', POSTURES)
def test_the_spiral_joins_the_postures(start, goal):
    result = cubic_spiral(start, goal, ds=0.01)
    assert result.found, result.reason
    samples = result.details['samples']
    assert samples[0] == pytest.approx(start, abs=1e-12)
    assert samples[-1, :2] == pytest.approx(goal[:2], abs=1e-8)
    assert wrapped(samples[-1, 2] - goal[2]) == pytest.approx(0.0, abs=1e-8)
    assert samples[-1, 3] == pytest.approx(goal[3], abs=1e-9)
    assert result.cost == pytest.approx(result.details['s'][-1])


@pytest.mark.parametrize('start, goal', POSTURES)
def test_the_samples_are_the_integral_of_their_cubic_curvature(start, goal):
    result = cubic_spiral(start, goal, ds=0.01)
    s, kappa, poses = result.details['s'], result.details['curvature'], result.path
    profile = CubicSpline(s, kappa)           # a cubic profile is its own cubic spline
    sol = solve_ivp(lambda u, q: [math.cos(q[2]), math.sin(q[2]), profile(u)], (0.0, s[-1]),
                    poses[0], t_eval=s, rtol=1e-12, atol=1e-13)
    assert np.abs(sol.y.T - poses).max() < 1e-8
    # κ is one cubic: continuous, its fourth differences vanish, the peak is its own
    assert np.abs(np.diff(kappa, 4)).max() < 1e-9
    assert result.details['max_curvature'] >= np.abs(kappa).max() - 1e-12
    assert result.details['max_curvature'] <= np.abs(kappa).max() + 1e-3


def test_a_line_an_arc_and_a_clothoid_are_found_as_such():
    line = cubic_spiral([0, 0, 0, 0], [5, 0, 0, 0])
    assert line.cost == pytest.approx(5.0) and np.abs(line.details['curvature']).max() < 1e-9
    radius, turn, theta0 = 2.0, 1.2, 0.3
    centre = np.array([1.0, 2.0]) + radius * np.array([-math.sin(theta0), math.cos(theta0)])
    end = centre + radius * np.array([math.sin(theta0 + turn), -math.cos(theta0 + turn)])
    arc = cubic_spiral([1.0, 2.0, theta0, 1 / radius], [*end, theta0 + turn, 1 / radius])
    assert arc.cost == pytest.approx(radius * turn, abs=1e-9)
    assert arc.details['coefficients'] == pytest.approx([0.5, 0.0, 0.0, 0.0], abs=1e-8)
    sigma, length = 0.5, 2.0                     # κ = σ s: x + i y = √(π/σ) (C + i S)
    fs, fc = fresnel(length * math.sqrt(sigma / math.pi))
    scale = math.sqrt(math.pi / sigma)
    clothoid = cubic_spiral([0, 0, 0, 0], [scale * fc, scale * fs, sigma * length ** 2 / 2,
                                           sigma * length])
    assert clothoid.cost == pytest.approx(length, abs=1e-9)
    assert clothoid.details['coefficients'] == pytest.approx([0.0, sigma, 0.0, 0.0], abs=1e-8)


def test_the_knots_are_the_curvatures_at_thirds():
    for knots in ([0.0, 1.0, -1.0, 0.5], [0.3, 0.3, 0.3, 0.3], [1.0, -2.0, 0.0, 4.0]):
        a, b, c, d = spiral_coefficients(knots, 3.0)
        s = np.array([0.0, 1.0, 2.0, 3.0])
        assert (a + b * s + c * s ** 2 + d * s ** 3).tolist() == pytest.approx(knots)


def test_a_bound_below_the_spiral_is_refused_with_its_peak():
    free = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0])
    peak = free.details['max_curvature']               # measured: 0.3385 1/m
    assert cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], max_curvature=peak * 1.001).found
    refused = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], max_curvature=0.9 * peak)
    assert not refused.found and 'max_curvature' in refused.reason
    assert refused.details['peak_curvature'] == pytest.approx(peak)
    start_beyond = cubic_spiral([0, 0, 0, 1.5], [4, 1, 0, 0], max_curvature=1.0)
    assert not start_beyond.found and 'start curvature' in start_beyond.reason


def test_the_budget_and_the_clock_bound_the_search():
    few = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], budget=SearchBudget(max_expansions=2))
    assert not few.found and 'budget' in few.reason and few.expansions <= 2
    ticks = iter(np.arange(0.0, 100.0, 10.0))
    late = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], budget=SearchBudget(max_seconds=5.0),
                        clock=lambda: float(next(ticks)))
    assert not late.found and 'budget' in late.reason


def test_one_point_and_a_collision():
    same = cubic_spiral([1, 1, 0.5, 0.2], [1, 1, 0.5, 0.2])
    assert same.found and same.cost == 0.0 and same.path.shape == (1, 3)
    turned = cubic_spiral([1, 1, 0.5, 0.0], [1, 1, 2.0, 0.0])
    assert not turned.found and 'one point' in turned.reason
    box = make_world(boxes=[([2.0, 0.5], [0.4, 0.4], 0.0)])   # on the lane change
    hit = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], world=box, footprint=0.2)
    assert not hit.found and 'meets an obstacle' in hit.reason
    clear = cubic_spiral([0, 0, 0, 0], [4, 1, 0, 0], world=make_world(), footprint=0.2)
    assert clear.found


@pytest.mark.parametrize('kwargs, match', [
    ({'start': [0, 0, 0]}, 'start'), ({'goal': [0, 0, math.nan, 0]}, 'goal'),
    ({'ds': 0.0}, 'ds'), ({'max_curvature': -1.0}, 'max_curvature'),
    ({'world': make_world()}, 'footprint')])
def test_bad_input_is_refused(kwargs, match):
    args = {'start': [0, 0, 0, 0], 'goal': [4, 1, 0, 0], **kwargs}
    with pytest.raises(ValueError, match=match):
        cubic_spiral(**args)
