"""
Dijkstra's search of a roadmap (book §12.6.2): the last step of the graph planners.

The visibility graph and the Voronoi roadmap both end in a graph whose node 0 is the start S
and node 1 the goal G, with edges weighted by their length; :func:`roadmap_path` searches it
with ``scipy.sparse.csgraph.dijkstra`` and returns the shortest chain as a
:class:`~.plan_result.PlanResult`.
"""

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.planning.plan_result import PlanResult
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

__all__ = ['roadmap_path']


def roadmap_path(nodes: NDArray[np.float64], pairs: NDArray[np.intp], expansions: int,
                 details: dict[str, Any], unreachable: str) -> PlanResult:
    """
    Return the shortest path from node 0 to node 1 of an undirected roadmap.

    Parameters
    ----------
    nodes : ndarray, shape (n, 2)
        Node positions [m], map frame; S is node 0, G node 1.
    pairs : ndarray of int, shape (e, 2)
        The edges (i, j), each once; an edge's weight is its length (zero-length ones, between
        copies of one point, are left out).
    expansions : int
        The work the planner did, reported in the result.
    details : dict
        The planner's details, passed on.
    unreachable : str
        The reason when no chain of edges joins S to G.

    Returns
    -------
    PlanResult
        ``path`` (k, 2) [m] and ``cost`` its length [m], or none with ``unreachable``.

    Examples
    --------
    >>> nodes = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, -3.0]])
    >>> roadmap_path(nodes, np.array([[0, 2], [2, 1], [0, 3], [3, 1]]), 4, {}, 'none').path
    array([[0., 0.],
           [1., 1.],
           [2., 0.]])

    """
    lengths = np.hypot(*(nodes[pairs[:, 1]] - nodes[pairs[:, 0]]).T)
    keep = lengths > 0.0
    graph = csr_matrix((lengths[keep], (pairs[keep, 0], pairs[keep, 1])),
                       shape=(len(nodes), len(nodes)))
    distance, previous = dijkstra(graph, directed=False, indices=0, return_predecessors=True)
    if not math.isfinite(distance[1]):
        return PlanResult.none(unreachable, expansions, **details)
    chain = [1]
    while chain[-1] != 0:
        chain.append(int(previous[chain[-1]]))
    path = nodes[chain[::-1]]
    return PlanResult(path, float(np.hypot(*np.diff(path, axis=0).T).sum()),
                      expansions=expansions, details=details)
