"""
Kinematic simulation of a differential-drive robot at a fixed step (the simulator's core).

The robot follows the differential-drive model of book §4.7.4 (4.109)-(4.114), in REP-103 form,
integrated with classic RK4 over each step with the command held constant (zero-order hold).
Commands are body twists (v [m/s], w [rad/s]) turned into wheel speeds by (4.111)-(4.112); a
command older than ``cmd_timeout`` brakes the robot (stale-command safety of ros2_controllers'
``cmd_vel_timeout``).
"""
from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.integrators import rk4_step
from robotica_kin.mobile.differential_drive import (
    differential_drive_deriv, DifferentialDriveParams, twist_to_wheel_speeds,
    wheel_speeds_to_twist)


@dataclass(frozen=True)
class SimulationParams:
    """Fixed-step integration settings."""

    step_period: float = 0.02   # [s] simulated time per step (publishing period)
    rk4_substeps: int = 1       # RK4 steps per simulation step
    cmd_timeout: float = 0.5    # [s] a command older than this (simulated time) brakes

    def __post_init__(self) -> None:
        if not (math.isfinite(self.step_period) and self.step_period > 0.0):
            raise ValueError(f'step_period must be > 0 s, got {self.step_period!r}')
        if self.rk4_substeps < 1:
            raise ValueError(f'rk4_substeps must be >= 1, got {self.rk4_substeps!r}')
        if not (math.isfinite(self.cmd_timeout) and self.cmd_timeout > 0.0):
            raise ValueError(f'cmd_timeout must be > 0 s, got {self.cmd_timeout!r}')


class DiffDriveSimulation:
    """
    State and stepping of one simulated differential-drive robot.

    The state is ``[x, y, theta, wheel_angle_left, wheel_angle_right]`` [m, m, rad, rad, rad],
    world frame, REP-103. Time starts at 0 and advances by ``step_period`` per :meth:`step`.

    Driving at 0.5 m/s with a command that goes stale after 0.5 s: six steps of 0.1 s move the
    robot, then it brakes.

    >>> robot = DifferentialDriveParams(wheel_radius=0.1, wheel_separation=0.4)
    >>> sim = DiffDriveSimulation(robot, SimulationParams(step_period=0.1, cmd_timeout=0.5))
    >>> sim.set_command(0.5, 0.0, t=0.0)
    >>> for _ in range(10):
    ...     sim.step()
    >>> [round(float(v), 9) for v in sim.pose]
    [0.3, 0.0, 0.0]
    """

    def __init__(self, robot: DifferentialDriveParams, params: SimulationParams,
                 initial_pose: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        self._robot = robot
        self._params = params
        pose = np.asarray(initial_pose, dtype=float)
        if pose.shape != (3,) or not np.all(np.isfinite(pose)):
            raise ValueError(f'initial_pose must be 3 finite numbers (x, y, theta), got {pose}')
        self._state = np.concatenate([pose, [0.0, 0.0]])
        self._step = 0
        self._wheel_speeds = np.zeros(2)
        self._command = (0.0, 0.0)
        self._command_time = -math.inf

    @property
    def t(self) -> float:
        """Return the simulated time [s] of the current state."""
        return self._step * self._params.step_period

    @property
    def step_count(self) -> int:
        """Return the number of steps taken since the start."""
        return self._step

    @property
    def pose(self) -> NDArray[np.float64]:
        """Return the pose ``(x, y, theta)`` [m, m, rad], world frame, theta in (-pi, pi]."""
        x, y, theta = self._state[:3]
        return np.array([x, y, math.atan2(math.sin(theta), math.cos(theta))])

    @property
    def wheel_angles(self) -> NDArray[np.float64]:
        """Return the cumulative wheel angles (left, right) [rad]."""
        return self._state[3:].copy()

    @property
    def wheel_speeds(self) -> NDArray[np.float64]:
        """Return the wheel speeds (left, right) [rad/s] applied during the last step."""
        return self._wheel_speeds.copy()

    @property
    def twist(self) -> tuple[float, float]:
        """Return the body twist of the last step: v [m/s] and w [rad/s], base frame."""
        return wheel_speeds_to_twist(self._robot, *self._wheel_speeds)

    def set_command(self, v: float, w: float, t: float) -> None:
        """
        Take the command (v [m/s], w [rad/s]) received at simulated time ``t`` [s].

        Raises ValueError for a non-finite command (the caller keeps the safe stop).
        """
        if not (math.isfinite(v) and math.isfinite(w) and math.isfinite(t)):
            raise ValueError(f'command and its time must be finite, got v={v!r}, w={w!r}, '
                             f't={t!r}')
        self._command = (float(v), float(w))
        self._command_time = float(t)

    def command_is_stale(self) -> bool:
        """Tell whether the newest command is older than ``cmd_timeout`` at the current time."""
        return self.t - self._command_time > self._params.cmd_timeout

    def step(self) -> None:
        """Advance one step with the current command (zero wheel speeds when it is stale)."""
        if self.command_is_stale():
            self._wheel_speeds = np.zeros(2)
        else:
            self._wheel_speeds = np.array(twist_to_wheel_speeds(self._robot, *self._command))
        h = self._params.step_period / self._params.rk4_substeps
        t = self.t
        for _ in range(self._params.rk4_substeps):
            self._state = rk4_step(differential_drive_deriv, t, self._state, h,
                                   self._wheel_speeds, self._robot)
            t += h
        self._step += 1
