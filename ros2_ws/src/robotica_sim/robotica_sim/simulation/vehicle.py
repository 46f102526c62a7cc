"""
Kinematic simulation of any wheeled vehicle at a fixed step (the vehicle simulator's core).

The vehicle is one of :data:`robotica_kin.mobile.vehicles.VEHICLE_TYPES`. Its state is the pose
(x, y, θ) of the guide point in the world frame (REP-103, θ from the x axis), its actuators
(wheel speeds, drive speed, steering angle) and the angles of its two odometry wheels. Per step,
with the command held (zero-order hold), classic RK4 integrates

* the pose: x' = vx cos θ − vy sin θ, y' = vx sin θ + vy cos θ, θ' = ω, with (vx, vy, ω) the
  direct model of the actuators (book §4.7.4) scaled by ``1 − longitudinal_slip`` (the ground
  moves less than the wheels roll: slip is what dead reckoning cannot see, §4.7.5);
* the actuators: a first-order lag towards the inverse model's targets,
  a' = (a* − a) / τ, with τ the traction or the steering time constant (0: instantaneous);
* the odometry wheels' angles: their rolling rates (unslipped).

A command older than ``cmd_timeout`` sets the targets to a stop (zero speeds; a steered vehicle
keeps its steering angle): the stale-command safety of ros2_controllers' ``cmd_vel_timeout``.

With a world (:class:`robotica_kin.world.shapes.World`), each step's motion is checked against
it (:mod:`robotica_sim.simulation.contact`): the vehicle's footprint stops where it first
touches an obstacle, its speeds zeroed and its odometry wheels' angles at the same fraction of
the step, and the contact is counted. Without one (the default) nothing of this runs.
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.bounds import bounded, MAX_ANGULAR_RATE, MAX_SPEED
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.vehicles import (as_command, GEOMETRY_PARAMETERS, POSE_PARAMETERS,
                                          vehicle_kinematics, VEHICLE_TYPES, VehicleGeometry,
                                          VehicleKinematics)
from robotica_kin.parameter_specs import parameter_values, ParameterSpec
from robotica_kin.world.queries import Footprint, footprint_distance
from robotica_kin.world.shapes import World
from robotica_sim.simulation.contact import (CONTACT_DISTANCE, contact_point,
                                             footprint_from_parameters, step_fraction)

__all__ = ['SIMULATOR_PARAMETERS', 'VehicleSimulation', 'VehicleSimulationParams',
           'vehicle_simulation']


@dataclass(frozen=True)
class VehicleSimulationParams:
    """Fixed-step integration and actuator settings (SI units)."""

    step_period: float = 0.02             # [s] simulated time per step (publishing period)
    rk4_substeps: int = 1                 # RK4 steps per simulation step
    cmd_timeout: float = 0.5              # [s] a command older than this (simulated) stops
    traction_time_constant: float = 0.0   # [s] first-order lag of speeds; 0: none
    steering_time_constant: float = 0.0   # [s] first-order lag of steering; 0: none
    longitudinal_slip: float = 0.0        # [-] in [0, 1): ground speed / rolling speed = 1 - s

    def __post_init__(self) -> None:
        if not (math.isfinite(self.step_period) and self.step_period > 0.0):
            raise ValueError(f'step_period must be > 0 s, got {self.step_period!r}')
        if self.rk4_substeps < 1:
            raise ValueError(f'rk4_substeps must be >= 1, got {self.rk4_substeps!r}')
        if not (math.isfinite(self.cmd_timeout) and self.cmd_timeout > 0.0):
            raise ValueError(f'cmd_timeout must be > 0 s, got {self.cmd_timeout!r}')
        for name in ('traction_time_constant', 'steering_time_constant'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0 s, got {value!r}')
        if not (0.0 <= self.longitudinal_slip < 1.0):
            raise ValueError('longitudinal_slip must be in [0, 1), got '
                             f'{self.longitudinal_slip!r}')


SIMULATOR_PARAMETERS: dict[str, ParameterSpec] = {
    'vehicle.type': ParameterSpec('differential', 'Configuration', choices=VEHICLE_TYPES),
    **{f'vehicle.{name}': spec for name, spec in GEOMETRY_PARAMETERS.items()},
    **POSE_PARAMETERS,
    'rk4_substeps': ParameterSpec(1, 'RK4 integration steps per step', 1, 1000),
    'cmd_timeout': ParameterSpec(0.5, 'A command older than this [s, simulated] stops the '
                                 'vehicle', 1e-3, 60.0),
    'traction_time_constant': ParameterSpec(0.0, 'First-order lag of the wheel/drive speeds '
                                            '[s]; 0: none', 0.0, 60.0),
    'steering_time_constant': ParameterSpec(0.0, 'First-order lag of the steering [s]; 0: none',
                                            0.0, 60.0),
    'longitudinal_slip': ParameterSpec(0.0, 'Wheel slip s: the ground moves (1 - s) of what the '
                                       'wheels roll', 0.0, 0.9),
    'footprint.radius': ParameterSpec(0.0, 'Footprint for contact with the world: a circle of '
                                      'this radius [m] about base_link; 0: the polygon', 0.0,
                                      100.0),
    'footprint.polygon': ParameterSpec((0.0,), 'Footprint polygon [x1, y1, x2, y2, ...] [m] in '
                                       "base_link; [0.0]: the vehicle's outline (as drawn)",
                                       -100.0, 100.0),
}
"""The vehicle simulator node's parameters of the plant, by name: :func:`vehicle_simulation`."""


