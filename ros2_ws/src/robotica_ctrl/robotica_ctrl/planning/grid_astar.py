"""
A* on an occupancy grid, as the book's algorithm (§12.6.2, (12.1); seed catalogue Part 10.5).

The cost of a cell x is f(x) = g(x) + h(x) (12.1): g the cost of the best path found from the
start S, h an estimate of the rest to the goal G. The book's algorithm keeps an open list LA
and a closed list LC:

1. compute f(S) and put S in LA;
2. take the x of least f out of LA and put it in LC;
3. stop if x = G (the path is the chain of parent pointers from G back to S);
4. for each neighbour x_i of x: (a) in LA with a smaller new g: update its g, f and parent
   pointer; (b) in LC with a smaller new g: redirect its pointer to x; (c) in neither:
   compute f and put it in LA;
5. LA empty: there is no path; 6. go to 2.

Here LA is a binary heap with lazy deletion (step 4a pushes the better entry; the stale one is
skipped when it surfaces, being closed by then) and LC an array of flags, so a step costs
O(log |LA|). Ties of f go to the smaller h (the deeper cell), which expands far fewer cells on
open ground. The neighbours (8 or 16, the book's 2-D choices) are the moves to the centre of an
adjacent cell, of cost 1 (along a row or column), √2 (diagonal) and, with 16, √5 (the
"knight's" moves (±1, ±2), (±2, ±1)) cells. A move is allowed when the straight segment between
the two centres meets free cells only: a diagonal needs both cells beside it free (no cutting a
corner of an obstacle), a knight's move the two cells its segment crosses. Only collision-free
cells are expanded (the book's rule).

h is the octile distance with 8 neighbours, the Euclidean distance with 16 (the octile one
overestimates a knight's move): both never overestimate and are consistent, so the first path
to reach G is the shortest on the grid's graph and step 4b never applies; with
``weight`` w > 1 (f = g + w h, weighted A*) the path costs at most w times the optimum, the
search expands fewer cells, and step 4b redirects pointers (counted in the details).

Obstacles of an :class:`~robotica_kin.world.OccupancyGrid` (:func:`grid_obstacles`): cells at
or above the occupancy threshold (percent, the grid's ``occupied_thresh`` by default) and,
unless told otherwise, the unknown ones (-1); a circular robot of radius r is planned as a
point among obstacles grown by r (§12.4.4, :func:`robotica_kin.world.grow`).
"""

from heapq import heappop, heappush
import math
from typing import Any, Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_ctrl.planning.search_setup import (BudgetMeter, Clock, IN_OBSTACLE, planar_point,
                                                 robot_radius as radius_value)
from robotica_kin.world import grow, OccupancyGrid, World

__all__ = ['NEIGHBOURHOODS', 'astar_cells', 'grid_astar', 'grid_moves', 'grid_obstacles']

NEIGHBOURHOODS = (8, 16)
"""The neighbourhoods of the book in 2-D."""

_REDIRECT_TOLERANCE = 1e-9   # [cells] a closed cell's g must improve by more to redirect (4b)
_CLOCK_EVERY = 1024          # expansions between two readings of the clock


