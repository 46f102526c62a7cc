"""
Fixtures of the robotica_sim tests: a small reference bag written with rosbags.

``bag``: 11 std_msgs/Float64 on /a at 10 Hz (t = 1.0 ... 2.0 s, data 0 ... 10) and 3 on /b at
0.5 Hz (t = 1.0, 3.0, 5.0 s), and the scenario ``SCENARIO`` in the metadata's custom_data, as
the recorder node stores it.
"""
import pytest
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import get_typestore, Stores

SCENARIO = 'name: ej9_3a\ndescription: Ejemplo 9.3 (a)\nseed: 7\npacing: lockstep\n'


@pytest.fixture
def bag(tmp_path):
    store = get_typestore(Stores.ROS2_JAZZY)
    Float64 = store.types['std_msgs/msg/Float64']
    path = tmp_path / 'bag'
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    writer.set_custom_data('robotica.scenario.yaml', SCENARIO)
    a = writer.add_connection('/a', 'std_msgs/msg/Float64', typestore=store)
    b = writer.add_connection('/b', 'std_msgs/msg/Float64', typestore=store)
    for i in range(11):
        writer.write(a, 1_000_000_000 + i * 100_000_000,
                     store.serialize_cdr(Float64(data=float(i)), 'std_msgs/msg/Float64'))
    for t in (1, 3, 5):
        writer.write(b, t * 1_000_000_000,
                     store.serialize_cdr(Float64(data=0.0), 'std_msgs/msg/Float64'))
    writer.close()
    return path
