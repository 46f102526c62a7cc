"""
Joint references of the trajectory publisher: a generator's samples from the node's parameters.

The ``joint_trajectory_publisher`` node publishes what :func:`reference_samples` returns for its
parameters (:data:`REFERENCE_PARAMETERS`, ``joint_names`` and ``via.*``), and the plan of a run
(:mod:`robotica_sim.runs.plan`) calls it with the same values before any process starts:

* ``sine``: ``offset + amplitude sin(2π t / period + phase)`` per joint for ``duration`` s
  (Ej. 8.1 (8.47), the appendix's PUMA reference (A.2)), :func:`~.sinusoid.sinusoid`;
* ``pol3``, ``pol5``: cubic or quintic segments through ``via.positions`` (HEMERO ``pol3``,
  ``pol5``, §10.3.1, §10.6), with ``via.velocities`` (``via.accelerations``) at the points,
  zero when not given;
* ``parab``: linear segments with parabolic blends (HEMERO ``parab``, §10.6.4), blend
  accelerations ``parab.acceleration``.
"""
import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray
from robotica_ctrl.trajectory.parabolic_blend import parab
from robotica_ctrl.trajectory.polynomial import pol3, pol5
from robotica_ctrl.trajectory.sinusoid import sinusoid
from robotica_kin.parameter_specs import (named_error, parameter_values, ParameterError,
                                          ParameterSpec)

__all__ = ['GENERATORS', 'MAX_TRAJECTORY_POINTS', 'REFERENCE_PARAMETERS', 'reference_samples',
           'trajectory_samples']

GENERATORS = ('sine', 'pol3', 'pol5', 'parab')
MAX_TRAJECTORY_POINTS = 1_000_000   # of one trajectory (one JointTrajectory message)
REFERENCE_PARAMETERS: dict[str, ParameterSpec] = {
    'generator': ParameterSpec('sine', 'How the trajectory is made', choices=GENERATORS),
    'sample_period': ParameterSpec(0.01, 'Time between trajectory points [s]', 1e-4, 10.0),
    'start_time': ParameterSpec(0.0, 'Header stamp [s]: when the trajectory starts; 0: on '
                                'receipt', 0.0, 1e7),
    'duration': ParameterSpec(10.0, 'Length of a sine reference [s]', 0.0, 1e6),
    'sine.amplitude': ParameterSpec((1.0,), 'A [rad | m] per joint (one value: all joints)'),
    'sine.period': ParameterSpec((2.0 * math.pi,), 'T [s] per joint'),
    'sine.phase': ParameterSpec((0.0,), 'phi [rad] per joint'),
    'sine.offset': ParameterSpec((0.0,), 'Offset [rad | m] per joint'),
    'parab.acceleration': ParameterSpec((1.0,), 'Blend acceleration magnitudes [/s^2] (1 or one '
                                        'per joint)'),
}
"""The node's parameters with a default; ``joint_names`` and ``via.*`` (none) are apart."""
VIA_KEYS = ('positions', 'velocities', 'accelerations', 'segment_durations')
Samples = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                NDArray[np.float64]]


def _via(values: Any, n: int, name: str) -> NDArray[np.float64]:
    array = np.asarray(values if values is not None else [], dtype=np.float64)
    if array.size == 0 or array.size % n:
        raise ParameterError(name, f'must hold points x {n} values (row-major), got '
                             f'{array.size}')
    return array.reshape(-1, n)


def _check_points(span: float, sample_period: float, name: str) -> None:
    """Refuse a trajectory of more than MAX_TRAJECTORY_POINTS samples, before sampling it."""
    if math.isfinite(span) and span / sample_period + 1.0 > MAX_TRAJECTORY_POINTS:
        raise ParameterError(name, f'of {span:g} s gives about {span / sample_period + 1.0:.3g} '
                             f'points of {sample_period:g} s, more than {MAX_TRAJECTORY_POINTS}: '
                             'sample it more coarsely (sample_period) or make it shorter')


def _sine(t: NDArray[np.float64], sine: Mapping[str, Any]) -> tuple[NDArray[np.float64], ...]:
    """Return :func:`sinusoid` at ``t``; its errors name the parameter (``sine.period``)."""
    try:
        return sinusoid(t, **sine)
    except ValueError as err:
        raise named_error(err, sine, 'sine.') from None


