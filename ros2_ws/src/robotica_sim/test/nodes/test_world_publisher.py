"""
Node tests of world_publisher: /map from a world file, latched; a bad file is exit 2.

Reference: a 1 m wall along y = 0.2 m drawn at 0.5 m cells with the 0.5 m margin: the grid
starts at (-0.5, -0.5), 4 x 3 cells, and the wall occupies the 4 cells of the row whose
centres are at y = 0.25 m (each within half a diagonal of it); the others are free.
"""
from nav_msgs.msg import OccupancyGrid
import pytest
from robotica_kin.ros.qos import LATCHED_QOS
from visualization_msgs.msg import Marker, MarkerArray

pytestmark = pytest.mark.ros


def test_publishes_the_world_on_map(tmp_path, start_node, ros_node, spin):
    world = tmp_path / 'scenario.yaml'
    world.write_text('name: w\nworld:\n  walls: [[0.0, 0.2, 1.0, 0.2]]\n')
    start_node('robotica_sim', 'world_publisher', '-p', f'world_file:={world}',
               '-p', 'resolution:=0.5')
    node, executor = ros_node
    maps, markers = [], []
    node.create_subscription(OccupancyGrid, '/map', maps.append, LATCHED_QOS)
    node.create_subscription(MarkerArray, '/world_publisher/markers', markers.append,
                             LATCHED_QOS)
    assert spin(executor, lambda: maps and markers)
    (walls,) = markers[0].markers
    assert walls.type == Marker.LINE_LIST and walls.header.frame_id == 'map'
    assert [(p.x, p.y) for p in walls.points] == [(0.0, 0.2), (1.0, 0.2)]
    grid = maps[0]
    assert grid.header.frame_id == 'map'
    assert (grid.info.width, grid.info.height, grid.info.resolution) == (4, 3, 0.5)
    assert (grid.info.origin.position.x, grid.info.origin.position.y) == (-0.5, -0.5)
    rows = [list(grid.data[4 * i:4 * i + 4]) for i in range(3)]
    assert rows == [[0, 0, 0, 0], [100, 100, 100, 100], [0, 0, 0, 0]]


@pytest.mark.parametrize('value, message', [('', 'parameter world_file is required'),
                                            ('missing.yaml', 'cannot read the world file')])
def test_a_bad_world_file_is_exit_2(tmp_path, start_node, read_output, value, message):
    proc = start_node('robotica_sim', 'world_publisher', '-p',
                      f"world_file:={tmp_path / value if value else repr('')}")
    assert proc.wait(timeout=30) == 2
    out = read_output(proc)
    assert message in out and 'Traceback' not in out
