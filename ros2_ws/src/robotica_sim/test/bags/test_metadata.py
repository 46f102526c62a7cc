"""Tests of the rosbag2 metadata pieces: offered QoS as rosbag2 v9 writes it, and back."""
from rclpy.duration import Duration
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile,
                       ReliabilityPolicy)
from robotica_sim.bags.metadata import (bag_metadata, FileRecord, qos_from_yaml, qos_to_dict,
                                        qos_yaml, TopicRecord)


def test_an_offered_profile_becomes_rosbag2s_dictionary():
    profile = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=500,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL,
                         liveliness=LivelinessPolicy.AUTOMATIC,
                         deadline=Duration(seconds=1, nanoseconds=250_000_000))
    stored = qos_to_dict(profile)
    assert stored['history'] == 'keep_last' and stored['depth'] == 500
    assert stored['reliability'] == 'reliable' and stored['durability'] == 'transient_local'
    assert stored['deadline'] == {'sec': 1, 'nsec': 250_000_000}
    assert stored['liveliness'] == 'automatic'
    assert stored['avoid_ros_namespace_conventions'] is False
    assert qos_from_yaml(qos_yaml([stored])) == [stored]


def test_malformed_or_empty_qos_text_reads_as_no_profile():
    assert qos_from_yaml('') == [] and qos_from_yaml('{a: [') == []
    assert qos_from_yaml('just text') == [] and qos_yaml([]) == ''


def test_the_bag_spans_its_files_and_counts_their_messages():
    first, second = FileRecord('b_0.mcap'), FileRecord('b_1.mcap')
    for t in (5, 3, 9):
        first.note(t)
    second.note(12)
    topic = TopicRecord('/a', 'std_msgs/msg/Float64', 'float64 data\n', 'RIHS01_0', count=4)
    information = bag_metadata('mcap', [topic], [first, second], {'k': 'v'})
    assert information['starting_time'] == {'nanoseconds_since_epoch': 3}
    assert information['duration'] == {'nanoseconds': 9}
    assert information['message_count'] == 4
    assert [f['message_count'] for f in information['files']] == [3, 1]
    assert information['files'][0]['duration'] == {'nanoseconds': 6}
    assert information['relative_file_paths'] == ['b_0.mcap', 'b_1.mcap']
    assert information['custom_data'] == {'k': 'v'}