class VehicleSimulation:
    """
    State and stepping of one simulated vehicle.

    Time starts at 0 and advances by ``step_period`` per :meth:`step`.

    A differential-drive robot (Ejemplo 4.9 (a): c = 0.25 m, b = 1 m, both wheels at 1 rad/s,
    that is v = 0.25 m/s) drives for 2 s along its heading:

    >>> from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
    >>> kin = vehicle_kinematics('differential', VehicleGeometry(wheel_radius=0.25, track=1.0))
    >>> sim = VehicleSimulation(kin, VehicleSimulationParams(step_period=0.1, cmd_timeout=5.0))
    >>> sim.set_command([0.25, 0.0, 0.0], t=0.0)
    >>> for _ in range(20):
    ...     sim.step()
    >>> [round(float(v), 9) for v in sim.pose], [round(float(a), 9) for a in sim.wheel_angles]
    ([0.5, 0.0, 0.0], [2.0, 2.0])
    """

    def __init__(self, kinematics: VehicleKinematics, params: VehicleSimulationParams,
                 initial_pose: ArrayLike = (0.0, 0.0, 0.0), world: Optional[World] = None,
                 footprint: Optional[Footprint] = None) -> None:
        pose = np.asarray(initial_pose, dtype=np.float64)
        if pose.shape != (3,) or not np.isfinite(pose).all():
            raise ValueError(f'initial_pose must be 3 finite numbers (x, y, theta), got '
                             f'{initial_pose!r}')
        self.world = world
        self.footprint = footprint
        self._obstacles: Optional[tuple[World, Footprint]] = None
        if world is not None:
            if footprint is None:
                raise ValueError('a world needs the footprint of the vehicle (a radius or '
                                 'polygon)')
            self._obstacles = (world, footprint)
        self.in_contact = False          # the footprint touches an obstacle now
        self.contacts = 0                # contacts begun (touching after being free)
        self.time_in_contact = 0.0       # [s] steps begun in contact, times the step period
        self.contact_point = np.full(2, np.nan)    # [m] map frame, on the obstacle
        self.contact_normal = np.full(2, np.nan)   # unit, map frame, facing the vehicle
        if self._obstacles is not None:
            if footprint_distance(*self._obstacles, pose) <= 0.0:
                raise ValueError(f'initial_pose {pose.tolist()} (x, y, theta) puts the '
                                 "vehicle's footprint inside an obstacle of the world")
            self._update_contact(pose, *self._obstacles)
        self.kinematics = kinematics
        self.params = params
        m = len(kinematics.actuator_names)
        self._m = m
        self._steering = np.array(kinematics.steering_actuators, dtype=bool)
        self._lags = np.where(self._steering, params.steering_time_constant,
                              params.traction_time_constant)
        self._lagged = self._lags > 0.0       # the others take their target at once
        self._state = np.concatenate([pose, np.zeros(m), [0.0, 0.0]])
        self._step = 0
        self._command = np.zeros(3)
        self._command_time = -math.inf
        self._targets = np.zeros(m)

    # -- read-outs ------------------------------------------------------------------------
    @property
    def t(self) -> float:
        """Return the simulated time [s] of the current state."""
        return round(self._step * self.params.step_period, 12)

    @property
    def step_count(self) -> int:
        """Return the number of steps taken since the start."""
        return self._step

    @property
    def pose(self) -> NDArray[np.float64]:
        """Return the pose [m, m, rad]: x, y and θ in (−π, π], world frame."""
        x, y, theta = self._state[:3]
        return np.array([x, y, math.atan2(math.sin(theta), math.cos(theta))])

    @property
    def actuators(self) -> NDArray[np.float64]:
        """Return the actuator values (see ``kinematics.actuator_names``)."""
        return self._state[3:3 + self._m].copy()

    @property
    def twist(self) -> tuple[float, float, float]:
        """Return the ground twist in ``base_link``: vx [m/s], vy [m/s], ω [rad/s]."""
        scale = 1.0 - self.params.longitudinal_slip
        vx, vy, omega = self.kinematics.body_twist(self._state[3:3 + self._m])
        return scale * vx, scale * vy, scale * omega

    @property
    def wheel_angles(self) -> NDArray[np.float64]:
        """Return the cumulative angles (left, right) [rad] of the odometry wheels."""
        return self._state[3 + self._m:].copy()

    @property
    def wheel_rates(self) -> tuple[float, float]:
        """Return the rolling rates (left, right) [rad/s] of the odometry wheels."""
        return self.kinematics.wheel_rates(self._state[3:3 + self._m])

    def joint_positions(self) -> dict[str, float]:
        """Return the steering joints' angles [rad] (empty for unsteered vehicles)."""
        return self.kinematics.joint_positions(self._state[3:3 + self._m])

    # -- commands ---------------------------------------------------------------------------
    def set_command(self, command: ArrayLike, t: float) -> None:
        """
        Take ``command`` received at simulated time ``t`` [s].

        ``command`` is (vx [m/s], vy [m/s], ω [rad/s]) for a twist-driven vehicle and
        (v [m/s], α [rad], 0) for a steered one. Raises ValueError for a non-finite command or
        time, a speed beyond :data:`~robotica_kin.bounds.MAX_SPEED` or a rate beyond
        :data:`~robotica_kin.bounds.MAX_ANGULAR_RATE`, or actuator targets that are not finite;
        the previous command then stays (and goes stale on its own, or :meth:`stop` stops it).
        """
        array = as_command(command)
        if not math.isfinite(t):
            raise ValueError(f'command time must be finite, got {t!r}')
        bounded('speed', array[0], MAX_SPEED)
        if not self.kinematics.steered:
            bounded('lateral speed', array[1], MAX_SPEED)
            bounded('yaw rate', array[2], MAX_ANGULAR_RATE)
        targets = self.kinematics.actuator_targets(array)
        if not np.isfinite(targets).all():
            raise ValueError(f'command {array.tolist()} gives non-finite actuator targets')
        self._targets = targets
        self._command = array
        self._command_time = float(t)

    def stop(self) -> None:
        """Stop now, as a stale command does (zero speeds; the steering is kept)."""
        self._command_time = -math.inf

    def command_is_stale(self) -> bool:
        """Tell whether the newest command is older than ``cmd_timeout`` at the current time."""
        return self.t - self._command_time > self.params.cmd_timeout + 1e-12

    def _stop_targets(self) -> NDArray[np.float64]:
        stop = np.zeros(self._m)
        if self.kinematics.steered:   # keep the wheels where they are steered
            stop[self._steering] = self._state[3:3 + self._m][self._steering]
        return stop

    # -- stepping -----------------------------------------------------------------------------
    def _deriv(self, t: float, state: NDArray[np.float64], targets: NDArray[np.float64]
               ) -> NDArray[np.float64]:
        actuators = state[3:3 + self._m]
        scale = 1.0 - self.params.longitudinal_slip
        vx, vy, omega = self.kinematics.body_twist(actuators)
        c, s = math.cos(state[2]), math.sin(state[2])
        lagged = self._lagged
        rates = np.zeros(self._m)
        rates[lagged] = (targets[lagged] - actuators[lagged]) / self._lags[lagged]
        return np.concatenate([[scale * (vx * c - vy * s), scale * (vx * s + vy * c),
                                scale * omega], rates, self.kinematics.wheel_rates(actuators)])

    def step(self) -> None:
        """
        Advance one step with the current command (a stop when it is stale).

        With a world, a step that meets an obstacle ends where the footprint first touches it,
        with zero speeds (a steered vehicle keeps its steering angle).
        """
        targets = self._stop_targets() if self.command_is_stale() else self._targets
        instant = ~self._lagged
        self._state[3:3 + self._m][instant] = targets[instant]
        start = self._state.copy()
        h = self.params.step_period / self.params.rk4_substeps
        t = self.t
        for _ in range(self.params.rk4_substeps):
            self._state = rk4_step(self._deriv, t, self._state, h, targets)
            t += h
        self._step += 1
        if self._obstacles is not None:
            self._constrain(start, *self._obstacles)

    # -- contact with the world -----------------------------------------------------------
    def _constrain(self, start: NDArray[np.float64], world: World,
                   footprint: Footprint) -> None:
        """Stop the step at its first contact with the world; count the contact."""
        if self.in_contact:
            self.time_in_contact += self.params.step_period
        fraction = step_fraction(world, footprint, start[:3], self._state[:3])
        if fraction is not None:
            delta = self._state - start
            delta[2] = math.atan2(math.sin(delta[2]), math.cos(delta[2]))
            state = start + fraction * delta
            state[3:3 + self._m] = self._stop_targets()
            self._state = state
        self._update_contact(self._state[:3], world, footprint)

    def _update_contact(self, pose: NDArray[np.float64], world: World,
                        footprint: Footprint) -> None:
        touching = footprint_distance(world, footprint, pose) <= CONTACT_DISTANCE
        if touching and not self.in_contact:
            self.contacts += 1
        self.in_contact = touching
        if touching:
            self.contact_point, self.contact_normal = contact_point(world, footprint, pose)
        else:
            self.contact_point = self.contact_normal = np.full(2, np.nan)


