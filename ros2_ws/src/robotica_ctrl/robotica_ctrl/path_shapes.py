"""
Reference paths for the mobile-robot trackers of book ch. 9, as (N, 2) point arrays [m].

The book tests its path trackers on a straight path (Ejemplo 9.1, §9.3.1) and on paths made
of straights and arcs (§9.2 lists where paths come from). These functions sample such shapes
as polylines for :class:`robotica_ctrl.mobile.path.PolylinePath`: consecutive points are at
most ``spacing`` apart (arcs are sampled by angle, and a chord is shorter than its arc), and a
closed shape repeats its first point exactly at the end. Frames are REP-103; closed shapes are
traversed counter-clockwise unless stated otherwise.
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['circle', 'figure_eight', 'rounded_rectangle', 'straight_line']


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
