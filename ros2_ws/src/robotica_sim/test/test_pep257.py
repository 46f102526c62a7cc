"""Docstring check of this package with ament_pep257."""
from pathlib import Path

from ament_pep257.main import main
import pytest


@pytest.mark.linter
@pytest.mark.pep257
def test_pep257():
    package_dir = Path(__file__).resolve().parents[1]
    rc = main(argv=[str(package_dir)])
    assert rc == 0, 'Found code style errors / warnings'
