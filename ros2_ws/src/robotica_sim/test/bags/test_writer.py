"""
Tests of the bag writer: what ``rosbags`` and ``mcap`` read back, splitting, flushing.

References are the messages written here (Float64 counters): every one must come back, in
order, with its time, whichever reader and however the bag is split.
"""
import shutil

from mcap.reader import make_reader
from mcap.records import Message
from mcap.stream_reader import StreamReader
import pytest
from robotica_sim.bags.typestore import jazzy_typestore
from robotica_sim.bags.writer import BagWriter
from rosbags.highlevel import AnyReader
from rosbags.rosbag2 import Reader
import yaml

FLOAT64 = 'std_msgs/msg/Float64'
QOS = [{'history': 'keep_last', 'depth': 7, 'reliability': 'best_effort',
        'durability': 'transient_local', 'deadline': {'sec': 1, 'nsec': 5},
        'lifespan': {'sec': 9223372036, 'nsec': 854775807}, 'liveliness': 'automatic',
        'liveliness_lease_duration': {'sec': 9223372036, 'nsec': 854775807},
        'avoid_ros_namespace_conventions': False}]


@pytest.fixture(scope='module')
def store():
    return jazzy_typestore()


def float_topic(store, writer: BagWriter, name: str, qos=None) -> int:
    msgdef, _ = store.generate_msgdef(FLOAT64, ros_version=2)
    return writer.add_topic(name, FLOAT64, msgdef, store.hash_rihs01(FLOAT64), qos)


def cdr(store, value: float) -> bytes:
    return bytes(store.serialize_cdr(store.types[FLOAT64](data=value), FLOAT64))


def read(store, bag) -> list[tuple[str, int, float]]:
    with AnyReader([bag]) as reader:
        return [(c.topic, t, reader.deserialize(raw, c.msgtype).data)
                for c, t, raw in reader.messages()]


def test_rosbags_and_mcap_read_back_every_message_with_its_topic_and_time(store, tmp_path):
    writer = BagWriter(tmp_path / 'bag', custom_data={'robotica.scenario.yaml': 'name: x\n'})
    a, b = float_topic(store, writer, '/a', QOS), float_topic(store, writer, '/b')
    for i in range(300):
        writer.write(a if i % 3 else b, 1_000 + 10 * i, cdr(store, float(i)))
    information = writer.close()
    expected = [('/b' if i % 3 == 0 else '/a', 1_000 + 10 * i, float(i)) for i in range(300)]
    assert read(store, tmp_path / 'bag') == expected
    assert information['message_count'] == 300 and information['ros_distro'] == 'jazzy'
    stored = yaml.safe_load((tmp_path / 'bag' / 'metadata.yaml').read_text())
    assert stored['rosbag2_bagfile_information']['custom_data'] == {
        'robotica.scenario.yaml': 'name: x\n'}
    with Reader(tmp_path / 'bag') as reader:
        assert reader.ros_distro == 'jazzy'
        qos = {c.topic: c.ext.offered_qos_profiles for c in reader.connections}
    assert qos['/a'][0].depth == 7 and qos['/a'][0].deadline.nsec == 5 and qos['/b'] == []
    with open(tmp_path / 'bag' / 'bag_0.mcap', 'rb') as stream:
        mcap = make_reader(stream)
        assert mcap.get_header().profile == 'ros2'
        summary = mcap.get_summary()
        assert summary.statistics.message_count == 300
        assert {s.name for s in summary.schemas.values()} == {FLOAT64}
        assert {c.message_encoding for c in summary.channels.values()} == {'cdr'}
        hashes = {c.metadata['topic_type_hash'] for c in summary.channels.values()}
    assert hashes == {store.hash_rihs01(FLOAT64)}


@pytest.mark.parametrize('compression', ['zstd', 'none'])
@pytest.mark.parametrize('limits, files', [({'max_bag_size': 3_000}, 4),
                                           ({'max_bag_duration': 0.25}, 4),
                                           ({}, 1)])
def test_a_split_bag_holds_every_message_in_order(store, tmp_path, compression, limits, files):
    # 1000 messages over 1 s; flush_period tiny so the size limit sees bytes on disk
    writer = BagWriter(tmp_path / 'bag', compression=compression, flush_period=1e-6, **limits)
    a = float_topic(store, writer, '/a')
    for i in range(1000):
        writer.write(a, i * 1_000_000, cdr(store, float(i)))
    information = writer.close()
    names = sorted(p.name for p in (tmp_path / 'bag').glob('*.mcap'))
    assert len(names) >= files if limits else len(names) == 1
    assert information['relative_file_paths'] == sorted(names, key=lambda n: int(n[4:-5]))
    assert [v for _, _, v in read(store, tmp_path / 'bag')] == [float(i) for i in range(1000)]
    assert sum(f['message_count'] for f in information['files']) == 1000
    if 'max_bag_duration' in limits:
        assert all(f['duration']['nanoseconds'] < 250_000_000 for f in information['files'])


def test_flushed_messages_are_on_disk_before_the_bag_is_closed(store, tmp_path):
    writer = BagWriter(tmp_path / 'bag', flush_period=3600.0)   # only explicit flushes
    a = float_topic(store, writer, '/a')
    for i in range(50):
        writer.write(a, i, cdr(store, float(i)))
    writer.flush()
    for i in range(50, 60):
        writer.write(a, i, cdr(store, float(i)))   # still in memory
    shutil.copy(tmp_path / 'bag' / 'bag_0.mcap', tmp_path / 'snapshot.mcap')   # as a kill
    writer.close()
    messages = []
    with open(tmp_path / 'snapshot.mcap', 'rb') as stream:
        with pytest.raises(Exception):    # no footer: the stream ends after the last chunk
            for record in StreamReader(stream).records:
                if isinstance(record, Message):
                    messages.append(record.log_time)
    assert messages == list(range(50))


def test_bad_arguments_are_refused(tmp_path):
    with pytest.raises(ValueError, match='compression'):
        BagWriter(tmp_path / 'a', compression='lz4')
    with pytest.raises(ValueError, match='flush_period'):
        BagWriter(tmp_path / 'b', flush_period=0.0)
    (tmp_path / 'c').mkdir()
    with pytest.raises(FileExistsError, match='exists already'):
        BagWriter(tmp_path / 'c')


def test_a_topic_is_added_once(store, tmp_path):
    writer = BagWriter(tmp_path / 'bag')
    float_topic(store, writer, '/a')
    with pytest.raises(ValueError, match='/a was added already'):
        float_topic(store, writer, '/a')
    writer.close()
