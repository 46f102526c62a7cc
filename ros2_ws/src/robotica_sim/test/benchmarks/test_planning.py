"""
Tests of robotica_sim.benchmarks.planning and ``robotica bench planning`` (issue 21).

Tiny grids only: the structure of the rows and that every method found the same cost (the
comparison means nothing otherwise). No timings are asserted.
"""
import json
import math

import numpy as np
import pytest

from robotica_ctrl.planning.grid_astar import astar_cells
from robotica_sim.benchmarks.planning import (baseline_astar, check_costs, CostMismatch,
                                              format_planning_table, GOALS, grid_edges,
                                              planning_benchmark,
                                              planning_rows_json, PlanningRow, random_grid)
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


def test_cli(capsys):
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '8', '--repeats', '1', '--skip-networkx',
              '--json', '--quiet'])
    assert info.value.code == 0
    printed = json.loads(capsys.readouterr().out)
    assert [row['method'] for row in printed] == METHODS_8 + METHODS_16
    assert len({round(row['cost'], 9) for row in printed if row['neighbours'] == 8}) == 1
    with pytest.raises(SystemExit) as info:
        main(['bench', 'planning', '--sizes', '1'])
    assert info.value.code == 2
