"""
The task-space laws the joint controller runs, by name, with their reference in time.

Besides its joint-space laws (:mod:`.control_laws`), the ``joint_controller`` node runs the
force laws of §8.7 and the Cartesian laws of §8.6 (seed catalogue Part 6, §6.6-§6.7). Their
reference is not a joint trajectory but a task one, made here from parameters:

====================== ============================================= ===============
law                    class (``robotica_ctrl.``)                    book
====================== ============================================= ===============
``stiffness``          ``force_control.StiffnessControl``            (8.168)/(8.189)
``hybrid``             ``force_control.HybridForcePosition``         (8.193)-(8.214)
``impedance``          ``force_control.ImpedanceControl``            (outside §8.7)
``resolved_rate``      ``cartesian_control.ResolvedRate``            fig. 8.39
``transpose_jacobian`` ``cartesian_control.TransposeJacobian``       (8.158)
``operational_space``  ``cartesian_control.OperationalSpace``        (8.163)
====================== ============================================= ===============

* a force law works in a constant task frame (``task.axes``: its axes in {0}, normal ones
  first, ``task.normal_axes`` of them) and follows a :class:`~robotica_ctrl.force_control.
  reference_profile.TaskReferenceProfile` (``task.position.*``, ``task.force.*``); the measured
  contact wrench comes as an F/T sensor at the tool gives it (the wrench the environment applies
  to the tool, tool axes) and is turned into ψ, the force the end effector exerts, in task axes;
* a Cartesian law follows the straight line from the pose of its first step to ``cartesian.goal``
  (x, y, z [m], roll, pitch, yaw [rad] in {0}) in ``cartesian.duration`` seconds
  (:class:`~robotica_ctrl.cartesian_control.timed_line.TimedLine`).

t is the time since the law's first step. Pure: no ROS, no clock.
"""
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.cartesian_control import (CartesianGains, OperationalSpace, ResolvedRate,
                                             ResolvedRateParams, TransposeJacobian)
from robotica_ctrl.cartesian_control.resolved_rate import MODES
from robotica_ctrl.cartesian_control.timed_line import TimedLine
from robotica_ctrl.force_control import (HybridForcePosition, HybridGains, ImpedanceControl,
                                         ImpedanceGains, StiffnessControl, StiffnessGains,
                                         TaskFrame)
from robotica_ctrl.force_control.reference_profile import TaskReferenceProfile
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.forward_kinematics import fkine
from robotica_kin.parameter_specs import (named_error, parameter_values, ParameterError,
                                          ParameterSpec)
from robotica_kin.transforms import rpy2tr, transl

from .law import JointState

__all__ = ['CARTESIAN_LAWS', 'FORCE_LAWS', 'TASK_LAWS', 'TASK_LAW_PARAMETERS',
           'TASK_PARAMETERS', 'TaskSpaceControl']

FORCE_LAWS = ('stiffness', 'hybrid', 'impedance')
CARTESIAN_LAWS = ('resolved_rate', 'transpose_jacobian', 'operational_space')
TASK_LAWS = FORCE_LAWS + CARTESIAN_LAWS

_CARTESIAN_GAINS = {'kp': ParameterSpec(25.0, 'K_p on the pose error (per row: one value for all)',
                                        0.0, 1e9),
                    'kv': ParameterSpec(10.0, 'K_v on the twist error', 0.0, 1e9)}
