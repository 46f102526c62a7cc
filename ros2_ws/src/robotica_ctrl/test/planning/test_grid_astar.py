"""
Grid A* (book §12.6.2, (12.1)) against an independent Dijkstra, and its "no path" reasons.

The reference graph is built here from geometry alone: a move between two cell centres is an
edge when every cell whose closed square meets the segment is free (a slab test per cell), its
weight the segment's length; SciPy's Dijkstra then gives the optimum the A* cost must equal.
"""
import itertools
import math

import numpy as np
import pytest
from robotica_ctrl.planning import PlanResult, SearchBudget
from robotica_ctrl.planning.grid_astar import astar_cells, grid_astar, grid_obstacles
from robotica_kin.world import OccupancyGrid
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra


def square_meets_segment(cell, a, b):
    """Return whether the closed unit square centred on ``cell`` meets the segment a-b."""
    lo, hi = np.asarray(cell, float) - 0.5, np.asarray(cell, float) + 0.5
    d = np.asarray(b, float) - np.asarray(a, float)
    t0, t1 = 0.0, 1.0
    for k in range(2):
        if d[k] == 0.0:
            if not lo[k] <= a[k] <= hi[k]:
                return False
            continue
        ta, tb = sorted(((lo[k] - a[k]) / d[k], (hi[k] - a[k]) / d[k]))
        t0, t1 = max(t0, ta), min(t1, tb)
    return t0 <= t1


def reference_graph(blocked, neighbours):
    """Return the grid's graph (csr, weights in cells) built from the geometry of each move."""
    rows, cols = blocked.shape
    steps = [(dc, dr) for dc in range(-2, 3) for dr in range(-2, 3)
             if (dc, dr) != (0, 0) and max(abs(dc), abs(dr)) == 1
             or (neighbours == 16 and {abs(dc), abs(dr)} == {1, 2})]
    assert len(steps) == neighbours
    src, dst, weight = [], [], []
    for r, c in itertools.product(range(rows), range(cols)):
        for dc, dr in steps:
            c2, r2 = c + dc, r + dr
            if not (0 <= c2 < cols and 0 <= r2 < rows):
                continue
            crossed = [(cc, rr) for cc in range(min(c, c2), max(c, c2) + 1)
                       for rr in range(min(r, r2), max(r, r2) + 1)
                       if square_meets_segment((cc, rr), (c, r), (c2, r2))]
            if all(not blocked[rr, cc] for cc, rr in crossed):
                src.append(r * cols + c)
                dst.append(r2 * cols + c2)
                weight.append(math.hypot(dc, dr))
    n = rows * cols
    return csr_matrix((weight, (src, dst)), shape=(n, n))


@pytest.mark.parametrize('neighbours', [8, 16])
def test_astar_cost_equals_dijkstra_on_random_grids(neighbours):
    rng = np.random.default_rng(21)
    compared = unreachable = 0
    for trial in range(40):
        rows, cols = rng.integers(4, 11, size=2)
        blocked = rng.random((rows, cols)) < rng.uniform(0.1, 0.4)
        free = np.argwhere(~blocked)
        if len(free) < 2:
            continue
        (r0, c0), (r1, c1) = free[rng.choice(len(free), 2, replace=False)]
        graph = reference_graph(blocked, neighbours)
        optimum = dijkstra(graph, indices=r0 * cols + c0)[r1 * cols + c1]
        plan = astar_cells(blocked, [c0, r0], [c1, r1], neighbours)
        if math.isinf(optimum):
            assert not plan.found and 'unreachable' in plan.reason
            unreachable += 1
            continue
        compared += 1
        assert plan.found, plan.reason
        assert plan.cost == pytest.approx(optimum, abs=1e-9)
        assert plan.details['redirections'] == 0     # consistent h: step 4b never applies
        cells = plan.path.astype(int)
        assert cells[0].tolist() == [c0, r0] and cells[-1].tolist() == [c1, r1]
        # Each step of the path is an edge of the reference graph.
        for (ca, ra), (cb, rb) in zip(cells[:-1], cells[1:]):
            assert graph[ra * cols + ca, rb * cols + cb] > 0.0
    assert compared >= 25 and unreachable >= 1


