"""
Issue 21: grid A* against a straightforward Python A*, SciPy and NetworkX on the same graph.

``robotica bench planning`` plans across seeded random grids of 200 x 200 and 1000 x 1000
cells (:data:`RESOLUTION` 5 cm: 10 m and 50 m a side) with about :data:`OBSTACLE_FRACTION`
of the cells occupied at random (:func:`random_grid`): the start is the cell (0, 0), the goal
the opposite corner (n - 1, n - 1), both free and connected (a grid whose corners are not
connected is drawn again). Every method searches the same graph, measured in one process:

- **ours**: :func:`robotica_ctrl.planning.grid_astar.grid_astar` on an
  :class:`~robotica_kin.world.OccupancyGrid` (points in metres: the obstacles thresholded from
  the map, the cells of the two points, the search, the path back in metres), and
  :func:`~robotica_ctrl.planning.grid_astar.astar_cells` on the boolean mask (the search and
  its move table alone), with 8 neighbours and, as a second row, 16;
- **baseline**: :func:`baseline_astar`, the textbook A* in plain Python written here (open list
  a ``heapq`` of (f, h, cell), g and parent pointers in dicts, the closed list a set): the
  straightforward version to compare against, with the same moves, costs, heuristic (octile)
  and tie rule as ours, so the difference is the implementation, not the search;
- **SciPy**: ``scipy.sparse.csgraph.dijkstra`` and ``shortest_path(method='D')`` from the start
  on the graph as a CSR matrix (:func:`grid_edges`); Dijkstra without a target settles every
  reachable cell, reported as its expansions;
- **NetworkX**: ``networkx.astar_path_length`` (the octile heuristic) and
  ``networkx.dijkstra_path_length`` on an ``nx.Graph`` of the same edges.

The graph (:func:`grid_edges`, written apart from ``grid_astar``'s move table): a cell joins
its 8 neighbours (cost 1 along a row or column, √2 diagonally) when the neighbour is free and,
for a diagonal, both cells beside the move are free (no corner cut), as ``grid_astar``'s
rule; with 16 the knight's moves (±1, ±2), (±2, ±1) of cost √5 are added, allowed when the two
cells their segment crosses are free. The 16-neighbour rows of ours are checked against SciPy's
Dijkstra on the 16-neighbour graph.

Times are wall-clock (``time.perf_counter``) per search, the minimum and median over
``repeats`` runs, the garbage collector on (as in use) and run before each round of runs (not
timed); the methods of a group (ours and the baseline; SciPy's two; NetworkX's two) take turns
run by run, so that they share the machine's load. The machine is shared: the minimum is the
figure. Building a library's graph (from the mask: edge arrays, then the CSR matrix or the
``nx.Graph``) is timed once and reported in its own column; ``grid_astar`` and ``astar_cells``
build what they need inside the timed call. Every cost (in cells) must agree with
``grid_astar``'s to :data:`COST_TOLERANCE` (relative): otherwise :class:`CostMismatch` is raised
and nothing is reported. The issue's goals (:data:`GOALS`: 200 x 200 under 50 ms, 1000 x 1000
under 1 s) are judged on the minimum time of our rows.

NetworkX is a dependency of the package for this comparison (pinned in
``requirements/robotica.txt``); ``networkx=False`` skips it (on 1000 x 1000 its graph takes
seconds to build and about a gigabyte of memory).

The command's second table, the course's parallel-parking planner, is
:mod:`robotica_sim.benchmarks.parking_planning`; it shares :func:`alternate_runs` and
:func:`format_ms`.
"""
import dataclasses
from dataclasses import dataclass
import gc
from heapq import heappop, heappush
import math
import statistics
import time
from typing import Any, Callable, Optional, Sequence

import networkx as nx
import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.planning.grid_astar import astar_cells, grid_astar
from robotica_kin.world import OccupancyGrid
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra, shortest_path

__all__ = ['COST_TOLERANCE', 'CostMismatch', 'GOALS', 'OBSTACLE_FRACTION', 'PlanningRow',
           'Progress', 'REPEATS', 'RESOLUTION', 'SIZES', 'alternate_runs', 'baseline_astar',
           'check_costs', 'format_ms', 'format_planning_table', 'grid_edges',
           'planning_benchmark', 'planning_rows_json', 'random_grid']

