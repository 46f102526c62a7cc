"""
Numerical inverse kinematics: HEMERO's ``ikine`` with a Levenberg-Marquardt solver (book §4.4).

HEMERO (catalog §12.2) iterates ``q <- q + pinv(jacob0(dh, q)) (M .* tr2diff(fkine(dh, q), T))``
from ``q0`` until the pose error is below ``stol``; the book warns that it may not converge even
inside the reachable workspace (Ej. H.3.1). This solver keeps HEMERO's interface and error
measure and replaces the iteration by damped least squares:

    e = M .* [p_d - p ; log(R_d R^T)]          pose error in the base frame {0}
    (J^T J + lambda I) dq = J^T e,   lambda = e^T e / 2   (Chan and Lawrence's damping)

with ``J = jacob0`` restricted to the masked rows. The damping vanishes with the error, so the
last iterations are Gauss-Newton steps (quadratic convergence), while far from the goal the
step shrinks instead of overshooting. A search that has not converged after ``slimit``
iterations, or converges outside the joint limits, is restarted from another start; revolute
angles are wrapped by 2π into their limits when they fit.

Starts: the given ``q0`` first (HEMERO's default is zeros); without ``q0`` the configurations of a
fixed table of ``seed_count`` joint vectors sampled within the limits are tried in the order of
the distance of their poses to the goal (nearest first), then random configurations drawn
from a seeded generator. Everything is deterministic for a given ``seed``.

Each iteration is one Pinocchio ``computeJointJacobians`` call (forward kinematics and the
Jacobian in C++) plus a 6×6 Cholesky solve (LAPACK ``dposv``).
"""

from dataclasses import dataclass
import functools
import math
from typing import Any, Iterator

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.forward_kinematics import link_frames
from robotica_kin.pinocchio_model import TOOL_FRAME
from scipy.linalg import lapack

__all__ = ['IKError', 'IKResult', 'ikine', 'ikine_solve']

_TWO_PI = 2.0 * math.pi
_ROTATION_SCALE = math.sqrt(0.05)  # [m] weight of rotation entries in the seed distance
_SEED_TABLE_SEED = 20010101      # fixed: the seed table is part of the solver, not of a call
_NEWTON_ERROR_SQ = 1e-2          # [m^2, rad^2] below this squared error: plain Newton steps


class IKError(RuntimeError):
    """
    Raised by :func:`ikine` when a pose is not reached within ``ilimit`` iterations.

    Attributes
    ----------
    index : int or None
        Index of the failing point of a trajectory (None for a single pose).
    residual : float
        Norm of the masked pose error at the last iterate.
    q : ndarray
        The last iterate.

    """

    def __init__(self, message: str, *, index: int | None, residual: float,
                 q: NDArray[np.float64]) -> None:
        super().__init__(message)
        self.index = index
        self.residual = residual
        self.q = q


@dataclass(frozen=True)
class IKResult:
    """
    Outcome of :func:`ikine_solve`, one pose or a trajectory of m poses.

    Attributes
    ----------
    q : ndarray, shape (n,) or (m, n)
        Solution [rad | m]; where a point failed, its last iterate.
    success : bool or ndarray of bool, shape (m,)
        True where the masked pose error fell below ``stol`` within the joint limits.
    iterations : int or ndarray of int, shape (m,)
        Iterations used (all searches together).
    residual : float or ndarray, shape (m,)
        Norm of the masked pose error ``[p_d - p; log(R_d R^T)]`` [m, rad] at ``q``.

    """

    q: NDArray[np.float64]
    success: bool | NDArray[np.bool_]
    iterations: int | NDArray[np.int64]
    residual: float | NDArray[np.float64]


@dataclass(frozen=True)
class _RobotSolver:
    """What the iteration needs of one robot, computed once per robot."""

    robot: DHModel
    model: Any                      # pinocchio.Model
    n: int
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    revolute: NDArray[np.bool_]
    tool_inverse: Any | None        # pinocchio.SE3 of tool^-1, None for the identity
    tool_frame: int


@functools.lru_cache(maxsize=16)
def _robot_solver(robot: DHModel) -> _RobotSolver:
    model = robot.pinocchio_model
    has_tool = not np.array_equal(robot.tool, np.eye(4))
    return _RobotSolver(robot=robot, model=model, n=robot.n, lower=robot.qlim[:, 0],
                        upper=robot.qlim[:, 1], revolute=~robot.prismatic,
                        tool_inverse=robot.tool_se3.inverse() if has_tool else None,
                        tool_frame=model.getFrameId(TOOL_FRAME))


