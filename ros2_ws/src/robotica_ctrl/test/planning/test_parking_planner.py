"""
End-to-end tests of the parallel-parking planner (issue 21, catalogue §14.4-§14.5).

Every path is checked here with geometry independent of the planner: the parked cars and the
curb are rectangles written in tests/parking_reference.py, and the body swept between two
postures is the convex hull of the two footprints (SciPy's ConvexHull), tested against each
rectangle by the separating-axis theorem. The hull misses the true swept region by at most the
sagitta of a corner's arc over one 5 cm step (under 0.4 mm here), so the obstacles are grown
by 1 mm more than the clearance asserted.
"""

import itertools
import math

import numpy as np
from parking_reference import (assert_swept_free, CAR, obstacles, on_map, ORIGIN, ROBOT,
                               SLOW_STEERING, space_for, start_for)
import pytest
from robotica_ctrl.planning.parking import (
    detect_spaces, ParkingParams, ParkingSpace, ParkingVehicle, plan_parallel_parking)
from robotica_ctrl.planning.plan_result import SearchBudget
from robotica_kin.world import cast_rays, make_world


def test_the_independent_check_sees_a_collision():
    space = space_for(CAR)
    through = space.to_map([[x, -1.0, 0.0] for x in np.arange(4.0, 9.0, 0.05)])
    with pytest.raises(AssertionError, match='meets'):
        assert_swept_free(CAR, through, obstacles(space, 0.0))
    grazing = space.to_map([[x, 0.85 + 0.05, 0.0] for x in np.arange(4.0, 9.0, 0.05)])
    assert_swept_free(CAR, grazing, obstacles(space, 0.049))
    with pytest.raises(AssertionError, match='meets'):
        assert_swept_free(CAR, grazing, obstacles(space, 0.051))


CASES = {
    'car': (CAR, ParkingParams()),
    'car, slow steering': (SLOW_STEERING, ParkingParams()),
    'car, progressive': (CAR, ParkingParams(mode='progressive')),
    'robot': (ROBOT, ParkingParams()),
    'robot, progressive': (ROBOT, ParkingParams(mode='progressive', steering_rate=1.0,
                                                manoeuvre_speed=0.2, path_step=0.02)),
}


# Every case on the right; the left side is the mirror image, so two cases suffice there.
@pytest.mark.parametrize('case, side', [(case, 'right') for case in CASES]
                         + [('car', 'left'), ('robot', 'left')])
def test_a_space_of_one_and_a_half_vehicle_lengths_is_solved(case, side):
    vehicle, params = CASES[case]
    space = space_for(vehicle, side=side)
    plan = plan_parallel_parking(space, vehicle, start_for(space, vehicle), params)
    assert plan.found, plan.reason
    manoeuvres = plan.details['manoeuvres']
    parking = [m for m in manoeuvres if m.kind == 'parking']
    assert 1 <= len(parking) == plan.details['parking_manoeuvres'] <= params.max_manoeuvres
    # Reverse first, then alternating; each starts and ends parallel to the street.
    assert [m.direction for m in parking] == [(-1) ** (k + 1) for k in range(len(parking))]
    canonical = space.from_map(plan.path)
    for m in manoeuvres:
        assert abs(canonical[m.first_posture, 2]) < 1e-7
        assert abs(canonical[m.last_posture, 2]) < 1e-7
    # Collision-free with half the margin under the independent check.
    assert_swept_free(vehicle, plan.path, obstacles(space, 0.5 * space.margin + 1e-3))
    # Parked: parallel, inside the space, centred along it, at the lateral goal.
    x, y, theta = canonical[-1]
    assert abs(theta) < 1e-7
    assert x - vehicle.b1 >= space.margin - 1e-9
    assert x + vehicle.a1 <= space.length - space.margin + 1e-9
    assert x + 0.5 * (vehicle.a1 - vehicle.b1) == pytest.approx(0.5 * space.length)
    assert -space.depth + space.margin <= y - 0.5 * vehicle.c1 and y + 0.5 * vehicle.c1 <= 0.0
    goal = space.from_map(plan.details['goal'][None, :])[0]
    assert goal == pytest.approx(canonical[-1], abs=1e-9)
    # The directions say how each segment is driven; the steering stays within θ_dmax.
    step = np.diff(plan.path[:, :2], axis=0)
    along = step[:, 0] * np.cos(plan.path[:-1, 2]) + step[:, 1] * np.sin(plan.path[:-1, 2])
    assert (along * plan.directions > 0.0).all()
    assert np.abs(plan.details['steering']).max() <= vehicle.theta_dmax + 1e-12
    assert np.hypot(step[:, 0], step[:, 1]).max() <= params.path_step + 1e-12
    assert plan.cost == pytest.approx(sum(m.length for m in manoeuvres))
    # Every reversal of the direction of travel is a stop.
    cusps = np.flatnonzero(np.diff(plan.directions) != 0) + 1
    assert set(cusps) <= set(plan.details['stops'].tolist())


