"""
Assignments: the folder a teacher hands out (``robotica assignment init|check``).

An assignment folder holds a manifest, ``assignment.yaml`` (docs/assignments.md)::

    title: A path tracker of your own
    role: tracker                 # the role students' nodes take (docs/your_node.md)
    scenarios: [scenario.yaml]    # each runs the template in that role (external command)
    rubric: rubric.yaml           # grades the bag of each scenario's run
    template: my_tracker.py       # the working node students start from
    hand_in: my_tracker.py        # the file students hand in, with their run folder
    statement: statement.md       # the task, how to run, how it is graded, what to hand in

and the files it names, all inside the folder. :func:`load_assignment` reads the manifest as
strictly as a scenario (an unknown, missing or repeated key, a wrong type, a path that leaves
the folder: :class:`AssignmentError`, one line). :func:`check_assignment` checks what the
manifest names: every file is there, every scenario loads and plans (its command and script
exist), runs the template as the manifest's role, and the rubric loads and names every
scenario. :func:`init_files` lays out a new folder from the files of ``robotica new``'s
template.

Pure data and files: no rclpy here.
"""
from dataclasses import dataclass
import json
from pathlib import Path
import textwrap
from typing import Any, Optional

from robotica_sim.grading.metrics import METRICS
from robotica_sim.grading.rubric import load_rubric, parse_rubric, Rubric, RubricError
from robotica_sim.runs.plan import external_roles, plan_run
from robotica_sim.runs.roles import ROLES
from robotica_sim.runs.scenario import load_scenario, Scenario
from robotica_sim.runs.strict_yaml import read_strict_yaml
import yaml

__all__ = ['Assignment', 'AssignmentCheck', 'AssignmentError', 'CheckedAssignment',
           'MANIFEST', 'RUBRIC_FILE', 'SCENARIO_FILE', 'STATEMENT_FILE', 'check_assignment',
           'init_files', 'load_assignment', 'parse_assignment', 'statement_text']

MANIFEST = 'assignment.yaml'
SCENARIO_FILE = 'scenario.yaml'
RUBRIC_FILE = 'rubric.yaml'
STATEMENT_FILE = 'statement.md'
_KEYS = ('title', 'role', 'scenarios', 'rubric', 'template', 'hand_in', 'statement')


class AssignmentError(ValueError):
    """An assignment folder or manifest that cannot be used; the message says where and why."""


@dataclass(frozen=True)
class Assignment:
    """A validated manifest; its file names are relative to ``folder``."""

    title: str
    role: str                          # a key of robotica_sim.runs.roles.ROLES
    scenarios: tuple[str, ...]
    rubric: str
    template: str
    hand_in: str
    statement: str
    folder: Path = Path('.')

    def path(self, name: str) -> Path:
        """Return the path of the file ``name`` of the manifest."""
        return self.folder / name

    @staticmethod
    def run_name(scenario: str) -> str:
        """
        Return the name of the run folder of the manifest's ``scenario``: one per scenario.

        >>> Assignment.run_name('part2/scenario.yaml')
        'part2_scenario'
        """
        return Path(scenario).with_suffix('').as_posix().replace('/', '_')

    @property
    def files(self) -> tuple[str, ...]:
        """Return the files the manifest names, each once (the handed-in one is the students')."""
        return tuple(dict.fromkeys((self.statement, self.template, *self.scenarios,
                                    self.rubric)))


@dataclass(frozen=True)
class AssignmentCheck:
    """The outcome of one check of :func:`check_assignment`."""

    subject: str                       # 'files', 'scenario scenario.yaml', ...
    passed: bool
    text: str                          # what was found, or why it failed

    def line(self) -> str:
        """
        Return the check as one line: OK or FAIL, the subject, the text.

        >>> AssignmentCheck('files', False, 'missing rubric.yaml').line()
        'FAIL  files: missing rubric.yaml'
        """
        return f'{"OK  " if self.passed else "FAIL"}  {self.subject}: {self.text}'


@dataclass(frozen=True)
class CheckedAssignment:
    """The checks of an assignment, and what passed them (for a run of each scenario)."""

    assignment: Assignment
    checks: tuple[AssignmentCheck, ...]
    scenarios: tuple[str, ...]         # the manifest's scenarios that load, plan and fit
    rubric: Optional[Rubric]

    @property
    def passed(self) -> bool:
        """Return whether every check passed."""
        return all(c.passed for c in self.checks)


