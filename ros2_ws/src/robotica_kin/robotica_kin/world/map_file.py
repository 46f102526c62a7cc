"""
Map files in the map_server format (ROS 1 map_server, Nav2's nav2_map_server): YAML + image.

The YAML names ``image`` (relative to the YAML's folder), ``resolution`` [m/cell], ``origin``
[x, y, yaw] (the pose of the image's lower-left pixel in the map frame [m, rad]), and
optionally ``negate`` (0), ``occupied_thresh`` (0.65), ``free_thresh`` (0.196) and ``mode``
(``trinary``, ``scale`` or ``raw``; trinary by default). Other keys are ignored, as Nav2 does.
Each pixel's shade s in [0, 1] (the mean of its colour channels over the image's maximum; the
top image row is the grid's last row) gives the occupancy p = 1 - s (p = s with negate), and
the cell, as map_server does:

* ``trinary``: 100 if p > occupied_thresh, 0 if p < free_thresh, else -1 (unknown);
* ``scale``: as trinary, but a pixel that is not opaque is unknown and p between the
  thresholds becomes rint(100 (p - free) / (occupied - free));
* ``raw``: the pixel value itself (0..255) if it is 0..100, else -1 (no negate).

The grid's binary view counts 100 as occupied (``occupied_thresh`` 1.0: the cells
map_server marks occupied) for trinary and scale, and the YAML's ``occupied_thresh`` of the
raw values for raw. PGM images (P5 binary, P2 text, 8 or 16 bit) are parsed with NumPy; any
other format (PNG, BMP, ...) with Pillow. :func:`write_map` writes map_saver's trinary PGM
(occupied 0, free 254, unknown 205) and its YAML. Every error is a WorldError naming the
file and the field.
"""

from pathlib import Path
import re
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import NDArray
from robotica_kin.world.errors import WorldError
from robotica_kin.world.occupancy_grid import OccupancyGrid
import yaml

__all__ = ['MODES', 'load_map', 'read_image', 'write_map']

MODES = ('trinary', 'scale', 'raw')
_PGM_HEADER = re.compile(rb'\A(P[25])(?:\s|#[^\n]*\n)+(\d+)(?:\s|#[^\n]*\n)+(\d+)'
                         rb'(?:\s|#[^\n]*\n)+(\d+)\s')


def _read_pgm(path: Path, raw: bytes) -> NDArray[np.float64]:
    match = _PGM_HEADER.match(raw)
    if match is None:
        raise WorldError(f'{path}: image: a malformed PGM header')
    kind, width, height, maxval = match.group(1), *(int(g) for g in match.groups()[1:])
    if width == 0 or height == 0 or not 0 < maxval < 65536:
        raise WorldError(f'{path}: image: PGM size {width}x{height}, maxval {maxval}')
    body = raw[match.end():]
    if kind == b'P5':
        dtype = np.dtype('>u2') if maxval > 255 else np.dtype(np.uint8)
        count = width * height
        if len(body) < count * dtype.itemsize:
            raise WorldError(f'{path}: image: PGM data ends early ({len(body)} bytes for '
                             f'{width}x{height})')
        values = np.frombuffer(body, dtype=dtype, count=count).astype(np.float64)
    else:
        try:
            values = np.array(body.split(), dtype=np.float64)
        except ValueError as err:
            raise WorldError(f'{path}: image: PGM text data is not numbers') from err
        if values.size != width * height:
            raise WorldError(f'{path}: image: PGM holds {values.size} values for '
                             f'{width}x{height}')
    return values.reshape(height, width) / maxval


def read_image(path: Union[str, Path]
               ) -> tuple[NDArray[np.float64], Optional[NDArray[np.float64]]]:
    """
    Return an image's shade (h, w) in [0, 1] (channel mean) and its alpha (h, w) or None.

    Row 0 is the image's top row. PGM is parsed here; other formats need Pillow.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise WorldError(f'{path}: image: cannot read ({err.strerror})') from err
    if raw[:2] in (b'P5', b'P2'):
        return _read_pgm(path, raw), None
    from PIL import Image, UnidentifiedImageError
    try:
        with Image.open(path) as opened:
            image: Image.Image = opened
            if image.mode not in ('L', 'LA', 'RGB', 'RGBA'):
                image = image.convert('RGBA' if 'A' in image.getbands() or
                                      'transparency' in image.info else 'RGB')
            pixels = np.asarray(image, dtype=np.float64) / 255.0
    except (UnidentifiedImageError, OSError) as err:
        raise WorldError(f'{path}: image: not an image Pillow can read ({err})') from err
    if pixels.ndim == 2:
        return pixels, None
    channels = pixels.shape[2]
    has_alpha = channels in (2, 4)
    colour = pixels[..., :channels - 1] if has_alpha else pixels
    return colour.mean(axis=2), (pixels[..., -1] if has_alpha else None)


def _number(path: Path, data: dict[str, Any], key: str, default: Optional[float]) -> float:
    if key not in data:
        if default is None:
            raise WorldError(f'{path}: {key}: missing')
        return default
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise WorldError(f'{path}: {key}: must be a finite number, got {value!r}')
    return float(value)


def _cells(shade: NDArray[np.float64], alpha: Optional[NDArray[np.float64]], negate: bool,
           mode: str, occupied: float, free: float) -> NDArray[np.int8]:
    """Return map_server's cell values for the image (top row first)."""
    if mode == 'raw':
        value = np.rint(shade * 255.0)
        return np.where(value <= 100.0, value, -1.0).astype(np.int8)
    p = shade if negate else 1.0 - shade
    cells = np.full(p.shape, -1.0)
    if mode == 'scale':
        cells = np.rint((p - free) / (occupied - free) * 100.0)
    cells = np.where(p > occupied, 100.0, np.where(p < free, 0.0, cells))
    if mode == 'scale' and alpha is not None:
        cells = np.where(alpha < 1.0, -1.0, cells)
    return cells.astype(np.int8)


