"""
Tests of the parking collision predicates and the positioning point (catalogue §14.3, §14.5).

The reference is the vehicle's rectangle carried along the arcs, written here: poses on a
circle in closed form (x = x0 + (sin(θ0 + κs) − sin θ0)/κ, y = y0 − (cos(θ0 + κs) − cos θ0)/κ),
20 000 per arc, and the rectangle's corners at each pose. Its extremes are those of the swept
body up to the sampling (below 1e-7 m here).
"""

import math

import numpy as np
import pytest
from robotica_ctrl.planning.parking.collision_predicates import (
    front_rear_collision_free, front_rear_singular_angle, lateral_reach, sampled_extents,
    two_arc_extents)
from robotica_ctrl.planning.parking.execution_modes import GeometricMode, ProgressiveMode
from robotica_ctrl.planning.parking.positioning_point import (
    approach, front_corner_offset, positioning_offset, sampled_corner_offset)
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle

CAR = ParkingVehicle()
ROBOT = ParkingVehicle(a1=0.45, b1=0.1, h1=0.35, c1=0.3, theta_dmax=0.5, d1=0.28, r=0.05)
WIDE = ParkingVehicle(a1=1.5, b1=1.0, h1=0.5, c1=2.0, theta_dmax=1.2)   # ρ_min < c1/2
SAMPLES = 20000


def arc_poses(start, curvature, signed_length):
    """Return poses (SAMPLES + 1, 3) along a circle from ``start`` (closed form)."""
    s = np.linspace(0.0, signed_length, SAMPLES + 1)
    x0, y0, t0 = start
    theta = t0 + curvature * s
    return np.column_stack([x0 + (np.sin(theta) - math.sin(t0)) / curvature,
                            y0 - (np.cos(theta) - math.cos(t0)) / curvature, theta])


def two_arcs(rho, xi, direction):
    """Return the poses of the two arcs of a manoeuvre shifting right (start at the origin)."""
    first = arc_poses((0.0, 0.0, 0.0), -1.0 / rho, direction * rho * xi)
    second = arc_poses(first[-1], 1.0 / rho, direction * rho * xi)
    return first, second


def corners(vehicle, poses):
    """Return the rectangle's corners at each pose, (n, 4, 2): RR, FR, FL, RL."""
    half = 0.5 * vehicle.c1
    body = np.array([[-vehicle.b1, -half], [vehicle.a1, -half], [vehicle.a1, half],
                     [-vehicle.b1, half]])
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    return np.stack([poses[:, 0:1] + c * body[:, 0] - s * body[:, 1],
                     poses[:, 1:2] + s * body[:, 0] + c * body[:, 1]], axis=-1)


@pytest.mark.parametrize('vehicle', [CAR, ROBOT])
@pytest.mark.parametrize('direction, corner', [(-1, 1), (1, 2)])
@pytest.mark.parametrize('fraction', [0.05, 0.3, 0.7, 1.0])
def test_lateral_reach_is_the_swept_body_s_reach_towards_the_curb(
        vehicle, direction, corner, fraction):
    rho = vehicle.rho_min
    xi = fraction * 0.5 * math.pi          # both sides of θ̂ = δ_i: δ_1, δ_2 in (0.02, 0.9)
    first, second = two_arcs(rho, xi, direction)
    body = corners(vehicle, np.vstack([first, second]))
    reach = lateral_reach(vehicle, rho, xi, corner)
    # The leading corner on the curb side: rear-right reversing, front-right forward.
    leading = corners(vehicle, second)[:, 0 if corner == 1 else 1, 1]
    assert -leading.min() == pytest.approx(reach, abs=1e-7)
    # The slides' claim: that corner on the second arc is where the whole body reaches.
    assert -body[..., 1].min() == pytest.approx(reach, abs=1e-7)


