"""
Tests of robotica_sim.benchmarks.planning, .parking_planning and ``robotica bench planning``.

Issue 21. Tiny grids only: the structure of the rows and that every method found the same cost
(the comparison means nothing otherwise). The parking part with one run per call: a row per
case, a plan or a reason, the scene's readings and the detected space against the geometry
written here. No timings are asserted (only that they are positive).
"""
import json
import math

import numpy as np
import pytest

from robotica_ctrl.planning.grid_astar import astar_cells
from robotica_ctrl.planning.parking import ParkingParams, ParkingVehicle, plan_parallel_parking
from robotica_sim.benchmarks import parking_planning
from robotica_sim.benchmarks.parking_planning import (format_parking_table, MODES,
                                                      parking_benchmark, parking_rows_json,
                                                      parking_space, ParkingRow,
                                                      READING_SPACING, SENSOR_POSE, side_pass,
                                                      START)
from robotica_sim.benchmarks.planning import (baseline_astar, check_costs, CostMismatch,
                                              format_planning_table, GOALS, grid_edges,
                                              planning_benchmark,
                                              planning_rows_json, PlanningRow, random_grid)
from robotica_sim.cli import bench
from robotica_sim.cli.main import main
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

METHODS_8 = ['grid_astar (OccupancyGrid, points in m)', 'astar_cells (bool mask)',
             'baseline: textbook Python A* (dicts, heapq)', 'scipy.sparse.csgraph.dijkstra',
             "scipy.sparse.csgraph.shortest_path(method='D')"]
METHODS_NX = ['networkx.astar_path_length', 'networkx.dijkstra_path_length']
METHODS_16 = ['grid_astar (OccupancyGrid, points in m)', 'astar_cells (bool mask)',
              'scipy.sparse.csgraph.dijkstra']


def test_random_grid_has_free_connected_corners_and_is_seeded():
    for size in (2, 5, 30):
        mask = random_grid(size, seed=7)
        assert mask.shape == (size, size) and mask.dtype == np.bool_
        assert not mask[0, 0] and not mask[-1, -1]
        assert math.isfinite(astar_cells(mask, [0, 0], [size - 1, size - 1]).cost)
        np.testing.assert_array_equal(mask, random_grid(size, seed=7))
    assert 0.15 < random_grid(100).mean() < 0.25
    with pytest.raises(ValueError):
        random_grid(1)


@pytest.mark.parametrize('neighbours', [8, 16])
def test_graph_and_baseline_agree_with_astar_cells(neighbours):
    rng = np.random.default_rng(5)
    for _ in range(20):
        mask = rng.random((9, 11)) < 0.3
        mask[0, 0] = mask[-1, -1] = False
        plan = astar_cells(mask, [0, 0], [10, 8], neighbours)
        src, dst, cost = grid_edges(mask, neighbours)
        graph = csr_matrix((cost, (src, dst)), shape=(mask.size, mask.size))
        reference = dijkstra(graph, indices=0)[mask.size - 1]
        if not plan.found:
            assert reference == math.inf
            continue
        assert plan.cost == pytest.approx(reference, rel=1e-12)
        if neighbours == 8:
            cost8, expansions, path = baseline_astar(mask, (0, 0), (10, 8))
            assert cost8 == pytest.approx(plan.cost, rel=1e-12)
            assert path[0] == (0, 0) and path[-1] == (10, 8)
            assert expansions >= 1


def test_baseline_reports_no_path():
    wall = np.zeros((4, 4), bool)
    wall[:, 2] = True
    cost, expansions, path = baseline_astar(wall, (0, 0), (3, 3))
    assert cost == math.inf and path == [] and expansions == 8


def test_diagonal_needs_both_side_cells_free():
    mask = np.array([[False, True], [False, False]])     # cell (col 1, row 0) blocked
    src, dst, _cost = grid_edges(mask)
    assert (0, 3) not in set(zip(src.tolist(), dst.tolist()))
    assert baseline_astar(mask, (0, 0), (1, 1))[0] == 2.0


def test_rows_have_every_method_and_one_cost_per_case():
    rows = planning_benchmark(sizes=(6, 14), repeats=2, seed=3,
                              networkx=True)
    methods_8 = METHODS_8 + METHODS_NX
    for size in (6, 14):
        for neighbours, methods in ((8, methods_8), (16, METHODS_16)):
            case = [r for r in rows if r.size == size and r.neighbours == neighbours]
            assert [r.method for r in case] == methods
            costs = [r.cost for r in case]
            assert all(math.isfinite(c) for c in costs)
            assert max(costs) - min(costs) <= 1e-9 * max(costs)
    for row in rows:
        assert row.repeats == 2 and 0.0 < row.min_ms <= row.median_ms
        assert row.goal_ms is None and row.goal_met is None   # no goal for these sizes
        assert (row.build_ms is not None) == (row.method.startswith(('scipy', 'networkx')))
    ours = {r.method: r.expansions for r in rows if r.size == 14 and r.neighbours == 8}
    assert ours['grid_astar (OccupancyGrid, points in m)'] == ours['astar_cells (bool mask)']
    table = format_planning_table(rows)
    assert table.count('\n') == len(rows) + 1
    assert 'not met' not in table


def test_goals_and_mismatch_fail_loudly():
    def row(method, cost, size=200, ms=10.0):
        return PlanningRow(size, 0.2, method, 8, None, ms, ms, 1, None, cost,
                           1e3 * GOALS[size], '')

    assert row('a', 1.0).goal_met is True
    assert row('a', 1.0, 1000, 1500.0).goal_met is False
    assert planning_rows_json([row('a', 1.0)])[0]['goal_met'] is True
    check_costs([row('a', 100.0), row('b', 100.0 + 1e-8)])
    with pytest.raises(CostMismatch, match='b'):
        check_costs([row('a', 100.0), row('b', 100.001)])
    with pytest.raises(CostMismatch):
        check_costs([row('a', 100.0), row('b', math.inf)])


