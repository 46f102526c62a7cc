"""
ReversingPurePursuit drives a parallel-parking plan on the kinematic car, forward and reverse.

The plan is the course's planner's (H' = 1.5 (a1 + b1), geometric mode: arcs with stops). The
vehicle is simulated here, independently of the law: the bicycle model of its rear-axle midpoint
x' = v cos θ, y' = v sin θ, θ' = v tan φ / h1 (book (4.119)), the steering φ = atan(h1 ω / v)
of the law's (v, ω) clamped at θ_dmax, Euler steps of 10 ms. The car must end where the plan
ends and never touch the parked cars or the curb (the body swept step by step, separating-axis
test of the planner's own test file, with the rectangles not grown).
"""
import math

import numpy as np
from parking_reference import assert_swept_free, CAR, obstacles, space_for, start_for
import pytest
from robotica_ctrl.mobile.pure_pursuit import PurePursuitParams
from robotica_ctrl.mobile.reversing_pure_pursuit import motion_directions, ReversingPurePursuit
from robotica_ctrl.planning.parking import plan_parallel_parking

# The arcs are at the sharpest steering (ρ_min): pure pursuit's chord needs the whole steering
# range, so a piece ends within 0.2 m of its cusp rather than on it (measured: the car parks
# 0.198 m from the plan's end, 0.063 rad off its heading; 0.050 m, 0.037 rad with a
# goal_tolerance of 0.05 m).
PARAMS = PurePursuitParams(lookahead_distance=0.8, desired_linear_velocity=0.5,
                           max_angular_velocity=1.5, goal_tolerance=0.2,
                           approach_distance=0.4, min_approach_velocity=0.05)


def drive(law, start, wheelbase, max_steering, dt=0.01, limit=120.0):
    """Return the poses of the car driven by ``law`` from ``start`` until it finishes."""
    pose = np.array(start, dtype=float)
    poses, t = [pose.copy()], 0.0
    while t < limit:
        out = law.update(pose, t)
        if out.finished and out.linear == 0.0:
            break
        v = out.linear
        phi = 0.0 if v == 0.0 else math.atan(wheelbase * out.angular / v)
        phi = max(-max_steering, min(max_steering, phi))
        pose = pose + dt * np.array([v * math.cos(pose[2]), v * math.sin(pose[2]),
                                     v * math.tan(phi) / wheelbase])
        poses.append(pose.copy())
        t += dt
    return np.array(poses), t


def test_directions_of_a_path_with_cusps():
    poses = [[0, 0, 0], [1, 0, 0], [0.5, 0, 0], [0.5, 0, 0], [1.5, 0, 0]]
    assert motion_directions(poses).tolist() == [1, -1, -1, 1]
    with pytest.raises(ValueError):
        motion_directions([[0, 0, 0]])


def test_a_parking_plan_is_driven_into_the_space_without_contact():
    space = space_for(CAR)
    plan = plan_parallel_parking(space, CAR, start_for(space, CAR))
    assert plan.found, plan.reason
    law = ReversingPurePursuit(plan.path, PARAMS)
    assert law.pieces == len(np.flatnonzero(np.diff(plan.directions))) + 1
    poses, t = drive(law, plan.path[0], CAR.h1, CAR.theta_dmax)
    assert law.piece == law.pieces - 1 and t < 120.0
    end, goal = poses[-1], plan.path[-1]
    assert math.hypot(*(end[:2] - goal[:2])) < 0.25
    assert abs(math.remainder(end[2] - goal[2], 2.0 * math.pi)) < 0.1
    assert_swept_free(CAR, poses[::5], obstacles(space, 0.0))
    assert (np.diff(poses[:, :2], axis=0) != 0.0).any()   # it moved, in reverse too:
    backwards = [d for d, p, q in zip(poses[:-1, 2], poses[:-1, :2], poses[1:, :2])
                 if (q - p) @ (math.cos(d), math.sin(d)) < -1e-9]
    assert backwards
