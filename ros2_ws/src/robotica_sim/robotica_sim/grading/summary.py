"""
The one-line summary of a run, computed from its bag.

Read through the one loader (:func:`robotica_sim.grading.series.load_run`) and measured with the
one projection and RMS of :mod:`robotica_sim.grading.metrics`, so that the line ``robotica run``
prints and ``robotica grade`` agree: duration from ``/clock``; real-time factor and lockstep
timeouts from the simulator's last ``~/status``; cross-track error of the ground truth
(``/ground_truth/odom``) against the reference ``/path`` (signed positive to the left,
:func:`~robotica_sim.grading.metrics.truth_path_errors` with the default search window): the final
one and the RMS over the run. For a manipulator run, the joint position errors ``e = q_d - q``
of the joint controller's ``~/controller_state``: per joint, the RMS over the run and the
largest magnitude over its last quarter (the steady state of the book's ch. 8 examples). For
a task-space law (force or Cartesian control, no joint trajectory) the last step instead: the
position error on the axes with a position reference and the force on the environment (its
error where there is a force reference), or the pose error.

A run whose bag lacks messages says so (``missing``, and the line ends with ``RECORDING
INCOMPLETE``): the simulator publishes each of :data:`STEP_TOPICS` once per step, step 0
included, so a bag holds ``steps + 1`` of each (the simulator's last ``~/status`` gives
``steps``; measured: ``ej8_2`` 20 001 for 20 000 steps, ``demo`` 1601 for 1600, in lockstep and
in real time). In lockstep the joint controller also answers every state once
(:data:`ANSWER_TOPICS`), so those topics hold ``steps + 1`` less the lockstep timeouts (a step
not answered is a timeout); in real time a controller may skip states, so they are not
counted. A recorder that falls behind loses messages from a keep-last queue without any DDS
"message lost" event (docs/recording.md): only these counts show it. Exact where the series
is decoded (the ground truth, the controller's state: distinct stamps, so the step 0 that a
lockstep simulator publishes again while it waits for the controller's first answer is
counted once); on the other topics a repeated step 0 can hide as many lost messages.
"""
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np
from numpy.typing import NDArray
from robotica_sim.bags.run_record import ROBOTICA
from robotica_sim.grading.metrics import rms, truth_path_errors
from robotica_sim.grading.series import load_run, RunSeries, TOPICS

__all__ = ['ANSWER_TOPICS', 'RunSummary', 'STEP_TOPICS', 'expected_messages',
           'incomplete_text', 'missing_messages', 'summarize_bag']

STEP_TOPICS = tuple(TOPICS[role] for role in ('clock', 'joint_states', 'truth', 'bumper'))
"""The simulator's topics, one message per step in either pacing (those the bag has)."""
ANSWER_TOPICS = tuple(TOPICS[role] for role in (
    'torques', 'controller', 'force_control', 'cartesian_control'))
"""The joint controller's answers, one per state in lockstep: its torques and the telemetry of
its law (the one of the last three that has messages)."""

_SUMMARY_TOPICS = tuple(TOPICS[role] for role in (
    'path', 'truth', 'status', 'controller', 'force_control', 'cartesian_control'))


@dataclass(frozen=True)
class RunSummary:
    """Key numbers of a run."""

    bag: str
    duration: float                 # [s] simulated
    steps: int
    real_time_factor: float         # simulated s per wall-clock s
    lockstep_timeouts: int
    message_count: int
    final_cross_track: Optional[float]   # [m]
    rms_cross_track: Optional[float]     # [m]
    rms_joint_error: Optional[list[float]] = None       # [rad | m] per joint, whole run
    max_late_joint_error: Optional[list[float]] = None  # [rad | m] per joint, last quarter
    final_task: Optional[dict[str, list[float]]] = None   # last step: [m], [N], [m, rad]
    missing: dict[str, int] = field(default_factory=dict)  # topic -> messages the bag lacks

    def line(self) -> str:
        """Return the summary as one human-readable line, RECORDING INCOMPLETE at its end."""
        return self._numbers() + self._incomplete()

    def _incomplete(self) -> str:
        """Return the line's end that names the topics the bag lacks messages of, or ''."""
        text = incomplete_text(self.missing, self.steps, self.lockstep_timeouts)
        return f'; RECORDING INCOMPLETE: {text}' if text else ''

    def _numbers(self) -> str:
        """Return the line without its end."""
        def metres(v: Optional[float]) -> str:
            return 'n/a' if v is None else f'{v:+.4f} m'
        if self.final_task is not None:
            parts = ', '.join(f'final {name.replace("_", " ")} '
                              + '[' + ', '.join(f'{v:.4g}' for v in values) + ']'
                              for name, values in self.final_task.items())
            return (f'duration {self.duration:.2f} s, real-time factor '
                    f'{self.real_time_factor:.1f}, {parts}, {self.message_count} messages, '
                    f'lockstep timeouts {self.lockstep_timeouts}')
        if self.rms_joint_error is not None and self.max_late_joint_error is not None:
            def joints(values: list[float]) -> str:
                return '[' + ', '.join(f'{v:.4g}' for v in values) + ']'
            return (f'duration {self.duration:.2f} s, real-time factor '
                    f'{self.real_time_factor:.1f}, RMS joint error '
                    f'{joints(self.rms_joint_error)}, max joint error in the last quarter '
                    f'{joints(self.max_late_joint_error)}, {self.message_count} messages, '
                    f'lockstep timeouts {self.lockstep_timeouts}')
        return (f'duration {self.duration:.2f} s, real-time factor {self.real_time_factor:.1f}, '
                f'final cross-track {metres(self.final_cross_track)}, RMS cross-track '
                f'{metres(self.rms_cross_track).lstrip("+")}, {self.message_count} messages, '
                f'lockstep timeouts {self.lockstep_timeouts}')

    def as_dict(self) -> dict:
        """Return the summary as a JSON-ready dictionary."""
        return asdict(self)


