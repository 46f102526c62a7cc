"""Tests of robotica_kin.world.world_file: a world from a map file or a world: section."""
import pytest
from robotica_kin.world import WorldError
from robotica_kin.world.world_file import load_world_file


def test_a_scenario_file_with_a_world_section(tmp_path):
    path = tmp_path / 'scenario.yaml'
    path.write_text('name: x\nworld:\n  walls: [[0, 0, 2, 0]]\n  circles: [[1, 1, 0.25]]\n')
    world = load_world_file(path)
    assert world.segments.tolist() == [[0.0, 0.0, 2.0, 0.0]]
    assert world.circles.tolist() == [[1.0, 1.0, 0.25]]


def test_a_map_server_map(tmp_path):
    (tmp_path / 'room.pgm').write_bytes(b'P5\n2 1\n255\n' + bytes([0, 254]))
    (tmp_path / 'room.yaml').write_text('image: room.pgm\nresolution: 0.5\n'
                                        'origin: [1.0, 2.0, 0.0]\nnegate: 0\n'
                                        'occupied_thresh: 0.65\nfree_thresh: 0.196\n')
    world = load_world_file(tmp_path / 'room.yaml')
    assert world.grid.resolution == 0.5 and world.grid.origin == (1.0, 2.0, 0.0)
    assert world.grid.occupied.tolist() == [[True, False]]   # black occupied, white free


@pytest.mark.parametrize('text, message', [
    ('name: x\n', 'a world file is a map_server map (image: ...) or a YAML file with a world:'),
    ('world: [\n', 'not valid YAML'),
    ('world:\n  walls: [[0, 0, 0, 0]]\n', 'a wall of zero length'),
    ('world:\n  boxes: [{center: [0, 0]}]\n', 'world.boxes[0]'),
])
def test_bad_world_files(tmp_path, text, message):
    path = tmp_path / 'w.yaml'
    path.write_text(text)
    with pytest.raises(WorldError, match='w.yaml') as err:
        load_world_file(path)
    assert message in str(err.value)
    with pytest.raises(WorldError, match='cannot read the world file'):
        load_world_file(tmp_path / 'missing.yaml')
