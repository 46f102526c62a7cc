"""
Manipulator simulation: the forward dynamics (5.88) integrated at a fixed step (book §5.7).

``q'' = ABA(q, q', tau - F(q') - B_u q')`` by Pinocchio's articulated-body algorithm, advanced by
classical RK4 with the torque held over the step (zero-order hold, as a digital controller
applies it). ``F`` is the friction of the robot's ``dyn`` table; ``B_u`` an optional unmodelled
viscous friction per joint [N m s] that the controller's model does not know (the appendix's
PUMA example adds 0.1 N m s on joint 1). Torques are saturated at ``tau_max``; a joint that
reaches a limit stops there (its velocity is zeroed if it points outwards). A payload grasped
at some instant (Ej. 8.4) is added to the last link's inertia with
:meth:`ArmSimulation.add_payload`; :meth:`ArmSimulation.step_braked` is the safe stop (brakes
hold the joints). An optional environment, a
:class:`~robotica_sim.simulation.compliant_environment.CompliantPlane`, loads the joints with
``τ_e = Jᵀ ψ`` (8.165)-(8.166) of the force ψ the end effector exerts on it: computed at the
start of each step from the state and held over the step like the torque, which becomes
``tau - τ_e`` for the compiled step; :meth:`ArmSimulation.contact_wrench` reads ψ.

The state is owned here; time is a step counter times ``step_period`` (no clock is read). The
RK4 step and the joint stops run compiled (package ``robotica_native``, arm_step.cpp: four ABA
calls of Pinocchio's C++ API with the friction law, one ctypes call per step) on the same
Pinocchio model, passed through Pinocchio's serialisation; this module validates the input and
saturates the torque.
"""

import ctypes
from dataclasses import dataclass
import math
from typing import Any, Mapping
import weakref

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.dynamics import DEFAULT_GRAVITY, inertia, set_gravity
from robotica_kin.finite import all_finite
from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.joint_friction import JointFriction
from robotica_kin.native_library import address, ERROR_SIZE, native_library
from robotica_kin.parameter_specs import (named_error, parameter_values, ParameterError,
                                          ParameterSpec)
from robotica_kin.pinocchio_model import build_model, pinocchio_arm

from .compliant_environment import CompliantPlane, ContactWrench

__all__ = ['ARM_SIMULATOR_PARAMETERS', 'ArmSimulation', 'ArmSimulationParams', 'arm_simulation']


@dataclass(frozen=True)
class ArmSimulationParams:
    """Settings of :class:`ArmSimulation` (SI units)."""

    step_period: float = 1e-3                       # [s] integration step (1 kHz)
    gravity: tuple[float, float, float] = DEFAULT_GRAVITY   # [m/s^2] in the base frame {0}
    tau_max: tuple[float, ...] = ()                 # [N m] per joint; () = no saturation
    unmodelled_viscous: tuple[float, ...] = ()      # [N m s] per joint; () = none
    respect_limits: bool = True                     # stop joints at their limits

    def __post_init__(self) -> None:
        if not (math.isfinite(self.step_period) and 0.0 < self.step_period <= 0.1):
            raise ValueError(f'step_period must be in (0, 0.1] s, got {self.step_period!r}')
        if len(self.gravity) != 3 or not all(math.isfinite(g) for g in self.gravity):
            raise ValueError(f'gravity must be three finite values, got {self.gravity!r}')
        if any(not (t > 0.0) for t in self.tau_max):
            raise ValueError(f'tau_max must be > 0 N m per joint, got {self.tau_max!r}')
        if any(not (math.isfinite(b) and b >= 0.0) for b in self.unmodelled_viscous):
            raise ValueError('unmodelled_viscous must be finite and >= 0 N m s, got '
                             f'{self.unmodelled_viscous!r}')


