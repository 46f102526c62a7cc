"""
Speed and success of the manipulator kinematics, against a plain NumPy baseline in the same run.

For each robot (PUMA 560 and the planar 3R of Ej. 4.1 by default) and m random configurations
within the joint limits (a seeded generator), it times:

- ``fkine`` and ``jacob0`` per call, on the robot's Pinocchio arm and one scratch ``data`` kept
  across the calls (as a caller that computes often keeps them), and batched (one call on the
  (m, n) array);
- ``ikine`` on the poses ``fkine(q)`` of those configurations, per call, with its success rate;
- the baseline: the product of Craig's link matrices (4.5) built with NumPy for each call, the
  geometric Jacobian from those frames, and HEMERO's own ``ikine`` iteration
  ``q <- q + pinv(J0) tr2diff(fkine(q), T)`` from ``q0 = 0`` (catalog §12.2), all in plain NumPy;
- for a robot with dynamics (the PUMA 560), each function of :mod:`robotica_kin.dynamics` per
  call (checked inputs, the arm and one ``data``), the bare call it wraps and the floor of a
  checked Python wrapper, by :func:`robotica_sim.benchmarks.dynamics.time_dynamics` (CPU time,
  best of 15 blocks over the m configurations); the robotica and floor rows carry the ratio to
  the bare call.

Other times are wall-clock per configuration [µs] (``time.perf_counter``): median and 95th
percentile of the per-call times, or the batch time divided by m. Run it with
``robotica bench kin``.
"""

from dataclasses import dataclass
import math
import time
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray
from robotica_kin.dh import DHModel
from robotica_kin.forward_kinematics import fkine
from robotica_kin.ik import ikine_solve
from robotica_kin.jacobian import jacob0
from robotica_kin.pinocchio_model import pinocchio_arm, PinocchioArm
from robotica_kin.robots import planar_rrr, puma560
from robotica_sim.benchmarks.dynamics import time_dynamics

__all__ = ['BenchmarkRow', 'baseline_fkine', 'baseline_ikine', 'baseline_jacob0',
           'run_kinematics_benchmark']

PLANAR_MASK = (1, 1, 0, 0, 0, 1)


@dataclass(frozen=True)
class BenchmarkRow:
    """One line of the benchmark table."""

    robot: str
    function: str            # fkine, jacob0 or ikine
    route: str               # robotica or numpy baseline
    mode: str                # 'per call' or 'batch'
    count: int               # configurations timed
    median_us: float         # [µs] per configuration
    p95_us: float | None     # [µs] per configuration (per-call mode only)
    success_rate: float | None = None   # ikine only
    ratio: float | None = None          # dynamics, robotica and floor routes: over the raw call


def _link(alpha: float, a: float, theta: float, d: float) -> NDArray[np.float64]:
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array([[ct, -st, 0.0, a], [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d], [0.0, 0.0, 0.0, 1.0]])


