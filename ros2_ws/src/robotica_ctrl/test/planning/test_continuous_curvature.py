"""
Tests of the continuous-curvature paths of book §10.4: clothoid turns at a polyline's corners.

References are computed here, independent of the code: the turn's and the path's poses from a
numerical integration (scipy solve_ivp) of x' = cos θ, y' = sin θ, θ' = κ(s), κ interpolated
linearly between the samples the code returns; the arc limit (σ -> ∞) and the two-clothoid peak
in closed form; curvature continuity and the bounds by finite differences of the samples; the
curvature of the sampled positions by (10.81). The tracking test drives the bicycle of
robotica_kin.mobile.vehicles (4.121) with the pure-pursuit law of §9.3.1 and measures the
distance to the path and the steering it asks for.
"""

import math

import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.tracking_laws import steering_angle
from robotica_ctrl.planning.continuous_curvature import (cc_turn, continuous_curvature_path,
                                                         sample_pieces, sharpness_bound)
from robotica_ctrl.planning.cubic_spiral import cubic_spiral
from robotica_kin.mobile.bicycle import curvature_from_steering
from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
from robotica_kin.world import make_world
from scipy.integrate import solve_ivp

ROUTE = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 5.0], [2.0, 7.0], [-1.0, 4.0], [-1.0, 1.5]])
KAPPA_MAX = 0.8    # [1/m]
SIGMA_MAX = 1.0    # [1/m²]


def integrate(s, kappa, start):
    """Return the poses (n, 3) of x' = cos θ, y' = sin θ, θ' = κ(s) at s, κ linear between."""
    def deriv(u, state):
        return [math.cos(state[2]), math.sin(state[2]), np.interp(u, s, kappa)]
    step = float(np.diff(s).min()) if len(s) > 1 else 1.0
    sol = solve_ivp(deriv, (s[0], s[-1]), start, t_eval=s, rtol=1e-11, atol=1e-12,
                    max_step=step)
    return sol.y.T


def wrapped(angle):
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def distance_to_polyline(points, polyline):
    a, b = polyline[None, :-1], polyline[None, 1:]
    ab, ap = b - a, points[:, None] - a
    t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    return np.hypot(*(ap - t[..., None] * ab).transpose(2, 0, 1)).min(axis=1)


@pytest.fixture(scope='module')
def route():
    return continuous_curvature_path(ROUTE, KAPPA_MAX, SIGMA_MAX, ds=0.02)


# ---------------------------------------------------------------- one turn


def integrate_pieces(pieces, start):
    """Return the end pose of x' = cos θ, y' = sin θ, θ' = κ0 + σ u, piece by piece."""
    state = list(start)
    for kappa0, sigma, length in pieces:
        def deriv(u, q, k=kappa0, g=sigma):
            return [math.cos(q[2]), math.sin(q[2]), k + g * u]
        sol = solve_ivp(deriv, (0.0, length), state, rtol=1e-12, atol=1e-13)
        state = sol.y[:, -1].tolist()
    return np.array(state)