def load_map(path: Union[str, Path]) -> OccupancyGrid:
    """
    Return the occupancy grid of a map_server map (YAML + image), as map_server reads it.

    Raises WorldError naming the file and the field: unreadable or malformed YAML, a missing
    image, resolution or origin, a bad value, free_thresh >= occupied_thresh, an unknown mode,
    an image that cannot be read.
    """
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as err:
        raise WorldError(f'{path}: cannot read the map file ({err.strerror})') from err
    except yaml.YAMLError as err:
        raise WorldError(f'{path}: malformed YAML ({err})') from err
    if not isinstance(data, dict):
        raise WorldError(f'{path}: a map file must be a YAML mapping')
    image = data.get('image')
    if not isinstance(image, str) or not image:
        raise WorldError(f'{path}: image: missing or not a file name ({image!r})')
    resolution = _number(path, data, 'resolution', None)
    if resolution <= 0.0:
        raise WorldError(f'{path}: resolution: must be > 0 m/cell, got {resolution!r}')
    origin = data.get('origin')
    if (not isinstance(origin, list) or len(origin) != 3 or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)
            for v in origin)):
        raise WorldError(f'{path}: origin: must be [x, y, yaw] (finite), got {origin!r}')
    occupied = _number(path, data, 'occupied_thresh', 0.65)
    free = _number(path, data, 'free_thresh', 0.196)
    if not 0.0 <= free < occupied <= 1.0:
        raise WorldError(f'{path}: free_thresh, occupied_thresh: must satisfy 0 <= free_thresh'
                         f' < occupied_thresh <= 1, got {free} and {occupied}')
    negate = data.get('negate', 0)
    if negate not in (0, 1) or isinstance(negate, float):
        raise WorldError(f'{path}: negate: must be 0 or 1, got {negate!r}')
    mode = data.get('mode', 'trinary')
    if mode not in MODES:
        raise WorldError(f'{path}: mode: must be one of {", ".join(MODES)}, got {mode!r}')
    image_path = path.parent / image
    if not image_path.is_file():
        raise WorldError(f'{path}: image: {image_path} not found')
    shade, alpha = read_image(image_path)
    cells = _cells(shade, alpha, bool(negate), mode, occupied, free)
    origin_xyz = (float(origin[0]), float(origin[1]), float(origin[2]))
    if mode == 'raw':
        return OccupancyGrid(np.flipud(cells), resolution, origin_xyz, occupied, free)
    return OccupancyGrid(np.flipud(cells), resolution, origin_xyz, 1.0, free)


def write_map(grid: OccupancyGrid, path: Union[str, Path]) -> Path:
    """
    Write ``grid`` as map_saver does: a trinary PGM beside the YAML ``path``; return its path.

    Occupied cells (the binary view) are 0, cells of occupancy below 19.6 % are free (254),
    the rest unknown (205); the YAML has mode trinary, negate 0, occupied_thresh 0.65 and
    free_thresh 0.196, so that :func:`load_map` reads back 100, 0 and -1.
    """
    path = Path(path)
    image = path.with_suffix('.pgm')
    pixels = np.where(grid.occupied, 0, np.where((grid.data >= 0) & (grid.data < 19.6),
                                                 254, 205)).astype(np.uint8)
    header = f'P5\n# robotica write_map\n{grid.width} {grid.height}\n255\n'.encode()
    image.write_bytes(header + np.flipud(pixels).tobytes())
    x, y, yaw = grid.origin
    path.write_text(yaml.safe_dump({
        'image': image.name, 'mode': 'trinary', 'resolution': grid.resolution,
        'origin': [x, y, yaw], 'negate': 0, 'occupied_thresh': 0.65, 'free_thresh': 0.196,
    }, sort_keys=False))
    return image
