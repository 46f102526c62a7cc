"""
A world from a file: a map_server map, or a YAML file with a ``world:`` section.

The nodes that need the world (the simulator's contact, the range sensors, the map publisher)
take one parameter, ``world_file``: either a map in the map_server format (a YAML file with
``image:``, :func:`robotica_kin.world.map_file.load_map`) or any YAML file whose top-level
``world:`` key is a world section (:func:`robotica_kin.world.world_section.world_from_mapping`),
such as a scenario file itself: a run passes its scenario. Paths inside are relative to the
file's folder.
"""
from pathlib import Path
from typing import Union

from robotica_kin.world.errors import WorldError
from robotica_kin.world.map_file import load_map
from robotica_kin.world.shapes import World
from robotica_kin.world.world_section import world_from_mapping
import yaml

__all__ = ['load_world_file']


def load_world_file(path: Union[str, Path]) -> World:
    """
    Return the World of ``path`` (a map_server YAML, or a YAML with a ``world:`` section).

    Raises
    ------
    WorldError
        One line naming the file: not found or not readable, not YAML, neither ``image:`` nor
        ``world:`` at its top level, or what the map or the section refuses.

    """
    file = Path(path)
    try:
        data = yaml.safe_load(file.read_text(encoding='utf-8'))
    except (OSError, UnicodeDecodeError) as err:
        raise WorldError(f'{file}: cannot read the world file: '
                         f'{getattr(err, "strerror", None) or err}') from None
    except yaml.YAMLError as err:
        raise WorldError(f'{file}: not valid YAML: {" ".join(str(err).split())}') from None
    if isinstance(data, dict) and 'image' in data:
        return World(grid=load_map(file))
    if not isinstance(data, dict) or 'world' not in data:
        raise WorldError(f'{file}: a world file is a map_server map (image: ...) or a YAML '
                         'file with a world: section')
    return world_from_mapping(data['world'], file.parent, f'{file}: world')
