"""
The runs of a sweep: a scenario with some of its values varied, checked before any run.

A variation is ``KEY=V1,V2,...``: ``KEY`` is a dotted key of the scenario's YAML
(``tracker.lookahead_distance`` is the key ``lookahead_distance`` of the section ``tracker``;
``duration``, ``seed``, ``robot.wheel_radius``, ``path.corner_radius`` work the same) and the
values are YAML flow values (``0.5,1,2``, ``stanley,pure_pursuit``, ``[0,0,0],[1,0,0]``).
Several variations give their cartesian product, each combination run once per seed (seeds
0..N-1, or the scenario's own seed). :func:`sweep_runs` applies every combination to the
scenario's data and validates it as ``robotica run`` would (:func:`load_scenario` then
:func:`plan_run`), so that an unknown key or an invalid value is a :class:`ScenarioError` of
one line before any run starts. :func:`write_scenarios` then writes each run's scenario file.
"""
import copy
from dataclasses import dataclass
import itertools
from pathlib import Path
import re
import tempfile
from typing import Any, Optional, Sequence

from robotica_sim.runs.plan import plan_run
from robotica_sim.runs.roles import ROLE_SECTIONS
from robotica_sim.runs.scenario import (load_scenario, resolve_scenario_path, Scenario,
                                        ScenarioError)
from robotica_sim.runs.strict_yaml import read_strict_yaml
import yaml

__all__ = ['MAX_RUNS', 'SweepRun', 'Variation', 'apply_setting', 'parse_domain_ids',
           'parse_vary', 'sweep_runs', 'write_scenarios']

MAX_RUNS = 10_000
"""The most runs of one sweep (combinations x seeds)."""
_KEY = re.compile(r'[a-z_][a-z0-9_]*(\.[a-z_][a-z0-9_]*)*')
_RESERVED = ('name', 'source')   # a run's name is the scenario's, its source its file


@dataclass(frozen=True)
class Variation:
    """One ``--vary KEY=V1,V2,...``: a dotted scenario key and the values it takes."""

    key: str
    values: tuple


@dataclass(frozen=True)
class SweepRun:
    """One run of a sweep: its name, what it sets, and its validated scenario data."""

    name: str                      # 'run-003': its folder and scenario file
    settings: dict                 # the varied keys and 'seed' when seeds are swept
    data: dict                     # the whole scenario YAML of the run
    scenario: Scenario             # as loaded from ``data``


def parse_vary(text: str) -> Variation:
    """
    Parse ``KEY=V1,V2,...`` into a :class:`Variation`; ScenarioError if malformed.

    >>> parse_vary('tracker.lookahead_distance=0.5,1,2')
    Variation(key='tracker.lookahead_distance', values=(0.5, 1, 2))
    >>> parse_vary('tracker.law=stanley,pure_pursuit').values
    ('stanley', 'pure_pursuit')
    """
    key, sep, rest = text.partition('=')
    key = key.strip()
    if not sep or not _KEY.fullmatch(key):
        raise ScenarioError(f'--vary {text!r}: expected KEY=V1,V2,... with KEY a dotted '
                            'scenario key (tracker.lookahead_distance=0.5,1,2)')
    if key.split('.')[0] in _RESERVED:
        raise ScenarioError(f'--vary {text!r}: {key} cannot be varied')
    try:
        values = yaml.safe_load(f'[{rest}]')
    except yaml.YAMLError as err:
        problem = str(err).splitlines()[0]
        raise ScenarioError(f'--vary {text!r}: the values are not YAML: {problem}') from None
    if not rest.strip() or not values or any(v is None for v in values):
        raise ScenarioError(f'--vary {text!r}: give one or more values, separated by commas')
    if len({yaml.safe_dump(v) for v in values}) != len(values):
        raise ScenarioError(f'--vary {text!r}: a value is repeated')
    return Variation(key, tuple(values))


def parse_domain_ids(text: str) -> tuple[int, ...]:
    """
    Parse a pool of ROS domain ids: ``40-60``, ``3,5,7`` or both (``1-4,9``), each 0-232.

    >>> parse_domain_ids('40-42,50')
    (40, 41, 42, 50)
    """
    ids: list[int] = []
    for part in text.split(','):
        low, dash, high = part.strip().partition('-')
        try:
            first, last = int(low), int(high if dash else low)
        except ValueError:
            raise ValueError(f'expected ids or ranges like 40-60,70, got {text!r}') from None
        if not 0 <= first <= last <= 232:
            raise ValueError(f'ids must be in 0-232 and ranges increasing, got {part.strip()!r}')
        ids.extend(range(first, last + 1))
    if len(set(ids)) != len(ids):
        raise ValueError(f'an id is given twice in {text!r}')
    return tuple(ids)


