"""
Tests of a vehicle's contact with the world (robotica_sim.simulation.contact and vehicle).

Closed forms, computed here: a circle of radius r driven along x at v towards a wall at x = d
stops with its centre at d - r (exact: the circle's step is a ray cast), a polygon within the
swept tolerance (1e-4 m); a rectangle of half-length a and half-width b turning in place
towards a wall y = h first touches it with its corner (a, b), whose height is
sqrt(a² + b²) sin(θ + atan2(b, a)), at θ = asin(h / sqrt(a² + b²)) - atan2(b, a).
"""
import math

import numpy as np
import pytest

from robotica_kin.bounds import MAX_SPEED
from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
from robotica_kin.world.shapes import box_polygon, World
from robotica_sim.simulation.contact import (CONTACT_DISTANCE, footprint_from_parameters,
                                             step_fraction)
from robotica_sim.simulation.vehicle import (vehicle_simulation, VehicleSimulation,
                                             VehicleSimulationParams)

C, B = 0.1, 0.4   # wheel radius c [m], track b [m]
ROBOT = vehicle_kinematics('differential', VehicleGeometry(wheel_radius=C, track=B))
DT = 0.02         # [s]
SWEPT = 1e-4      # [m] the polygon's contact tolerance
SQUARE = np.array([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]])


def wall_at(x):
    """Return a world with one vertical wall at ``x`` [m], y in [-5, 5]."""
    return World(walls=[[x, -5.0, x, 5.0]])


def simulation(world, footprint, pose=(0.0, 0.0, 0.0)):
    return VehicleSimulation(ROBOT, VehicleSimulationParams(DT, 1, 1e3), pose, world, footprint)


def drive(sim, v, w, steps):
    sim.set_command((v, 0.0, w), t=sim.t)
    for _ in range(steps):
        sim.step()
    return sim


def test_a_circle_driving_at_a_wall_stops_at_d_minus_r_and_stays():
    d, r, v = 2.005, 0.3, 1.0
    sim = drive(simulation(wall_at(d), r), v, 0.0, 200)
    # Contact at x = 1.705 m, in step 86 (1.70 -> 1.72 m); steps 87..200 begin in contact.
    assert sim.pose == pytest.approx([d - r, 0.0, 0.0], abs=1e-12)
    assert sim.twist == (0.0, 0.0, 0.0) and sim.wheel_rates == (0.0, 0.0)
    assert sim.wheel_angles == pytest.approx([(d - r) / C] * 2, abs=1e-9)
    assert sim.in_contact and sim.contacts == 1
    assert sim.time_in_contact == pytest.approx(114 * DT, abs=1e-9)
    assert sim.contact_point == pytest.approx([d, 0.0], abs=1e-9)
    assert sim.contact_normal == pytest.approx([-1.0, 0.0], abs=1e-9)


def test_backing_away_frees_the_robot_and_a_new_touch_is_a_new_contact():
    sim = drive(simulation(wall_at(2.005), 0.3), 1.0, 0.0, 100)
    drive(sim, -0.5, 0.0, 1)
    assert sim.pose[0] == pytest.approx(1.705 - 0.5 * DT, abs=1e-12)
    assert not sim.in_contact and sim.contacts == 1
    assert np.isnan(sim.contact_point).all()
    drive(sim, 0.5, 0.0, 10)
    assert sim.pose[0] == pytest.approx(1.705, abs=1e-12) and sim.contacts == 2


@pytest.mark.parametrize('footprint, stop', [(0.1, 0.995 - 0.1), (SQUARE, 0.995 - 0.1)])
def test_no_tunnelling_through_a_1_cm_wall_at_max_speed_in_one_step(footprint, stop):
    world = World(polygons=(box_polygon([1.0, 0.0], [0.01, 2.0]),))   # x in [0.995, 1.005]
    sim = drive(simulation(world, footprint), MAX_SPEED, 0.0, 1)    # 2 m in one step
    assert stop - SWEPT <= sim.pose[0] <= stop
    assert sim.in_contact and sim.contacts == 1 and sim.twist == (0.0, 0.0, 0.0)


