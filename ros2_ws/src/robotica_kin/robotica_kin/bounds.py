"""
Physical bounds of the inputs a node takes from others: what no robot of the book can reach.

A value beyond its bound (finite but absurd, e.g. a speed of 1e308 m/s that overflows a wheel
speed to inf) is refused where it enters a core, with :func:`bounded`, like a non-finite one.
The bounds are generous: they catch corrupt or hostile values, never a real robot's.
"""
import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real

__all__ = ['MAX_ANGULAR_RATE', 'MAX_FORCE_TORQUE', 'MAX_JOINT_ACCELERATION',
           'MAX_JOINT_POSITION', 'MAX_JOINT_VELOCITY', 'MAX_JOINTS', 'MAX_LATITUDE',
           'MAX_LONGITUDE', 'MAX_POSITION', 'MAX_SPEED', 'MAX_TIME_JUMP', 'bounded',
           'bounded_array', 'StampGate']

MAX_SPEED = 100.0              # [m/s] a linear speed (a car on a motorway: 36 m/s)
MAX_POSITION = 1e7             # [m] a coordinate in a map or odometry frame (10 000 km)
MAX_ANGULAR_RATE = 100.0       # [rad/s] a yaw rate or a steering rate (16 turns per second)
MAX_JOINT_POSITION = 1e4       # [rad | m] a joint position (1600 turns of a revolute joint)
MAX_JOINT_VELOCITY = 1e3       # [rad/s | m/s] a joint velocity
MAX_JOINT_ACCELERATION = 1e6   # [rad/s² | m/s²] a joint acceleration (0 to 1e3 rad/s in 1 ms)
MAX_FORCE_TORQUE = 1e6         # [N m | N] a joint torque or force
MAX_JOINTS = 100               # joints of a robot sent in a message (the book's have at most 7;
#                                the inverse kinematics of 500 joints took 4 GB and 20 s)
MAX_LATITUDE = 90.0            # [deg] WGS-84 latitude
MAX_LONGITUDE = 180.0          # [deg] WGS-84 longitude
MAX_TIME_JUMP = 3600.0         # [s] a stamp this far from the latest accepted one is refused


def bounded(name: str, value: object, bound: float) -> float:
    """
    Return ``value`` as a float if it is finite with ``|value| <= bound``, else ValueError.

    >>> bounded('speed', 2, MAX_SPEED)
    2.0
    >>> bounded('speed', 1e308, MAX_SPEED)
    Traceback (most recent call last):
    ...
    ValueError: |speed| must be <= 100.0, got 1e+308
    """
    number = finite_real(name, value)
    if abs(number) > bound:
        raise ValueError(f'|{name}| must be <= {bound}, got {number!r}')
    return number


def bounded_array(name: str, values: ArrayLike, bound: float) -> NDArray[np.float64]:
    """
    Return ``values`` as a float64 array if every element is finite and within ``±bound``.

    >>> bounded_array('q', [0.5, -1.0], MAX_JOINT_POSITION).tolist()
    [0.5, -1.0]
    >>> bounded_array('qd', [0.0, 1e200], MAX_JOINT_VELOCITY)
    Traceback (most recent call last):
    ...
    ValueError: qd must be finite with every |value| <= 1000.0, got [0.e+000 1.e+200]
    """
    array = np.asarray(values, dtype=np.float64)
    if not (np.isfinite(array).all() and (np.abs(array) <= bound).all()):
        raise ValueError(f'{name} must be finite with every |value| <= {bound}, got {array}')
    return array


class StampGate:
    """
    Refuse stamps that jump more than ``max_jump`` [s] from the latest accepted one.

    One absurd stamp (``sec = 2**31 - 1`` amid a run at t = 12 s) is refused and changes
    nothing, so it cannot wedge the node that checks it. Only ``confirmations`` refused stamps in
    a row that agree with each other (each within ``max_jump`` after the previous one) move the
    time base there: a restarted clock, or a first stamp that was the absurd one.
    :meth:`check` then says ``'restart'``, and the caller restarts what depends on the time.

    >>> gate = StampGate()
    >>> gate.check(12.0), gate.check(12.02)
    ('accept', 'accept')
    >>> gate.check(2.0 ** 31 - 1)
    Traceback (most recent call last):
    ...
    ValueError: stamp 2147483647.0 s is more than 3600.0 s from the latest accepted, 12.02 s
    >>> gate.check(12.04)
    'accept'
    """

    def __init__(self, max_jump: float = MAX_TIME_JUMP, confirmations: int = 3) -> None:
        self.max_jump = max_jump
        self.confirmations = confirmations
        self.latest: float | None = None
        self._jumped: list[float] = []

    def check(self, t: float) -> str:
        """Return ``'accept'`` or ``'restart'`` for the stamp ``t`` [s], or raise ValueError."""
        t = finite_real('stamp', t)
        if self.latest is None or abs(t - self.latest) <= self.max_jump:
            self.latest, self._jumped = t, []
            return 'accept'
        agrees = self._jumped and 0.0 < t - self._jumped[-1] <= self.max_jump
        self._jumped = self._jumped + [t] if agrees else [t]
        if len(self._jumped) < self.confirmations:
            raise ValueError(f'stamp {t!r} s is more than {self.max_jump} s from the latest '
                             f'accepted, {self.latest!r} s')
        self.latest, self._jumped = t, []
        return 'restart'
