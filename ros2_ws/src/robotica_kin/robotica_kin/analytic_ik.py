"""
Closed-form (analytic) inverse kinematics of the book's manipulators (Ollero 2001, §4.4).

The inverse problem of §4.4 asks for the joint values that put the wrist frame {M} = {n} at a
given pose. Where the robot's structure allows it the answer has a closed form, with several
solutions (elbow up/down, shoulder left/right, wrist flip); these functions return all of
them, and :func:`choose_solution` applies the book's selection criteria (least weighted joint
motion from the current configuration, within the joint limits).

- :func:`ikine_planar_2r`, :func:`ikine_planar_2r_geometric`, :func:`ikine_planar_3r`: the
  planar arm of Ej. 4.1 / Ej. 4.4, algebraic solution (4.28)-(4.39) and geometric solution
  (4.40)-(4.44). Reachable workspace: the annulus ``|l1 - l2| <= r <= l1 + l2``.
- :func:`ikine_rp`, :func:`ikine_rpr`: the R-P-R robot of Ej. 4.2; Ej. 4.3 (4.24)-(4.25) for
  the first two joints, and the whole arm from the structure of its forward model.
- :func:`ikine_puma560`: the eight solutions of the PUMA 560 of HEMERO's ``dhp560`` (book
  §A.2) by Pieper's method (§4.4): axes 4, 5, 6 meet at the wrist centre, whose position gives
  θ1..θ3 and the orientation θ4..θ6.

Angles are in rad, lengths in m; revolute results are wrapped to (-π, π]. An unreachable goal
raises ``ValueError`` with a message that says "unreachable" and why. Each function takes a
distance tolerance ``tol`` [m]: a goal within ``tol`` of the boundary of the reachable
workspace is treated as lying on it (one solution instead of two nearly equal ones).
"""

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.finite import finite_real
from robotica_kin.robots import puma560
from robotica_kin.transforms import ishomog, trinv
from robotica_kin.types import Vector

__all__ = [
    'choose_solution', 'ikine_planar_2r', 'ikine_planar_2r_geometric', 'ikine_planar_3r',
    'ikine_puma560', 'ikine_rp', 'ikine_rpr',
]

BOUNDARY_TOL = 1e-10
"""Default distance tolerance [m] of the workspace boundary (one solution within it)."""

WRIST_SINGULAR_TOL = 1e-10
"""|sin θ5| at or below which the PUMA wrist is taken as singular (axes 4 and 6 aligned)."""

RPR_POSE_TOL = 1e-9
"""Default tolerance of :func:`ikine_rpr` on the pose (rotation entries [-], z [m], d2 [m])."""

_STRUCTURE_TOL = 1e-9


def _length(name: str, value: float) -> float:
    number = finite_real(name, value)
    if number <= 0.0:
        raise ValueError(f'{name} must be a length > 0 m, got {value!r}')
    return number


def _tolerance(tol: float) -> float:
    number = finite_real('tol', tol)
    if number < 0.0:
        raise ValueError(f'tol must be >= 0, got {tol!r}')
    return number


def _transform(T: ArrayLike, name: str) -> NDArray[np.float64]:
    if not ishomog(T):
        raise ValueError(f'{name}: T must be a finite 4x4 homogeneous transform, got {T!r}')
    return np.asarray(T, dtype=np.float64)


