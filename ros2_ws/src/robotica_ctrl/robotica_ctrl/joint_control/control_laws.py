"""
The joint control laws by name, with their gains as node parameters: the registry.

The ``joint_controller`` node builds its law with :func:`make_joint_law` from its parameters
(``law`` and ``<law>.<gain>``, described in :data:`JOINT_LAW_PARAMETERS`), and the plan of a
run (:mod:`robotica_sim.runs.plan`) calls it with the same values before any process starts.

=========================== ======================================================= =============
law                         class                                                   book
=========================== ======================================================= =============
``pid``                     :class:`~robotica_ctrl.joint_control.pid.DecoupledPID`  §8.2 (8.10)
``computed_torque``         :class:`~.computed_torque.ComputedTorque`              (8.27)-(8.37)
``adaptive_computed_torque`` :class:`~.adaptive_computed_torque.AdaptiveComputedTorque` (8.95)
``slotine_li``              :class:`~.slotine_li.SlotineLi`                        (8.123)-(8.125)
``model_reference``         :class:`~.reference_model.ModelReferenceAdaptive`      (8.75)-(8.78)
``learning``                :class:`~.iterative_learning.IterativeLearningControl` (8.138)-(8.150)
=========================== ======================================================= =============

The adaptive laws estimate the link masses of the controller's model (its masses are the
initial estimates, :class:`~.regressor.LinkMassRegressor`: any arm, not only the 2R).
"""
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.joint_control.adaptive_computed_torque import (AdaptiveComputedTorque,
                                                                  AdaptiveComputedTorqueGains)
from robotica_ctrl.joint_control.computed_torque import ComputedTorque, ComputedTorqueGains
from robotica_ctrl.joint_control.iterative_learning import IterativeLearningControl, LearningGains
from robotica_ctrl.joint_control.law import JointControlLaw, per_joint
from robotica_ctrl.joint_control.pid import DecoupledPID, PIDGains
from robotica_ctrl.joint_control.reference_model import ModelReferenceAdaptive, ModelReferenceGains
from robotica_ctrl.joint_control.regressor import LinkMassRegressor
from robotica_ctrl.joint_control.slotine_li import SlotineLi, SlotineLiGains
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.parameter_specs import (named_error, parameter_values, ParameterError,
                                          ParameterSpec)

__all__ = ['FIRST_PERIOD', 'JOINT_LAWS', 'JOINT_LAW_PARAMETERS', 'MAX_PERIOD', 'TRIAL_PERIOD',
           'make_joint_law']

JOINT_LAWS = ('pid', 'computed_torque', 'adaptive_computed_torque', 'slotine_li',
              'model_reference', 'learning')
JOINT_LAW_PARAMETERS: dict[str, dict[str, ParameterSpec]] = {
    'pid': {
        'kp': ParameterSpec((25.0,), 'K_p [N m/rad] per joint (one value: all joints), book '
                            '(8.10)'),
        'kv': ParameterSpec((10.0,), 'K_v [N m s/rad] per joint'),
        'ki': ParameterSpec((0.0,), 'K_i [N m/(rad s)] per joint'),
        'tau_max': ParameterSpec((math.inf,), 'Torque saturation [N m] per joint, > 0'),
        'integral_max': ParameterSpec((math.inf,), 'Clamp of the error integral [rad s] '
                                      '(anti-windup)'),
        'derivative_time_constant': ParameterSpec((0.0,), 'T_f [s] of the low-pass filter of '
                                                  "e'; 0: none")},
    'computed_torque': {
        'kp': ParameterSpec((25.0,), 'K_p [1/s^2] per joint, book (8.30); omega_n = sqrt(K_p) '
                            '(8.22)'),
        'kv': ParameterSpec((10.0,), 'K_v [1/s] per joint; damping K_v / (2 sqrt(K_p)) (8.23)'),
        'ki': ParameterSpec((0.0,), 'K_i [1/s^3] per joint, PID variant (8.36)'),
        'integral_max': ParameterSpec((math.inf,), 'Clamp of the error integral [rad s] '
                                      '(anti-windup)')},
    'adaptive_computed_torque': {
        'kp': ParameterSpec((25.0,), 'K_p [1/s^2] per joint, > 0, book (8.30)'),
        'kv': ParameterSpec((10.0,), 'K_v [1/s] per joint, > 0.5 (the Q of (8.103))'),
        'gamma': ParameterSpec((1.0,), 'Gamma per adapted link mass, > 0, adaptation law (8.95)'),
        'acceleration_time_constant': ParameterSpec(
            (0.0,), "T [s] of the low-pass on q'' (differenced velocities; the law's drawback: "
            'measured accelerations are noisy); 0: none')},
    'slotine_li': {
        'kv': ParameterSpec((10.0,), 'K_v [N m s/rad] per joint, > 0, book (8.123); Ej. 8.8: 10'),
        'lam': ParameterSpec((2.5,), "Lambda [1/s] per joint, > 0: r = Lambda e + e' (8.111)"),
        'gamma': ParameterSpec((20.0,), "Gamma per adapted link mass, > 0: phi' = Gamma Y^T r "
                               '(8.125); Ej. 8.8: 20')},
    'model_reference': {
        'natural_frequency': ParameterSpec((5.0,), 'omega_n [rad/s] of the reference model per '
                                           'joint, > 0 (8.76)'),
        'damping': ParameterSpec((1.0,), 'delta of the reference model per joint, > 0 (8.76)'),
        'kp': ParameterSpec((25.0,), 'Initial K_p [N m/rad] per joint'),
        'kv': ParameterSpec((10.0,), 'Initial K_v [N m s/rad] per joint'),
        'gamma_p': ParameterSpec((1.0,), 'Adaptation rate of K_p (MIT rule on (8.78))'),
        'gamma_v': ParameterSpec((1.0,), 'Adaptation rate of K_v (MIT rule on (8.78))'),
        'w0': ParameterSpec((1.0,), 'Weight of epsilon in J (8.78)'),
        'w1': ParameterSpec((0.0,), "Weight of epsilon' [s] in J"),
        'w2': ParameterSpec((0.0,), "Weight of epsilon'' [s^2] in J (uses q'' estimated)"),
        'acceleration_time_constant': ParameterSpec((0.0,), "T [s] of the low-pass on q''")},
    'learning': {
        'kp': ParameterSpec((625.0,), 'K_p [1/s^2] per joint (8.138); Ej. 8.9: 625'),
        'kv': ParameterSpec((50.0,), 'K_v [1/s] per joint; Ej. 8.9: 50'),
        'mu': ParameterSpec((3.0,), 'mu of the learning filter (8.150) per joint; refused unless '
                            'max |G(jw)| < 1; Ej. 8.9: 3'),
        'max_feedforward': ParameterSpec((math.inf,), 'Bound of the learned |D| [rad/s^2] per '
                                         'joint, > 0')},
}
"""The gains of each law by name (the node's parameters ``<law>.<gain>``); each 1 or n values."""
FIRST_PERIOD = ParameterSpec(1e-3, 'dt [s] of the first step (no previous state yet)', 1e-6, 1.0)
"""The joint controller's ``first_period``: the sample period before a second state."""
MAX_PERIOD = ParameterSpec(
    1.0, 'Longest gap between two states that is integrated [s]; a longer one resets the law '
    '(its integrals) as a new start', 1e-6, 3600.0)
