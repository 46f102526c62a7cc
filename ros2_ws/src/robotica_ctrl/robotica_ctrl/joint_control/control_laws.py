"""
The joint control laws by name, with their gains as node parameters: the registry.

The ``joint_controller`` node builds its law with :func:`make_joint_law` from its parameters
(``law`` and ``<law>.<gain>``, described in :data:`JOINT_LAW_PARAMETERS`), and the plan of a
run (:mod:`robotica_sim.runs.plan`) calls it with the same values before any process starts.

================== ====================================================== =================
law                class                                                  book
================== ====================================================== =================
``pid``            :class:`~robotica_ctrl.joint_control.pid.DecoupledPID` §8.2 (8.10)
``computed_torque`` :class:`~.computed_torque.ComputedTorque`             (8.27)-(8.37)
================== ====================================================== =================
"""
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike
from robotica_ctrl.joint_control.computed_torque import ComputedTorque, ComputedTorqueGains
from robotica_ctrl.joint_control.law import JointControlLaw, per_joint
from robotica_ctrl.joint_control.pid import DecoupledPID, PIDGains
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.parameter_specs import (named_error, parameter_values, ParameterError,
                                          ParameterSpec)

__all__ = ['FIRST_PERIOD', 'JOINT_LAWS', 'JOINT_LAW_PARAMETERS', 'make_joint_law']

JOINT_LAWS = ('pid', 'computed_torque')
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
}
"""The gains of each law by name (the node's parameters ``<law>.<gain>``); each 1 or n values."""
FIRST_PERIOD = ParameterSpec(1e-3, 'dt [s] of the first step (no previous state yet)', 1e-6, 1.0)
"""The joint controller's ``first_period``: the sample period before a second state."""
MAX_PERIOD = ParameterSpec(
    1.0, 'Longest gap between two states that is integrated [s]; a longer one resets the law '
    '(its integrals) as a new start', 1e-6, 3600.0)
"""The joint controller's ``max_period``: one stamp gap of 1000 s wound a PID integral up by
1000 s of error (any gap under the stamp gate's 3600 s was integrated)."""


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
            per_joint(name, value, robot.n)
        if law == 'pid':
            return DecoupledPID(PIDGains(**values))
        return ComputedTorque(robot, ComputedTorqueGains(**values), grav,
                              use_friction=use_friction)
    except ValueError as err:
        raise named_error(err, values) from None
