"""
Detection of a parking space from side ultrasonic readings in one pass (catalogue §14.4 step 1).

slides: phase 1 detects the parking space (a rectangle) with ultrasonic sensors in one pass
("Detectar el espacio de aparcamiento (rectángulo) con una pasada"), at the lateral
separation dx2 from the parked obstacles; the planner then knows H and J, hence H' and J'.

completion (ours), the algorithm and its thresholds (:class:`SpaceDetectionParams`):

1. The input is the pass as samples: P_f's pose (x, y, θ) in the map frame and the range of
   one side sensor mounted at ``sensor_pose`` (x, y, yaw) in ``base_link``. The pass must be
   straight (headings within ``max_heading_spread`` of their circular mean, which gives the
   street's direction) and forward (the sensor never moves back along the street). Readings
   follow REP-117: a range at or beyond ``range_max`` (or +inf) is no echo, −inf or below
   ``range_min`` an object too close (taken at ``range_min``), NaN unknown (dropped).
2. A reading of at most ``max_obstacle_range`` [m] is a parked obstacle beside the pass;
   farther, or no echo, is free (the space, with the curb or wall beyond it).
3. A space is a run of free readings with obstacle readings on both sides: its rear end is
   where the beam's axis of the first free reading crosses the obstacles' line (step 4),
   its front end that of the last one, along the street's direction: H = front − rear. A
   beam that misses the obstacles passes beyond their ends, so H is never longer than the
   space: with one ray per reading it is short by less than two sampling intervals, and a
   sonar cone, which meets the cars' corners and end faces before its axis does, shortens
   it further (the conservative error; by up to ``max_obstacle_range``·tan of the cone's
   half angle at each end). Runs shorter than ``min_gap_length`` are dropouts (a missed
   echo on a car's body) and are ignored.
4. The line of the parked obstacles' sides is at the median distance of the echoes of the
   two bounding obstacle runs from P_f's line; J is the median distance of the echoes inside
   the run (the curb or wall) beyond that line, capped at ``max_depth``; with no echo inside
   (nothing within range) J = ``max_depth`` and ``depth_measured`` is False.

The result is a :class:`.ParkingSpace` per space, its frame on the obstacles' line at the
rear obstacle's end (:mod:`.space`), with the margin MS of the parameters.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.parking.space import ParkingSpace, Side
from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import finite_real

__all__ = ['DetectedSpace', 'SpaceDetectionParams', 'detect_spaces']


@dataclass(frozen=True)
class SpaceDetectionParams:
    """
    Thresholds of the space detection (module docstring) [m, rad].

    >>> SpaceDetectionParams().max_obstacle_range
    2.0
    """

    max_obstacle_range: float = 2.0    # [m] a reading at most this is a parked obstacle
    min_gap_length: float = 0.5        # [m] shorter free runs are dropouts, not spaces
    max_depth: float = 2.5             # [m] J without a curb echo, and the cap of J
    max_heading_spread: float = 0.1    # [rad] the pass's headings about their mean, at most
    margin: float = 0.2                # MS [m] of the detected spaces

    def __post_init__(self) -> None:
        for name in ('max_obstacle_range', 'min_gap_length', 'max_depth',
                     'max_heading_spread'):
            if not finite_real(name, getattr(self, name)) > 0.0:
                raise ValueError(f'{name} must be > 0, got {getattr(self, name)!r}')
        if not finite_real('margin', self.margin) >= 0.0:
            raise ValueError(f'margin must be >= 0 m, got {self.margin!r}')


@dataclass(frozen=True)
class DetectedSpace:
    """
    A space found in a pass: the space, whether its depth was measured, its samples.

    ``first_sample`` and ``last_sample`` index the free readings that make it (inclusive);
    ``line_offset`` [m] is P_f's distance from the parked obstacles' line during the pass.
    """

    space: ParkingSpace
    depth_measured: bool
    first_sample: int
    last_sample: int
    line_offset: float


def _inputs(poses: ArrayLike, ranges: ArrayLike, sensor_pose: ArrayLike, range_min: float,
            range_max: float) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                       NDArray[np.float64]]:
    q = np.asarray(poses, dtype=np.float64)
    r = np.asarray(ranges, dtype=np.float64)
    mount = np.asarray(sensor_pose, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != 3 or len(q) < 2 or not np.isfinite(q).all():
        raise ValueError(f'poses must be finite with shape (k, 3), k >= 2, got {q.shape}')
    if r.shape != (len(q),):
        raise ValueError(f'ranges must have shape ({len(q)},), got {r.shape}')
    if mount.shape != (3,) or not np.isfinite(mount).all():
        raise ValueError(f'sensor_pose must be a finite (x, y, yaw), got {sensor_pose!r}')
    low, high = finite_real('range_min', range_min), finite_real('range_max', range_max)
    if not 0.0 <= low < high:
        raise ValueError(f'need 0 <= range_min < range_max, got {range_min!r}, {range_max!r}')
    return q, r, mount


def detect_spaces(poses: ArrayLike, ranges: ArrayLike, sensor_pose: ArrayLike,
                  range_min: float, range_max: float,
                  params: SpaceDetectionParams = SpaceDetectionParams()) -> list[DetectedSpace]:
    """
    Return the spaces between parked obstacles seen by a side sensor in one straight pass.

    ``poses`` (k, 3) P_f's (x [m], y [m], θ [rad]) in the map frame, in the order driven;
    ``ranges`` (k,) [m] the side sensor's readings there (REP-117); ``sensor_pose`` (x, y,
    yaw) [m, rad] of the sensor in ``base_link`` (yaw −π/2 looks right); ``range_min``,
    ``range_max`` [m] its limits. Spaces in the order passed; ValueError on bad input, a
    sensor that does not look sideways, or a pass that turns or goes back.

    >>> x = np.arange(0.0, 12.0, 0.1)
    >>> poses = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    >>> ranges = np.where((x > 4.0) & (x < 10.5), 3.2, 1.0)
    >>> found = detect_spaces(poses, ranges, (0.0, -0.85, -math.pi / 2), 0.1, 5.0)
    >>> s = found[0].space
    >>> [round(v, 3) for v in (s.length, s.depth, *s.origin)], s.side
    ([6.3, 2.2, 4.1, -1.85, 0.0], 'right')
    """
    q, r, mount = _inputs(poses, ranges, sensor_pose, range_min, range_max)
    heading = math.atan2(float(np.sin(q[:, 2]).mean()), float(np.cos(q[:, 2]).mean()))
    spread = float(np.abs(wrap_to_pi(q[:, 2] - heading)).max())
    if spread > params.max_heading_spread:
        raise ValueError(f'the pass must be straight: headings spread {spread:.3f} rad > '
                         f'max_heading_spread = {params.max_heading_spread} rad')
    lateral = math.sin(float(mount[2]))
    if abs(lateral) < 0.5:
        raise ValueError(f'the sensor must look sideways (|sin yaw| >= 0.5), got yaw '
                         f'{float(mount[2])!r} rad')
    side: Side = 'right' if lateral < 0.0 else 'left'
    along_dir = np.array([math.cos(heading), math.sin(heading)])
    sense = 1.0 if side == 'right' else -1.0
    towards = sense * np.array([math.sin(heading), -math.cos(heading)])
    c, s = np.cos(q[:, 2]), np.sin(q[:, 2])
    sensor = q[:, :2] + np.column_stack([c * mount[0] - s * mount[1],
                                         s * mount[0] + c * mount[1]])
    known = ~np.isnan(r)
    echo = known & (r < range_max)
    reading = np.clip(np.where(echo, r, range_max), range_min, range_max)
    beam = q[:, 2] + mount[2]
    points = sensor + reading[:, None] * np.column_stack([np.cos(beam), np.sin(beam)])
    base = q[0, :2]
    sensor_along = (sensor - base) @ along_dir
    if np.any(np.diff(sensor_along[known]) < -1e-9):
        raise ValueError('the pass must go forward: the sensor moved back along the street')
    depth = (points - base) @ towards
    obstacle = echo & (reading <= params.max_obstacle_range)
    order = np.flatnonzero(known)
    found: list[DetectedSpace] = []
    runs = np.split(order, np.flatnonzero(np.diff(obstacle[order].astype(np.int8))) + 1)
    beam_along = np.cos(beam) * along_dir[0] + np.sin(beam) * along_dir[1]
    beam_depth = np.cos(beam) * towards[0] + np.sin(beam) * towards[1]
    sensor_depth = (sensor - base) @ towards
    for k in range(1, len(runs) - 1):
        run = runs[k]
        if obstacle[run[0]]:
            continue
        line = float(np.median(depth[np.concatenate([runs[k - 1], runs[k + 1]])]))
        # Where the beams of the first and last free readings cross the obstacles' line.
        ends = run[[0, -1]]
        reach = (line - sensor_depth[ends]) / beam_depth[ends]
        rear, front = (sensor_along[ends] + reach * beam_along[ends]).tolist()
        if front - rear < params.min_gap_length:
            continue
        inside = run[echo[run]]
        measured = len(inside) > 0
        width = (min(float(np.median(depth[inside])) - line, params.max_depth) if measured
                 else params.max_depth)
        if width <= 0.0:
            continue
        corner = base + rear * along_dir + line * towards
        space = ParkingSpace((float(corner[0]), float(corner[1]), heading), front - rear,
                             width, side, params.margin)
        found.append(DetectedSpace(space, measured, int(run[0]), int(run[-1]), line))
    return found
