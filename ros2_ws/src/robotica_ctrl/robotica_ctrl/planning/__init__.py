"""
Path planning of book ch. 12 and the course's parallel parking, pure (no ROS).

The planners of seed catalogue Part 10 and the parallel-parking planner of Part 14, in
NumPy/SciPy on the world model of :mod:`robotica_kin.world`.

Every planner returns a :class:`~.plan_result.PlanResult`: a path with its cost, or no path and
the reason, and what the search did (expanded nodes, time, whether a bound on work was hit).
"""

from .continuous_curvature import cc_turn, continuous_curvature_path, sharpness_bound
from .cubic_spiral import cubic_spiral
from .grid_astar import astar_cells, grid_astar
from .parking import (detect_spaces, DetectedSpace, Manoeuvre, ParkingParams, ParkingSpace,
                      ParkingVehicle, plan_parallel_parking, SpaceDetectionParams)
from .path_collision import polyline_collision, pose_collision
from .path_shortcut import shortcut_path
from .path_smoothing import smooth_path
from .plan_result import PlanResult, SearchBudget
from .planners import plan_path, PLANNER_METHODS, PLANNER_PARAMETERS
from .potential_planner import potential_planner, PotentialPlannerParams
from .visibility_graph import visibility_graph
from .voronoi_roadmap import voronoi_roadmap

__all__ = ['DetectedSpace', 'Manoeuvre', 'PLANNER_METHODS', 'PLANNER_PARAMETERS', 'ParkingParams',
           'ParkingSpace', 'ParkingVehicle', 'PlanResult', 'PotentialPlannerParams',
           'SearchBudget', 'SpaceDetectionParams', 'astar_cells', 'cc_turn',
           'continuous_curvature_path', 'cubic_spiral', 'detect_spaces', 'grid_astar',
           'plan_parallel_parking', 'plan_path', 'polyline_collision', 'pose_collision',
           'potential_planner', 'sharpness_bound', 'shortcut_path', 'smooth_path',
           'visibility_graph', 'voronoi_roadmap']
