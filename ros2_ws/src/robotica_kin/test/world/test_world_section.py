"""Tests of robotica_kin.world.world_section: a scenario's ``world:`` mapping, strictly."""

import numpy as np
import pytest
from robotica_kin.world import OccupancyGrid, world_from_mapping, WorldError, write_map
import yaml


def test_every_key(tmp_path):
    (tmp_path / 'maps').mkdir()
    write_map(OccupancyGrid(np.zeros((4, 4), np.int8), 0.5), tmp_path / 'maps' / 'm.yaml')
    section = yaml.safe_load("""
        map: maps/m.yaml
        walls: [[0, 0, 10, 0]]
        boxes: [{center: [2, 3], size: [1, 0.5], yaw: 0.3}, {center: [5, 5], size: [1, 1]}]
        polygons: [[[0, 0], [1, 0], [0, 1]]]
        circles: [[5, 5, 0.4]]
    """)
    world = world_from_mapping(section, tmp_path)
    assert world.walls.shape == (1, 4) and world.circles.shape == (1, 3)
    assert len(world.polygons) == 3
    assert world.segments.shape == (1 + 3 + 4 + 4, 4)
    assert world.grid is not None and world.grid.data.shape == (4, 4)


def test_empty_section_is_an_empty_world(tmp_path):
    assert world_from_mapping(None, tmp_path).segments.shape == (0, 4)
    assert world_from_mapping({}, tmp_path).grid is None


@pytest.mark.parametrize(('section', 'message'), [
    ({'wall': []}, r'^world.wall: unknown key'),
    ([1, 2], '^world: must be a mapping'),
    ({'walls': [[0, 0, 1]]}, r'^world.walls: must have shape \(n, 4\)'),
    ({'walls': 'none'}, '^world.walls: must be a list'),
    ({'boxes': [{'center': [0, 0], 'size': [1, 1]}, {'center': [0, 0]}] * 2},
     r'^world.boxes\[1\].size: missing'),
    ({'boxes': [{'center': [0, 0], 'size': [1, 1], 'colour': 'red'}]},
     r'^world.boxes\[0\].colour: unknown key'),
    ({'boxes': [0, 0, {'center': [0, 0], 'size': [1, 0]}]},
     r'^world.boxes\[0\]: must be a mapping'),
    ({'polygons': [[[0, 0], [1, 1], [1, 0], [0, 1]]]},
     r'^world.polygons\[0\]: self-intersecting'),
    ({'polygons': [[[0, 0], [1, 1]]]}, r'^world.polygons\[0\]: a polygon needs at least 3'),
    ({'circles': [[0, 0, 0.0]]}, r'^world.circles\[0\]: radius must be > 0 m'),
    ({'map': 'absent.yaml'}, '^world.map: .*absent.yaml: cannot read the map file'),
    ({'map': 3}, '^world.map: must be a map file name'),
])
def test_bad_section_names_the_key(tmp_path, section, message):
    with pytest.raises(WorldError, match=message):
        world_from_mapping(section, tmp_path)


def test_box_size_error_names_its_index(tmp_path):
    boxes = [{'center': [0, 0], 'size': [1, 1]}] * 2 + [{'center': [0, 0], 'size': [1, -2]}]
    with pytest.raises(WorldError, match=r'^world.boxes\[2\].size: width and height'):
        world_from_mapping({'boxes': boxes}, tmp_path)
