"""
Heading and cross-track errors of a path driven partly in reverse (issue 21's parking plans).

A parking plan's nav_msgs/Path carries the vehicle's heading as each pose's orientation: on a
reverse segment it points against the travel. The reference values are geometry worked here:
a truth that drives the plan exactly, with the plan's headings, has heading error 0 and the
cross-track error of its own lateral offset (> 0 left of the vehicle, as the reversing tracker
measures it); along a path whose orientations are all the identity (not its tangents) the
tangent stays the reference; a reverse arc of radius R sampled every ds has chords within
ds / (2 R) of its headings and sagittas of R (1 - cos(ds / (2 R))).
"""
import math
from pathlib import Path

import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_sim.grading.metrics import (compute_metrics, MetricParams, path_errors,
                                          segment_directions)
from robotica_sim.grading.rubric import parse_rubric, RubricError
from robotica_sim.grading.series import RunSeries, Series, TOPICS

DIAGONAL = np.array([math.cos(math.pi / 4.0), math.sin(math.pi / 4.0)])


def oriented_run(postures, x, y, theta, v=None):
    """Return a run of the path of ``postures`` (x, y, heading) and a truth through (x, y)."""
    plan = np.asarray(postures, dtype=float)
    n = len(x)
    truth = Series(np.arange(n) * 0.05, {
        'x': np.asarray(x, dtype=float), 'y': np.asarray(y, dtype=float),
        'theta': np.asarray(theta, dtype=float), 'v': np.ones(n) if v is None else v,
        'vy': np.zeros(n), 'w': np.zeros(n)})
    return RunSeries(Path('synthetic'), None, 0.0, {TOPICS['truth']: n, TOPICS['path']: 1},
                     plan[:, :2], None, truth, *[None] * 10, path_headings=plan[:, 2])


def out_and_back():
    """Two metres out along x and 1.5 m back along the same line, heading 0 throughout."""
    out = np.linspace(0.0, 2.0, 21)
    back = np.linspace(1.9, 0.5, 15)
    xs = np.concatenate([out, back])
    return np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)])


def test_a_path_driven_back_along_itself_is_measured_against_its_headings():
    postures = out_and_back()
    assert segment_directions(postures[:, :2], postures[:, 2]).tolist() == [1] * 20 + [-1] * 15
    # The truth drives it 1 cm left of the vehicle (+y: the vehicle faces +x both ways).
    x = np.concatenate([np.linspace(0.0, 2.0, 201), np.linspace(1.99, 0.5, 150)])
    v = np.concatenate([np.ones(201), -np.ones(150)])
    run = oriented_run(postures, x, np.full(len(x), 0.01), np.zeros(len(x)), v)
    metrics = compute_metrics(run)
    m = metrics.values
    assert m['rms_heading_error'] == 0.0 and m['max_heading_error'] == 0.0
    assert m['rms_cross_track'] == pytest.approx(0.01, abs=1e-12)
    assert m['max_cross_track'] == pytest.approx(0.01, abs=1e-12)
    # Progress goes on past the cusp (2 m out + 1.5 m back = the path's 3.5 m), not back.
    assert m['completion'] == pytest.approx(1.0, abs=1e-12) and m['finished'] is True
    assert m['manoeuvres'] == 2
    assert metrics.notes['rms_heading_error'] == (
        'against the /path orientations (15 of 35 segments reverse)')
    s, cross, _ = path_errors(PolylinePath(postures[:, :2]), x, np.full(len(x), 0.01),
                              np.zeros(len(x)), 2.0, segment_directions(postures[:, :2],
                                                                        postures[:, 2]))
    assert s[-1] == pytest.approx(3.5, abs=1e-9) and np.all(np.diff(s) > 0.0)
    assert cross == pytest.approx(np.full(len(x), 0.01), abs=1e-12)   # left of the vehicle


def cusp_plan():
    """
    Out 2 m along x heading 0, then backing 1.5 m down-left with the heading pi/4.

    The cusp's point is repeated with the new heading (a zero-length step: no segment).
    """
    out = [(x, 0.0, 0.0) for x in np.linspace(0.0, 2.0, 21)]
    back = [(2.0 - d * DIAGONAL[0], -d * DIAGONAL[1], math.pi / 4.0)
            for d in np.linspace(0.0, 1.5, 16)]
    return np.array(out + back)


def test_a_reverse_leg_is_measured_against_the_heading_not_the_travel():
    plan = cusp_plan()
    directions = segment_directions(plan[:, :2], plan[:, 2])
    assert directions.tolist() == [1] * 20 + [-1] * 15   # the repeated cusp point is skipped
    # The truth drives it 2 cm left of the vehicle: +y out, (-sin, cos)(pi/4) back.
    out = np.linspace(0.0, 2.0, 201)
    back = np.linspace(0.01, 1.5, 150)
    left = 0.02 * np.array([-DIAGONAL[1], DIAGONAL[0]])
    x = np.concatenate([out, 2.0 - back * DIAGONAL[0] + left[0]])
    y = np.concatenate([np.full(201, 0.02), -back * DIAGONAL[1] + left[1]])
    theta = np.concatenate([np.zeros(201), np.full(150, math.pi / 4.0)])
    path = PolylinePath(plan[:, :2])
    s, cross, heading = path_errors(path, x, y, theta, 2.0, directions)
    away = np.hypot(x - 2.0, y) > 0.1   # beyond the cusp's corner, where both legs are near
    assert heading[away] == pytest.approx(np.zeros(away.sum()), abs=1e-12)
    assert cross[away] == pytest.approx(np.full(away.sum(), 0.02), abs=1e-12)
    assert s[-1] == pytest.approx(3.5, abs=1e-9)
    # Against the tangent (orientations ignored) the reverse leg is pi off, right of travel.
    _, tangent_cross, tangent_heading = path_errors(path, x, y, theta, 2.0)
    assert np.abs(tangent_heading[201:][away[201:]]) == pytest.approx(math.pi, abs=1e-12)
    assert tangent_cross[201:][away[201:]] == pytest.approx(-0.02, abs=1e-12)
    m = compute_metrics(oriented_run(plan, x, y, theta)).values
    assert m['max_heading_error'] < math.pi / 4.0 + 1e-12   # only at the cusp's corner


