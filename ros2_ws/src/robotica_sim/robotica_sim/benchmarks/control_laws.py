"""
Issue 20: time per control step and closed-loop error of every law of the joint controller.

``robotica bench laws`` builds every law the ``joint_controller`` node runs, as the node builds
it, with the node's default gains, on the PUMA 560 (``robotica_kin.robots.puma560()``, gravity
``[0, 0, -9.81]``):

- the joint laws of :data:`~robotica_ctrl.joint_control.control_laws.JOINT_LAWS` by
  :func:`~robotica_ctrl.joint_control.control_laws.make_joint_law`;
- the task-space laws of :data:`~robotica_ctrl.joint_control.task_laws.TASK_LAWS` by
  :class:`~robotica_ctrl.joint_control.task_laws.TaskSpaceControl`. The hybrid and the
  impedance laws invert the task Jacobian and a task frame has at most 3 axes: they refuse an
  arm of 6 joints (ValueError), so they are timed on the PP robot of Ej. 8.10 instead
  (``robotica_kin.robots.pp_robot()``), and their row says so.

**Time per control step**: the wall-clock time of the law's ``update`` alone, timeit-style
(``time.perf_counter`` around a batch of ``count`` calls, the garbage collector off, the
per-call mean of each batch), :data:`REPEATS` batches; the minimum and the median over the
batches [µs], and the minimum as a fraction of the book's servo period of 1 ms (fig. 6.3). The
calls replay the inputs of the law's own closed-loop run below (references and states built
beforehand, so only ``update`` is timed) from a ``reset``, after one untimed call (the first call
of a Cartesian law builds its line). The stiffness law is timed on the PUMA in free space (a
set point 10 cm from :data:`LINE_START`, the task axes those of {0}), its error measured on the PP
robot as the other force laws'.

**Closed-loop error**, each law driving :class:`~robotica_sim.simulation.arm.ArmSimulation` at
1 ms, the torque held over each step (``arm_simulation(robot, {...}, 1e-3)``); the error is
sampled at every control step, before the step's torque acts:

- joint laws: the appendix's reference θ_i(t) = sin t on every joint (A.2) from rest at q = 0,
  5 s; max |e| over the last second (over joints and samples) and the RMS of each joint over the
  run, the largest of the six [rad]. Computed torque and learning use the exact model; the
  adaptive laws (adaptive computed torque, Slotine-Li) start from a model whose link masses are
  1.5 times the table's (the links with a mass; their inertia tensors scaled alike, the shape the
  regressor assumes) and adapt them; PID and model-reference adaptive control have no model
  (no gravity term). Learning runs :data:`LEARNING_TRIALS` trials of 2π s (one period of the
  reference), the arm put back at rest at q = 0 before each, as the arm simulator does every
  ``trial_period``: its errors are the last trial's;
- Cartesian laws: a straight line of 10 cm up (+z of {0}) in 2 s from the pose at
  :data:`LINE_START` (away from singularities: σ_min(J) 0.18 at the start, 0.17 at the goal);
  the distance of the tool origin from the goal at the end, and the RMS over the run of its
  distance from the line's reference [m];
- force laws: the PP robot on the compliant plane of Ej. 8.10 (``scenarios/ej8_10.yaml``:
  K_e1 = 1200 N/m at x_e1 = 2 m, from x(0) = (2, 4) m at rest, gravity ``[0, -9.81, 0]``), the
  law fed the contact wrench an ideal wrist F/T sensor reads; |ψ_d - ψ| on the normal axis at
  5 s and its RMS over the run [N]. Stiffness and impedance ask for Ej. 8.10's ψ_d1 = 3 N
  through their set point x_d1 = ψ_d1 / K + x_e1 (8.179), x_d2 = 2 m (they regulate position,
  and settle at ψ_d1 K_e / (K + K_e), (8.178)); hybrid follows Ej. 8.11 (``ej8_11.yaml``):
  x_d2 = 2 + cos t, ψ_d1 = 1 - e^(-2t).

``duration`` caps every run (and each learning trial) at that many simulated seconds, a shorter
line keeping its 10 cm. One process, no ROS; the machine's other work shows in the medians.
"""
import dataclasses
from dataclasses import dataclass
import gc
import math
import statistics
import time
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.force_control import stiffness_set_point
from robotica_ctrl.joint_control import JointReference, JointState
from robotica_ctrl.joint_control.control_laws import JOINT_LAWS, make_joint_law
from robotica_ctrl.joint_control.task_laws import (CARTESIAN_LAWS, FORCE_LAWS, TASK_LAW_PARAMETERS,
                                                   TaskSpaceControl)