SIZES = (200, 1000)           # cells a side
RESOLUTION = 0.05             # [m/cell]
OBSTACLE_FRACTION = 0.2       # probability of a cell being occupied
REPEATS = 5                   # timed searches per method
GOALS = {200: 0.050, 1000: 1.0}   # [s] issue 21's goals, by size
COST_TOLERANCE = 1e-9         # relative agreement of the costs
MAX_DRAWS = 100               # grids drawn before giving up on connected corners
_SQRT2 = math.sqrt(2.0)
_DIAGONAL_SAVING = _SQRT2 - 2.0   # octile: dr + dc - (2 - √2) min(dr, dc)

Progress = Callable[[str], None]


class CostMismatch(RuntimeError):
    """The methods found different costs: the comparison would mean nothing."""


@dataclass(frozen=True)
class PlanningRow:
    """One method on one grid: its time, work and cost (module docstring)."""

    size: int                  # cells a side
    obstacles: float           # fraction of the cells occupied
    method: str
    neighbours: int
    build_ms: Optional[float]  # [ms] the library's graph from the mask, once; None: none built
    min_ms: float              # [ms] per search, fastest of the repeats
    median_ms: float           # [ms] per search, median of the repeats
    repeats: int
    expansions: Optional[int]  # cells expanded (closed); None where the library does not say
    cost: float                # [cells] path length
    goal_ms: Optional[float]   # [ms] issue 21's goal for this size, on our rows; else None
    note: str

    @property
    def goal_met(self) -> Optional[bool]:
        """Whether ``min_ms`` is under the goal (None without one)."""
        return None if self.goal_ms is None else self.min_ms < self.goal_ms


def random_grid(size: int, seed: int = 0, fraction: float = OBSTACLE_FRACTION
                ) -> NDArray[np.bool_]:
    """
    Return a size x size obstacle mask with corners (0, 0) and (n - 1, n - 1) free and connected.

    Each cell is occupied with probability ``fraction`` (the corners cleared), drawn from
    ``numpy.random.default_rng([seed, size])``; a draw whose corners are not connected is
    replaced by the next. Connected means 4-connected: a diagonal move needs both cells beside
    it free, so the cells reachable with 8 or 16 neighbours are those reachable with 4.

    >>> mask = random_grid(50, seed=3)
    >>> mask.shape, bool(mask[0, 0] or mask[-1, -1]), bool(0.1 < mask.mean() < 0.3)
    ((50, 50), False, True)
    """
    if not (isinstance(size, int) and size >= 2):
        raise ValueError(f'size must be an integer >= 2, got {size!r}')
    rng = np.random.default_rng([seed, size])
    for _ in range(MAX_DRAWS):
        blocked = rng.random((size, size)) < fraction
        blocked[0, 0] = blocked[-1, -1] = False
        labels, _count = ndimage.label(~blocked)
        if labels[0, 0] == labels[-1, -1]:
            return blocked
    raise RuntimeError(f'no {size} x {size} grid with connected corners in {MAX_DRAWS} draws '
                       f'at {fraction:.0%} obstacles')


