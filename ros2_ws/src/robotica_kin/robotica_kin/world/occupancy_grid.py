"""
Cell occupancy grids (book §12.4.1): cells of one size, each free, occupied or unknown.

The layout is ROS's ``nav_msgs/OccupancyGrid``: ``data[i, j]`` is the cell of row i (from the
origin along the grid's y axis) and column j (along its x axis); the grid's frame is placed in
the map frame by ``origin`` = (x [m], y [m], yaw [rad]), the pose of the lower-left corner of
cell (0, 0). A cell holds -1 (unknown) or an occupancy probability in percent, 0..100; the
binary view :attr:`OccupancyGrid.occupied` is the cells at or above ``occupied_thresh``
(unknown cells are not occupied). Probabilistic grids (certainty grids, Moravec and Elfes
1985) keep their percentages; :func:`log_odds_update` is the Bayesian update of one
measurement in log-odds form.
"""

from dataclasses import dataclass
from functools import cached_property
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.world.errors import WorldError

__all__ = ['OccupancyGrid', 'log_odds_update']

UNKNOWN = -1


@dataclass(frozen=True, eq=False)
class OccupancyGrid:
    """
    An occupancy grid: data (rows, cols) int8, resolution [m/cell], origin (x, y, yaw).

    Validated once when built: int8 data in {-1} ∪ [0, 100], resolution > 0, a finite origin,
    0 <= free_thresh < occupied_thresh <= 1 (probabilities, map_server's thresholds).

    >>> grid = OccupancyGrid(np.array([[0, 100], [-1, 0]], dtype=np.int8), 0.5)
    >>> grid.occupied.tolist(), grid.width, grid.height
    ([[False, True], [False, False]], 2, 2)
    """

    data: NDArray[np.int8]
    resolution: float                                  # [m/cell]
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)   # lower-left corner (x, y, yaw)
    occupied_thresh: float = 0.65                      # probability at/above which occupied
    free_thresh: float = 0.196                         # probability below which free

    def __post_init__(self) -> None:
        data = np.asarray(self.data)
        if data.ndim != 2 or data.size == 0:
            raise WorldError(f'grid data must be a non-empty 2-D array, got shape {data.shape}')
        if data.dtype.kind not in 'iu':
            raise WorldError(f'grid data must be integers, got dtype {data.dtype}')
        if np.any((data < UNKNOWN) | (data > 100)):
            raise WorldError('grid data must be -1 (unknown) or 0..100 (occupancy percent)')
        data = data.astype(np.int8)
        data.flags.writeable = False
        object.__setattr__(self, 'data', data)
        if not (isinstance(self.resolution, (int, float)) and math.isfinite(self.resolution)
                and self.resolution > 0.0):
            raise WorldError(f'grid resolution must be > 0 m/cell, got {self.resolution!r}')
        origin = tuple(float(v) for v in self.origin)
        if len(origin) != 3 or not all(math.isfinite(v) for v in origin):
            raise WorldError(f'grid origin must be finite [x, y, yaw], got {self.origin!r}')
        object.__setattr__(self, 'origin', origin)
        object.__setattr__(self, 'resolution', float(self.resolution))
        if not 0.0 <= self.free_thresh < self.occupied_thresh <= 1.0:
            raise WorldError('grid thresholds must satisfy 0 <= free_thresh < occupied_thresh'
                             f' <= 1, got free_thresh {self.free_thresh!r}, occupied_thresh'
                             f' {self.occupied_thresh!r}')

    @property
    def height(self) -> int:
        """Return the number of rows (cells along the grid's y axis)."""
        return int(self.data.shape[0])

    @property
    def width(self) -> int:
        """Return the number of columns (cells along the grid's x axis)."""
        return int(self.data.shape[1])

    @cached_property
    def occupied(self) -> NDArray[np.bool_]:
        """Return the binary view: True where data >= 100 * occupied_thresh (not unknown)."""
        mask = self.data >= 100.0 * self.occupied_thresh
        mask.flags.writeable = False
        return mask

    @cached_property
    def occupied_padded(self) -> NDArray[np.bool_]:
        """Return :attr:`occupied` with a border of one free cell, flattened (ray casting)."""
        padded = np.zeros((self.height + 2, self.width + 2), dtype=bool)
        padded[1:-1, 1:-1] = self.occupied
        flat: NDArray[np.bool_] = padded.ravel()
        flat.flags.writeable = False
        return flat

    @cached_property
    def occupied_cells(self) -> NDArray[np.int64]:
        """Return the (col, row) (c, 2) of the occupied cells."""
        rows, cols = np.nonzero(self.occupied)
        return np.column_stack([cols, rows]).astype(np.int64)

    @cached_property
    def occupied_centres(self) -> NDArray[np.float64]:
        """Return the centres (c, 2) [m], map frame, of the occupied cells."""
        return self.cell_to_world(self.occupied_cells)

    @cached_property
    def occupied_tree(self) -> Any:
        """Return a k-d tree (scipy cKDTree) of :attr:`occupied_centres`, built once."""
        from scipy.spatial import cKDTree
        return cKDTree(self.occupied_centres)

    def world_to_grid(self, points: ArrayLike) -> NDArray[np.float64]:
        """
        Return points (k, 2) [m] of the map frame in continuous cell units (u, v) (k, 2).

        u along the grid's x axis, v along its y axis; cell (row i, col j) covers
        j <= u < j + 1, i <= v < i + 1.

        >>> OccupancyGrid(np.zeros((2, 2), np.int8), 0.5, (1.0, 0.0, 0.0)).world_to_grid(
        ...     [[1.75, 0.25]])
        array([[1.5, 0.5]])
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        rx, ry = p[:, 0] - x0, p[:, 1] - y0
        return np.column_stack([c * rx + s * ry, -s * rx + c * ry]) / self.resolution

    def world_to_cell(self, points: ArrayLike) -> NDArray[np.int64]:
        """
        Return the (col, row) (k, 2) of the cell holding each point [m]; may lie off the grid.

        >>> OccupancyGrid(np.zeros((2, 2), np.int8), 0.5).world_to_cell([[0.7, 0.2]])
        array([[1, 0]])
        """
        return np.floor(self.world_to_grid(points)).astype(np.int64)

    def cell_to_world(self, cells: ArrayLike) -> NDArray[np.float64]:
        """
        Return the centre [m], map frame, of each cell (col, row) (k, 2).

        >>> OccupancyGrid(np.zeros((2, 2), np.int8), 0.5).cell_to_world([[1, 0]])
        array([[0.75, 0.25]])
        """
        c_r = np.asarray(cells, dtype=np.float64).reshape(-1, 2) + 0.5
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        u, v = c_r[:, 0] * self.resolution, c_r[:, 1] * self.resolution
        return np.column_stack([x0 + c * u - s * v, y0 + s * u + c * v])

    def inside(self, cells: ArrayLike) -> NDArray[np.bool_]:
        """Return whether each cell (col, row) (k, 2) lies on the grid."""
        cr = np.asarray(cells).reshape(-1, 2)
        return np.asarray((cr[:, 0] >= 0) & (cr[:, 0] < self.width)
                          & (cr[:, 1] >= 0) & (cr[:, 1] < self.height))


def log_odds_update(prior: ArrayLike, measurement: ArrayLike) -> NDArray[np.float64]:
    """
    Return the occupancy probability after one measurement, by the log-odds (Bayes) update.

    ``prior`` and ``measurement`` are probabilities in (0, 1) (the inverse sensor model's
    p(occupied | z)), any matching shape; with a 0.5 prior of the grid,
    l = logit(prior) + logit(measurement) (certainty grids, Elfes 1987; book §12.4.1).

    >>> log_odds_update(0.5, 0.7).round(3), log_odds_update(0.7, 0.7).round(3)
    (np.float64(0.7), np.float64(0.845))
    """
    p = np.clip(np.asarray(prior, dtype=np.float64), 1e-9, 1 - 1e-9)
    m = np.clip(np.asarray(measurement, dtype=np.float64), 1e-9, 1 - 1e-9)
    log_odds = np.log(p / (1 - p)) + np.log(m / (1 - m))
    return np.asarray(1.0 / (1.0 + np.exp(-log_odds)))
