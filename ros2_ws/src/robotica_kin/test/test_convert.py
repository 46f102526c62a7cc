"""Tests of the conversions between messages and values that the docstrings do not show."""
from nav_msgs.msg import Odometry
from rclpy.serialization import serialize_message
from robotica_kin.ros.convert import header_stamp
from robotica_msgs.msg import WheelEncoders
from rosgraph_msgs.msg import Clock


def test_the_header_stamp_is_read_from_the_serialized_message():
    odom = Odometry()
    odom.header.stamp.sec, odom.header.stamp.nanosec = 12, 340_000_000
    odom.header.frame_id = 'odom'
    ticks = WheelEncoders(left_ticks=-5, right_ticks=7)
    ticks.header.stamp.sec, ticks.header.stamp.nanosec = 0, 10_000_000
    assert header_stamp(serialize_message(odom)) == 12.34
    assert header_stamp(serialize_message(ticks)) == 0.01


def test_a_big_endian_message_is_read_too():
    # CDR big endian: encapsulation 00 00, options 00 00, then sec = 3, nanosec = 5e8
    data = bytes([0, 0, 0, 0]) + (3).to_bytes(4, 'big') + (500_000_000).to_bytes(4, 'big')
    assert header_stamp(data) == 3.5


def test_a_clock_is_read_as_its_time():
    clock = Clock()
    clock.clock.sec, clock.clock.nanosec = 7, 250_000_000
    assert header_stamp(serialize_message(clock)) == 7.25