def apply_setting(data: dict, key: str, value: Any) -> dict:
    """
    Return a copy of scenario ``data`` with dotted ``key`` set to ``value``.

    A missing section is created (the scenario's defaults apply to the rest of it).

    >>> apply_setting({'tracker': {'law': 'stanley'}}, 'tracker.gain', 2.0)
    {'tracker': {'law': 'stanley', 'gain': 2.0}}
    """
    out = copy.deepcopy(data)
    node = out
    parts = key.split('.')
    for depth, part in enumerate(parts[:-1]):
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise ScenarioError(f'{key}: {".".join(parts[:depth + 1])} is a value, not a '
                                'section')
    node[parts[-1]] = value
    return out


def _setting_text(settings: dict) -> str:
    return ', '.join(f'{k}={yaml.safe_dump(v, default_flow_style=True).strip()}'
                     .removesuffix('...').strip() for k, v in settings.items())


def sweep_runs(scenario: str, variations: Sequence[Variation], seeds: Optional[int] = None,
               fixed: Optional[dict] = None) -> list[SweepRun]:
    """
    Return the runs of a sweep, every one validated as ``robotica run`` validates a scenario.

    Parameters
    ----------
    scenario : str
        A scenario file or a shipped scenario's name.
    variations : sequence of Variation
        The varied keys (their cartesian product; none: one combination).
    seeds : int, optional
        Run each combination with seeds 0..seeds-1; None: with the scenario's seed.
    fixed : dict, optional
        Dotted keys set in every run (``{'duration': 2.0}``), not varied.

    Raises
    ------
    ScenarioError
        One line: an unknown key, an invalid value, a plan that fails (the combination and
        the reason), a key varied twice, seeds with ``--vary seed``, too many runs.

    """
    keys = [v.key for v in variations]
    if len(set(keys)) != len(keys):
        raise ScenarioError(f'--vary: a key is varied twice ({", ".join(keys)})')
    if seeds is not None and 'seed' in keys:
        raise ScenarioError('--vary seed and --seeds: give one of them')
    if seeds is not None and seeds < 1:
        raise ScenarioError(f'--seeds must be >= 1, got {seeds}')
    path = resolve_scenario_path(scenario)
    base = read_strict_yaml(path, ScenarioError)
    if not isinstance(base, dict):
        raise ScenarioError(f'{path}: a scenario is a YAML mapping')
    base.setdefault('name', path.stem)
    for section in ROLE_SECTIONS:   # a user's node keeps running in the scenario's folder
        values = base.get(section)
        external = values.get('external') if isinstance(values, dict) else None
        if isinstance(external, dict):
            external['folder'] = str(path.parent.resolve() / external.get('folder', '.'))
    for key, value in (fixed or {}).items():
        base = apply_setting(base, key, value)
    combos = [dict(zip(keys, values)) for values in
              itertools.product(*(v.values for v in variations))]
    seed_values = [None] if seeds is None else list(range(seeds))
    total = len(combos) * len(seed_values)
    if total > MAX_RUNS:
        raise ScenarioError(f'the sweep has {total} runs, more than {MAX_RUNS}')
    runs: list[SweepRun] = []
    with tempfile.TemporaryDirectory(prefix='robotica-sweep-') as folder:
        for combo, seed in itertools.product(combos, seed_values):
            settings = {**combo, **({} if seed is None else {'seed': seed})}
            name = f'run-{len(runs):03d}'
            file = Path(folder) / f'{name}.yaml'
            try:
                data = base
                for key, value in settings.items():
                    data = apply_setting(data, key, value)
                file.write_text(yaml.safe_dump(data, sort_keys=False))
                loaded = load_scenario(str(file))
                plan_run(loaded)
            except ScenarioError as err:
                reason = str(err)
                for text in (f'{file}: ', f'{file}.', str(file)):
                    reason = reason.replace(text, '')
                raise ScenarioError(f'{path.name} with {_setting_text(settings) or "no change"}'
                                    f': {reason}') from None
            runs.append(SweepRun(name, settings, data, loaded))
    return runs


def write_scenarios(runs: Sequence[SweepRun], folder: Path) -> dict[str, Path]:
    """Write each run's scenario YAML into ``folder`` (created); return the files by run."""
    folder.mkdir(parents=True, exist_ok=True)
    files = {}
    for run in runs:
        files[run.name] = folder / f'{run.name}.yaml'
        files[run.name].write_text(yaml.safe_dump(run.data, sort_keys=False))
    return files
