"""
Grading rubrics: thresholds on the metrics of a run (``robotica grade --rubric``).

A rubric is a YAML mapping (docs/grading.md)::

    rubric: ej9_1 pure pursuit        # title
    scenario: ej9_1                   # optional: the scenario (or a list of them) the bag
                                      # must have run; another one fails the check 'scenario'
    parameters:                       # optional: MetricParams overrides
      goal_tolerance: 0.2             # [m]
    checks:
      rms_cross_track: {max: 0.2}     # [m]
      completion: {min: 0.6}

:func:`resolve_rubric` finds a rubric by path or by the name of a shipped one
(``share/robotica_sim/rubrics``); :func:`parse_rubric` validates it strictly (unknown keys and
metric names, non-numeric bounds, ``min > max``) and raises :class:`RubricError`;
:func:`check_metrics` checks a run's :class:`~robotica_sim.grading.metrics.RunMetrics` against
it. A bound on a per-joint metric applies to every joint; a check on a metric the run lacks or
cannot define fails with the reason.
"""
from dataclasses import dataclass, field, fields
import math
from pathlib import Path
from typing import Any

from robotica_sim.grading.metrics import MetricParams, METRICS, MetricValue, RunMetrics
from robotica_sim.runs.shipped import resolve_shipped
from robotica_sim.runs.strict_yaml import read_strict_yaml

__all__ = ['Bound', 'CheckResult', 'Rubric', 'RubricError', 'check_metrics', 'load_rubric',
           'parse_rubric', 'resolve_rubric']

_TOP_KEYS = ('rubric', 'scenario', 'parameters', 'checks')


class RubricError(ValueError):
    """The rubric cannot be used; the message says where and why."""


@dataclass(frozen=True)
class Bound:
    """Bounds of one check: ``lower <= value <= upper`` (a rubric's min and max) or open."""

    lower: float | None = None
    upper: float | None = None

    def admits(self, value: float) -> bool:
        """
        Return whether ``value`` lies within the bounds (both inclusive).

        >>> Bound(upper=0.2).admits(0.2), Bound(0.5, 1.0).admits(0.4)
        (True, False)
        """
        return ((self.lower is None or value >= self.lower)
                and (self.upper is None or value <= self.upper))

    def text(self) -> str:
        """
        Return the bounds as a short text.

        >>> Bound(upper=0.2).text(), Bound(0.1, 0.3).text()
        ('<= 0.2', '0.1 .. 0.3')
        """
        if self.lower is not None and self.upper is not None:
            return f'{self.lower:g} .. {self.upper:g}'
        if self.lower is not None:
            return f'>= {self.lower:g}'
        return f'<= {self.upper:g}'


@dataclass(frozen=True)
class Rubric:
    """A validated rubric."""

    title: str
    checks: dict[str, Bound]
    scenario: tuple[str, ...] | None = None     # the scenarios the rubric is for; None: any
    params: MetricParams = field(default_factory=MetricParams)
    source: str = '<rubric>'


@dataclass(frozen=True)
class CheckResult:
    """The outcome of one check; ``message`` explains a failure that is not a plain bound."""

    metric: str
    value: MetricValue | str
    bound: Bound | None
    passed: bool
    message: str = ''


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(
            value):
        raise RubricError(f'{where} must be a finite number, got {value!r}')
    return float(value)


def _bound(value: Any, where: str) -> Bound:
    if not isinstance(value, dict) or not value:
        raise RubricError(f'{where} must be a mapping with min and/or max, e.g. {{max: 0.2}}, '
                          f'got {value!r}')
    unknown = sorted(str(k) for k in value if k not in ('min', 'max'))
    if unknown:
        raise RubricError(f'{where}: unknown key(s) {", ".join(unknown)}; use min and/or max')
    low = _number(value['min'], f'{where}.min') if 'min' in value else None
    high = _number(value['max'], f'{where}.max') if 'max' in value else None
    if low is not None and high is not None and low > high:
        raise RubricError(f'{where}: min {low:g} > max {high:g}')
    return Bound(low, high)


def _params(value: Any, where: str) -> MetricParams:
    names = [f.name for f in fields(MetricParams)]
    if not isinstance(value, dict):
        raise RubricError(f'{where} must be a mapping of {", ".join(names)}, got {value!r}')
    unknown = sorted(str(k) for k in value if k not in names)
    if unknown:
        raise RubricError(f'{where}: unknown parameter(s) {", ".join(unknown)}; known: '
                          f'{", ".join(names)}')
    numbers = {k: _number(v, f'{where}.{k}') for k, v in value.items()}
    try:
        return MetricParams(**numbers)
    except ValueError as err:
        raise RubricError(f'{where}: {err}') from None


