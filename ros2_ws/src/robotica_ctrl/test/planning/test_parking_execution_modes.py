"""
Tests of the parking execution modes (catalogue §14.4 step 4): arcs with a stop, progressive.

The reference motion is SciPy's solve_ivp on the bicycle model in the distance s travelled
by P_f: x' = d cos θ, y' = d sin θ, θ' = d tan φ(s) / h1, d = ±1 the direction, with the
steering φ(s) of each piece written here (linear in s).
"""

import math

import numpy as np
import pytest
from robotica_ctrl.planning.parking.execution_modes import (
    GeometricMode, make_mode, Piece, ProgressiveMode, sample_pieces)
from robotica_ctrl.planning.parking.manoeuvre_arcs import two_arc_displacement
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from scipy.integrate import solve_ivp

CAR = ParkingVehicle()
ROBOT = ParkingVehicle(a1=0.45, b1=0.1, h1=0.35, c1=0.3, theta_dmax=0.5, d1=0.28, r=0.05)


def integrate(vehicle, pieces, at):
    """Return the poses (len(at), 3) at the distances ``at`` [m] driven through ``pieces``."""
    bounds = np.cumsum([0.0] + [p.length for p in pieces])

    def rhs(s, state):
        k = min(int(np.searchsorted(bounds, s, side='right')) - 1, len(pieces) - 1)
        piece = pieces[k]
        u = (s - bounds[k]) / piece.length if piece.length > 0.0 else 0.0
        phi = piece.steering_start + (piece.steering_end - piece.steering_start) * u
        d = piece.direction
        return [d * math.cos(state[2]), d * math.sin(state[2]),
                d * math.tan(phi) / vehicle.h1]

    at = np.minimum(at, bounds[-1])
    sol = solve_ivp(rhs, (0.0, bounds[-1]), [0.0, 0.0, 0.0], t_eval=at, rtol=1e-11,
                    atol=1e-12, max_step=0.01)
    return sol.y.T


def distances(pieces, step):
    """Return the distance driven at each sampled posture: pieces cut in equal steps <= step."""
    counts = [math.ceil(p.length / step - 1e-9) for p in pieces if p.length > 0.0]
    cuts = [np.full(n, p.length / n) for n, p in zip(counts, [p for p in pieces
                                                              if p.length > 0.0])]
    return np.concatenate([[0.0], np.cumsum(np.concatenate(cuts))])


@pytest.mark.parametrize('vehicle', [CAR, ROBOT])
@pytest.mark.parametrize('direction', [-1, 1])
@pytest.mark.parametrize('size', [0.4, 1.0, 1.6])
def test_progressive_path_against_the_integrated_bicycle_model(vehicle, direction, size):
    mode = ProgressiveMode(vehicle, vehicle.theta_dmax, 2.0 / vehicle.length)
    pieces = mode.pieces(size, direction)
    motion = sample_pieces(np.zeros(3), pieces, vehicle.h1, 0.02 * vehicle.length)
    steps = np.hypot(*np.diff(motion.postures[:, :2], axis=0).T)
    lengths = distances(pieces, 0.02 * vehicle.length)
    assert len(lengths) == len(motion.postures)
    assert steps.sum() <= lengths[-1] + 1e-12
    reference = integrate(vehicle, [p for p in pieces if p.length > 0.0], lengths)
    assert motion.postures == pytest.approx(reference, abs=1e-8 * vehicle.length)
    # Parallel at both ends, shifted to the right, along the direction of travel.
    end = motion.postures[-1]
    assert abs(end[2]) < 1e-9 and end[1] < 0.0 and direction * end[0] > 0.0
    assert (motion.directions == direction).all()


@pytest.mark.parametrize('vehicle', [CAR, ROBOT])
def test_progressive_steering_is_continuous_and_starts_and_ends_straight(vehicle):
    sigma = 2.0 / vehicle.length
    mode = ProgressiveMode(vehicle, vehicle.theta_dmax, sigma)
    step = 0.01 * vehicle.length
    motion = sample_pieces(np.zeros(3), mode.pieces(1.5, -1), vehicle.h1, step)
    phi = motion.steering
    assert np.abs(np.diff(phi)).max() <= sigma * step * (1.0 + 1e-9)
    assert abs(phi[0]) <= 0.5 * sigma * step + 1e-12
    assert abs(phi[-1]) <= 0.5 * sigma * step + 1e-12
    assert np.abs(phi).max() <= vehicle.theta_dmax
    assert not mode.stops_between_arcs


