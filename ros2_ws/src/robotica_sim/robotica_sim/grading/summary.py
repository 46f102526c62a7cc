"""
The one-line summary of a run, computed from its bag.

Duration from ``/clock``; real-time factor and lockstep timeouts from the simulator's last
``~/status``; cross-track error of the ground truth (``/ground_truth/odom``) against the
reference ``/path``: the final one and the RMS over the run (the distance to the path, signed
positive to the left). For a manipulator run, the joint position errors ``e = q_d - q`` of the
joint controller's ``~/controller_state``: per joint, the RMS over the run and the largest
magnitude over its last quarter (the steady state of the book's ch. 8 examples).
"""
from dataclasses import asdict, dataclass
import math
from pathlib import Path
from typing import Any, Optional

import numpy as np
from robotica_ctrl.mobile.path import PolylinePath
from rosbags.highlevel import AnyReader


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

    def line(self) -> str:
        """Return the summary as one human-readable line."""
        def metres(v: Optional[float]) -> str:
            return 'n/a' if v is None else f'{v:+.4f} m'
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
    """Read a run's bag and compute its summary. Raises ValueError when it is not a bag."""
    path_points = None
    truth = []
    joint_errors: list[tuple[float, list[float]]] = []
    status: Any = None
    clock = 0.0
    count = 0
    try:
        reader = AnyReader([Path(bag)])
    except Exception as err:  # rosbags raises its own error classes for broken bags
        raise ValueError(f'{bag}: not a readable bag ({err})') from None
    with reader:
        wanted = {'/path', '/ground_truth/odom', '/simulator/status', '/clock',
                  '/joint_controller/controller_state'}
        connections = [c for c in reader.connections if c.topic in wanted]
        count = sum(c.msgcount for c in reader.connections)
        for connection, _, raw in reader.messages(connections=connections):
            msg: Any = reader.deserialize(raw, connection.msgtype)
            if connection.topic == '/path':
                path_points = np.array([[p.pose.position.x, p.pose.position.y]
                                        for p in msg.poses])
            elif connection.topic == '/ground_truth/odom':
                truth.append((msg.pose.pose.position.x, msg.pose.pose.position.y))
            elif connection.topic == '/simulator/status':
                status = msg
            elif connection.topic == '/joint_controller/controller_state':
                joint_errors.append((msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9,
                                     list(msg.position_error)))
            else:
                clock = max(clock, msg.clock.sec + msg.clock.nanosec * 1e-9)
    final = rms = None
    if path_points is not None and len(path_points) >= 2 and truth:
        path = PolylinePath(path_points)
        errors = np.array([path.project(p).cross_track for p in truth])
        final = float(errors[-1])
        rms = float(math.sqrt(np.mean(errors ** 2)))
    rms_joint = late_joint = None
    if joint_errors:
        times = np.array([t for t, _ in joint_errors])
        errors = np.array([e for _, e in joint_errors])
        rms_joint = np.sqrt(np.mean(errors ** 2, axis=0)).tolist()
        late_joint = np.max(np.abs(errors[times >= 0.75 * times[-1]]), axis=0).tolist()
    return RunSummary(bag=str(bag), duration=clock,
                      steps=int(status.step) if status is not None else 0,
                      real_time_factor=float(status.real_time_factor) if status else 0.0,
                      lockstep_timeouts=int(status.lockstep_timeouts) if status else 0,
                      message_count=count, final_cross_track=final, rms_cross_track=rms,
                      rms_joint_error=rms_joint, max_late_joint_error=late_joint)