from robotica_ctrl.trajectory.sinusoid import sinusoid
from robotica_kin.dh import DHModel
from robotica_kin.forward_kinematics import fkine
from robotica_kin.robots import pp_robot, puma560
from robotica_kin.transforms import tr2rpy
from robotica_sim.grading.metrics import rms
from robotica_sim.simulation.arm import arm_simulation, ArmSimulation
from robotica_sim.simulation.compliant_environment import CompliantPlane

__all__ = ['ADAPTIVE_MASS_FACTOR', 'LawBenchmarkRow', 'LEARNING_TRIALS', 'LINE_START',
           'REPEATS', 'SERVO_PERIOD', 'control_law_benchmark', 'format_law_table',
           'law_rows_json']

SERVO_PERIOD = 1e-3          # [s] the book's servo period (fig. 6.3), the runs' step
REPEATS = 7                  # timed batches of update calls per law
GRAVITY = (0.0, 0.0, -9.81)  # [m/s²] the PUMA's, in {0}
JOINT_SECONDS = 5.0          # [s] of θ_i = sin t (A.2)
LEARNING_TRIALS = 3
LEARNING_TRIAL_SECONDS = 2.0 * math.pi   # one period of sin t
ADAPTIVE_MASS_FACTOR = 1.5   # the adaptive laws' initial link masses over the true ones
ADAPTIVE_LAWS = ('adaptive_computed_torque', 'slotine_li')
LINE_START = (0.0, 0.5, 0.5, 0.0, 0.5, 0.0)   # [rad] q of the Cartesian runs' start pose
LINE_DISPLACEMENT = (0.0, 0.0, 0.1)           # [m] in {0}: 10 cm up
LINE_SECONDS = 2.0
FORCE_SECONDS = 5.0
LAST_SECONDS = 1.0           # the window of the joint laws' max |e|
# Ej. 8.10-8.11 (scenarios/ej8_10.yaml, ej8_11.yaml): the PP robot, the surface at 45°
# (x1 = (d1 - d2)/√2 normal to it, x2 = (d1 + d2)/√2 along it), K_e1 = 1200 N/m at x_e1 = 2 m.
_S = 1.0 / math.sqrt(2.0)
PP_GRAVITY = (0.0, -9.81, 0.0)
PP_START = (math.sqrt(2.0), 3.0 * math.sqrt(2.0))   # q = [d2, d1]: x(0) = (2, 4) m
PP_SURFACE = 2.0              # x_e1 [m]
PP_SURFACE_STIFFNESS = 1200.0  # K_e1 [N/m]
PP_FORCE = 3.0                # ψ_d1 [N] of Ej. 8.10
_PP_TASK = {'task.axes': [_S, -_S, 0.0, _S, _S, 0.0], 'task.normal_axes': 1}
_HYBRID_TASK = {**_PP_TASK, 'task.position.offset': [0.0, 2.0],       # x_d2 = 2 + cos t
                'task.position.amplitude': [0.0, 1.0], 'task.position.phase': [0.0, math.pi / 2],
                'task.force.final': [1.0, 0.0],                          # ψ_d1 = 1 - e^(-2t)
                'task.force.time_constant': [0.5, 0.0]}
_NOTES = {
    'pid': 'node defaults, no model: gravity not compensated',
    'computed_torque': 'exact model',
    'adaptive_computed_torque': f'masses start at {ADAPTIVE_MASS_FACTOR:g}×, adapted',
    'slotine_li': f'masses start at {ADAPTIVE_MASS_FACTOR:g}×, adapted',
    'model_reference': 'node defaults, no model: gravity not compensated',
    'learning': "exact model; the last trial's errors",
    'stiffness': 'Ej. 8.10; timed on the PUMA in free space',
    'hybrid': 'Ej. 8.11',
    'impedance': 'Ej. 8.10 with K_d = 100 N/m',
    'resolved_rate': 'exact model (inner computed torque)',
    'transpose_jacobian': 'K_p = 25 N/m: soft',
    'operational_space': 'exact model',
}
_SQUARE_TASK = 'n/a on a 6-joint arm (needs one task axis per joint); timed on pp_robot'


