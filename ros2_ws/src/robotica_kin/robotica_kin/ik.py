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

Without a mask the iteration uses Pinocchio's ``log6`` of ``T_n^-1 T_goal`` (the twist from
frame {n} to the goal, in {n}) with the Jacobian in {n}, the cheapest equivalent formulation (a
tool is handled by moving the goal to frame {n}, ``T_goal tool^-1``), and close to the goal a
square Jacobian takes plain Newton steps; a mask is defined in {0}, so with one the error above
and the rows of ``jacob0`` are used as they are.

The search (starts, iterations, restarts, 2π fitting) runs compiled, one call per pose or
trajectory: the package ``robotica_native`` (C++ on Pinocchio's API, loaded with ctypes on
the first solve) receives the robot's Pinocchio model (``build_model``, through Pinocchio's
serialisation) and the seed table once per robot. This module validates the input.
"""

import ctypes
from dataclasses import dataclass
import functools
import math
import weakref

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.forward_kinematics import link_frames
from robotica_kin.native_library import address, ERROR_SIZE, native_library
from robotica_kin.pinocchio_model import build_model, TOOL_FRAME

__all__ = ['IKError', 'IKResult', 'ikine', 'ikine_solve']

_ROTATION_SCALE = math.sqrt(0.05)  # [m] weight of rotation entries in the seed distance
_SEED_TABLE_SEED = 20010101      # fixed: the seed table is part of the solver, not of a call


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
class _SeedTable:
    """Start configurations and a feature per pose of frame {n}: ``[p, sqrt(w) R(:)]``."""

    q: NDArray[np.float64]          # (K, n) joint vectors within the limits
    features: NDArray[np.float64]   # (K, 12) position [m] and weighted rotation entries


@functools.lru_cache(maxsize=16)
def _seed_table(robot: DHModel, count: int) -> _SeedTable:
    rng = np.random.default_rng(_SEED_TABLE_SEED)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(count, robot.n))
    frames = link_frames(robot, q)[:, -1]
    features = np.hstack([frames[:, :3, 3], _ROTATION_SCALE * frames[:, :3, :3].reshape(-1, 9)])
    return _SeedTable(q=q, features=features)


class _NativeRobot:
    """The compiled solver's copy of one robot (Pinocchio model, tool frame, seed table)."""

    def __init__(self, robot: DHModel, seed_count: int) -> None:
        lib = native_library()
        table = _seed_table(robot, seed_count)
        revolute = np.ascontiguousarray(~robot.prismatic, dtype=np.uint8)
        error = ctypes.create_string_buffer(ERROR_SIZE)
        # Pinocchio's own serialisation carries the model built by build_model to C++.
        handle = lib.rik_robot_new(build_model(robot).saveToString().encode(),
                                   TOOL_FRAME.encode(), address(revolute), seed_count,
                                   address(table.q), address(table.features),
                                   _ROTATION_SCALE, error, ERROR_SIZE)
        if not handle:
            raise RuntimeError(f'robotica_native: {error.value.decode()}')
        self.handle = handle
        weakref.finalize(self, lib.rik_robot_free, handle)


@functools.lru_cache(maxsize=16)
def _native_robot(robot: DHModel, seed_count: int) -> _NativeRobot:
    return _NativeRobot(robot, seed_count)


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
    # Each pose is checked to be homogeneous by the compiled solver before it solves any.
    return np.ascontiguousarray(poses), single


def _as_mask(mask: ArrayLike | None) -> NDArray[np.float64] | None:
    """Return the 0/1 weights of [x y z rx ry rz], None when all six are enforced."""
    if mask is None:
        return None
    m = np.array(mask, dtype=np.float64)
    weights = m.tolist() if m.shape == (6,) else [math.nan]   # lists: cheaper than ufuncs
    if any(w != 0.0 and w != 1.0 for w in weights):
        raise ValueError(f'mask must be six 0/1 weights of [x y z rx ry rz], got {mask!r}')
    if not any(weights):
        raise ValueError('mask must enforce at least one Cartesian coordinate')
    return None if all(weights) else m


def ikine_solve(dh: DHModel | ArrayLike, T: ArrayLike, stol: float = 1e-6, ilimit: int = 1000,
                q0: ArrayLike | None = None, mask: ArrayLike | None = None, *,
                slimit: int = 30, seed: int = 0, seed_count: int = 1024) -> IKResult:
    """
    Solve the inverse kinematics numerically and report, without raising on failure.

    Same arguments as :func:`ikine`, plus:

    slimit : int
        Iterations of one search before it is restarted from the next start.
    seed : int
        Seed in [0, 2**64) of the generator of random restarts (deterministic results).
    seed_count : int
        Size of the table of start configurations used when ``q0`` is not given.

    Returns
    -------
    IKResult
        Scalars for a single pose; arrays of length m for a trajectory.

    Raises
    ------
    ValueError
        For a bad table, T, q0, mask, stol, ilimit, slimit, seed or seed_count (never for
        non-convergence).
    RuntimeError
        When the compiled solver (package ``robotica_native``) is not built.

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
    if isinstance(seed, bool) or int(seed) != seed or not 0 <= seed < 2 ** 64:
        raise ValueError(f'seed must be an integer in [0, 2**64), got {seed!r}')
    if seed_count < 1:
        raise ValueError(f'seed_count must be >= 1, got {seed_count!r}')
    start = None if q0 is None else np.ascontiguousarray(robot.check_q(q0, 'q0'))
    if start is not None and start.ndim != 1:
        raise ValueError(f'q0 must have shape ({robot.n},), got {start.shape}')
    weights = _as_mask(mask)
    native = _native_robot(robot, int(seed_count))
    m, n = poses.shape[0], robot.n
    out = np.empty((m, n + 3))      # per pose: q, residual, iterations, success (0/1)
    error = ctypes.create_string_buffer(ERROR_SIZE)
    status = native_library().rik_solve(
        native.handle, m, address(poses), None if start is None else address(start),
        None if weights is None else address(weights), float(stol), int(ilimit), int(slimit),
        int(seed), address(out), error, ERROR_SIZE)
    if status > 0:
        raise ValueError(f'T[{status - 1}] is not a finite homogeneous transform (rotation '
                         'block orthonormal with det +1, last row [0 0 0 1])')
    if status < 0:
        raise RuntimeError(f'robotica_native: {error.value.decode()}')
    q, residual, iterations, success = out[:, :n], out[:, n], out[:, n + 1], out[:, n + 2]
    if single:
        return IKResult(q=q[0].copy(), success=bool(success[0]), iterations=int(iterations[0]),
                        residual=float(residual[0]))
    return IKResult(q=q.copy(), success=success == 1.0, iterations=iterations.astype(np.int64),
                    residual=residual.copy())


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
    RuntimeError
        When the compiled solver is not built (see :func:`ikine_solve`).

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