def vehicle_simulation(parameters: Mapping[str, Any], step_period: float,
                       world: Optional[World] = None) -> VehicleSimulation:
    """
    Return the simulation the vehicle simulator node runs for its ``parameters`` (by name).

    ``parameters`` maps names of :data:`SIMULATOR_PARAMETERS` (others are ignored; missing
    ones take their defaults) to values; ``step_period`` [s] is the simulated time per step.
    ``world``: the obstacles the vehicle stops at (None: none), its footprint the
    ``footprint.*`` parameters' (:func:`~robotica_sim.simulation.contact.
    footprint_from_parameters`).

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For a value out of its range or choices (``name`` is the parameter's).
    ValueError
        For values the models refuse together, a bad footprint (naming ``footprint.radius`` or
        ``footprint.polygon``) or an initial pose whose footprint is inside an obstacle of
        the world (naming ``initial_pose``).

    Examples
    --------
    >>> vehicle_simulation({'vehicle.type': 'bicycle', 'initial_pose.x': 1.0}, 0.02).pose
    array([1., 0., 0.])

    """
    values = parameter_values(SIMULATOR_PARAMETERS, parameters)
    geometry = VehicleGeometry(**{name: values[f'vehicle.{name}']
                                  for name in GEOMETRY_PARAMETERS})
    params = VehicleSimulationParams(
        step_period=step_period, **{name: values[name] for name in (
            'rk4_substeps', 'cmd_timeout', 'traction_time_constant', 'steering_time_constant',
            'longitudinal_slip')})
    pose = [values[f'initial_pose.{axis}'] for axis in ('x', 'y', 'theta')]
    kinematics = vehicle_kinematics(values['vehicle.type'], geometry)
    if world is None:
        return VehicleSimulation(kinematics, params, pose)
    footprint = footprint_from_parameters(values['vehicle.type'], geometry,
                                          values['footprint.radius'],
                                          values['footprint.polygon'])
    return VehicleSimulation(kinematics, params, pose, world, footprint)
