"""
A world drawn as an occupancy grid: what ``/map`` (nav_msgs/OccupancyGrid) publishes of it.

The geometric obstacles (walls, polygons, circles) are drawn into a grid of ``resolution``
covering their extent plus ``margin``: a cell is occupied (100) when an obstacle comes within
half the cell's diagonal of its centre, free (0) otherwise (book §12.4.1, cell occupancy). So
every cell an obstacle crosses is occupied (a wall never falls between cells), and so are a
few it passes near a corner: the drawing is for seeing and for grid planners, which must not
find a gap that is not there. A world with a grid of its own has its cells drawn as they are.
"""
import math

import numpy as np
from robotica_kin.world.errors import WorldError
from robotica_kin.world.occupancy_grid import OccupancyGrid
from robotica_kin.world.queries import distance_to_obstacles
from robotica_kin.world.shapes import World

__all__ = ['MAX_CELLS', 'world_as_grid', 'world_grid']

MAX_CELLS = 4_000_000   # of a drawn grid (2000 x 2000): beyond it, raise the resolution


def world_grid(world: World, resolution: float = 0.05, margin: float = 0.5) -> OccupancyGrid:
    """
    Return the occupancy grid of ``world`` at ``resolution`` [m/cell], ``margin`` [m] around.

    Raises
    ------
    WorldError
        If the world is empty, the resolution is not > 0, or the grid would have more than
        :data:`MAX_CELLS` cells.

    Examples
    --------
    A wall along the line between two rows of cells occupies both rows (each cell's square
    touches it; the end cells touch its ends at their corners):

    >>> grid = world_grid(World(walls=[[0.0, 0.0, 1.0, 0.0]]), 0.5, 0.5)
    >>> grid.origin, grid.data.shape, int(grid.data.sum()) // 100
    ((-0.5, -0.5, 0.0), (2, 4), 8)
    >>> int(world_grid(World(walls=[[0.0, 0.2, 1.0, 0.2]]), 0.5, 0.5).data.sum()) // 100
    4

    """
    if not (math.isfinite(resolution) and resolution > 0.0):
        raise WorldError(f'resolution must be > 0 m/cell, got {resolution!r}')
    corners = [world.segments[:, 0:2], world.segments[:, 2:4],
               world.circles[:, 0:2] - world.circles[:, 2:3],
               world.circles[:, 0:2] + world.circles[:, 2:3]]
    if world.grid is not None:
        g = world.grid
        corners.append(g.cell_to_world([[0, 0], [g.height, g.width]]) - 0.5 * g.resolution)
    points = np.vstack(corners)
    if len(points) == 0:
        raise WorldError('the world has no obstacle to draw')
    # Rounded first: (0.5 - 0.2) / 0.1 is 2.9999999999999996, whose floor would shift the grid.
    low = np.floor(np.round((points.min(axis=0) - margin) / resolution, 9)) * resolution
    high = points.max(axis=0) + margin
    cols, rows = (int(math.ceil(v)) for v in (high - low) / resolution)
    if rows * cols > MAX_CELLS:
        raise WorldError(f'a grid of {rows} x {cols} cells at {resolution} m is more than '
                         f'{MAX_CELLS}: raise the resolution')
    i, j = np.mgrid[0:rows, 0:cols]
    centres = np.column_stack([low[0] + (j.ravel() + 0.5) * resolution,
                               low[1] + (i.ravel() + 0.5) * resolution])
    # Half the diagonal, and a rounding's worth more: an obstacle touching a corner counts.
    reach = 0.5 * math.sqrt(2.0) * resolution * (1.0 + 1e-9)
    occupied = distance_to_obstacles(world, centres) <= reach
    data = np.where(occupied, 100, 0).astype(np.int8).reshape(rows, cols)
    return OccupancyGrid(data, resolution, (float(low[0]), float(low[1]), 0.0))


def world_as_grid(world: World, resolution: float = 0.05) -> OccupancyGrid:
    """
    Return the world's own grid when it is nothing else, else :func:`world_grid` of it.

    A map file's grid keeps its cells and resolution; walls, polygons or circles (with or
    without a grid) are drawn at ``resolution`` [m/cell]. WorldError as :func:`world_grid`.

    >>> world_as_grid(World(walls=[[0.0, 0.0, 1.0, 0.0]]), 0.5).resolution
    0.5
    """
    if world.grid is not None and not len(world.segments) and not len(world.circles):
        return world.grid
    return world_grid(world, resolution)
