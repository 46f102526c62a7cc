"""
The versions of the software a run used, stored in its bag (``custom_data``).

The robotica packages' versions come from their installed ``package.xml`` (ament index); the
Python libraries' from their installed distributions (``importlib.metadata``). A package that
is not installed is reported as ``not installed``, never guessed.
"""
from importlib import metadata
from pathlib import Path
import platform
import re

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError

ROBOTICA_PACKAGES = ('robotica_msgs', 'robotica_kin', 'robotica_ctrl', 'robotica_sim',
                     'robotica_native')
DISTRIBUTIONS = ('rclpy', 'pin', 'numpy', 'scipy', 'mcap', 'rosbags', 'matplotlib')
NOT_INSTALLED = 'not installed'


def _ament_version(package: str) -> str:
    try:
        share = Path(get_package_share_directory(package))
    except PackageNotFoundError:
        return NOT_INSTALLED
    match = re.search(r'<version>\s*([^<\s]+)\s*</version>', (share / 'package.xml').read_text())
    return match.group(1) if match else 'unknown'


def _distribution_version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return NOT_INSTALLED


def software_versions() -> dict[str, str]:
    """Return {name: version} of Python, the robotica packages and the libraries they use."""
    versions = {'python': platform.python_version()}
    versions.update({p: _ament_version(p) for p in ROBOTICA_PACKAGES})
    versions.update({d: _distribution_version(d) for d in DISTRIBUTIONS})
    return versions
