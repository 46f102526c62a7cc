"""
Speed of the manipulator dynamics against the bare Pinocchio calls they wrap, in one run.

Issue 20 asks each single-call function of :mod:`robotica_kin.dynamics` (``rne``, ``inertia``,
``gravity``, ``coriolis``, ``coriolis_matrix``, ``friction`` and fdyn's cost per evaluation)
to stay within 2× of raw Pinocchio, checked inputs included. For each, on one robot (the
PUMA 560 by default), its arm and one ``data`` kept, m configurations:

- **robotica**: the function, with its checks;
- **raw**: the bare call it wraps on the same model and ``data`` (``pin.rnea``, ``pin.crba``,
  ``pin.computeGeneralizedGravity``, ``pin.nonLinearEffects`` on the gravity-free model,
  ``pin.computeCoriolisMatrix``); for ``friction``, which Pinocchio does not compute, the
  arm's friction law evaluated without checks (NumPy);
- **floor**: the least a checked Python wrapper can cost: one Python call that clears each
  vector by the norm of its values (``math.hypot(*x.tolist()) <= bound``, as the fast route
  does) and then makes the bare call;
- **fdyn**: ``fdyn`` over ``FDYN_DURATION`` s from rest without torque, against SciPy's same
  ``RK45`` on a bare right-hand side ``[q', aba(q, q', 0)]`` (the same steps): the time per
  evaluation of the right-hand side, SciPy's share included on both sides.

Timing: the CPU time of the process (``time.process_time``) for one block of calls over the m
configurations, the routes interleaved, the best of ``repeats`` blocks; the loop over the
configurations is the same on every route. CPU time, not wall-clock time: other people's
processes on a shared machine then lengthen a block only through the caches.
"""

from dataclasses import dataclass
import math
import time
import timeit
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray
import pinocchio as pin
from robotica_kin.bounds import MAX_JOINT_ACCELERATION, MAX_JOINT_POSITION, MAX_JOINT_VELOCITY
from robotica_kin.dynamics import (coriolis, coriolis_matrix, fdyn, friction, gravity, inertia,
                                   rne)
from robotica_kin.pinocchio_model import PinocchioArm
from scipy.integrate import solve_ivp

__all__ = ['DYNAMICS_FUNCTIONS', 'DynamicsTiming', 'FDYN_DURATION', 'time_dynamics']

FDYN_DURATION = 1.0   # [s] simulated by each fdyn run
DYNAMICS_FUNCTIONS = ('rne', 'inertia', 'gravity', 'coriolis', 'coriolis_matrix', 'friction',
                      'fdyn')


@dataclass(frozen=True)
class DynamicsTiming:
    """One function's time per call [µs]: robotica's, the bare call's and the Python floor."""

    function: str            # rne … friction, or fdyn (per evaluation of the right-hand side)
    raw_name: str            # the bare call, e.g. 'pin.rnea'
    robotica_us: float
    raw_us: float
    floor_us: float | None   # None for fdyn (its bare right-hand side is the floor)
    count: int               # calls per block (configurations, or fdyn's evaluations)
    blocks: int              # blocks timed per route, the best kept

    @property
    def ratio(self) -> float:
        """Return robotica's time over the bare call's."""
        return self.robotica_us / self.raw_us

    @property
    def floor_ratio(self) -> float | None:
        """Return the floor's time over the bare call's."""
        return None if self.floor_us is None else self.floor_us / self.raw_us


# Per function: robotica's call, the bare call and the floor as statements on one configuration
# (x, v, a) of the names of _namespace, and the bare call's name.
_STATEMENTS = {
    'rne': ('rne(arm, x, v, a, data=data)', 'pin.rnea(model, data, x, v, a)',
            'floor_rne(x, v, a)', 'pin.rnea'),
    'inertia': ('inertia(arm, x, data=data)', 'pin.crba(model, data, x)', 'floor_crba(x)',
                'pin.crba'),
    'gravity': ('gravity(arm, x, data=data)', 'pin.computeGeneralizedGravity(model, data, x)',
                'floor_gravity(x)', 'pin.computeGeneralizedGravity'),
    'coriolis': ('coriolis(arm, x, v, data=data)', 'pin.nonLinearEffects(free, data, x, v)',
                 'floor_coriolis(x, v)', 'pin.nonLinearEffects (no gravity)'),
    'coriolis_matrix': ('coriolis_matrix(arm, x, v, data=data)',
                        'pin.computeCoriolisMatrix(model, data, x, v)', 'floor_matrix(x, v)',
                        'pin.computeCoriolisMatrix'),
    'friction': ('friction(arm, v)', 'law(v)', 'floor_friction(v)',
                 'the friction law, unchecked (NumPy)'),
}