def _two_link(l1: float, l2: float, x: float, y: float, tol: float,
              what: str) -> list[tuple[float, float]]:
    """
    Return the solutions (θ1, θ2) of the planar 2R arm, book (4.28)-(4.39), unwrapped.

    ``1 - c2`` and ``1 + c2`` are evaluated in factored form, ((l1 + l2)^2 - r^2) / (2 l1 l2)
    and (r^2 - (l1 - l2)^2) / (2 l1 l2), so that s2 = sqrt((1 - c2)(1 + c2)) keeps its
    accuracy near the boundary circles; ``l1 + l2 c2`` is evaluated as (l1 - l2) + l2 (1 + c2).
    """
    r = math.hypot(x, y)
    inner, outer = abs(l1 - l2), l1 + l2
    if r < inner - tol or r > outer + tol:
        raise ValueError(
            f'{what} ({x:.6g}, {y:.6g}) is unreachable: its distance r = {r:.6g} m lies '
            f'outside the annulus {inner:.6g} m <= r <= {outer:.6g} m (book §4.4)')
    if r <= tol and inner <= tol:
        # l1 = l2 and the goal at the origin: any θ1 works (4.36); θ1 = 0 is returned.
        return [(0.0, math.pi)]
    one_minus_c2 = (outer - r) * (outer + r) / (2.0 * l1 * l2)
    one_plus_c2 = (r - inner) * (r + inner) / (2.0 * l1 * l2)
    on_boundary = outer - r <= tol or r - inner <= tol
    if outer - r <= tol:
        one_minus_c2 = 0.0
    elif r - inner <= tol:
        one_plus_c2 = 0.0
    c2 = 0.5 * (one_plus_c2 - one_minus_c2)                       # (4.28)
    s2 = 0.0 if on_boundary else math.sqrt(one_minus_c2 * one_plus_c2)  # (4.29)
    k1 = (l1 - l2) + l2 * one_plus_c2                              # l1 + l2 c2
    beta = math.atan2(y, x) if r > 0.0 else 0.0
    solutions = []
    for sign in ((1.0,) if on_boundary else (1.0, -1.0)):
        theta2 = math.atan2(sign * s2, c2)                          # (4.30)
        theta1 = beta - math.atan2(l2 * sign * s2, k1)              # (4.35)
        solutions.append((theta1, theta2))
    return solutions


def ikine_planar_2r(l1: float, l2: float, x: float, y: float, *,
                    tol: float = BOUNDARY_TOL) -> NDArray[np.float64]:
    """
    Return every joint solution of the planar 2R arm reaching (x, y), algebraic method.

    Book §4.4, Ej. 4.4, (4.28)-(4.39): c2 = (x^2 + y^2 - l1^2 - l2^2) / (2 l1 l2),
    s2 = ±sqrt(1 - c2^2), θ2 = atan2(s2, c2), θ1 = atan2(y, x) - atan2(l2 s2, l1 + l2 c2).
    The tip is at x = l1 c1 + l2 c12, y = l1 s1 + l2 s12 (4.10), i.e. the position of frame
    {3} of Ej. 4.1 and the tip of :func:`robotica_kin.robots.planar_rr`.

    Parameters
    ----------
    l1, l2 : float
        Link lengths [m], > 0.
    x, y : float
        Goal position of the tip [m] in frame {0}.
    tol : float, optional
        Distance tolerance [m] of the boundary circles (default :data:`BOUNDARY_TOL`).

    Returns
    -------
    ndarray, shape (k, 2)
        Rows [θ1, θ2] [rad], wrapped to (-π, π]. Inside the annulus
        ``|l1 - l2| < r < l1 + l2`` (r = sqrt(x^2 + y^2)) k = 2: first θ2 >= 0 (the elbow
        clockwise of the line from the base to the tip, "elbow down" for a goal on the +x
        side), then θ2 < 0 (elbow counter-clockwise of that line, "elbow up", the triangle
        drawn in the book's geometric solution). On a boundary circle (within ``tol``) k = 1.
        With l1 = l2 and x = y = 0 (both within ``tol``) every θ1 reaches the goal
        (θ2 = π); θ1 = 0 is returned.

    Raises
    ------
    ValueError
        If the goal is unreachable (outside the annulus; the message gives r and the
        annulus), or for non-positive lengths or non-finite input.

    Examples
    --------
    >>> np.degrees(ikine_planar_2r(1.0, 1.0, 1.0, 1.0)).round(6)
    array([[  0.,  90.],
           [ 90., -90.]])
    >>> ikine_planar_2r(4.0, 3.0, 7.0, 0.0)
    array([[0., 0.]])

    """
    l1, l2 = _length('l1', l1), _length('l2', l2)
    x, y, tol = finite_real('x', x), finite_real('y', y), _tolerance(tol)
    solutions = _two_link(l1, l2, x, y, tol, 'goal')
    return np.asarray(wrap_to_pi(np.array(solutions, dtype=np.float64)))