def test_cli(capsys, monkeypatch):
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '8', '--repeats', '1', '--skip-networkx',
              '--skip-parking', '--json', '--quiet'])
    assert info.value.code == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed['parking'] == []
    assert [row['method'] for row in printed['grid']] == METHODS_8 + METHODS_16
    assert len({round(row['cost'], 9) for row in printed['grid']
                if row['neighbours'] == 8}) == 1
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '1'])
    assert info.value.code == 2


def test_cli_prints_the_parking_table_after_the_grid_table(capsys, monkeypatch):
    calls = []
    made = [ParkingRow('plan_parallel_parking', 1.2, 5.8, 'geometric', False, 'a bound hit',
                       None, None, None, 1593, 150.0, 160.0, 1, ''),
            ParkingRow('detect_spaces', 1.2, 5.8, None, True, '', None, None, None, None,
                       0.3, 0.3, 1, '300 readings')]

    def stub(repeats, progress):                 # the wiring alone (the rows: tests below)
        calls.append(repeats)
        return made

    monkeypatch.setattr(bench, 'parking_benchmark', stub)
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '6', '--repeats', '2', '--skip-networkx'])
    assert info.value.code == 0 and calls == [2]
    grid, parking = capsys.readouterr().out.strip().split('\n\n')
    assert grid.startswith('| grid |') and parking == format_parking_table(made)
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '6', '--repeats', '1', '--skip-networkx',
              '--json', '--quiet'])
    printed = json.loads(capsys.readouterr().out)
    assert printed['parking'] == parking_rows_json(made)
    assert printed['parking'][0]['cost'] is None and len(printed['grid']) == 8


def test_parking_scene_readings_follow_the_geometry():
    vehicle = ParkingVehicle()
    for ratio in (1.2, 2.0):
        space = parking_space(ratio)
        assert space.length == pytest.approx(ratio * (vehicle.a1 + vehicle.b1) + 0.4)
        assert space.effective_length == pytest.approx(ratio * vehicle.length)
        poses, ranges = side_pass(space)
        assert poses.shape == (300, 3) and np.all(poses[:, 1:] == [START[1], START[2]])
        sensor_x = poses[:, 0] + SENSOR_POSE[0]
        line = START[1] + SENSOR_POSE[1]           # sonar to the parked cars' sides: 0.55 m
        inside = (sensor_x > 1e-9) & (sensor_x < space.length - 1e-9)
        expected = np.where(inside, line + space.depth, line)
        np.testing.assert_allclose(ranges, expected, atol=1e-9)
        assert sensor_x[0] < 0.0 and sensor_x[-1] > space.length   # both cars seen
    with pytest.raises(ValueError, match='ratio'):
        parking_space(0.0)
    with pytest.raises(ValueError, match='repeats'):
        parking_benchmark(repeats=0)


def test_parking_rows_per_case_plan_or_reason():
    progress = []
    rows = parking_benchmark(repeats=1, progress=progress.append)
    assert [m.split(':')[:2] for m in progress] == [
        ['planning', ' parking']] * 3 and "H' = 1.5 (a1 + b1)" in progress[1]
    vehicle = ParkingVehicle()
    for ratio in (1.2, 1.5, 2.0):
        case = [r for r in rows if r.ratio == ratio]
        assert [(r.method, r.mode) for r in case] == [
            (method, mode) for mode in MODES
            for method in ('plan_parallel_parking', 'ParkingSearch')] + [('detect_spaces', None)]
        for row in case:
            assert row.repeats == 1 and 0.0 < row.min_ms <= row.median_ms
            assert row.space_length == pytest.approx(ratio * vehicle.length + 0.4)
        for row in case[:-1]:
            assert row.expansions > 0
            if row.found:
                assert row.reason == '' and row.parking_manoeuvres >= 1
                assert row.poses >= 2 and row.cost > 0.0
            else:                                    # a reason, not a crash
                assert row.reason and row.cost is None and row.parking_manoeuvres is None
        detection = case[-1]
        assert detection.found, detection.reason
        # one ray per reading: H short by at most two sampling intervals, J the curb's depth
        detected = detection.note.split('H = ')[1]
        length, depth = float(detected.split(' m')[0]), float(detected.split('J = ')[1][:5])
        assert 0.0 < detection.space_length - length <= 2 * READING_SPACING + 1e-9
        assert depth == pytest.approx(2.2, abs=1e-3)
    for ratio in (1.5, 2.0):                         # H' >= 1.5 (a1 + b1): parked
        assert all(r.found for r in rows if r.ratio == ratio)
    plan = plan_parallel_parking(parking_space(2.0), vehicle, START,
                                 ParkingParams(mode='geometric'))
    row = rows[10]
    assert (row.ratio, row.method, row.mode) == (2.0, 'plan_parallel_parking', 'geometric')
    assert (row.cost, row.poses, row.expansions) == (
        plan.cost, len(plan.path), plan.expansions)
    table = format_parking_table(rows)
    assert table.count('\n') == len(rows) + 1
    assert table.count('| no: ') == sum(not r.found for r in rows)
    printed = json.loads(json.dumps(parking_rows_json(rows)))
    assert [r['found'] for r in printed] == [r.found for r in rows]


def test_parking_module_constants_are_the_scene():
    assert parking_planning.RATIOS == (1.2, 1.5, 2.0)
    assert parking_planning.START == (0.0, 1.4, 0.0)
    assert parking_planning.PASS_READINGS == 300
