"""
The telemetry of the joint controller's laws beyond ``JointControllerState`` (book ch. 8).

What a law shows depends on what it is, read from the law object (the core stays free of ROS):

* a law with parameter ``estimates`` (the adaptive laws of §8.4) is published as
  robotica_msgs/AdaptationState every step: the estimates by name and the per-joint error that
  drives them (``adaptation_error``, or ``filtered_error`` r = Λe + e' of Slotine–Li);
* a law with ``end_trial`` (iterative learning, §8.5) as robotica_msgs/LearningTrial each time a
  trial ends: its mean squared error (8.153) per joint;
* a force law (§8.7) as robotica_msgs/ForceControlState and a Cartesian law (§8.6) as
  robotica_msgs/CartesianControlState every step, from its ``telemetry``.
"""
from typing import Any

from builtin_interfaces.msg import Time
import numpy as np
from numpy.typing import ArrayLike
from robotica_kin.ros.dh_messages import pose_message
from robotica_msgs.msg import (AdaptationState, CartesianControlState, ForceControlState,
                               LearningTrial)

__all__ = ['adaptation_message', 'cartesian_control_message', 'force_control_message',
           'is_adaptive', 'is_learning', 'learning_trial_message']


def is_adaptive(law: Any) -> bool:
    """Return whether ``law`` adapts parameter estimates (it has ``estimates``)."""
    return hasattr(law, 'estimates') and hasattr(law, 'parameter_names')


def is_learning(law: Any) -> bool:
    """Return whether ``law`` learns from trial to trial (it has ``end_trial``)."""
    return callable(getattr(law, 'end_trial', None))


def adaptation_message(law_name: str, law: Any, joint_names: list[str],
                       stamp: Time) -> AdaptationState:
    """Return the AdaptationState of an adaptive ``law`` after its step at ``stamp``."""
    error = getattr(law, 'adaptation_error', None)
    if error is None:
        error = getattr(law, 'filtered_error', None)
    msg = AdaptationState(law=law_name, parameter_names=list(law.parameter_names),
                          estimates=np.asarray(law.estimates, dtype=float).tolist(),
                          joint_names=joint_names,
                          adaptation_error=[] if error is None
                          else np.asarray(error, dtype=float).tolist())
    msg.header.stamp = stamp
    return msg


def learning_trial_message(law_name: str, trial: int, duration: float, joint_names: list[str],
                           mean_squared_error: Any, max_feedforward: float,
                           stamp: Time) -> LearningTrial:
    """Return the LearningTrial of trial number ``trial`` (from 1) that ended at ``stamp``."""
    msg = LearningTrial(law=law_name, trial=trial, duration=float(duration),
                        joint_names=joint_names,
                        mean_squared_error=np.asarray(mean_squared_error, dtype=float).tolist(),
                        max_feedforward=float(max_feedforward))
    msg.header.stamp = stamp
    return msg


def force_control_message(telemetry: Any, axis_names: tuple[str, ...], force_controlled: Any,
                          frame_id: str, stamp: Time) -> ForceControlState:
    """Return the ForceControlState of a force law's ``telemetry`` (task frame ``frame_id``)."""
    msg = ForceControlState(
        law=telemetry.law, axis_names=list(axis_names),
        force_controlled=[bool(f) for f in force_controlled],
        position_reference=np.asarray(telemetry.position_reference, dtype=float).tolist(),
        position=np.asarray(telemetry.position, dtype=float).tolist(),
        force_reference=np.asarray(telemetry.force_reference, dtype=float).tolist(),
        force=np.asarray(telemetry.force, dtype=float).tolist(),
        effort=np.asarray(telemetry.effort, dtype=float).tolist())
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg


def cartesian_control_message(law_name: str, telemetry: Any, reference: ArrayLike,
                              pose: ArrayLike, effort: ArrayLike, frame_id: str,
                              stamp: Time) -> CartesianControlState:
    """Return the CartesianControlState of a Cartesian law's step (poses 4x4 in ``frame_id``)."""
    msg = CartesianControlState(
        law=law_name, reference=pose_message(reference), pose=pose_message(pose),
        error=np.asarray(telemetry.pose_error, dtype=float).tolist(),
        manipulability=float(telemetry.manipulability),
        min_singular_value=float(telemetry.min_singular_value),
        near_singularity=bool(telemetry.near_singularity), damping=float(telemetry.damping),
        effort=np.asarray(effort, dtype=float).tolist())
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg
