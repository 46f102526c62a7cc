"""
Tests of ``robotica bag repair``: a writer that is never closed stands for a killed recorder.

Reference: the Float64 counters written; the repaired bag must hold exactly the messages that
were flushed before the "kill", in order, and whatever ``rosbags`` needs to read it.
"""
import os
import subprocess
import sys

import pytest
from robotica_sim.bags.info import bag_info, BagError
from robotica_sim.bags.repair import needs_repair, partial_reason, repair_bag, RepairError
from robotica_sim.bags.typestore import jazzy_typestore
from robotica_sim.bags.writer import BagWriter
from rosbags.highlevel import AnyReader

FLOAT64 = 'std_msgs/msg/Float64'
QOS = [{'history': 'keep_last', 'depth': 3, 'reliability': 'reliable', 'durability': 'volatile',
        'deadline': {'sec': 0, 'nsec': 0}, 'lifespan': {'sec': 0, 'nsec': 0},
        'liveliness': 'automatic', 'liveliness_lease_duration': {'sec': 0, 'nsec': 0},
        'avoid_ros_namespace_conventions': False}]


def killed_bag(path, flushed: int, unflushed: int, cut: int = 0, **limits):
    """Write ``flushed`` messages and flush, ``unflushed`` more, then drop the writer."""
    store = jazzy_typestore()
    msgdef, _ = store.generate_msgdef(FLOAT64, ros_version=2)
    writer = BagWriter(path, flush_period=3600.0, custom_data={'robotica.seed': '7'}, **limits)
    topic = writer.add_topic('/a', FLOAT64, msgdef, store.hash_rihs01(FLOAT64), QOS)
    for i in range(flushed + unflushed):
        writer.write(topic, i * 1_000_000, bytes(store.serialize_cdr(
            store.types[FLOAT64](data=float(i)), FLOAT64)))
        if i == flushed - 1:
            writer.flush()
    writer._stream.flush()      # what the OS has of the file when the process dies
    if cut:
        last = sorted(path.glob('*.mcap'))[-1]
        os.truncate(last, last.stat().st_size - cut)
    return path


def values(path) -> list[float]:
    with AnyReader([path]) as reader:
        return [reader.deserialize(raw, c.msgtype).data for c, _, raw in reader.messages()]


@pytest.mark.parametrize('cut', [0, 1, 40])
def test_the_repaired_bag_holds_every_flushed_message(tmp_path, cut):
    bag = killed_bag(tmp_path / 'bag', flushed=500, unflushed=77, cut=cut)
    assert needs_repair(bag)
    with pytest.raises(BagError, match='robotica bag repair'):
        bag_info(bag)
    report = repair_bag(bag)
    kept = values(bag)
    assert kept == [float(i) for i in range(len(kept))]   # a prefix, in order
    assert len(kept) == report.messages
    assert len(kept) == 500 if cut == 0 else 0 < len(kept) <= 500
    info = bag_info(bag)
    assert info.topics[0].name == '/a' and info.topics[0].count == len(kept)
    text = (bag / 'metadata.yaml').read_text()
    assert 'robotica.seed' in text and 'depth: 3' in text
    assert (bag / 'bag_0.mcap.broken').is_file()
    assert not needs_repair(bag)


@pytest.mark.parametrize('keep', [None, 0.5])
def test_a_cut_file_is_repaired_although_metadata_yaml_exists(tmp_path, keep):
    # A closed bag whose file was cut afterwards (a copy interrupted, a full disk): its last
    # byte only (footer), or half of it (chunks lost).
    store = jazzy_typestore()
    msgdef, _ = store.generate_msgdef(FLOAT64, ros_version=2)
    bag = tmp_path / 'bag'
    writer = BagWriter(bag, flush_period=1e-4, custom_data={'robotica.seed': '7'})  # chunks
    topic = writer.add_topic('/a', FLOAT64, msgdef, store.hash_rihs01(FLOAT64), QOS)
    for i in range(3000):
        writer.write(topic, i * 1_000_000, bytes(store.serialize_cdr(
            store.types[FLOAT64](data=float(i)), FLOAT64)))
    writer.close()
    data = bag / 'bag_0.mcap'
    size = data.stat().st_size
    os.truncate(data, size - 1 if keep is None else int(size * keep))
    assert (bag / 'metadata.yaml').is_file() and needs_repair(bag)
    with pytest.raises(BagError, match='partial bag .*cut short.*robotica bag repair'):
        bag_info(bag)
    report = repair_bag(bag)
    kept = values(bag)
    assert kept == [float(i) for i in range(len(kept))] and len(kept) == report.messages
    assert len(kept) == 3000 if keep is None else 0 < len(kept) < 3000
    assert (bag / 'metadata.yaml.broken').is_file() and not needs_repair(bag)
    assert report.old_metadata
    assert 'robotica.seed' in (bag / 'metadata.yaml').read_text()
    assert bag_info(bag).message_count == len(kept)


def test_custom_data_set_while_recording_survives_a_kill(tmp_path):
    store = jazzy_typestore()
    msgdef, _ = store.generate_msgdef(FLOAT64, ros_version=2)
    writer = BagWriter(tmp_path / 'bag', flush_period=3600.0, custom_data={'robotica.a': '1'})
    topic = writer.add_topic('/a', FLOAT64, msgdef, store.hash_rihs01(FLOAT64), QOS)
    writer.set_custom_data('robotica.publishers', '/a: [/mine]\n')
    writer.set_custom_data('robotica.a', '2')
    writer.write(topic, 0, bytes(store.serialize_cdr(store.types[FLOAT64](data=1.0), FLOAT64)))
    writer.flush()
    writer._stream.flush()
    repair_bag(tmp_path / 'bag')
    text = (tmp_path / 'bag' / 'metadata.yaml').read_text()
    assert "robotica.publishers: '/a: [/mine]" in text and "robotica.a: '2'" in text


def test_a_split_bag_is_repaired_file_by_file(tmp_path):
    bag = killed_bag(tmp_path / 'bag', flushed=2000, unflushed=10, max_bag_duration=0.5)
    report = repair_bag(bag)
    assert len(report.files) >= 4 and all(f.complete for f in report.files[:-1])
    assert not report.files[-1].complete
    assert values(bag) == [float(i) for i in range(2000)]


def test_what_cannot_be_repaired_says_why(tmp_path):
    with pytest.raises(RepairError, match='not a directory'):
        repair_bag(tmp_path / 'missing')
    (tmp_path / 'empty').mkdir()
    with pytest.raises(RepairError, match='no .mcap file'):
        repair_bag(tmp_path / 'empty')
    bag = killed_bag(tmp_path / 'bag', flushed=5, unflushed=0)
    repair_bag(bag)
    with pytest.raises(RepairError, match='nothing to repair'):
        repair_bag(bag)
    nothing = killed_bag(tmp_path / 'nothing', flushed=0, unflushed=9)
    with pytest.raises(RepairError, match='no complete message'):
        repair_bag(nothing)


def test_the_command_repairs_and_reports(tmp_path):
    bag = killed_bag(tmp_path / 'bag', flushed=30, unflushed=3)
    command = [sys.executable, '-m', 'robotica_sim.cli.main', 'bag', 'repair']
    done = subprocess.run(command + [str(bag)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert '30 messages of 1 topics' in done.stdout
    again = subprocess.run(command + [str(bag)], capture_output=True, text=True, timeout=60)
    assert again.returncode == 1 and 'nothing to repair' in again.stderr
    assert 'Traceback' not in again.stderr


def test_a_file_that_only_ends_with_the_magic_bytes_is_not_closed(tmp_path):
    bag = killed_bag(tmp_path / 'bag', flushed=5, unflushed=0)
    repair_bag(bag)
    assert partial_reason(bag) == ''
    (mcap,) = bag.glob('*.mcap')
    data = bytearray(mcap.read_bytes())
    data[-(8 + 29)] = 0x0F   # the footer's opcode (29 bytes before the closing magic bytes)
    mcap.write_bytes(bytes(data))
    assert partial_reason(bag) == f'{mcap.name} cut short (no MCAP footer)'
    mcap.write_bytes(bytes(data[:8]) + os.urandom(5000) + bytes(data[-8:]))
    assert partial_reason(bag) == f'{mcap.name} cut short (no MCAP footer)'
