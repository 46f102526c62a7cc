"""
Tests of the parking manoeuvre's arcs (catalogue §14.2, §14.5): (A) and the corner geometry.

References are computed here, independent of the code under test: the end of two arcs by
SciPy's solve_ivp on the bicycle model x' = v cos θ, y' = v sin θ, θ' = v tan φ / L (book
(4.121)), and the corners by placing the vehicle's rectangle on its circle about the ICR.
"""

import math

import numpy as np
import pytest
from robotica_ctrl.planning.parking.manoeuvre_arcs import (
    arc_extreme, corner_distances, corner_positions, two_arc_centres, two_arc_displacement)
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from scipy.integrate import solve_ivp

CAR = ParkingVehicle()                                        # a1 3.6, b1 0.9, h1 2.6, c1 1.7
ROBOT = ParkingVehicle(a1=0.45, b1=0.1, h1=0.35, c1=0.3, theta_dmax=0.5, d1=0.28, r=0.05)
WIDE = ParkingVehicle(a1=1.5, b1=1.0, h1=0.5, c1=2.0, theta_dmax=1.2)   # ρ_min < c1/2


def bicycle(steering, speed, wheelbase):
    """Return the bicycle model's right-hand side for a constant steering and speed."""
    def rhs(_, state):
        return [speed * math.cos(state[2]), speed * math.sin(state[2]),
                speed * math.tan(steering) / wheelbase]
    return rhs


def integrate_two_arcs(vehicle, steering, xi, direction):
    """Return the poses after the first and the second arc (right, then left), by solve_ivp."""
    rho = vehicle.h1 / math.tan(steering)
    duration = rho * xi                     # |v| = 1 m/s
    state = np.zeros(3)
    ends = []
    for phi in (-steering, steering):
        sol = solve_ivp(bicycle(phi, float(direction), vehicle.h1), (0.0, duration), state,
                        rtol=1e-11, atol=1e-12)
        state = sol.y[:, -1]
        ends.append(state)
    return ends


@pytest.mark.parametrize('vehicle', [CAR, ROBOT, WIDE])
@pytest.mark.parametrize('direction', [-1, 1])
@pytest.mark.parametrize('fraction', [0.1, 0.5, 1.0])
@pytest.mark.parametrize('xi', [0.05, 0.4, 0.9, math.pi / 2])
def test_equations_a_against_the_integrated_bicycle_model(vehicle, direction, fraction, xi):
    steering = fraction * vehicle.theta_dmax
    rho = vehicle.h1 / math.tan(steering)
    middle, end = integrate_two_arcs(vehicle, steering, xi, direction)
    x, y, z = two_arc_displacement(rho, xi)
    # Parallel again, shifted X to the right (-y) and Y along the direction of motion.
    assert end[2] == pytest.approx(0.0, abs=1e-8)
    assert -end[1] == pytest.approx(x, abs=1e-8 * max(1.0, rho))
    assert direction * end[0] == pytest.approx(y, abs=1e-8 * max(1.0, rho))
    # Z: the second ICR is ρ to the left of P_f at the end of the first arc.
    centre_y = middle[1] + rho * math.cos(middle[2])
    assert -centre_y == pytest.approx(z, abs=1e-8 * max(1.0, rho))
    first, second = two_arc_centres(rho, xi, direction)
    assert first[0] == pytest.approx([0.0, -rho])
    assert second[0][1] == pytest.approx(centre_y, abs=1e-8 * max(1.0, rho))