TASK_LAW_PARAMETERS: dict[str, dict[str, ParameterSpec]] = {
    'stiffness': {
        'kp': ParameterSpec((10.0,), "K_p [N/m] per task axis, the arm's stiffness (8.168); "
                            'Ej. 8.10: 10'),
        'kv': ParameterSpec((10.0,), 'K_v [N s/m] per task axis; Ej. 8.10: 10')},
    'hybrid': {
        'kp_tangential': ParameterSpec((15.0,), 'K_Tp [1/s^2] of the position loop (8.197); Ej. '
                                       '8.11: 15'),
        'kv_tangential': ParameterSpec((15.0,), 'K_Tv [1/s] (8.197)'),
        'kp_normal': ParameterSpec((15.0,), 'K_Np [1/s^2] of the force loop (8.205)'),
        'kv_normal': ParameterSpec((15.0,), 'K_Nv [1/s] (8.205)'),
        'environment_stiffness': ParameterSpec((1200.0,), 'K_e [N/m] per normal axis, the '
                                               "law's model of the surface (8.201)")},
    'impedance': {
        'inertia': ParameterSpec((1.0,), 'M_d [kg] per task axis of the target impedance'),
        'damping': ParameterSpec((20.0,), 'B_d [N s/m]'),
        'stiffness': ParameterSpec((100.0,), 'K_d [N/m]')},
    'resolved_rate': {
        'mode': ParameterSpec('damped_least_squares', 'How J is inverted (fig. 8.39)',
                              choices=MODES),
        'kx': ParameterSpec(20.0, 'K_x [1/s] on the pose error', 0.0, 1e6),
        'damping': ParameterSpec(0.05, 'lambda of damped least squares (its maximum when '
                                 'variable)', 0.0, 1e3),
        'variable_damping': ParameterSpec(True, 'Damp only near a singularity (Nakamura, '
                                          'Wampler)')},
    'transpose_jacobian': {**_CARTESIAN_GAINS,
                           'gravity_compensation': ParameterSpec(True, "Add the model's G(q)")},
    'operational_space': dict(_CARTESIAN_GAINS),
}
"""The gains of each task-space law (the node's parameters ``<law>.<gain>``)."""
TASK_PARAMETERS: dict[str, ParameterSpec] = {
    'task.axes': ParameterSpec((1.0, 0.0, 0.0), 'Force laws: the task axes in the base frame '
                               '{0}, 3 numbers per axis, normal (force) axes first; Ej. 8.10: '
                               '[0.7071, -0.7071, 0, 0.7071, 0.7071, 0]'),
    'task.origin': ParameterSpec((0.0, 0.0, 0.0), 'Origin of the task frame [m] in {0}'),
    'task.normal_axes': ParameterSpec(1, 'How many of the task axes are normal to the surface',
                                      0, 3),
    'task.position.offset': ParameterSpec((0.0,), 'x_0 [m] per task axis: x_d = x_0 + A sin('
                                          '2 pi t/T + phi)'),
    'task.position.amplitude': ParameterSpec((0.0,), 'A [m] per task axis'),
    'task.position.period': ParameterSpec((2.0 * math.pi,), 'T [s] per task axis, > 0'),
    'task.position.phase': ParameterSpec((0.0,), 'phi [rad] per task axis'),
    'task.force.final': ParameterSpec((0.0,), 'psi_f [N] per task axis: psi_d = psi_f (1 - '
                                      'exp(-t/tau)), the force on the environment'),
    'task.force.time_constant': ParameterSpec((0.0,), 'tau [s] per task axis; 0: a step'),
    'cartesian.goal': ParameterSpec((0.0, 0.0, 0.0, 0.0, 0.0, 0.0), 'Cartesian laws: the goal '
                                    'pose x, y, z [m], roll, pitch, yaw [rad] in {0}'),
    'cartesian.duration': ParameterSpec(5.0, 'Time to reach the goal along a straight line [s]',
                                        1e-3, 1e6),
    'cartesian.singular_threshold': ParameterSpec(0.05, 'sigma_min of J below which the arm is '
                                                  'near a singularity (reported)', 0.0, 1e3),
}
"""The task frame and the task reference of the task-space laws (node parameters)."""


def _gains(law: str, gains: Mapping[str, Any]) -> dict[str, Any]:
    specs = TASK_LAW_PARAMETERS[law]
    unknown = sorted(set(gains) - set(specs))
    if unknown:
        raise ValueError(f'{law} has no gain {unknown}; its gains: {sorted(specs)}')
    return {name: (value[0] if len(value) == 1 else np.array(value, dtype=np.float64))
            if isinstance(value, (list, tuple)) else value
            for name, value in parameter_values(specs, gains).items()}


def _task_frame(values: Mapping[str, Any]) -> TaskFrame:
    axes = np.array(values['task.axes'], dtype=np.float64)
    if axes.size not in (3, 6, 9):
        raise ParameterError('task.axes', f'must be 3, 6 or 9 numbers (1 to 3 axes), got '
                             f'{axes.size}')
    try:
        return TaskFrame(axes.reshape(-1, 3).T, values['task.origin'], values['task.normal_axes'])
    except ValueError as err:
        raise ParameterError('task.axes', str(err)) from None


def _profile(values: Mapping[str, Any], m: int) -> TaskReferenceProfile:
    names = {'offset': 'task.position.offset', 'amplitude': 'task.position.amplitude',
             'period': 'task.position.period', 'phase': 'task.position.phase',
             'force': 'task.force.final', 'time_constant': 'task.force.time_constant'}
    try:
        return TaskReferenceProfile(m, **{field: values[name] for field, name in names.items()})
    except ValueError as err:
        field = str(err).partition(' ')[0]
        raise ParameterError(names.get(field, 'task.position.offset'),
                             str(err).partition(' ')[2]) from None


