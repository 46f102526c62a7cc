"""
Batch grading: many bags graded at once on a Dask cluster (``robotica grade FOLDER``).

Each bag is one task of :func:`robotica_sim.grading.entry.grade_bag` (the same entry as for
one bag; a bag that cannot be read is an ``error`` entry, it does not stop the others).
"""
from functools import partial
from pathlib import Path
from typing import Callable, Optional, Sequence, TYPE_CHECKING

from robotica_sim.batch.cluster import map_on_cluster
from robotica_sim.grading.entry import grade_bag
from robotica_sim.grading.rubric import Rubric

if TYPE_CHECKING:
    from distributed import Client

__all__ = ['grade_bags']


def grade_bags(client: 'Client', bags: Sequence[Path], rubric: Optional[Rubric],
               progress: Optional[Callable[[int, dict], None]] = None) -> list[dict]:
    """Return the entries of ``bags`` (in their order), graded on ``client``'s cluster."""
    # Largest bags first, so that the last one to finish is a small one.
    order = sorted(range(len(bags)), key=lambda i: -sum(
        f.stat().st_size for f in bags[i].iterdir() if f.is_file()))
    graded = map_on_cluster(client, partial(grade_bag, rubric=rubric),
                            [bags[i] for i in order],
                            [f'grade-{bags[i].name}-{i}' for i in order], progress)
    entries: list[dict] = [{}] * len(bags)
    for i, entry in zip(order, graded):
        entries[i] = entry
    return entries
