"""
Tests of the node guard (robotica_kin.ros.guarded) in process, and of the bounds it enforces.

A callback that raises is logged and dropped, the node's safe output is issued, the next message
is handled; a non-finite message is not published; a publish after shutdown is silent.
"""
import math

from builtin_interfaces.msg import Time
from nav_msgs.msg import Odometry
import pytest
import rclpy
from rclpy.parameter import Parameter
from robotica_kin.bounds import bounded, MAX_SPEED, StampGate
from robotica_kin.ros.guarded import GuardedNode, non_finite_fields, NonFiniteOutput
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState, LaserScan
from std_msgs.msg import Float64, Header

pytestmark = pytest.mark.ros


@pytest.fixture
def guarded(ros_domain):
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=ros_domain)

    class Probe(GuardedNode):
        safe = []

        def on_callback_error(self, source):
            self.safe.append(source)

    node = Probe('guard_probe', context=context)
    yield node, context
    node.destroy_node()
    rclpy.try_shutdown(context=context)


def test_non_finite_fields_names_each_field_and_allows_declared_nan():
    msg = Odometry()
    msg.pose.covariance[35] = math.inf
    msg.twist.twist.angular.z = math.nan
    assert non_finite_fields(msg) == ['twist.twist.angular.z', 'pose.covariance']
    joints = JointState(position=[0.0], velocity=[math.nan])
    assert non_finite_fields(joints, ('velocity',)) == []
    joints.velocity = [math.inf]
    assert non_finite_fields(joints, ('velocity',)) == ['velocity']


def test_rep117_infinities_are_allowed_only_where_declared():
    scan = LaserScan(ranges=[1.0, math.inf, -math.inf], range_max=math.inf)
    assert non_finite_fields(scan) == ['range_max', 'ranges']
    assert non_finite_fields(scan, allow_inf=('ranges',)) == ['range_max']
    scan.range_max, scan.ranges = 80.0, [math.nan, math.inf]
    assert non_finite_fields(scan, allow_inf=('ranges',)) == ['ranges']
    assert non_finite_fields(scan, ('ranges',), allow_inf=('ranges',)) == []


def test_a_failing_callback_is_dropped_and_the_safe_output_issued(guarded):
    node, _ = guarded
    handled = []

    def callback(msg):
        handled.append(bounded('speed', msg.data, MAX_SPEED))

    sub = node.create_subscription(Float64, 'speed', callback, 10)
    sub.callback(Float64(data=1e308))   # what the executor calls
    sub.callback(Float64(data=0.5))
    assert handled == [0.5]
    assert node.safe == ['speed'] and node.callback_errors == 1


def test_a_callback_failing_during_shutdown_is_silent(guarded):
    # A timer racing SIGINT fails on the invalid context; reporting it would fail too ("Failed
    # to publish log message to rosout: publisher's context is invalid") and kill the node.
    node, context = guarded

    def callback(msg):
        raise RuntimeError("publisher's context is invalid")

    sub = node.create_subscription(Float64, 'late', callback, 10)
    rclpy.try_shutdown(context=context)
    assert sub.callback(Float64(data=1.0)) is None
    assert node.safe == [] and node.callback_errors == 0


def test_an_observing_subscription_drops_without_the_safe_output(guarded):
    node, _ = guarded
    sub = node.create_subscription(Float64, 'seen', lambda msg: bounded('x', msg.data, 1.0), 10,
                                   safe_output=False)
    sub.callback(Float64(data=2.0))
    assert node.safe == [] and node.callback_errors == 1


def test_a_clock_tick_that_jumps_or_is_malformed_leaves_the_time(ros_domain):
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=ros_domain)
    node = GuardedNode('clock_probe', context=context,
                       parameter_overrides=[Parameter('use_sim_time', value=True)])
    try:
        (sub,) = [s for s in node.subscriptions if s.topic_name == '/clock']
        sub.callback(Clock(clock=Time(sec=10)))
        for hostile in (Time(sec=2 ** 31 - 1), Time(sec=10, nanosec=2 ** 32 - 1),
                        Time(sec=-5), Time(sec=10 + 3601)):
            sub.callback(Clock(clock=hostile))
            assert node.get_clock().now().nanoseconds == 10 * 10 ** 9, hostile
        sub.callback(Clock(clock=Time(sec=11)))
        assert node.get_clock().now().nanoseconds == 11 * 10 ** 9
        assert node.callback_errors == 4
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def test_a_non_finite_message_is_not_published_and_shutdown_is_silent(guarded):
    node, context = guarded
    pub = node.create_publisher(Float64, 'out', 10)
    with pytest.raises(NonFiniteOutput, match='data'):
        pub.publish(Float64(data=math.nan))
    pub.publish(Float64(data=1.0))
    stamped = node.create_publisher(JointState, 'stamped', 10)
    with pytest.raises(ValueError, match='nanosec'):   # a stamp passed on from a hostile input
        stamped.publish(JointState(header=Header(stamp=Time(sec=1, nanosec=2 ** 32 - 1))))
    stamped.publish(JointState(header=Header(stamp=Time(sec=1, nanosec=999_999_999))))
    rclpy.try_shutdown(context=context)
    pub.publish(Float64(data=1.0))   # the context is invalid: nothing, and no traceback


def test_the_stamp_gate_refuses_a_jump_and_restarts_on_three_agreeing():
    gate = StampGate(max_jump=10.0)
    assert gate.check(1e9) == 'accept'   # an absurd first stamp
    with pytest.raises(ValueError, match='more than 10.0 s'):
        gate.check(1.0)
    with pytest.raises(ValueError):
        gate.check(1.02)
    assert gate.check(1.04) == 'restart'
    assert gate.check(1.06) == 'accept'
    with pytest.raises(ValueError):
        gate.check(-2.0 ** 31)
    with pytest.raises(ValueError):
        gate.check(math.nan)
    assert gate.check(1.08) == 'accept' and gate.latest == 1.08
