"""
What a bag says about the run that recorded it: the settings that ran and the nodes that ran.

The recorder stores in the bag's ``custom_data`` the files ``robotica run`` gives it and what it
saw itself:

* ``robotica.run.yaml``: the settings the run actually used (scenario name, seed, pacing,
  duration, step period, after the command line's overrides, listed in ``overrides``) and the
  nodes it started, each with its command and who provided it (``robotica``);
* ``robotica.scenario.yaml``: the scenario file as it was (its description, robot, sensors);
* ``robotica.publishers``: for each recorded topic, the nodes that published it (seen by the
  recorder when it subscribed and when it closed the bag).

Once the recorder has closed the bag, ``robotica run`` adds how the run ended (``ended`` in
``robotica.run.yaml``: ``completed``, or why it ended early: interrupted, a node that died, a
timeout; :func:`record_end`), so that a run stopped after 2 s of its 60 is never shown as a
60 s run.

:func:`run_record` reads them into a :class:`RunRecord`. A bag recorded before the run settings
were stored (no ``robotica.run.yaml``) falls back to the scenario file's settings and says so
(``settings_from``); a node that published a recorded topic but was not started by
``robotica run`` (a user's node) is listed as such, so that a scenario's description is never
taken for what ran when something else did.
"""
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robotica_sim.bags.metadata import METADATA_FILE, write_metadata
import yaml

__all__ = ['COMPLETED', 'RUN_KEY', 'PUBLISHERS_KEY', 'SCENARIO_KEY', 'RunNode', 'RunRecord',
           'custom_data', 'record_end', 'run_record']

RUN_KEY = 'robotica.run.yaml'
SCENARIO_KEY = 'robotica.scenario.yaml'
PUBLISHERS_KEY = 'robotica.publishers'
SETTINGS = ('seed', 'pacing', 'duration', 'step_period')
ROBOTICA = 'robotica'   # started_by of robotica's own nodes
USER = 'user'           # started_by of a user's command in a role of the run
COMPLETED = 'completed'   # how a run that reached its end time ended
# Topics every node publishes: they do not tell what a node did in the run.
GRAPH_TOPICS = ('/rosout', '/parameter_events')
_LOADER = getattr(yaml, 'CSafeLoader', yaml.SafeLoader)   # LibYAML when available


@dataclass(frozen=True)
class RunNode:
    """
    One node of a run: its name, who started it, its command and the topics it published.

    ``started_by`` is ``'robotica'`` for a node ``robotica run`` started (``command`` is
    its ``<package>/<executable>``), ``'user'`` for a user's command that ``robotica run``
    started in a ``role`` of the scenario (docs/your_node.md), and ``''`` for any other (a
    node of the user's own, or every node of a bag recorded by hand).
    """

    name: str
    started_by: str = ''
    command: str = ''
    topics: tuple[str, ...] = ()
    role: str = ''


@dataclass(frozen=True)
class RunRecord:
    """The run a bag recorded: effective settings, their origin, the scenario and the nodes."""

    name: str | None = None
    description: str | None = None
    settings: dict[str, Any] = field(default_factory=dict)   # seed, pacing, duration, ...
    settings_from: str = ''          # 'run' (what ran), 'scenario file' (old bag) or ''
    overrides: dict[str, Any] = field(default_factory=dict)  # command-line overrides
    nodes: tuple[RunNode, ...] = ()
    scenario: dict[str, Any] = field(default_factory=dict)   # the scenario file, parsed
    ended: str = ''                  # COMPLETED, why the run ended early, or '' (not recorded)

    @property
    def foreign_nodes(self) -> tuple[RunNode, ...]:
        """Return the nodes not started by ``robotica run`` that published a run topic."""
        return tuple(n for n in self.nodes
                     if n.started_by not in (ROBOTICA, USER)
                     and any(t not in GRAPH_TOPICS for t in n.topics))

    def lines(self) -> list[tuple[str, str]]:
        """
        Return the run's description as ``robotica info`` prints it (label, then text).

        >>> RunRecord('demo', settings={'pacing': 'realtime', 'duration': 3.0},
        ...           settings_from='run').lines()
        [('Scenario', 'demo'), ('Run', 'pacing realtime, duration 3 s (as run)')]
        >>> RunRecord('demo', settings={'duration': 60.0}, settings_from='run',
        ...           ended='interrupted').lines()[1]
        ('Run', 'duration 60 s (as run); ended early: interrupted')
        """
        out: list[tuple[str, str]] = []
        if self.name is not None:
            out.append(('Scenario', self.name))
        if self.description:
            foreign = self.foreign_nodes
            out.append(('Description', self.description + (
                " (the scenario's words; nodes not started by robotica run also published: "
                f'{", ".join(n.name for n in foreign)})' if foreign else '')))
        if self.settings:
            text = ', '.join(_setting(k, self.settings[k]) for k in SETTINGS
                             if k in self.settings)
            if self.settings_from == 'run':
                text += ' (as run' + (', overridden: ' + ', '.join(
                    f'{k} {self.overrides[k]}' for k in self.overrides) if self.overrides
                    else '') + ')'
            else:
                text += (' (from the scenario file: this bag records no run settings, so '
                         'command-line overrides are not shown)')
            if self.ended and self.ended != COMPLETED:
                text += f'; ended early: {self.ended}'
            out.append(('Run', text))
        elif self.name is None:
            out.append(('Run', 'no run settings in the bag (recorded outside robotica run)'))
        ours = [n.name for n in self.nodes if n.started_by == ROBOTICA]
        if ours:
            out.append(('Nodes', f'{", ".join(ours)} (started by robotica run)'))
        for node in (n for n in self.nodes if n.started_by == USER):
            out.append(('' if ours else 'Nodes',
                        f"{node.name}: the user's {node.role or 'node'}, started by robotica "
                        f'run ({node.command})'))
        others = [n for n in self.nodes if n.started_by not in (ROBOTICA, USER)]
        for i, node in enumerate(others):
            topics = [t for t in node.topics if t not in GRAPH_TOPICS]
            out.append(('' if ours or i else 'Nodes',
                        f'{node.name}: not started by robotica run'
                        + (f' (published {", ".join(topics)})' if topics else '')))
        return out


