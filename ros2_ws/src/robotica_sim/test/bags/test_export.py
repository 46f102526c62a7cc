"""Tests of the bag export: tables read back with the csv module and pyarrow, not our code."""
import csv
import json
import subprocess
import sys

import numpy as np
import pyarrow.parquet as pq
import pytest
from robotica_sim.bags.export import export_bag, ExportError
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import get_typestore, Stores

STORE = get_typestore(Stores.ROS2_JAZZY)
T = STORE.types
ODOM, JOINTS, TF = 'nav_msgs/msg/Odometry', 'sensor_msgs/msg/JointState', 'tf2_msgs/msg/TFMessage'


def _odometry(k: int):
    header = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
        sec=k, nanosec=250_000_000), frame_id='odom')
    pose = T['geometry_msgs/msg/Pose'](
        position=T['geometry_msgs/msg/Point'](x=0.1 * k, y=-2.0, z=0.0),
        orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0))
    covariance = np.arange(36, dtype=float)
    vector = T['geometry_msgs/msg/Vector3']
    twist = T['geometry_msgs/msg/Twist'](linear=vector(x=0.5, y=0.0, z=0.0),
                                         angular=vector(x=0.0, y=0.0, z=k))
    return T[ODOM](
        header=header, child_frame_id='base_link',
        pose=T['geometry_msgs/msg/PoseWithCovariance'](pose=pose, covariance=covariance),
        twist=T['geometry_msgs/msg/TwistWithCovariance'](twist=twist, covariance=np.zeros(36)))


def _joints(names: list[str]):
    header = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0),
                                      frame_id='')
    return T[JOINTS](header=header, name=names, position=np.full(len(names), 1.5),
                     velocity=np.zeros(0), effort=np.zeros(0))


@pytest.fixture
def run_bag(tmp_path):
    """Return a bag: 3 Odometry, 2 JointState of 1 then 2 joints, 1 TFMessage of 2 transforms."""
    path = tmp_path / 'bag'
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    odom = writer.add_connection('/odom', ODOM, typestore=STORE)
    joints = writer.add_connection('/joint_states', JOINTS, typestore=STORE)
    tf = writer.add_connection('/tf', TF, typestore=STORE)
    for k in range(3):
        writer.write(odom, k * 500_000_000, STORE.serialize_cdr(_odometry(k), ODOM))
    for k, names in enumerate((['a'], ['a', 'b'])):
        writer.write(joints, k * 1_000_000_000, STORE.serialize_cdr(_joints(names), JOINTS))
    transform = T['geometry_msgs/msg/TransformStamped'](
        header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=2, nanosec=0),
                                        frame_id='odom'), child_frame_id='base_link',
        transform=T['geometry_msgs/msg/Transform'](
            translation=T['geometry_msgs/msg/Vector3'](x=1.0, y=2.0, z=0.0),
            rotation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=0.0, w=1.0)))
    writer.write(tf, 0, STORE.serialize_cdr(T[TF](transforms=[transform, transform]), TF))
    writer.close()
    return path


def test_csv_holds_one_row_per_message_with_flattened_fields(run_bag, tmp_path):
    tables = {t.topic: t for t in export_bag(run_bag, tmp_path / 'out')}
    assert sorted(tables) == ['/joint_states', '/odom', '/tf']
    with open(tables['/odom'].path, newline='') as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == tables['/odom'].rows == 3
    for k, row in enumerate(rows):
        assert float(row['t']) == 0.5 * k
        assert float(row['header.stamp']) == k + 0.25
        assert row['header.frame_id'] == 'odom' and row['child_frame_id'] == 'base_link'
        assert float(row['pose.pose.position.x']) == 0.1 * k   # full precision (0.1 * 3)
        assert float(row['twist.twist.angular.z']) == k
        assert [float(row[f'pose.covariance.{i}']) for i in range(36)] == list(range(36))
    assert '__msgtype__' not in ''.join(rows[0])


def test_variable_arrays_get_the_longest_width_and_message_arrays_json(run_bag, tmp_path):
    tables = {t.topic: t for t in export_bag(run_bag, tmp_path / 'out')}
    with open(tables['/joint_states'].path, newline='') as stream:
        rows = list(csv.DictReader(stream))
    assert [json.loads(r['name']) for r in rows] == [['a'], ['a', 'b']]
    assert (rows[0]['position.0'], rows[0]['position.1']) == ('1.5', '')   # missing: empty
    assert (rows[1]['position.0'], rows[1]['position.1']) == ('1.5', '1.5')
    with open(tables['/tf'].path, newline='') as stream:
        (row,) = list(csv.DictReader(stream))
    transforms = json.loads(row['transforms'])
    assert len(transforms) == 2 and transforms[0]['transform.translation.y'] == 2.0
    assert transforms[0]['header.stamp'] == 2.0 and transforms[0]['child_frame_id'] == 'base_link'


def test_parquet_holds_the_same_values_with_nulls_for_missing_ones(run_bag, tmp_path):
    export_bag(run_bag, tmp_path / 'out', 'parquet', ['/odom', '/joint_states'])
    assert sorted(p.name for p in (tmp_path / 'out').iterdir()) == [
        'joint_states.parquet', 'odom.parquet']
    odom = pq.read_table(tmp_path / 'out' / 'odom.parquet').to_pydict()
    assert odom['pose.pose.position.x'] == [0.0, 0.1, 0.2] and odom['t'] == [0.0, 0.5, 1.0]
    assert odom['header.stamp'] == [0.25, 1.25, 2.25]
    joints = pq.read_table(tmp_path / 'out' / 'joint_states.parquet').to_pydict()
    assert joints['position.1'] == [None, 1.5]


def test_bad_requests_change_nothing(run_bag, tmp_path):
    with pytest.raises(ExportError, match='/nope not in .*; its topics: /joint_states, /odom'):
        export_bag(run_bag, tmp_path / 'out', topics=['/nope'])
    assert not (tmp_path / 'out').exists()
    with pytest.raises(ExportError, match='format must be one of csv, parquet'):
        export_bag(run_bag, tmp_path / 'out', 'xlsx')
    export_bag(run_bag, tmp_path / 'out', topics=['/odom'])
    before = (tmp_path / 'out' / 'odom.csv').read_bytes()
    with pytest.raises(ExportError, match='odom.csv exists already'):
        export_bag(run_bag, tmp_path / 'out', topics=['/tf', '/odom'])
    assert (tmp_path / 'out' / 'odom.csv').read_bytes() == before
    assert not (tmp_path / 'out' / 'tf.csv').exists()


def test_the_command_writes_beside_the_bag_and_refuses_in_one_line(run_bag):
    command = [sys.executable, '-m', 'robotica_sim.cli.main', 'export']
    done = subprocess.run(command + [str(run_bag), '--topics', '/odom'], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout == f'{run_bag}-csv/odom.csv: /odom, 3 rows x 89 columns\n'
    for args, code, text in (([str(run_bag), '--topics', '/nope'], 2, '/nope not in'),
                             ([str(run_bag.parent / 'none')], 1, 'not a bag directory')):
        failed = subprocess.run(command + args, capture_output=True, text=True, timeout=120)
        assert failed.returncode == code and text in failed.stderr
        assert failed.stderr.count('\n') == 1 and 'Traceback' not in failed.stderr
