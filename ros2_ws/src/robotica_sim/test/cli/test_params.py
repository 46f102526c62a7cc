"""
``robotica params``, and the parameter files of ``config/``: current, and accepted by every node.

The files are regenerated from the node classes and compared with the committed ones, so that a
parameter added, renamed or re-ranged without ``robotica params NODE -o config/NODE.yaml``
fails here. Every node is built with ``--ros-args --params-file`` of its file, in-process as
its ``main()`` passes the arguments to rclpy: the values it declares must be the file's, as an
independent YAML parser reads them. The slow test starts every executable so, all at once,
waits until each is up and stops it by SIGINT (exit code 0).
"""
import array
from pathlib import Path
import re
import signal
import time

import pytest
from rcl_interfaces.srv import GetParameters
import rclpy
from robotica_sim.cli.main import run_verb
from robotica_sim.cli.params import node_class, node_executables, node_parameter_file
import yaml

pytestmark = pytest.mark.ros

ROOT = Path(__file__).resolve().parents[5]
CONFIG = ROOT / 'config'
NODES = node_executables()


def _required(tmp_path: Path) -> dict[str, dict]:
    """Return, per executable, the values it cannot start without (the file leaves them unset)."""
    world = tmp_path / 'world.yaml'
    world.write_text('world:\n  walls: [[3.0, -5.0, 3.0, 5.0]]\n')
    return {'recorder': {'output': str(tmp_path / 'bag')},
            **{sensor: {'world_file': str(world)}
               for sensor in ('sonar_emulator', 'infrared_emulator', 'laser_emulator',
                              'world_publisher')},
            'path_publisher': {'x': [0.0, 1.0], 'y': [0.0, 0.0]},
            'joint_trajectory_publisher': {'joint_names': ['joint_1']},
            'view_relay': {'port': 0}}   # any free port: the default one may be in use


def test_every_node_executable_is_known_and_has_its_file():
    declared = set()
    for setup in (ROOT / 'ros2_ws' / 'src').glob('*/setup.py'):
        package = setup.parent.name
        declared |= {f'{package}/{name}' for name, module in re.findall(
            r"'(\w+) = (\w+)\.nodes\.\w+:main'", setup.read_text()) if module == package}
    assert set(NODES) == declared
    assert {p.stem for p in CONFIG.glob('*.yaml')} == {n.split('/')[1] for n in NODES}


@pytest.mark.parametrize('node', NODES)
def test_the_committed_file_is_the_generated_one(ros_domain, node):
    executable = node.split('/')[1]
    text, _ = node_parameter_file(node, NODES[node])
    assert text == (CONFIG / f'{executable}.yaml').read_text(), (
        f'config/{executable}.yaml is stale: robotica params {node} -o config/{executable}.yaml')


def _overrides(required: dict) -> list[str]:
    """Return ``-p name:=value`` arguments (YAML values) for ``required``."""
    return [a for name, value in required.items()
            for a in ('-p', f'{name}:=' + yaml.safe_dump(value, default_flow_style=True)
                      .removesuffix('\n...\n').strip())]


def _file_values(executable: str, required: dict) -> tuple[str, dict]:
    """Return the node name and the values of its file (yaml.safe_load), bar ``required``."""
    (name, section), = yaml.safe_load((CONFIG / f'{executable}.yaml').read_text()).items()
    return name, {k: v for k, v in section['ros__parameters'].items() if k not in required}


def _python(value):
    """Return a parameter value as YAML reads it (an array as a list)."""
    return list(value) if isinstance(value, (list, tuple, array.array)) else value


@pytest.mark.parametrize('node', NODES)
def test_every_node_declares_the_values_of_its_file(tmp_path, ros_domain, node):
    """In-process, as ``main()`` passes them: rclpy.init reads the file, the node declares."""
    executable = node.split('/')[1]
    required = _required(tmp_path).get(executable, {})
    name, values = _file_values(executable, required)
    rclpy.init(args=['--ros-args', '--params-file', str(CONFIG / f'{executable}.yaml'),
                     *_overrides(required)], domain_id=ros_domain)
    try:
        built = node_class(NODES[node])()   # raises what the node refuses
        try:
            assert built.get_name() == name
            assert {k: _python(built.get_parameter(k).value) for k in values} == values
        finally:
            built.destroy_node()
    finally:
        rclpy.try_shutdown()


@pytest.mark.slow
def test_every_executable_starts_with_its_file_and_stops_on_sigint(
        tmp_path, start_node, ros_node, read_output):
    """
    All at once, in real processes: each up (its parameter services), then SIGINT: code 0.

    A node that refused its file would have exited with code 2 (its values are checked
    in-process above: over ``/get_parameters`` a simulator stepping in real time under the load
    of 17 starting processes answered too late).
    """
    probe, _ = ros_node
    required = _required(tmp_path)
    procs = {node.split('/')[1]: start_node(
        *node.split('/'), '--params-file', str(CONFIG / f'{node.split("/")[1]}.yaml'),
        *_overrides(required.get(node.split('/')[1], {}))) for node in NODES}
    for executable, proc in procs.items():
        name, _ = _file_values(executable, required.get(executable, {}))
        client = probe.create_client(GetParameters, f'/{name}/get_parameters')
        assert client.wait_for_service(timeout_sec=60.0), (
            f'{executable}: not up\n{read_output(proc)}')
    for proc in procs.values():
        proc.send_signal(signal.SIGINT)
    deadline = time.monotonic() + 30.0
    for executable, proc in procs.items():
        code = proc.wait(timeout=max(0.1, deadline - time.monotonic()))
        assert code == 0, f'{executable} exited {code}\n{read_output(proc)}'


def test_an_unknown_node_lists_the_nodes(capsys):
    assert run_verb(['params', 'no_such_node']) == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and "unknown node 'no_such_node'" in err
    assert all(n in err for n in NODES)


def test_prints_or_writes_the_file(ros_domain, tmp_path, capsys):
    assert run_verb(['params', 'robotica_kin/fk_node']) == 0
    assert capsys.readouterr().out == (CONFIG / 'fk_node.yaml').read_text()
    assert run_verb(['params', 'fk_node', '-o', str(tmp_path / 'fk.yaml')]) == 0
    assert (tmp_path / 'fk.yaml').read_text() == (CONFIG / 'fk_node.yaml').read_text()
    assert run_verb(['params', 'fk_node', '-o', str(tmp_path / 'none' / 'fk.yaml')]) == 2
    assert 'no directory' in capsys.readouterr().err


def test_a_node_that_refuses_its_defaults_still_gets_its_file(ros_domain, capsys):
    assert run_verb(['params', 'recorder']) == 0
    out, err = capsys.readouterr()
    assert out == (CONFIG / 'recorder.yaml').read_text()
    assert 'refuses its defaults (parameter output' in err