class ArmSimulation:
    """
    A manipulator integrated at a fixed step with Pinocchio's ABA and RK4.

    Parameters
    ----------
    robot : DHModel
        The plant, with its ``dyn`` table (e.g. ``robotica_kin.robots.puma560()``).
    params : ArmSimulationParams
        Step, gravity, saturation and unmodelled friction.
    q0, qd0 : array_like, shape (n,)
        Initial joint positions [rad | m] and velocities.
    environment : CompliantPlane, optional
        A surface the end effector (the tool frame's origin) presses on; default none.

    Attributes
    ----------
    contact_joint_torque : ndarray, shape (n,)
        ``τ_e = Jᵀ ψ`` [N m | N] at the current state, the load the next step holds.

    Examples
    --------
    >>> from robotica_kin.dh import dh_model
    >>> from robotica_kin.robots import two_link_arm
    >>> dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> sim = ArmSimulation(dh_model(dh, dyn=dyn), ArmSimulationParams(gravity=(0.0, -9.81, 0.0)),
    ...                     [-np.pi / 2, 0.0], [0.0, 0.0])
    >>> for _ in range(100):
    ...     _ = sim.step([0.0, 0.0])       # hanging: an equilibrium
    >>> sim.time, bool(np.allclose(sim.q, [-np.pi / 2, 0.0]))
    (0.1, True)

    """

    def __init__(self, robot: DHModel, params: ArmSimulationParams, q0: ArrayLike,
                 qd0: ArrayLike, environment: CompliantPlane | None = None) -> None:
        robot = as_dyn_model(robot)
        n = robot.n
        if environment is not None and not isinstance(environment, CompliantPlane):
            raise ValueError(f'environment must be a CompliantPlane or None, got '
                             f'{type(environment).__name__}')
        self.environment = environment
        # Kinematics of the contact point (its own model and scratch: the payload changes
        # only the dynamics model), and the wrench without an environment.
        self._kinematics = pinocchio_arm(robot) if environment is not None else None
        self._kinematics_data = (self._kinematics.model.createData()
                                 if self._kinematics is not None else None)
        self._contact = ContactWrench(np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3),
                                      math.nan)
        self.contact_joint_torque = np.zeros(n)
        for name, values in (('tau_max', params.tau_max),
                             ('unmodelled_viscous', params.unmodelled_viscous)):
            if values and len(values) != n:
                raise ValueError(f'{name} needs {n} values (one per joint), got {len(values)}')
        self.robot = robot
        self.params = params
        self._model = build_model(robot)     # the plant's own: add_payload changes it
        set_gravity(self._model, params.gravity)
        self._tau_max = np.array(params.tau_max) if params.tau_max else np.full(n, np.inf)
        self._saturates = bool(np.isfinite(self._tau_max).any())
        unlimited = np.full(n, np.inf)
        self._limits = ([np.ascontiguousarray(robot.qlim[:, 0], dtype=np.float64),
                         np.ascontiguousarray(robot.qlim[:, 1], dtype=np.float64)]
                        if params.respect_limits else [-unlimited, unlimited])
        friction = JointFriction(robot)
        unmodelled = np.array(params.unmodelled_viscous) if params.unmodelled_viscous else 0.0
        self._friction = [np.ascontiguousarray(friction.viscous + unmodelled, dtype=np.float64),
                          np.ascontiguousarray(friction.coulomb_positive, dtype=np.float64),
                          np.ascontiguousarray(friction.coulomb_negative, dtype=np.float64)]
        self._error = ctypes.create_string_buffer(ERROR_SIZE)
        # The compiled step works in place on these buffers, whose addresses are taken once
        # (taking an array's address costs 2-3 µs in Python, as much as the step's own ABA).
        self._buffers = np.zeros((3, n))          # q, q', tau
        self._addresses = [address(row) for row in self._buffers]
        self._native = 0
        self._native_step = native_library().ras_arm_step
        self._free_native: weakref.finalize | None = None
        self._load_native_model()
        self.reset(q0, qd0)

    def _load_native_model(self) -> None:
        """Give the compiled step (a new copy of) the plant's model, gravity and friction."""
        lib = native_library()
        gravity = np.ascontiguousarray(self.params.gravity, dtype=np.float64)
        viscous, coulomb_positive, coulomb_negative = self._friction
        lower, upper = self._limits
        handle = lib.ras_arm_new(self._model.saveToString().encode(), address(gravity),
                                 address(viscous), address(coulomb_positive),
                                 address(coulomb_negative), address(lower), address(upper),
                                 self._error, ERROR_SIZE)
        if not handle:
            raise RuntimeError(f'robotica_native: {self._error.value.decode()}')
        if self._free_native is not None:
            self._free_native()
        self._native = handle
        self._free_native = weakref.finalize(self, lib.ras_arm_free, handle)

    def reset(self, q0: ArrayLike, qd0: ArrayLike) -> None:
        """Set the state to (q0, qd0) at time 0."""
        q = self.robot.check_q(q0, 'q0')
        qd = self.robot.check_q(qd0, 'qd0')
        if q.ndim != 1 or qd.ndim != 1:
            raise ValueError(f'q0 and qd0 must have shape ({self.robot.n},)')
        self.q = q.copy()
        self.qd = qd.copy()
        self.steps = 0
        self.applied_torque = np.zeros(self.robot.n)
        self._update_contact()

    def _update_contact(self) -> None:
        """Compute ψ, the contact wrench and τ_e = Jᵀ ψ at the current state (q, q')."""
        if self.environment is None or self._kinematics is None:
            return
        T_0_tool = fkine(self._kinematics, self.q, data=self._kinematics_data)
        J = jacob0(self._kinematics, self.q, data=self._kinematics_data)[:3]
        point, R_0_tool = T_0_tool[:3, 3], T_0_tool[:3, :3]
        psi = self.environment.force(point, J @ self.qd)
        self.contact_joint_torque = J.T @ psi
        self._contact = ContactWrench(force=psi, torque=np.zeros(3), force_tool=R_0_tool.T @ psi,
                                      torque_tool=np.zeros(3),
                                      penetration=self.environment.penetration(point))

    def contact_wrench(self) -> ContactWrench:
        """
        Return the contact wrench at the current state: ψ in {0} and in the tool frame.

        The force the end effector exerts on the environment (book (8.164)); zero, with a NaN
        penetration, for an arm without environment.
        """
        return self._contact

    @property
    def time(self) -> float:
        """Return the simulated time [s]."""
        return round(self.steps * self.params.step_period, 12)

    def step(self, tau: ArrayLike) -> NDArray[np.float64]:
        """
        Advance one step with joint torques ``tau`` [N m] (shape (n,)); return the new q.

        Raises
        ------
        ValueError
            For a torque of the wrong size or not finite (the state is left unchanged).

        """
        torque = np.asarray(tau, dtype=np.float64)
        if torque.shape != (self.robot.n,) or not all_finite(torque):
            raise ValueError(f'tau must be {self.robot.n} finite torques, got {tau!r}')
        if self._saturates:
            torque = np.clip(torque, -self._tau_max, self._tau_max)
        buffers = self._buffers
        buffers[0], buffers[1] = self.q, self.qd
        buffers[2] = torque if self.environment is None else torque - self.contact_joint_torque
        if self._native_step(self._native, *self._addresses, self.params.step_period,
                             self._error, ERROR_SIZE):
            raise RuntimeError(f'robotica_native: {self._error.value.decode()}')
        self.q, self.qd = buffers[0].copy(), buffers[1].copy()   # callers may keep old ones
        self.applied_torque = torque
        self.steps += 1
        self._update_contact()
        return self.q

    def step_braked(self) -> NDArray[np.float64]:
        """
        Advance one step with the joint brakes engaged: velocities zero, positions held.

        The safe stop of a simulator whose torque command is stale or missing; return q.
        """
        self.qd = np.zeros(self.robot.n)
        self.applied_torque = np.zeros(self.robot.n)
        self.steps += 1
        self._update_contact()
        return self.q

    def add_payload(self, mass: float, com: ArrayLike) -> None:
        """
        Rigidly attach a point mass to the last link (the plant changes, not the controller's).

        Parameters
        ----------
        mass : float
            Payload mass [kg], finite and > 0 (Ej. 8.4: 2 kg grasped at t = 10 s).
        com : array_like, shape (3,)
            Its position [m] in the last link's frame {n} (Ej. 8.4: the link-2 mass point,
            ``[l2, 0, 0]``, so that the link's centre of mass is unchanged).

        Raises
        ------
        ValueError
            For a mass that is not finite and > 0, or a position that is not 3 finite values.

        """
        point = np.asarray(com, dtype=np.float64)
        if not (math.isfinite(mass) and mass > 0.0):
            raise ValueError(f'payload mass must be finite and > 0 kg, got {mass!r}')
        if point.shape != (3,) or not np.isfinite(point).all():
            raise ValueError(f'payload com must be 3 finite values [m] in frame {{n}}, '
                             f'got {com!r}')
        n = self.robot.n
        self._model.inertias[n] = self._model.inertias[n] + pin.Inertia(mass, point,
                                                                        np.zeros((3, 3)))
        self._load_native_model()


