"""
Tests of robotica_ctrl.mobile.reactive: reactive laws of book §9.6 and §12.7.

Hand-computed values come from the formulas of the seed catalogue (Part 7.6 law (9.93),
Part 10.6 VFF (12.9)-(12.15) with the repulsive sign, Krogh (12.3)-(12.8)). Closed-loop tests
integrate the unicycle x' = v cos θ, y' = v sin θ, θ' = ω written below with the classic
RK4 step (commands held over the step) and build the sensor readings from the world geometry.
"""

import dataclasses
import math

import numpy as np
import pytest

from robotica_ctrl.mobile.reactive import (
    corridor_centring, CorridorCentringParams, generalised_potential,
    GeneralisedPotentialParams, speed_modulation, SpeedModulationParams, VelocityCommand,
    virtual_force_field, VirtualForceFieldParams, wall_following, WallFollowingParams)


def unicycle_step(pose, v, omega, dt):
    """Advance (x, y, θ) by one RK4 step of the unicycle with (v, ω) held constant."""
    def f(q):
        return np.array([v * math.cos(q[2]), v * math.sin(q[2]), omega])
    k1 = f(pose)
    k2 = f(pose + 0.5 * dt * k1)
    k3 = f(pose + 0.5 * dt * k2)
    k4 = f(pose + dt * k3)
    return pose + dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0


