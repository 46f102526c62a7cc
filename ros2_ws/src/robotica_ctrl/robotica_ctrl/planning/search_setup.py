"""
What every planner of this package does before and while it searches (book §12.6-§12.7).

* :func:`planar_point` checks a start or goal (x, y) [m] of the map frame, and
  :func:`robot_radius` a circular robot's radius (ValueError, one message naming it);
  :data:`IN_OBSTACLE` words the reason when either end lies in an obstacle;
* :class:`BudgetMeter` holds a :class:`~.plan_result.SearchBudget` against the work done: the
  expansions counted by the planner and, when the caller gives a ``clock`` (a function returning
  seconds, e.g. ``time.monotonic``; the pure core reads none), the time since the search began.
  Its :meth:`BudgetMeter.exhausted` is the reason a search must stop, or '' while it may go on.
"""

import math
from typing import Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_ctrl.planning.plan_result import SearchBudget

__all__ = ['BudgetMeter', 'Clock', 'IN_OBSTACLE', 'planar_point', 'robot_radius']

Clock = Callable[[], float]
"""A function returning the time [s] (monotonic): the time bound of a search is read from it."""


IN_OBSTACLE = {'start': 'the start is in collision', 'goal': 'the goal is in an obstacle'}
"""How a "no path" reason begins when the start or the goal lies in an obstacle."""


def planar_point(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """
    Return ``value`` as a finite point (x, y) [m], shape (2,), or raise ValueError naming it.

    >>> planar_point('start', [1, 2])
    array([1., 2.])
    >>> planar_point('goal', [1.0, float('nan')])
    Traceback (most recent call last):
    ...
    ValueError: goal must be a finite point (x, y) [m], got [1.0, nan]
    """
    try:
        point = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        point = np.full(1, np.nan)
    if point.shape != (2,) or not np.isfinite(point).all():
        raise ValueError(f'{name} must be a finite point (x, y) [m], got {value!r}')
    return point


def robot_radius(value: float) -> float:
    """
    Return a circular robot's radius r [m] >= 0 as a float, or raise ValueError.

    >>> robot_radius(0), robot_radius(0.25)
    (0.0, 0.25)
    """
    if not (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value) and value >= 0.0):
        raise ValueError(f'robot_radius must be >= 0 m, got {value!r}')
    return float(value)


class BudgetMeter:
    """
    The work of one search against its :class:`SearchBudget` (expansions and clock time).

    >>> meter = BudgetMeter(SearchBudget(max_expansions=10))
    >>> meter.exhausted(9), meter.exhausted(10)
    ('', 'the search budget was exhausted: 10 expansions, the most allowed')
    """

    def __init__(self, budget: SearchBudget, clock: Optional[Clock] = None) -> None:
        if not isinstance(budget, SearchBudget):
            raise ValueError(f'budget must be a SearchBudget, got {type(budget).__name__}')
        if clock is not None and not callable(clock):
            raise ValueError(f'clock must be a function returning seconds, got {clock!r}')
        self.budget = budget
        self.clock = clock
        self.started = clock() if clock is not None else math.nan

    def elapsed(self) -> float:
        """Return the seconds since the search began by the clock (nan without a clock)."""
        return self.clock() - self.started if self.clock is not None else math.nan

    def exhausted(self, expansions: int) -> str:
        """Return why the search must stop after ``expansions``, or '' if it may go on."""
        if expansions >= self.budget.max_expansions:
            return f'the search budget was exhausted: {expansions} expansions, the most allowed'
        return self.overtime(f' (after {expansions} expansions)')

    def overtime(self, after: str = '') -> str:
        """Return why the search must stop for its time (``after`` appended), or ''."""
        elapsed = self.elapsed()
        if elapsed > self.budget.max_seconds:
            return (f'the search budget was exhausted: {elapsed:.3g} s, more than the '
                    f'{self.budget.max_seconds:g} s allowed{after}')
        return ''
