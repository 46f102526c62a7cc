"""
Tests of the parking-space detection from side readings in one pass (catalogue §14.4 step 1).

The readings are simulated here with the world model's ray casting
(:func:`robotica_kin.world.cast_rays`) on a street with parked cars (boxes) and a curb (a
wall); the space's true length, depth and corner are those the world was built with.
"""

import math

import numpy as np
import pytest
from robotica_ctrl.planning.parking.space_detection import detect_spaces, SpaceDetectionParams
from robotica_kin.world import cast_rays, make_world

HEADING = 0.3                      # [rad] the street's direction in the map
ORIGIN = np.array([5.0, -2.0])     # [m] the space's corner (rear car's end, cars' side line)
LENGTH, DEPTH = 7.0, 2.2           # [m] H, J
PASS = 1.5                         # [m] P_f's distance from the cars' side line (dx2)
MOUNT = (1.0, -0.85, -0.5 * math.pi)    # the right-hand sensor in base_link
STEP = 0.1                         # [m] between readings


def to_map(points, side='right'):
    """Return street-frame points (x along, y left) in the map frame (mirrored for 'left')."""
    p = np.asarray(points, dtype=float) * [1.0, 1.0 if side == 'right' else -1.0]
    c, s = math.cos(HEADING), math.sin(HEADING)
    return ORIGIN + p @ np.array([[c, s], [-s, c]])


def street(side='right', curb=True, gaps=((0.0, LENGTH),)):
    """Return the world: 4.5 m cars 1.8 m deep around the gaps, and the curb at -J."""
    edges = [-4.5] + [v for gap in gaps for v in gap] + [gaps[-1][1] + 4.5]
    boxes = []
    for start, end in zip(edges[::2], edges[1::2]):
        corners = to_map([[start, -1.8], [end, -1.8], [end, 0.0], [start, 0.0]], side)
        boxes.append(corners)
    walls = [to_map([[-10.0, -DEPTH], [LENGTH + 20.0, -DEPTH]], side).reshape(4)] if curb \
        else []
    return make_world(walls=walls, polygons=boxes)


def drive_by(world, side='right', mount=MOUNT, cone=(0.0,), range_max=5.0, end=None):
    """Return the poses of a straight pass and the sensor's readings (nearest of the cone)."""
    along = np.arange(-6.0, (LENGTH + 6.0) if end is None else end, STEP)
    pf = to_map(np.column_stack([along, np.full_like(along, PASS)]), side)
    heading = HEADING
    poses = np.column_stack([pf, np.full(len(pf), heading)])
    sign = 1.0 if side == 'right' else -1.0
    x, y, yaw = mount[0], sign * mount[1], sign * mount[2]
    c, s = math.cos(heading), math.sin(heading)
    sensor = pf + np.array([c * x - s * y, s * x + c * y])
    ranges = np.full(len(pf), np.inf)
    for offset in cone:
        hits = cast_rays(world, sensor, np.full(len(pf), heading + yaw + offset), range_max)
        ranges = np.minimum(ranges, hits.ranges)
    return poses, ranges, (x, y, yaw)


def test_one_ray_finds_the_space_within_a_sampling_step():
    poses, ranges, mount = drive_by(street())
    found = detect_spaces(poses, ranges, mount, 0.05, 5.0)
    assert len(found) == 1
    space = found[0].space
    assert LENGTH - 2 * STEP <= space.length <= LENGTH
    assert space.depth == pytest.approx(DEPTH, abs=1e-9) and found[0].depth_measured
    assert space.side == 'right' and space.origin[2] == pytest.approx(HEADING)
    assert np.hypot(*(np.array(space.origin[:2]) - ORIGIN)) <= STEP
    assert found[0].line_offset == pytest.approx(PASS)
    assert space.effective_length == pytest.approx(space.length - 2 * 0.2)
    # The space's frame maps its corner at the rear car's end onto the side line.
    corner = space.to_map([[0.0, 0.0, 0.0]])[0, :2]
    assert abs(np.dot(corner - ORIGIN, [-math.sin(HEADING), math.cos(HEADING)])) < 1e-9


