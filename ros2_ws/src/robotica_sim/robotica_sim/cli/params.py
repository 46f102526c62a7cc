"""
Print a node's parameters as a ROS 2 parameter file, descriptions and ranges as comments.

The file is what ``ros2 run PKG NODE --ros-args --params-file FILE`` reads: every parameter the
node declares, at its default value, each preceded by its description and range, generated
from the node's declared descriptors (they cannot drift apart). ``config/`` holds one per node.
NODE is ``PKG/EXECUTABLE`` or, when no other package has it, the executable alone.

The node class is built in-process, on a context whose discovery is off (nothing reaches the
ROS graph), and its parameters are read from it, as ``ros2 param dump`` reads them from a
running node but without a process to start and discover (a few milliseconds, not 1-2 s). A
node that refuses its defaults (the recorder needs an ``output``) still declares them first:
its file is written and the refusal is noted on stderr. rclpy's own parameters
(``use_sim_time``, ...) are left out: every node has them.
"""
import argparse
import array
import importlib
from importlib.metadata import entry_points
import inspect
import os
from pathlib import Path
import sys
from typing import Any, Optional

from robotica_sim.cli.main import one_line
from robotica_sim.cli.options import output_problem, path
from robotica_sim.runs.parameter_file import DeclaredParameter, parameter_file

HELP = "print a node's parameters as a parameter file (--params-file), with their ranges"
EPILOG = """examples:
  robotica params path_tracker
  robotica params robotica_sim/odometry -o odometry.yaml
  ros2 run robotica_sim odometry --ros-args --params-file odometry.yaml
"""
PACKAGES = ('robotica_kin', 'robotica_ctrl', 'robotica_sim')


def node_executables() -> dict[str, str]:
    """Return every node executable, ``PKG/EXECUTABLE`` -> ``module:main`` (its entry point)."""
    nodes = {}
    for entry in entry_points(group='console_scripts'):
        package = entry.value.split('.')[0]
        if package in PACKAGES and entry.module.startswith(f'{package}.nodes.'):
            nodes[f'{package}/{entry.name}'] = entry.value
    return dict(sorted(nodes.items()))


def resolve_node(name: str, nodes: dict[str, str]) -> Optional[str]:
    """
    Return the ``PKG/EXECUTABLE`` that ``name`` means, None if none or several do.

    >>> nodes = {'a/x': 'a.nodes.x:main', 'b/x': 'b.nodes.x:main', 'b/y': 'b.nodes.y:main'}
    >>> resolve_node('y', nodes), resolve_node('a/x', nodes), resolve_node('x', nodes)
    ('b/y', 'a/x', None)
    """
    if name in nodes:
        return name
    matches = [key for key in nodes if key.split('/')[1] == name]
    return matches[0] if len(matches) == 1 else None


def node_class(entry_point: str) -> type:
    """Return the node class of a node executable's module (the one rclpy Node it defines)."""
    from rclpy.node import Node
    module = importlib.import_module(entry_point.split(':')[0])
    classes = [c for c in vars(module).values() if inspect.isclass(c)
               and issubclass(c, Node) and c.__module__ == module.__name__]
    if len(classes) != 1:
        raise RuntimeError(f'{module.__name__} defines {len(classes)} node classes, not one')
    return classes[0]


def _plain(value: Any) -> Any:
    """Return a parameter value as YAML writes it (an array as a list)."""
    return list(value) if isinstance(value, (list, tuple, array.array)) else value


def declared_parameters(cls: type) -> tuple[str, list[DeclaredParameter], str]:
    """
    Build node class ``cls`` with its defaults; return its name, parameters and refusal.

    The refusal is '' or why the node refused its defaults (after declaring its parameters).
    rclpy is initialised here, with discovery off, and shut down before returning.
    """
    import rclpy
    from rclpy.exceptions import ParameterException
    from rclpy.node import Node

    discovery = os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE')
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'OFF'
    try:
        rclpy.init(args=['--ros-args', '--log-level', 'warn'])   # not the nodes' start-up lines
    finally:
        if discovery is None:
            del os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE']
        else:
            os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = discovery
    try:
        bare = Node('robotica_params')
        builtin = set(bare.list_parameters([], 0).names)
        bare.destroy_node()
        node = cls.__new__(cls)
        refusal = ''
        try:
            node.__init__()
        except (ValueError, ParameterException) as err:
            if not node.__dict__.get('_parameters'):   # refused before it declared anything
                raise
            refusal = one_line(str(err))
        names = [n for n in node.list_parameters([], 0).names if n not in builtin]
        parameters = [_declared(name, node, descriptor)
                      for name, descriptor in zip(names, node.describe_parameters(names))]
        name = node.get_name()
        (Node.destroy_node if refusal else cls.destroy_node)(node)
        return name, parameters, refusal
    finally:
        rclpy.try_shutdown()


def _declared(name: str, node: Any, descriptor: Any) -> DeclaredParameter:
    """Return the plain data of ``node``'s parameter ``name`` and its ``ParameterDescriptor``."""
    from rclpy.exceptions import ParameterUninitializedException
    from rclpy.parameter import Parameter
    try:
        value = _plain(node.get_parameter(name).value)
    except ParameterUninitializedException:   # declared with a type, no value
        value = None
    ranges = list(descriptor.floating_point_range) or list(descriptor.integer_range)
    bounds = ranges[0] if ranges else None
    return DeclaredParameter(
        name=name, value=value, description=descriptor.description,
        low=bounds.from_value if bounds else None, high=bounds.to_value if bounds else None,
        step=bounds.step if bounds else 0.0, read_only=descriptor.read_only,
        type_name=Parameter.Type(descriptor.type).name.lower().replace('_', ' '))


def node_parameter_file(node: str, entry_point: str) -> tuple[str, str]:
    """Return the parameter file of node executable ``node`` (``PKG/EXECUTABLE``), refusal."""
    name, parameters, refusal = declared_parameters(node_class(entry_point))
    package, executable = node.split('/')
    header = (f'{node}: its parameters at their defaults, generated by\n'
              f'`robotica params {node}` from the descriptors the node declares.\n'
              f'Use: ros2 run {package} {executable} --ros-args --params-file {executable}.yaml\n'
              'The key is the node name; "/**:" matches any name (a remapped node).')
    return parameter_file(name, parameters, header), refusal


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica params``."""
    parser.add_argument('node', metavar='NODE',
                        help='PKG/EXECUTABLE, or EXECUTABLE when one package has it')
    parser.add_argument('--output', '-o', type=path, metavar='FILE',
                        help='write the file here (default: print it)')


def main(args: argparse.Namespace) -> int:
    """Print or write the node's parameter file; return the exit code."""
    nodes = node_executables()
    node = resolve_node(args.node, nodes)
    if node is None:
        known = 'ambiguous' if args.node in [k.split('/')[1] for k in nodes] else 'unknown'
        print(f'robotica params: error: {known} node {args.node!r}; nodes: {" ".join(nodes)}',
              file=sys.stderr)
        return 2
    problem = args.output and output_problem(args.output)
    if problem:
        print(f'robotica params: error: cannot write {args.output}: {problem}', file=sys.stderr)
        return 2
    text, refusal = node_parameter_file(node, nodes[node])
    if refusal:
        print(f'robotica params: note: {node} refuses its defaults ({refusal}): set it in the '
              'file', file=sys.stderr)
    if args.output:
        Path(args.output).write_text(text)
    else:
        print(text, end='')
    return 0
