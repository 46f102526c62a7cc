"""
Reference paths for the mobile-robot trackers of book ch. 9, as (N, 2) point arrays [m].

The book tests its path trackers on a straight path (Ejemplo 9.1, §9.3.1) and on paths made
of straights and arcs (§9.2 lists where paths come from). These functions sample such shapes
as polylines for :class:`robotica_ctrl.mobile.path.PolylinePath`: consecutive points are at
most ``spacing`` apart (arcs are sampled by angle, and a chord is shorter than its arc), and a
closed shape repeats its first point exactly at the end. Frames are REP-103; closed shapes are
traversed counter-clockwise unless stated otherwise. :func:`unicycle_trajectory` is a
trajectory: its points carry a third column, their time [s] (trajectory tracking, §9.4.2).
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['circle', 'figure_eight', 'parabola', 'polyline', 'rounded_rectangle', 'straight_line',
           'unicycle_trajectory']


def straight_line(start: ArrayLike, end: ArrayLike, spacing: float = 0.05) -> NDArray[np.float64]:
    """
    Return points (N, 2) [m] from ``start`` to ``end`` [m], evenly spaced <= ``spacing`` [m].

    Raises
    ------
    ValueError
        If a point is not a finite (2,) vector, ``start == end``, or ``spacing`` is not
        positive and finite.

    >>> straight_line([0.0, 0.0], [1.0, 0.0], spacing=0.5)
    array([[0. , 0. ],
           [0.5, 0. ],
           [1. , 0. ]])

    """
    a = _finite_point(start, 'start')
    b = _finite_point(end, 'end')
    _check_positive(spacing, 'spacing')
    length = math.hypot(*(b - a))
    if length == 0.0:
        raise ValueError('start and end must differ')
    f = np.linspace(0.0, 1.0, math.ceil(length / spacing) + 1)[:, np.newaxis]
    return (1.0 - f) * a + f * b


def circle(center: ArrayLike, radius: float, spacing: float = 0.05,
           start_angle: float = 0.0) -> NDArray[np.float64]:
    """
    Return points (N, 2) [m] on a closed counter-clockwise circle, <= ``spacing`` apart.

    Parameters
    ----------
    center : array_like, shape (2,)
        Centre (x, y) [m].
    radius : float
        Radius r [m] > 0; the length tends to 2 π r as ``spacing`` shrinks.
    spacing : float
        Largest distance between consecutive points [m] (at least 3 segments are used).
    start_angle : float
        Polar angle [rad] of the first (and last) point about the centre, from the x axis;
        the path starts heading ``start_angle + π/2``.

    Raises
    ------
    ValueError
        If ``center`` is not a finite (2,) vector or a scalar is not positive and finite
        (``start_angle``: not finite).

    >>> circle([0.0, 0.0], 1.0, spacing=2.5).round(3)
    array([[ 1.   ,  0.   ],
           [-0.5  ,  0.866],
           [-0.5  , -0.866],
           [ 1.   ,  0.   ]])

    """
    c = _finite_point(center, 'center')
    _check_positive(radius, 'radius')
    _check_positive(spacing, 'spacing')
    if not math.isfinite(start_angle):
        raise ValueError(f'start_angle must be finite, got {start_angle!r}')
    points = _arc(c, radius, start_angle, 2.0 * math.pi, spacing)
    points[-1] = points[0]
    return points


def rounded_rectangle(width: float, height: float, corner_radius: float,
                      spacing: float = 0.05) -> NDArray[np.float64]:
    """
    Return a closed counter-clockwise rectangle with rounded corners (N, 2) [m].

    The path starts at the origin heading +x, at the beginning of the bottom straight, so it
    occupies x in [-r, width - r], y in [0, height]. Its length is
    2 (width + height) - 8 r + 2 π r, approached as ``spacing`` shrinks.

    Parameters
    ----------
    width, height : float
        Outer size [m] along x and y.
    corner_radius : float
        Radius r [m] of the quarter-circle corners, 0 < 2 r <= min(width, height).
    spacing : float
        Largest distance between consecutive points [m].

    Raises
    ------
    ValueError
        If a value is not positive and finite or 2 r > min(width, height).

    >>> rounded_rectangle(2.0, 2.0, 0.5, spacing=0.5).round(3)[:4]
    array([[0.   , 0.   ],
           [0.5  , 0.   ],
           [1.   , 0.   ],
           [1.354, 0.146]])

    """
    for value, name in ((width, 'width'), (height, 'height'), (corner_radius, 'corner_radius'),
                        (spacing, 'spacing')):
        _check_positive(value, name)
    r = corner_radius
    if 2.0 * r > min(width, height):
        raise ValueError(f'need 2 corner_radius <= min(width, height), got r = {r!r}, '
                         f'width = {width!r}, height = {height!r}')
    right, top = width - 2.0 * r, height - 2.0 * r  # centres of the corner arcs span these
    half_pi = 0.5 * math.pi
    pieces = [
        straight_line([0.0, 0.0], [right, 0.0], spacing) if right > 0.0 else None,
        _arc(np.array([right, r]), r, -half_pi, half_pi, spacing),
        straight_line([right + r, r], [right + r, r + top], spacing) if top > 0.0 else None,
        _arc(np.array([right, r + top]), r, 0.0, half_pi, spacing),
        straight_line([right, height], [0.0, height], spacing) if right > 0.0 else None,
        _arc(np.array([0.0, r + top]), r, half_pi, half_pi, spacing),
        straight_line([-r, r + top], [-r, r], spacing) if top > 0.0 else None,
        _arc(np.array([0.0, r]), r, math.pi, half_pi, spacing),
    ]
    kept = [piece for piece in pieces if piece is not None]
    # Each piece starts where the previous one ended: keep that shared point once.
    points = np.concatenate([kept[0]] + [piece[1:] for piece in kept[1:]])
    points[0] = points[-1] = 0.0
    return points


def figure_eight(radius: float, spacing: float = 0.05) -> NDArray[np.float64]:
    """
    Return a closed figure eight (N, 2) [m] of two circles of radius r tangent at the origin.

    The path starts at the origin heading +x, runs the upper circle (centre (0, r))
    counter-clockwise, crosses the origin heading +x again and runs the lower circle
    (centre (0, -r)) clockwise back to the origin. Its length tends to 4 π r.

    Raises
    ------
    ValueError
        If ``radius`` or ``spacing`` is not positive and finite.

    >>> points = figure_eight(1.0, spacing=0.5)
    >>> points[0], points[len(points) // 2], points[-1]
    (array([0., 0.]), array([0., 0.]), array([0., 0.]))

    """
    _check_positive(radius, 'radius')
    _check_positive(spacing, 'spacing')
    upper = _arc(np.array([0.0, radius]), radius, -0.5 * math.pi, 2.0 * math.pi, spacing)
    lower = _arc(np.array([0.0, -radius]), radius, 0.5 * math.pi, -2.0 * math.pi, spacing)
    points = np.concatenate((upper, lower[1:]))
    points[[0, len(upper) - 1, -1]] = 0.0  # the two circles meet exactly at the origin
    return points


def polyline(points: ArrayLike, spacing: float = 0.05) -> NDArray[np.float64]:
    """
    Return the straight segments through the corner ``points`` (M, 2) [m], <= ``spacing`` apart.

    A path with sharp corners (the tracking benchmark's turn); consecutive corners must differ.

    >>> polyline([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], spacing=1.0)
    array([[0., 0.],
           [1., 0.],
           [1., 1.]])

    """
    corners = np.asarray(points, dtype=np.float64)
    if corners.ndim != 2 or corners.shape[1] != 2 or len(corners) < 2:
        raise ValueError(f'points must have shape (M, 2) with M >= 2, got {corners.shape}')
    pieces = [straight_line(a, b, spacing)[:-1] for a, b in zip(corners[:-1], corners[1:])]
    return np.vstack([*pieces, corners[-1:]])


def parabola(a: float, length: float, offset: float = 0.0,
             spacing: float = 0.05) -> NDArray[np.float64]:
    """
    Return points (N, 2) [m] of y = offset + a x² for 0 <= x <= ``length`` [m].

    ``a`` [1/m] is half the curvature at the vertex (x = 0), where the path heads along +x;
    the x step keeps consecutive points <= ``spacing`` apart.

    >>> parabola(0.5, 2.0, spacing=1.0)[-1]
    array([2., 2.])

    """
    _check_positive(length, 'length')
    _check_positive(spacing, 'spacing')
    if not (math.isfinite(a) and math.isfinite(offset)):
        raise ValueError(f'a and offset must be finite, got {a!r}, {offset!r}')
    # |dy/dx| <= 2 |a| length, so a step dx = spacing / sqrt(1 + (2 a length)²) is short enough.
    count = math.ceil(length * math.hypot(1.0, 2.0 * a * length) / spacing)
    x = np.linspace(0.0, length, count + 1)
    return np.column_stack([x, offset + a * x * x])


def unicycle_trajectory(start: ArrayLike, segments: ArrayLike,
                        step: float = 0.02) -> NDArray[np.float64]:
    """
    Return (N, 3) rows (x [m], y [m], t [s]) of a unicycle driven by piecewise-constant inputs.

    The reference of trajectory tracking (book (9.59)): from ``start`` (x, y, θ) at t = 0,
    each row (v [m/s], ω [rad/s], duration [s]) of ``segments`` drives exact arcs (straights
    when ω = 0), sampled every ``step`` [s] (each segment ends on a sample). Speeds must be
    > 0, so that the points are distinct. Ejemplo 9.3: start (0, 0, π/2) (the book's φ = 0),
    segments [[0.2, 0.3, 10], [0.2, 0.2, 10], [0.1, 0.2, 10]].

    >>> unicycle_trajectory([0.0, 0.0, 0.0], [[1.0, 0.0, 1.0]], step=0.5)
    array([[0. , 0. , 0. ],
           [0.5, 0. , 0.5],
           [1. , 0. , 1. ]])

    """
    pose = np.asarray(start, dtype=np.float64)
    rows = np.asarray(segments, dtype=np.float64)
    if pose.shape != (3,) or not np.all(np.isfinite(pose)):
        raise ValueError(f'start must be a finite (x, y, theta), got {start!r}')
    if rows.ndim != 2 or rows.shape[1] != 3 or len(rows) == 0 or not np.all(np.isfinite(rows)):
        raise ValueError('segments must be rows of finite (v, omega, duration)')
    if np.any(rows[:, 0] <= 0.0) or np.any(rows[:, 2] <= 0.0):
        raise ValueError('segment speeds and durations must be > 0')
    _check_positive(step, 'step')
    x, y, theta = pose
    out = [[x, y, 0.0]]
    t0 = 0.0
    for v, omega, duration in rows:
        tau = np.linspace(0.0, duration, max(math.ceil(duration / step - 1e-9), 1) + 1)[1:]
        heading = theta + omega * tau
        if omega == 0.0:
            xs, ys = x + v * tau * math.cos(theta), y + v * tau * math.sin(theta)
        else:
            xs = x + v / omega * (np.sin(heading) - math.sin(theta))
            ys = y - v / omega * (np.cos(heading) - math.cos(theta))
        out.extend(np.column_stack([xs, ys, t0 + tau]).tolist())
        x, y, theta, t0 = float(xs[-1]), float(ys[-1]), float(heading[-1]), t0 + duration
    return np.array(out)


def _arc(center: NDArray[np.float64], radius: float, start_angle: float, sweep: float,
         spacing: float) -> NDArray[np.float64]:
    """
    Return points on an arc, polar angles start_angle .. start_angle + sweep [rad].

    The arc is cut into equal angles with arcs (hence chords) <= ``spacing``; a full turn
    gets at least 3 segments.
    """
    minimum = 3 if abs(sweep) >= 2.0 * math.pi else 1
    n = max(math.ceil(radius * abs(sweep) / spacing), minimum)
    angles = start_angle + np.linspace(0.0, sweep, n + 1)
    return center + radius * np.column_stack((np.cos(angles), np.sin(angles)))


def _finite_point(p: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return ``p`` as a float64 (2,) vector, or raise ValueError."""
    q = np.asarray(p, dtype=np.float64)
    if q.shape != (2,) or not np.all(np.isfinite(q)):
        raise ValueError(f'{name} must be a finite (2,) vector, got {p!r}')
    return q


def _check_positive(value: float, name: str) -> None:
    """Raise ValueError unless ``value`` is positive and finite."""
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f'{name} must be positive and finite, got {value!r}')
