"""
Solid primitives in 3-D (book §12.4.3): intersection and minimum-distance tests.

The book models robots and their surroundings by unions of primitives (spheres, cylinders,
boxes, cones, planes) and singles out the **cylsphere** (a cylinder with a sphere on each end,
the model of a link with a joint at each end; Shaffer and Herb 1992). Here: :class:`Sphere`,
:class:`Box` (oriented), :class:`Cylinder` (flat caps) and :class:`Cylsphere` (capsule), all
closed convex sets in one frame [m]; :func:`distance` gives the least distance between two of
them (0 when they meet) and :func:`intersect` whether they meet. Cones and planes are not
implemented.

How each pair is computed (no sampling anywhere):

================================  =========================================================
sphere, cylsphere with each other  closed form: distance between centres / axis segments,
                                   less the radii. Segment-segment: the squared distance is a
                                   convex quadratic on [0, 1]²; its minimum is the interior
                                   stationary point when that lies in the square, else the
                                   least of the four endpoint-to-segment distances.
sphere - box, sphere - cylinder    closed form: the point's distance to the solid (clamping
                                   in the box's frame; axial and radial excess for the
                                   cylinder, hypot of the two), less the radius.
cylsphere - box                    exact: along the axis segment the squared distance to the
                                   box is piecewise quadratic (breaks where a box coordinate
                                   crosses ±half-extent); each piece is minimised in closed
                                   form. Less the radius.
box - box                          separating-axis test (15 axes) for intersection; when
                                   apart, the least of the 16 vertex-to-box and 144 edge-edge
                                   distances (two disjoint convex polytopes have a nearest
                                   pair that is vertex-face or edge-edge).
cylsphere - cylinder               iterative-exact: the distance from the axis point p(t) to
                                   the cylinder is convex in t (the distance to a convex set,
                                   composed with an affine map), minimised on [0, 1] by
                                   bounded Brent (SciPy) to 1e-12 in t. Less the radius.
box - cylinder, cylinder pairs     iterative-exact: min |x - y|² over x in A, y in B is a
                                   convex program (convex quadratic objective in the
                                   parameters, box bounds and the disc constraint
                                   w1² + w2² <= r²), solved by SciPy's SLSQP; a KKT point of a
                                   convex program is its global minimum. The result is then
                                   *certified*: n = (y - x) / |y - x| gives the lower bound
                                   -h_A(n) - h_B(-n) (support functions, a separating plane),
                                   and alternating projections (Cheney and Goldstein 1959)
                                   refine x, y until the bounds agree within ``tolerance``.
================================  =========================================================

The iterative pairs report the upper bound |y - x| once certified; if the bounds have not met
after the iteration cap, the lower bound (never more clearance than there is).
"""

from dataclasses import dataclass, field
import math
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['Box', 'Cylinder', 'Cylsphere', 'Solid', 'Sphere', 'closest_point', 'distance',
           'intersect', 'point_distance', 'segment_segment_distance_3d', 'support']

_MAX_PROJECTIONS = 20000   # alternating projections before reporting the lower bound


def _vector(value: ArrayLike, name: str) -> NDArray[np.float64]:
    v = np.array(value, dtype=np.float64)
    if v.shape != (3,) or not np.isfinite(v).all():
        raise ValueError(f'{name} must be a finite 3-vector [m], got {value!r}')
    v.flags.writeable = False
    return v


def _positive(value: float, name: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
        raise ValueError(f'{name} must be > 0 m, got {value!r}')
    return float(value)


@dataclass(frozen=True)
class Sphere:
    """
    A solid sphere: ``center`` (3,) [m], ``radius`` > 0 [m].

    >>> Sphere([0, 0, 0], 1.0).radius
    1.0
    """

    center: NDArray[np.float64]
    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, 'center', _vector(self.center, 'center'))
        object.__setattr__(self, 'radius', _positive(self.radius, 'radius'))