ARM_SIMULATOR_PARAMETERS: dict[str, ParameterSpec] = {
    'gravity': ParameterSpec(DEFAULT_GRAVITY, 'Gravity acceleration [m/s^2] in the base frame '
                             '{0}'),
    'respect_limits': ParameterSpec(True, 'Stop the joints at their limits'),
    'payload.mass': ParameterSpec(0.0, 'Mass grasped at payload.time [kg]; 0: none (Ej. 8.4: '
                                  '2)', 0.0, 1e4),
    'payload.com': ParameterSpec((0.0, 0.0, 0.0), 'Its position [m] in the last link frame {n}'),
    'payload.time': ParameterSpec(0.0, 'Simulated time [s] of the grasp (Ej. 8.4: 10)',
                                  0.0, 1e7),
    'cmd_timeout': ParameterSpec(0.01, 'A command older than this [s, simulated] engages the '
                                 'brakes', 1e-4, 60.0),
}
"""The arm simulator node's parameters with a default, by name: :func:`arm_simulation`.
``initial_positions``, ``initial_velocities`` (default zeros), ``tau_max`` and
``unmodelled_viscous`` (1 or n values; default none) are apart: their size is the robot's."""


def _per_joint(values: Any, n: int, name: str) -> tuple[float, ...]:
    """Return () for no values, n values as given, or one value repeated n times."""
    values = list(values) if values is not None else []
    if len(values) == 1:
        values = values * n
    if values and len(values) != n:
        raise ParameterError(name, f'needs 1 or {n} values, got {len(values)}')
    return tuple(float(v) for v in values)