@pytest.mark.parametrize('vehicle', [CAR, ROBOT, WIDE])
@pytest.mark.parametrize('xi', [0.05, 0.2, 0.5, 1.0, 1.5])
@pytest.mark.parametrize('corner, ab', [(3, 'b1'), (4, 'a1')])
def test_front_rear_decision_against_the_corner_on_one_arc(vehicle, xi, corner, ab):
    # One arc about an ICR on the left from the vehicle parallel to x (the slides' θ = 0):
    # P3 (rear-inner: rear-left) followed driving forward, P4 (front-inner: front-left) in
    # reverse. "No front/rear collision" must mean that the corner never passes beyond the
    # arc's ends along x: backwards (-x) for P3, ahead (+x) for P4.
    rho = vehicle.rho_min
    direction = 1 if corner == 3 else -1
    poses = arc_poses((0.0, 0.0, 0.0), 1.0 / rho, direction * rho * xi)
    track = corners(vehicle, poses)[:, 3 if corner == 3 else 2, 0]
    along = (-1.0 if corner == 3 else 1.0) * track
    beyond = along.max() > max(along[0], along[-1]) + 1e-9
    free = front_rear_collision_free(rho, vehicle.c1, getattr(vehicle, ab), xi)
    assert free == (not beyond)
    if corner == 3:
        inside = 0.0 <= front_rear_singular_angle(vehicle, rho, 3) <= xi
        assert inside == beyond


def test_front_rear_decision_table():
    assert front_rear_collision_free(0.85, 1.7, 0.9, 1.2)          # ρ = c1/2
    assert front_rear_collision_free(0.1, 2.0, 1.0, 0.5)           # 0.1 <= 1 - tan(0.5)
    assert not front_rear_collision_free(0.5, 2.0, 1.0, 0.5)       # 0.5 > 0.4537


@pytest.mark.parametrize('vehicle', [CAR, ROBOT, WIDE])
@pytest.mark.parametrize('direction', [-1, 1])
def test_two_arc_extents_against_the_swept_body(vehicle, direction):
    rng = np.random.default_rng(14)
    for _ in range(6):
        rho = vehicle.rho_min * rng.uniform(1.0, 4.0)
        xi = rng.uniform(0.01, 0.5 * math.pi)
        first, second = two_arcs(rho, xi, direction)
        body = corners(vehicle, np.vstack([first, second]))
        e = two_arc_extents(vehicle, rho, xi, direction)
        expected = [-body[..., 1].min(), body[..., 1].max(), -body[..., 0].min(),
                    body[..., 0].max()]
        assert [e.curb, e.street, e.back, e.ahead] == pytest.approx(expected, abs=1e-7)
        sampled = sampled_extents(np.vstack([first, second])[::10], vehicle.footprint)
        assert sampled.curb <= e.curb + 1e-12 and sampled.back <= e.back + 1e-12
        assert sampled.curb == pytest.approx(e.curb, abs=1e-5)


def test_extents_mirror_and_rest():
    e = two_arc_extents(CAR, 4.0, 0.0, 1)
    assert (e.curb, e.street, e.back, e.ahead) == pytest.approx((0.85, 0.85, 0.9, 3.6))
    m = two_arc_extents(CAR, 4.0, 0.5, 1).mirrored()
    assert m.street == pytest.approx(two_arc_extents(CAR, 4.0, 0.5, 1).curb)


def test_bad_corner_and_postures_are_refused():
    with pytest.raises(ValueError, match='corner'):
        lateral_reach(CAR, 4.0, 0.3, 3)
    with pytest.raises(ValueError, match='corner'):
        front_rear_singular_angle(CAR, 4.0, 1)
    with pytest.raises(ValueError, match='postures'):
        sampled_extents([[0.0, 0.0]], CAR.footprint)


def inside_body(vehicle, poses, point):
    """Return whether ``point`` (2,) lies inside the rectangle at any of ``poses``."""
    dx, dy = point[0] - poses[:, 0], point[1] - poses[:, 1]
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    along, across = c * dx + s * dy, -s * dx + c * dy
    return bool(np.any((along >= -vehicle.b1) & (along <= vehicle.a1)
                       & (np.abs(across) <= 0.5 * vehicle.c1)))


@pytest.mark.parametrize('vehicle, xi', [(CAR, 0.75), (CAR, 0.8), (CAR, 0.85), (ROBOT, 0.4),
                                         (ROBOT, 0.55), (ROBOT, 0.7)])