@dataclass(frozen=True)
class _SeedTable:
    """Start configurations and a feature per pose of frame {n}: ``[p, sqrt(w) R(:)]``."""

    q: NDArray[np.float64]          # (K, n) joint vectors within the limits
    features: NDArray[np.float64]   # (K, 12) position [m] and weighted rotation entries
    features_sq: NDArray[np.float64]  # (K,) squared norms of the features
    positions_sq: NDArray[np.float64]  # (K,) squared norms of the positions


@functools.lru_cache(maxsize=16)
def _seed_table(robot: DHModel, count: int) -> _SeedTable:
    rng = np.random.default_rng(_SEED_TABLE_SEED)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(count, robot.n))
    frames = link_frames(robot, q)[:, -1]
    features = np.hstack([frames[:, :3, 3], _ROTATION_SCALE * frames[:, :3, :3].reshape(-1, 9)])
    return _SeedTable(q=q, features=features,
                      features_sq=np.einsum('ij,ij->i', features, features),
                      positions_sq=np.einsum('ij,ij->i', features[:, :3], features[:, :3]))


def _check_pose(pose: NDArray[np.float64], index: int) -> None:
    """Raise ValueError unless ``pose`` (4, 4) is a finite homogeneous transform."""
    if np.isfinite(pose).all():
        (r0, r1, r2, last) = pose.tolist()
        x, y, z = r0[:3], r1[:3], r2[:3]
        gram = [x[0] * x[0] + y[0] * y[0] + z[0] * z[0] - 1.0,
                x[1] * x[1] + y[1] * y[1] + z[1] * z[1] - 1.0,
                x[2] * x[2] + y[2] * y[2] + z[2] * z[2] - 1.0,
                x[0] * x[1] + y[0] * y[1] + z[0] * z[1],
                x[0] * x[2] + y[0] * y[2] + z[0] * z[2],
                x[1] * x[2] + y[1] * y[2] + z[1] * z[2]]
        det = (x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0])
               + x[2] * (y[0] * z[1] - y[1] * z[0]))
        if (max(abs(g) for g in gram) <= 1e-6 and det > 0.0
                and max(abs(a - b) for a, b in zip(last, (0.0, 0.0, 0.0, 1.0))) <= 1e-9):
            return
    raise ValueError(f'T[{index}] is not a finite homogeneous transform (rotation block '
                     'orthonormal with det +1, last row [0 0 0 1])')


def _as_poses(T: ArrayLike) -> tuple[NDArray[np.float64], bool]:
    """Return T as (m, 4, 4) and whether it was a single pose; accept HEMERO's m×16 rows."""
    arr = np.asarray(T, dtype=np.float64)
    if arr.shape == (4, 4):
        poses, single = arr[np.newaxis], True
    elif arr.ndim == 3 and arr.shape[1:] == (4, 4) and arr.shape[0] > 0:
        poses, single = arr, False
    elif arr.ndim == 2 and arr.shape[1] == 16 and arr.shape[0] > 0:
        # [H] Ej. H.3.1 stores each transform as a row T(:)' (MATLAB column-major order).
        poses, single = arr.reshape(-1, 4, 4).transpose(0, 2, 1), False
    else:
        raise ValueError(f'T must have shape (4, 4), (m, 4, 4) or (m, 16), got {arr.shape}')
    for k in range(poses.shape[0]):
        _check_pose(poses[k], k)
    return poses, single


def _as_mask(mask: ArrayLike | None) -> NDArray[np.intp] | None:
    """Return the indices of the enforced rows of [x y z rx ry rz], None for all six."""
    if mask is None:
        return None
    m = np.asarray(mask, dtype=np.float64)
    if m.shape != (6,) or not np.all((m == 0.0) | (m == 1.0)):
        raise ValueError(f'mask must be six 0/1 weights of [x y z rx ry rz], got {mask!r}')
    rows = np.flatnonzero(m)
    if rows.size == 0:
        raise ValueError('mask must enforce at least one Cartesian coordinate')
    return None if rows.size == 6 else rows