def _generate(generator: str, n: int, sample_period: float, duration: float,
              sine: Mapping[str, Any], via: Mapping[str, Any], acceleration: Any) -> Samples:
    """Return the samples of :func:`trajectory_samples`, not checked finite."""
    if generator == 'sine':
        if not duration > 0.0:
            raise ParameterError('duration', f'must be > 0 s for a sine, got {duration!r}')
        _check_points(duration, sample_period, 'duration')
        t = np.arange(0.0, duration + 0.5 * sample_period, sample_period)
        q, qd, qdd = _sine(t, sine)
        if q.shape[1] not in (1, n):
            raise ValueError(f'sine parameters give {q.shape[1]} joints, expected {n}')
        ones = np.ones((1, n))
        return t, q * ones, qd * ones, qdd * ones
    if generator not in GENERATORS:
        raise ValueError(f'generator must be one of {GENERATORS}, got {generator!r}')
    positions = _via(via.get('positions'), n, 'via.positions')
    durations = np.asarray(via.get('segment_durations') or [], dtype=np.float64)
    _check_points(float(np.sum(durations)), sample_period, 'via.segment_durations')
    zeros = np.zeros_like(positions)
    velocities = (zeros if not via.get('velocities')
                  else _via(via['velocities'], n, 'via.velocities'))
    if generator == 'pol3':
        _, t, q, qd, qdd = pol3(positions, velocities, 0.0, durations, sample_period)
    elif generator == 'pol5':
        accelerations = (zeros if not via.get('accelerations')
                         else _via(via['accelerations'], n, 'via.accelerations'))
        _, t, q, qd, qdd = pol5(positions, velocities, accelerations, 0.0, durations,
                                sample_period)
    else:
        ac = np.asarray(acceleration or [], dtype=np.float64)
        if ac.size not in (1, n):
            raise ParameterError('parab.acceleration', f'must hold 1 or {n} values, got '
                                 f'{ac.size}')
        _, t, q, qd, qdd, _ = parab(positions, ac if ac.size > 1 else float(ac[0]), 0.0,
                                    durations, sample_period)
    return t, q, qd, qdd


def trajectory_samples(generator: str, n: int, sample_period: float, *,
                       duration: float = 0.0, sine: dict | None = None,
                       via: dict | None = None, acceleration: list[float] | None = None
                       ) -> Samples:
    """
    Return ``(t, q, qd, qdd)`` of a generator, t (m,) [s] from 0, the others (m, n).

    ``sine`` holds the keyword arguments of :func:`sinusoid` but ``t``; ``via`` the flattened
    ``positions`` and, optionally, ``velocities`` / ``accelerations`` (points x n, row-major)
    and the ``segment_durations`` [s]; ``acceleration`` the blend accelerations of ``parab``
    (1 or n values) [/s²].

    Raises
    ------
    ValueError
        For an unknown generator or arguments the generator refuses (with its reason), more
        than :data:`MAX_TRAJECTORY_POINTS` samples, samples that overflow or times that do
        not increase strictly (what a controller's ``SampledTrajectory`` refuses); a
        :class:`~robotica_kin.parameter_specs.ParameterError` names the node's parameter.

    Examples
    --------
    >>> t, q, qd, qdd = trajectory_samples('pol3', 1, 0.5, via={
    ...     'positions': [0.0, 1.0], 'segment_durations': [1.0]})
    >>> t.tolist(), q[:, 0].tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.5, 1.0])

    """
    with np.errstate(over='ignore', invalid='ignore'):   # overflows: refused just below
        samples = _generate(generator, n, sample_period, duration, sine or {}, via or {},
                            acceleration)
    if not all(np.isfinite(array).all() for array in samples):
        raise ValueError(f'the {generator} trajectory is not finite: its positions, velocities '
                         'or accelerations overflow')
    if np.any(np.diff(samples[0]) <= 0.0):   # a controller refuses the trajectory then
        raise ValueError(f'the times of the {generator} trajectory do not increase strictly')
    return samples


def reference_samples(parameters: Mapping[str, Any]) -> Samples:
    """
    Return ``(t, q, qd, qdd)`` of the trajectory publisher node for its ``parameters``.

    ``parameters`` maps the node's parameter names (:data:`REFERENCE_PARAMETERS`,
    ``joint_names``, ``via.positions`` ...) to values; missing ones take their defaults.

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For a value out of its range or refused by the generator (``name`` is the parameter's).
    ValueError
        For other arguments the generator refuses.

    Examples
    --------
    >>> t, q, qd, qdd = reference_samples({'joint_names': ['a', 'b'], 'duration': 1.0,
    ...                                    'sample_period': 0.5, 'sine.amplitude': [0.1]})
    >>> t.tolist(), q.shape
    ([0.0, 0.5, 1.0], (3, 2))

    """
    values = parameter_values(REFERENCE_PARAMETERS, parameters)
    names = parameters.get('joint_names') or []
    if not names:
        raise ParameterError('joint_names', 'must name the joints of the trajectory')
    return trajectory_samples(
        values['generator'], len(names), values['sample_period'], duration=values['duration'],
        sine={key: values[f'sine.{key}'] for key in ('amplitude', 'period', 'phase', 'offset')},
        via={key: parameters.get(f'via.{key}') for key in VIA_KEYS},
        acceleration=values['parab.acceleration'])