@dataclass(frozen=True)
class Box:
    """
    An oriented solid box: ``center`` (3,), ``half_extents`` (3,) > 0 [m], ``rotation`` (3, 3).

    ``rotation`` is R_world_box: its columns are the box's axes in the world frame (a proper
    rotation, orthonormal to 1e-9 with determinant +1).

    >>> Box([0, 0, 0], [1, 2, 3]).rotation.tolist()[0]
    [1.0, 0.0, 0.0]
    """

    center: NDArray[np.float64]
    half_extents: NDArray[np.float64]
    rotation: NDArray[np.float64] = field(default_factory=lambda: np.eye(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, 'center', _vector(self.center, 'center'))
        h = _vector(self.half_extents, 'half_extents')
        if not (h > 0.0).all():
            raise ValueError(f'half_extents must be > 0 m, got {h.tolist()}')
        object.__setattr__(self, 'half_extents', h)
        r = np.array(self.rotation, dtype=np.float64)
        if (r.shape != (3, 3) or not np.isfinite(r).all()
                or not np.allclose(r.T @ r, np.eye(3), atol=1e-9)
                or not np.linalg.det(r) > 0.0):
            raise ValueError('rotation must be a proper rotation matrix (3, 3)')
        r.flags.writeable = False
        object.__setattr__(self, 'rotation', r)

    def vertices(self) -> NDArray[np.float64]:
        """Return the 8 corners (8, 3) [m] in the world frame."""
        signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)],
                         dtype=np.float64)
        return np.asarray(self.center + (signs * self.half_extents) @ self.rotation.T)

    def edges(self) -> NDArray[np.float64]:
        """Return the twelve edges as corner pairs (12, 2, 3) [m], corners one sign apart."""
        v = self.vertices()
        pairs = [(a, b) for a in range(8) for b in range(a + 1, 8)
                 if bin(a ^ b).count('1') == 1]
        return np.array([[v[a], v[b]] for a, b in pairs])


@dataclass(frozen=True)
class _Axial:
    """A solid around the segment ``start`` - ``end`` [m] at ``radius`` [m]."""

    start: NDArray[np.float64]
    end: NDArray[np.float64]
    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, 'start', _vector(self.start, 'start'))
        object.__setattr__(self, 'end', _vector(self.end, 'end'))
        object.__setattr__(self, 'radius', _positive(self.radius, 'radius'))

    def frame(self) -> tuple[NDArray[np.float64], NDArray[np.float64], float,
                             NDArray[np.float64], NDArray[np.float64]]:
        """Return the centre, unit axis u, half-length and two unit vectors normal to u."""
        axis = self.end - self.start
        length = float(np.linalg.norm(axis))
        u = axis / length if length > 0.0 else np.array([0.0, 0.0, 1.0])
        pick = np.eye(3)[int(np.argmin(np.abs(u)))]
        e1 = np.cross(u, pick)
        e1 /= np.linalg.norm(e1)
        return 0.5 * (self.start + self.end), u, 0.5 * length, e1, np.cross(u, e1)


@dataclass(frozen=True)
class Cylinder(_Axial):
    """
    A solid cylinder with flat caps: axis from ``start`` to ``end`` (3,) [m], ``radius`` [m].

    >>> Cylinder([0, 0, 0], [0, 0, 2], 0.5).frame()[2]
    1.0
    """

    def __post_init__(self) -> None:
        super().__post_init__()
        if np.array_equal(self.start, self.end):
            raise ValueError('a cylinder needs start != end (its axis)')


@dataclass(frozen=True)
class Cylsphere(_Axial):
    """
    A cylsphere (capsule): the points within ``radius`` [m] of the segment start - end [m].

    The book's cylinder with a sphere on each end (§12.4.3); start = end is a sphere.

    >>> Cylsphere([0, 0, 0], [1, 0, 0], 0.2).radius
    0.2
    """


Solid = Union[Sphere, Box, Cylinder, Cylsphere]


def _points(points: ArrayLike) -> NDArray[np.float64]:
    p = np.asarray(points, dtype=np.float64)
    if p.shape[-1:] != (3,) or not np.isfinite(p).all():
        raise ValueError(f'points must be finite with shape (k, 3), got shape {p.shape}')
    return p.reshape(-1, 3)