class _Solver:
    """
    The damped least-squares iteration for one robot, mask and call (holds the scratch space).

    Without a mask the error is Pinocchio's ``log6`` of ``T_n^-1 T_goal`` (the twist from the
    current frame {n} to the goal, in {n}) with the Jacobian in {n}, the cheapest formulation;
    a tool is handled by moving the goal to frame {n} (``T_goal tool^-1``), exact when all six
    coordinates are enforced. A mask is defined in {0}, so with one the error is
    ``[p_d - p; log(R_d R^T)]`` in {0} with the rows of ``jacob0``. Close to the goal a square
    Jacobian takes plain Newton steps (one LU solve).
    """

    def __init__(self, robot: DHModel, rows: NDArray[np.intp] | None, stol: float,
                 slimit: int, seed: int, seed_count: int) -> None:
        self.c = _robot_solver(robot)
        self.data = robot.pinocchio_data()
        self.rows = rows
        self.stol = stol
        self.slimit = slimit
        self.seed = seed
        self.seed_count = seed_count
        self.newton = rows is None and robot.n == 6

    def _pose_error(self, pose: Any, p_d: NDArray[np.float64],
                    R_d: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the masked base-frame error ``[p_d - p; log(R_d R^T)]`` of a tool ``pose``."""
        e = np.concatenate((p_d - pose.translation, pin.log3(R_d.dot(pose.rotation.T))))
        return e if self.rows is None else e[self.rows]

    def _world_error(self, q: NDArray[np.float64], p_d: NDArray[np.float64],
                     R_d: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the masked base-frame pose error at q and the matching rows of jacob0."""
        c, data = self.c, self.data
        pin.computeJointJacobians(c.model, data, q)
        pin.updateFramePlacement(c.model, data, c.tool_frame)
        J = pin.getFrameJacobian(c.model, data, c.tool_frame, pin.LOCAL_WORLD_ALIGNED)
        e = self._pose_error(data.oMf[c.tool_frame], p_d, R_d)
        return e, (J if self.rows is None else J[self.rows])

    def _local_residual(self, p_d: NDArray[np.float64], R_d: NDArray[np.float64]) -> float:
        """
        Return the masked base-frame pose error [m, rad] after :meth:`_search_local`'s step.

        That step leaves the pose of frame {n} in ``data.iMf[0]``.
        """
        c = self.c
        pose = self.data.iMf[0]
        if c.tool_inverse is not None:
            pose = pose * c.robot.tool_se3
        e = self._pose_error(pose, p_d, R_d)
        return math.sqrt(e.dot(e))

    def _fit_limits(self, q: NDArray[np.float64]) -> NDArray[np.float64] | None:
        """Return q with revolute angles shifted by 2π into the limits, None if impossible."""
        c = self.c
        if (q >= c.lower).all() and (q <= c.upper).all():
            return q
        q = np.where(c.revolute, q - _TWO_PI * np.round(q / _TWO_PI), q)
        q = np.where(c.revolute & (q < c.lower), q + _TWO_PI, q)
        q = np.where(c.revolute & (q > c.upper), q - _TWO_PI, q)
        if (q >= c.lower).all() and (q <= c.upper).all():
            return q
        return None

    def _starts(self, q0: NDArray[np.float64] | None,
                goal_n: Any) -> Iterator[NDArray[np.float64]]:
        """Yield starts: q0, the seeds nearest to the goal pose of {n}, then random ones."""
        if q0 is not None:
            yield q0
        table = _seed_table(self.c.robot, self.seed_count)
        position = goal_n.translation
        if self.rows is None:
            feature = np.concatenate((position, _ROTATION_SCALE * goal_n.rotation.ravel()))
            distance = table.features_sq - 2.0 * table.features.dot(feature)
        else:
            # A mask leaves some orientation free: compare positions only.
            distance = table.positions_sq - 2.0 * table.features[:, :3].dot(position)
        nearest = int(distance.argmin())
        yield table.q[nearest]
        for k in np.argsort(distance):
            if k != nearest:
                yield table.q[k]
        rng = np.random.default_rng(self.seed)
        while True:
            yield rng.uniform(self.c.lower, self.c.upper)

    def solve(self, pose: NDArray[np.float64], q0: NDArray[np.float64] | None,
              ilimit: int) -> tuple[NDArray[np.float64], bool, int, float]:
        """Return (q, success, iterations, residual) for one goal pose of the tool."""
        p_d = pose[:3, 3].copy()
        R_d = pose[:3, :3].copy()
        goal = pin.SE3(R_d, p_d)
        goal_n = goal if self.c.tool_inverse is None else goal * self.c.tool_inverse
        search = self._search_local if self.rows is None else self._search_world
        iterations = 0
        for start in self._starts(q0, goal_n):
            q, used, residual = search(start, goal_n, p_d, R_d,
                                       min(self.slimit, ilimit - iterations))
            iterations += used
            if residual < self.stol:
                fitted = self._fit_limits(q)
                if fitted is not None:
                    return fitted, True, iterations, residual
            if iterations >= ilimit:
                break
        e, _ = self._world_error(q, p_d, R_d)
        return q, False, iterations, math.sqrt(e.dot(e))

    def _search_local(self, q: NDArray[np.float64], goal_n: Any, p_d: NDArray[np.float64],
                      R_d: NDArray[np.float64],
                      limit: int) -> tuple[NDArray[np.float64], int, float]:
        """Iterate from q without a mask; return (q, iterations, residual or inf)."""
        model, data, n = self.c.model, self.data, self.c.n
        tol_sq = self.stol * self.stol
        newton = self.newton
        dgesv, dposv = lapack.dgesv, lapack.dposv
        compute_jacobian, log6 = pin.computeJointJacobian, pin.log6
        for k in range(limit + 1):
            J = compute_jacobian(model, data, q, n)
            e = log6(data.iMf[0].actInv(goal_n)).vector
            err_sq = e.dot(e)
            if err_sq < tol_sq:
                residual = self._local_residual(p_d, R_d)
                if residual < self.stol:
                    return q, k, residual
            if k == limit:
                break
            if newton and err_sq < _NEWTON_ERROR_SQ:
                dq, info = dgesv(J, e)[2:]
                if info == 0:
                    q = q + dq
                    continue
            Jt = J.T
            A = Jt.dot(J)
            A.flat[::n + 1] += 0.5 * err_sq
            dq, info = dposv(A, Jt.dot(e))[1:]
            if info != 0:
                break
            q = q + dq
        return q, limit, math.inf

    def _search_world(self, q: NDArray[np.float64], goal_n: Any, p_d: NDArray[np.float64],
                      R_d: NDArray[np.float64],
                      limit: int) -> tuple[NDArray[np.float64], int, float]:
        """Iterate from q with a mask (error in {0}); return (q, iterations, residual or inf)."""
        tol_sq = self.stol * self.stol
        n = self.c.n
        for k in range(limit + 1):
            e, J = self._world_error(q, p_d, R_d)
            err_sq = e.dot(e)
            if err_sq < tol_sq:
                return q, k, math.sqrt(err_sq)
            if k == limit:
                break
            Jt = J.T
            A = Jt.dot(J)
            A.flat[::n + 1] += 0.5 * err_sq
            dq, info = lapack.dposv(A, Jt.dot(e))[1:]
            if info != 0:
                break
            q = q + dq
        return q, limit, math.inf


def ikine_solve(dh: DHModel | ArrayLike, T: ArrayLike, stol: float = 1e-6, ilimit: int = 1000,
                q0: ArrayLike | None = None, mask: ArrayLike | None = None, *,
                slimit: int = 30, seed: int = 0, seed_count: int = 1024) -> IKResult:
    """
    Solve the inverse kinematics numerically and report, without raising on failure.

    Same arguments as :func:`ikine`, plus:

    slimit : int
        Iterations of one search before it is restarted from the next start.
    seed : int
        Seed of the generator of random restarts (deterministic results).
    seed_count : int
        Size of the table of start configurations used when ``q0`` is not given.

    Returns
    -------
    IKResult
        Scalars for a single pose; arrays of length m for a trajectory.

    Raises
    ------
    ValueError
        For a bad table, T, q0, mask, stol or ilimit (never for non-convergence).

    Examples
    --------
    >>> from robotica_kin.forward_kinematics import fkine
    >>> from robotica_kin.robots import puma560
    >>> robot = puma560()
    >>> goal = fkine(robot, [0.1, -0.5, 0.6, 0.2, 0.4, -0.3])
    >>> result = ikine_solve(robot, goal)
    >>> bool(result.success), bool(np.allclose(fkine(robot, result.q), goal, atol=1e-6))
    (True, True)

    """
    robot = as_dh_model(dh)
    poses, single = _as_poses(T)
    if not (math.isfinite(stol) and stol > 0.0):
        raise ValueError(f'stol must be a finite tolerance > 0, got {stol!r}')
    if isinstance(ilimit, bool) or int(ilimit) != ilimit or ilimit < 1:
        raise ValueError(f'ilimit must be a positive integer, got {ilimit!r}')
    if isinstance(slimit, bool) or int(slimit) != slimit or slimit < 1:
        raise ValueError(f'slimit must be a positive integer, got {slimit!r}')
    if seed_count < 1:
        raise ValueError(f'seed_count must be >= 1, got {seed_count!r}')
    start = None if q0 is None else robot.check_q(q0, 'q0')
    if start is not None and start.ndim != 1:
        raise ValueError(f'q0 must have shape ({robot.n},), got {start.shape}')
    solver = _Solver(robot, _as_mask(mask), float(stol), int(slimit), seed, int(seed_count))
    if single:
        q1, ok, used, res = solver.solve(poses[0], start, int(ilimit))
        return IKResult(q=q1, success=ok, iterations=used, residual=res)
    m = poses.shape[0]
    q = np.empty((m, robot.n))
    success = np.zeros(m, dtype=bool)
    iterations = np.zeros(m, dtype=np.int64)
    residual = np.empty(m)
    for k in range(m):
        q[k], success[k], iterations[k], residual[k] = solver.solve(poses[k], start, int(ilimit))
        if success[k]:
            start = q[k]
    return IKResult(q=q, success=success, iterations=iterations, residual=residual)


def ikine(dh: DHModel | ArrayLike, T: ArrayLike, stol: float = 1e-6, ilimit: int = 1000,
          q0: ArrayLike | None = None, mask: ArrayLike | None = None) -> NDArray[np.float64]:
    """
    Return joint values that place the tool at pose T (HEMERO ``ikine``, book §4.4).

    Parameters
    ----------
    dh : DHModel or array_like, shape (n, 4) or (n, 5)
        The robot (Craig's modified DH).
    T : array_like, shape (4, 4), (m, 4, 4) or (m, 16)
        Goal pose of the tool in {0} [m]; a trajectory of m poses (HEMERO's ``TG``; rows of
        16 are MATLAB's column-major ``T(:)'``). Each point starts from the previous solution.
    stol : float
        Largest admissible norm of the masked pose error [m, rad]; HEMERO's typical 1e-6.
    ilimit : int
        Largest number of iterations per pose, all restarts included (HEMERO: 1000).
    q0 : array_like, shape (n,), optional
        First start [rad | m]. Without it the solver starts from the stored configuration whose
        pose is nearest to T (HEMERO starts from zeros).
    mask : array_like, shape (6,), optional
        HEMERO's M: 0/1 weights of the error in [x y z rx ry rz] of {0}; a robot with fewer
        than six joints needs one (e.g. ``[1 1 0 0 0 1]`` for a planar 3R).

    Returns
    -------
    ndarray, shape (n,) or (m, n)
        Joint values within the joint limits.

    Raises
    ------
    IKError
        When a pose is not reached within ``ilimit`` iterations; it carries the point's index
        and residual.
    ValueError
        For bad input (see :func:`ikine_solve`).

    Examples
    --------
    Ej. H.3.1, the planar 3R with l1 = 4 m, l2 = 3 m, a point of the arc of radius 5 m:

    >>> from robotica_kin.forward_kinematics import fkine
    >>> from robotica_kin.transforms import transl
    >>> dh = [[0, 0, 0, 0, 0], [0, 4, 0, 0, 0], [0, 3, 0, 0, 0]]
    >>> q = ikine(dh, transl(3.0, 4.0, 0.0), q0=[0, 0, 0], mask=[1, 1, 0, 0, 0, 1])
    >>> fkine(dh, q)[:2, 3].round(9).tolist(), round(float(q.sum()), 9)
    ([3.0, 4.0], 0.0)

    """
    result = ikine_solve(dh, T, stol, ilimit, q0, mask)
    failed = np.flatnonzero(np.atleast_1d(result.success) == 0)
    if failed.size:
        k = int(failed[0])
        single = np.ndim(result.success) == 0
        residual = float(np.atleast_1d(result.residual)[k])
        where = 'the pose' if single else f'point {k} of the trajectory'
        raise IKError(
            f'ikine did not converge for {where}: residual {residual:.3g} > stol {stol:g} '
            f'after {int(np.atleast_1d(result.iterations)[k])} iterations (unreachable pose, '
            'or raise ilimit)', index=None if single else k, residual=residual,
            q=np.atleast_2d(result.q)[k])
    return result.q