"""The joint controller's ``max_period``: one stamp gap of 1000 s wound a PID integral up by
1000 s of error (any gap under the stamp gate's 3600 s was integrated)."""
TRIAL_PERIOD = ParameterSpec(
    0.0, 'Length of a trial [s]: the reference restarts every trial_period and a learning law '
    'learns from each trial (8.150); 0: one trial', 0.0, 1e6)
"""The joint controller's ``trial_period`` (iterative learning, §8.5)."""


def make_joint_law(law: str, model: DHModel | ArrayLike, gains: Mapping[str, Any],
                   grav: ArrayLike | None = None, *, use_friction: bool = True
                   ) -> JointControlLaw:
    """
    Return the joint control law ``law`` for the robot ``model`` with ``gains`` (by name).

    Parameters
    ----------
    law : str
        One of :data:`JOINT_LAWS`.
    model : DHModel or array_like, shape (n, 20)
        The controller's model of the robot (its number of joints n sizes the gains).
    gains : mapping
        Gains by the names of ``JOINT_LAW_PARAMETERS[law]``, lists of 1 or n values; missing
        ones take their defaults.
    grav : array_like, shape (3,), optional
        Gravity [m/s²] in {0} of the model (computed torque).
    use_friction : bool
        Compensate the model's friction (computed torque).

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For an unknown law (``name`` 'law') or a gain the law refuses (``name`` the gain's).
    ValueError
        For an unknown gain or a model the law refuses.

    Examples
    --------
    >>> from robotica_kin.robots import two_link_arm
    >>> law = make_joint_law('pid', two_link_arm(2.0, 1.0, 3.0, 1.0)[1], {'kp': [100.0]})
    >>> law.gains.kp
    array(100.)

    """
    if law not in JOINT_LAW_PARAMETERS:
        raise ParameterError('law', f'must be one of {JOINT_LAWS}, got {law!r}')
    specs = JOINT_LAW_PARAMETERS[law]
    unknown = sorted(set(gains) - set(specs))
    if unknown:
        raise ValueError(f'{law} has no gain {unknown}; its gains: {sorted(specs)}')
    values = {name: value[0] if len(value) == 1 else np.array(value, dtype=np.float64)
              for name, value in parameter_values(specs, gains).items()}
    robot = as_dyn_model(model)
    try:
        for name, value in values.items():
            if name != 'gamma':   # one per adapted parameter, checked by the law
                per_joint(name, value, robot.n)
        return _build(law, robot, values, grav, use_friction)
    except ValueError as err:
        raise named_error(err, values) from None


def _build(law: str, robot: DHModel, values: dict, grav: ArrayLike | None,
           use_friction: bool) -> JointControlLaw:
    """Return the law ``law`` on ``robot`` with its checked gains ``values``."""
    if law == 'pid':
        return DecoupledPID(PIDGains(**values))
    if law == 'model_reference':
        return ModelReferenceAdaptive(ModelReferenceGains(**values))
    if law == 'learning':
        return IterativeLearningControl(robot, LearningGains(**values), grav,
                                        use_friction=use_friction)
    if law in ('adaptive_computed_torque', 'slotine_li'):
        regressor = LinkMassRegressor(robot, grav)
        if law == 'slotine_li':
            return SlotineLi(regressor, regressor.masses, SlotineLiGains(**values))
        return AdaptiveComputedTorque(regressor, regressor.masses,
                                      AdaptiveComputedTorqueGains(**values))
    return ComputedTorque(robot, ComputedTorqueGains(**values), grav, use_friction=use_friction)