def _relative(value: Any, where: str) -> str:
    """Return ``value`` if it is a path inside the assignment folder; else AssignmentError."""
    if not isinstance(value, str) or not value.strip() or '\0' in value:
        raise AssignmentError(f'{where} must be a file name in the assignment folder, got '
                              f'{value!r}')
    path = Path(value)
    if path.is_absolute() or '..' in path.parts:
        raise AssignmentError(f'{where} must be a path inside the assignment folder (relative, '
                              f'no ..), got {value!r}')
    return value


def parse_assignment(data: Any, folder: Path, source: str = MANIFEST) -> Assignment:
    """
    Validate manifest ``data`` (the loaded YAML) of the folder ``folder``; return it.

    Raises
    ------
    AssignmentError
        For anything but a mapping of exactly the keys title (a non-empty string), role (a
        role of docs/your_node.md), scenarios (a file or a non-empty list of files), rubric,
        template, hand_in and statement (files), each file a relative path without ``..``;
        the message names ``source``.

    Examples
    --------
    >>> parse_assignment({'title': 'T', 'role': 'tracker', 'scenarios': 's.yaml',
    ...                   'rubric': 'r.yaml', 'template': 'n.py', 'hand_in': 'n.py',
    ...                   'statement': 'statement.md'}, Path('lab')).scenarios
    ('s.yaml',)

    """
    if not isinstance(data, dict):
        raise AssignmentError(f'{source}: an assignment manifest is a YAML mapping of '
                              f'{", ".join(_KEYS)}')
    unknown = sorted(str(k) for k in data if k not in _KEYS)
    if unknown:
        raise AssignmentError(f'{source}: unknown key(s) {", ".join(unknown)}; a manifest has '
                              f'{", ".join(_KEYS)}')
    missing = [k for k in _KEYS if k not in data]
    if missing:
        raise AssignmentError(f'{source}: missing key(s) {", ".join(missing)}')
    title = data['title']
    if not isinstance(title, str) or not title.strip():
        raise AssignmentError(f'{source}: title must be a non-empty string, got {title!r}')
    if data['role'] not in ROLES:
        raise AssignmentError(f'{source}: role must be one of {", ".join(ROLES)}, got '
                              f'{data["role"]!r}')
    scenarios = data['scenarios']
    scenarios = [scenarios] if isinstance(scenarios, str) else scenarios
    if not isinstance(scenarios, list) or not scenarios:
        raise AssignmentError(f'{source}: scenarios must be a scenario file or a non-empty '
                              f'list of them, got {data["scenarios"]!r}')
    twice = sorted({str(s) for s in scenarios if scenarios.count(s) > 1})
    if twice:
        raise AssignmentError(f'{source}: scenarios: {", ".join(twice)} given twice')
    return Assignment(
        title=title.strip(), role=data['role'],
        scenarios=tuple(_relative(s, f'{source}: scenarios[{i}]')
                        for i, s in enumerate(scenarios)),
        **{key: _relative(data[key], f'{source}: {key}')
           for key in ('rubric', 'template', 'hand_in', 'statement')},
        folder=folder)


def load_assignment(folder: str | Path) -> Assignment:
    """Read and validate the manifest of the assignment folder ``folder``; AssignmentError."""
    folder = Path(folder)
    if not folder.is_dir():
        raise AssignmentError(f'{folder}: no such folder (an assignment is a folder with '
                              f'{MANIFEST}; robotica assignment init writes one)')
    manifest = folder / MANIFEST
    if not manifest.is_file():
        raise AssignmentError(f'{folder}: no {MANIFEST} (robotica assignment init writes one)')
    return parse_assignment(read_strict_yaml(manifest, AssignmentError), folder,
                            str(manifest))


def _one_line(err: Exception) -> str:
    return ' '.join(str(err).split())