def summarize_bag(bag: Path) -> RunSummary:
    """
    Read a run's bag and compute its summary.

    Raises
    ------
    robotica_sim.bags.info.BagError
        If ``bag`` is not a readable bag.

    """
    run = load_run(bag, _SUMMARY_TOPICS)
    final = rms_cross = None
    truth = run.truth
    if run.path is not None and len(run.path) >= 2 and truth is not None and len(truth):
        _, cross, _, _ = truth_path_errors(run)
        final, rms_cross = float(cross[-1]), rms(cross)
    rms_joint = late_joint = None
    controller = run.controller
    if controller is not None and len(controller):
        errors = controller['position_error']
        rms_joint = [rms(column) for column in errors.T]
        late = errors[controller.t >= 0.75 * controller.t[-1]]
        late_joint = np.max(np.abs(late), axis=0).tolist()
    status = run.status or {}
    final_task = None if run.task_final is None else _task_summary(run.task_final)
    return RunSummary(bag=str(bag), duration=run.duration, steps=int(status.get('step', 0)),
                      real_time_factor=float(status.get('real_time_factor', 0.0)),
                      lockstep_timeouts=int(status.get('lockstep_timeouts', 0)),
                      message_count=sum(run.counts.values()), final_cross_track=final,
                      rms_cross_track=rms_cross, rms_joint_error=rms_joint,
                      max_late_joint_error=late_joint, final_task=final_task,
                      missing=missing_messages(run))


def expected_messages(topic: str, steps: int, lockstep_timeouts: int) -> int:
    """
    Return how many messages of per-step ``topic`` a run of ``steps`` steps records.

    ``steps + 1`` (step 0 included) on :data:`STEP_TOPICS`; on :data:`ANSWER_TOPICS` (lockstep
    only) less the steps that went on without an answer (``lockstep_timeouts``).

    >>> expected_messages('/clock', 20000, 3), expected_messages('/joint_torques', 20000, 3)
    (20001, 19998)

    """
    return steps + 1 - (lockstep_timeouts if topic in ANSWER_TOPICS else 0)


def incomplete_text(missing: dict[str, int], steps: int, lockstep_timeouts: int) -> str:
    """
    Return what a bag lacks (:func:`missing_messages`) in words, '' when it lacks nothing.

    >>> incomplete_text({'/clock': 2}, 10, 0)
    '/clock 9 of 11 steps (the recorder fell behind)'
    """
    parts = []
    for topic, lacking in missing.items():
        expected = expected_messages(topic, steps, lockstep_timeouts)
        what = 'steps' if expected == steps + 1 else 'answered steps'
        parts.append(f'{topic} {expected - lacking} of {expected} {what}')
    return f'{", ".join(parts)} (the recorder fell behind)' if parts else ''


def missing_messages(run: RunSeries) -> dict[str, int]:
    """
    Return the per-step topics of which the bag lacks messages, each with how many.

    Compared with :func:`expected_messages` for the steps and lockstep timeouts of the
    simulator's last ``~/status`` (no status: {}): the simulator's :data:`STEP_TOPICS` that the
    bag has, and in a lockstep run (the run record's pacing, as run) whose joint controller is
    robotica's, its :data:`ANSWER_TOPICS` that have messages (a task-space law publishes no
    ``~/controller_state``; a user's controller answers on ``/joint_torques`` only, as its
    contract says). The messages received are the distinct stamps of a decoded series (the
    ground truth, the controller's state), else the bag's count.
    """
    if run.status is None:
        return {}
    steps, timeouts = int(run.status['step']), int(run.status['lockstep_timeouts'])
    received = dict(run.counts)
    for topic, series in ((TOPICS['truth'], run.truth), (TOPICS['controller'], run.controller),
                          (TOPICS['joint_states'], run.joint_states)):
        if series is not None and topic in received:
            received[topic] = len(np.unique(series.t))
    topics = [topic for topic in STEP_TOPICS if topic in received]
    record = run.run
    if record.settings_from == 'run' and record.settings.get('pacing') == 'lockstep':
        ours = any(n.name == 'joint_controller' and n.started_by == ROBOTICA
                   for n in record.nodes)
        topics += [topic for topic in ANSWER_TOPICS if received.get(topic)
                   and (ours or topic == TOPICS['torques'])]
    missing = {topic: expected_messages(topic, steps, timeouts) - received[topic]
               for topic in topics}
    return {topic: lacking for topic, lacking in missing.items() if lacking > 0}


def _task_summary(last: dict[str, NDArray[np.float64]]) -> dict[str, list[float]]:
    """Return the summary of a task-space law's last step (RunSeries.task_final)."""
    if 'error' in last:
        return {'pose_error': last['error'].tolist()}
    position = ~np.isnan(last['position_reference'])
    forced = ~np.isnan(last['force_reference'])
    summary = {'position_error': (last['position_reference'] - last['position'])[
        position].tolist(), 'force': last['force'].tolist()}
    if forced.any():
        summary['force_error'] = (last['force_reference'] - last['force'])[forced].tolist()
    return summary