@dataclass(frozen=True)
class LawBenchmarkRow:
    """One law: its time per ``update`` and its closed-loop error (module docstring)."""

    law: str
    kind: str                # 'joint', 'force' or 'cartesian'
    timed_on: str            # the robot whose update was timed
    calls: int               # update calls per timed batch
    repeats: int             # timed batches
    min_us: float            # [µs] per call, fastest batch
    median_us: float         # [µs] per call, median batch
    period_fraction: float   # min_us over the servo period of 1 ms
    run: str                 # the closed-loop run
    error: float             # see error_what, in error_unit
    error_unit: str
    error_what: str
    rms_error: float         # over the run, same unit
    note: str


@dataclass(frozen=True)
class _Run:
    """A closed-loop run: the update calls made, in order, and the law's errors."""

    calls: list[tuple[Any, ...]]
    error: float
    rms_error: float
    run: str          # what was run
    error_what: str   # what ``error`` is
    extra: str = ''   # added to the row's note


def _time_update(update: Callable[..., Any], reset: Callable[[], None],
                 calls: Sequence[tuple[Any, ...]], count: int) -> tuple[float, float, int]:
    """Return the min and median [µs] per ``update`` call over the batches, and the batch size."""
    timed = calls[1:count + 1]
    if not timed:
        raise ValueError('a run of at least two steps is needed to time a law')
    per_call = []
    enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(REPEATS):
            reset()
            update(*calls[0])
            start = time.perf_counter()
            for args in timed:
                update(*args)
            per_call.append((time.perf_counter() - start) / len(timed) * 1e6)
    finally:
        if enabled:
            gc.enable()
    return min(per_call), statistics.median(per_call), len(timed)


def _steps(seconds: float) -> int:
    return max(2, round(seconds / SERVO_PERIOD))


def _joint_trial(law: Any, sim: ArmSimulation, seconds: float
                 ) -> tuple[list[tuple[Any, ...]], NDArray[np.float64]]:
    """Run θ_i = sin t from rest at q = 0; return the update calls and the errors (steps, n)."""
    n = sim.robot.n
    sim.reset(np.zeros(n), np.zeros(n))
    steps = _steps(seconds)
    q_d, qd_d, qdd_d = (np.repeat(x, n, axis=1) for x in
                        sinusoid(np.arange(steps) * SERVO_PERIOD, 1.0, 2.0 * math.pi))
    calls = []
    errors = np.empty((steps, n))
    for k in range(steps):
        args = (JointReference(q_d[k], qd_d[k], qdd_d[k]), JointState(sim.q, sim.qd),
                SERVO_PERIOD)
        calls.append(args)
        errors[k] = q_d[k] - sim.q
        sim.step(law.update(*args))
    return calls, errors


def _joint_errors(errors: NDArray[np.float64]) -> tuple[float, float]:
    """Return max |e| over the last second and the largest per-joint RMS [rad]."""
    last = errors[-_steps(LAST_SECONDS):]
    return float(np.abs(last).max()), max(rms(column) for column in errors.T)


def _initial_masses(robot: DHModel, factor: float) -> DHModel:
    """Return ``robot`` with the links that have a mass ``factor`` times heavier (and inertia)."""
    dyn = np.array(robot.dyn)
    heavy = dyn[:, 5] > 0.0
    dyn[heavy, 5] *= factor
    dyn[heavy, 9:15] *= factor
    dyn.setflags(write=False)
    return dataclasses.replace(robot, dyn=dyn)


def _joint_run(name: str, law: Any, cap: float) -> _Run:
    """Run the joint law ``law`` on the PUMA 560 (learning: its trials); return the run."""
    sim = arm_simulation(puma560(), {}, SERVO_PERIOD)
    if name != 'learning':
        seconds = min(JOINT_SECONDS, cap)
        calls, errors = _joint_trial(law, sim, seconds)
        return _Run(calls, *_joint_errors(errors), f'PUMA 560, θ_i = sin t, {seconds:g} s',
                    f'max |e| over the last {min(LAST_SECONDS, seconds):g} s')
    seconds = min(LEARNING_TRIAL_SECONDS, cap)
    first = ''
    for trial in range(LEARNING_TRIALS):
        if trial:
            law.end_trial()
        calls, errors = _joint_trial(law, sim, seconds)
        if not trial:
            first = f'; trial 1: {_joint_errors(errors)[0]:.1e} rad'
    return _Run(calls, *_joint_errors(errors),
                f'PUMA 560, θ_i = sin t, {LEARNING_TRIALS} trials of {seconds:.3g} s',
                f'max |e| over the last {min(LAST_SECONDS, seconds):g} s of the last trial',
                first)