def ikine_planar_2r_geometric(l1: float, l2: float, x: float, y: float, *,
                              tol: float = BOUNDARY_TOL) -> NDArray[np.float64]:
    """
    Return every joint solution of the planar 2R arm reaching (x, y), geometric method.

    Book §4.4, Ej. 4.4, (4.40)-(4.44): the law of cosines in the triangle of sides l1, l2 and
    r = sqrt(x^2 + y^2) gives cos θ2 = (x^2 + y^2 - l1^2 - l2^2) / (2 l1 l2) (4.41), with
    β = atan2(y, x) and cos ψ = (x^2 + y^2 + l1^2 - l2^2) / (2 l1 r), ψ in [0, π] (4.42)-(4.43);
    then θ1 = β - ψ for θ2 >= 0 and θ1 = β + ψ for θ2 < 0 (4.44). The same solutions, in the
    same order, as :func:`ikine_planar_2r` (less accurate near the boundary, where acos is
    ill-conditioned).

    Parameters
    ----------
    l1, l2 : float
        Link lengths [m], > 0.
    x, y : float
        Goal position of the tip [m] in frame {0}.
    tol : float, optional
        Distance tolerance [m] of the boundary circles (default :data:`BOUNDARY_TOL`).

    Returns
    -------
    ndarray, shape (k, 2)
        Rows [θ1, θ2] [rad] in (-π, π]: first θ2 >= 0, then θ2 < 0; k = 1 on a boundary
        circle; θ1 = 0 for the origin when l1 = l2.

    Raises
    ------
    ValueError
        If the goal is unreachable (outside the annulus), or for bad input.

    Examples
    --------
    >>> np.degrees(ikine_planar_2r_geometric(1.0, 1.0, 1.0, 1.0)).round(6)
    array([[  0.,  90.],
           [ 90., -90.]])

    """
    l1, l2 = _length('l1', l1), _length('l2', l2)
    x, y, tol = finite_real('x', x), finite_real('y', y), _tolerance(tol)
    r = math.hypot(x, y)
    inner, outer = abs(l1 - l2), l1 + l2
    if r < inner - tol or r > outer + tol:
        raise ValueError(
            f'goal ({x:.6g}, {y:.6g}) is unreachable: its distance r = {r:.6g} m lies '
            f'outside the annulus {inner:.6g} m <= r <= {outer:.6g} m (book (4.40))')
    if r <= tol and inner <= tol:
        return np.array([[0.0, math.pi]])
    cos_theta2 = (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)                 # (4.41)
    theta2 = math.acos(min(1.0, max(-1.0, cos_theta2)))
    beta = math.atan2(y, x)                                                    # (4.42)
    cos_psi = (r * r + l1 * l1 - l2 * l2) / (2.0 * l1 * r)                     # (4.43)
    psi = math.acos(min(1.0, max(-1.0, cos_psi)))
    rows = [[beta - psi, theta2]]                                              # (4.44)
    if not (outer - r <= tol or r - inner <= tol):
        rows.append([beta + psi, -theta2])
    return np.asarray(wrap_to_pi(np.array(rows, dtype=np.float64)))


def ikine_planar_3r(l1: float, l2: float, x: float, y: float, phi: float, *,
                    tol: float = BOUNDARY_TOL) -> NDArray[np.float64]:
    """
    Return every joint solution of the planar 3R arm of Ej. 4.1 for the goal (x, y, φ).

    Book §4.4, Ej. 4.4: the goal (4.27) is the pose of frame {3} of the Ej. 4.1 table (at the
    end of link 2, turning with θ3), position (x, y) and orientation φ about Z_0. θ1, θ2 come
    from the 2R solution (4.28)-(4.35) (:func:`ikine_planar_2r`) and θ3 = φ - θ1 - θ2 (4.39).

    Parameters
    ----------
    l1, l2 : float
        Link lengths [m], > 0.
    x, y : float
        Goal position of frame {3} [m] in frame {0}.
    phi : float
        Goal orientation of frame {3} [rad] (angle of X_3 from X_0).
    tol : float, optional
        Distance tolerance [m] of the boundary circles (default :data:`BOUNDARY_TOL`).

    Returns
    -------
    ndarray, shape (k, 3)
        Rows [θ1, θ2, θ3] [rad] in (-π, π], in the order of :func:`ikine_planar_2r`.

    Raises
    ------
    ValueError
        If (x, y) is unreachable, or for bad input.

    Examples
    --------
    >>> np.degrees(ikine_planar_3r(1.0, 1.0, 1.0, 1.0, 0.0)).round(6)
    array([[  0.,  90., -90.],
           [ 90., -90.,   0.]])

    """
    phi = finite_real('phi', phi)
    q12 = ikine_planar_2r(l1, l2, x, y, tol=tol)
    theta3 = wrap_to_pi(phi - q12[:, 0] - q12[:, 1])                          # (4.39)
    return np.column_stack([q12, theta3])


