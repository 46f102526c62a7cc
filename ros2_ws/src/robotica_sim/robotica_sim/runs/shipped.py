"""
Files shipped with robotica_sim: a scenario or rubric named without its folder or extension.

The package installs its scenarios and rubrics as YAML files under
``share/robotica_sim/scenarios`` and ``share/robotica_sim/rubrics``, so that ``robotica run
demo`` and ``robotica grade BAG --rubric ej9_1`` name them. :func:`resolve_shipped` is the one
place that turns such a name, or a path, into a file.
"""
from pathlib import Path

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError

__all__ = ['SHIPPED_KINDS', 'resolve_shipped']

SHIPPED_KINDS = ('scenario', 'rubric')
"""The kinds of shipped file; each lives in the share folder named by its plural."""


def resolve_shipped(name_or_path: str, kind: str) -> Path:
    """
    Return the file of a ``kind`` given as a path or as the name of a shipped one.

    A path to an existing file is taken as it is, before any shipped name; else
    ``share/robotica_sim/<kind>s/<name>`` and then ``<name>.yaml`` there.

    Parameters
    ----------
    name_or_path : str
        A file path, or a shipped file's name with or without ``.yaml``.
    kind : str
        One of :data:`SHIPPED_KINDS`.

    Returns
    -------
    Path
        The file.

    Raises
    ------
    FileNotFoundError
        If there is no such file; the message lists the shipped names (``none found`` when
        the package is not installed): ``no rubric file 'x'; shipped rubrics: ej9_1, ...``.
    ValueError
        If ``kind`` is not one of :data:`SHIPPED_KINDS`.

    """
    if kind not in SHIPPED_KINDS:
        raise ValueError(f'kind must be one of {SHIPPED_KINDS}, got {kind!r}')
    path = Path(name_or_path)
    if path.is_file():
        return path
    try:
        folder: Path | None = Path(get_package_share_directory('robotica_sim')) / f'{kind}s'
    except PackageNotFoundError:
        folder = None
    if folder is not None:
        for candidate in (folder / name_or_path, folder / f'{name_or_path}.yaml'):
            if candidate.is_file():
                return candidate
    names = sorted(p.stem for p in folder.glob('*.yaml')) if folder else []
    raise FileNotFoundError(f'no {kind} file {name_or_path!r}; shipped {kind}s: '
                            f'{", ".join(names) or "none found"}')