def _baseline_frames(robot: DHModel, q: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    frames = [np.eye(4)]
    for i in range(robot.n):
        if robot.prismatic[i]:
            link = _link(robot.alpha[i], robot.a[i], robot.theta[i], q[i])
        else:
            link = _link(robot.alpha[i], robot.a[i], q[i], robot.d[i])
        frames.append(frames[-1] @ link)
    return frames


def baseline_fkine(robot: DHModel, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``T_0_tool`` as the plain NumPy product of the link matrices (4.5)-(4.6)."""
    return _baseline_frames(robot, q)[-1] @ robot.tool


def baseline_jacob0(robot: DHModel, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the geometric Jacobian in {0}: columns ``[z_i x (p - p_i); z_i]`` or ``[z_i; 0]``."""
    frames = _baseline_frames(robot, q)
    tip = (frames[-1] @ robot.tool)[:3, 3]
    J = np.zeros((6, robot.n))
    for i in range(robot.n):
        z, origin = frames[i + 1][:3, 2], frames[i + 1][:3, 3]
        if robot.prismatic[i]:
            J[:3, i] = z
        else:
            r = tip - origin
            J[:3, i] = (z[1] * r[2] - z[2] * r[1], z[2] * r[0] - z[0] * r[2],
                        z[0] * r[1] - z[1] * r[0])
            J[3:, i] = z
    return J


def baseline_ikine(robot: DHModel, T: NDArray[np.float64], mask: NDArray[np.float64],
                   stol: float = 1e-6, ilimit: int = 1000) -> tuple[NDArray[np.float64], bool]:
    """Return (q, converged) of HEMERO's pseudo-inverse iteration from q0 = 0 (catalog §12.2)."""
    q = np.zeros(robot.n)
    for _ in range(ilimit):
        current = baseline_fkine(robot, q)
        # tr2diff(T1, T2) (3.25)-(3.26): [p2 - p1; (n1 x n2 + o1 x o2 + a1 x a2) / 2].
        rot = 0.5 * (np.cross(current[:3, 0], T[:3, 0]) + np.cross(current[:3, 1], T[:3, 1])
                     + np.cross(current[:3, 2], T[:3, 2]))
        e = mask * np.concatenate((T[:3, 3] - current[:3, 3], rot))
        if np.linalg.norm(e) < stol:
            return q, True
        q = q + np.linalg.pinv(baseline_jacob0(robot, q)) @ e
    return q, False


def _per_call(fn: Callable[[Any], object], inputs: NDArray[Any]) -> NDArray[np.float64]:
    times = np.empty(len(inputs))
    for k, x in enumerate(inputs):
        start = time.perf_counter()
        fn(x)
        times[k] = time.perf_counter() - start
    return times * 1e6


def _row(robot: str, function: str, route: str, times_us: NDArray[np.float64],
         success: float | None = None) -> BenchmarkRow:
    return BenchmarkRow(robot, function, route, 'per call', len(times_us),
                        float(np.median(times_us)), float(np.percentile(times_us, 95)), success)


def _batch_row(robot: str, function: str, route: str, fn: Callable[[], object],
               count: int) -> BenchmarkRow:
    fn()   # warm-up (caches, lazy model construction)
    start = time.perf_counter()
    fn()
    per = (time.perf_counter() - start) / count * 1e6
    return BenchmarkRow(robot, function, route, 'batch', count, per, None)


def _dynamics_rows(arm: PinocchioArm, q: NDArray[np.float64],
                   qd: NDArray[np.float64], qdd: NDArray[np.float64]) -> list[BenchmarkRow]:
    """Time each dynamics function, the bare call it wraps and the Python floor (CPU time)."""
    name, rows = arm.robot.name, []
    for t in time_dynamics(arm, q, qd, qdd):
        function = 'fdyn (per evaluation)' if t.function == 'fdyn' else t.function
        mode = f'per call, CPU, best of {t.blocks} blocks'
        rows += [BenchmarkRow(name, function, 'robotica', mode, t.count, t.robotica_us, None,
                              ratio=t.ratio),
                 BenchmarkRow(name, function, f'raw: {t.raw_name}', mode, t.count, t.raw_us,
                              None)]
        if t.floor_us is not None:
            rows.append(BenchmarkRow(name, function, 'floor: one Python call + norm checks',
                                     mode, t.count, t.floor_us, None, ratio=t.floor_ratio))
    return rows


def run_kinematics_benchmark(count: int = 1000, baseline_ik_count: int = 100, seed: int = 0,
                             progress: Callable[[str], None] | None = None
                             ) -> list[BenchmarkRow]:
    """
    Time fkine, jacob0 and ikine on PUMA 560 and the planar 3R, with the NumPy baseline.

    Parameters
    ----------
    count : int
        Random configurations per robot (per-call and batch timings, and ikine).
    baseline_ik_count : int
        Poses given to the slow baseline ikine (a failure costs it 1000 iterations).
    seed : int
        Seed of the configuration generator.
    progress : callable, optional
        Called with a short message before each measurement.

    Returns
    -------
    list of BenchmarkRow

    """
    if count < 1 or baseline_ik_count < 1:
        raise ValueError('count and baseline_ik_count must be >= 1')
    say = progress or (lambda _msg: None)
    rows: list[BenchmarkRow] = []
    for robot, mask in ((puma560(), None), (planar_rrr(4.0, 3.0), PLANAR_MASK)):
        rng = np.random.default_rng(seed)
        q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(count, robot.n))
        goals = fkine(robot, q)
        arm = pinocchio_arm(robot)
        data = arm.model.createData()
        fkine(arm, q[0], data=data)
        jacob0(arm, q[0], data=data)
        say(f'{robot.name}: fkine')
        rows.append(_row(robot.name, 'fkine', 'robotica',
                         _per_call(lambda x: fkine(arm, x, data=data), q)))
        rows.append(_row(robot.name, 'fkine', 'numpy baseline',
                         _per_call(lambda x: baseline_fkine(robot, x), q)))
        rows.append(_batch_row(robot.name, 'fkine', 'robotica', lambda: fkine(robot, q), count))
        rows.append(_batch_row(robot.name, 'fkine', 'numpy baseline',
                               lambda: [baseline_fkine(robot, x) for x in q], count))
        say(f'{robot.name}: jacob0')
        rows.append(_row(robot.name, 'jacob0', 'robotica',
                         _per_call(lambda x: jacob0(arm, x, data=data), q)))
        rows.append(_row(robot.name, 'jacob0', 'numpy baseline',
                         _per_call(lambda x: baseline_jacob0(robot, x), q)))
        rows.append(_batch_row(robot.name, 'jacob0', 'robotica', lambda: jacob0(robot, q), count))
        rows.append(_batch_row(robot.name, 'jacob0', 'numpy baseline',
                               lambda: [baseline_jacob0(robot, x) for x in q], count))
        say(f'{robot.name}: ikine ({count} poses)')
        ikine_solve(robot, goals[0], mask=mask)
        solved: list[bool] = []
        rows.append(_row(robot.name, 'ikine', 'robotica', _per_call(
            lambda T: solved.append(bool(ikine_solve(robot, T, mask=mask).success)), goals),
            success=float(np.mean(solved))))
        say(f'{robot.name}: baseline ikine ({baseline_ik_count} poses)')
        weights = np.ones(6) if mask is None else np.array(mask, dtype=np.float64)
        baseline_solved: list[bool] = []
        rows.append(_row(robot.name, 'ikine', 'numpy baseline (HEMERO pinv)', _per_call(
            lambda T: baseline_solved.append(baseline_ikine(robot, T, weights)[1]),
            goals[:baseline_ik_count]), success=float(np.mean(baseline_solved))))
        if robot.dyn is not None:
            say(f'{robot.name}: the dynamics against raw Pinocchio')
            rows += _dynamics_rows(arm, q, *rng.uniform(-1.0, 1.0, size=(2,) + q.shape))
    return rows
