"""
Node tests of the planner's parking mode: the pass, a space found from side readings, the plan.

The street runs along x with the curb on y = 0 and two parked cars (1.7 m wide, their street
sides on y = 2.2) from x = 2.0 to 6.5 and from 13.7 to 18.2 m: a space of 7.2 m. The car (the
planner's default vehicle: a1 3.6, b1 0.9, c1 1.7 m) passes with P_f on y = 3.6, its side sensor
at the front-right corner (3.4, -0.85) looking right. The readings are written here from that
geometry: 0.55 m beside a car, 2.75 m to the curb in the space.
"""
import math

from nav_msgs.msg import Odometry, Path
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.convert import path_postures
from robotica_msgs.msg import PlanStatus
from sensor_msgs.msg import Range
from std_srvs.srv import Trigger

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
STREET = ('world:\n  walls: [[-10, 0, 40, 0]]\n  boxes:\n'
          '    - {center: [4.25, 1.35], size: [4.5, 1.7]}\n'
          '    - {center: [15.95, 1.35], size: [4.5, 1.7]}\n')
SPACE = (6.5, 13.7)           # [m] along x, between the cars
LANE = 3.6                    # [m] P_f's y on the pass
SENSOR = (3.4, -0.85, -0.5 * math.pi)


def reading(x):
    """Return the side sensor's range [m] with P_f at x on the pass: the car or the curb."""
    sensor_x = x + SENSOR[0]
    beside_car = 2.0 <= sensor_x <= SPACE[0] or SPACE[1] <= sensor_x <= 18.2
    return LANE + SENSOR[1] - (2.2 if beside_car else 0.0)


def odom(t, x):
    msg = Odometry()
    msg.header.frame_id = 'map'
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), int(round((t % 1) * 1e9))
    msg.pose.pose.position.x, msg.pose.pose.position.y = float(x), LANE
    msg.pose.pose.orientation.w = 1.0
    msg.twist.twist.linear.x = 1.0
    return msg


def side(t, x):
    msg = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.05, min_range=0.15,
                max_range=5.0, range=float(reading(x)))
    msg.header.frame_id = 'sonar_0'
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), int(round((t % 1) * 1e9))
    return msg


@pytest.fixture
def street(tmp_path):
    path = tmp_path / 'street.yaml'
    path.write_text(STREET)
    return str(path)


def _start(start_node, street, *extra):
    return start_node('robotica_ctrl', 'planner', '-p', 'method:=parking', '-p',
                      f'world_file:={street}', '-p', f'parking.sensor_pose:={list(SENSOR)}',
                      '-p', 'parking.pass_length:=25.0', *extra)


def _drive(node, executor, spin, until, x_end=16.0):
    """Publish the pass's poses (1 m/s, 50 Hz) and side readings (10 Hz) until ``until()``."""
    pose_pub = node.create_publisher(Odometry, 'odom', 50)
    range_pub = node.create_publisher(Range, 'side_range', 50)
    assert spin(executor, lambda: pose_pub.get_subscription_count() > 0
                and range_pub.get_subscription_count() > 0)
    for k, x in enumerate(np.arange(-2.0, x_end, 0.02)):
        t = 10.0 + k * 0.02
        pose_pub.publish(odom(t, x))
        if k % 5 == 1:   # the reading of the step before: its pose has been sent
            range_pub.publish(side(t - 0.02, x - 0.02))
        if k % 5 == 4:
            spin(executor, lambda: False, timeout=0.002)
        if until():
            return True
    return spin(executor, until, timeout=10.0)


def test_a_pass_finds_the_space_and_the_plan_parks_in_it(start_node, ros_node, spin, street):
    node, executor = ros_node
    _start(start_node, street, '-p', 'parking.autostart:=true')
    plans, statuses = [], []
    node.create_subscription(Path, 'plan', plans.append, LATCHED)
    node.create_subscription(PlanStatus, '/planner/status', statuses.append, LATCHED)
    assert _drive(node, executor, spin, lambda: len(plans) >= 2 and statuses[-1].found
                  and statuses[-1].points > 100)
    passing = path_postures(plans[0])
    start = passing[0]   # the first pose received (the first ones may go before matching)
    assert -2.0 <= start[0] <= 0.0 and start[1:] == pytest.approx([LANE, 0.0])
    assert passing[-1] == pytest.approx([start[0] + 25.0, LANE, 0.0])   # 25 m straight on
    plan = path_postures(plans[-1])
    steps = np.diff(plan[:, :2], axis=0)
    along = steps[:, 0] * np.cos(plan[:-1, 2]) + steps[:, 1] * np.sin(plan[:-1, 2])
    assert (along < -1e-6).any() and (along > 1e-6).any()        # forward and in reverse
    end = plan[-1]
    assert abs(math.remainder(end[2], 2 * math.pi)) < 0.05        # parallel to the street
    c1, a1, b1 = 1.7, 3.6, 0.9                                    # the body, in the space:
    assert SPACE[0] < end[0] - b1 and end[0] + a1 < SPACE[1]
    assert 0.0 < end[1] - c1 / 2 and end[1] + c1 / 2 < 2.2
    assert statuses[-1].method == 'parking'
    assert statuses[-1].goal.position.x == pytest.approx(end[0], abs=1e-6)