def test_open_grid_costs_the_octile_and_euclidean_distances():
    free = np.zeros((20, 30), dtype=bool)
    assert astar_cells(free, [0, 0], [29, 10], 8).cost == pytest.approx(19 + 10 * math.sqrt(2))
    # 16 neighbours: 10 knight's moves (2, 1) and 9 straight steps.
    assert astar_cells(free, [0, 0], [29, 10], 16).cost == pytest.approx(
        10 * math.sqrt(5) + 9)


def test_weighted_astar_is_within_its_bound_and_expands_less():
    rng = np.random.default_rng(5)
    blocked = rng.random((60, 60)) < 0.2
    blocked[0, 0] = blocked[-1, -1] = False
    exact = astar_cells(blocked, [0, 0], [59, 59])
    fast = astar_cells(blocked, [0, 0], [59, 59], weight=2.0)
    assert exact.found and fast.found
    assert exact.cost <= fast.cost <= 2.0 * exact.cost
    assert fast.expansions < exact.expansions


def grid(data, resolution=0.5, origin=(0.0, 0.0, 0.0)):
    return OccupancyGrid(np.asarray(data, dtype=np.int8), resolution, origin)


def test_the_path_runs_between_the_cell_centres_in_the_map_frame():
    data = np.zeros((5, 6), dtype=np.int8)
    data[0:4, 3] = 100                                # a wall with a gap at the top row
    g = grid(data, 0.5, (1.0, -1.0, math.pi / 2))     # the grid turned by 90°
    start = g.cell_to_world([[0, 0]])[0]
    goal = g.cell_to_world([[5, 0]])[0]
    plan = grid_astar(g, start, goal)
    assert plan.found, plan.reason
    assert np.allclose(plan.path[0], start) and np.allclose(plan.path[-1], goal)
    assert np.allclose(plan.path, g.cell_to_world(plan.details['cells']))
    assert plan.cost == pytest.approx(np.hypot(*np.diff(plan.path, axis=0).T).sum())
    assert not plan.details['obstacles'][plan.details['cells'][:, 1],
                                         plan.details['cells'][:, 0]].any()
    assert plan.details['cells'][:, 1].max() == 4     # through the gap
    assert len(plan.details['expanded']) == plan.expansions


def test_unknown_cells_and_the_threshold_are_obstacles_as_configured():
    data = np.zeros((3, 5), dtype=np.int8)
    data[:, 2] = [-1, 60, 70]                         # the only ways from left to right
    g = grid(data, 1.0)
    s, t = [0.5, 1.5], [4.5, 1.5]
    assert grid_obstacles(g)[:, 2].tolist() == [True, False, True]   # thresh 65 %, -1 blocks
    through = grid_astar(g, s, t)
    assert through.found and [2, 1] in through.details['cells'].tolist()
    known = grid_astar(g, s, t, occupied_threshold=60, unknown_is_obstacle=False)
    assert known.found and [2, 0] in known.details['cells'].tolist()
    assert not grid_astar(g, s, t, occupied_threshold=60).found


def test_a_robot_radius_closes_a_narrow_gap():
    data = np.full((9, 9), 0, dtype=np.int8)
    data[:, 4] = 100
    data[4, 4] = 0                                    # a gap of one 0.1 m cell
    g = grid(data, 0.1)
    s, t = [0.05, 0.45], [0.85, 0.45]
    assert grid_astar(g, s, t).found
    plan = grid_astar(g, s, t, robot_radius=0.06)
    assert not plan.found and 'start is in collision' not in plan.reason