class TaskSpaceControl:
    """
    A task-space law of the joint controller with its reference in time (module docstring).

    Parameters
    ----------
    law : str
        One of :data:`TASK_LAWS`.
    model : DHModel or array_like (n, 20)
        The controller's model of the robot.
    gains : mapping
        The law's gains by the names of ``TASK_LAW_PARAMETERS[law]``; missing ones default.
    task : mapping
        The values of :data:`TASK_PARAMETERS` by name; missing ones default.
    grav : array_like (3,), optional
        Gravity [m/s²] in {0}.
    use_friction : bool
        Compensate the model's friction (force laws).
    step : float
        The controller's step [s]: the sample period of a Cartesian line.

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For an unknown law or a value the law or its reference refuses (by parameter name).

    Examples
    --------
    Ej. 8.10 on the PP robot (q = [d2, d1]): at x = (2, 4) m, out of contact, pulled towards
    x_d = (2.3, 2) m with K_p = 10: ψ = (3, -20) N in task axes, (-17, -23)/√2 N in {0}, plus
    the weight (m1 + m2) g = 23.05 N on d2.

    >>> from robotica_kin.robots import pp_robot
    >>> s = 1 / math.sqrt(2)
    >>> control = TaskSpaceControl('stiffness', pp_robot(), {}, {
    ...     'task.axes': [s, -s, 0, s, s, 0], 'task.position.offset': [2.3, 2.0]},
    ...     grav=[0.0, -9.81, 0.0])
    >>> control.update(0.0, JointState([s * 2, s * 6], [0.0, 0.0]), np.zeros(6), 1e-3).round(3)
    array([  6.79 , -12.021])

    """

    def __init__(self, law: str, model: DHModel | ArrayLike, gains: Mapping[str, Any],
                 task: Mapping[str, Any], grav: ArrayLike | None = None, *,
                 use_friction: bool = True, step: float = 1e-3) -> None:
        if law not in TASK_LAW_PARAMETERS:
            raise ParameterError('law', f'must be one of {TASK_LAWS}, got {law!r}')
        self.law_name = law
        self.robot = robot = as_dyn_model(model)
        values = parameter_values(TASK_PARAMETERS, task)
        self.is_force = law in FORCE_LAWS
        self.step = step
        self._start: float | None = None
        self._line: TimedLine | None = None
        self.reference: Any = None   # of the last step: a TaskReference or CartesianReference
        g = _gains(law, gains)
        try:
            self.law = self._make(law, robot, g, values, grav, use_friction)
        except ValueError as err:
            raise named_error(err, g, f'{law}.') from None
        self._goal = values['cartesian.goal']
        self._duration = values['cartesian.duration']
        if len(self._goal) != 6:
            raise ParameterError('cartesian.goal', f'must be 6 numbers, got {len(self._goal)}')

    def _make(self, law: str, robot: DHModel, g: dict, values: Mapping[str, Any],
              grav: ArrayLike | None, use_friction: bool) -> Any:
        threshold = values['cartesian.singular_threshold']
        if law == 'resolved_rate':
            return ResolvedRate(robot, ResolvedRateParams(**g), grav,
                                singular_threshold=threshold)
        if law == 'transpose_jacobian':
            compensation = g.pop('gravity_compensation')
            return TransposeJacobian(robot, CartesianGains(**g), grav,
                                     gravity_compensation=compensation,
                                     singular_threshold=threshold)
        if law == 'operational_space':
            return OperationalSpace(robot, CartesianGains(**g), grav,
                                    singular_threshold=threshold)
        self.frame = frame = _task_frame(values)
        self.profile = _profile(values, frame.m)
        if law == 'stiffness':
            return StiffnessControl(robot, frame, StiffnessGains(**g), grav,
                                    use_friction=use_friction)
        if law == 'impedance':
            return ImpedanceControl(robot, frame, ImpedanceGains(**g), grav,
                                    use_friction=use_friction)
        stiffness = g.pop('environment_stiffness')
        return HybridForcePosition(robot, frame, stiffness, HybridGains(**g), grav,
                                   use_friction=use_friction)

    def reset(self) -> None:
        """Start again: the reference's time and a Cartesian line start at the next step."""
        self.law.reset()
        self._start = None
        self._line = None

    def task_force(self, q: NDArray[np.float64], wrench_on_tool: ArrayLike) -> NDArray[np.float64]:
        """
        Return ψ in task axes: the force the end effector exerts on the environment [N].

        ``wrench_on_tool`` (6,) is what a wrist F/T sensor aligned with the tool frame reads:
        the wrench the environment applies to the tool, in tool axes (force first).
        """
        rotation = fkine(self.robot, q)[:3, :3]
        return self.frame.to_task(-rotation @ np.asarray(wrench_on_tool, dtype=np.float64)[:3])

    def update(self, t: float, state: JointState, wrench_on_tool: ArrayLike | None,
               dt: float) -> NDArray[np.float64]:
        """
        Return the joint torques (n,) at time ``t`` [s] for ``state``; advance by ``dt``.

        ``wrench_on_tool`` is the measured contact wrench (force laws; ignored otherwise). The
        reference of the step is left in :attr:`reference`.
        """
        if self._start is None:
            self._start = t
        elapsed = t - self._start
        if self.is_force:
            force = self.task_force(state.q, np.zeros(6) if wrench_on_tool is None
                                    else wrench_on_tool)
            self.reference = self.profile.at(elapsed)
            return self.law.update(self.reference, state, force, dt)
        if self._line is None:
            goal = transl(*self._goal[:3]) @ rpy2tr(*self._goal[3:])
            self._line = TimedLine(fkine(self.robot, state.q), goal, self._duration, self.step)
        self.reference = self._line.at(elapsed)
        return self.law.update(self.reference, state, dt)
