"""
Tests of robotica_kin.world.map_file: map_server maps written here and read back cell by cell.

The expected cells are computed in the test from map_server's rules (nav2_map_server map_io),
one pixel at a time in plain Python.
"""

import math

import numpy as np
from PIL import Image
import pytest
from robotica_kin.world import load_map, OccupancyGrid, WorldError, write_map
import yaml


def write_pgm(path, pixels, binary=True):
    height, width = pixels.shape
    if binary:
        path.write_bytes(f'P5\n# a comment\n{width} {height}\n255\n'.encode()
                         + pixels.astype(np.uint8).tobytes())
    else:
        body = '\n'.join(' '.join(str(v) for v in row) for row in pixels)
        path.write_text(f'P2\n{width} {height}\n# comment\n255\n{body}\n')


def write_yaml(path, **fields):
    path.write_text(yaml.safe_dump(fields))
    return path


def expected_cell(value, mode, negate, occupied, free, alpha=255):
    """Return map_server's cell for one 8-bit pixel."""
    shade = value / 255.0
    if mode == 'raw':
        return value if value <= 100 else -1
    p = shade if negate else 1.0 - shade
    if mode == 'scale' and alpha < 255:
        return -1
    if p > occupied:
        return 100
    if p < free:
        return 0
    return -1 if mode == 'trinary' else int(np.rint((p - free) / (occupied - free) * 100.0))


PIXELS = np.arange(0, 256, 5, dtype=np.uint8)[:50].reshape(5, 10)


@pytest.mark.parametrize('mode', ['trinary', 'scale', 'raw'])
@pytest.mark.parametrize('negate', [0, 1])
@pytest.mark.parametrize('binary', [True, False])
def test_threshold_semantics_cell_by_cell(tmp_path, mode, negate, binary):
    write_pgm(tmp_path / 'map.pgm', PIXELS, binary)
    grid = load_map(write_yaml(tmp_path / 'map.yaml', image='map.pgm', resolution=0.05,
                               origin=[-1.0, 2.0, 0.0], negate=negate, occupied_thresh=0.65,
                               free_thresh=0.196, mode=mode))
    assert grid.data.shape == (5, 10)
    for row in range(5):
        for col in range(10):
            # The image's top row is the grid's last row.
            value = int(PIXELS[4 - row, col])
            assert grid.data[row, col] == expected_cell(value, mode, negate, 0.65, 0.196), (
                row, col, value)
    assert grid.resolution == 0.05 and grid.origin == (-1.0, 2.0, 0.0)


def test_png_with_alpha_in_scale_mode(tmp_path):
    rgba = np.zeros((2, 3, 4), np.uint8)
    rgba[..., 0:3] = [[[0, 0, 0], [100, 110, 120], [255, 255, 255]],
                      [[30, 30, 30], [200, 200, 200], [90, 90, 90]]]
    rgba[..., 3] = 255
    rgba[1, 2, 3] = 0
    Image.fromarray(rgba, 'RGBA').save(tmp_path / 'map.png')
    grid = load_map(write_yaml(tmp_path / 'map.yaml', image='map.png', resolution=1.0,
                               origin=[0, 0, 0], negate=0, occupied_thresh=0.65,
                               free_thresh=0.196, mode='scale'))
    for row in range(2):
        for col in range(3):
            value = rgba[row, col, 0:3].mean()
            expected = expected_cell(value, 'scale', 0, 0.65, 0.196, rgba[row, col, 3])
            assert grid.data[1 - row, col] == expected


def test_write_then_load_round_trip(tmp_path):
    rng = np.random.default_rng(5)
    data = rng.choice(np.array([-1, 0, 100], np.int8), (7, 9))
    grid = OccupancyGrid(data, 0.1, (0.5, -0.5, math.pi / 4))
    write_map(grid, tmp_path / 'saved.yaml')
    back = load_map(tmp_path / 'saved.yaml')
    np.testing.assert_array_equal(back.data, data)
    np.testing.assert_array_equal(back.occupied, grid.occupied)
    assert back.origin == pytest.approx(grid.origin)


@pytest.mark.parametrize(('fields', 'message'), [
    ({'image': 'map.pgm', 'origin': [0, 0, 0]}, 'resolution: missing'),
    ({'image': 'other.pgm', 'resolution': 0.1, 'origin': [0, 0, 0]}, 'image: .*not found'),
    ({'resolution': 0.1, 'origin': [0, 0, 0]}, 'image: missing'),
    ({'image': 'map.pgm', 'resolution': -0.1, 'origin': [0, 0, 0]}, 'resolution: must be > 0'),
    ({'image': 'map.pgm', 'resolution': 0.1, 'origin': [0, 0]}, 'origin: must be'),
    ({'image': 'map.pgm', 'resolution': 0.1, 'origin': [0, 0, 0], 'occupied_thresh': 0.2,
      'free_thresh': 0.5}, 'free_thresh, occupied_thresh: must satisfy'),
    ({'image': 'map.pgm', 'resolution': 0.1, 'origin': [0, 0, 0], 'mode': 'binary'},
     'mode: must be one of'),
    ({'image': 'map.pgm', 'resolution': 0.1, 'origin': [0, 0, 0], 'negate': 2},
     'negate: must be 0 or 1'),
    ({'image': 'map.pgm', 'resolution': 'fine', 'origin': [0, 0, 0]},
     'resolution: must be a finite number'),
])
def test_bad_map_file_names_file_and_field(tmp_path, fields, message):
    write_pgm(tmp_path / 'map.pgm', PIXELS)
    path = write_yaml(tmp_path / 'map.yaml', **fields)
    with pytest.raises(WorldError, match=message) as info:
        load_map(path)
    assert str(info.value).startswith(f'{path}: ')


@pytest.mark.parametrize(('content', 'message'), [
    (b'P5\n10 5\n255\n' + bytes(10), 'PGM data ends early'),
    (b'P5 x\n', 'malformed PGM header'),
    (b'\x89PNG not really', 'not an image Pillow can read'),
])
def test_bad_image(tmp_path, content, message):
    (tmp_path / 'map.pgm').write_bytes(content)
    path = write_yaml(tmp_path / 'map.yaml', image='map.pgm', resolution=0.1, origin=[0, 0, 0])
    with pytest.raises(WorldError, match=message):
        load_map(path)


def test_malformed_yaml_and_missing_file(tmp_path):
    (tmp_path / 'bad.yaml').write_text('image: [unclosed\n')
    with pytest.raises(WorldError, match='bad.yaml: malformed YAML'):
        load_map(tmp_path / 'bad.yaml')
    with pytest.raises(WorldError, match='absent.yaml: cannot read the map file'):
        load_map(tmp_path / 'absent.yaml')