def arm_simulation(robot: DHModel, parameters: Mapping[str, Any], step_period: float,
                   environment: CompliantPlane | None = None) -> ArmSimulation:
    """
    Return the simulation the arm simulator node runs for ``robot`` and its ``parameters``.

    ``parameters`` maps the node's names (:data:`ARM_SIMULATOR_PARAMETERS`,
    ``initial_positions`` ...) to values; missing ones take their defaults, others are ignored.
    ``step_period`` [s] is the simulated time per step; ``environment`` an optional surface
    (:class:`ArmSimulation`).

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For a value out of its range or refused by the simulation (``name`` is the parameter's).
    ValueError
        For other values the simulation refuses.

    Examples
    --------
    >>> from robotica_kin.robots import puma560
    >>> arm_simulation(puma560(), {'tau_max': [50.0]}, 1e-3).params.tau_max[5]
    50.0

    """
    values = parameter_values(ARM_SIMULATOR_PARAMETERS, parameters)
    if len(values['payload.com']) != 3:
        raise ParameterError('payload.com', f'must be 3 values [m], got {values["payload.com"]}')
    n = robot.n
    sizes = {name: _per_joint(parameters.get(name), n, name)
             for name in ('tau_max', 'unmodelled_viscous')}
    given = {name: parameters.get(name) for name in ('initial_positions', 'initial_velocities')}
    try:
        start = {name: robot.check_q(q if q is not None and len(q) else [0.0] * n, name)
                 for name, q in given.items()}
        params = ArmSimulationParams(step_period=step_period, gravity=tuple(values['gravity']),
                                     respect_limits=values['respect_limits'], **sizes)
    except ValueError as err:
        raise named_error(err, ('step_period', 'gravity', *sizes, *given)) from None
    # ABA inverts M(q): a singular one (a link of zero mass, point masses in line) gives NaN.
    eigenvalues = np.linalg.eigvalsh(inertia(robot, start['initial_positions']))
    if not eigenvalues[0] > 1e-9 * max(eigenvalues[-1], 1e-300):
        raise ValueError(f'the mass matrix M(q0) is singular (eigenvalues '
                         f'{np.round(eigenvalues, 12).tolist()}): a link without mass or '
                         'inertia cannot be simulated')
    return ArmSimulation(robot, params, start['initial_positions'], start['initial_velocities'],
                         environment)
