"""
Every wheeled configuration of the book and the slides behind one interface, for the simulator.

A vehicle is driven through its *actuators* (wheel speeds, a drive speed, a steering angle). Each
configuration maps a command to actuator targets (its inverse model) and actuator values to the
body twist of its guide point (its direct model), using the models of this package:

=============== ===================== =============================== ==========================
type            command               actuators                       model
=============== ===================== =============================== ==========================
differential    twist (v, ω)          ω_left, ω_right [rad/s]         (4.109)-(4.112)
synchronous     twist (v, ω)          v [m/s], steering rate [rad/s]  (4.102), fig. 4.17a
skid_steer      twist (v, ω)          ω_left, ω_right [rad/s]         ICR slip model
omni_three      twist (vx, vy, ω)     three wheel speeds [rad/s]      three wheels at 120°
mecanum         twist (vx, vy, ω)     four wheel speeds [rad/s]       FL, FR, RL, RR, 45° rollers
tricycle        steering (v, α)       v [m/s], α [rad]                (4.115)-(4.118)
bicycle         steering (v, α)       v [m/s], α [rad]                (4.121)
ackermann       steering (v, α)       v [m/s], α [rad] (equivalent)   (4.121), cot θo − cot θi
=============== ===================== =============================== ==========================

Twists are in ``base_link`` (x forward, y left, REP-103) at the guide point: the axle midpoint of
a differential or skid-steer base, the rear-axle midpoint of a steered one (book §4.7.4), the
centre of a synchronous, omnidirectional or mecanum base. Steered vehicles take the guide point's
speed v and the (equivalent) front steering angle α, as ``robotica_msgs/VehicleCommand``.

Every configuration also names its *odometry wheels*: the left and right wheels of the guide
point's axle (the drive wheels of a differential or skid-steer base, the passive rear wheels of a
steered one), whose encoders feed the dead reckoning of §4.7.5. Their joint names,
:attr:`VehicleKinematics.odometry_wheel_joints`, are the one naming that the simulator's
``joint_states`` and the vehicle's URDF (:mod:`robotica_kin.urdf`) share: ``left_wheel_joint``
and ``right_wheel_joint`` where those wheels are wheels of the vehicle, else
``left_odometry_wheel_joint`` and ``right_odometry_wheel_joint`` (:data:`ODOMETRY_WHEEL_JOINTS`):
passive measuring wheels at (0, ±b/2) under the guide point (a bicycle has one rear wheel, and
a mecanum, omnidirectional or synchronous base has none on that axle).
"""

from abc import ABC, abstractmethod
from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.mobile.ackermann import ackermann_left_right, AckermannParams
from robotica_kin.mobile.differential_drive import (
    DifferentialDriveParams, twist_to_wheel_speeds, wheel_speeds_to_twist)
from robotica_kin.mobile.omnidirectional import (
    mecanum_direct, mecanum_inverse, MecanumParams, omni_three_direct, omni_three_inverse,
    OmniThreeParams)
from robotica_kin.mobile.skid_steer import skid_steer_direct, skid_steer_inverse, SkidSteerParams
from robotica_kin.mobile.unicycle import _vector
from robotica_kin.parameter_specs import ParameterSpec
from robotica_kin.types import Vector

__all__ = ['GEOMETRY_PARAMETERS', 'ODOMETRY_WHEEL_JOINTS', 'POSE_PARAMETERS', 'STEERED_TYPES',
           'VEHICLE_TYPES', 'VehicleGeometry', 'VehicleKinematics', 'as_command',
           'vehicle_kinematics']

VEHICLE_TYPES = ('differential', 'synchronous', 'skid_steer', 'omni_three', 'mecanum',
                 'tricycle', 'bicycle', 'ackermann')
STEERED_TYPES = ('tricycle', 'bicycle', 'ackermann')
"""Types commanded by (v, α) (``VehicleCommand``); the others take a twist (``cmd_vel``)."""
ODOMETRY_WHEEL_JOINTS = ('left_odometry_wheel_joint', 'right_odometry_wheel_joint')
"""The odometry wheels' joint names of a vehicle with no wheels of its own on the guide axle."""


