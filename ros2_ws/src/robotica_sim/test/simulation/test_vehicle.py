"""
Tests of robotica_sim.simulation.vehicle against closed forms (catalog §2.8, book §4.7.4).

With a constant twist (v, w) the model (4.113)-(4.114) in REP-103 form has the exact solution
theta = theta0 + w t and, for w != 0, the arc x = x0 + (v/w)(sin(theta0 + w t) - sin theta0),
y = y0 - (v/w)(cos(theta0 + w t) - cos theta0); the wheels turn at (4.111)-(4.112)
w_left = (v - w b/2)/c, w_right = (v + w b/2)/c. The bicycle model (4.121) at constant (v, α)
drives a circle of radius l / tan α; a first-order lag gives v(t) = v*(1 - exp(-t/τ)). All
expected values are computed here.
"""
import math

import numpy as np
import pytest

from robotica_kin.mobile.vehicles import vehicle_kinematics, VEHICLE_TYPES, VehicleGeometry
from robotica_sim.simulation.vehicle import VehicleSimulation, VehicleSimulationParams

C, B, L = 0.1, 0.4, 0.5   # wheel radius c [m], track b [m], wheelbase l [m]
GEOMETRY = VehicleGeometry(wheel_radius=C, track=B, wheelbase=L)
ROBOT = vehicle_kinematics('differential', GEOMETRY)
LONG_TIMEOUT = 1e3   # [s] so that a single command stays fresh for the whole run