def test_park_service_starts_the_search(start_node, ros_node, spin, street):
    node, executor = ros_node
    _start(start_node, street)
    client = node.create_client(Trigger, 'park')
    assert client.wait_for_service(timeout_sec=20.0)
    future = client.call_async(Trigger.Request())
    assert spin(executor, future.done)
    assert not future.result().success and 'no pose yet' in future.result().message
    plans = []
    node.create_subscription(Path, 'plan', plans.append, LATCHED)
    pose_pub = node.create_publisher(Odometry, 'odom', 10)
    assert spin(executor, lambda: pose_pub.get_subscription_count() > 0)
    answered = []

    def call_when_posed():
        pose_pub.publish(odom(1.0, 0.0))
        if not answered:
            answered.append(client.call_async(Trigger.Request()))
        future = answered[0]
        if future.done() and not future.result().success:   # the pose had not arrived yet
            answered.clear()
        return future.done() and future.result().success and plans

    assert spin(executor, call_when_posed, timeout=20.0)
    assert 'searching for a space along a pass of 25 m' in answered[0].result().message
    assert path_postures(plans[-1])[0][:2] == pytest.approx([0.0, LANE], abs=1e-6)


def test_a_pass_without_a_space_ends_with_the_reason(start_node, ros_node, spin, tmp_path):
    node, executor = ros_node
    path = tmp_path / 'full.yaml'
    path.write_text('world:\n  walls: [[-10, 0, 40, 0]]\n')
    start_node('robotica_ctrl', 'planner', '-p', 'method:=parking', '-p',
               f'world_file:={path}', '-p', 'parking.pass_length:=3.0', '-p',
               'parking.autostart:=true')
    statuses = []
    node.create_subscription(PlanStatus, '/planner/status', statuses.append, LATCHED)
    assert _drive(node, executor, spin, lambda: statuses and 'no space' in statuses[-1].reason,
                  x_end=2.0)
    assert not statuses[-1].found
    assert any('searching for a space along a pass of 3 m' in s.reason and not s.found
               for s in statuses)                        # the pass is no parking plan
    assert 'no space to park in was found along the pass of 3 m' in statuses[-1].reason


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'parking.sensor_pose:=[0.0, 0.0, 0.0]'), 'sensor_pose must look sideways'),
    (('-p', 'parking.execution:=fast'), 'execution'),
    (('-p', 'parking.c1:=0.0'), 'parking.c1'),
])
def test_bad_parking_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'planner', '-p', 'method:=parking', *arguments)
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert reason in text and 'Traceback' not in text


def test_hostile_readings_are_dropped_and_the_search_goes_on(start_node, ros_node, spin,
                                                             read_output, street):
    # Readings with NaN or inverted limits, and REP-117's NaN and +inf ranges, among the good
    # ones: the bad ones are logged and dropped, the others (NaN: unknown, +inf: no echo) read.
    node, executor = ros_node
    proc = _start(start_node, street, '-p', 'parking.autostart:=true')
    statuses = []
    node.create_subscription(PlanStatus, '/planner/status', statuses.append, LATCHED)
    hostile = node.create_publisher(Range, 'side_range', 50)
    bad = 0

    def found():
        nonlocal bad
        for field, value in (('min_range', math.nan), ('max_range', -1.0), ('range', math.nan),
                             ('range', math.inf)):
            msg = side(9.99, 0.0)
            setattr(msg, field, value)
            hostile.publish(msg)
        bad += 1
        return statuses and statuses[-1].found and statuses[-1].points > 100

    assert _drive(node, executor, spin, found)
    assert bad > 10 and proc.poll() is None
    assert spin(executor, lambda: 'a Range needs finite 0 <= min_range < max_range'
                in read_output(proc))
