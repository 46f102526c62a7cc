"""Style check of this package with ament_flake8 (line 99, single quotes, Google imports)."""
from pathlib import Path

from ament_flake8.main import main_with_errors
import pytest


@pytest.mark.flake8
@pytest.mark.linter
def test_flake8():
    package_dir = Path(__file__).resolve().parents[1]
    rc, errors = main_with_errors(argv=[str(package_dir)])
    assert rc == 0, f'Found {len(errors)} code style errors / warnings:\n' + '\n'.join(errors)