def ikine_rp(x: float, y: float) -> tuple[float, float]:
    """
    Return θ1 and d2 of the first two joints of the R-P-R robot for the point (x, y).

    Book §4.4, Ej. 4.3, (4.24)-(4.25): θ1 = atan2(x, -y), d2 = sqrt(x^2 + y^2), from the
    forward model of the first two links (4.23), whose origin of frame {2} is
    (d2 s1, -d2 c1, 0). With x = y = 0, θ1 is arbitrary and 0 is returned.

    Parameters
    ----------
    x, y : float
        Position of the origin of frame {2} [m] in frame {0} (z = 0).

    Returns
    -------
    tuple of float
        θ1 [rad] in (-π, π] and d2 [m] >= 0.

    Raises
    ------
    ValueError
        For non-finite input.

    Examples
    --------
    >>> ikine_rp(0.0, -1.0)
    (0.0, 1.0)
    >>> ikine_rp(1.0, 0.0)
    (1.5707963267948966, 1.0)

    """
    x, y = finite_real('x', x), finite_real('y', y)
    d2 = math.hypot(x, y)                                                      # (4.25)
    if d2 == 0.0:
        return 0.0, 0.0
    return wrap_to_pi(math.atan2(x, -y)), d2                                   # (4.24)


def ikine_rpr(T: ArrayLike, l2: float, *, tol: float = RPR_POSE_TOL) -> Vector:
    """
    Return the joint values [θ1, d2, θ3] of the R-P-R robot of Ej. 4.2 for the pose T.

    The robot is :func:`robotica_kin.robots.cylindrical_rpr` (Table 4.3,
    ``[[0 0 θ1 0 0], [π/2 0 0 d2 1], [0 0 θ3 l2 0]]``). Its forward model, (4.15)-(4.17)
    chained, is ``T_0_3 = T_0_2 Rot(Z, θ3) Tras(Z, l2)`` with ``T_0_2`` of (4.23):
    ``R_0_3 = R_0_2 Rz(θ3)``, ``R_0_2 = [[c1, 0, s1], [s1, 0, -c1], [0, 1, 0]]``, and origin
    ``p = (d2 + l2) (s1, -c1, 0)``. So the reachable poses have z = 0 and Z_3 horizontal, along
    p; the position gives θ1 = atan2(x, -y) and d2 = sqrt(x^2 + y^2) - l2 (Ej. 4.3, (4.24)-(4.25)
    with the offset l2), and ``R_0_2^T R_0_3 = Rz(θ3)`` gives θ3. The solution is unique.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Goal pose of frame {3} in frame {0}.
    l2 : float
        The offset l2 [m] > 0 of the model (d_3 of Table 4.3).
    tol : float, optional
        Tolerance on the reachable form: the largest rotation-entry error [-], |z| [m] and
        the most negative d2 [m] accepted (default :data:`RPR_POSE_TOL`).

    Returns
    -------
    ndarray, shape (3,)
        [θ1 [rad], d2 [m], θ3 [rad]]; angles in (-π, π], d2 >= 0. Joint 2's upper limit is
        not checked (see :func:`choose_solution`).

    Raises
    ------
    ValueError
        If T is not a homogeneous transform, or not reachable by this 3-dof robot: z != 0,
        an orientation not of the form ``R_0_2(θ1) Rz(θ3)``, or d2 < 0 (the point is closer
        than l2 to the axis of joint 1).

    Examples
    --------
    >>> from robotica_kin.forward_kinematics import fkine
    >>> from robotica_kin.robots import cylindrical_rpr
    >>> ikine_rpr(fkine(cylindrical_rpr(0.2), [0.5, 0.3, -1.0]), 0.2).round(12)
    array([ 0.5,  0.3, -1. ])

    """
    T = _transform(T, 'ikine_rpr')
    l2, tol = _length('l2', l2), _tolerance(tol)
    x, y, z = T[:3, 3]
    if abs(z) > tol:
        raise ValueError(
            f'ikine_rpr: pose unreachable: the R-P-R robot reaches only z = 0, got z = {z:.6g} m')
    r = math.hypot(x, y)
    d2 = r - l2
    if d2 < -tol:
        raise ValueError(
            f'ikine_rpr: pose unreachable: the point is at r = {r:.6g} m from the axis of '
            f'joint 1, which needs d2 = r - l2 = {d2:.6g} m < 0')
    theta1 = wrap_to_pi(math.atan2(x, -y))                                     # (4.24)
    c1, s1 = math.cos(theta1), math.sin(theta1)
    R_0_2 = np.array([[c1, 0.0, s1], [s1, 0.0, -c1], [0.0, 1.0, 0.0]])          # (4.23)
    R_2_3 = R_0_2.T @ T[:3, :3]
    theta3 = math.atan2(R_2_3[1, 0], R_2_3[0, 0])
    error = np.max(np.abs(R_2_3 - _rz(theta3)))
    if error > tol:
        raise ValueError(
            f'ikine_rpr: pose unreachable: the orientation is not R_0_2(θ1) Rz(θ3) with Z_3 '
            f'horizontal along the position (rotation error {error:.3g} > tol = {tol:.3g})')
    return np.array([theta1, max(d2, 0.0), wrap_to_pi(theta3)])


