"""
A parking search: the reconnaissance pass, the side readings along it and the plan (§14.4).

What the planner node runs in its ``parking`` mode, the course's manoeuvre (seed catalogue
Part 14) from start to end, as a pure core that a node feeds with poses and readings:

1. :meth:`ParkingSearch.start` lays the pass: a straight line of ``pass_length`` metres from
   the vehicle's pose along its heading, which a tracker drives (slides, phase 1: "one pass").
2. :meth:`ParkingSearch.add_reading` collects P_f's pose and the side sensor's reading of each
   sample, and runs :func:`~.space_detection.detect_spaces` on the pass so far.
3. completion (ours): a space is *taken* once the sensor has travelled ``confirm_distance``
   past its last free reading, so that the front obstacle's side is seen over that length
   before the obstacles' line is estimated from it; each space is taken once.
4. :meth:`ParkingSearch.plan` runs :func:`~.parking_planner.plan_parallel_parking` for a
   taken space from the pose of the sample that took it (the rest of the pass to the stop
   point, the approach, the manoeuvres, the centring). A space without a plan (too short, too
   narrow, a contact) is reported and the search goes on along the pass.

:data:`PARKING_PARAMETERS` are the node's ``parking.*`` parameters; :func:`parking_search`
builds a search from their values.
"""

from dataclasses import dataclass
import math
from typing import Any, Callable, Mapping, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.parking.parking_planner import ParkingParams, plan_parallel_parking
from robotica_ctrl.planning.parking.space_detection import (
    detect_spaces, DetectedSpace, SpaceDetectionParams)
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_ctrl.planning.plan_result import PlanResult, SearchBudget
from robotica_kin.finite import finite_real
from robotica_kin.parameter_specs import parameter_values, ParameterSpec
from robotica_kin.world import World

__all__ = ['PARKING_PARAMETERS', 'ParkingSearch', 'ParkingSearchParams', 'parking_search']

_VEHICLE, _DETECTION, _PLANNING = ParkingVehicle(), SpaceDetectionParams(), ParkingParams()

PARKING_PARAMETERS: dict[str, ParameterSpec] = {
    'a1': ParameterSpec(_VEHICLE.a1, 'a1 [m]: rear axle (P_f) to the front end', 1e-3, 100.0),
    'b1': ParameterSpec(_VEHICLE.b1, 'b1 [m]: rear axle to the rear end', 0.0, 100.0),
    'h1': ParameterSpec(_VEHICLE.h1, 'h1 [m]: wheelbase, rear axle to the steering wheel',
                        1e-3, 100.0),
    'c1': ParameterSpec(_VEHICLE.c1, 'c1 [m]: width of the body', 1e-3, 100.0),
    'max_steering': ParameterSpec(_VEHICLE.theta_dmax, 'theta_dmax [rad]: largest angle of the '
                                  'equivalent steering wheel', 1e-3, 1.5),
    'sensor_pose': ParameterSpec((0.0, -0.85, -0.5 * math.pi), 'The side range sensor (x [m], '
                                 'y [m], yaw [rad]) in base_link; yaw -pi/2 looks right'),
    'pass_length': ParameterSpec(30.0, 'Length [m] of the straight reconnaissance pass', 0.1,
                                 10_000.0),
    'confirm_distance': ParameterSpec(0.5, 'The sensor travels this far [m] past a space '
                                      'before it is taken', 0.0, 100.0),
    'max_obstacle_range': ParameterSpec(_DETECTION.max_obstacle_range, 'A reading of at most '
                                        'this [m] is a parked obstacle', 1e-3, 100.0),
    'min_gap_length': ParameterSpec(_DETECTION.min_gap_length, 'Free runs shorter than this '
                                    '[m] are dropouts, not spaces', 1e-3, 100.0),
    'max_depth': ParameterSpec(_DETECTION.max_depth, 'Depth J [m] of a space without a curb '
                               'echo, and the cap of J', 1e-3, 100.0),
    'margin': ParameterSpec(_DETECTION.margin, 'MS [m]: the safety margin inside the space',
                            0.0, 10.0),
    'execution': ParameterSpec(_PLANNING.mode, 'geometric (stop and re-orient the wheels '
                               'between arcs) or progressive (steer while moving)',
                               choices=('geometric', 'progressive')),
    'max_manoeuvres': ParameterSpec(_PLANNING.max_manoeuvres, 'Backward and forward '
                                    'manoeuvres, at most', 1, 1000),
    'autostart': ParameterSpec(False, 'Start the search at the first pose (else on a call of '
                               'the park service)'),
}
"""The planner node's ``parking.*`` parameters, by name without the prefix."""


