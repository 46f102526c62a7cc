"""
The course's parallel-parking planner (slides, seed catalogue Part 14), a pure core.

Space detection from side ultrasonic readings (:mod:`.space_detection`), the space and its
frames (:mod:`.space`), the car-like vehicle (:mod:`.vehicle`), the arcs and the corner
geometry (:mod:`.manoeuvre_arcs`), the collision predicates (:mod:`.collision_predicates`),
the positioning point dx1 and the stop dy3 (:mod:`.positioning_point`), the two execution
modes (:mod:`.execution_modes`) and the planner (:mod:`.parking_planner`), which returns a
:class:`~robotica_ctrl.planning.plan_result.PlanResult` with the manoeuvre list and a path.
"""

from robotica_ctrl.planning.parking.collision_predicates import (
    front_rear_collision_free, front_rear_singular_angle, lateral_reach, sampled_extents,
    SweptExtents, two_arc_extents)
from robotica_ctrl.planning.parking.execution_modes import (
    ExecutionMode, GeometricMode, make_mode, ManoeuvreShape, Piece, ProgressiveMode,
    sample_pieces, SampledMotion)
from robotica_ctrl.planning.parking.manoeuvre_arcs import (
    arc_extreme, corner_distances, corner_positions, two_arc_centres, two_arc_displacement)
from robotica_ctrl.planning.parking.parking_planner import (
    Manoeuvre, ParkingParams, plan_parallel_parking)
from robotica_ctrl.planning.parking.positioning_point import (
    Approach, approach, front_corner_offset, positioning_offset, sampled_corner_offset)
from robotica_ctrl.planning.parking.space import ParkingSpace, Side
from robotica_ctrl.planning.parking.space_detection import (
    detect_spaces, DetectedSpace, SpaceDetectionParams)
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle

__all__ = ['Approach', 'DetectedSpace', 'ExecutionMode', 'GeometricMode', 'Manoeuvre',
           'ManoeuvreShape', 'ParkingParams', 'ParkingSpace', 'ParkingVehicle', 'Piece',
           'ProgressiveMode', 'SampledMotion', 'Side', 'SpaceDetectionParams', 'SweptExtents',
           'approach', 'arc_extreme', 'corner_distances', 'corner_positions', 'detect_spaces',
           'front_corner_offset', 'front_rear_collision_free', 'front_rear_singular_angle',
           'lateral_reach', 'make_mode', 'plan_parallel_parking', 'positioning_offset',
           'sample_pieces', 'sampled_corner_offset', 'sampled_extents', 'two_arc_centres',
           'two_arc_displacement', 'two_arc_extents']
