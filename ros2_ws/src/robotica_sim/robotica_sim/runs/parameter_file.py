"""
A node's declared parameters as a ROS 2 parameter file, with descriptions and ranges as comments.

The file is the one ``--ros-args --params-file FILE`` reads (and ``ros2 param dump`` writes)::

    odometry:
      ros__parameters:
        # Wheel radius r [m]
        # range [0.001, 10.0]; read-only
        wheel_radius: 0.1

Each parameter is a :class:`DeclaredParameter`, the plain data of a ``ParameterDescriptor``
and its value (``robotica params`` reads them from the node class, so that the file cannot
drift from what the node declares). Values are written as YAML reads them back into the same
ROS type: a float keeps its decimal point (``1.0``, not ``1``: rclpy refuses an integer for a
double parameter), a list is a flow sequence.
"""
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import yaml


@dataclass(frozen=True)
class DeclaredParameter:
    """One declared parameter: name, value and what its descriptor says."""

    name: str
    value: Any                    # None: declared without a value (unset)
    description: str = ''
    low: Optional[float] = None   # inclusive range of a number (both or neither)
    high: Optional[float] = None
    step: float = 0.0             # 0: any value in the range
    read_only: bool = False
    type_name: str = ''           # of an unset parameter, e.g. 'double array'


def range_text(parameter: DeclaredParameter) -> str:
    """
    Return the comment line of ``parameter``'s range, step and read-only flag ('' if none).

    >>> range_text(DeclaredParameter('port', 8765, low=0, high=65535, read_only=True))
    'range [0, 65535]; read-only'
    >>> range_text(DeclaredParameter('n', 4, low=0, high=8, step=2))
    'range [0, 8], step 2'
    >>> range_text(DeclaredParameter('frame_id', 'odom'))
    ''
    """
    parts = []
    if parameter.low is not None and parameter.high is not None:
        parts.append(f'range [{parameter.low!r}, {parameter.high!r}]'
                     + (f', step {parameter.step!r}' if parameter.step else ''))
    if parameter.read_only:
        parts.append('read-only')
    return '; '.join(parts)


def parameter_file(node_name: str, parameters: Sequence[DeclaredParameter],
                   header: str = '') -> str:
    """
    Return the parameter file of node ``node_name``: one entry per parameter, in the given order.

    Each entry is preceded by its description (one comment line per line of it) and its range;
    a parameter without a value is a comment line. ``header`` (lines) opens the file as comments.

    >>> print(parameter_file('tracker', [DeclaredParameter(
    ...     'lookahead_distance', 0.5, 'Look-ahead distance L [m]', 0.01, 100.0),
    ...     DeclaredParameter('joint_names', None, 'Joint names', type_name='string array')]),
    ...     end='')
    tracker:
      ros__parameters:
        # Look-ahead distance L [m]
        # range [0.01, 100.0]
        lookahead_distance: 0.5
        # Joint names
        # joint_names: <string array, unset by default>
    """
    lines = [f'# {line}'.rstrip() for line in header.splitlines()]
    lines += [f'{node_name}:', '  ros__parameters:']
    for parameter in parameters:
        comments = parameter.description.splitlines() + [range_text(parameter)]
        lines += [f'    # {c}'.rstrip() for c in comments if c.strip()]
        if parameter.value is None:   # the node has no default: shown, commented out
            lines.append(f'    # {parameter.name}: <{parameter.type_name}, unset by default>')
        else:
            lines.append('    ' + _entry(parameter.name, parameter.value))
    return '\n'.join(lines) + '\n'


def _entry(name: str, value: Any) -> str:
    """Return ``name: value`` on one line, a list as a flow sequence."""
    text = yaml.safe_dump(value, default_flow_style=True, width=float('inf'), allow_unicode=True)
    return f'{name}: ' + text.removesuffix('...\n').strip()