def grid_moves(neighbours: int) -> list[tuple[int, int, tuple[tuple[int, int], ...]]]:
    """
    Return the moves (Δcol, Δrow, cells the segment crosses besides its ends) of a neighbourhood.

    Each move goes from a cell's centre to another's; it is allowed when the destination and
    every listed cell (offsets from the origin cell) are free.

    >>> [m for m in grid_moves(8) if m[:2] == (1, 1)]
    [(1, 1, ((1, 0), (0, 1)))]
    >>> [m for m in grid_moves(16) if m[:2] == (2, 1)]
    [(2, 1, ((1, 0), (1, 1)))]
    """
    if neighbours not in NEIGHBOURHOODS:
        raise ValueError(f'neighbours must be 8 or 16, got {neighbours!r}')
    moves: list[tuple[int, int, tuple[tuple[int, int], ...]]] = []
    for dc, dr in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        moves.append((dc, dr, ()))
    for dc in (1, -1):
        for dr in (1, -1):
            moves.append((dc, dr, ((dc, 0), (0, dr))))
    if neighbours == 16:
        for dc, dr in ((2, 1), (2, -1), (-2, 1), (-2, -1)):
            moves.append((dc, dr, ((dc // 2, 0), (dc // 2, dr))))
        for dc, dr in ((1, 2), (-1, 2), (1, -2), (-1, -2)):
            moves.append((dc, dr, ((0, dr // 2), (dc, dr // 2))))
    return moves


def grid_obstacles(grid: OccupancyGrid, occupied_threshold: Optional[int] = None,
                   unknown_is_obstacle: bool = True, robot_radius: float = 0.0
                   ) -> NDArray[np.bool_]:
    """
    Return the cells (rows, cols) a point robot may not enter: True for an obstacle.

    Parameters
    ----------
    grid : OccupancyGrid
        The map (cells -1 unknown or 0..100 percent occupied).
    occupied_threshold : int, optional
        Cells with occupancy >= this [%] are obstacles; default 100 * ``grid.occupied_thresh``.
    unknown_is_obstacle : bool
        Whether the unknown cells (-1) are obstacles.
    robot_radius : float
        r [m] >= 0: the obstacles grown by r (§12.4.4; a cell joins them when its square comes
        within r of an obstacle cell's, :func:`robotica_kin.world.grow`).

    Examples
    --------
    >>> grid = OccupancyGrid(np.array([[0, 70, -1], [0, 50, 0]], np.int8), 1.0)
    >>> grid_obstacles(grid).astype(int).tolist()
    [[0, 1, 1], [0, 0, 0]]
    >>> grid_obstacles(grid, 50, False).astype(int).tolist()
    [[0, 1, 0], [0, 1, 0]]

    """
    if not isinstance(grid, OccupancyGrid):
        raise ValueError(f'grid must be an OccupancyGrid, got {type(grid).__name__}')
    if occupied_threshold is None:
        threshold = 100.0 * grid.occupied_thresh
    elif isinstance(occupied_threshold, (int, np.integer)) and 0 <= occupied_threshold <= 100:
        threshold = float(occupied_threshold)
    else:
        raise ValueError(f'occupied_threshold must be an integer in 0..100 [%], got '
                         f'{occupied_threshold!r}')
    radius = radius_value(robot_radius)
    blocked = grid.data >= threshold
    if unknown_is_obstacle:
        blocked |= grid.data < 0
    if radius > 0.0 and blocked.any():
        binary = OccupancyGrid(np.where(blocked, 100, 0).astype(np.int8), grid.resolution,
                               grid.origin, grid.occupied_thresh, grid.free_thresh)
        grown = grow(World(grid=binary), radius).grid
        assert grown is not None
        blocked = grown.occupied.copy()
    return np.asarray(blocked)


def _allowed_moves(free: NDArray[np.bool_], moves: Sequence[tuple[int, int, tuple[
        tuple[int, int], ...]]], pad: int) -> NDArray[np.uint16]:
    """Return, per cell of the grid padded by ``pad`` blocked cells, the bits of its moves."""
    rows, cols = free.shape
    padded = np.zeros((rows + 2 * pad, cols + 2 * pad), dtype=bool)
    padded[pad:pad + rows, pad:pad + cols] = free

    def shifted(dc: int, dr: int) -> NDArray[np.bool_]:
        return padded[pad + dr:pad + dr + rows, pad + dc:pad + dc + cols]

    masks = np.zeros(padded.shape, dtype=np.uint16)
    inner = masks[pad:pad + rows, pad:pad + cols]
    for bit, (dc, dr, crossed) in enumerate(moves):
        allowed = free & shifted(dc, dr)
        for cc, cr in crossed:
            allowed &= shifted(cc, cr)
        inner |= allowed.astype(np.uint16) << np.uint16(bit)
    return masks


def _endpoint_reason(blocked: NDArray[np.bool_], cell: tuple[int, int], role: str,
                     label: str) -> str:
    rows, cols = blocked.shape
    c, r = cell
    if not (0 <= c < cols and 0 <= r < rows):
        return f'the {role} {label} is off the map ({cols} x {rows} cells)'
    if blocked[r, c]:
        return f'{IN_OBSTACLE[role]}: {label} is an obstacle cell'
    return ''


def _as_cell(name: str, value: ArrayLike) -> tuple[int, int]:
    cell = np.asarray(value)
    if cell.shape != (2,) or cell.dtype.kind not in 'iu':
        raise ValueError(f'{name} must be an integer cell (col, row), got {value!r}')
    return int(cell[0]), int(cell[1])


def astar_cells(blocked: ArrayLike, start: ArrayLike, goal: ArrayLike, neighbours: int = 8,
                weight: float = 1.0, budget: SearchBudget = SearchBudget(),
                clock: Optional[Clock] = None,
                labels: tuple[str, str] = ('', '')) -> PlanResult:
    """
    Return the A* path between two cells of a boolean grid, in cell units (book (12.1)).

    Parameters
    ----------
    blocked : array_like of bool, shape (rows, cols)
        True for the cells that may not be entered; row i, column j as in an OccupancyGrid.
    start, goal : array_like of int, shape (2,)
        Cells (col, row).
    neighbours : int
        8 or 16 (see the module's docstring for the moves and their costs).
    weight : float
        w >= 1 of f = g + w h (1: A*, optimal).
    budget : SearchBudget
        At most ``max_expansions`` cells expanded and ``max_seconds`` by ``clock``.
    clock : callable, optional
        Returns the time [s]; without it only expansions are bounded.
    labels : (str, str)
        How the reasons name the start and the goal (default: their cells).

    Returns
    -------
    PlanResult
        ``path`` (k, 2) cells (col, row) as floats from start to goal and ``cost`` its length
        [cells]; or none with the reason: an end off the grid or blocked, no free cell, the
        goal unreachable, the budget exhausted. ``details``: ``expanded`` (e, 2) the cells
        (col, row) in the order they entered LC, ``redirections`` (step 4b),
        ``neighbours``, ``weight``.

    Raises
    ------
    ValueError
        For a grid that is not 2-D and non-empty, a cell that is not two integers, a
        neighbourhood other than 8 or 16, or a weight below 1.

    Examples
    --------
    Around the end of a wall (row 1, columns 0-1), without cutting its corner:

    >>> wall = np.zeros((3, 3), bool); wall[1, 0:2] = True
    >>> plan = astar_cells(wall, [0, 0], [0, 2])
    >>> plan.path.astype(int).tolist(), plan.cost
    ([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2]], 6.0)

    """
    grid = np.asarray(blocked)
    if grid.ndim != 2 or grid.size == 0 or grid.dtype != np.bool_:
        raise ValueError(f'blocked must be a non-empty 2-D bool array, got {grid.dtype} '
                         f'of shape {grid.shape}')
    moves = grid_moves(neighbours)
    if not (isinstance(weight, (int, float)) and math.isfinite(weight) and weight >= 1.0):
        raise ValueError(f'weight must be >= 1, got {weight!r}')
    s, g = _as_cell('start', start), _as_cell('goal', goal)
    meter = BudgetMeter(budget, clock)
    for cell, role, label in ((s, 'start', labels[0]), (g, 'goal', labels[1])):
        reason = _endpoint_reason(grid, cell, role, label or f'cell {cell}')
        if reason and grid.all():
            return PlanResult.none(f'the map has no free cell ({reason})')
        if reason:
            return PlanResult.none(reason)
    details: dict[str, Any] = {'neighbours': neighbours, 'weight': float(weight)}
    if s == g:
        return PlanResult(np.array([s], dtype=np.float64), 0.0, expansions=0,
                          details={**details, 'expanded': np.array([s]), 'redirections': 0})
    return _search(grid, s, g, moves, float(weight), meter, details)


def _search(blocked: NDArray[np.bool_], start: tuple[int, int], goal: tuple[int, int],
            moves: list[tuple[int, int, tuple[tuple[int, int], ...]]], weight: float,
            meter: BudgetMeter, details: dict[str, Any]) -> PlanResult:
    """Run steps 1-6 of the book's A* on a grid padded by blocked cells (no bounds checks)."""
    pad = 2 if len(moves) > 8 else 1
    rows, cols = blocked.shape
    width = cols + 2 * pad
    masks = _allowed_moves(~blocked, moves, pad).ravel()
    offsets = [dr * width + dc for dc, dr, _ in moves]
    costs = [math.hypot(dc, dr) for dc, dr, _ in moves]
    table: list[tuple[tuple[int, float], ...]] = [()] * (1 << len(moves))   # moves by mask
    for m in np.flatnonzero(np.bincount(masks, minlength=len(table))):
        table[m] = tuple((offsets[k], costs[k]) for k in range(len(moves)) if m >> k & 1)
    n = masks.size
    s = (start[1] + pad) * width + start[0] + pad
    t = (goal[1] + pad) * width + goal[0] + pad
    goal_row, goal_col = divmod(t, width)
    octile = len(moves) == 8
    diagonal_saving = math.sqrt(2.0) - 2.0                    # octile: dr + dc - (2 - √2) min
    mask_of = masks.tolist()
    g_of = [math.inf] * n
    parent = [-1] * n
    closed = bytearray(n)
    expanded: list[int] = []
    expand = expanded.append
    pop, push = heappop, heappush
    max_expansions = meter.budget.max_expansions
    check_every = _CLOCK_EVERY if meter.clock is not None else max_expansions
    count = 0
    redirections = 0
    g_of[s] = 0.0
    heap = [(0.0, 0.0, s)]
    found = False
    reason = ''
    while heap:                                               # 5: LA empty -> no path
        x = pop(heap)[2]                                      # 2: least f out of LA ...
        if closed[x]:
            continue                                          # a stale entry (lazy deletion)
        closed[x] = 1                                         # ... into LC
        expand(x)
        if x == t:                                            # 3
            found = True
            break
        count += 1
        if count >= max_expansions or not count % check_every:
            reason = meter.exhausted(count)
            if reason:
                break
        gx = g_of[x]
        for offset, cost in table[mask_of[x]]:                # 4: the allowed neighbours
            y = x + offset
            g_new = gx + cost
            if g_new < g_of[y]:
                if closed[y]:                                  # 4b: redirect the pointer
                    if g_new < g_of[y] - _REDIRECT_TOLERANCE:
                        g_of[y] = g_new
                        parent[y] = x
                        redirections += 1
                    continue
                g_of[y] = g_new                                # 4a / 4c
                parent[y] = x
                row, col = divmod(y, width)
                dr = abs(row - goal_row)
                dc = abs(col - goal_col)
                if octile:
                    h = weight * (dr + dc + diagonal_saving * (dr if dr < dc else dc))
                else:
                    h = weight * math.sqrt(dr * dr + dc * dc)
                push(heap, (g_new + h, h, y))
    flat = np.array(expanded, dtype=np.int64)
    details['expanded'] = np.column_stack([flat % width - pad, flat // width - pad])
    details['redirections'] = redirections
    if reason:
        return PlanResult.none(reason, len(expanded), **details)
    if not found:
        return PlanResult.none(
            f'the goal is unreachable: the open list emptied after {len(expanded)} expansions',
            len(expanded), **details)
    chain = [t]
    while chain[-1] != s and len(chain) <= n:
        chain.append(parent[chain[-1]])
    cells = np.array(chain[::-1], dtype=np.int64)
    path = np.column_stack([cells % width - pad, cells // width - pad]).astype(np.float64)
    steps = np.diff(path, axis=0)
    cost = float(np.hypot(steps[:, 0], steps[:, 1]).sum())
    return PlanResult(path, cost, expansions=len(expanded), details=details)


def grid_astar(grid: OccupancyGrid, start: ArrayLike, goal: ArrayLike, neighbours: int = 8,
               robot_radius: float = 0.0, occupied_threshold: Optional[int] = None,
               unknown_is_obstacle: bool = True, weight: float = 1.0,
               budget: SearchBudget = SearchBudget(), clock: Optional[Clock] = None
               ) -> PlanResult:
    """
    Return the A* path between two points of an occupancy grid's map (book §12.6.2, (12.1)).

    Parameters
    ----------
    grid : OccupancyGrid
        The map.
    start, goal : array_like, shape (2,)
        Points (x, y) [m] in the map frame; each is planned from the cell that holds it.
    neighbours, weight, budget, clock
        As :func:`astar_cells`.
    robot_radius, occupied_threshold, unknown_is_obstacle
        What is an obstacle, as :func:`grid_obstacles` (r [m], a threshold [%], a flag).

    Returns
    -------
    PlanResult
        ``path`` (k, 2) [m]: the centres of the cells from the start's to the goal's, map
        frame; ``cost`` its length [m]. None with the reason for an end off the map or in an
        obstacle, no free cell, an unreachable goal, the budget exhausted. ``details`` as
        :func:`astar_cells` plus ``cells`` (k, 2) (col, row) of the path and ``obstacles``
        (rows, cols) bool, the cells planned around.

    Raises
    ------
    ValueError
        For a non-finite start or goal, or bad options.

    Examples
    --------
    >>> free = OccupancyGrid(np.zeros((4, 4), np.int8), 0.5)
    >>> plan = grid_astar(free, [0.1, 0.1], [1.9, 0.1])
    >>> plan.path.tolist(), plan.cost
    ([[0.25, 0.25], [0.75, 0.25], [1.25, 0.25], [1.75, 0.25]], 1.5)
    >>> grid_astar(free, [0.1, 0.1], [2.5, 0.1]).reason
    'the goal (2.5, 0.1) m is off the map (4 x 4 cells)'

    """
    p_start, p_goal = planar_point('start', start), planar_point('goal', goal)
    blocked = grid_obstacles(grid, occupied_threshold, unknown_is_obstacle, robot_radius)
    cells = grid.world_to_cell(np.vstack([p_start, p_goal]))
    labels = (f'({p_start[0]:g}, {p_start[1]:g}) m', f'({p_goal[0]:g}, {p_goal[1]:g}) m')
    plan = astar_cells(blocked, cells[0], cells[1], neighbours, weight, budget, clock, labels)
    details = {**plan.details, 'obstacles': blocked}
    if not plan.found:
        return PlanResult.none(plan.reason, plan.expansions, **details)
    assert plan.path is not None
    path_cells = plan.path.astype(np.int64)
    details['cells'] = path_cells
    return PlanResult(grid.cell_to_world(path_cells), plan.cost * grid.resolution,
                      expansions=plan.expansions, details=details)