def test_a_rectangle_turning_in_place_stops_when_its_corner_touches_the_wall():
    a, b, h = 0.5, 0.1, 0.3
    rectangle = [[-a, -b], [a, -b], [a, b], [-a, b]]
    sim = drive(simulation(World(walls=[[-2.0, h, 2.0, h]]), rectangle), 0.0, 1.0, 50)
    touch = math.asin(h / math.hypot(a, b)) - math.atan2(b, a)   # 0.43154 rad
    assert sim.pose[:2].tolist() == [0.0, 0.0]
    assert touch - 5e-4 <= sim.pose[2] <= touch   # within SWEPT of the wall, never past
    assert sim.in_contact and sim.contacts == 1
    assert sim.contact_point[1] == pytest.approx(h) and sim.contact_normal[1] == pytest.approx(
        -1.0)
    drive(sim, 0.0, -1.0, 1)   # turning away frees it
    assert sim.pose[2] == pytest.approx(touch - DT, abs=5e-4) and not sim.in_contact


def test_turning_in_place_against_a_wall_is_free_for_a_circle():
    sim = drive(simulation(wall_at(1.0), 0.3), 1.0, 0.0, 50)
    drive(sim, 0.0, 2.0, 10)
    assert sim.pose == pytest.approx([0.7, 0.0, 20 * DT], abs=1e-12) and sim.in_contact


def test_the_default_footprint_is_the_outline_the_viewer_draws():
    # The differential outline's nose is one wheel radius ahead of the wheels: x = 0.2 m.
    sim = vehicle_simulation({'cmd_timeout': 60.0}, DT, world=wall_at(1.0))
    drive(sim, 1.0, 0.0, 50)
    assert 0.8 - SWEPT <= sim.pose[0] <= 0.8 and sim.contacts == 1


def test_without_a_world_nothing_changes():
    free = drive(VehicleSimulation(ROBOT, VehicleSimulationParams(DT, 1, 1e3)), 1.0, 0.5, 50)
    far = drive(simulation(wall_at(100.0), 0.3), 1.0, 0.5, 50)
    assert far.pose.tolist() == free.pose.tolist() and far.contacts == free.contacts == 0


def test_a_robot_starting_inside_an_obstacle_is_refused_naming_initial_pose():
    with pytest.raises(ValueError, match='initial_pose'):
        vehicle_simulation({'initial_pose.x': 0.9, 'footprint.radius': 0.3}, DT,
                           world=wall_at(1.0))


def test_a_robot_starting_against_a_wall_starts_in_contact():
    sim = simulation(wall_at(1.0), 0.3, (0.7 - CONTACT_DISTANCE / 2, 0.0, 0.0))
    assert sim.in_contact and sim.contacts == 1
    drive(sim, 1.0, 0.0, 5)
    assert sim.pose[0] == pytest.approx(0.7 - CONTACT_DISTANCE / 2) and sim.contacts == 1


@pytest.mark.parametrize('radius, polygon, field', [
    (0.3, [0, 0, 1, 0, 0, 1], 'footprint.radius'),
    (0.0, [0, 0, 1, 0, 0], 'footprint.polygon'),
    (0.0, [0, 0, 1, 0], 'footprint.polygon'),
    (0.0, [0, 0, 1, 1, 1, 0, 0, 1], 'footprint.polygon'),   # self-intersecting
])
def test_a_bad_footprint_names_its_parameter(radius, polygon, field):
    with pytest.raises(ValueError, match=field.replace('.', r'\.')):
        footprint_from_parameters('differential', VehicleGeometry(), radius, polygon)


def test_a_step_that_stays_still_against_a_wall_is_free():
    assert step_fraction(wall_at(1.0), 0.5, [0.5, 0.0, 0.0], [0.5, 0.0, 0.0]) is None
