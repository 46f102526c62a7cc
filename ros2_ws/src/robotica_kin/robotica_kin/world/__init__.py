"""
The world model (book §12.4): obstacles in the plane, occupancy grids, ray casting, collisions.

Pure core (NumPy, SciPy; Pillow for map images other than PGM): the simulator's range sensors
and contact, and the controllers' planners, use the same model. See docs/world.md.
"""

from robotica_kin.world.configuration_space import (
    arm_2r_cspace, cspace_grid, cspace_obstacle, minkowski_sum, phi_slice)
from robotica_kin.world.errors import WorldError
from robotica_kin.world.map_file import load_map, write_map
from robotica_kin.world.occupancy_grid import log_odds_update, OccupancyGrid
from robotica_kin.world.occupancy_mapping import (
    evidence_to_percent, OccupancyMap, OccupancyMappingParams, percent_to_evidence)
from robotica_kin.world.quadtree import build_quadtree, Quadtree, QuadtreeGraph
from robotica_kin.world.queries import (
    distance_to_obstacles, footprint_collides, footprint_distance, grow, point_in_obstacle,
    swept_collision)
from robotica_kin.world.raycast import cast_rays, RayHits
from robotica_kin.world.shapes import box_polygon, make_world, validate_polygon, World
from robotica_kin.world.solids import Box, Cylinder, Cylsphere, Sphere
from robotica_kin.world.world_section import world_from_mapping

__all__ = ['Box', 'Cylinder', 'Cylsphere', 'OccupancyGrid', 'OccupancyMap',
           'OccupancyMappingParams', 'Quadtree', 'QuadtreeGraph', 'RayHits', 'Sphere', 'World',
           'WorldError', 'arm_2r_cspace', 'box_polygon', 'build_quadtree', 'cast_rays',
           'cspace_grid', 'cspace_obstacle', 'distance_to_obstacles', 'evidence_to_percent',
           'footprint_collides', 'footprint_distance', 'grow', 'load_map', 'log_odds_update',
           'make_world', 'minkowski_sum', 'percent_to_evidence', 'phi_slice',
           'point_in_obstacle', 'swept_collision', 'validate_polygon', 'world_from_mapping',
           'write_map']
