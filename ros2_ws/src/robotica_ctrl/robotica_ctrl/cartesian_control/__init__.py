"""
Cartesian-space control laws of book §8.6 (seed catalogue §6.6), pure NumPy/Pinocchio (no ROS).

Every law is a :class:`CartesianControlLaw`: ``update(reference, state, dt) -> tau`` (n,) [N m]
with a :class:`CartesianReference` (tool pose T_d, twist x_d', acceleration x_d'' in the base
frame {0}) and the measured :class:`~robotica_ctrl.joint_control.JointState` (q, q'), and
``reset()``; after each update ``law.telemetry`` is a :class:`CartesianTelemetry`.

- :class:`ResolvedRate`: the inverse-Jacobian scheme (fig. 8.39), δq = J^# δx with the modes
  ``inverse``, ``pseudo_inverse`` and ``damped_least_squares``, integrated into a joint
  reference that an inner joint law (computed torque by default) tracks;
- :class:`TransposeJacobian`: ``tau = Jᵀ (K_p x̃ + K_v x̃') + Ĝ`` (fig. 8.40, (8.158)-(8.162));
- :class:`OperationalSpace`: Khatib's decoupling ``tau = Jᵀ (M_x x'' + V_x + G_x)`` (fig. 8.41,
  (8.163)).

:func:`line_references` samples a reference from the straight line of ``cartesian_line``.
"""

from .cartesian_reference import CartesianReference, line_references
from .law import CartesianControlLaw, CartesianGains, CartesianTelemetry, task_mask
from .operational_space import OperationalSpace
from .resolved_rate import (damping_factor, joint_rates, MODES, ResolvedRate,
                            ResolvedRateParams)
from .transpose_jacobian import TransposeJacobian

__all__ = ['CartesianControlLaw', 'CartesianGains', 'CartesianReference', 'CartesianTelemetry',
           'MODES', 'OperationalSpace', 'ResolvedRate', 'ResolvedRateParams',
           'TransposeJacobian', 'damping_factor', 'joint_rates', 'line_references', 'task_mask']
