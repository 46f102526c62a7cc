"""
ParkingSearch: the pass, when a space is taken, a short space refused and the next one taken.

The street is written here: the curb on y = 0, parked cars whose street sides are on y = 2.2,
P_f passing on y = 3.6 at 0.1 m a sample, the side sensor at the front-right corner (3.4,
-0.85) looking right: it reads 0.55 m beside a car and 2.75 m (the curb) in a space.
"""
import math

import numpy as np
import pytest
from robotica_ctrl.planning.parking import ParkingVehicle
from robotica_ctrl.planning.parking.parking_search import (parking_search, ParkingSearch,
                                                           ParkingSearchParams)
from robotica_kin.parameter_specs import ParameterError

SENSOR = (3.4, -0.85, -0.5 * math.pi)
LANE = 3.6


def street(cars):
    """Return the reading at P_f = x for parked cars given as (start, end) along x [m]."""
    def reading(x):
        sensor_x = x + SENSOR[0]
        return 0.55 if any(a <= sensor_x <= b for a, b in cars) else 2.75
    return reading


def drive(search, reading, x_end, step=0.1):
    """Feed the pass from x = -2 m; return (x of P_f, space) for each space taken."""
    taken = []
    for x in np.arange(-2.0, x_end, step):
        found = search.add_reading((x, LANE, 0.0), reading(x), 0.15, 5.0)
        if found is not None:
            taken.append((float(x), found))
    return taken


def test_the_pass_is_straight_along_the_heading():
    search = ParkingSearch(ParkingVehicle(), SENSOR, ParkingSearchParams(pass_length=10.0,
                                                                         point_spacing=0.3))
    postures = search.start((1.0, 2.0, 0.5 * math.pi))
    assert postures[0] == pytest.approx([1.0, 2.0, 0.5 * math.pi])
    assert postures[-1] == pytest.approx([1.0, 12.0, 0.5 * math.pi])
    assert np.diff(postures[:, 1]).max() <= 0.3 + 1e-12
    assert np.allclose(postures[:, 0], 1.0)
    assert search.along((1.0, 7.0, 0.0)) == pytest.approx(5.0)
    assert not search.finished((1.0, 11.0, 0.5)) and search.finished((1.0, 11.8, 0.5))


def test_a_space_is_taken_once_the_sensor_is_confirm_distance_past_it():
    search = ParkingSearch(ParkingVehicle(), SENSOR, ParkingSearchParams(confirm_distance=0.5))
    search.start((-2.0, LANE, 0.0))
    taken = drive(search, street([(2.0, 6.5), (13.7, 18.2)]), 16.0)
    assert len(taken) == 1                                     # once, not at every sample
    x, found = taken[0]
    last_free = -2.0 + 0.1 * found.last_sample + SENSOR[0]     # the sensor there
    assert x + SENSOR[0] - last_free >= 0.5 - 1e-9
    assert x - 0.1 + SENSOR[0] - last_free < 0.5 - 1e-9       # and not a sample before
    assert found.space.length == pytest.approx(7.2, abs=0.2)
    assert found.space.depth == pytest.approx(2.2, abs=1e-9)
    plan = search.plan(found, (x, LANE, 0.0))
    assert plan.found, plan.reason
    assert plan.path[0] == pytest.approx([x, LANE, 0.0])      # from the taking sample's pose


def test_a_short_space_is_refused_and_the_next_one_taken():
    search = ParkingSearch(ParkingVehicle(), SENSOR)
    search.start((-2.0, LANE, 0.0))
    cars = [(2.0, 6.5), (10.0, 14.5), (22.0, 26.5)]            # 3.5 m, then 7.5 m
    taken = drive(search, street(cars), 25.0)
    assert [round(f.space.length, 1) for _, f in taken] == [3.4, 7.4]
    short = search.plan(taken[0][1], (taken[1][0], LANE, 0.0))
    assert not short.found and short.reason.startswith('the space is too short')
    assert search.plan(taken[1][1]).found


def test_a_turning_pass_and_bad_input_are_refused():
    search = ParkingSearch(ParkingVehicle(), SENSOR)
    with pytest.raises(ValueError, match='no pass has been started'):
        search.add_reading((0.0, 0.0, 0.0), 1.0, 0.15, 5.0)
    search.start((0.0, 0.0, 0.0))
    search.add_reading((0.0, 0.0, 0.0), 1.0, 0.15, 5.0)
    with pytest.raises(ValueError, match='the pass must be straight'):
        search.add_reading((0.1, 0.0, 0.5), 1.0, 0.15, 5.0)
    with pytest.raises(ValueError, match='finite'):
        search.add_reading((math.nan, 0.0, 0.0), 1.0, 0.15, 5.0)
    with pytest.raises(ValueError, match='look sideways'):
        ParkingSearch(ParkingVehicle(), (0.0, 0.0, 0.0))


def test_parameters_build_the_search_and_refuse_bad_values():
    search = parking_search({'a1': 0.45, 'b1': 0.1, 'h1': 0.35, 'c1': 0.3,
                             'max_steering': 0.5, 'execution': 'progressive',
                             'sensor_pose': (0.4, -0.15, -1.5708), 'margin': 0.05})
    assert search.vehicle.length == pytest.approx(0.55)
    assert search.planning.mode == 'progressive' and search.detection.margin == 0.05
    with pytest.raises(ParameterError, match='execution'):
        parking_search({'execution': 'fast'})
    with pytest.raises(ParameterError, match='c1'):
        parking_search({'c1': 0.0})
