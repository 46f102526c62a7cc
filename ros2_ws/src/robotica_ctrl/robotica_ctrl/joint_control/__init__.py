"""
Joint control laws of book ch. 8 (seed catalogue Part 6), pure NumPy/Pinocchio (no ROS).

Every law is a :class:`JointControlLaw`: ``update(reference, state, dt) -> tau`` with a
:class:`JointReference` (q_d, q_d', q_d'') and a :class:`JointState` (q, q'), and ``reset()``.
:class:`DecoupledPID` is the independent-joint PID of §8.2 (8.10); :class:`ComputedTorque` the
inverse-dynamics control of §8.3.2 (8.27)-(8.31), (8.36). The adaptive laws of §8.4:
:class:`GainScheduledPID` (§8.4.1), :class:`ModelReferenceAdaptive` (MRAC, (8.75)-(8.78)),
:class:`AdaptiveComputedTorque` ((8.79)-(8.95)) and :class:`SlotineLi` ((8.111)-(8.136)), the last
two on a :class:`ParameterRegressor` (:class:`LinkMassRegressor`, :class:`TwoLinkRegressor`).
"""

from .adaptive_computed_torque import AdaptiveComputedTorque, AdaptiveComputedTorqueGains
from .computed_torque import ComputedTorque, ComputedTorqueGains
from .gain_scheduling import GainSchedule, GainScheduledPID
from .iterative_learning import (IterativeLearningControl, LearnedFeedforward,
                                 learning_gain_margin, LearningGains)
from .law import JointControlLaw, JointReference, JointState
from .pid import DecoupledPID, PIDGains
from .reference_model import ModelReferenceAdaptive, ModelReferenceGains
from .regressor import (LinkMassRegressor, ParameterRegressor,
                        two_link_computed_torque_regressor, two_link_slotine_li_regressor,
                        TwoLinkRegressor)
from .slotine_li import SlotineLi, SlotineLiGains

__all__ = ['AdaptiveComputedTorque', 'AdaptiveComputedTorqueGains', 'ComputedTorque',
           'ComputedTorqueGains', 'DecoupledPID', 'GainSchedule', 'GainScheduledPID',
           'IterativeLearningControl', 'JointControlLaw', 'JointReference', 'JointState',
           'LearnedFeedforward', 'LearningGains', 'learning_gain_margin', 'LinkMassRegressor',
           'ModelReferenceAdaptive', 'ModelReferenceGains', 'ParameterRegressor', 'PIDGains',
           'SlotineLi', 'SlotineLiGains', 'TwoLinkRegressor', 'two_link_computed_torque_regressor',
           'two_link_slotine_li_regressor']
