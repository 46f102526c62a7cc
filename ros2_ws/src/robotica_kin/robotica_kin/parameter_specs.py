"""
Node parameters as data: default, description with unit, range or choices, and their check.

A node declares each parameter from its :class:`ParameterSpec` (rclpy then refuses an
out-of-range override at start-up), and whoever configures the node beforehand (the plan of a
run, :mod:`robotica_sim.runs.plan`) checks the same values against the same specs with
:func:`check_parameters`: one source of truth per range, so that a value the node would refuse
is refused before any process starts. The specs live next to the model they bound (the sensor
models, the simulations, the control laws); this module holds only the mechanism.
"""
from dataclasses import dataclass
import math
from typing import Any, Collection, Mapping, Sequence

__all__ = ['MAX_SEED', 'ParameterError', 'ParameterSpec', 'check_parameters', 'named_error',
           'parameter_values', 'seed_spec']

MAX_SEED = 2**31 - 1
"""The largest seed a node takes (an rclpy integer parameter, a NumPy SeedSequence entropy)."""


class ParameterError(ValueError):
    """
    A parameter value refused: ``name`` is the parameter, ``reason`` what it must be.

    ``str()`` is ``'<name> <reason>'`` (``'seed must be in [0, 2147483647], got -1'``).
    """

    def __init__(self, name: str, reason: str) -> None:
        super().__init__(f'{name} {reason}')
        self.name = name
        self.reason = reason


def _bound(value: float) -> str:
    return f'{value:g}' if isinstance(value, float) else str(value)


@dataclass(frozen=True)
class ParameterSpec:
    """
    One parameter: default, description with unit and book symbol, range or choices.

    ``low``/``high`` bound a number, or each number of a list, inclusively (both or neither,
    as ``robotica_kin.ros.parameters.declare`` takes them); ``choices`` list the values of a
    string. A tuple default is a list of numbers.
    """

    default: float | int | bool | str | tuple[float, ...]
    description: str
    low: float | None = None
    high: float | None = None
    choices: tuple[str, ...] = ()

    def check(self, name: str, value: Any) -> None:
        """
        Raise :class:`ParameterError` unless ``value`` is within the range or the choices.

        >>> try:
        ...     ParameterSpec(0.5, 'L [m]', 0.01, 100.0).check('lookahead_distance', 0.0)
        ... except ParameterError as err:
        ...     print(f'{err.name}: {err.reason}')
        lookahead_distance: must be in [0.01, 100], got 0.0
        """
        if self.choices and value not in self.choices:
            raise ParameterError(name, f'must be one of {self.choices}, got {value!r}')
        is_list = isinstance(value, Sequence) and not isinstance(value, str)
        if isinstance(self.default, tuple) and not is_list:
            raise ParameterError(name, f'must be a list of numbers, got {value!r}')
        if isinstance(self.default, (int, float)) and not isinstance(self.default, bool) \
                and is_list:
            raise ParameterError(name, f'must be one number, got {value!r}')
        if self.low is None or self.high is None:
            return
        values = list(value) if is_list else [value]
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(v) \
                    or not self.low <= v <= self.high:
                raise ParameterError(name, f'must be in [{_bound(self.low)}, '
                                     f'{_bound(self.high)}], got {value!r}')
        if isinstance(self.default, int) and not isinstance(self.default, bool) \
                and any(v != int(v) for v in values):
            raise ParameterError(name, f'must be an integer, got {value!r}')


def check_parameters(specs: Mapping[str, ParameterSpec], values: Mapping[str, Any]) -> None:
    """
    Check every value of ``values`` whose name has a spec in ``specs``; ParameterError if not.

    >>> check_parameters({'seed': ParameterSpec(0, 'Seed', 0, 10)}, {'seed': 3, 'other': 'x'})
    """
    for name, value in values.items():
        if name in specs:
            specs[name].check(name, value)


def parameter_values(specs: Mapping[str, ParameterSpec],
                     values: Mapping[str, Any]) -> dict[str, Any]:
    """
    Return the value of every parameter of ``specs``: from ``values``, else its default.

    The values are checked first (:func:`check_parameters`).

    >>> parameter_values({'seed': ParameterSpec(0, 'Seed', 0, 10)}, {})
    {'seed': 0}
    """
    check_parameters(specs, values)
    return {name: values.get(name, spec.default) for name, spec in specs.items()}


def seed_spec(description: str) -> ParameterSpec:
    """
    Return the spec of a node's ``seed`` parameter: 0 to :data:`MAX_SEED`.

    >>> seed_spec('Seed of the noise draws').high
    2147483647
    """
    return ParameterSpec(0, description, 0, MAX_SEED)


def named_error(err: ValueError, names: Collection[str], prefix: str = '') -> ValueError:
    """
    Return a model's ``err`` as a ParameterError when its message opens with one of ``names``.

    Models name their arguments first (``'kp must be >= 0, got -1'``); a node's parameter is
    that name after ``prefix`` (``'pid.'``). Any other error is returned as it is.

    >>> err = named_error(ValueError('kp must be >= 0, got -1'), ['kp', 'kv'], 'pid.')
    >>> err.name, err.reason
    ('pid.kp', 'must be >= 0, got -1')
    """
    name, _, reason = str(err).partition(' ')
    return ParameterError(prefix + name, reason) if name in names and reason else err