def _segment_points(p: NDArray[np.float64], a: NDArray[np.float64],
                    b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the nearest point of segment a-b to each point (k, 3)."""
    e = b - a
    ee = float(e @ e)
    t = np.zeros(len(p)) if ee == 0.0 else np.clip((p - a) @ e / ee, 0.0, 1.0)
    return np.asarray(a + t[:, None] * e)


def closest_point(solid: Solid, points: ArrayLike) -> NDArray[np.float64]:
    """
    Return the point of ``solid`` nearest to each point (k, 3) [m] (itself if inside).

    The Euclidean projection, in closed form for every primitive (a cylinder is the product
    of an interval along its axis and a disc across it, projected one factor at a time).

    >>> closest_point(Box([0, 0, 0], [1, 1, 1]), [[3.0, 0.5, -4.0]]).tolist()
    [[1.0, 0.5, -1.0]]
    """
    p = _points(points)
    if isinstance(solid, Sphere):
        d = p - solid.center
        n = np.linalg.norm(d, axis=1, keepdims=True)
        scale = np.where(n > solid.radius, solid.radius / np.maximum(n, 1e-300), 1.0)
        return np.asarray(solid.center + d * scale)
    if isinstance(solid, Box):
        local = (p - solid.center) @ solid.rotation
        clamped = np.clip(local, -solid.half_extents, solid.half_extents)
        return np.asarray(solid.center + clamped @ solid.rotation.T)
    if isinstance(solid, Cylsphere):
        q = _segment_points(p, solid.start, solid.end)
        d = p - q
        n = np.linalg.norm(d, axis=1, keepdims=True)
        scale = np.where(n > solid.radius, solid.radius / np.maximum(n, 1e-300), 1.0)
        return np.asarray(q + d * scale)
    if isinstance(solid, Cylinder):
        c, u, h, _, _ = solid.frame()
        rel = p - c
        a = rel @ u
        w = rel - a[:, None] * u
        n = np.linalg.norm(w, axis=1, keepdims=True)
        scale = np.where(n > solid.radius, solid.radius / np.maximum(n, 1e-300), 1.0)
        return np.asarray(c + np.clip(a, -h, h)[:, None] * u + w * scale)
    raise ValueError(f'not a solid primitive: {type(solid).__name__}')


def point_distance(solid: Solid, points: ArrayLike) -> NDArray[np.float64]:
    """
    Return the distance [m] from each point (k, 3) to ``solid``; 0 inside.

    >>> point_distance(Cylinder([0, 0, -1], [0, 0, 1], 1.0), [[2, 0, 2], [0, 0, 0]]).tolist()
    [1.4142135623730951, 0.0]
    """
    p = _points(points)
    if isinstance(solid, Cylinder):       # hypot of the axial and radial excess: exact
        c, u, h, _, _ = solid.frame()
        rel = p - c
        a = rel @ u
        radial = np.linalg.norm(rel - a[:, None] * u, axis=1)
        return np.asarray(np.hypot(np.maximum(np.abs(a) - h, 0.0),
                                   np.maximum(radial - solid.radius, 0.0)))
    return np.asarray(np.linalg.norm(p - closest_point(solid, p), axis=1))


def support(solid: Solid, direction: ArrayLike) -> NDArray[np.float64]:
    """
    Return a point of ``solid`` farthest along ``direction`` (3,): the support mapping.

    h(n) = support(n) · n is the support function: every point x of the solid has
    x · n <= h(n).

    >>> support(Box([0, 0, 0], [1, 2, 3]), [1.0, -1.0, 0.0]).tolist()
    [1.0, -2.0, 3.0]
    """
    n = _vector(direction, 'direction')
    if isinstance(solid, Sphere):
        norm = float(np.linalg.norm(n))
        return np.asarray(solid.center + (solid.radius * n / norm if norm > 0.0 else 0.0))
    if isinstance(solid, Box):
        local = solid.rotation.T @ n
        return np.asarray(solid.center
                          + solid.rotation @ (np.where(local >= 0.0, 1.0, -1.0)
                                              * solid.half_extents))
    if isinstance(solid, Cylsphere):
        end = solid.end if float((solid.end - solid.start) @ n) > 0.0 else solid.start
        norm = float(np.linalg.norm(n))
        return np.asarray(end + (solid.radius * n / norm if norm > 0.0 else 0.0))
    if isinstance(solid, Cylinder):
        c, u, h, e1, e2 = solid.frame()
        along = float(n @ u)
        # The rim's direction from n's components across the axis: exactly normal to u.
        w1, w2 = float(n @ e1), float(n @ e2)
        norm = math.hypot(w1, w2)
        rim = solid.radius * (w1 * e1 + w2 * e2) / norm if norm > 0.0 else np.zeros(3)
        return np.asarray(c + (h if along >= 0.0 else -h) * u + rim)
    raise ValueError(f'not a solid primitive: {type(solid).__name__}')


def segment_segment_distance_3d(p0: ArrayLike, p1: ArrayLike, q0: ArrayLike,
                                q1: ArrayLike) -> NDArray[np.float64]:
    """
    Return the distance [m] between segments p0-p1 and q0-q1, each (3,) or (k, 3): (k,).

    |p(s) - q(t)|² is a convex quadratic on [0, 1]²: its minimum is the stationary point when
    that lies inside the square (non-parallel segments), else on an edge of the square, i.e. one
    of the four endpoint-to-segment distances. Exact up to rounding, parallel segments included.

    >>> segment_segment_distance_3d([0, 0, 0], [2, 0, 0], [1, -1, 2], [1, 1, 2]).tolist()
    [2.0]
    """
    a0, a1, b0, b1 = (np.atleast_2d(np.asarray(v, dtype=np.float64)) for v in (p0, p1, q0, q1))
    d1, d2, r = a1 - a0, b1 - b0, a0 - b0
    a, e = (d1 * d1).sum(axis=1), (d2 * d2).sum(axis=1)
    b, c, f = (d1 * d2).sum(axis=1), (d1 * r).sum(axis=1), (d2 * r).sum(axis=1)
    det = a * e - b * b

    def point_segment(p: NDArray[np.float64], s0: NDArray[np.float64],
                      s1: NDArray[np.float64]) -> NDArray[np.float64]:
        d = s1 - s0
        dd = (d * d).sum(axis=1)
        with np.errstate(divide='ignore', invalid='ignore'):
            t = np.where(dd > 0.0, ((p - s0) * d).sum(axis=1) / dd, 0.0)
        t = np.clip(t, 0.0, 1.0)
        return np.asarray(np.linalg.norm(p - s0 - t[:, None] * d, axis=1))

    best = np.minimum.reduce([point_segment(a0, b0, b1), point_segment(a1, b0, b1),
                              point_segment(b0, a0, a1), point_segment(b1, a0, a1)])
    with np.errstate(divide='ignore', invalid='ignore'):
        s = (b * f - c * e) / det
        t = (a * f - b * c) / det
    inside = (det > 1e-14 * a * e) & (s >= 0.0) & (s <= 1.0) & (t >= 0.0) & (t <= 1.0)
    if inside.any():
        gap = (a0 + s[:, None] * d1) - (b0 + t[:, None] * d2)
        best = np.where(inside, np.minimum(best, np.linalg.norm(gap, axis=1)), best)
    return np.asarray(best)


def _segment_box(p0: NDArray[np.float64], p1: NDArray[np.float64], box: Box) -> float:
    """Return the exact distance between a segment and a box (piecewise quadratic in t)."""
    q0 = box.rotation.T @ (p0 - box.center)
    e = box.rotation.T @ (p1 - p0)
    h = box.half_extents
    breaks = [0.0, 1.0]
    for i in range(3):
        if e[i] != 0.0:
            breaks += [t for t in ((-h[i] - q0[i]) / e[i], (h[i] - q0[i]) / e[i]) if 0 < t < 1]
    breaks = sorted(breaks)

    def squared(t: float) -> float:
        q = q0 + t * e
        excess = np.maximum(np.abs(q) - h, 0.0)
        return float(excess @ excess)

    best = min(squared(t) for t in breaks)
    for lo, hi in zip(breaks, breaks[1:]):
        mid = q0 + 0.5 * (lo + hi) * e
        outside = np.abs(mid) > h                       # the clamped axes on this piece
        target = np.sign(mid) * h
        # Σ over clamped axes of (q0_i - target_i + t e_i)²: A t² + B t + C.
        quad = float((e[outside] ** 2).sum())
        lin = float(2.0 * ((q0 - target)[outside] * e[outside]).sum())
        if quad > 0.0:
            best = min(best, squared(min(max(-lin / (2.0 * quad), lo), hi)))
    return math.sqrt(best)


def _separated_on(axis: NDArray[np.float64], a: Box, b: Box) -> bool:
    norm = float(np.linalg.norm(axis))
    if norm < 1e-12:
        return False
    n = axis / norm
    reach_a = float(np.abs(a.rotation.T @ n) @ a.half_extents)
    reach_b = float(np.abs(b.rotation.T @ n) @ b.half_extents)
    return abs(float((b.center - a.center) @ n)) > reach_a + reach_b


def _boxes_intersect(a: Box, b: Box) -> bool:
    """Return whether two oriented boxes meet: the separating-axis test (15 axes)."""
    axes = [a.rotation[:, i] for i in range(3)] + [b.rotation[:, j] for j in range(3)]
    axes += [np.cross(a.rotation[:, i], b.rotation[:, j]) for i in range(3) for j in range(3)]
    return not any(_separated_on(axis, a, b) for axis in axes)


def _box_box(a: Box, b: Box) -> float:
    if _boxes_intersect(a, b):
        return 0.0
    d = min(float(point_distance(b, a.vertices()).min()),
            float(point_distance(a, b.vertices()).min()))
    ea, eb = a.edges(), b.edges()
    i, j = np.meshgrid(np.arange(12), np.arange(12), indexing='ij')
    edge = segment_segment_distance_3d(ea[i.ravel(), 0], ea[i.ravel(), 1],
                                       eb[j.ravel(), 0], eb[j.ravel(), 1])
    return min(d, float(edge.min()))


def _segment_cylinder(p0: NDArray[np.float64], p1: NDArray[np.float64],
                      cylinder: Cylinder) -> float:
    """Return the distance from segment p0-p1 to a cylinder: convex in t, bounded Brent."""
    from scipy.optimize import minimize_scalar

    def f(t: float) -> float:
        return float(point_distance(cylinder, p0 + t * (p1 - p0))[0])

    ends = min(f(0.0), f(1.0))
    if np.array_equal(p0, p1):
        return ends
    result = minimize_scalar(f, bounds=(0.0, 1.0), method='bounded',
                             options={'xatol': 1e-12, 'maxiter': 500})
    return min(ends, float(result.fun))


def _parametrise(solid: Solid) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                        list[tuple[float, float]], list[int]]:
    """Return x = offset + M z, the bounds of z and the disc variables (cylinder) of a solid."""
    if isinstance(solid, Box):
        return solid.center, solid.rotation, [(-v, v) for v in solid.half_extents.tolist()], []
    if isinstance(solid, Cylinder):
        c, u, half, e1, e2 = solid.frame()
        r = solid.radius
        return c, np.column_stack([u, e1, e2]), [(-half, half), (-r, r), (-r, r)], [1, 2]
    raise ValueError(f'no parametrisation for {type(solid).__name__}')


def _convex_pair(a: Solid, b: Solid, tolerance: float) -> tuple[float, float]:
    """Return (lower, upper) bounds of the distance of two convex solids (module docstring)."""
    from scipy.optimize import minimize
    oa, ma, bounds_a, disc_a = _parametrise(a)
    ob, mb, bounds_b, disc_b = _parametrise(b)
    na = ma.shape[1]
    m = np.hstack([ma, -mb])
    o = oa - ob

    def objective(z: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
        g = o + m @ z
        return float(g @ g), 2.0 * (m.T @ g)

    constraints: list[dict[str, Any]] = []
    for disc, shift, solid in ((disc_a, 0, a), (disc_b, na, b)):
        if disc:
            idx = [shift + k for k in disc]
            r2 = float(solid.radius) ** 2            # type: ignore[union-attr]

            def disc_fun(z: NDArray[np.float64], idx: list[int] = idx,
                         r2: float = r2) -> float:
                return r2 - float(z[idx] @ z[idx])

            def disc_jac(z: NDArray[np.float64], idx: list[int] = idx) -> NDArray[np.float64]:
                g = np.zeros_like(z)
                g[idx] = -2.0 * z[idx]
                return g

            constraints.append({'type': 'ineq', 'fun': disc_fun, 'jac': disc_jac})
    z0 = np.zeros(m.shape[1])
    result = minimize(objective, z0, jac=True, method='SLSQP', bounds=bounds_a + bounds_b,
                      constraints=constraints, options={'ftol': 1e-16, 'maxiter': 500})
    # The solver's points, put back into the solids (its constraints hold only to rounding).
    x = closest_point(a, oa + ma @ result.x[:na])[0]
    y = closest_point(b, ob + mb @ result.x[na:])[0]
    return _certify(a, b, x, y, tolerance)


def _certify(a: Solid, b: Solid, x: NDArray[np.float64], y: NDArray[np.float64],
             tolerance: float) -> tuple[float, float]:
    """Refine x in a, y in b by alternating projections until the bounds meet."""
    lower, upper = 0.0, float(np.linalg.norm(y - x))
    for k in range(_MAX_PROJECTIONS):
        if upper <= tolerance:
            return 0.0, upper
        n = (y - x) / upper
        lower = max(lower, float(support(b, -n) @ n - support(a, n) @ n))
        if upper - lower <= tolerance:
            return lower, upper
        y = closest_point(b, x)[0]
        x = closest_point(a, y)[0]
        upper = min(upper, float(np.linalg.norm(y - x)))
    return lower, upper


def _distance_bounds(a: Solid, b: Solid, tolerance: float) -> tuple[float, float]:
    """Return (lower, upper) bounds of the distance; equal for the closed-form pairs."""
    rank = {Sphere: 0, Cylsphere: 1, Box: 2, Cylinder: 3}
    for solid in (a, b):
        if type(solid) not in rank:
            raise ValueError(f'not a solid primitive: {type(solid).__name__}')
    if rank[type(a)] > rank[type(b)]:
        a, b = b, a
    d: float
    if isinstance(a, Sphere):
        d = float(point_distance(b, a.center)[0]) - a.radius
    elif isinstance(a, Cylsphere):
        if isinstance(b, Cylsphere):
            d = float(segment_segment_distance_3d(a.start, a.end, b.start, b.end)[0]) - b.radius
        elif isinstance(b, Box):
            d = _segment_box(a.start, a.end, b)
        else:
            assert isinstance(b, Cylinder)
            d = _segment_cylinder(a.start, a.end, b)
        d -= a.radius
    elif isinstance(a, Box) and isinstance(b, Box):
        d = _box_box(a, b)
    else:
        return _convex_pair(a, b, tolerance)
    d = max(d, 0.0)
    return d, d


def _check_tolerance(tolerance: float) -> None:
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise ValueError(f'tolerance must be > 0 m, got {tolerance!r}')


def distance(a: Solid, b: Solid, tolerance: float = 1e-9) -> float:
    """
    Return the least distance [m] between two solids; 0 when they meet.

    Exact (closed form) for every pair without a cylinder, and for sphere - cylinder; within
    ``tolerance`` [m] for the iterative pairs (module docstring: the method of each pair).

    >>> distance(Sphere([0, 0, 0], 1.0), Sphere([5, 0, 0], 2.0))
    2.0
    >>> round(distance(Cylinder([0, 0, 0], [0, 0, 1], 1.0), Cylinder([3, 0, 2], [3, 0, 3], 1.0)),
    ...       9)
    1.414213562
    """
    _check_tolerance(tolerance)
    lower, upper = _distance_bounds(a, b, tolerance)
    return upper if upper - lower <= tolerance else lower


def intersect(a: Solid, b: Solid, tolerance: float = 1e-9) -> bool:
    """
    Return whether two solids meet (touching counts); within ``tolerance`` [m] when iterative.

    >>> intersect(Box([0, 0, 0], [1, 1, 1]), Cylsphere([2, 0, 0], [3, 0, 0], 1.0))
    True
    """
    _check_tolerance(tolerance)
    if isinstance(a, Box) and isinstance(b, Box):
        return _boxes_intersect(a, b)
    lower, upper = _distance_bounds(a, b, tolerance)
    return lower <= 0.0 or upper <= tolerance