def _namespace(arm: PinocchioArm, data: Any, configs: list[Any]) -> dict[str, Any]:
    """Return the names the statements use, the floor wrappers among them."""
    model, free, law = arm.model, arm.model_without_gravity, arm.friction
    hypot = math.hypot
    q_max, qd_max, qdd_max = MAX_JOINT_POSITION, MAX_JOINT_VELOCITY, MAX_JOINT_ACCELERATION

    def floor_q(algorithm: Callable[..., object], on: Any) -> Callable[[Any], object]:
        def call(x: Any) -> object:
            return hypot(*x.tolist()) <= q_max and algorithm(on, data, x)
        return call

    def floor_q_qd(algorithm: Callable[..., object], on: Any) -> Callable[[Any, Any], object]:
        def call(x: Any, v: Any) -> object:
            return (hypot(*x.tolist()) <= q_max and hypot(*v.tolist()) <= qd_max
                    and algorithm(on, data, x, v))
        return call

    def floor_rne(x: Any, v: Any, a: Any) -> object:
        return (hypot(*x.tolist()) <= q_max and hypot(*v.tolist()) <= qd_max
                and hypot(*a.tolist()) <= qdd_max and pin.rnea(model, data, x, v, a))

    def floor_friction(v: Any) -> object:
        return hypot(*v.tolist()) <= qd_max and law(v)

    return {'arm': arm, 'data': data, 'model': model, 'free': free, 'law': law, 'pin': pin,
            'configs': configs, 'rne': rne, 'inertia': inertia, 'gravity': gravity,
            'coriolis': coriolis, 'coriolis_matrix': coriolis_matrix, 'friction': friction,
            'floor_rne': floor_rne, 'floor_crba': floor_q(pin.crba, model),
            'floor_gravity': floor_q(pin.computeGeneralizedGravity, model),
            'floor_coriolis': floor_q_qd(pin.nonLinearEffects, free),
            'floor_matrix': floor_q_qd(pin.computeCoriolisMatrix, model),
            'floor_friction': floor_friction}


def _cpu_time(block: Callable[[], object]) -> float:
    """Return the CPU time of one call of ``block`` [s]."""
    start = time.process_time()
    block()
    return time.process_time() - start


def _fdyn_timing(arm: PinocchioArm, q0: NDArray[np.float64], repeats: int) -> DynamicsTiming:
    """Time fdyn against SciPy's RK45 on a bare ABA right-hand side, per evaluation."""
    model, data, n = arm.model, arm.model.createData(), arm.robot.n
    no_torque = np.zeros(n)

    def bare(t: float, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate((x[n:], pin.aba(model, data, x[:n], x[n:], no_torque)))

    start = np.concatenate((q0, np.zeros(n)))
    # fdyn's own settings (RK45, rtol 1e-8, atol 1e-10): the same steps on the same equations.
    solution = solve_ivp(bare, (0.0, FDYN_DURATION), start, method='RK45', rtol=1e-8,
                         atol=1e-10)
    steps = len(fdyn(arm, 0.0, FDYN_DURATION, None, q0, np.zeros(n)).t)
    if steps != len(solution.t):
        raise RuntimeError(f'fdyn took {steps} steps, the bare RK45 {len(solution.t)}')
    ours, raw = np.inf, np.inf
    for _ in range(repeats):   # fdyn's runs are long: a third of the blocks of the others
        ours = min(ours, _cpu_time(lambda: fdyn(arm, 0.0, FDYN_DURATION, None, q0, np.zeros(n))))
        raw = min(raw, _cpu_time(lambda: solve_ivp(bare, (0.0, FDYN_DURATION), start,
                                                   method='RK45', rtol=1e-8, atol=1e-10)))
    per = 1e6 / solution.nfev
    return DynamicsTiming('fdyn', 'pin.aba in the same RK45', ours * per, raw * per, None,
                          int(solution.nfev), repeats)


def time_dynamics(arm: PinocchioArm, q: NDArray[np.float64], qd: NDArray[np.float64],
                  qdd: NDArray[np.float64], repeats: int = 15) -> list[DynamicsTiming]:
    """
    Time each function of :data:`DYNAMICS_FUNCTIONS` against its bare call and the floor.

    Parameters
    ----------
    arm : PinocchioArm
        A robot with a ``dyn`` table.
    q, qd, qdd : ndarray, shape (m, n)
        The configurations [rad, rad/s, rad/s²], within the bounds of
        :mod:`robotica_kin.bounds`; fdyn starts at rest from ``q[0]``.
    repeats : int
        Blocks per route; the best is kept.

    Returns
    -------
    list of DynamicsTiming
        In the order of :data:`DYNAMICS_FUNCTIONS`.

    """
    if repeats < 1 or len(q) < 1:
        raise ValueError('time_dynamics needs repeats >= 1 and one configuration at least')
    configs = list(zip(q, qd, qdd))
    names = _namespace(arm, arm.model.createData(), configs)
    timings = []
    for function, (*statements, raw_name) in _STATEMENTS.items():
        # The loop is compiled around each statement: no wrapper call on any route (a lambda
        # would add its own call to both sides and shrink the ratio).
        timers = [timeit.Timer(f'for x, v, a in configs: {statement}', globals=names,
                               timer=time.process_time) for statement in statements]
        for timer in timers:
            timer.timeit(1)   # warm-up: the arm's caches, the thread's scratch
        best = [np.inf] * len(timers)
        for _ in range(repeats):
            best = [min(b, timer.timeit(1)) for b, timer in zip(best, timers)]
        us = [b / len(configs) * 1e6 for b in best]
        timings.append(DynamicsTiming(function, raw_name, us[0], us[1], us[2], len(configs),
                                      repeats))
    return timings + [_fdyn_timing(arm, q[0], max(1, repeats // 3))]