@pytest.mark.parametrize('delta', [0.2, -0.64, 0.64 + 1e-9, math.pi / 2, -2.5, 3.0])
def test_a_turn_is_tangent_to_both_legs(delta):
    """The integrated end lies on the outgoing leg, T beyond the vertex (T, 0), heading δ."""
    turn = cc_turn(delta, KAPPA_MAX, SIGMA_MAX)
    end = integrate_pieces(turn.pieces, [0.0, 0.0, 0.0])
    t = turn.tangent_length
    assert end == pytest.approx([t + t * math.cos(delta), t * math.sin(delta), delta],
                                abs=1e-9)
    s, poses, kappa = sample_pieces([0.0, 0.0, 0.0], turn.pieces, 0.005)
    assert poses[-1] == pytest.approx(end, abs=1e-9)
    assert np.abs(kappa).max() <= KAPPA_MAX + 1e-12
    assert np.abs(np.diff(kappa)).max() <= SIGMA_MAX * 0.005 + 1e-12
    assert turn.peak_curvature == pytest.approx(min(KAPPA_MAX, math.sqrt(SIGMA_MAX * abs(delta))))
    assert kappa[0] == 0.0 and abs(kappa[-1]) < 1e-12
    middle = integrate_pieces(turn.pieces[:len(turn.pieces) // 2], [0.0, 0.0, 0.0]) \
        if len(turn.pieces) == 2 else integrate_pieces(
            [*turn.pieces[:1], [turn.pieces[1, 0], 0.0, turn.pieces[1, 2] / 2]], [0.0, 0.0, 0.0])
    assert turn.deviation == pytest.approx(math.hypot(middle[0] - t, middle[1]), abs=1e-9)


def test_a_sharp_turn_tends_to_the_arc_and_a_gentle_one_is_two_clothoids():
    for delta in (0.3, 1.2, 2.8):
        arc = cc_turn(delta, 0.5, 1e9)     # σ -> ∞: the arc of radius 2 m
        assert arc.tangent_length == pytest.approx(2.0 * math.tan(delta / 2), rel=1e-6)
        assert arc.deviation == pytest.approx(2.0 * (1 / math.cos(delta / 2) - 1), rel=1e-5)
    gentle = cc_turn(0.1, 1.0, 4.0)       # 0.1 < κ²/σ = 0.25: peak sqrt(0.4)
    assert gentle.pieces[:, 2].tolist() == pytest.approx([math.sqrt(0.1 / 4)] * 2)
    assert gentle.peak_curvature == pytest.approx(math.sqrt(0.4))
    assert cc_turn(1e-14, 1.0, 4.0).tangent_length == 0.0


# ---------------------------------------------------------------- a whole path


def test_the_path_is_curvature_continuous_within_its_bounds(route):
    s, kappa, poses = route.details['s'], route.details['curvature'], route.path
    ds = np.diff(s)
    assert ds.max() <= 0.02 and ds.min() > 0.0199
    assert np.abs(kappa).max() <= KAPPA_MAX + 1e-12
    assert route.details['max_curvature'] == pytest.approx(KAPPA_MAX)
    assert np.abs(np.diff(kappa)).max() <= SIGMA_MAX * ds.max() + 1e-12   # no step of κ
    assert np.abs(np.diff(poses[:, 2])).max() <= KAPPA_MAX * ds.max() + 1e-12
    assert np.abs(np.diff(poses[:, :2], axis=0)).max() <= ds.max() + 1e-12
    # κ of the sampled positions, (10.81) by central differences
    x1, y1 = np.gradient(poses[:, 0], s), np.gradient(poses[:, 1], s)
    x2, y2 = np.gradient(x1, s), np.gradient(y1, s)
    from_positions = (x1 * y2 - y1 * x2) / (x1 ** 2 + y1 ** 2) ** 1.5
    assert np.abs(from_positions - kappa)[2:-2].max() < 0.01     # measured: 6.6e-3
    assert route.cost == pytest.approx(s[-1])
    assert route.details['samples'].shape == (len(s), 4)


def test_the_ends_are_the_polyline_postures(route):
    legs = np.diff(ROUTE, axis=0)
    first, last = np.arctan2(legs[[0, -1], 1], legs[[0, -1], 0])
    samples = route.details['samples']
    assert samples[0] == pytest.approx([*ROUTE[0], first, 0.0], abs=1e-12)
    assert samples[-1, :2] == pytest.approx(ROUTE[-1], abs=1e-9)
    assert wrapped(samples[-1, 2] - last) == pytest.approx(0.0, abs=1e-9)
    assert samples[-1, 3] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize('ds, tolerance', [(0.02, 2e-4), (0.004, 1e-5)])
def test_the_samples_are_the_integral_of_their_curvature(ds, tolerance):
    """
    Integrating κ linear between samples misses each kink of κ by at most σ ds² / 4 of heading.

    Measured: 6.4e-5 m at ds = 0.02 m, 2.3e-6 m at ds = 0.004 m (the error falls as ds²).
    """
    result = continuous_curvature_path(ROUTE, KAPPA_MAX, SIGMA_MAX, ds=ds)
    s, kappa = result.details['s'], result.details['curvature']
    reference = integrate(s, kappa, result.path[0])
    assert np.abs(reference - result.path).max() < tolerance


def test_the_path_stays_within_each_turns_deviation_of_the_polyline(route):
    gap = distance_to_polyline(route.path[:, :2], ROUTE)
    deviation = max(turn.deviation for turn in route.details['turns'])
    assert gap.max() <= deviation + 1e-9
    straight = route.details['curvature'] == 0.0
    assert gap[straight].max() < 1e-9


# ---------------------------------------------------------------- refusals


def test_legs_too_short_for_their_turns_are_refused_with_the_lengths():
    result = continuous_curvature_path([[0, 0], [5, 0], [5, 1], [0, 1]], KAPPA_MAX, SIGMA_MAX)
    assert not result.found
    assert result.reason.startswith('leg 1 (vertex 1 to 2) is 1.000 m long, its turns need ')
    assert 'shortcut' in result.reason and result.details['leg'] == 1
    assert continuous_curvature_path([[0, 0], [5, 0], [5, 1], [0, 1]], 4.0, 40.0).found


def test_a_cusp_and_a_collision_are_refused_with_the_reason():
    cusp = continuous_curvature_path([[0, 0], [5, 0], [2, 0]], KAPPA_MAX, SIGMA_MAX)
    assert not cusp.found and 'turns back at vertex 1' in cusp.reason
    # a box in the inside of the corner: the polyline clears it, the rounded turn does not
    box = make_world(boxes=[([5.65, 0.35], [0.1, 0.1], 0.0)])
    points = [[0, 0], [6, 0], [6, 6]]
    assert continuous_curvature_path(points, KAPPA_MAX, SIGMA_MAX).found
    hit = continuous_curvature_path(points, KAPPA_MAX, SIGMA_MAX, world=box, footprint=0.1)
    assert not hit.found and 'meets an obstacle' in hit.reason
    assert 'collision' in hit.details


@pytest.mark.parametrize('args, kwargs, match', [
    (([[0, 0]], 1.0, 1.0), {}, 'shape'), (([[0, 0], [0, 0]], 1.0, 1.0), {}, 'distinct'),
    (([[0, 0], [1, 0]], 0.0, 1.0), {}, 'max_curvature'),
    (([[0, 0], [1, 0]], 1.0, math.nan), {}, 'max_sharpness'),
    (([[0, 0], [1, 0]], 1.0, 1.0), {'ds': -1.0}, 'ds'),
    (([[0, 0], [1, 0]], 1.0, 1.0), {'world': make_world()}, 'footprint')])
def test_bad_input_is_refused(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        continuous_curvature_path(*args, **kwargs)
    with pytest.raises(ValueError, match='deflection'):
        cc_turn(math.pi, 1.0, 1.0)
    with pytest.raises(ValueError, match='length'):
        sample_pieces([0, 0, 0], [[0.0, 0.0, 0.0]], 0.1)


def test_the_sharpness_bound_keeps_the_steering_rate():
    """Along a clothoid of σ_max the steering α = atan(l κ) turns at most α'_max at speed v."""
    rate, v, wheelbase = 0.4, 1.5, 2.0
    sigma = sharpness_bound(rate, v, wheelbase)
    s = np.linspace(0.0, 2.0, 2001)
    alpha = np.arctan(wheelbase * sigma * s)
    assert (np.diff(alpha) / (np.diff(s) / v)).max() <= rate * (1 + 1e-9)


# ---------------------------------------------------------------- tracking


WHEELBASE, STEERING_LIMIT = 0.5, 0.5       # [m], [rad]: κ_vehicle = tan(0.5) / 0.5 = 1.09


def drive(points, duration, dt=0.01, lookahead=0.25):
    """
    Return the poses and the steering angles of the bicycle driven by pure pursuit on points.

    The commanded (v, ω) becomes α = atan(l ω / v) (4.119); the vehicle's inverse model clamps
    it at its limit, its direct model gives the twist, integrated exactly over dt (an arc).
    """
    geometry = VehicleGeometry(wheelbase=WHEELBASE, max_steering_angle=STEERING_LIMIT)
    vehicle = vehicle_kinematics('bicycle', geometry)
    tracker = PurePursuit(PolylinePath(points),
                          PurePursuitParams(lookahead_distance=lookahead,
                                            desired_linear_velocity=0.5))
    start = points[1] - points[0]
    pose = np.array([*points[0], math.atan2(start[1], start[0])])
    poses, asked = [pose], []
    for k in range(round(duration / dt)):
        out = tracker.update(pose, k * dt)
        if out.finished:
            break
        alpha = steering_angle(out.linear, out.angular, WHEELBASE)
        asked.append(alpha)
        v, _, omega = vehicle.body_twist(vehicle.actuator_targets(np.array([out.linear, alpha,
                                                                            0.0])))
        half = 0.5 * omega * dt
        chord = v * dt * (math.sin(half) / half if half else 1.0)
        pose = pose + [chord * math.cos(pose[2] + half), chord * math.sin(pose[2] + half),
                       2.0 * half]
        poses.append(pose)
    return np.array(poses), np.array(asked)


def test_a_bicycle_follows_the_path_within_its_steering_limit():
    kappa_vehicle = curvature_from_steering(STEERING_LIMIT, WHEELBASE)
    result = continuous_curvature_path(ROUTE, 0.7 * kappa_vehicle, 2.0, ds=0.02)   # σ_max = 2
    assert result.found
    poses, asked = drive(result.path[:, :2], 60.0)
    error = distance_to_polyline(poses[:, :2], result.path[:, :2])
    assert np.abs(asked).max() < STEERING_LIMIT          # measured: 0.378 rad, never clamped
    assert error.max() < 0.02                             # measured: 0.0041 m
    assert np.hypot(*(poses[-1, :2] - ROUTE[-1])) < 0.06  # the end, within goal_tolerance
    # σ_max = 2 1/m² at v = 0.5 m/s, l = 0.5 m is a steering rate of σ v l = 0.5 rad/s
    assert np.abs(np.diff(asked)).max() / 0.01 <= 2.0 * 0.5 * WHEELBASE   # measured: 0.435
    # the same law on the raw polyline asks for more steering than the vehicle has
    _, raw = drive(ROUTE, 60.0)
    assert np.abs(raw).max() > STEERING_LIMIT            # measured: 1.36 rad


def test_a_bicycle_follows_a_cubic_spiral_lane_change():
    kappa_vehicle = curvature_from_steering(STEERING_LIMIT, WHEELBASE)
    spiral = cubic_spiral([0, 0, 0, 0], [5.0, 1.5, 0, 0], max_curvature=kappa_vehicle, ds=0.02)
    assert spiral.found
    points = np.vstack([spiral.path[:, :2], [[6.0, 1.5]]])   # 1 m straight to finish on
    poses, asked = drive(points, 30.0)
    assert np.abs(asked).max() < STEERING_LIMIT          # measured: 0.158 rad
    assert distance_to_polyline(poses[:, :2], points).max() < 0.01   # measured: 0.0011 m