@pytest.mark.parametrize('vehicle', [CAR, ROBOT])
@pytest.mark.parametrize('xi', [0.1, 0.5, 1.0])
def test_an_equivalent_progressive_manoeuvre_shifts_as_the_arcs(vehicle, xi):
    geometric = GeometricMode(vehicle, vehicle.theta_dmax)
    progressive = ProgressiveMode(vehicle, vehicle.theta_dmax, 2.0 / vehicle.length)
    arcs = geometric.shape(xi, -1)
    size = progressive.size_for_shift(arcs.lateral)
    ramps = progressive.shape(size, -1)
    assert ramps.lateral == pytest.approx(arcs.lateral, abs=1e-7)
    # Steering less sharply on the ramps, it takes more room along the street.
    assert ramps.longitudinal > arcs.longitudinal
    pieces = progressive.pieces(size, -1)
    reference = integrate(vehicle, [p for p in pieces if p.length > 0.0],
                          [sum(p.length for p in pieces)])[-1]
    assert -reference[1] == pytest.approx(arcs.lateral, abs=1e-5 * vehicle.length)


@pytest.mark.parametrize('direction', [-1, 1])
def test_geometric_mode_is_two_arcs_of_equations_a(direction):
    mode = GeometricMode(CAR, 0.5)
    rho = CAR.h1 / math.tan(0.5)
    first, second = mode.pieces(0.7, direction)
    assert (first.steering_start, second.steering_start) == (-0.5, 0.5)
    assert first.length == pytest.approx(rho * 0.7) and second.length == first.length
    assert first.kind == second.kind == 'arc' and mode.stops_between_arcs
    shape = mode.shape(0.7, direction)
    x, y, _ = two_arc_displacement(rho, 0.7)
    assert (shape.lateral, shape.longitudinal) == pytest.approx((x, y))
    end = sample_pieces(np.zeros(3), (first, second), CAR.h1, 0.05).postures[-1]
    assert end == pytest.approx([direction * y, -x, 0.0], abs=1e-9)
    assert mode.size_for_shift(x) == pytest.approx(0.7)
    assert mode.size_for_shift(10 * rho) == pytest.approx(0.5 * math.pi)


def test_sampled_steps_stay_within_the_step():
    pieces = (Piece(1, 1.0, 0.0, 0.0, 'straight'), Piece(-1, 0.0, 0.2, 0.2, 'arc'),
              Piece(-1, 0.33, 0.2, 0.2, 'arc'))
    motion = sample_pieces([1.0, 2.0, 0.5], pieces, 2.0, 0.1)
    assert len(motion.postures) == 11 + 4
    assert motion.piece.tolist() == [0] * 10 + [2] * 4
    assert motion.directions.tolist() == [1] * 10 + [-1] * 4
    assert motion.postures[10] == pytest.approx([1.0 + math.cos(0.5), 2.0 + math.sin(0.5),
                                                 0.5])


def test_bad_modes_and_pieces_are_refused():
    with pytest.raises(ValueError, match='mode'):
        make_mode('teleport', CAR, 0.5, 1.0)
    with pytest.raises(ValueError, match='steering'):
        GeometricMode(CAR, 0.7)                           # beyond θ_dmax = 0.6
    with pytest.raises(ValueError, match='steering_per_metre'):
        ProgressiveMode(CAR, 0.5, 0.0)
    with pytest.raises(ValueError, match='size'):
        GeometricMode(CAR, 0.5).pieces(2.0, 1)
    with pytest.raises(ValueError, match='direction'):
        Piece(0, 1.0, 0.0, 0.0, 'straight')
    with pytest.raises(ValueError, match='length'):
        Piece(1, -1.0, 0.0, 0.0, 'straight')
    with pytest.raises(ValueError, match='step'):
        sample_pieces(np.zeros(3), (), 2.0, 0.0)
