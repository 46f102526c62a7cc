"""
What a planner returns: a path with its cost, or "no path" with the reason (book ch. 12).

A planner never hangs and never hides a failure: its work is bounded by a
:class:`SearchBudget` (expansions and wall time), and a search stopped by it says so in
``reason``. Paths are (N, 2) points [m] in the world frame, or (N, 3) postures (x, y, θ [rad])
for a planner that plans headings; ``directions`` (N - 1,) gives +1 forward / -1 reverse per
segment where a manoeuvre reverses (parking), else None.
"""

from dataclasses import dataclass, field
import math
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

__all__ = ['PlanResult', 'SearchBudget']


@dataclass(frozen=True)
class SearchBudget:
    """
    The bound on a planner's work: at most ``max_expansions`` nodes and ``max_seconds`` of time.

    The time is measured by the caller's clock function (pure code reads none): a planner takes
    ``clock`` (e.g. ``time.monotonic``) or counts expansions only.

    >>> SearchBudget().max_expansions
    10000000
    """

    max_expansions: int = 10_000_000   # nodes expanded (A*, Dijkstra) or iterations
    max_seconds: float = 30.0          # [s] of wall time, when a clock is given

    def __post_init__(self) -> None:
        if not (isinstance(self.max_expansions, int) and self.max_expansions > 0):
            raise ValueError(f'max_expansions must be an integer > 0, got '
                             f'{self.max_expansions!r}')
        if not (math.isfinite(self.max_seconds) and self.max_seconds > 0.0):
            raise ValueError(f'max_seconds must be finite and > 0 s, got {self.max_seconds!r}')


@dataclass(frozen=True)
class PlanResult:
    """
    A plan: ``path`` and ``cost``, or ``path`` None and the ``reason`` there is none.

    Attributes
    ----------
    path : ndarray (N, 2) or (N, 3), or None
        The points [m] (or postures x, y [m], θ [rad]) from start to goal, world frame.
    cost : float
        The path's cost (its length [m] unless the planner says otherwise); inf without a path.
    reason : str
        Why there is no path ('' when there is one): the goal in an obstacle, off the map,
        unreachable, the budget exhausted, ...
    expansions : int
        Nodes expanded (or iterations) by the search.
    directions : ndarray (N - 1,) or None
        +1 forward / -1 reverse per segment for a manoeuvre that reverses.
    details : dict
        Planner-specific results for markers and reports (expanded cells, the graph, ...).

    Examples
    --------
    >>> PlanResult.none('the goal is inside an obstacle').found
    False

    """

    path: Optional[NDArray[np.float64]]
    cost: float = math.inf
    reason: str = ''
    expansions: int = 0
    directions: Optional[NDArray[np.int8]] = None
    details: dict[str, Any] = field(default_factory=dict)

    @property
    def found(self) -> bool:
        """Return whether there is a path."""
        return self.path is not None

    @classmethod
    def none(cls, reason: str, expansions: int = 0, **details: Any) -> 'PlanResult':
        """Return "no path" for ``reason`` (one clear sentence)."""
        if not reason:
            raise ValueError('a plan without a path needs a reason')
        return cls(path=None, reason=reason, expansions=expansions, details=dict(details))