def test_random_vehicles_park_in_one_and_a_half_lengths():
    # Overhangs, wheelbase, width, steering limit and depth drawn at random (seeded): each
    # is parked within the bound, free under the independent check. (Offline, 80 such draws
    # took 1 to 17 manoeuvres.)
    rng = np.random.default_rng(2001)
    for mode in ('geometric', 'progressive', 'geometric'):
        scale = rng.uniform(0.2, 1.5)
        a1 = rng.uniform(2.5, 4.0) * scale
        vehicle = ParkingVehicle(a1=a1, b1=rng.uniform(0.3, 1.2) * scale,
                                 h1=rng.uniform(0.55, 0.8) * a1,
                                 c1=rng.uniform(1.4, 2.0) * scale,
                                 theta_dmax=rng.uniform(0.45, 0.75))
        space = space_for(vehicle, depth=vehicle.c1 * rng.uniform(1.25, 1.6),
                          margin=0.1 * vehicle.c1)
        params = ParkingParams(mode=mode, steering_rate=0.8 / scale)
        plan = plan_parallel_parking(space, vehicle, start_for(space, vehicle), params)
        assert plan.found, (vehicle, space, plan.reason)
        assert_swept_free(vehicle, plan.path, obstacles(space, 0.5 * space.margin + 1e-3))


def test_the_geometric_mode_stops_between_the_arcs_and_the_progressive_one_does_not():
    space = space_for(CAR)
    start = start_for(space, CAR)
    arcs = plan_parallel_parking(space, CAR, start)
    ramps = plan_parallel_parking(space, CAR, start, ParkingParams(mode='progressive'))
    first = next(m for m in arcs.details['manoeuvres'] if m.kind == 'parking')
    junction = first.first_posture + round(first.pieces[0].length / 0.05 + 0.4999)
    assert junction in arcs.details['stops'].tolist()
    steering = ramps.details['steering']
    reversing = ramps.directions[:-1] == ramps.directions[1:]
    sigma = ParkingParams().steering_per_metre
    assert np.abs(np.diff(steering))[reversing].max() <= sigma * 0.05 + 1e-9
    assert len(ramps.details['stops']) == len(np.flatnonzero(np.diff(ramps.directions))) + 1


def test_the_positioning_point_and_the_stop_point():
    space = space_for(CAR)
    for dx2 in (1.6, 2.4):
        plan = plan_parallel_parking(space, CAR, start_for(space, CAR, dx2))
        d = plan.details
        point = space.from_map(d['positioning_point'][None, :])[0]
        stop = space.from_map(d['stop_point'][None, :])[0]
        assert point == pytest.approx([space.length - space.margin, d['dx1'], 0.0])
        assert stop == pytest.approx([space.length - space.margin + d['dy3'], dx2, 0.0])
        assert d['dx1'] >= 0.5 * CAR.c1 + space.margin and d['dy3'] > 0.0
        approach = next(m for m in d['manoeuvres'] if m.kind == 'approach')
        assert space.from_map(plan.path[approach.last_posture][None, :])[0] == pytest.approx(
            point, abs=1e-9)


def test_a_space_shorter_than_the_vehicle_is_refused_with_the_reason():
    space = space_for(CAR, ratio=0.99)
    plan = plan_parallel_parking(space, CAR, start_for(space, CAR))
    assert not plan.found
    assert plan.reason == ("the space is too short: H' = H - 2 MS = 4.455 m < a1 + b1 = "
                           '4.500 m')


def test_refusals_with_their_reasons():
    space = space_for(CAR)
    narrow = space_for(CAR, depth=1.8)
    cases = [
        (narrow, start_for(narrow, CAR), ParkingParams(), 'the space is too narrow'),
        (space, start_for(space, CAR, heading=0.3), ParkingParams(), 'not parallel'),
        (space, start_for(space, CAR, dx2=0.5), ParkingParams(), 'not beside'),
        (space, start_for(space, CAR, dx2=0.9), ParkingParams(), 'the pass is too close'),
    ]
    for where, start, params, reason in cases:
        plan = plan_parallel_parking(where, CAR, start, params)
        assert not plan.found and reason in plan.reason, plan.reason