def _task_run(control: TaskSpaceControl, sim: ArmSimulation, seconds: float,
              error: Callable[[TaskSpaceControl, JointState, Any], float]
              ) -> tuple[list[tuple[Any, ...]], list[float]]:
    """Run a task-space law; return its update calls and ``error`` at every step."""
    calls, errors = [], []
    for k in range(_steps(seconds)):
        state = JointState(sim.q, sim.qd)
        wrench = None if sim.environment is None else sim.contact_wrench().on_tool()
        args = (k * SERVO_PERIOD, state, wrench, SERVO_PERIOD)
        calls.append(args)
        tau = control.update(*args)
        errors.append(error(control, state, wrench))
        sim.step(tau)
    return calls, errors


def _line_goal(robot: DHModel) -> tuple[NDArray[np.float64], list[float]]:
    """Return the goal position [m] and the goal pose x, y, z, roll, pitch, yaw of the line."""
    start = fkine(robot, np.array(LINE_START))
    position = start[:3, 3] + np.array(LINE_DISPLACEMENT)
    return position, [*position.tolist(), *np.asarray(tr2rpy(start), dtype=float).tolist()]


def _pp_task(name: str) -> dict[str, Any]:
    """Return the task of a force law on the PP robot (module docstring)."""
    if name == 'hybrid':
        return dict(_HYBRID_TASK)
    gain = 'kp' if name == 'stiffness' else 'stiffness'
    default: Any = TASK_LAW_PARAMETERS[name][gain].default
    k = float(default[0])   # the law's stiffness along x1 [N/m]
    x_d1 = float(stiffness_set_point(PP_FORCE, k, PP_SURFACE))
    return {**_PP_TASK, 'task.position.offset': [x_d1, 2.0], 'task.force.final': [PP_FORCE, 0.0]}


def _force_run(name: str, cap: float) -> tuple[TaskSpaceControl, _Run]:
    control = TaskSpaceControl(name, pp_robot(), {}, _pp_task(name), PP_GRAVITY,
                               step=SERVO_PERIOD)
    plane = CompliantPlane(PP_SURFACE * np.array([_S, -_S, 0.0]), [1.0, -1.0, 0.0],
                           PP_SURFACE_STIFFNESS)
    sim = arm_simulation(pp_robot(), {'gravity': list(PP_GRAVITY),
                                      'initial_positions': list(PP_START),
                                      'respect_limits': False}, SERVO_PERIOD, plane)
    normal = control.frame.normal_axes

    def force_error(psi_d: NDArray[np.float64], q: NDArray[np.float64], wrench: Any) -> float:
        psi = control.task_force(q, wrench)
        return float(np.linalg.norm(psi_d[:normal] - psi[:normal]))

    def step_error(control: TaskSpaceControl, state: JointState, wrench: Any) -> float:
        return force_error(control.reference.psi_d, state.q, wrench)

    seconds = min(FORCE_SECONDS, cap)
    calls, errors = _task_run(control, sim, seconds, step_error)
    end = force_error(control.profile.at(seconds).psi_d, sim.q, sim.contact_wrench().on_tool())
    return control, _Run(calls, end, rms(errors), f"pp_robot on Ej. 8.10's plane, {seconds:g} s",
                         f'|ψ_d - ψ| normal to it at {seconds:g} s')


def _cartesian_run(control: TaskSpaceControl, seconds: float) -> _Run:
    """Run a law from :data:`LINE_START` for ``seconds``; its errors from the line's goal."""
    robot = control.robot
    goal, _ = _line_goal(robot)
    sim = arm_simulation(puma560(), {'initial_positions': list(LINE_START)}, SERVO_PERIOD)

    def distance(control: TaskSpaceControl, state: JointState, wrench: Any) -> float:
        target = control.reference.T_d[:3, 3] if not control.is_force else goal
        return float(np.linalg.norm(target - fkine(robot, state.q)[:3, 3]))

    calls, errors = _task_run(control, sim, seconds, distance)
    end = float(np.linalg.norm(goal - fkine(robot, sim.q)[:3, 3]))
    return _Run(calls, end, rms(errors), f'PUMA 560, 10 cm line in {seconds:g} s',
                'distance from the goal at the end')