def parse_rubric(data: Any, source: str = '<rubric>') -> Rubric:
    """
    Validate rubric ``data`` (the loaded YAML) and return it as a :class:`Rubric`.

    Raises
    ------
    RubricError
        For anything but a mapping with a non-empty ``checks`` mapping of known metrics to ``{min,
        max}`` bounds (finite numbers, min <= max), an optional string ``rubric`` (title), an
        optional ``scenario`` (a name or a list of names), and optional ``parameters`` of
        :class:`~robotica_sim.grading.metrics.MetricParams`; the message names ``source``.

    Examples
    --------
    >>> parse_rubric({'checks': {'completion': {'min': 0.9}}}).checks
    {'completion': Bound(lower=0.9, upper=None)}

    """
    if not isinstance(data, dict):
        raise RubricError(f'{source}: a rubric is a YAML mapping with a checks section')
    unknown = sorted(str(k) for k in data if k not in _TOP_KEYS)
    if unknown:
        raise RubricError(f'{source}: unknown key(s) {", ".join(unknown)}; a rubric has '
                          f'{", ".join(_TOP_KEYS)}')
    if 'rubric' in data and not isinstance(data['rubric'], str):
        raise RubricError(f'{source}: rubric must be a string, got {data["rubric"]!r}')
    scenario = data.get('scenario')
    if scenario is not None:
        names = [scenario] if isinstance(scenario, str) else scenario
        if not isinstance(names, list) or not names or not all(
                isinstance(n, str) and n for n in names):
            raise RubricError(f'{source}: scenario must be a scenario name or a list of them, '
                              f'got {scenario!r}')
        scenario = tuple(names)
    checks = data.get('checks')
    if not isinstance(checks, dict) or not checks:
        raise RubricError(f'{source}: checks must be a non-empty mapping of metric names to '
                          '{min, max} bounds')
    bounds = {}
    for name, value in checks.items():
        if name not in METRICS:
            raise RubricError(f'{source}: unknown metric {name!r} in checks; known metrics: '
                              f'{", ".join(METRICS)}')
        bounds[name] = _bound(value, f'{source}: checks.{name}')
    params = (_params(data['parameters'], f'{source}: parameters') if 'parameters' in data
              else MetricParams())
    return Rubric(title=data.get('rubric', Path(source).stem), checks=bounds,
                  scenario=scenario, params=params, source=source)


def resolve_rubric(name_or_path: str) -> Path:
    """Return the file of a rubric given as a path or as a shipped rubric's name."""
    try:
        return resolve_shipped(name_or_path, 'rubric')
    except FileNotFoundError as err:
        raise RubricError(str(err)) from None


def load_rubric(path: str | Path) -> Rubric:
    """
    Read and validate the rubric file ``path``; RubricError when it cannot be used.

    Read as strictly as a scenario (:func:`robotica_sim.runs.strict_yaml.read_strict_yaml`): a
    check or a key given twice is refused, not silently replaced by the last one.
    """
    return parse_rubric(read_strict_yaml(path, RubricError), str(path))


def _check(name: str, bound: Bound, metrics: RunMetrics) -> CheckResult:
    if name in metrics.absent:
        return CheckResult(name, 'absent', bound, False,
                           f'metric {name} {metrics.absent[name]}')
    if name not in metrics.values:
        return CheckResult(name, 'absent', bound, False, f'metric {name} was not computed')
    value = metrics.values[name]
    note = metrics.notes.get(name, '')
    if value is None:
        return CheckResult(name, None, bound, False, f'metric {name} is n/a: {note}')
    if not isinstance(value, list):
        admitted = bound.admits(float(value))
        return CheckResult(name, value, bound, admitted,
                           '' if admitted else f'{name} = {float(value):.4g}, want {bound.text()}')
    joints = list(metrics.joint_names) or [f'joint_{j + 1}' for j in range(len(value))]
    failures = []
    for joint, v in zip(joints, value):
        if v is None:
            failures.append(f'{joint} n/a')
        elif not bound.admits(v):
            failures.append(f'{joint} = {v:.4g}')
    message = f'{name}: {", ".join(failures)}; want {bound.text()}' if failures else ''
    if failures and note:
        message += f' ({note})'
    return CheckResult(name, value, bound, not failures, message)


def check_metrics(rubric: Rubric, metrics: RunMetrics,
                  scenario_name: str | None) -> list[CheckResult]:
    """
    Check a run's metrics against ``rubric``; one result per check, in the rubric's order.

    When the rubric names its scenarios, a first result ``scenario`` checks that the run's
    ``scenario_name`` is one of them (a bag that records no scenario fails it). A metric the run
    lacks (absent) or cannot define (None) fails, with the reason in ``message``.
    """
    results = []
    if rubric.scenario is not None:
        matches = scenario_name in rubric.scenario
        wanted = (f'scenario {rubric.scenario[0]!r}' if len(rubric.scenario) == 1
                  else f'scenarios {", ".join(rubric.scenario)}')
        ran = (f'the bag ran {scenario_name!r}' if scenario_name is not None
               else 'the bag records no scenario (recorded outside robotica run?)')
        results.append(CheckResult('scenario', scenario_name or 'none', None, matches,
                                   '' if matches else f'the rubric is for {wanted}, {ran}'))
    results.extend(_check(name, bound, metrics) for name, bound in rubric.checks.items())
    return results