def test_the_bounds_are_reported_when_hit():
    space = space_for(SLOW_STEERING)
    start = start_for(space, SLOW_STEERING)
    plan = plan_parallel_parking(space, SLOW_STEERING, start, ParkingParams(max_manoeuvres=3))
    assert not plan.found
    assert plan.reason.startswith('the bound of 3 manoeuvres was hit with')
    assert len([m for m in plan.details['manoeuvres'] if m.kind == 'parking']) == 3
    plan = plan_parallel_parking(space, SLOW_STEERING, start,
                                 budget=SearchBudget(max_expansions=200))
    assert not plan.found and 'search budget was exhausted: 2' in plan.reason
    ticks = itertools.count()
    plan = plan_parallel_parking(space, SLOW_STEERING, start,
                                 budget=SearchBudget(max_seconds=2.0),
                                 clock=lambda: float(next(ticks)))
    assert not plan.found and 'more than the 2 s allowed' in plan.reason


def test_an_obstacle_of_the_world_on_the_way_is_reported():
    space = space_for(CAR)
    world = space.obstacle_world()
    lamp = on_map(space, [[8.0, 2.0], [8.3, 2.0], [8.3, 2.3], [8.0, 2.3]])
    blocked = make_world(walls=world.walls, polygons=[*world.polygons, lamp])
    plan = plan_parallel_parking(space, CAR, start_for(space, CAR), world=blocked)
    assert not plan.found
    assert plan.reason.startswith('the pass manoeuvre meets an obstacle of the world near')


def test_bad_input_raises():
    space = space_for(CAR)
    with pytest.raises(ValueError, match='start'):
        plan_parallel_parking(space, CAR, (0.0, 1.0))
    with pytest.raises(ValueError, match='start'):
        plan_parallel_parking(space, CAR, (0.0, math.nan, 0.0))
    with pytest.raises(ValueError, match='space'):
        plan_parallel_parking('space', CAR, (0.0, 1.0, 0.0))
    with pytest.raises(ValueError, match='exceeds theta_dmax'):
        plan_parallel_parking(space, CAR, (0.0, 1.0, 0.0), ParkingParams(steering=0.7))
    with pytest.raises(ValueError, match='mode'):
        ParkingParams(mode='teleport')
    with pytest.raises(ValueError, match='max_manoeuvres'):
        ParkingParams(max_manoeuvres=0)
    with pytest.raises(ValueError, match='margin'):
        ParkingSpace(ORIGIN, 7.0, 2.2, 'right', -0.1)
    with pytest.raises(ValueError, match='side'):
        ParkingSpace(ORIGIN, 7.0, 2.2, 'up')


def test_detect_then_park_in_the_world_that_was_sensed():
    # Two parked cars 1.8 m deep, a gap of 1.5 (a1 + b1) + 2 MS = 7.15 m, the curb at 2.2 m.
    truth = space_for(CAR)
    world = make_world(walls=on_map(truth, [[-30.0, -2.2], [40.0, -2.2]]).reshape(1, 4),
                       polygons=[on_map(truth, [[x0, -1.8], [x1, -1.8], [x1, 0.0], [x0, 0.0]])
                                 for x0, x1 in ((-4.5, 0.0), (7.15, 11.65))])
    along = np.arange(-8.0, 14.0, 0.05)
    poses = truth.to_map(np.column_stack([along, np.full_like(along, 1.5), 0 * along]))
    mount = (0.0, -0.85, -0.5 * math.pi)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    sensors = poses[:, :2] + np.column_stack([0.85 * s, -0.85 * c])
    ranges = cast_rays(world, sensors, poses[:, 2] - 0.5 * math.pi, 5.0).ranges
    sensed = detect_spaces(poses, ranges, mount, 0.05, 5.0)
    assert len(sensed) == 1
    space = sensed[0].space
    assert 7.15 - 0.1 <= space.length <= 7.15 and space.depth == pytest.approx(2.2)
    plan = plan_parallel_parking(space, CAR, poses[0], world=world)
    assert plan.found, plan.reason
    rectangles = [np.asarray(p) for p in world.polygons]
    curb = on_map(truth, [[-30.0, -3.2], [40.0, -3.2], [40.0, -2.2], [-30.0, -2.2]])
    assert_swept_free(CAR, plan.path, rectangles + [curb])
