"""
Joint control laws of book ch. 8 (seed catalogue Part 6), pure NumPy/Pinocchio (no ROS).

Every law is a :class:`JointControlLaw`: ``update(reference, state, dt) -> tau`` with a
:class:`JointReference` (q_d, q_d', q_d'') and a :class:`JointState` (q, q'), and ``reset()``.
:class:`DecoupledPID` is the independent-joint PID of §8.2 (8.10); :class:`ComputedTorque` the
inverse-dynamics control of §8.3.2 (8.27)-(8.31), (8.36).
"""

from .computed_torque import ComputedTorque, ComputedTorqueGains
from .iterative_learning import (IterativeLearningControl, LearnedFeedforward,
                                 learning_gain_margin, LearningGains)
from .law import JointControlLaw, JointReference, JointState
from .pid import DecoupledPID, PIDGains

__all__ = ['ComputedTorque', 'ComputedTorqueGains', 'DecoupledPID', 'IterativeLearningControl',
           'JointControlLaw', 'JointReference', 'JointState', 'LearnedFeedforward',
           'LearningGains', 'learning_gain_margin', 'PIDGains']
