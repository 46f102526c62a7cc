"""
The templates of users' nodes that robotica ships: one per role (docs/your_node.md).

For each role of :data:`robotica_sim.runs.roles.ROLES` the package installs, under
``share/robotica_sim/templates``, ``<role>.py`` (a working node in plain rclpy that keeps the
role's contract), ``<role>.yaml`` (a scenario that runs it in that role) and
``<role>_rubric.yaml`` (the rubric it passes). Their own name, ``my_<role>``, is the node's,
the files' and the scenario's; :func:`render_template` gives the three files for another name
(``robotica new``, ``robotica assignment init``).
"""
from pathlib import Path
import re

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
from robotica_sim.runs.roles import ROLES

__all__ = ['NODE_NAME', 'render_template', 'template_folder']

NODE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]{0,62}')
"""A name for a user's node and its files: a ROS node name and a Python module name."""
_FILES = {'.py': '{name}.py', '.yaml': '{name}.yaml', '_rubric.yaml': '{name}_rubric.yaml'}


def template_folder() -> Path:
    """
    Return the folder of the shipped templates (``share/robotica_sim/templates``).

    Raises OSError when the package is not installed.
    """
    try:
        return Path(get_package_share_directory('robotica_sim')) / 'templates'
    except PackageNotFoundError:
        raise OSError('package robotica_sim is not installed: source scripts/env.sh '
                      '(or your workspace) first') from None


def render_template(role: str, name: str) -> dict[str, str]:
    """
    Return the template files of ``role`` for a node called ``name``: {file name: text}.

    The files are ``<name>.py``, ``<name>.yaml`` and ``<name>_rubric.yaml``; the template's
    own name, ``my_<role>``, becomes ``name`` in each.

    Raises
    ------
    ValueError
        If ``role`` is not a role or ``name`` does not match :data:`NODE_NAME`.
    OSError
        If the templates cannot be read.

    """
    if role not in ROLES:
        raise ValueError(f'no role {role!r}; the roles: {", ".join(ROLES)}')
    if not NODE_NAME.fullmatch(name):
        raise ValueError(f'must be a letter followed by letters, digits or _ (at most 63), '
                         f'got {name!r}')
    folder = template_folder()
    return {pattern.format(name=name): (folder / f'{role}{suffix}').read_text().replace(
        f'my_{role}', name) for suffix, pattern in _FILES.items()}