def _puma_task(name: str, seconds: float) -> TaskSpaceControl:
    """Return the task-space law ``name`` on the PUMA towards the line's goal (ValueError)."""
    _, pose = _line_goal(puma560())
    task: dict[str, Any] = {'cartesian.goal': pose, 'cartesian.duration': seconds}
    if name in FORCE_LAWS:   # free space: a set point at the goal, the axes of {0}
        task = {'task.axes': [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                'task.position.offset': pose[:3]}
    return TaskSpaceControl(name, puma560(), {}, task, GRAVITY, step=SERVO_PERIOD)


def _row(name: str, kind: str, timed_on: str, timing: tuple[float, float, int], run: _Run,
         unit: str, note: str) -> LawBenchmarkRow:
    minimum, median, calls = timing
    return LawBenchmarkRow(
        law=name, kind=kind, timed_on=timed_on, calls=calls, repeats=REPEATS, min_us=minimum,
        median_us=median, period_fraction=minimum * 1e-6 / SERVO_PERIOD, run=run.run,
        error=run.error, error_unit=unit, error_what=run.error_what, rms_error=run.rms_error,
        note=note + run.extra)


def control_law_benchmark(count: int = 1000, duration: float | None = None,
                          progress: Callable[[str], None] | None = None) -> list[LawBenchmarkRow]:
    """
    Time and run every law of the joint controller; return one row per law (module docstring).

    Parameters
    ----------
    count : int
        ``update`` calls per timed batch (at most the steps of the law's run less one).
    duration : float, optional
        Cap of every closed-loop run and learning trial [s] (default none: 5 s, 2π s, 2 s).
    progress : callable, optional
        Called with a short message before each law.

    """
    cap = math.inf if duration is None else float(duration)
    if not cap > 0.0:
        raise ValueError(f'duration must be > 0 s, got {duration!r}')
    rows = []
    say = progress or (lambda message: None)
    for name in JOINT_LAWS:
        say(f'laws: {name} on the PUMA 560')
        model = (_initial_masses(puma560(), ADAPTIVE_MASS_FACTOR) if name in ADAPTIVE_LAWS
                 else puma560())
        law = make_joint_law(name, model, {}, GRAVITY)
        run = _joint_run(name, law, cap)
        timing = _time_update(law.update, law.reset, run.calls, count)
        rows.append(_row(name, 'joint', 'puma560', timing, run, 'rad', _NOTES[name]))
    line = min(LINE_SECONDS, cap)
    for name in FORCE_LAWS:
        say(f'laws: {name} on pp_robot against the plane of Ej. 8.10')
        control, run = _force_run(name, cap)
        try:
            on_puma = _puma_task(name, line)
        except ValueError:
            timing = _time_update(control.update, control.reset, run.calls, count)
            rows.append(_row(name, 'force', 'pp_robot', timing, run, 'N',
                             f'{_SQUARE_TASK}; {_NOTES[name]}'))
            continue
        free = _cartesian_run(on_puma, line)
        timing = _time_update(on_puma.update, on_puma.reset, free.calls, count)
        rows.append(_row(name, 'force', 'puma560', timing, run, 'N', _NOTES[name]))
    for name in CARTESIAN_LAWS:
        say(f'laws: {name} on the PUMA 560')
        control = _puma_task(name, line)
        run = _cartesian_run(control, line)
        timing = _time_update(control.update, control.reset, run.calls, count)
        rows.append(_row(name, 'cartesian', 'puma560', timing, run, 'm', _NOTES[name]))
    return rows


def format_law_table(rows: Sequence[LawBenchmarkRow]) -> str:
    """Return the rows as a Markdown table (times in µs per ``update`` call)."""
    lines = ['| law | timed on | min [µs] | median [µs] | min / 1 ms | closed-loop run | error '
             '| RMS over the run | note |',
             '|---|---|---:|---:|---:|---|---|---:|---|']
    for r in rows:
        what = r.error_what.replace('|', '\\|')
        lines.append(f'| {r.law} | {r.timed_on} | {r.min_us:.1f} | {r.median_us:.1f} '
                     f'| {100.0 * r.period_fraction:.1f} % | {r.run} '
                     f'| {r.error:.2e} {r.error_unit} ({what}) | {r.rms_error:.2e} {r.error_unit} '
                     f'| {r.note} |')
    return '\n'.join(lines)


def law_rows_json(rows: Sequence[LawBenchmarkRow]) -> list[dict[str, Any]]:
    """Return the rows as JSON-ready dicts (a value that is not finite as None)."""
    return [{name: None if isinstance(value, float) and not math.isfinite(value) else value
             for name, value in dataclasses.asdict(row).items()} for row in rows]