def to_base(points, pose):
    """Express world points (N, 2) in base_link of ``pose``."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    rel = np.atleast_2d(points) - pose[:2]
    return np.column_stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]])


# --- wall following and corridor centring -------------------------------------------------

def test_wall_following_hand_values():
    p = WallFollowingParams(desired_distance=0.5, linear_velocity=0.4, k_distance=2.0,
                            k_angle=3.0, max_angular_velocity=10.0)
    # left wall, d = 0.8, wall angle 0.1: ξ = 0.5 − 0.8 = −0.3, φ̃ = −0.1
    # ω = −2·0.4·(−0.3) − 3·0.4·(−0.1) = 0.24 + 0.12 = 0.36
    v, w = wall_following(0.8, 0.1, 'left', p)
    assert v == 0.4
    assert w == pytest.approx(0.36)
    # right wall, d = 0.3, angle −0.2: ξ = 0.3 − 0.5 = −0.2, φ̃ = 0.2
    # ω = −2·0.4·(−0.2) − 3·0.4·0.2 = 0.16 − 0.24 = −0.08
    assert wall_following(0.3, -0.2, 'right', p).angular == pytest.approx(-0.08)
    # on the set line, parallel to the wall: go straight
    assert wall_following(0.5, 0.0, 'left', p) == VelocityCommand(0.4, 0.0)


def test_wall_following_saturates():
    p = WallFollowingParams(max_angular_velocity=0.5)
    assert wall_following(5.0, 0.0, 'left', p).angular == 0.5
    assert wall_following(5.0, 0.0, 'right', p).angular == -0.5


@pytest.mark.parametrize('d', [0.2, 0.5, 0.9])
@pytest.mark.parametrize('angle', [-0.4, 0.0, 0.3])
def test_wall_following_mirror_symmetry(d, angle):
    p = WallFollowingParams()
    left = wall_following(d, angle, 'left', p)
    right = wall_following(d, -angle, 'right', p)
    assert right.linear == left.linear
    assert right.angular == pytest.approx(-left.angular, abs=1e-15)


def test_corridor_hand_values_and_symmetry():
    p = CorridorCentringParams(linear_velocity=0.5, k_distance=2.0, k_angle=1.0,
                               max_angular_velocity=10.0)
    # ξ = (1.4 − 0.6)/2 = 0.4 (left of centre), φ̃ = −0.2
    # ω = −2·0.5·0.4 − 1·0.5·(−0.2) = −0.4 + 0.1 = −0.3
    assert corridor_centring(0.6, 1.4, 0.2, p).angular == pytest.approx(-0.3)
    assert corridor_centring(1.4, 0.6, -0.2, p).angular == pytest.approx(0.3)
    assert corridor_centring(1.0, 1.0, 0.0, p) == VelocityCommand(0.5, 0.0)


def test_wall_following_converges_along_straight_wall():
    """Wall y = 2 on the left; the robot starts at y = 0.4 heading 0.3 rad off the wall."""
    p = WallFollowingParams(desired_distance=0.6, linear_velocity=0.5)
    wall_y, dt = 2.0, 0.02
    pose = np.array([0.0, 0.4, 0.3])
    for _ in range(round(30.0 / dt)):
        v, w = wall_following(wall_y - pose[1], -pose[2], 'left', p)
        pose = unicycle_step(pose, v, w, dt)
    assert wall_y - pose[1] == pytest.approx(0.6, abs=1e-3)
    assert pose[2] == pytest.approx(0.0, abs=1e-3)
    # right wall y = −1 from the mirrored start
    pose = np.array([0.0, -0.4, -0.3])
    for _ in range(round(30.0 / dt)):
        v, w = wall_following(pose[1] + 1.0, -pose[2], 'right', p)
        pose = unicycle_step(pose, v, w, dt)
    assert pose[1] + 1.0 == pytest.approx(0.6, abs=1e-3)


def test_wall_following_decay_rate_in_distance():
    """Law (9.93), (9.97): with k1 = b², k2 = 2b (δ = 1) ξ ≈ (ξ0 + b ξ0 ρ) e^{−bρ}, small φ̃."""
    b = 2.0
    p = WallFollowingParams(desired_distance=1.0, linear_velocity=0.5, k_distance=b * b,
                            k_angle=2.0 * b, max_angular_velocity=10.0)
    xi0, dt, steps = 0.05, 0.01, 200
    pose = np.array([0.0, xi0, 0.0])  # wall at y = 1 + 0, left: ξ = y
    for _ in range(steps):
        v, w = wall_following(1.0 - pose[1], -pose[2], 'left', p)
        pose = unicycle_step(pose, v, w, dt)
    rho = 0.5 * dt * steps
    expected = xi0 * (1.0 + b * rho) * math.exp(-b * rho)
    assert pose[1] == pytest.approx(expected, abs=2e-4)


def test_corridor_centring_converges_to_middle():
    p = CorridorCentringParams(linear_velocity=0.6)
    left_y, right_y, dt = 1.5, -0.5, 0.02  # centre line y = 0.5
    pose = np.array([0.0, 1.2, -0.4])
    for _ in range(round(30.0 / dt)):
        v, w = corridor_centring(left_y - pose[1], pose[1] - right_y, -pose[2], p)
        pose = unicycle_step(pose, v, w, dt)
        assert right_y < pose[1] < left_y
    assert pose[1] == pytest.approx(0.5, abs=1e-3)
    assert pose[2] == pytest.approx(0.0, abs=1e-3)


@pytest.mark.parametrize('args', [
    (0.0, 0.0, 'left'), (-1.0, 0.0, 'left'), (math.nan, 0.0, 'left'), (1.0, math.inf, 'left'),
    (1.0, 1.6, 'left'), (1.0, 0.0, 'up'), (1.0, -math.pi / 2, 'right')])
def test_wall_following_rejects_bad_input(args):
    with pytest.raises(ValueError):
        wall_following(*args, WallFollowingParams())


@pytest.mark.parametrize('args', [(0.0, 1.0, 0.0), (1.0, math.nan, 0.0), (1.0, 1.0, 2.0)])
def test_corridor_rejects_bad_input(args):
    with pytest.raises(ValueError):
        corridor_centring(*args, CorridorCentringParams())


@pytest.mark.parametrize('cls, field', [
    (WallFollowingParams, 'desired_distance'), (WallFollowingParams, 'k_angle'),
    (CorridorCentringParams, 'k_distance'), (VirtualForceFieldParams, 'window_radius'),
    (GeneralisedPotentialParams, 'max_deceleration'),
    (SpeedModulationParams, 'safety_distance')])
@pytest.mark.parametrize('value', [0.0, -1.0, math.nan, math.inf])
def test_params_validation(cls, field, value):
    with pytest.raises(ValueError):
        cls(**{field: value})


def test_params_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        WallFollowingParams().k_angle = 1.0  # type: ignore[misc]


# --- virtual force field ------------------------------------------------------------------

def test_vff_no_obstacle_is_pure_goal_seeking():
    p = VirtualForceFieldParams(k_heading=1.0, max_angular_velocity=10.0)
    v, w = virtual_force_field(np.zeros((0, 2)), [1.0, 1.0], p)
    assert v == p.max_linear_velocity
    assert w == pytest.approx(math.pi / 4)
    # a point outside the window is ignored
    assert virtual_force_field([[3.0, 0.1]], [1.0, 1.0], p) == (v, w)


def test_vff_hand_values():
    p = VirtualForceFieldParams(repulsive_gain=2.0, attractive_gain=1.0, window_radius=3.0,
                                max_linear_velocity=1.0, k_heading=1.0,
                                max_angular_velocity=10.0)
    # obstacle at (1, 1): d = √2, F_r = 2/2 · (−1, −1)/√2 = (−1/√2, −1/√2)
    # goal (2, 0): F_a = (1, 0); R = (1 − 1/√2, −1/√2)
    # cos θ = F_rx/|F_r| = −1/√2 → v = 1 − 1/√2
    v, w = virtual_force_field([[1.0, 1.0]], [2.0, 0.0], p)
    r = 1.0 / math.sqrt(2.0)
    assert v == pytest.approx(1.0 - r)
    assert w == pytest.approx(math.atan2(-r, 1.0 - r))
    # obstacle abeam (0, 1): F_r = 2/1² (0, −1), v = V_max, R = (1, −2)
    v, w = virtual_force_field([[0.0, 1.0]], [2.0, 0.0], p)
    assert v == pytest.approx(1.0)
    assert w == pytest.approx(math.atan2(-2.0, 1.0))
    # weak push dead ahead (2.5, 0): |F_r| = 2/6.25 = 0.32 < F_ca, cos θ = −1
    # v = 1 − 0.32 (the book's 1 − |cos θ| would stall at 0); R = (1 − 0.32, 0): ω = 0
    assert virtual_force_field([[2.5, 0.0]], [5.0, 0.0], p) == pytest.approx((0.68, 0.0))


def test_vff_mirror_symmetry():
    p = VirtualForceFieldParams()
    obstacles = np.array([[1.0, 0.4], [0.5, -1.2], [1.5, 0.9]])
    goal = np.array([3.0, 0.7])
    v, w = virtual_force_field(obstacles, goal, p)
    vm, wm = virtual_force_field(obstacles * [1.0, -1.0], goal * [1.0, -1.0], p)
    assert vm == pytest.approx(v)
    assert wm == pytest.approx(-w)
    assert w != 0.0


def test_vff_closed_loop_passes_point_obstacle():
    p = VirtualForceFieldParams(repulsive_gain=0.5, window_radius=1.5, max_linear_velocity=0.5,
                                k_heading=2.0, max_angular_velocity=1.5, goal_tolerance=0.1)
    obstacle, goal = np.array([[3.0, 0.1]]), np.array([6.0, 0.0])
    pose, dt, safety = np.array([0.0, 0.0, 0.0]), 0.02, 0.4
    closest = math.inf
    for _ in range(round(60.0 / dt)):
        v, w = virtual_force_field(to_base(obstacle, pose), to_base(goal, pose)[0], p)
        if v == 0.0 and w == 0.0:
            break
        pose = unicycle_step(pose, v, w, dt)
        closest = min(closest, float(np.hypot(*(pose[:2] - obstacle[0]))))
    assert np.hypot(*(pose[:2] - goal)) <= 0.1
    assert closest > safety


# --- generalised potential ----------------------------------------------------------------

def test_generalised_potential_hand_values():
    p = GeneralisedPotentialParams(max_deceleration=2.0, repulsive_gain=1.0,
                                   attractive_gain=1.0, max_linear_velocity=1.0, k_heading=1.0,
                                   max_angular_velocity=10.0)
    # obstacle (1, 1), speed 1: d = √2, v_i = 1/√2, P = α v_i/(2 d α − v_i²)
    d, vi, alpha = math.sqrt(2.0), 1.0 / math.sqrt(2.0), 2.0
    pot = alpha * vi / (2 * d * alpha - vi ** 2)
    # t_max − t_min = 2d/v_i − v_i/α must be 1/P
    assert 2 * d / vi - vi / alpha == pytest.approx(1.0 / pot)
    force = 2 * pot ** 2 / vi * np.array([-1.0, -1.0]) / d
    resultant = np.array([1.0, 0.0]) + force
    beta = math.atan2(resultant[1], resultant[0])
    v, w = generalised_potential([[1.0, 1.0]], [5.0, 0.0], 1.0, p)
    assert w == pytest.approx(beta)
    assert v == pytest.approx(math.cos(beta))
    # receding obstacle (behind) or robot at rest: no repulsion, pure goal seeking
    assert generalised_potential([[-1.0, 0.2]], [1.0, 1.0], 1.0, p).angular == pytest.approx(
        math.pi / 4)
    assert generalised_potential([[1.0, 0.2]], [1.0, 1.0], 0.0, p).angular == pytest.approx(
        math.pi / 4)


def test_generalised_potential_gradient_matches_finite_difference():
    """−∂P/∂d = 2 P² / v_i (12.8), checked by a central difference of P(d) (12.6)."""
    alpha, vi, d, h = 1.5, 0.8, 1.2, 1e-6

    def pot(dd):
        return alpha * vi / (2 * dd * alpha - vi * vi)
    fd = -(pot(d + h) - pot(d - h)) / (2 * h)
    assert fd == pytest.approx(2 * pot(d) ** 2 / vi, rel=1e-7)


def test_generalised_potential_unavoidable_stops_and_symmetry():
    p = GeneralisedPotentialParams(max_deceleration=1.0)
    # 2 d α = 0.2 < v_i² = 1: cannot stop in time
    assert generalised_potential([[0.1, 0.0]], [5.0, 0.0], 1.0, p) == (0.0, 0.0)
    obstacles = np.array([[1.0, 0.3], [2.0, -0.5]])
    v, w = generalised_potential(obstacles, [4.0, 0.2], 0.4, p)
    vm, wm = generalised_potential(obstacles * [1, -1], [4.0, -0.2], 0.4, p)
    assert (vm, wm) == pytest.approx((v, -w))


def test_generalised_potential_closed_loop_passes_point_obstacle():
    """The measured speed fed back is the previous command (a perfect speed loop)."""
    p = GeneralisedPotentialParams(max_deceleration=0.5, repulsive_gain=1.0,
                                   max_linear_velocity=0.5, goal_tolerance=0.1)
    obstacle, goal = np.array([[3.0, 0.1]]), np.array([6.0, 0.0])
    pose, dt, v = np.array([0.0, 0.0, 0.0]), 0.02, 0.0
    closest = math.inf
    for _ in range(round(30.0 / dt)):
        v, w = generalised_potential(to_base(obstacle, pose), to_base(goal, pose)[0], v, p)
        if v == 0.0 and w == 0.0:
            break
        pose = unicycle_step(pose, v, w, dt)
        closest = min(closest, float(np.hypot(*(pose[:2] - obstacle[0]))))
    assert np.hypot(*(pose[:2] - goal)) <= 0.1
    assert closest > 0.35


@pytest.mark.parametrize('obstacles, goal', [
    ([[1.0, 2.0, 3.0]], [1.0, 0.0]), ([[math.nan, 1.0]], [1.0, 0.0]),
    ([[0.0, 0.0]], [1.0, 0.0]), ([[1.0, 1.0]], [1.0]), ([[1.0, 1.0]], [math.inf, 0.0])])
def test_potential_laws_reject_bad_input(obstacles, goal):
    with pytest.raises(ValueError):
        virtual_force_field(obstacles, goal, VirtualForceFieldParams())
    with pytest.raises(ValueError):
        generalised_potential(obstacles, goal, 0.5, GeneralisedPotentialParams())


def test_generalised_potential_rejects_bad_speed():
    with pytest.raises(ValueError):
        generalised_potential([], [1.0, 0.0], -0.1, GeneralisedPotentialParams())


def test_at_goal_commands_stop():
    assert virtual_force_field([[0.5, 0.0]], [0.01, 0.0], VirtualForceFieldParams()) == (0, 0)
    assert generalised_potential([], [0.0, 0.01], 0.3, GeneralisedPotentialParams()) == (0, 0)


# --- speed modulation ---------------------------------------------------------------------

def test_speed_modulation_values_monotone_and_stop():
    p = SpeedModulationParams(safety_distance=0.4, slowdown_distance=1.2)
    assert speed_modulation(0.8, 0.8, p) == pytest.approx(0.4)  # 0.8 · 0.4 / 0.8
    assert speed_modulation(0.8, math.inf, p) == 0.8
    assert speed_modulation(0.8, 5.0, p) == 0.8
    distances = np.linspace(0.0, 2.0, 401)
    speeds = [speed_modulation(0.8, d, p) for d in distances]
    assert np.all(np.diff(speeds) >= 0.0)
    assert all(s == 0.0 for d, s in zip(distances, speeds) if d <= 0.4)
    assert all(s > 0.0 for d, s in zip(distances, speeds) if d > 0.4)
    assert max(speeds) == 0.8


@pytest.mark.parametrize('v, d', [(math.nan, 1.0), (1.0, math.nan), (1.0, -0.1)])
def test_speed_modulation_rejects_bad_input(v, d):
    with pytest.raises(ValueError):
        speed_modulation(v, d, SpeedModulationParams())


def test_speed_modulation_params_ordering():
    with pytest.raises(ValueError):
        SpeedModulationParams(safety_distance=1.0, slowdown_distance=1.0)