def test_a_space_on_the_left():
    poses, ranges, mount = drive_by(street('left'), 'left')
    found = detect_spaces(poses, ranges, mount, 0.05, 5.0)
    assert [f.space.side for f in found] == ['left']
    assert LENGTH - 2 * STEP <= found[0].space.length <= LENGTH
    assert found[0].space.depth == pytest.approx(DEPTH, abs=1e-9)
    near_corner = found[0].space.to_map([[0.0, 0.0, 0.0]])[0, :2]
    assert np.hypot(*(near_corner - ORIGIN)) <= STEP + 1e-9
    inner = found[0].space.to_map([[1.0, 1.0, 0.0]])[0, :2]     # inside: left of the pass
    assert np.dot(inner - ORIGIN, [-math.sin(HEADING), math.cos(HEADING)]) < 0.0


def test_a_sonar_cone_makes_the_space_look_shorter():
    # A cone of ±12° meets each car's side corner (2 r tan 12° = 0.28 m in all at r = 0.65 m)
    # and, beyond it, its end face while the range is within max_obstacle_range (2 m).
    poses, ranges, mount = drive_by(street(), cone=np.radians(np.linspace(-12, 12, 7)))
    space = detect_spaces(poses, ranges, mount, 0.05, 5.0)[0].space
    tan12 = math.tan(math.radians(12.0))
    assert LENGTH - 2 * 2.0 * tan12 - 2 * STEP <= space.length
    assert space.length <= LENGTH - 2 * (PASS - 0.85) * tan12
    assert space.depth == pytest.approx(DEPTH, abs=0.01)


def test_noise_dropouts_and_unknown_readings():
    poses, ranges, mount = drive_by(street())
    rng = np.random.default_rng(3)
    ranges = ranges + rng.normal(0.0, 0.01, len(ranges))
    # The sensor's along-street position is -5 + 0.1 k [m]: the rear car is k < 50, the
    # front one 120 <= k < 165.
    ranges[10] = np.inf             # a missed echo on the rear car's body: a one-reading run
    ranges[25] = np.nan             # an erroneous reading: dropped
    ranges[140] = -np.inf           # too close to measure: an obstacle at range_min
    found = detect_spaces(poses, ranges, mount, 0.05, 5.0)
    assert len(found) == 1
    assert LENGTH - 2 * STEP - 0.05 <= found[0].space.length <= LENGTH + 0.05
    assert found[0].space.depth == pytest.approx(DEPTH, abs=0.02)


def test_no_curb_in_range_gives_the_capped_depth():
    poses, ranges, mount = drive_by(street(curb=False))
    found = detect_spaces(poses, ranges, mount, 0.05, 5.0, SpaceDetectionParams(max_depth=2.4))
    assert not found[0].depth_measured and found[0].space.depth == 2.4


def test_two_spaces_in_order_and_none_without_a_gap():
    gaps = ((0.0, 6.0), (10.5, 16.0))
    poses, ranges, mount = drive_by(street(gaps=gaps), end=22.0)
    found = detect_spaces(poses, ranges, mount, 0.05, 5.0)
    assert len(found) == 2 and found[0].first_sample < found[1].first_sample
    assert all(g[1] - g[0] - 2 * STEP <= f.space.length <= g[1] - g[0]
               for f, g in zip(found, gaps))
    x = np.arange(0.0, 10.0, 0.1)
    poses = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    assert detect_spaces(poses, np.full(len(x), 0.7), MOUNT, 0.05, 5.0) == []
    assert detect_spaces(poses, np.full(len(x), np.inf), MOUNT, 0.05, 5.0) == []


def test_bad_passes_are_refused():
    x = np.arange(0.0, 5.0, 0.1)
    poses = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    ranges = np.full(len(x), 1.0)
    with pytest.raises(ValueError, match='straight'):
        turning = poses.copy()
        turning[:, 2] = np.linspace(0.0, 0.5, len(x))
        detect_spaces(turning, ranges, MOUNT, 0.05, 5.0)
    with pytest.raises(ValueError, match='forward'):
        detect_spaces(poses[::-1], ranges, MOUNT, 0.05, 5.0)
    with pytest.raises(ValueError, match='sideways'):
        detect_spaces(poses, ranges, (0.0, 0.0, 0.1), 0.05, 5.0)
    with pytest.raises(ValueError, match='ranges'):
        detect_spaces(poses, ranges[:-1], MOUNT, 0.05, 5.0)
    with pytest.raises(ValueError, match='poses'):
        detect_spaces(poses[:, :2], ranges, MOUNT, 0.05, 5.0)
    with pytest.raises(ValueError, match='range_min'):
        detect_spaces(poses, ranges, MOUNT, 5.0, 5.0)
    with pytest.raises(ValueError, match='max_obstacle_range'):
        SpaceDetectionParams(max_obstacle_range=0.0)