def _setting(key: str, value: Any) -> str:
    if key in ('duration', 'step_period') and isinstance(value, (int, float)):
        return f'{key.replace("_", " ")} {value:g} s'
    return f'{key.replace("_", " ")} {value}'


def custom_data(bag: str | Path) -> dict[str, str]:
    """Return the ``custom_data`` of the bag's ``metadata.yaml``; {} when there is none."""
    try:
        metadata = yaml.load((Path(bag) / METADATA_FILE).read_text(), Loader=_LOADER)
        custom = metadata['rosbag2_bagfile_information'].get('custom_data') or {}
    except (OSError, KeyError, TypeError, AttributeError, UnicodeDecodeError, yaml.YAMLError):
        return {}
    return {str(k): str(v) for k, v in custom.items()} if isinstance(custom, dict) else {}


def _mapping(text: str | None) -> dict:
    try:
        value = yaml.load(text or '', Loader=_LOADER)
    except yaml.YAMLError:
        return {}
    return value if isinstance(value, dict) else {}


def _name(node: Any) -> str:
    return str(node).lstrip('/')


def run_record(custom: dict[str, str]) -> RunRecord:
    r"""
    Return the run a bag's ``custom`` data describes.

    >>> record = run_record({'robotica.run.yaml': 'scenario: demo\npacing: realtime\n'
    ...                      'nodes: [{name: simulator, command: robotica_sim/simulator}]',
    ...                      'robotica.publishers': "{/cmd_vel: [/mine], /clock: [/simulator]}"})
    >>> record.settings, [(n.name, n.started_by) for n in record.nodes]
    ({'pacing': 'realtime'}, [('simulator', 'robotica'), ('mine', '')])
    """
    run = _mapping(custom.get(RUN_KEY))
    scenario = _mapping(custom.get(SCENARIO_KEY))
    published: dict[str, list[str]] = {}
    for topic, nodes in _mapping(custom.get(PUBLISHERS_KEY)).items():
        for node in nodes if isinstance(nodes, list) else ():
            published.setdefault(_name(node), []).append(str(topic))
    nodes = []
    for entry in run.get('nodes') or ():
        if isinstance(entry, dict) and 'name' in entry:
            name = _name(entry['name'])
            nodes.append(RunNode(name, str(entry.get('started_by', ROBOTICA)),
                                 str(entry.get('command', '')),
                                 tuple(sorted(published.pop(name, ()))),
                                 str(entry.get('role', ''))))
    nodes += [RunNode(name, '', '', tuple(sorted(topics)))
              for name, topics in sorted(published.items())]
    source = run if run else scenario
    ran = run.get('scenario', scenario.get('name'))
    overrides = run.get('overrides')
    ended = run.get('ended')
    return RunRecord(
        ended='' if ended is None else str(ended),
        name=None if ran is None else str(ran),
        description=None if scenario.get('description') is None
        else str(scenario['description']),
        settings={k: source[k] for k in SETTINGS if k in source},
        settings_from='run' if run else 'scenario file' if scenario else '',
        overrides=overrides if isinstance(overrides, dict) else {},
        nodes=tuple(nodes), scenario=scenario)


def record_end(bag: str | Path, ended: str) -> None:
    """
    Record how the run ended (``ended``) in the closed bag's ``metadata.yaml``.

    ``ended`` is :data:`COMPLETED` or why the run ended early; it goes into the bag's
    ``robotica.run.yaml`` (a bag without one is left as it is). The file is replaced
    atomically (:func:`robotica_sim.bags.metadata.write_metadata`).

    Raises
    ------
    OSError
        If the metadata cannot be read or written.

    """
    path = Path(bag)
    metadata = yaml.load((path / METADATA_FILE).read_text(), Loader=_LOADER)
    information = metadata['rosbag2_bagfile_information']
    custom = dict(information.get('custom_data') or {})
    run = _mapping(custom.get(RUN_KEY))
    if not run:
        return
    run['ended'] = ended
    custom[RUN_KEY] = yaml.safe_dump(run, sort_keys=False)
    write_metadata(path, {**information, 'custom_data': custom})