def _role_check(assignment: Assignment, name: str, scenario: Scenario) -> AssignmentCheck:
    """Check that ``scenario`` runs the template, and only it, in the manifest's role."""
    subject = f'role {name}'
    role = ROLES[assignment.role]
    given = external_roles(scenario)
    if [r.name for r, _ in given] != [role.name]:
        others = ', '.join(r.name for r, _ in given) or 'none'
        return AssignmentCheck(subject, False, f"the assignment's role is {role.name}: the "
                               f'scenario must give it (and it only) to a command with '
                               f'{role.section}: {{external: {{command: [...]}}}}; its roles '
                               f'of users: {others}')
    command = given[0][1].command
    folder = Path(scenario.source or '.').parent
    template = assignment.path(assignment.template).resolve()
    if not any((folder / word).resolve() == template for word in command):
        return AssignmentCheck(subject, False, f'the {role.name} runs {" ".join(command)!r}, '
                               f'not the template {assignment.template}')
    return AssignmentCheck(subject, True, f'the {role.name} runs {" ".join(command)!r}')


def _scenario_checks(assignment: Assignment, name: str,
                     ) -> tuple[list[AssignmentCheck], Optional[Scenario]]:
    """Load and plan scenario ``name``; return its checks and the scenario if all passed."""
    subject = f'scenario {name}'
    try:
        scenario = load_scenario(str(assignment.path(name)))
    except (ValueError, OSError) as err:
        return [AssignmentCheck(subject, False, _one_line(err))], None
    checks = []
    try:
        nodes = plan_run(scenario)
    except (ValueError, OSError) as err:
        checks.append(AssignmentCheck(subject, False, _one_line(err)))
    else:
        checks.append(AssignmentCheck(subject, True, f'{scenario.name} loads and plans '
                                      f'({len(nodes)} nodes, {scenario.duration:g} s)'))
    checks.append(_role_check(assignment, name, scenario))
    return checks, scenario if all(c.passed for c in checks) else None


def _rubric_checks(assignment: Assignment, scenarios: dict[str, Scenario],
                   ) -> tuple[list[AssignmentCheck], Optional[Rubric]]:
    """Load the rubric and check that it names every scenario that loaded."""
    subject = f'rubric {assignment.rubric}'
    try:
        rubric = load_rubric(assignment.path(assignment.rubric))
    except RubricError as err:
        return [AssignmentCheck(subject, False, _one_line(err))], None
    checks = [AssignmentCheck(subject, True, f'{rubric.title!r}: {len(rubric.checks)} checks '
                              f'({", ".join(rubric.checks)})')]
    for file_name, scenario in scenarios.items():
        if rubric.scenario is None:
            checks.append(AssignmentCheck(
                f'{subject} scenario', False, f'names no scenario: add scenario: '
                f'{scenario.name} (else a bag of any run passes its checks)'))
            break
        named = scenario.name in rubric.scenario
        checks.append(AssignmentCheck(
            f'{subject} scenario', named,
            f'names {scenario.name} ({file_name})' if named else
            f'names {", ".join(rubric.scenario)}, not {scenario.name} (the name of '
            f'{file_name}): the bags of its runs would fail the check "scenario"'))
    return checks, rubric


def check_assignment(assignment: Assignment) -> CheckedAssignment:
    """
    Check what ``assignment`` names; return every check (each passed or failed, with why).

    The files are all there; each scenario loads and plans (:func:`plan_run` checks its
    command and script), gives the manifest's role, and only it, to a command that runs the
    template; the rubric loads and names each scenario (a bag of another run fails it).
    """
    missing = [f for f in assignment.files if not assignment.path(f).is_file()]
    checks = [AssignmentCheck('files', not missing, f'missing {", ".join(missing)}' if missing
                              else ', '.join(assignment.files))]
    loaded: dict[str, Scenario] = {}
    planned = []
    for name in assignment.scenarios:
        if name in missing:
            continue
        found, scenario = _scenario_checks(assignment, name)
        checks += found
        if scenario is not None:
            loaded[name] = scenario
            planned.append(name)
    rubric = None
    if assignment.rubric not in missing:
        found, rubric = _rubric_checks(assignment, loaded)
        checks += found
    return CheckedAssignment(assignment, tuple(checks), tuple(planned), rubric)


def _rename(text: str, name: str) -> str:
    """Point the template's file names (``robotica new``'s) at the assignment's."""
    return text.replace(f'{name}_rubric.yaml', RUBRIC_FILE).replace(f'{name}.yaml',
                                                                    SCENARIO_FILE)


def _bound_text(metric: str, rubric: Rubric) -> str:
    unit = METRICS[metric].unit
    return f'{rubric.checks[metric].text()}{"" if unit in ("", "-") else " " + unit}'