def _moves(neighbours: int) -> list[tuple[int, int, float, tuple[tuple[int, int], ...]]]:
    """Return (Δcol, Δrow, cost, cells beside the move that must be free) of a neighbourhood."""
    moves: list[tuple[int, int, float, tuple[tuple[int, int], ...]]] = [
        (1, 0, 1.0, ()), (-1, 0, 1.0, ()), (0, 1, 1.0, ()), (0, -1, 1.0, ())]
    moves += [(dc, dr, _SQRT2, ((dc, 0), (0, dr))) for dc in (1, -1) for dr in (1, -1)]
    if neighbours == 16:
        for a in (1, -1):
            for b in (2, -2):
                moves.append((b, a, math.sqrt(5.0), ((b // 2, 0), (b // 2, a))))
                moves.append((a, b, math.sqrt(5.0), ((0, b // 2), (a, b // 2))))
    elif neighbours != 8:
        raise ValueError(f'neighbours must be 8 or 16, got {neighbours!r}')
    return moves


def grid_edges(blocked: NDArray[np.bool_], neighbours: int = 8
               ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """
    Return the directed edges (from, to, cost) of the grid's graph, both ways of every move.

    The cells are numbered row * cols + col.

    >>> wall = np.zeros((2, 2), bool); wall[0, 1] = True
    >>> src, dst, cost = grid_edges(wall)
    >>> sorted(zip(src.tolist(), dst.tolist()))   # no diagonal 0-3: it would cut cell 1
    [(0, 2), (2, 0), (2, 3), (3, 2)]
    """
    free = ~np.asarray(blocked, dtype=bool)
    rows, cols = free.shape
    sources, targets, costs = [], [], []
    for dc, dr, cost, beside in _moves(neighbours):
        r0, r1 = max(0, -dr), rows - max(0, dr)
        c0, c1 = max(0, -dc), cols - max(0, dc)
        if r0 >= r1 or c0 >= c1:
            continue
        ok = free[r0:r1, c0:c1] & free[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
        for bc, br in beside:
            ok &= free[r0 + br:r1 + br, c0 + bc:c1 + bc]
        r, c = np.nonzero(ok)
        src = (r + r0) * cols + c + c0
        sources.append(src)
        targets.append(src + dr * cols + dc)
        costs.append(np.full(src.size, cost))
    return np.concatenate(sources), np.concatenate(targets), np.concatenate(costs)


def baseline_astar(blocked: NDArray[np.bool_], start: tuple[int, int], goal: tuple[int, int]
                   ) -> tuple[float, int, list[tuple[int, int]]]:
    """
    Return (cost, expansions, path) of the textbook A* with 8 neighbours; cells are (col, row).

    The straightforward version (the baseline of the benchmark): open list a ``heapq`` of
    (f, h, (row, col)), g and parent pointers in dicts, closed list a set, the grid as nested
    lists; the octile heuristic. No path: (inf, expansions, []).

    >>> wall = np.zeros((3, 3), bool); wall[1, 0:2] = True
    >>> cost, expansions, path = baseline_astar(wall, (0, 0), (0, 2))
    >>> cost, path
    (6.0, [(0, 0), (1, 0), (2, 0), (2, 1), (2, 2), (1, 2), (0, 2)])
    """
    free = (~np.asarray(blocked, dtype=bool)).tolist()
    rows, cols = len(free), len(free[0])
    moves = [(0, 1, 1.0), (0, -1, 1.0), (1, 0, 1.0), (-1, 0, 1.0),
             (1, 1, _SQRT2), (1, -1, _SQRT2), (-1, 1, _SQRT2), (-1, -1, _SQRT2)]
    goal_node = (goal[1], goal[0])

    def heuristic(node: tuple[int, int]) -> float:
        dr = abs(node[0] - goal_node[0])
        dc = abs(node[1] - goal_node[1])
        return dr + dc + _DIAGONAL_SAVING * min(dr, dc)

    start_node = (start[1], start[0])
    g: dict[tuple[int, int], float] = {start_node: 0.0}
    parent: dict[tuple[int, int], Optional[tuple[int, int]]] = {start_node: None}
    closed: set[tuple[int, int]] = set()
    h0 = heuristic(start_node)
    open_list = [(h0, h0, start_node)]
    while open_list:
        _f, _h, node = heappop(open_list)
        if node in closed:
            continue
        closed.add(node)
        if node == goal_node:
            path = []
            step: Optional[tuple[int, int]] = node
            while step is not None:
                path.append((step[1], step[0]))
                step = parent[step]
            return g[node], len(closed), path[::-1]
        r, c = node
        for dr, dc, cost in moves:
            nr, nc = r + dr, c + dc
            if not (0 <= nr < rows and 0 <= nc < cols) or not free[nr][nc]:
                continue
            if dr and dc and not (free[r][nc] and free[nr][c]):
                continue                                  # a diagonal cutting a corner
            neighbour = (nr, nc)
            if neighbour in closed:
                continue
            new_g = g[node] + cost
            if new_g < g.get(neighbour, math.inf):
                g[neighbour] = new_g
                parent[neighbour] = node
                h = heuristic(neighbour)
                heappush(open_list, (new_g + h, h, neighbour))
    return math.inf, len(closed), []


def alternate_runs(calls: Sequence[Callable[[], Any]], repeats: int
                   ) -> list[tuple[list[float], Any]]:
    """
    Return, per call, the seconds of ``repeats`` runs and the last run's result.

    The calls alternate (one run of each per round), so that they share the machine's load;
    the garbage collector runs before each round (untimed) and stays on in the calls.
    """
    times: list[list[float]] = [[] for _ in calls]
    results: list[Any] = [None] * len(calls)
    for _ in range(repeats):
        gc.collect()
        for k, call in enumerate(calls):
            start = time.perf_counter()
            results[k] = call()
            times[k].append(time.perf_counter() - start)
    return list(zip(times, results))


def _timed_once(call: Callable[[], Any]) -> tuple[float, Any]:
    gc.collect()
    start = time.perf_counter()
    result = call()
    return time.perf_counter() - start, result


class _Case:
    """One grid: the rows of its methods as they are measured."""

    def __init__(self, size: int, blocked: NDArray[np.bool_], repeats: int) -> None:
        self.size = size
        self.obstacles = float(blocked.mean())
        self.repeats = repeats
        self.rows: list[PlanningRow] = []

    def add(self, method: str, neighbours: int, times: list[float], cost: float,
            expansions: Optional[int], note: str, build: Optional[float] = None,
            ours: bool = False) -> None:
        goal = GOALS.get(self.size) if ours else None
        self.rows.append(PlanningRow(
            self.size, self.obstacles, method, neighbours,
            None if build is None else 1e3 * build, 1e3 * min(times),
            1e3 * statistics.median(times), len(times), expansions, float(cost),
            None if goal is None else 1e3 * goal, note))


def check_costs(rows: Sequence[PlanningRow]) -> None:
    """
    Raise :class:`CostMismatch` unless the rows of each grid and neighbourhood agree on the cost.

    The reference is the first row of each (size, neighbours) (``grid_astar``'s in the
    benchmark); agreement is relative, to
    :data:`COST_TOLERANCE`; a cost that is not finite (no path) never agrees.
    """
    reference: dict[tuple[int, int], PlanningRow] = {}
    bad = []
    for row in rows:
        first = reference.setdefault((row.size, row.neighbours), row)
        if not (math.isfinite(row.cost) and math.isclose(row.cost, first.cost,
                                                         rel_tol=COST_TOLERANCE, abs_tol=0.0)):
            bad.append(f'{row.size}x{row.size}, {row.neighbours} neighbours: {row.method} '
                       f'{row.cost!r} against {first.method} {first.cost!r}')
    if bad:
        raise CostMismatch('the methods disagree on the cost: ' + '; '.join(bad))


def _ours(case: _Case, blocked: NDArray[np.bool_], grid: OccupancyGrid, neighbours: int,
          progress: Progress) -> None:
    """Time grid_astar, astar_cells and, with 8 neighbours, the baseline, alternating."""
    n = case.size
    start, goal = (0, 0), (n - 1, n - 1)
    points = [((c + 0.5) * RESOLUTION, (r + 0.5) * RESOLUTION) for c, r in (start, goal)]
    calls: list[Callable[[], Any]] = [
        lambda: grid_astar(grid, points[0], points[1], neighbours),
        lambda: astar_cells(blocked, start, goal, neighbours)]
    if neighbours == 8:
        calls.append(lambda: baseline_astar(blocked, start, goal))
    progress(f'planning: {n} x {n}, {neighbours} neighbours: grid_astar, astar_cells'
             + (' and the plain-Python baseline' if neighbours == 8 else ''))
    timed = alternate_runs(calls, case.repeats)
    (times, plan), (mask_times, mask_plan) = timed[:2]
    for name, result in (('grid_astar', plan), ('astar_cells', mask_plan)):
        if not result.found:
            raise CostMismatch(f'{name} found no path on {n} x {n}: {result.reason}')
    case.add('grid_astar (OccupancyGrid, points in m)', neighbours, times,
             plan.cost / RESOLUTION, plan.expansions,
             f'path {plan.cost:.2f} m at {RESOLUTION:g} m/cell; obstacles thresholded from '
             'the map inside the call', ours=True)
    case.add('astar_cells (bool mask)', neighbours, mask_times, mask_plan.cost,
             mask_plan.expansions, 'the search and its move table alone', ours=True)
    if neighbours == 8:
        times, (cost, expansions, _path) = timed[2]
        case.add('baseline: textbook Python A* (dicts, heapq)', 8, times, cost, expansions,
                 'written in the benchmark; same moves, heuristic and ties as ours')


def _scipy(case: _Case, blocked: NDArray[np.bool_], neighbours: int, progress: Progress,
           both: bool = True) -> None:
    n = case.size
    s, t = 0, n * n - 1
    progress(f'planning: {n} x {n}, {neighbours} neighbours: SciPy graph and Dijkstra')

    def build() -> Any:
        src, dst, cost = grid_edges(blocked, neighbours)
        return csr_matrix((cost, (src, dst)), shape=(n * n, n * n))

    build_time, graph = _timed_once(build)
    edges = f'{graph.nnz} directed edges'
    calls: list[Callable[[], Any]] = [lambda: dijkstra(graph, directed=True, indices=s)]
    if both:
        calls.append(lambda: shortest_path(graph, method='D', directed=True, indices=s))
    timed = alternate_runs(calls, case.repeats)
    times, dist = timed[0]
    reached = int(np.isfinite(dist).sum())
    case.add('scipy.sparse.csgraph.dijkstra', neighbours, times, dist[t], reached,
             f'{edges}; no early exit: settles every reachable cell', build_time)
    if both:
        times, dist = timed[1]
        case.add("scipy.sparse.csgraph.shortest_path(method='D')", neighbours, times, dist[t],
                 reached, 'as dijkstra, after its input checks', build_time)


def _networkx(case: _Case, blocked: NDArray[np.bool_], progress: Progress) -> None:
    n = case.size
    s, t = 0, n * n - 1
    progress(f'planning: {n} x {n}: NetworkX graph (slow on large grids)')

    def build() -> Any:
        src, dst, cost = grid_edges(blocked, 8)
        once = src < dst                                  # undirected: each edge once
        graph = nx.Graph()
        graph.add_weighted_edges_from(zip(src[once].tolist(), dst[once].tolist(),
                                          cost[once].tolist()))
        return graph

    build_time, graph = _timed_once(build)
    edges = f'nx.Graph, {graph.number_of_nodes()} nodes, {graph.number_of_edges()} edges'

    def octile(u: int, v: int) -> float:
        ur, uc = divmod(u, n)
        vr, vc = divmod(v, n)
        dr, dc = abs(ur - vr), abs(uc - vc)
        return dr + dc + _DIAGONAL_SAVING * min(dr, dc)

    progress(f'planning: {n} x {n}: NetworkX A* and Dijkstra')
    (times, cost), (dijkstra_times, dijkstra_cost) = alternate_runs(
        [lambda: nx.astar_path_length(graph, s, t, octile, 'weight'),
         lambda: nx.dijkstra_path_length(graph, s, t, 'weight')], case.repeats)
    case.add('networkx.astar_path_length', 8, times, cost, None,
             f'{edges}; octile heuristic', build_time)
    case.add('networkx.dijkstra_path_length', 8, dijkstra_times, dijkstra_cost, None,
             f'{edges}; stops at the goal', build_time)


def planning_benchmark(sizes: Sequence[int] = SIZES, repeats: int = REPEATS, seed: int = 0,
                       networkx: bool = True, progress: Progress = lambda message: None
                       ) -> list[PlanningRow]:
    """
    Return the rows of the planning benchmark: every method on every size (module docstring).

    Raises
    ------
    CostMismatch
        When a method's cost differs from ``grid_astar``'s (or a method finds no path).
    RuntimeError
        When NetworkX is asked for but not installed.

    """
    rows: list[PlanningRow] = []
    for size in sizes:
        blocked = random_grid(size, seed)
        grid = OccupancyGrid(np.where(blocked, 100, 0).astype(np.int8), RESOLUTION)
        case = _Case(size, blocked, repeats)
        _ours(case, blocked, grid, 8, progress)
        _scipy(case, blocked, 8, progress)
        if networkx:
            _networkx(case, blocked, progress)
        _ours(case, blocked, grid, 16, progress)
        _scipy(case, blocked, 16, progress, both=False)
        check_costs(case.rows)
        rows += case.rows
    return rows


def format_ms(value: Optional[float]) -> str:
    """Return milliseconds with 3 significant figures or so ('' for None)."""
    if value is None:
        return ''
    return f'{value:.1f}' if value >= 10.0 else f'{value:.2f}'


def format_planning_table(rows: Sequence[PlanningRow]) -> str:
    """Return the rows as a Markdown table (times in ms per search)."""
    lines = ['| grid | method | neighbours | min [ms] | median [ms] | runs | graph build [ms] '
             '| expansions | cost [cells] | goal | note |',
             '|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|']
    for r in rows:
        goal = '' if r.goal_ms is None else (
            f'< {format_ms(r.goal_ms)} ms: {"met" if r.goal_met else "**not met**"}')
        expansions = '' if r.expansions is None else str(r.expansions)
        lines.append(f'| {r.size}×{r.size} ({r.obstacles:.1%} occupied) | {r.method} '
                     f'| {r.neighbours} | {format_ms(r.min_ms)} | {format_ms(r.median_ms)} '
                     f'| {r.repeats} | {format_ms(r.build_ms)} | {expansions} | {r.cost:.6f} '
                     f'| {goal} | {r.note} |')
    return '\n'.join(lines)


def planning_rows_json(rows: Sequence[PlanningRow]) -> list[dict[str, Any]]:
    """Return the rows as JSON-ready dicts, with ``goal_met``."""
    return [{**dataclasses.asdict(row), 'goal_met': row.goal_met} for row in rows]