def test_identity_orientations_leave_the_tangent_as_the_reference():
    # An L: 2 m along x, then 2 m along y, every orientation the identity (yaw 0), as some
    # external planners send it; along y the orientation is pi/2 off the tangent: no headings.
    plan = np.array([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 1.0, 0.0),
                     (2.0, 2.0, 0.0)])
    assert segment_directions(plan[:, :2], plan[:, 2]) is None
    x = np.concatenate([np.linspace(0.0, 2.0, 41), np.full(40, 2.0)])
    y = np.concatenate([np.zeros(41), np.linspace(0.05, 2.0, 40)])
    theta = np.concatenate([np.zeros(41), np.full(40, math.pi / 2.0)])
    metrics = compute_metrics(oriented_run(plan, x, y, theta))
    assert metrics.values['max_heading_error'] == pytest.approx(0.0, abs=1e-12)
    assert metrics.values['completion'] == pytest.approx(1.0, abs=1e-12)
    assert 'rms_heading_error' not in metrics.notes
    assert segment_directions([[0.0, 0.0], [0.0, 3.0]], [0.0, 0.0]) is None
    assert segment_directions([[0.0, 0.0], [1.0, 0.0]], [0.0, math.nan]) is None
    assert segment_directions([[0.0, 0.0], [1.0, 0.0]], None) is None


def reverse_arc(radius, ds, n):
    """
    Postures backing along a circle of ``radius`` about the origin, counter-clockwise.

    At angle phi the position is R (cos, sin) phi; the travel is clockwise (phi decreasing),
    so the vehicle, which faces against the travel, heads phi + pi/2 (the CCW tangent).
    """
    phi = np.pi - np.arange(n) * ds / radius
    return np.column_stack([radius * np.cos(phi), radius * np.sin(phi), phi + math.pi / 2.0])


def test_an_arc_backed_along_is_within_the_chord_bounds():
    radius, ds = 2.0, 0.1
    plan = reverse_arc(radius, ds, 31)
    half = ds / (2.0 * radius)                      # chord vs heading: 0.025 rad
    assert segment_directions(plan[:, :2], plan[:, 2]).tolist() == [-1] * 30
    assert segment_directions(plan[:, :2], plan[:, 2], tolerance=0.02) is None
    phi = np.linspace(plan[0, 2], plan[-1, 2], 301) - math.pi / 2.0
    x, y, theta = radius * np.cos(phi), radius * np.sin(phi), phi + math.pi / 2.0
    m = compute_metrics(oriented_run(plan, x, y, theta)).values
    assert 0.9 * half < m['max_heading_error'] <= half + 1e-9
    assert m['max_cross_track'] <= radius * (1.0 - math.cos(half)) + 1e-12   # the sagitta
    # A tolerance below 0.025 rad: the orientations are not taken as headings; the tangent
    # is the reference, and the vehicle faces against it.
    tight = compute_metrics(oriented_run(plan, x, y, theta),
                            MetricParams(orientation_tolerance=0.02)).values
    assert tight['rms_heading_error'] > math.pi - half - 1e-9


def test_a_forward_path_with_its_tangents_as_orientations_is_measured_as_before():
    # Orientations facing the next point (as path_message gives them to a list of points).
    rng = np.random.default_rng(3)
    points = np.cumsum(rng.uniform(0.05, 0.3, (40, 2)) * [1.0, 0.4], axis=0)
    step = np.diff(points, axis=0)
    yaw = np.append(np.arctan2(step[:, 1], step[:, 0]), math.atan2(step[-1, 1], step[-1, 0]))
    directions = segment_directions(points, yaw)
    assert directions.tolist() == [1] * 39
    x, y = points[:, 0] + rng.normal(0, 0.02, 40), points[:, 1] + rng.normal(0, 0.02, 40)
    theta = rng.uniform(-math.pi, math.pi, 40)
    path = PolylinePath(points)
    before = path_errors(path, x, y, theta, 2.0)
    after = path_errors(path, x, y, theta, 2.0, directions)
    for old, new in zip(before, after):
        assert np.array_equal(old, new)


def test_bad_directions_and_tolerances_are_refused():
    path = PolylinePath([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(ValueError, match='directions must be'):
        path_errors(path, [0.5], [0.0], [0.0], 2.0, [1])
    with pytest.raises(ValueError, match='directions must be'):
        path_errors(path, [0.5], [0.0], [0.0], 2.0, [1, 0])
    with pytest.raises(ValueError, match='headings must have shape'):
        segment_directions([[0.0, 0.0], [1.0, 0.0]], [0.0])
    with pytest.raises(ValueError, match='tolerance'):
        segment_directions([[0.0, 0.0], [1.0, 0.0]], [0.0, 0.0], tolerance=1.0)
    with pytest.raises(ValueError, match='orientation_tolerance'):
        MetricParams(orientation_tolerance=1.0)
    assert parse_rubric({'parameters': {'orientation_tolerance': 0.1},
                         'checks': {'max_heading_error': {'max': 0.3}}}
                        ).params.orientation_tolerance == 0.1
    with pytest.raises(RubricError, match='orientation_tolerance'):
        parse_rubric({'parameters': {'orientation_tolerance': 0.0},
                      'checks': {'max_heading_error': {'max': 0.3}}})
