"""
Gain scheduling of decoupled PID control, book §8.4.1 (catalogue §6.4).

The coupling torques a joint's PID sees change with the configuration and the payload (§8.2,
(8.7)-(8.10); Ej. 8.4 and 8.5: gains tuned for the empty gripper fail after a 2 kg pick-up).
Gain scheduling keeps a table of PID gains (3n parameters per entry: K_p, K_v, K_i per joint)
indexed by the region of each joint variable (breakpoints per joint) and of the payload, and
uses the entry of the region the robot is in. The regions of one axis are
``(-inf, b_1), [b_1, b_2), …, [b_m, inf)``: a value on a breakpoint belongs to the region above.

The PID is :class:`~.pid.DecoupledPID` itself, whose gains are swapped at each step: the
integral and the derivative filter carry over a change of region (no reset, no bump in ∫e).
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import itertools
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real

from .law import JointControlLaw, JointReference, JointState, per_joint
from .pid import DecoupledPID, PIDGains

__all__ = ['GainSchedule', 'GainScheduledPID']


def _breakpoints(name: str, values: ArrayLike) -> NDArray[np.float64]:
    """Return ``values`` as a read-only strictly increasing finite vector, or raise ValueError."""
    try:
        array = np.array(values, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as err:
        raise ValueError(f'{name} must be a sequence of numbers, got {values!r}') from err
    if np.ndim(values) > 1 or not np.isfinite(array).all() or (np.diff(array) <= 0.0).any():
        raise ValueError(f'{name} must be finite and strictly increasing, got {values!r}')
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class GainSchedule:
    """
    The table of §8.4.1: PID gains by region of each joint variable and of the payload.

    Attributes
    ----------
    joint_breakpoints : sequence of array_like
        One sequence per joint (n of them) of strictly increasing values [rad | m]; an empty one
        leaves that joint out of the schedule (one region).
    gains : mapping
        ``{(r_1, …, r_n, r_payload): PIDGains}``, one entry for every combination of regions
        (``r_j`` from 0 to ``len(joint_breakpoints[j])``); gains of shape () or (n,).
    payload_breakpoints : array_like
        Strictly increasing payload masses [kg]; empty (default): one payload region.

    Raises
    ------
    ValueError
        For breakpoints not strictly increasing, a missing, extra or malformed entry, or gains
        whose size is not n.

    Examples
    --------
    Gains that change with the payload only (one joint region each), as Ej. 8.4 calls for:

    >>> light, heavy = PIDGains(kp=25.0, kv=10.0), PIDGains(kp=75.0, kv=30.0)
    >>> schedule = GainSchedule([(), ()], {(0, 0, 0): light, (0, 0, 1): heavy}, [1.0])
    >>> schedule.region([0.3, -0.2], 2.0)
    (0, 0, 1)

    """

    joint_breakpoints: Sequence[ArrayLike]
    gains: Mapping[tuple[int, ...], PIDGains]
    payload_breakpoints: ArrayLike = ()

    def __post_init__(self) -> None:
        if isinstance(self.joint_breakpoints, (str, bytes)) or not len(self.joint_breakpoints):
            raise ValueError('joint_breakpoints must hold one sequence per joint, got '
                             f'{self.joint_breakpoints!r}')
        joints = tuple(_breakpoints(f'joint_breakpoints[{j}]', values)
                       for j, values in enumerate(self.joint_breakpoints))
        payload = _breakpoints('payload_breakpoints', self.payload_breakpoints)
        object.__setattr__(self, 'joint_breakpoints', joints)
        object.__setattr__(self, 'payload_breakpoints', payload)
        regions = set(itertools.product(*(range(b.size + 1) for b in (*joints, payload))))
        if not isinstance(self.gains, Mapping):
            raise ValueError('gains must be a mapping {region: PIDGains}, got '
                             f'{type(self.gains).__name__}')
        if set(self.gains) != regions:
            raise ValueError(f'gains must have one entry per region {sorted(regions)}, got '
                             f'{sorted(self.gains, key=repr)}')
        for region, gains in self.gains.items():
            if not isinstance(gains, PIDGains):
                raise ValueError(f'gains[{region}] must be PIDGains, got {type(gains).__name__}')
            for name in ('kp', 'kv', 'ki', 'tau_max', 'integral_max',
                         'derivative_time_constant'):
                per_joint(f'gains[{region}].{name}', getattr(gains, name), len(joints))
        object.__setattr__(self, 'gains', MappingProxyType(dict(self.gains)))

    @property
    def n(self) -> int:
        """Return the number of joints."""
        return len(self.joint_breakpoints)

    def region(self, q: ArrayLike, payload: float) -> tuple[int, ...]:
        """
        Return the key ``(r_1, …, r_n, r_payload)`` of the region of q [rad | m] and payload [kg].

        Raises ValueError for a q of another size or not finite.
        """
        x = np.asarray(q, dtype=np.float64)
        if x.shape != (self.n,) or not np.isfinite(x).all():
            raise ValueError(f'q must be finite with shape ({self.n},), got {q!r}')
        mass = finite_real('payload', payload)
        joints = (int(np.searchsorted(b, v, side='right'))
                  for b, v in zip(self.joint_breakpoints, x))
        return (*joints, int(np.searchsorted(self.payload_breakpoints, mass, side='right')))


class GainScheduledPID(JointControlLaw):
    """
    Decoupled PID (8.10) with the gains of the :class:`GainSchedule` region the robot is in.

    Parameters
    ----------
    schedule : GainSchedule
        The table.
    payload : float
        The payload [kg] the robot carries now, >= 0; change it with :attr:`payload` (e.g. when
        the gripper closes on a known object).

    Examples
    --------
    >>> from robotica_ctrl.joint_control.law import JointReference, JointState
    >>> schedule = GainSchedule([[0.5]], {(0, 0): PIDGains(kp=10.0), (1, 0): PIDGains(kp=40.0)})
    >>> law = GainScheduledPID(schedule)
    >>> law.update(JointReference([1.0]), JointState([0.4], [0.0]), 0.01)   # 10 · 0.6
    array([6.])
    >>> law.update(JointReference([1.0]), JointState([0.5], [0.0]), 0.01)   # 40 · 0.5
    array([20.])

    """

    def __init__(self, schedule: GainSchedule, payload: float = 0.0) -> None:
        if not isinstance(schedule, GainSchedule):
            raise ValueError(f'schedule must be a GainSchedule, got {type(schedule).__name__}')
        self.schedule = schedule
        self.payload = payload
        self._pid = DecoupledPID(next(iter(schedule.gains.values())))
        self._region: tuple[int, ...] | None = None

    @property
    def payload(self) -> float:
        """Return the payload [kg] the gains are scheduled on."""
        return self._payload

    @payload.setter
    def payload(self, mass: float) -> None:
        """Set the payload [kg], finite and >= 0 (ValueError otherwise)."""
        value = finite_real('payload', mass)
        if value < 0.0:
            raise ValueError(f'payload must be >= 0 kg, got {mass!r}')
        self._payload = value

    @property
    def region(self) -> tuple[int, ...] | None:
        """Return the region key of the last update (None before the first one)."""
        return self._region

    @property
    def gains(self) -> PIDGains:
        """Return the PID gains in use (those of the last update's region)."""
        return self._pid.gains

    @property
    def integral(self) -> NDArray[np.float64] | None:
        """Return a copy of the PID's integral of the error (n,) [rad s], None after reset."""
        return self._pid.integral

    def reset(self) -> None:
        """Clear the PID's integral and filter; forget the region."""
        self._pid.reset()
        self._region = None

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return the PID torque (n,) [N m] with the gains of the state's region and the payload.

        Raises
        ------
        ValueError
            For ``dt <= 0``, NaN, or a number of joints other than the schedule's.

        """
        n = self.check_inputs(reference, state, dt)
        if n != self.schedule.n:
            raise ValueError(f'the schedule has {self.schedule.n} joints, got {n}')
        self._region = self.schedule.region(state.q, self._payload)
        self._pid.gains = self.schedule.gains[self._region]
        return self._pid.update(reference, state, dt)