def statement_text(assignment: Assignment, rubric: Rubric, scenario_name: str) -> str:
    """Return the statement (Markdown) of ``assignment``, whose rubric is ``rubric``."""
    role = ROLES[assignment.role]
    task = textwrap.fill(
        f'Write a {role.name.replace("_", " ")} of your own, a ROS 2 node that {role.summary}. '
        f'Start from `{assignment.template}`, a working node that keeps the contract, and '
        'change its law.', width=99)
    topics = '\n'.join(f'- {kind}: {topic.line()}: {topic.description}'
                       for kind, group in (('in', role.inputs), ('out', role.outputs))
                       for topic in group)
    checks = '\n'.join(f'- `{metric}` {_bound_text(metric, rubric)}' for metric in rubric.checks)
    run = f'runs/{scenario_name}-<time>'
    scenarios = ', '.join(f'`{s}`' for s in assignment.scenarios)
    return f"""# {assignment.title}

<!-- Written by robotica assignment init: edit it to set the task. -->

## The task

{task}

The contract, in short (in full, with what the run checks: `docs/your_node.md` in the robotica
repository); in lockstep your node answers each `{role.answers}` message with exactly one
`{role.answer}`:

{topics}

## How to run it

In this folder, in a terminal where `. scripts/env.sh` of the robotica repository has run:

```bash
robotica run {assignment.scenarios[0]}
robotica report {run}/bag
robotica grade {run}/bag --rubric {assignment.rubric}
```

`robotica run` starts the simulation and your node, records the run in `{run}/`
and prints where (`--output-dir DIR` chooses the folder). `robotica report` draws the run into
`{run}/report/index.html`.

## How it is graded

The bag of your run of {scenarios} is graded with `{assignment.rubric}`; every check must pass:

{checks}

`robotica grade` prints each metric against its bound and exits 0 when all pass. The metrics
are defined in `docs/grading.md`.

## What to hand in

`{assignment.hand_in}` and the run folder `{run}/` (or its `bag` folder), unchanged.
"""


def _scalar(value: str) -> str:
    """Return ``value`` as a YAML scalar (a JSON string is one)."""
    return json.dumps(value, ensure_ascii=False)


def init_files(role: str, name: str, title: str,
               template: dict[str, str]) -> dict[str, str]:
    """
    Return the files of a new assignment folder: file name, text.

    ``template`` is what ``robotica new ROLE NAME`` writes (``NAME.py``, ``NAME.yaml``,
    ``NAME_rubric.yaml``); its scenario and rubric become :data:`SCENARIO_FILE` and
    :data:`RUBRIC_FILE` (their references to each other follow), the node stays ``NAME.py``.
    The manifest names them; the statement lists the rubric's checks.
    """
    node = f'{name}.py'
    scenario = _rename(template[f'{name}.yaml'], name)
    rubric_text = _rename(template[f'{name}_rubric.yaml'], name)
    assignment = Assignment(title=title, role=role, scenarios=(SCENARIO_FILE,),
                            rubric=RUBRIC_FILE, template=node, hand_in=node,
                            statement=STATEMENT_FILE)
    rubric = parse_rubric(yaml.safe_load(rubric_text), RUBRIC_FILE)
    rows = (('title', _scalar(title), 'what students read first'),
            ('role', role, "the role of students' nodes (docs/your_node.md)"),
            ('scenarios', f'[{SCENARIO_FILE}]', 'each runs the template in that role'),
            ('rubric', RUBRIC_FILE, "grades the bag of each scenario's run"),
            ('template', node, 'the working node students start from'),
            ('hand_in', node, 'what students hand in, with their run folder'),
            ('statement', STATEMENT_FILE, 'the task, how to run, how it is graded'))
    manifest = ''.join(f'{f"{key}: {value}":<33} # {comment}\n' for key, value, comment in rows)
    manifest = ('# An assignment of robotica (docs/assignments.md). Check it, and that the '
                'template\n# passes its rubric: robotica assignment check FOLDER --run\n'
                + manifest)
    return {MANIFEST: manifest,
            STATEMENT_FILE: statement_text(assignment, rubric, name),
            node: _rename(template[node], name),
            SCENARIO_FILE: scenario,
            RUBRIC_FILE: rubric_text}