@pytest.mark.parametrize('start, goal, words', [
    ([0.25, 0.25], [1.25, 0.75], 'the goal is in an obstacle: (1.25, 0.75) m'),
    ([0.25, 0.25], [9.0, 0.25], 'the goal (9, 0.25) m is off the map (4 x 4 cells)'),
    ([-0.1, 0.25], [0.25, 1.75], 'the start (-0.1, 0.25) m is off the map'),
    ([1.25, 0.75], [0.25, 0.25], 'the start is in collision: (1.25, 0.75) m'),
    ([0.25, 0.25], [1.75, 1.75], 'the goal is unreachable'),
])
def test_no_path_comes_with_its_reason(start, goal, words):
    data = np.zeros((4, 4), dtype=np.int8)
    data[1, 2] = 100
    data[2:4, 2] = 100
    data[2, 3] = 100                                  # cells (3, 3) and (3, 2) walled off
    plan = grid_astar(grid(data), start, goal)
    assert isinstance(plan, PlanResult) and not plan.found
    assert plan.path is None and plan.cost == math.inf
    assert words in plan.reason


def test_a_map_with_no_free_cell_says_so():
    plan = grid_astar(grid(np.full((3, 3), 100)), [0.1, 0.1], [1.4, 1.4])
    assert not plan.found and plan.reason.startswith('the map has no free cell')
    unknown = grid_astar(grid(np.full((3, 3), -1)), [0.1, 0.1], [1.4, 1.4])
    assert unknown.reason.startswith('the map has no free cell')


def test_the_budget_stops_the_search_and_says_so():
    blocked = np.zeros((100, 100), dtype=bool)
    blocked[50, 0:99] = True                             # a long wall: many expansions
    plan = astar_cells(blocked, [0, 0], [0, 99], budget=SearchBudget(max_expansions=30))
    assert not plan.found and plan.expansions == 30
    assert plan.reason == 'the search budget was exhausted: 30 expansions, the most allowed'
    assert len(plan.details['expanded']) == 30
    ticks = itertools.count()
    slow = astar_cells(blocked, [0, 0], [0, 99], budget=SearchBudget(max_seconds=0.5),
                       clock=lambda: float(next(ticks)))  # 1 s per reading
    assert not slow.found and 'the search budget was exhausted: 1 s' in slow.reason
    assert slow.expansions == 1024                  # the clock is read every 1024 expansions
    enough = astar_cells(blocked, [0, 0], [0, 99], budget=SearchBudget(max_expansions=10000))
    assert enough.found and enough.expansions < 10000


def test_start_equal_to_goal_is_a_path_of_one_point():
    plan = grid_astar(grid(np.zeros((2, 2))), [0.1, 0.1], [0.2, 0.2])
    assert plan.found and plan.cost == 0.0 and plan.path.tolist() == [[0.25, 0.25]]


@pytest.mark.parametrize('kwargs, words', [
    ({'neighbours': 4}, 'neighbours must be 8 or 16'),
    ({'weight': 0.5}, 'weight must be >= 1'),
    ({'robot_radius': -1.0}, 'robot_radius must be >= 0 m'),
    ({'occupied_threshold': 101}, 'occupied_threshold must be an integer in 0..100'),
    ({'goal': [1.0, math.nan]}, 'goal must be a finite point'),
    ({'budget': 10}, 'budget must be a SearchBudget'),
])
def test_bad_input_is_refused(kwargs, words):
    call = {'grid': grid(np.zeros((3, 3))), 'start': [0.1, 0.1], 'goal': [1.0, 1.0], **kwargs}
    with pytest.raises(ValueError, match=words):
        grid_astar(**call)


def test_bad_cells_are_refused():
    with pytest.raises(ValueError, match='blocked must be a non-empty 2-D bool array'):
        astar_cells(np.zeros((3, 3)), [0, 0], [1, 1])
    with pytest.raises(ValueError, match='start must be an integer cell'):
        astar_cells(np.zeros((3, 3), bool), [0.5, 0], [1, 1])
