"""
The planners by name, with their options as node parameters: the planner node's registry.

The ``planner`` node plans with :func:`plan_path` on a :class:`~robotica_kin.world.shapes.World`
(a scenario's world or the ``/map`` grid): the method named by ``method``, the obstacles grown by
``robot_radius``, the work bounded by ``max_expansions`` and ``max_seconds``, and, with
``smooth``, the path shortened by line of sight and smoothed for a disc of ``robot_radius``
(:mod:`.path_shortcut`, :mod:`.path_smoothing`), never into an obstacle: a step that cannot
keep the path free (the grid's path may graze an obstacle of the world's exact geometry) leaves
it as it was, and ``details['smoothing']`` says why. With ``max_curvature`` (a steered
vehicle) the shortcut path's corners become clothoid turns within κ_max
(:mod:`.continuous_curvature`: poses (x, y, θ), swept free), or there is no path and the reason.

==================== ========================================================= ==============
method               planner                                                   book
==================== ========================================================= ==============
``astar``            :func:`~.grid_astar.grid_astar` on the world's grid       §12.6.2, (12.1)
``visibility_graph`` :func:`~.visibility_graph.visibility_graph` (+ Dijkstra)  §12.6.2
``voronoi``          :func:`~.voronoi_roadmap.voronoi_roadmap`                 §12.6.2
``potential``        :func:`~.potential_planner.potential_planner`, Krogh      (12.3)-(12.8)
``vff``              :func:`~.potential_planner.potential_planner`, VFF        (12.9)-(12.15)
==================== ========================================================= ==============

The geometric planners (visibility graph, Voronoi) need a world of walls, polygons and circles;
a map grid is planned on with A* (or the potential fields). A potential planner that stalls in
a local minimum says so in its reason: the trap is reported, never hidden.
"""
from typing import Any, Mapping, Optional

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.mobile.reactive import GeneralisedPotentialParams, VirtualForceFieldParams
from robotica_kin.parameter_specs import parameter_values, ParameterError, ParameterSpec
from robotica_kin.world.rasterise import world_as_grid
from robotica_kin.world.shapes import World

from .continuous_curvature import continuous_curvature_path
from .grid_astar import grid_astar
from .path_shortcut import shortcut_path
from .path_smoothing import smooth_path
from .plan_result import PlanResult, SearchBudget
from .potential_planner import potential_planner, PotentialPlannerParams
from .search_setup import Clock
from .visibility_graph import visibility_graph
from .voronoi_roadmap import voronoi_roadmap

__all__ = ['PLANNER_METHODS', 'PLANNER_PARAMETERS', 'plan_path', 'planner_options']

PLANNER_METHODS = ('astar', 'visibility_graph', 'voronoi', 'potential', 'vff')
PLANNER_PARAMETERS: dict[str, ParameterSpec] = {
    'method': ParameterSpec('astar', "The planner (book ch. 12); parking: the course's "
                            "parallel parking (the planner node's parking mode)",
                            choices=(*PLANNER_METHODS, 'parking')),
    'robot_radius': ParameterSpec(0.3, 'Radius of the robot [m]: obstacles are grown by it '
                                  '(§12.4.4)', 0.0, 100.0),
    'neighbours': ParameterSpec(8, 'A*: 8 or 16 neighbours of a cell (§12.6.2)', 8, 16),
    'resolution': ParameterSpec(0.05, 'Cell size [m] of the grid drawn from a world without '
                                'one', 0.001, 10.0),
    'unknown_is_obstacle': ParameterSpec(True, 'Plan around unknown cells (-1) of a map'),
    'smooth': ParameterSpec(True, 'Shorten the path by line of sight and smooth it, keeping '
                            'robot_radius of clearance'),
    'max_curvature': ParameterSpec(0.0, 'kappa_max [1/m] of a steered vehicle, tan(phi_max)/L: '
                                   'the path gets clothoid turns within it (§10.4); 0: none',
                                   0.0, 1e3),
    'max_sharpness': ParameterSpec(1.0, 'sigma_max [1/m^2], the largest change of curvature '
                                   'per metre of the clothoid turns', 1e-6, 1e6),
    'field_step': ParameterSpec(0.25, 'potential, vff: lattice [m] on which the direction of '
                                'the resultant force is drawn (details field, the markers); 0: '
                                'none', 0.0, 100.0),
    'max_expansions': ParameterSpec(2_000_000, 'Bound on the nodes a search expands', 1,
                                    1_000_000_000),
    'max_seconds': ParameterSpec(5.0, 'Bound on the time of a search [s]', 1e-3, 3600.0),
}
"""The planner node's planning parameters (the options of :func:`plan_path`)."""