@dataclass(frozen=True)
class ParkingSearchParams:
    """The pass and when a space is taken (module docstring) [m]."""

    pass_length: float = 30.0         # [m] of the straight pass from where the search starts
    confirm_distance: float = 0.5     # [m] the sensor travels past a space before it is taken
    point_spacing: float = 0.5        # [m] between the pass path's postures

    def __post_init__(self) -> None:
        for name in ('pass_length', 'point_spacing'):
            if not finite_real(name, getattr(self, name)) > 0.0:
                raise ValueError(f'{name} must be > 0 m, got {getattr(self, name)!r}')
        if not finite_real('confirm_distance', self.confirm_distance) >= 0.0:
            raise ValueError(f'confirm_distance must be >= 0 m, got {self.confirm_distance!r}')


class ParkingSearch:
    """
    The pass, its readings and the spaces found on it (module docstring).

    Parameters
    ----------
    vehicle : ParkingVehicle
        a1, b1, h1, c1, θ_dmax [m, rad].
    sensor_pose : array_like, shape (3,)
        The side sensor (x [m], y [m], yaw [rad]) in ``base_link``.
    params, detection, planning
        The pass (:class:`ParkingSearchParams`), the space detection's thresholds and the
        planner's tunables.

    Examples
    --------
    A street along x with parked cars on the right, 0.55 m from a sensor at the front-right
    corner, and a 7.2 m space between x = 6.5 and 13.7 m with the curb 2.2 m beyond them:

    >>> search = ParkingSearch(ParkingVehicle(), (3.4, -0.85, -math.pi / 2))
    >>> search.start((-2.0, 3.6, 0.0)).shape[1]
    3
    >>> taken = None
    >>> for x in np.arange(-2.0, 12.0, 0.1):
    ...     sensor_x = x + 3.4
    ...     reading = 2.75 if 6.5 < sensor_x < 13.7 else 0.55
    ...     taken = taken or search.add_reading((x, 3.6, 0.0), reading, 0.15, 5.0)
    >>> round(taken.space.length, 1), round(taken.space.depth, 2)
    (7.1, 2.2)
    >>> search.plan(taken).found
    True

    """

    def __init__(self, vehicle: ParkingVehicle, sensor_pose: ArrayLike,
                 params: ParkingSearchParams = ParkingSearchParams(),
                 detection: SpaceDetectionParams = SpaceDetectionParams(),
                 planning: ParkingParams = ParkingParams()) -> None:
        mount = np.asarray(sensor_pose, dtype=np.float64)
        if mount.shape != (3,) or not np.isfinite(mount).all():
            raise ValueError(f'sensor_pose must be a finite (x, y, yaw), got {sensor_pose!r}')
        if abs(math.sin(float(mount[2]))) < 0.5:
            raise ValueError(f'sensor_pose must look sideways (|sin yaw| >= 0.5), got yaw '
                             f'{float(mount[2])!r} rad')
        self.vehicle, self.sensor_pose = vehicle, mount
        self.params, self.detection, self.planning = params, detection, planning
        self._origin: Optional[NDArray[np.float64]] = None
        self._poses: list[tuple[float, float, float]] = []
        self._ranges: list[float] = []
        self._limits: Optional[tuple[float, float]] = None
        self._taken: set[int] = set()

    @property
    def samples(self) -> int:
        """Return the number of readings collected on this pass."""
        return len(self._ranges)

    def start(self, pose: ArrayLike) -> NDArray[np.float64]:
        """
        Start a pass at P_f's ``pose`` (x, y, θ) [m, rad]; return its postures (N, 3).

        The pass runs ``pass_length`` straight along θ, postures every ``point_spacing`` at
        most; the readings of an earlier pass are forgotten.
        """
        origin = np.asarray(pose, dtype=np.float64)
        if origin.shape != (3,) or not np.isfinite(origin).all():
            raise ValueError(f'pose must be a finite (x, y, theta), got {pose!r}')
        self._origin = origin
        self._poses, self._ranges, self._limits, self._taken = [], [], None, set()
        length = self.params.pass_length
        s = np.linspace(0.0, length, max(2, math.ceil(length / self.params.point_spacing) + 1))
        c, si = math.cos(origin[2]), math.sin(origin[2])
        return np.column_stack([origin[0] + s * c, origin[1] + s * si,
                                np.full_like(s, origin[2])])

    def along(self, pose: ArrayLike) -> float:
        """Return how far [m] the point (x, y) of ``pose`` is along the pass from its start."""
        if self._origin is None:
            raise ValueError('no pass has been started')
        p = np.asarray(pose, dtype=np.float64)
        theta = float(self._origin[2])
        return float((p[0] - self._origin[0]) * math.cos(theta)
                     + (p[1] - self._origin[1]) * math.sin(theta))

    def finished(self, pose: ArrayLike, tolerance: float = 0.3) -> bool:
        """Return whether P_f at ``pose`` is within ``tolerance`` [m] of the pass's end."""
        return self.along(pose) >= self.params.pass_length - tolerance

    def add_reading(self, pose: ArrayLike, reading: float, range_min: float,
                    range_max: float) -> Optional[DetectedSpace]:
        """
        Add one sample: P_f's ``pose`` (x, y, θ) and the side sensor's ``reading`` [m] there.

        ``reading`` follows REP-117 (+inf no echo, −inf too close, NaN unknown) within the
        sensor's ``range_min``, ``range_max`` [m] (those of the first reading are kept).
        Returns the space this sample takes (module docstring, step 3), else None.

        Raises
        ------
        ValueError
            Without a pass, for a pose that is not finite, or a pass that is not straight
            and forward (:func:`~.space_detection.detect_spaces`).

        """
        if self._origin is None:
            raise ValueError('no pass has been started')
        p = np.asarray(pose, dtype=np.float64)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f'pose must be a finite (x, y, theta), got {pose!r}')
        if self._limits is None:
            self._limits = (float(range_min), float(range_max))
        self._poses.append((float(p[0]), float(p[1]), float(p[2])))
        self._ranges.append(float(reading))
        if len(self._ranges) < 2:
            return None
        spaces = detect_spaces(self._poses, self._ranges, self.sensor_pose, *self._limits,
                               self.detection)
        newest = self._sensor_along(-1)
        for found in spaces:
            if found.first_sample in self._taken:
                continue
            if newest - self._sensor_along(found.last_sample) >= self.params.confirm_distance:
                self._taken.add(found.first_sample)
                return found
        return None

    def _sensor_along(self, sample: int) -> float:
        """Return the sensor's distance [m] along the pass at sample number ``sample``."""
        x, y, theta = self._poses[sample]
        c, s = math.cos(theta), math.sin(theta)
        mx, my = float(self.sensor_pose[0]), float(self.sensor_pose[1])
        return self.along((x + c * mx - s * my, y + s * mx + c * my))

    def plan(self, found: DetectedSpace, pose: Optional[ArrayLike] = None,
             world: Optional[World] = None, budget: SearchBudget = SearchBudget(),
             clock: Optional[Callable[[], float]] = None) -> PlanResult:
        """
        Return the parking plan into ``found`` from ``pose`` (default: the newest sample's).

        ``world`` is what the path is checked against (the space's own obstacles if None);
        ``budget`` and ``clock`` bound the planner (:func:`plan_parallel_parking`).
        """
        start = self._poses[-1] if pose is None else pose
        return plan_parallel_parking(found.space, self.vehicle, start, self.planning, world,
                                     budget, clock)


def parking_search(values: Mapping[str, Any]) -> ParkingSearch:
    """
    Return the search of the ``parking.*`` parameters (names of :data:`PARKING_PARAMETERS`).

    Missing names take their defaults. Raises ParameterError for a value out of its range or
    choices, ValueError for values the vehicle or the detection refuse together.

    >>> parking_search({'pass_length': 20.0}).params.pass_length
    20.0
    """
    v = parameter_values(PARKING_PARAMETERS, dict(values))
    vehicle = ParkingVehicle(a1=v['a1'], b1=v['b1'], h1=v['h1'], c1=v['c1'],
                             theta_dmax=v['max_steering'])
    detection = SpaceDetectionParams(v['max_obstacle_range'], v['min_gap_length'],
                                     v['max_depth'], _DETECTION.max_heading_spread, v['margin'])
    planning = ParkingParams(mode=v['execution'], max_manoeuvres=int(v['max_manoeuvres']))
    return ParkingSearch(vehicle, tuple(v['sensor_pose']),
                         ParkingSearchParams(v['pass_length'], v['confirm_distance']),
                         detection, planning)
