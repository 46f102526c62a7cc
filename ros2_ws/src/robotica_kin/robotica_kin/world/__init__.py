"""
The world model (book §12.4): obstacles in the plane, occupancy grids, ray casting, collisions.

Pure core (NumPy, SciPy): the simulator's range sensors and contact, and the controllers'
planners, use the same model. See docs/world.md.
"""

from robotica_kin.world.errors import WorldError
from robotica_kin.world.occupancy_grid import log_odds_update, OccupancyGrid
from robotica_kin.world.raycast import cast_rays, RayHits
from robotica_kin.world.shapes import box_polygon, make_world, validate_polygon, World

__all__ = ['OccupancyGrid', 'RayHits', 'World', 'WorldError', 'box_polygon', 'cast_rays',
           'log_odds_update', 'make_world', 'validate_polygon']
