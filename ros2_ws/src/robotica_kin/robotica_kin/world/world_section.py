"""
A scenario's ``world:`` section as a World: the keys, their shapes, strictly checked.

::

    world:
      map: maps/office.yaml          # a map_server map, relative to the scenario's folder
      walls: [[0, 0, 10, 0], ...]    # [x1, y1, x2, y2] [m]
      boxes: [{center: [2, 3], size: [1, 0.5], yaw: 0.3}]   # [m], [m], [rad] (yaw optional)
      polygons: [[[0, 0], [1, 0], [0, 1]], ...]             # vertices [m], >= 3, simple
      circles: [[5, 5, 0.4], ...]    # [cx, cy, r] [m]

Every key is optional; an unknown key or a value of the wrong shape raises WorldError naming
it (``world.boxes[2].size: ...``), a bad map file names the file and its field.
"""

from pathlib import Path
from typing import Any

from robotica_kin.world.errors import WorldError
from robotica_kin.world.map_file import load_map
from robotica_kin.world.shapes import box_polygon, make_world, World

__all__ = ['WORLD_KEYS', 'world_from_mapping']

WORLD_KEYS = ('map', 'walls', 'boxes', 'polygons', 'circles')
_BOX_KEYS = ('center', 'size', 'yaw')


def _list(value: Any, where: str) -> list[Any]:
    if not isinstance(value, list):
        raise WorldError(f'{where}: must be a list, got {value!r}')
    return value


def world_from_mapping(data: Any, folder: Path, where: str = 'world') -> World:
    """
    Return the World of a scenario's parsed ``world:`` mapping; a map path is under ``folder``.

    >>> world = world_from_mapping({'walls': [[0, 0, 1, 0]], 'circles': [[2, 2, 0.5]]}, Path())
    >>> world.segments.shape, world.circles.shape
    ((1, 4), (1, 3))
    >>> world_from_mapping({'boxes': [{'center': [0, 0], 'size': [1, -1]}]}, Path())
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    robotica_kin.world.errors.WorldError: world.boxes[0].size: width and height must be > 0...
    """
    if data is None:
        return World()
    if not isinstance(data, dict):
        raise WorldError(f'{where}: must be a mapping of {", ".join(WORLD_KEYS)}, got {data!r}')
    unknown = sorted(set(data) - set(WORLD_KEYS), key=str)
    if unknown:
        raise WorldError(f'{where}.{unknown[0]}: unknown key (known: {", ".join(WORLD_KEYS)})')
    grid = None
    if 'map' in data:
        name = data['map']
        if not isinstance(name, str) or not name:
            raise WorldError(f'{where}.map: must be a map file name, got {name!r}')
        try:
            grid = load_map(Path(folder) / name)
        except WorldError as err:
            raise WorldError(f'{where}.map: {err}') from err
    boxes = []
    for k, box in enumerate(_list(data.get('boxes', []), f'{where}.boxes')):
        at = f'{where}.boxes[{k}]'
        if not isinstance(box, dict):
            raise WorldError(f'{at}: must be a mapping of center, size, yaw, got {box!r}')
        extra = sorted(set(box) - set(_BOX_KEYS), key=str)
        if extra:
            raise WorldError(f'{at}.{extra[0]}: unknown key (known: {", ".join(_BOX_KEYS)})')
        for key in ('center', 'size'):
            if key not in box:
                raise WorldError(f'{at}.{key}: missing')
        boxes.append(box_polygon(box['center'], box['size'], box.get('yaw', 0.0), at))
    walls = _list(data.get('walls', []), f'{where}.walls')
    circles = _list(data.get('circles', []), f'{where}.circles')
    polygons = _list(data.get('polygons', []), f'{where}.polygons')
    try:
        world = make_world(walls=walls, polygons=polygons, circles=circles, grid=grid)
    except WorldError as err:
        raise WorldError(f'{where}.{err}') from err
    return World(walls=world.walls, circles=world.circles,
                 polygons=world.polygons + tuple(boxes), grid=grid)