def placed_corners(vehicle, rho, theta):
    """
    Return P1..P4 (4, 2) of the rectangle placed with P_f at polar angle θ about the ICR.

    The ICR is the origin; the vehicle drives counter-clockwise about it (its front towards
    increasing θ), so its heading is θ + π/2 and the ICR lies on its left: the outer side is
    its right. Body corners (x forward, y left): P1 rear-outer (-b1, -c1/2), P2 front-outer
    (a1, -c1/2), P3 rear-inner (-b1, c1/2), P4 front-inner (a1, c1/2).
    """
    heading = theta + 0.5 * math.pi
    rotation = np.array([[math.cos(heading), -math.sin(heading)],
                         [math.sin(heading), math.cos(heading)]])
    half = 0.5 * vehicle.c1
    body = np.array([[-vehicle.b1, -half], [vehicle.a1, -half], [-vehicle.b1, half],
                     [vehicle.a1, half]])
    return rho * np.array([math.cos(theta), math.sin(theta)]) + body @ rotation.T


@pytest.mark.parametrize('vehicle', [CAR, ROBOT, WIDE])
@pytest.mark.parametrize('rho', [0.3, 0.9, 3.8, 12.0])
@pytest.mark.parametrize('theta', [-2.0, 0.0, 0.7, 3.0])
def test_corner_distances_and_positions_against_direct_geometry(vehicle, rho, theta):
    corners = placed_corners(vehicle, rho, theta)
    d, delta = corner_distances(vehicle, rho)
    assert d == pytest.approx(np.hypot(corners[:, 0], corners[:, 1]), abs=1e-12)
    assert corner_positions(vehicle, rho, theta) == pytest.approx(corners, abs=1e-12)
    # δ_i is the angle between the ICR-P_f line and the ICR-P_i line: rear corners behind
    # (θ − δ), front corners ahead (θ + δ), each in [0, π].
    angles = np.arctan2(corners[:, 1], corners[:, 0]) - theta
    offsets = np.angle(np.exp(1j * angles))
    assert np.abs(offsets) == pytest.approx(delta, abs=1e-12)
    assert (offsets[[0, 2]] < 0.0).all() and (offsets[[1, 3]] > 0.0).all()
    assert ((delta >= 0.0) & (delta <= math.pi)).all()


def test_the_catalogue_reading_of_the_indices_fails_direct_geometry():
    # The slides print "i = 1, 2; j = 2, 3", the catalogue proposes i in {1, 2} (at θ − δ):
    # then P2, a front corner, would be behind P_f. Direct geometry puts it ahead (θ + δ_2).
    rho, theta = 3.8, 0.4
    d, delta = corner_distances(CAR, rho)
    p2 = placed_corners(CAR, rho, theta)[1]
    catalogue = d[1] * np.array([math.cos(theta - delta[1]), math.sin(theta - delta[1])])
    ours = d[1] * np.array([math.cos(theta + delta[1]), math.sin(theta + delta[1])])
    assert np.linalg.norm(catalogue - p2) > 1.0
    assert ours == pytest.approx(p2, abs=1e-12)


def test_delta3_passes_pi_over_2_when_rho_is_below_half_the_width():
    _, delta = corner_distances(WIDE, 0.5)
    assert delta[2] == pytest.approx(math.atan2(WIDE.b1, 0.5 - 1.0))
    assert delta[2] > 0.5 * math.pi


def test_arc_extreme_against_dense_sampling():
    rng = np.random.default_rng(21)
    for _ in range(300):
        radius = rng.uniform(0.1, 5.0)
        start, sweep, psi = rng.uniform(-7.0, 7.0), rng.uniform(-4.0, 4.0), rng.uniform(-7, 7)
        alpha = np.linspace(start, start + sweep, 20001)
        sampled = (radius * np.cos(alpha - psi)).max()
        exact = arc_extreme(radius, start, start + sweep, psi)
        assert exact >= sampled - 1e-12
        assert exact == pytest.approx(sampled, abs=radius * 2e-8)


@pytest.mark.parametrize('bad', [0.0, -1.0, math.nan, math.inf])
def test_bad_radius_is_refused(bad):
    with pytest.raises(ValueError, match='rho'):
        two_arc_displacement(bad, 0.3)
    with pytest.raises(ValueError, match='rho'):
        corner_distances(CAR, bad)


def test_bad_direction_is_refused():
    with pytest.raises(ValueError, match='direction'):
        two_arc_centres(3.0, 0.3, 0)