def test_dx1_makes_p2_pass_through_the_front_obstacle_s_corner(vehicle, xi):
    # ξ where P2 crosses the corner's line in the second arc: Y = 2ρ sin ξ >= a1 and P2 still
    # ahead of the line when the second arc begins.
    rho = vehicle.rho_min
    dx1 = front_corner_offset(vehicle, rho, xi)
    assert dx1 is not None
    first, second = two_arcs(rho, xi, -1)
    # The start frame has P_f at the origin; the corner is level with it, dx1 to the right.
    corner = np.array([0.0, -dx1])
    p2 = corners(vehicle, second)[:, 1]
    assert np.hypot(*(p2 - corner).T).min() < 2e-4 * vehicle.length
    # In the second arc the corner touches the body: closer by ε it is inside, farther not.
    tolerance = 1e-3 * vehicle.length
    assert inside_body(vehicle, second, corner + [0.0, tolerance])
    assert not inside_body(vehicle, second, corner - [0.0, tolerance])
    # The sampled measure (the body ahead of the corner's line, plus the most a point moves
    # between samples) bounds it from above, within that motion (d_2 ρ ξ / 20000 / ρ).
    if dx1 > 0.5 * vehicle.c1:
        sampled = sampled_corner_offset(np.vstack([first, second]), vehicle.footprint)
        step = xi / SAMPLES * (1.0 + vehicle.rho_min + math.hypot(vehicle.a1,
                                                                  0.5 * vehicle.c1))
        assert dx1 - 1e-9 <= sampled <= dx1 + 2.0 * step


def test_no_theta_star_when_p2_crosses_in_the_first_arc():
    rho = ROBOT.rho_min
    assert front_corner_offset(ROBOT, rho, 0.9) is None
    first, _ = two_arcs(rho, 0.9, -1)
    p2_line = corners(ROBOT, first)[:, 1, 0]          # P2's x: it passes x = 0 in arc 1
    assert p2_line[0] > 0.0 > p2_line[-1]


def test_dx1_without_a_crossing_in_the_second_arc():
    # A short manoeuvre leaves the front beyond the corner's line (Y < a1): no θ*.
    assert front_corner_offset(CAR, CAR.rho_min, 0.2) is None
    mode = GeometricMode(CAR, CAR.theta_dmax)
    first, second = two_arcs(CAR.rho_min, 0.2, -1)
    least = sampled_corner_offset(np.vstack([first, second]), CAR.footprint)
    assert positioning_offset(mode, 0.2, 0.2) >= least + 0.2 - 1e-3


def test_positioning_offset_keeps_the_start_clear_and_adds_the_margin():
    mode = GeometricMode(CAR, CAR.theta_dmax)
    slides = front_corner_offset(CAR, CAR.rho_min, 0.8)
    assert positioning_offset(mode, 0.8, 0.2) == pytest.approx(max(slides, 0.85) + 0.2)
    assert positioning_offset(mode, 0.78, 0.0) >= 0.85                # never below c1/2
    progressive = ProgressiveMode(CAR, CAR.theta_dmax, 1.0)
    assert positioning_offset(progressive, 1.5, 0.2) >= 0.85 + 0.2


def drive(vehicle, pieces, start=(0.0, 0.0, 0.0)):
    """Return the poses of driving constant-steering pieces (closed-form arcs, here)."""
    poses = [np.array([start])]
    for piece in pieces:
        assert piece.steering_start == piece.steering_end
        curvature = math.tan(piece.steering_start) / vehicle.h1
        poses.append(arc_poses(poses[-1][-1], curvature, piece.direction * piece.length))
    return np.vstack(poses)


@pytest.mark.parametrize('dx2', [1.4, 2.5, 1.0])
def test_the_approach_ends_at_the_positioning_point(dx2):
    mode = GeometricMode(CAR, CAR.theta_dmax)
    dx1 = 1.05
    way = approach(mode, dx1, dx2, 0.1)
    poses = drive(CAR, way.pieces)
    # From the stop point (0, dx2) back to the positioning point (-dy3, dx1).
    assert poses[-1] == pytest.approx([-way.dy3, dx1 - dx2, 0.0], abs=1e-9)
    assert all(p.direction == -1 for p in way.pieces)
    assert way.toward_curb == (dx2 > dx1)
    rho = CAR.h1 / math.tan(way.steering)
    assert way.dy3 == pytest.approx(math.sqrt(abs(dx2 - dx1) * (4 * rho - abs(dx2 - dx1))))
    # Beside the front obstacle (x >= -dy3, its corner level with the positioning point),
    # the body keeps the clearance from the obstacles' line, y = -dx2 in this frame.
    body = corners(CAR, poses)
    beside = body[..., 0] >= -way.dy3
    assert (body[..., 1][beside] >= -dx2 + 0.1 - 1e-6).all()


def test_no_approach_from_a_pass_too_close():
    assert approach(GeometricMode(CAR, CAR.theta_dmax), 1.05, 0.9, 0.1) is None
    straight = approach(GeometricMode(CAR, CAR.theta_dmax), 1.05, 1.05, 0.1)
    assert straight.dy3 == 0.0 and straight.pieces == ()