@dataclass(frozen=True)
class VehicleGeometry:
    """
    Dimensions of a vehicle [m, rad]; each configuration uses the ones it needs.

    >>> VehicleGeometry(wheel_radius=0.25, track=1.0).track   # Ejemplo 4.9
    1.0
    """

    wheel_radius: float = 0.1          # c [m]
    track: float = 0.4                 # b [m] between the left and right wheels of an axle
    wheelbase: float = 0.5             # l [m] rear axle to front axle (steered vehicles)
    base_radius: float = 0.2           # [m] centre to wheel (omni_three)
    half_length: float = 0.2           # [m] centre to axle (mecanum)
    max_steering_angle: float = 1.2    # [rad] |α| limit of steered vehicles
    icr_scale: float = 1.0             # skid steer: effective track / track, >= 1

    def __post_init__(self) -> None:
        for name in ('wheel_radius', 'track', 'wheelbase', 'base_radius', 'half_length',
                     'max_steering_angle'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if not self.max_steering_angle < math.pi / 2.0:
            raise ValueError('max_steering_angle must be < pi/2 rad, got '
                             f'{self.max_steering_angle!r}')
        if not (math.isfinite(self.icr_scale) and self.icr_scale >= 1.0):
            raise ValueError(f'icr_scale must be finite and >= 1, got {self.icr_scale!r}')


GEOMETRY_PARAMETERS: dict[str, ParameterSpec] = {
    'wheel_radius': ParameterSpec(0.1, 'Wheel radius c [m], book (4.109)', 1e-3, 10.0),
    'track': ParameterSpec(0.4, 'Track b between the left and right wheels of an axle [m], '
                           'book (4.110)', 1e-3, 100.0),
    'wheelbase': ParameterSpec(0.5, 'Wheelbase l, rear to front axle [m] (steered vehicles), '
                               'book (4.117)', 1e-3, 100.0),
    'base_radius': ParameterSpec(0.2, 'Centre-to-wheel distance [m] (omni_three)', 1e-3, 100.0),
    'half_length': ParameterSpec(0.2, 'Centre-to-axle distance [m] (mecanum)', 1e-3, 100.0),
    'max_steering_angle': ParameterSpec(1.2, 'Steering angle limit |alpha| [rad] (steered '
                                        'vehicles)', 1e-3, 1.57),
    'icr_scale': ParameterSpec(1.0, 'Skid steer: effective track / track (>= 1; 1 = no lateral '
                               'skid)', 1.0, 10.0),
}
"""The fields of :class:`VehicleGeometry` as a simulator's parameters: what a simulated vehicle
may be (its own checks allow any size; these bound the simulated ones)."""
POSE_PARAMETERS: dict[str, ParameterSpec] = {
    f'initial_pose.{axis}': ParameterSpec(0.0, description, -1e6, 1e6)
    for axis, description in (('x', 'Initial x [m]'), ('y', 'Initial y [m]'),
                              ('theta', 'Initial heading [rad], REP-103 (from the x axis)'))}
"""The initial pose of a vehicle as parameters (the simulator's, the odometry's)."""


class VehicleKinematics(ABC):
    """
    One configuration: command → actuator targets, actuators → body twist and wheel rates.

    Attributes
    ----------
    name : str
        One of :data:`VEHICLE_TYPES`.
    steered : bool
        True when commanded by (v, α), False for a twist.
    actuator_names : tuple of str
        Names of the actuators, in order.
    steering_actuators : tuple of bool
        Which actuators are steering angles (their lag is the steering lag, the others' the
        traction lag).
    odometry_wheel_joints : tuple of str
        Joint names (left, right) of the odometry wheels, in ``joint_states`` and in the URDF.

    """

    name: str
    steered = False
    actuator_names: tuple[str, ...]
    steering_actuators: tuple[bool, ...]
    odometry_wheel_joints: tuple[str, str] = ('left_wheel_joint', 'right_wheel_joint')

    def __init__(self, geometry: VehicleGeometry) -> None:
        self.geometry = geometry

    @abstractmethod
    def actuator_targets(self, command: Vector) -> Vector:
        """
        Return the actuator values that realise ``command`` (the inverse model).

        ``command`` is (vx [m/s], vy [m/s], ω [rad/s]) for a twist-driven vehicle (vy is ignored
        by the non-holonomic ones) and (v [m/s], α [rad], 0) for a steered one.
        """

    @abstractmethod
    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        """Return (vx [m/s], vy [m/s], ω [rad/s]) of the guide point, ``base_link`` (direct)."""

    def wheel_rates(self, actuators: Vector) -> tuple[float, float]:
        """
        Return the rates (left, right) [rad/s] of the odometry wheels.

        Default: wheels rolling without slip at y = ±b/2 on the guide point's axle,
        ω = (vx ∓ ω b/2) / c (4.111)-(4.112).
        """
        vx, _, omega = self.body_twist(actuators)
        half_b, c = 0.5 * self.geometry.track, self.geometry.wheel_radius
        return (vx - half_b * omega) / c, (vx + half_b * omega) / c

    def joint_positions(self, actuators: Vector) -> dict[str, float]:
        """Return the steering joints' angles [rad] to publish (none by default)."""
        return {}


class _Differential(VehicleKinematics):
    name = 'differential'
    actuator_names = ('left_wheel_speed', 'right_wheel_speed')
    steering_actuators = (False, False)

    def __init__(self, geometry: VehicleGeometry) -> None:
        super().__init__(geometry)
        self._params = DifferentialDriveParams(geometry.wheel_radius, geometry.track)

    def actuator_targets(self, command: Vector) -> Vector:
        return np.array(twist_to_wheel_speeds(self._params, command[0], command[2]))

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        v, omega = wheel_speeds_to_twist(self._params, actuators[0], actuators[1])
        return v, 0.0, omega

    def wheel_rates(self, actuators: Vector) -> tuple[float, float]:
        return float(actuators[0]), float(actuators[1])


class _SkidSteer(_Differential):
    name = 'skid_steer'

    def __init__(self, geometry: VehicleGeometry) -> None:
        super().__init__(geometry)
        self._skid = SkidSteerParams(geometry.wheel_radius, geometry.track,
                                     icr_scale=geometry.icr_scale)

    def actuator_targets(self, command: Vector) -> Vector:
        return np.array(skid_steer_inverse(self._skid, command[0], command[2]))

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        v, omega = skid_steer_direct(self._skid, actuators[0], actuators[1])
        return v, 0.0, omega


class _Synchronous(VehicleKinematics):
    name = 'synchronous'
    actuator_names = ('drive_speed', 'steering_rate')
    steering_actuators = (False, True)
    odometry_wheel_joints = ODOMETRY_WHEEL_JOINTS

    def actuator_targets(self, command: Vector) -> Vector:
        return np.array([command[0], command[2]])

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        return float(actuators[0]), 0.0, float(actuators[1])

    def wheel_rates(self, actuators: Vector) -> tuple[float, float]:
        rate = float(actuators[0]) / self.geometry.wheel_radius   # every wheel drives at v/c
        return rate, rate


class _OmniThree(VehicleKinematics):
    name = 'omni_three'
    actuator_names = ('wheel_0_speed', 'wheel_1_speed', 'wheel_2_speed')
    steering_actuators = (False, False, False)
    odometry_wheel_joints = ODOMETRY_WHEEL_JOINTS

    def __init__(self, geometry: VehicleGeometry) -> None:
        super().__init__(geometry)
        self._params = OmniThreeParams(geometry.wheel_radius, geometry.base_radius)

    def actuator_targets(self, command: Vector) -> Vector:
        return np.asarray(omni_three_inverse(self._params, command[0], command[1], command[2]),
                          dtype=np.float64)

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        vx, vy, omega = omni_three_direct(self._params, actuators)
        return float(vx), float(vy), float(omega)


class _Mecanum(VehicleKinematics):
    name = 'mecanum'
    actuator_names = ('front_left_speed', 'front_right_speed', 'rear_left_speed',
                      'rear_right_speed')
    steering_actuators = (False, False, False, False)
    odometry_wheel_joints = ODOMETRY_WHEEL_JOINTS

    def __init__(self, geometry: VehicleGeometry) -> None:
        super().__init__(geometry)
        self._params = MecanumParams(geometry.wheel_radius, geometry.half_length,
                                     0.5 * geometry.track)

    def actuator_targets(self, command: Vector) -> Vector:
        return np.asarray(mecanum_inverse(self._params, command[0], command[1], command[2]),
                          dtype=np.float64)

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        vx, vy, omega = mecanum_direct(self._params, actuators)
        return float(vx), float(vy), float(omega)


class _Bicycle(VehicleKinematics):
    """The bicycle model (4.121): x' = v cos θ, y' = v sin θ, θ' = v tan α / l (REP-103)."""

    name = 'bicycle'
    steered = True
    actuator_names = ('speed', 'steering_angle')
    steering_actuators = (False, True)
    odometry_wheel_joints = ODOMETRY_WHEEL_JOINTS   # one rear wheel, at the guide point

    def actuator_targets(self, command: Vector) -> Vector:
        limit = self.geometry.max_steering_angle
        return np.array([command[0], min(max(command[1], -limit), limit)])

    def body_twist(self, actuators: Vector) -> tuple[float, float, float]:
        v, alpha = float(actuators[0]), float(actuators[1])
        return v, 0.0, v * math.tan(alpha) / self.geometry.wheelbase

    def joint_positions(self, actuators: Vector) -> dict[str, float]:
        return {'steering_joint': float(actuators[1])}


class _Tricycle(_Bicycle):
    """The classic tricycle (4.115)-(4.118): the front wheel drives at v_t = v / cos α."""

    name = 'tricycle'
    odometry_wheel_joints = VehicleKinematics.odometry_wheel_joints


class _Ackermann(_Bicycle):
    """Ackermann steering: the bicycle model of the equivalent angle, with both front angles."""

    name = 'ackermann'
    odometry_wheel_joints = VehicleKinematics.odometry_wheel_joints

    def __init__(self, geometry: VehicleGeometry) -> None:
        super().__init__(geometry)
        self._params = AckermannParams(geometry.wheelbase, geometry.track, geometry.wheel_radius)

    def joint_positions(self, actuators: Vector) -> dict[str, float]:
        left, right = ackermann_left_right(self._params, float(actuators[1]))
        return {'front_left_steering_joint': float(left),
                'front_right_steering_joint': float(right)}


_CLASSES: dict[str, type[VehicleKinematics]] = {
    cls.name: cls for cls in (_Differential, _SkidSteer, _Synchronous, _OmniThree, _Mecanum,
                              _Bicycle, _Tricycle, _Ackermann)}


def vehicle_kinematics(vehicle_type: str, geometry: VehicleGeometry | None = None
                       ) -> VehicleKinematics:
    """
    Return the kinematics of ``vehicle_type`` (one of :data:`VEHICLE_TYPES`).

    Raises
    ------
    ValueError
        For an unknown type (the message lists the known ones).

    Examples
    --------
    >>> kin = vehicle_kinematics('differential', VehicleGeometry(wheel_radius=0.25, track=1.0))
    >>> kin.body_twist(np.array([1.0, 1.2]))     # Ejemplo 4.9 (b)
    (0.275, 0.0, 0.05)

    """
    if vehicle_type not in _CLASSES:
        raise ValueError(f'unknown vehicle type {vehicle_type!r}; known: {VEHICLE_TYPES}')
    return _CLASSES[vehicle_type](VehicleGeometry() if geometry is None else geometry)


def as_command(command: ArrayLike) -> Vector:
    """Return ``command`` as a finite float64 (3,) vector, or raise ValueError."""
    return _vector(command, 3, 'command')