def planner_options(options: Mapping[str, Any]) -> dict[str, Any]:
    """
    Return ``options`` (names of :data:`PLANNER_PARAMETERS`) checked, missing ones defaulted.

    Raises ParameterError (by name) for a value out of its range or choices, or a number of
    neighbours other than 8 or 16.

    >>> planner_options({'neighbours': 16})['method']
    'astar'
    """
    values = parameter_values(PLANNER_PARAMETERS, dict(options))
    if values['neighbours'] not in (8, 16):
        raise ParameterError('neighbours', f"must be 8 or 16, got {values['neighbours']}")
    return values


def plan_path(world: World, start: ArrayLike, goal: ArrayLike,
              options: Optional[Mapping[str, Any]] = None,
              clock: Optional[Clock] = None) -> PlanResult:
    """
    Return the plan from ``start`` to ``goal`` (x, y [m], map frame) in ``world``.

    ``options`` by the names of :data:`PLANNER_PARAMETERS` (missing ones default); ``clock``
    (seconds, e.g. ``time.monotonic``) bounds the search's time, which the pure core reads from
    no clock of its own.

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For an option out of its range or choices.
    ValueError
        For a start or goal that is not a finite point.

    Examples
    --------
    >>> from robotica_kin.world.shapes import make_world
    >>> room = make_world(walls=[[0, 0, 4, 0], [4, 0, 4, 4], [4, 4, 0, 4], [0, 4, 0, 0],
    ...                          [2, 0, 2, 3]])
    >>> plan = plan_path(room, [1.0, 1.0], [3.0, 1.0], {'robot_radius': 0.2})
    >>> plan.found, round(plan.cost, 1) > 4.0
    (True, True)

    """
    o = planner_options(options or {})
    budget = SearchBudget(int(o['max_expansions']), float(o['max_seconds']))
    method, radius = o['method'], o['robot_radius']
    if method == 'parking':
        return PlanResult.none('parking plans into a space found on a pass, not to a goal: '
                               "the planner node's parking mode (planning.parking)")
    if method in ('visibility_graph', 'voronoi') and world.grid is not None:
        return PlanResult.none(f'{method} plans among walls, polygons and circles: this world '
                               'is a grid (use astar)')
    if method == 'visibility_graph':
        result = visibility_graph(world, start, goal, radius, budget=budget, clock=clock)
    elif method == 'voronoi':
        result = voronoi_roadmap(world, start, goal, radius, budget=budget, clock=clock)
    elif method in ('potential', 'vff'):
        # VFF sums the repulsion of every certainty cell (0.1 m) in its window: the reactive
        # law's gain, tuned for a laser's returns, stalls it; the planner's is the tests'.
        law = GeneralisedPotentialParams() if method == 'potential' else \
            VirtualForceFieldParams(repulsive_gain=0.02, window_radius=1.0)
        return potential_planner(world, start, goal, law,
                                 PotentialPlannerParams(robot_radius=max(radius, 1e-3),
                                                        field_step=float(o['field_step'])),
                                 budget, clock)
    else:
        grid = world_as_grid(world, o['resolution'])
        result = grid_astar(grid, start, goal, int(o['neighbours']), radius,
                            unknown_is_obstacle=o['unknown_is_obstacle'], budget=budget,
                            clock=clock)
        result.details['grid'] = grid   # the grid of the expanded cells (the node draws them)
    if not result.found or not o['smooth'] or result.path is None or len(result.path) < 3:
        return result
    footprint = max(o['robot_radius'], 1e-3)
    path, steps = result.path, []
    curved = o['max_curvature'] > 0.0   # clothoid turns round the shortcut's corners instead
    for improve in (shortcut_path,) if curved else (shortcut_path, smooth_path):
        better = improve(world, path, footprint, budget=budget, clock=clock)
        steps.append(better.reason or 'done')
        if better.found and better.path is not None:   # else keep the path as it is
            path = better.path
    details = {**result.details, 'raw_path': result.path, 'smoothing': steps}
    if curved:   # a steered vehicle: clothoid turns, swept free, or no path
        curved = continuous_curvature_path(path, o['max_curvature'], o['max_sharpness'],
                                           world=world, footprint=footprint)
        if not curved.found:
            return PlanResult.none(f'no path within the curvature bound: {curved.reason}',
                                   result.expansions, **details)
        return PlanResult(curved.path, curved.cost, '', result.expansions, None,
                          {**details, **curved.details})
    length = float(np.sum(np.hypot(*np.diff(path, axis=0).T)))
    return PlanResult(path, length, '', result.expansions, None, details)
