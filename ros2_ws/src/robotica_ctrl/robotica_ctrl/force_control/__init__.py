"""
Force control of book §8.7 (seed catalogue Part 6, §6.7), pure NumPy/Pinocchio (no ROS).

The laws work in the task coordinates of a constant :class:`TaskFrame` (normal axes first,
force-controlled; then tangential ones) and are :class:`ForceControlLaw` objects:
``update(reference, state, force, dt) -> tau`` with a :class:`TaskReference` (x_d, x_d', x_d''
and ψ_d, ψ_d', ψ_d''), a ``JointState`` (q, q'), the measured contact force ψ in task
coordinates, and a :class:`ForceControlTelemetry` left in ``law.telemetry``.

- :class:`StiffnessControl`: stiffness (PD) control (8.168) with its steady state
  :func:`stiffness_steady_state` (8.176)-(8.178) and :func:`stiffness_set_point` (8.179);
- :class:`HybridForcePosition`: hybrid force/position control (8.193)-(8.207);
- :class:`ImpedanceControl`: impedance control with a measured force (outside the book's §8.7).
"""

from .hybrid import HybridForcePosition, HybridGains
from .impedance import ImpedanceControl, ImpedanceGains
from .law import ForceControlLaw, ForceControlTelemetry, TaskReference
from .stiffness import (stiffness_set_point, stiffness_steady_state, StiffnessControl,
                        StiffnessGains)
from .task_frame import TaskFrame, TaskKinematics

__all__ = ['ForceControlLaw', 'ForceControlTelemetry', 'HybridForcePosition', 'HybridGains',
           'ImpedanceControl', 'ImpedanceGains', 'StiffnessControl', 'StiffnessGains',
           'TaskFrame', 'TaskKinematics', 'TaskReference', 'stiffness_set_point',
           'stiffness_steady_state']
