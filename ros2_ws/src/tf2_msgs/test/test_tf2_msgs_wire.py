"""
The tf2_msgs importable here is ROS 2 Jazzy's on the wire: same type hashes, same CDR bytes.

On the pip route that is the workspace's copy (ros2_ws/src/tf2_msgs); on a full ROS 2 install it
is the system's. Reference values are independent of the package under test: the RIHS01 hashes
that Jazzy nodes advertise (``ros2 topic info -v /tf`` on Jazzy, and the ``type_description_hash``
of ``/tf`` in Jazzy rosbag2 metadata), and rosbags' own ROS2_JAZZY type store, which ships
tf2_msgs and computes hashes and CDR with its own code.
"""

import json
from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Quaternion, Transform, TransformStamped, Vector3
import pytest
from rclpy.serialization import deserialize_message, serialize_message
from rosbags.typesys import get_typestore, Stores
from std_msgs.msg import Header
from tf2_msgs.msg import TF2Error, TFMessage

# RIHS01 hashes published by ROS 2 Jazzy for these types.
JAZZY_HASHES = {
    'tf2_msgs/msg/TFMessage':
        'RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087',
    'tf2_msgs/msg/TF2Error':
        'RIHS01_db2485e7d6a0ec75bf087e058ee45df682acc3a621ca7780503d10aac141809a',
    'tf2_msgs/action/LookupTransform':
        'RIHS01_0b8adf6bc0b5958879e3265b41a457e03558fe523890a81252c70eba97a82c5d',
}

# Two transforms with awkward values: signs, tiny and large magnitudes, odd-length frame ids
# (so the CDR alignment padding after each string is exercised).
FRAMES = [
    ('map', 'odom', 12, 345678901, (1.5, -2.25, 0.0), (0.0, 0.0, 0.38268343236, 0.92387953251)),
    ('odom', 'base_link', 2**31 - 1, 999999999, (-1e-12, 3e7, -0.125),
     (0.5, -0.5, 0.5, 0.5)),
]


@pytest.fixture(scope='module')
def typestore():
    return get_typestore(Stores.ROS2_JAZZY)


def ours() -> TFMessage:
    return TFMessage(transforms=[
        TransformStamped(
            header=Header(stamp=Time(sec=sec, nanosec=nsec), frame_id=parent),
            child_frame_id=child,
            transform=Transform(translation=Vector3(x=t[0], y=t[1], z=t[2]),
                                rotation=Quaternion(x=r[0], y=r[1], z=r[2], w=r[3])))
        for parent, child, sec, nsec, t, r in FRAMES])


def theirs(typestore):
    types = typestore.types
    return types['tf2_msgs/msg/TFMessage'](transforms=[
        types['geometry_msgs/msg/TransformStamped'](
            header=types['std_msgs/msg/Header'](
                stamp=types['builtin_interfaces/msg/Time'](sec=sec, nanosec=nsec),
                frame_id=parent),
            child_frame_id=child,
            transform=types['geometry_msgs/msg/Transform'](
                translation=types['geometry_msgs/msg/Vector3'](x=t[0], y=t[1], z=t[2]),
                rotation=types['geometry_msgs/msg/Quaternion'](x=r[0], y=r[1], z=r[2], w=r[3])))
        for parent, child, sec, nsec, t, r in FRAMES])


def test_advertised_hash_is_jazzys(ros_node):
    node, _ = ros_node
    for msg_type, topic in ((TFMessage, '/tf_hash_probe'), (TF2Error, '/tf_error_probe')):
        node.create_publisher(msg_type, topic, 1)
        (info,) = node.get_publishers_info_by_topic(topic)
        assert str(info.topic_type_hash) == JAZZY_HASHES[info.topic_type]


def test_generated_type_descriptions_carry_jazzys_hashes():
    share = Path(get_package_share_directory('tf2_msgs'))
    for name, expected in JAZZY_HASHES.items():
        description = json.loads((share / f'{name.split("/", 1)[1]}.json').read_text())
        assert description['type_hashes'][0] == {'type_name': name, 'hash_string': expected}


def test_rosbags_jazzy_store_agrees(typestore):
    for name in ('tf2_msgs/msg/TFMessage', 'tf2_msgs/msg/TF2Error'):
        assert typestore.hash_rihs01(name) == JAZZY_HASHES[name]
    assert typestore.fielddefs['tf2_msgs/msg/TF2Error'][0] == [
        (name, 'uint8', value) for name, value in (
            ('NO_ERROR', 0), ('LOOKUP_ERROR', 1), ('CONNECTIVITY_ERROR', 2),
            ('EXTRAPOLATION_ERROR', 3), ('INVALID_ARGUMENT_ERROR', 4), ('TIMEOUT_ERROR', 5),
            ('TRANSFORM_ERROR', 6))]
    for name, _, value in typestore.fielddefs['tf2_msgs/msg/TF2Error'][0]:
        assert getattr(TF2Error, name) == value
    assert TF2Error.get_fields_and_field_types() == {'error': 'uint8', 'error_string': 'string'}


def test_cdr_bytes_identical_both_ways(typestore):
    ours_cdr = serialize_message(ours())
    theirs_cdr = bytes(typestore.serialize_cdr(theirs(typestore), 'tf2_msgs/msg/TFMessage'))
    assert ours_cdr == theirs_cdr
    assert deserialize_message(theirs_cdr, TFMessage) == ours()
    decoded = typestore.deserialize_cdr(ours_cdr, 'tf2_msgs/msg/TFMessage')
    assert [(t.header.frame_id, t.child_frame_id, t.header.stamp.sec,
             t.transform.translation.y) for t in decoded.transforms] == [
        (parent, child, sec, tr[1]) for parent, child, sec, _, tr, _ in FRAMES]
