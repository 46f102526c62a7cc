"""Tests of robotica_sim.runs.shipped: a scenario or rubric found by path or shipped name."""
from ament_index_python.packages import PackageNotFoundError
import pytest
from robotica_sim.runs import shipped as shipped_module
from robotica_sim.runs.shipped import resolve_shipped, SHIPPED_KINDS


@pytest.fixture
def share(tmp_path, monkeypatch):
    """Return a fake share directory of robotica_sim with two files of each kind."""
    for kind in SHIPPED_KINDS:
        (tmp_path / f'{kind}s').mkdir()
        for name in ('alpha', 'beta'):
            (tmp_path / f'{kind}s' / f'{name}.yaml').write_text(f'# {kind} {name}\n')
    monkeypatch.setattr(shipped_module, 'get_package_share_directory',
                        lambda package: str(tmp_path))
    return tmp_path


@pytest.mark.parametrize('kind', SHIPPED_KINDS)
def test_a_shipped_name_with_or_without_its_extension(share, kind):
    assert resolve_shipped('alpha', kind) == share / f'{kind}s' / 'alpha.yaml'
    assert resolve_shipped('beta.yaml', kind) == share / f'{kind}s' / 'beta.yaml'


def test_a_path_is_taken_before_a_shipped_name(share, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / 'alpha').write_text('# here\n')
    assert resolve_shipped('alpha', 'rubric').read_text() == '# here\n'
    assert resolve_shipped(str(tmp_path / 'alpha'), 'scenario') == tmp_path / 'alpha'


@pytest.mark.parametrize('kind', SHIPPED_KINDS)
def test_an_unknown_name_lists_the_shipped_ones_of_its_kind(share, kind):
    with pytest.raises(FileNotFoundError) as error:
        resolve_shipped('gamma', kind)
    assert str(error.value) == f"no {kind} file 'gamma'; shipped {kind}s: alpha, beta"


def test_without_an_installed_package_nothing_is_shipped(monkeypatch):
    def not_found(package):
        raise PackageNotFoundError(package)

    monkeypatch.setattr(shipped_module, 'get_package_share_directory', not_found)
    with pytest.raises(FileNotFoundError, match="no rubric file 'ej9_1'; shipped rubrics: "
                                                'none found'):
        resolve_shipped('ej9_1', 'rubric')


def test_an_unknown_kind_is_refused():
    with pytest.raises(ValueError, match='kind must be one of'):
        resolve_shipped('demo', 'map')
