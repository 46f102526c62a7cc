"""
Every ``package.xml`` declares what its package imports, so that ``rosdep install`` works.

On a full ROS 2 Jazzy install, ``rosdep install --from-paths ros2_ws/src --ignore-src`` reads
the ``package.xml`` files; an import that a manifest does not declare is a dependency that a user
finds only as an ``ImportError`` at run time. This test parses every import of each Python
package with ``ast`` (module code as ``exec_depend``, its ``test/`` folder as ``test_depend``;
an exec dependency also serves the tests) and maps the top-level module to its rosdep key.
"""
import ast
from pathlib import Path
import sys
import xml.etree.ElementTree as ElementTree

import pytest

SRC = Path(__file__).resolve().parents[1] / 'ros2_ws' / 'src'
PACKAGES = ('robotica_kin', 'robotica_ctrl', 'robotica_sim')
# Python modules whose rosdep key is not the module's own name. The ``-pip`` keys are pip-only
# packages (not in Ubuntu): docker/Dockerfile.ros installs them with pip.
ROSDEP_KEYS = {
    'numpy': 'python3-numpy', 'scipy': 'python3-scipy', 'yaml': 'python3-yaml',
    'matplotlib': 'python3-matplotlib', 'pytest': 'python3-pytest',
    'hypothesis': 'python3-hypothesis', 'PIL': 'python3-pil', 'pinocchio': 'pinocchio',
    'rosbags': 'python3-rosbags-pip', 'mcap': 'python3-mcap-pip',
    'foxglove': 'python3-foxglove-sdk-pip', 'websockets': 'python3-websockets-pip',
    'yourdfpy': 'python3-yourdfpy-pip', 'pyarrow': 'python3-pyarrow-pip',
    'distributed': 'python3-distributed', 'psutil': 'python3-psutil',
    'networkx': 'python3-networkx',
}
# Imported by tests from the repository's tests/ folder (pytest.ini's pythonpath), not packages.
REPOSITORY_MODULES = {'reference_models', 'parking_reference', 'conftest'}
DEPEND_TAGS = {'exec': ('depend', 'exec_depend', 'build_export_depend'),
               'test': ('depend', 'exec_depend', 'build_export_depend', 'test_depend')}


def _type_checking_only(tree: ast.Module) -> set[int]:
    """Return the ids of import nodes inside ``if TYPE_CHECKING:`` blocks (never run)."""
    hidden = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and 'TYPE_CHECKING' in ast.unparse(node.test):
            hidden.update(id(inner) for inner in ast.walk(node))
    return hidden


def imported_modules(files) -> dict[str, Path]:
    """Return each third-party top-level module imported by ``files``, with one file using it."""
    found = {}
    for path in files:
        tree = ast.parse(path.read_text(), str(path))
        hidden = _type_checking_only(tree)
        for node in ast.walk(tree):
            if id(node) in hidden:
                continue
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split('.')[0]
                if top not in sys.stdlib_module_names and top not in REPOSITORY_MODULES:
                    found.setdefault(top, path)
    return found


def declared(package: str, kind: str) -> set[str]:
    """Return the rosdep keys the package's manifest declares for ``kind`` (exec or test)."""
    root = ElementTree.parse(SRC / package / 'package.xml').getroot()
    return {element.text.strip() for tag in DEPEND_TAGS[kind] for element in root.iter(tag)}


def _files(package: str, kind: str):
    root = SRC / package
    if kind == 'test':
        return sorted((root / 'test').rglob('*.py'))
    return sorted(path for path in (root / package).rglob('*.py'))


@pytest.mark.parametrize('kind', ('exec', 'test'))
@pytest.mark.parametrize('package', PACKAGES)
def test_every_import_is_declared(package, kind):
    keys = declared(package, kind)
    missing = {ROSDEP_KEYS.get(module, module): str(path.relative_to(SRC))
               for module, path in imported_modules(_files(package, kind)).items()
               if module != package and ROSDEP_KEYS.get(module, module) not in keys}
    assert not missing, f'{package}/package.xml does not declare (key: a file importing it) ' \
                        f'{missing}'


def test_the_check_sees_an_undeclared_import(tmp_path):
    module = tmp_path / 'node.py'
    module.write_text('import os\nimport numpy as np\nfrom geometry_msgs.msg import Twist\n'
                      'from typing import TYPE_CHECKING\n'
                      'if TYPE_CHECKING:\n    from _typeshed import StrPath\n')
    assert set(imported_modules([module])) == {'numpy', 'geometry_msgs'}