def wrap(angle):
    """Return ``angle`` [rad] wrapped to (-pi, pi], computed independently of the module."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped


def run(v, w, steps, *, step_period=0.02, substeps=1, initial_pose=(0.0, 0.0, 0.0)):
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(step_period, substeps, LONG_TIMEOUT),
                            initial_pose)
    sim.set_command((v, 0.0, w), t=0.0)
    for _ in range(steps):
        sim.step()
    return sim


@pytest.mark.parametrize('theta0', [0.0, 2.0, -2.5])
@pytest.mark.parametrize('v', [0.4, -0.25])
def test_straight_line(v, theta0):
    sim = run(v, 0.0, 250, initial_pose=(1.0, -2.0, theta0))
    t = 250 * 0.02
    assert sim.t == pytest.approx(t, rel=1e-12)
    assert sim.step_count == 250
    x, y, theta = sim.pose
    assert x == pytest.approx(1.0 + v * t * math.cos(theta0), abs=1e-9)
    assert y == pytest.approx(-2.0 + v * t * math.sin(theta0), abs=1e-9)
    assert theta == pytest.approx(theta0, abs=1e-12)
    assert sim.twist == pytest.approx((v, 0.0, 0.0), abs=1e-12)


@pytest.mark.parametrize('w', [1.3, -0.7])
def test_spin_in_place(w):
    sim = run(0.0, w, 100, step_period=0.05, initial_pose=(0.5, 0.25, 0.0))
    t = 100 * 0.05
    x, y, theta = sim.pose
    assert (x, y) == pytest.approx((0.5, 0.25), abs=1e-12)
    assert -math.pi < theta <= math.pi
    assert theta == pytest.approx(wrap(w * t), abs=1e-9)
    if w == 1.3:
        assert theta == pytest.approx(6.5 - 2.0 * math.pi, abs=1e-9)  # 6.5 rad: one turn more
    assert sim.twist == pytest.approx((0.0, 0.0, w), abs=1e-12)


@pytest.mark.parametrize('substeps', [1, 10])
@pytest.mark.parametrize('v, w, theta0', [
    (0.5, 0.8, 0.0),
    (0.3, -1.0, 2.0),
    (-0.4, 0.6, -2.5),
    (0.5, 1.0, 1.0),
])
def test_exact_arc(v, w, theta0, substeps):
    x0, y0 = 1.0, -2.0
    sim = run(v, w, 500, substeps=substeps, initial_pose=(x0, y0, theta0))
    t = 500 * 0.02
    x, y, theta = sim.pose
    assert x == pytest.approx(x0 + v / w * (math.sin(theta0 + w * t) - math.sin(theta0)),
                              abs=1e-9)
    assert y == pytest.approx(y0 - v / w * (math.cos(theta0 + w * t) - math.cos(theta0)),
                              abs=1e-9)
    assert theta == pytest.approx(wrap(theta0 + w * t), abs=1e-9)


def test_exact_arc_from_the_origin():
    # The textbook form: x = (v/w) sin wt, y = (v/w)(1 - cos wt), a circle of radius v/w.
    v, w = 0.5, 0.8
    sim = run(v, w, 300, substeps=1)
    t = 300 * 0.02
    x, y, _ = sim.pose
    assert x == pytest.approx(v / w * math.sin(w * t), abs=1e-9)
    assert y == pytest.approx(v / w * (1.0 - math.cos(w * t)), abs=1e-9)
    assert math.hypot(x, y - v / w) == pytest.approx(v / w, abs=1e-9)


@pytest.mark.parametrize('substeps', [1, 10])
@pytest.mark.parametrize('v, w', [(0.5, 0.0), (0.0, 1.3), (0.3, -1.0), (-0.4, 0.6)])
def test_wheel_angles_integrate_the_wheel_speeds(v, w, substeps):
    sim = run(v, w, 200, substeps=substeps)
    t = 200 * 0.02
    left, right = (v - w * B / 2.0) / C, (v + w * B / 2.0) / C   # (4.111)-(4.112)
    assert sim.wheel_rates == pytest.approx((left, right), abs=1e-12)
    assert sim.wheel_angles == pytest.approx([left * t, right * t], abs=1e-9)
    assert sim.twist == pytest.approx((v, 0.0, w), abs=1e-12)


def test_wheel_angles_are_cumulative_not_wrapped():
    sim = run(0.0, 2.0, 250)  # 5 s at 2 rad/s: the wheels turn at -+(2 b/2)/c = -+4 rad/s
    assert sim.wheel_angles == pytest.approx([-20.0, 20.0], abs=1e-9)   # over three turns


def test_no_command_means_no_motion():
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(), (0.3, 0.2, 0.1))
    assert sim.command_is_stale()
    for _ in range(10):
        sim.step()
    assert sim.pose == pytest.approx([0.3, 0.2, 0.1], rel=0.0, abs=1e-15)
    np.testing.assert_array_equal(sim.wheel_angles, [0.0, 0.0])
    assert sim.twist == (0.0, 0.0, 0.0)


@pytest.mark.parametrize('cmd_timeout, moving_steps', [
    (0.5, 6),    # steps at t = 0.0 .. 0.5 s: t - t_cmd <= 0.5 s
    (0.45, 5),   # steps at t = 0.0 .. 0.4 s
    (0.05, 1),   # only the step at t = 0
])
def test_stale_command_brakes(cmd_timeout, moving_steps):
    v, w, dt = 0.5, 0.2, 0.1
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(step_period=dt,
                                                           cmd_timeout=cmd_timeout))
    sim.set_command((v, 0.0, w), t=0.0)
    for k in range(12):
        moving = k < moving_steps
        assert sim.command_is_stale() == (not moving), f'step {k} at t = {sim.t} s'
        sim.step()
        # The pose after this step is the exact arc over min(k + 1, moving_steps) steps.
        t_moved = min(k + 1, moving_steps) * dt
        expected = [v / w * math.sin(w * t_moved), v / w * (1.0 - math.cos(w * t_moved)),
                    w * t_moved]
        assert sim.pose == pytest.approx(expected, abs=1e-9), f'after step {k}'
        if moving:
            assert sim.twist == pytest.approx((v, 0.0, w), abs=1e-12)
        else:
            assert sim.twist == (0.0, 0.0, 0.0)
            assert sim.wheel_rates == (0.0, 0.0)
    left, right = (v - w * B / 2.0) / C, (v + w * B / 2.0) / C
    t_moved = moving_steps * dt
    assert sim.wheel_angles == pytest.approx([left * t_moved, right * t_moved], abs=1e-9)


def test_fresh_command_after_a_stale_period_moves_again():
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(step_period=0.1, cmd_timeout=0.5))
    sim.set_command((0.5, 0.0, 0.0), t=0.0)
    for _ in range(10):
        sim.step()
    assert sim.command_is_stale()
    assert sim.pose[0] == pytest.approx(0.3, abs=1e-12)   # 6 moving steps of 0.05 m
    sim.set_command((0.2, 0.0, 0.0), t=sim.t)
    assert not sim.command_is_stale()
    for _ in range(3):
        sim.step()
    assert sim.pose == pytest.approx([0.3 + 0.2 * 0.3, 0.0, 0.0], abs=1e-12)
    assert sim.twist == pytest.approx((0.2, 0.0, 0.0), abs=1e-12)


@pytest.mark.parametrize('v, w', [(math.nan, 0.0), (0.0, math.nan), (math.inf, 0.0),
                                  (0.0, -math.inf)])
def test_non_finite_command_is_refused_and_keeps_the_previous_one(v, w):
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(step_period=0.1, cmd_timeout=0.5))
    sim.set_command((0.5, 0.0, 0.0), t=0.0)
    for _ in range(4):
        sim.step()
    with pytest.raises(ValueError, match='finite'):
        sim.set_command((v, 0.0, w), t=sim.t)   # at t = 0.4 s
    # Still the first command, with its own time stamp: it moves 2 more steps (t = 0.4, 0.5 s)
    # and then brakes, as if the refused command had never arrived.
    for _ in range(6):
        sim.step()
    assert sim.pose == pytest.approx([0.3, 0.0, 0.0], abs=1e-12)
    assert sim.command_is_stale()


@pytest.mark.parametrize('vehicle, command', [
    ('differential', (1e308, 0.0, 0.0)),      # the Twist: wheel speeds overflowed to inf
    ('differential', (0.0, 0.0, -1e3)),
    ('omni_three', (0.0, 101.0, 0.0)),
    ('tricycle', (1e308, 0.3, 0.0)),          # the VehicleCommand: "math domain error"
    ('ackermann', (-1e200, 0.0, 0.0)),
])
def test_a_command_beyond_the_physical_bounds_is_refused_and_stop_brakes(vehicle, command):
    # Bounds of robotica_kin.bounds: 100 m/s, 100 rad/s.
    sim = VehicleSimulation(vehicle_kinematics(vehicle, VehicleGeometry()),
                            VehicleSimulationParams(step_period=0.1, cmd_timeout=5.0))
    sim.set_command((0.5, 0.0, 0.0), t=0.0)
    sim.step()
    with pytest.raises(ValueError, match='must be <= 100.0'):
        sim.set_command(command, t=sim.t)
    sim.stop()
    assert sim.command_is_stale()
    pose = sim.pose.copy()
    sim.step()
    assert np.isfinite(sim.pose).all() and sim.twist[0] == 0.0
    assert sim.pose[:2] == pytest.approx(pose[:2], abs=1e-12)


@pytest.mark.parametrize('initial_pose', [
    (0.0, 0.0),
    (0.0, 0.0, 0.0, 0.0),
    [[0.0, 0.0, 0.0]],
    (math.nan, 0.0, 0.0),
    (0.0, math.inf, 0.0),
    (0.0, 0.0, -math.inf),
])
def test_bad_initial_pose_is_refused(initial_pose):
    with pytest.raises(ValueError, match='initial_pose'):
        VehicleSimulation(ROBOT, VehicleSimulationParams(), initial_pose)


@pytest.mark.parametrize('initial_pose', [(1.0, -2.0, 3.0), [1.0, -2.0, 3.0],
                                          np.array([1.0, -2.0, 3.0])])
def test_initial_pose_is_taken(initial_pose):
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(), initial_pose)
    assert sim.pose == pytest.approx([1.0, -2.0, 3.0], rel=0.0, abs=1e-15)
    assert sim.t == 0.0 and sim.step_count == 0


def test_initial_heading_is_reported_wrapped():
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(), (0.0, 0.0, 4.0))
    assert sim.pose[2] == pytest.approx(4.0 - 2.0 * math.pi, abs=1e-12)


@pytest.mark.parametrize('kwargs, key', [
    ({'step_period': 0.0}, 'step_period'),
    ({'step_period': -0.02}, 'step_period'),
    ({'step_period': math.nan}, 'step_period'),
    ({'step_period': math.inf}, 'step_period'),
    ({'rk4_substeps': 0}, 'rk4_substeps'),
    ({'rk4_substeps': -1}, 'rk4_substeps'),
    ({'cmd_timeout': 0.0}, 'cmd_timeout'),
    ({'cmd_timeout': -0.5}, 'cmd_timeout'),
    ({'cmd_timeout': math.nan}, 'cmd_timeout'),
    ({'cmd_timeout': math.inf}, 'cmd_timeout'),
])
def test_bad_simulation_params_are_refused(kwargs, key):
    with pytest.raises(ValueError, match=key):
        VehicleSimulationParams(**kwargs)


def test_time_advances_by_the_step_period():
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(step_period=0.25))
    for _ in range(7):
        sim.step()
    assert sim.step_count == 7
    assert sim.t == pytest.approx(1.75, abs=1e-12)


def steered(vehicle_type='bicycle', **params):
    kinematics = vehicle_kinematics(vehicle_type, GEOMETRY)
    return VehicleSimulation(kinematics, VehicleSimulationParams(cmd_timeout=LONG_TIMEOUT,
                                                                 **params))


@pytest.mark.parametrize('vehicle_type', ['tricycle', 'bicycle', 'ackermann'])
@pytest.mark.parametrize('v, alpha', [(0.5, 0.3), (0.8, -0.6), (-0.4, 0.2)])
def test_steered_vehicle_drives_the_circle_of_radius_l_over_tan_alpha(vehicle_type, v, alpha):
    sim = steered(vehicle_type)
    sim.set_command((v, alpha, 0.0), t=0.0)
    for _ in range(400):
        sim.step()
    t = 400 * 0.02
    w = v * math.tan(alpha) / L                    # (4.121): θ' = v tan α / l
    x, y, theta = sim.pose
    assert x == pytest.approx(v / w * math.sin(w * t), abs=1e-8)
    assert y == pytest.approx(v / w * (1.0 - math.cos(w * t)), abs=1e-8)
    assert theta == pytest.approx(wrap(w * t), abs=1e-9)
    # The passive rear wheels roll at (v -+ w b/2)/c.
    assert sim.wheel_angles == pytest.approx([(v - w * B / 2) / C * t, (v + w * B / 2) / C * t],
                                             abs=1e-8)


def test_steering_is_clamped_to_its_limit():
    sim = steered('bicycle')
    sim.set_command((1.0, 3.0, 0.0), t=0.0)
    assert sim.actuators == pytest.approx([0.0, 0.0])   # targets apply at the next step
    sim.step()
    assert sim.actuators[1] == pytest.approx(GEOMETRY.max_steering_angle)


def test_ackermann_publishes_both_front_wheel_angles():
    sim = steered('ackermann')
    sim.set_command((1.0, 0.3, 0.0), t=0.0)
    sim.step()
    angles = sim.joint_positions()
    left, right = angles['front_left_steering_joint'], angles['front_right_steering_joint']
    # Left turn: the left wheel is inner (steers more); both wheels' axes meet at the ICR,
    # which lies on the rear axle at y = l / tan α (independent geometry).
    radius = L / math.tan(0.3)
    assert math.tan(left) == pytest.approx(L / (radius - B / 2), rel=1e-9)
    assert math.tan(right) == pytest.approx(L / (radius + B / 2), rel=1e-9)


@pytest.mark.parametrize('tau', [0.1, 0.5])
def test_traction_lag_is_first_order(tau):
    v = 0.6
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(
        step_period=0.01, cmd_timeout=LONG_TIMEOUT, traction_time_constant=tau))
    sim.set_command((v, 0.0, 0.0), t=0.0)
    for _ in range(150):
        sim.step()
    t = 1.5
    assert sim.twist[0] == pytest.approx(v * (1.0 - math.exp(-t / tau)), rel=1e-7)
    distance = v * (t - tau * (1.0 - math.exp(-t / tau)))   # ∫ v(1 - e^(-s/τ)) ds
    assert sim.pose[0] == pytest.approx(distance, rel=1e-7)


def test_steering_lag_is_first_order_and_traction_instant():
    sim = steered('bicycle', step_period=0.01, steering_time_constant=0.2)
    sim.set_command((0.5, 0.4, 0.0), t=0.0)
    for _ in range(30):
        sim.step()
    assert sim.actuators[0] == 0.5
    assert sim.actuators[1] == pytest.approx(0.4 * (1.0 - math.exp(-0.3 / 0.2)), rel=1e-7)


def test_slip_moves_the_ground_less_than_the_wheels_roll():
    sim = VehicleSimulation(ROBOT, VehicleSimulationParams(cmd_timeout=LONG_TIMEOUT,
                                                           longitudinal_slip=0.1))
    sim.set_command((0.5, 0.0, 0.0), t=0.0)
    for _ in range(100):
        sim.step()
    assert sim.pose[0] == pytest.approx(0.9 * 0.5 * 2.0, abs=1e-12)
    assert sim.wheel_angles == pytest.approx([0.5 * 2.0 / C] * 2, abs=1e-9)


def test_stale_command_stops_a_steered_vehicle_keeping_its_steering():
    sim = VehicleSimulation(vehicle_kinematics('tricycle', GEOMETRY),
                            VehicleSimulationParams(step_period=0.1, cmd_timeout=0.2))
    sim.set_command((1.0, 0.5, 0.0), t=0.0)
    for _ in range(6):
        sim.step()
    assert sim.command_is_stale()
    pose = sim.pose
    sim.step()
    assert sim.actuators == pytest.approx([0.0, 0.5])
    assert sim.pose == pytest.approx(pose, abs=1e-15)


@pytest.mark.parametrize('vehicle_type', ['omni_three', 'mecanum'])
def test_holonomic_bases_translate_sideways(vehicle_type):
    sim = VehicleSimulation(vehicle_kinematics(vehicle_type, GEOMETRY),
                            VehicleSimulationParams(cmd_timeout=LONG_TIMEOUT),
                            (1.0, 2.0, math.pi / 2))
    sim.set_command((0.0, 0.3, 0.0), t=0.0)     # 0.3 m/s to the robot's left
    for _ in range(50):
        sim.step()
    # Facing +y, the robot's left is -x in the world: 1 s at 0.3 m/s.
    assert sim.pose == pytest.approx([0.7, 2.0, math.pi / 2], abs=1e-9)
    assert sim.twist == pytest.approx((0.0, 0.3, 0.0), abs=1e-12)


@pytest.mark.parametrize('vehicle_type', VEHICLE_TYPES)
def test_every_vehicle_type_drives_forward(vehicle_type):
    sim = VehicleSimulation(vehicle_kinematics(vehicle_type, GEOMETRY),
                            VehicleSimulationParams(cmd_timeout=LONG_TIMEOUT))
    command = (0.4, 0.0, 0.0)
    sim.set_command(command, t=0.0)
    for _ in range(50):
        sim.step()
    assert sim.pose == pytest.approx([0.4, 0.0, 0.0], abs=1e-9)


@pytest.mark.parametrize('kwargs, key', [
    ({'traction_time_constant': -0.1}, 'traction_time_constant'),
    ({'steering_time_constant': math.nan}, 'steering_time_constant'),
    ({'longitudinal_slip': 1.0}, 'longitudinal_slip'),
    ({'longitudinal_slip': -0.1}, 'longitudinal_slip'),
])
def test_bad_actuator_params_are_refused(kwargs, key):
    with pytest.raises(ValueError, match=key):
        VehicleSimulationParams(**kwargs)