def _rx(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rz(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _right_angle_sign(robot: DHModel, i: int) -> float:
    """Return sin(alpha_i) = ±1 of a ±π/2 twist, or raise ValueError."""
    alpha = float(robot.alpha[i])
    if abs(math.cos(alpha)) > _STRUCTURE_TOL:
        raise ValueError(
            f'ikine_puma560: robot {robot.name!r} does not have the PUMA structure: alpha_{i} '
            f'must be ±π/2, got {alpha!r}')
    return math.copysign(1.0, math.sin(alpha))


def _check_puma_structure(robot: DHModel) -> tuple[float, float, float, float]:
    """Check the structure Pieper's solution below assumes; return σ1, σ3, σ4, σ5 = sin α_i."""
    if robot.n != 6 or bool(np.any(robot.prismatic)):
        raise ValueError(
            f'ikine_puma560: robot {robot.name!r} must have 6 revolute joints like puma560(), '
            f'got {robot.n} joints, prismatic {robot.prismatic.tolist()}')
    for i in (0, 2):
        alpha = float(robot.alpha[i])
        if abs(math.sin(alpha)) > _STRUCTURE_TOL or math.cos(alpha) < 0.0:
            raise ValueError(
                f'ikine_puma560: robot {robot.name!r} does not have the PUMA structure: '
                f'alpha_{i} must be 0, got {alpha!r}')
    zeros = {'a_0': robot.a[0], 'a_1': robot.a[1], 'a_4': robot.a[4], 'a_5': robot.a[5],
             'd_5': robot.d[4], 'd_6': robot.d[5]}
    for name, value in zeros.items():
        if abs(float(value)) > _STRUCTURE_TOL:
            raise ValueError(
                f'ikine_puma560: robot {robot.name!r} does not have the PUMA structure (axes 4, '
                f'5, 6 meeting at the wrist centre): {name} must be 0, got {float(value)!r}')
    if abs(float(robot.a[2])) <= _STRUCTURE_TOL:
        raise ValueError(f'ikine_puma560: robot {robot.name!r} needs a_2 != 0 (upper arm)')
    if math.hypot(float(robot.a[3]), float(robot.d[3])) <= _STRUCTURE_TOL:
        raise ValueError(
            f'ikine_puma560: robot {robot.name!r} needs (a_3, d_4) != 0 (forearm)')
    return (_right_angle_sign(robot, 1), _right_angle_sign(robot, 3),
            _right_angle_sign(robot, 4), _right_angle_sign(robot, 5))


def ikine_puma560(T: ArrayLike, robot: DHModel | ArrayLike | None = None, *,
                  theta4_singular: float = 0.0,
                  tol: float = BOUNDARY_TOL) -> NDArray[np.float64]:
    """
    Return all closed-form joint solutions of the PUMA 560 for the tool pose T (up to 8).

    Book §4.4 (Pieper 1968): axes 4, 5, 6 intersect at the wrist centre, the common origin of
    frames {4}, {5}, {6}, so its position fixes θ1, θ2, θ3 and the orientation then fixes
    θ4, θ5, θ6. Derived here for HEMERO's ``dhp560`` (book §A.2), whose twists differ in sign
    from Craig's textbook table; the lengths and the twist signs σ_i = sin α_i are read from
    the model, so any arm of the same structure works (α0 = α2 = 0, α1, α3, α4, α5 = ±π/2,
    a0 = a1 = a4 = a5 = 0, d5 = d6 = 0, a2 != 0). With link transforms (4.5):

    - Wrist centre p (origin of {6} in {0}) = ``Rz(θ1) (X, Y, σ1 Z') + (0, 0, d1)`` with
      ``Y = -σ1 (d2 + d3)`` fixed, so ``-s1 px + c1 py = Y``: θ1 = atan2(py, px) - atan2(Y, X)
      with X = ±sqrt(px^2 + py^2 - Y^2) (shoulder, two solutions).
    - In the arm plane, ``X + i σ1 (pz - d1) = a2 e^{iθ2} + R e^{i(θ2 + θ3 + γ)}`` with
      ``R e^{iγ} = a3 - i σ3 d4``: a planar 2R arm of links |a2| and R, solved by
      (4.28)-(4.35) (elbow, two solutions).
    - ``M = Rx(α3)^T R_0_3^T R_0_6 = Rz(θ4) Rx(α4) Rz(θ5) Rx(α5) Rz(θ6)``, whose third column is
      σ5 (c4 s5, s4 s5, -σ4 c5): θ5 = atan2(±sqrt(m13^2 + m23^2), -σ4 σ5 m33) (wrist, two
      solutions, the "wrist flip" θ4 + π, -θ5, θ6 + π of §4.4), θ4 = atan2(σ5 m23 / s5,
      σ5 m13 / s5), and θ6 from ``(Rz(θ4) Rx(α4) Rz(θ5) Rx(α5))^T M = Rz(θ6)``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        Goal pose of the tool frame in frame {0} (frame {6} when the model has no tool;
        otherwise T is first mapped to frame {6}, ``T @ inv(tool)``).
    robot : DHModel or array_like, optional
        The arm; default :func:`robotica_kin.robots.puma560`.
    theta4_singular : float, optional
        θ4 [rad] returned when the wrist is singular (|s5| <= :data:`WRIST_SINGULAR_TOL`,
        axes 4 and 6 aligned: only θ4 ± θ6 is determined); pass the current θ4 to keep it.
        An arm solution with a singular wrist gives one row (no flip), so k < 8.
    tol : float, optional
        Distance tolerance [m] of the boundaries of the wrist centre's reachable region
        (default :data:`BOUNDARY_TOL`).

    Returns
    -------
    ndarray, shape (k, 6)
        Rows [θ1 … θ6] [rad] in (-π, π]; k = 8 for a generic reachable pose. Order: shoulder
        X >= 0 then X < 0 (X: the wrist centre's coordinate along X_1), within it the
        elbow of :func:`ikine_planar_2r` order, within it s5 >= 0 then the wrist flip.
        Joint limits are not applied (see :func:`choose_solution`).

    Raises
    ------
    ValueError
        If T is not a homogeneous transform, the robot lacks this structure, or the wrist
        centre is unreachable (the message says why: inside the shoulder-offset cylinder
        around axis 1, or outside the annulus the upper arm and forearm reach).

    Examples
    --------
    >>> from robotica_kin.forward_kinematics import fkine
    >>> q = [0.1, -0.5, 0.4, 0.3, 0.6, -0.2]
    >>> solutions = ikine_puma560(fkine(puma560(), q))
    >>> solutions.shape, bool(np.any(np.all(np.abs(solutions - q) < 1e-9, axis=1)))
    ((8, 6), True)

    """
    model = puma560() if robot is None else as_dh_model(robot)
    sigma1, sigma3, sigma4, sigma5 = _check_puma_structure(model)
    T_0_t = _transform(T, 'ikine_puma560')
    theta4_singular, tol = finite_real('theta4_singular', theta4_singular), _tolerance(tol)
    T_0_6 = T_0_t @ trinv(model.tool)
    px, py, pz = T_0_6[:3, 3]
    a2, a3 = float(model.a[2]), float(model.a[3])
    d1, d2, d3, d4 = (float(v) for v in model.d[:4])
    alpha = [float(v) for v in model.alpha]

    # Shoulder: -s1 px + c1 py = Y, X = c1 px + s1 py.
    offset = -sigma1 * (d2 + d3)
    rho = math.hypot(px, py)
    if rho < abs(offset) - tol:
        raise ValueError(
            f'ikine_puma560: pose unreachable: the wrist centre is {rho:.6g} m from axis 1, '
            f'closer than the shoulder offset |d2 + d3| = {abs(offset):.6g} m')
    if rho - abs(offset) <= tol:
        reaches = [0.0]
    else:
        reach = math.sqrt((rho - abs(offset)) * (rho + abs(offset)))
        reaches = [reach, -reach]
    arm_length = math.hypot(a3, d4)
    gamma = math.atan2(-sigma3 * d4, a3)
    flip2 = math.pi if a2 < 0.0 else 0.0
    arm: list[tuple[float, float, float]] = []
    for reach in reaches:
        theta1 = 0.0 if rho <= tol else math.atan2(py, px) - math.atan2(offset, reach)
        planar = _two_link(abs(a2), arm_length, reach, sigma1 * (pz - d1), tol,
                           'ikine_puma560: the wrist centre, in the plane of the arm at')
        for phi1, phi2 in planar:
            arm.append((theta1, phi1 - flip2, phi2 - gamma + flip2))

    # Wrist: M = Rx(α3)^T R_0_3^T R_0_6 = Rz(θ4) Rx(α4) Rz(θ5) Rx(α5) Rz(θ6).
    rows = []
    for theta1, theta2, theta3 in arm:
        R_0_3 = (_rx(alpha[0]) @ _rz(theta1) @ _rx(alpha[1]) @ _rz(theta2) @ _rx(alpha[2])
                 @ _rz(theta3))
        M = _rx(alpha[3]).T @ R_0_3.T @ T_0_6[:3, :3]
        s5_abs = math.hypot(M[0, 2], M[1, 2])
        c5 = -sigma4 * sigma5 * M[2, 2]
        if s5_abs <= WRIST_SINGULAR_TOL:
            wrists = [(theta4_singular, math.atan2(0.0, c5))]
        else:
            theta4 = math.atan2(sigma5 * M[1, 2], sigma5 * M[0, 2])
            theta5 = math.atan2(s5_abs, c5)
            wrists = [(theta4, theta5), (theta4 + math.pi, -theta5)]
        for theta4, theta5 in wrists:
            N = (_rz(theta4) @ _rx(alpha[4]) @ _rz(theta5) @ _rx(alpha[5])).T @ M
            theta6 = math.atan2(N[1, 0], N[0, 0])
            rows.append([theta1, theta2, theta3, theta4, theta5, theta6])
    return np.asarray(wrap_to_pi(np.array(rows, dtype=np.float64)))


def choose_solution(solutions: ArrayLike, q_current: ArrayLike, *,
                    qlim: ArrayLike | None = None, weights: ArrayLike | None = None,
                    prismatic: ArrayLike | None = None) -> Vector:
    """
    Return the IK solution nearest to the current configuration, within the joint limits.

    Book §4.4, selection among multiple solutions: the least (weighted) joint motion from the
    current configuration, e.g. moving the long proximal links less, and respecting the
    joint limits. The distance is ``sqrt(sum_i w_i (q_i - q_current_i)^2)``.

    A revolute joint value is an angle: any value ``q_i + 2πk`` is the same solution. Each
    revolute entry is replaced by its equivalent nearest to ``q_current`` (so without limits
    its motion is ``wrap_to_pi(q_i - q_current_i)``); with ``qlim`` the equivalent must lie
    within the limits, and the nearest such one is taken: the joint then cannot cross the gap
    between its limits, so the motion is the real travel, which may exceed π. A row with
    any joint that has no equivalent within the limits is discarded. Prismatic entries are
    taken as they are. Ties go to the first row.

    Parameters
    ----------
    solutions : array_like, shape (k, n) or (n,)
        Candidate configurations [rad or m], e.g. from :func:`ikine_puma560`.
    q_current : array_like, shape (n,)
        Current configuration [rad or m].
    qlim : array_like, shape (n, 2), optional
        Lower and upper joint limits [rad or m] (e.g. ``robot.qlim``); default none.
    weights : array_like, shape (n,), optional
        Non-negative weights of each joint's motion; default all 1.
    prismatic : array_like of bool, shape (n,), optional
        True for prismatic joints (e.g. ``robot.prismatic``); default all revolute.

    Returns
    -------
    ndarray, shape (n,)
        The chosen configuration, its revolute angles shifted by multiples of 2π as above
        (so they may lie outside (-π, π]).

    Raises
    ------
    ValueError
        If no solution lies within the limits, for an empty or non-finite input, or for
        inconsistent shapes.

    Examples
    --------
    >>> choose_solution([[0.0, 3.0], [1.0, 0.0]], [0.0, -3.0])  # 3 - 2π is 0.28 rad away
    array([ 0.        , -3.28318531])
    >>> choose_solution([[0.0, 3.0], [1.0, 0.0]], [0.0, -3.0], qlim=[[-1, 1], [-3.1, 3.1]])
    array([1., 0.])

    """
    sols = np.array(solutions, dtype=np.float64)
    if sols.ndim == 1:
        sols = sols[np.newaxis, :]
    if sols.ndim != 2 or sols.shape[0] == 0 or sols.shape[1] == 0:
        raise ValueError(f'solutions must have shape (k, n) with k, n >= 1, got {sols.shape}')
    k, n = sols.shape
    current = np.asarray(q_current, dtype=np.float64)
    if current.shape != (n,):
        raise ValueError(f'q_current must have shape ({n},), got {current.shape}')
    if not (np.all(np.isfinite(sols)) and np.all(np.isfinite(current))):
        raise ValueError('solutions and q_current must be finite')
    w = np.ones(n) if weights is None else np.asarray(weights, dtype=np.float64)
    if w.shape != (n,) or not np.all(np.isfinite(w)) or np.any(w < 0.0):
        raise ValueError(f'weights must be {n} finite values >= 0, got {weights!r}')
    is_prismatic = (np.zeros(n, dtype=bool) if prismatic is None
                    else np.asarray(prismatic, dtype=bool))
    if is_prismatic.shape != (n,):
        raise ValueError(f'prismatic must have shape ({n},), got {is_prismatic.shape}')
    revolute = ~is_prismatic
    two_pi = 2.0 * math.pi
    turns = np.round((current - sols) / two_pi)
    valid = np.ones(k, dtype=bool)
    if qlim is not None:
        limits = np.asarray(qlim, dtype=np.float64)
        if limits.shape != (n, 2) or np.any(np.isnan(limits)) or np.any(
                limits[:, 0] > limits[:, 1]):
            raise ValueError(f'qlim must have shape ({n}, 2) with lower <= upper, got {qlim!r}')
        lowest = np.ceil((limits[:, 0] - sols) / two_pi)
        highest = np.floor((limits[:, 1] - sols) / two_pi)
        turns = np.clip(turns, lowest, highest)
        valid &= np.all(np.where(revolute, lowest <= highest, True), axis=1)
    candidates = np.where(revolute, sols + two_pi * turns, sols)
    if qlim is not None:
        inside = (candidates >= limits[:, 0]) & (candidates <= limits[:, 1])
        valid &= np.all(inside, axis=1)
    if not np.any(valid):
        raise ValueError(
            f'choose_solution: none of the {k} solutions lies within the joint limits {qlim!r}')
    distance = np.sqrt(np.sum(w * (candidates - current) ** 2, axis=1))
    distance[~valid] = np.inf
    return candidates[int(np.argmin(distance))]
