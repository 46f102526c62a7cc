"""Tests of the conversions between messages and values that the docstrings do not show."""
import math

from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.serialization import serialize_message
from robotica_kin.ros.convert import header_stamp, path_message, path_points, path_postures
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


def test_a_path_of_postures_carries_each_given_heading():
    # Forward 1 m along +x, then back 1 m with the heading kept at 0: the reverse poses face
    # against their travel (the next point is behind). Orientation of yaw ψ about z:
    # (z, w) = (sin ψ/2, cos ψ/2).
    postures = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0],
                [0.0, 1.0, math.pi / 2], [-1.0, 1.0, -3.0]]
    msg = path_message(postures, 'map', t=2.0)
    assert len(msg.poses) == 6 and msg.poses[4].header.frame_id == 'map'
    q = msg.poses[4].pose.orientation
    assert (q.z, q.w) == pytest.approx((math.sin(math.pi / 4), math.cos(math.pi / 4)))
    q = msg.poses[3].pose.orientation
    assert (q.x, q.y, q.z, q.w) == (0.0, 0.0, 0.0, 1.0)   # not facing the next point (+y)
    assert path_postures(msg) == pytest.approx(np.array(postures), abs=1e-12)
    assert path_points(msg) == pytest.approx(np.array(postures)[:, :2], abs=0.0)


def test_a_path_of_points_faces_the_next_point_as_before():
    msg = path_message([[0.0, 0.0], [0.0, 2.0], [-1.0, 2.0]], 'odom')
    assert path_postures(msg)[:, 2] == pytest.approx([math.pi / 2, math.pi, math.pi],
                                                     abs=1e-12)
    assert path_postures(path_message(np.zeros((0, 2)), 'odom')).shape == (0, 3)
    with pytest.raises(ValueError, match='one value per point'):
        path_message([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], 'odom', times=[0.0])
