"""
The one-line summary of a run, computed from its bag.

Read through the one loader (:func:`robotica_sim.grading.series.load_run`) and measured with the
one projection and RMS of :mod:`robotica_sim.grading.metrics`, so that the line ``robotica run``
prints and ``robotica grade`` agree: duration from ``/clock``; real-time factor and lockstep
timeouts from the simulator's last ``~/status``; cross-track error of the ground truth
(``/ground_truth/odom``) against the reference ``/path`` (signed positive to the left,
:func:`~robotica_sim.grading.metrics.path_errors` with the default search window): the final
one and the RMS over the run. For a manipulator run, the joint position errors ``e = q_d - q``
of the joint controller's ``~/controller_state``: per joint, the RMS over the run and the
largest magnitude over its last quarter (the steady state of the book's ch. 8 examples). For
a task-space law (force or Cartesian control, no joint trajectory) the last step instead: the
position error on the axes with a position reference and the force on the environment (its
error where there is a force reference), or the pose error.
"""
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Optional

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.mobile.path import PolylinePath
from robotica_sim.grading.metrics import MetricParams, path_errors, rms
from robotica_sim.grading.series import load_run, TOPICS

__all__ = ['RunSummary', 'summarize_bag']

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

    def line(self) -> str:
        """Return the summary as one human-readable line."""
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
        _, cross, _ = path_errors(PolylinePath(run.path), truth['x'], truth['y'],
                                  truth['theta'], MetricParams().search_window)
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
                      max_late_joint_error=late_joint, final_task=final_task)


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
