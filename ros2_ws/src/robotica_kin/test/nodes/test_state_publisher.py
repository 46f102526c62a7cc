"""
Node tests of state_publisher: /tf and /tf_static from joint states, the latched URDF, refusals.

References are computed here by another route: the PUMA 560's tool pose is the DH model's
``fkine(q)`` (Craig's product (4.6) in NumPy, not Pinocchio), and the test composes the received
transforms itself (quaternions read by SciPy); a differential vehicle's wheel frame is where the
geometry puts it, (0, ±b/2, c), turned about its axle (y) by the wheel angle.
"""
import math

from builtin_interfaces.msg import Time
import numpy as np
import pinocchio as pin
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.forward_kinematics import fkine
from robotica_kin.robots import puma560
from robotica_kin.transforms import roty, transl
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
TF = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
PUMA_JOINTS = [f'joint_{i}' for i in range(1, 7)]


def _joint_state(names, q, sec, nanosec=250):
    msg = JointState(name=list(names), position=[float(v) for v in q])
    msg.header.stamp = Time(sec=sec, nanosec=nanosec)
    return msg


def _matrix(transform):
    T = np.eye(4)
    r, p = transform.transform.rotation, transform.transform.translation
    T[:3, :3] = Rotation.from_quat([r.x, r.y, r.z, r.w]).as_matrix()
    T[:3, 3] = [p.x, p.y, p.z]
    return T


def _edges(*messages):
    """Return {child: (parent, T_parent_child)} of the transforms in ``messages``."""
    return {t.child_frame_id: (t.header.frame_id, _matrix(t))
            for msg in messages for t in msg.transforms}


def _chain(edges, base, tip):
    """Return T_base_tip composed from the tip up its parents."""
    T = np.eye(4)
    frame = tip
    while frame != base:
        parent, T_parent = edges[frame]
        T = T_parent @ T
        frame = parent
    return T


class _Graph:
    """The test's side: a joint-state publisher and the node's three outputs."""

    def __init__(self, node, executor, spin):
        self.node, self.executor = node, executor
        self.tf, self.static = [], []
        node.create_subscription(TFMessage, '/tf', self.tf.append, TF)
        node.create_subscription(TFMessage, '/tf_static', self.static.append, LATCHED)
        self.joints = node.create_publisher(JointState, 'joint_states', QOS)
        assert spin(executor, lambda: self.joints.get_subscription_count() > 0 and self.static)

    def stamped(self, sec):
        return lambda: any(m.transforms and m.transforms[0].header.stamp.sec == sec
                           for m in self.tf)

    def latest(self, sec):
        return [m for m in self.tf if m.transforms[0].header.stamp.sec == sec][-1]


def test_puma_tf_chain_is_fkine_and_joints_keep_their_values(start_node, ros_node, spin,
                                                             publish):
    node, executor = ros_node
    start_node('robotica_kin', 'state_publisher')
    graph = _Graph(node, executor, spin)
    robot = puma560()
    rng = np.random.default_rng(17)
    q = rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1])
    order = [3, 0, 5, 1, 4, 2]   # any order, with a joint the model does not have
    msg = _joint_state(['gripper'] + [PUMA_JOINTS[i] for i in order],
                       [0.02] + [q[i] for i in order], sec=5)
    assert publish(executor, graph.joints, msg, graph.stamped(5))
    received = graph.latest(5)
    assert {t.header.stamp.sec for t in received.transforms} == {5}
    assert {t.header.stamp.nanosec for t in received.transforms} == {250}
    assert len(received.transforms) == 6 and len(graph.static) == 1
    edges = _edges(received, graph.static[-1])
    assert [edges[f'link_{i}'][0] for i in range(1, 7)] == [f'link_{i}' for i in range(6)]
    assert edges['tool0'][0] == 'link_6'
    np.testing.assert_allclose(_chain(edges, 'link_0', 'tool0'), fkine(robot, q), rtol=0.0,
                               atol=1e-9)

    # Only joint_3 in the next state: the others keep their values (robot_state_publisher).
    q[2] = rng.uniform(*robot.qlim[2])
    assert publish(executor, graph.joints, _joint_state(['joint_3'], [q[2]], sec=6),
                   graph.stamped(6))
    edges = _edges(graph.latest(6), graph.static[-1])
    np.testing.assert_allclose(_chain(edges, 'link_0', 'tool0'), fkine(robot, q), rtol=0.0,
                               atol=1e-9)


def test_robot_description_reaches_a_late_subscriber(start_node, ros_node, spin):
    node, executor = ros_node
    start_node('robotica_kin', 'state_publisher', '-p', 'robot:=planar_rrr')
    static = []
    node.create_subscription(TFMessage, '/tf_static', static.append, LATCHED)
    assert spin(executor, lambda: static)   # published after the description: it is out
    descriptions = []
    node.create_subscription(String, 'robot_description', descriptions.append, LATCHED)
    assert spin(executor, lambda: descriptions)
    model = pin.buildModelFromXML(descriptions[0].data)
    names = [model.names[j] for j in range(1, model.njoints)]
    assert names == ['joint_1', 'joint_2', 'joint_3']
    assert [(t.header.frame_id, t.child_frame_id) for t in static[0].transforms] == [
        ('link_3', 'tool0')]


def test_differential_wheels_follow_their_angles_and_sensor_frames_are_static(
        start_node, ros_node, spin, publish):
    node, executor = ros_node
    c, b, imu, antenna = 0.15, 0.5, 0.2, 0.8
    start_node('robotica_kin', 'state_publisher', '-p', 'vehicle.type:=differential',
               '-p', f'vehicle.wheel_radius:={c}', '-p', f'vehicle.track:={b}',
               '-p', f'imu_height:={imu}', '-p', f'antenna_height:={antenna}',
               '-p', 'frame_prefix:=bot/')
    graph = _Graph(node, executor, spin)
    static = _edges(graph.static[-1])
    assert sorted(static) == ['bot/gps_link', 'bot/imu_link']
    for frame, height in (('bot/imu_link', imu), ('bot/gps_link', antenna)):
        parent, T = static[frame]
        assert parent == 'bot/base_link'
        np.testing.assert_allclose(T, transl(0.0, 0.0, height), atol=1e-12)
    for sec, (left, right) in enumerate([(0.7, -2.9), (12.5, 40.0)], start=1):
        assert publish(executor, graph.joints,
                       _joint_state(['right_wheel_joint', 'left_wheel_joint'], [right, left],
                                    sec=sec), graph.stamped(sec))
        edges = _edges(graph.latest(sec))
        assert sorted(edges) == ['bot/left_wheel_link', 'bot/right_wheel_link']
        for wheel, y, angle in (('left', b / 2, left), ('right', -b / 2, right)):
            parent, T = edges[f'bot/{wheel}_wheel_link']
            assert parent == 'bot/base_link'
            np.testing.assert_allclose(T, transl(0.0, y, c) @ roty(angle), atol=1e-12)


def test_bad_joint_states_are_refused_and_the_node_goes_on(start_node, ros_node, spin,
                                                           publish, read_output):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'state_publisher')
    graph = _Graph(node, executor, spin)
    assert publish(executor, graph.joints, _joint_state(PUMA_JOINTS, [0.1] * 6, sec=1),
                   graph.stamped(1))
    for bad, reason in [
            (_joint_state(['gripper'], [0.0], sec=2), 'names none of the joints'),
            (_joint_state(PUMA_JOINTS, [0.0, math.nan, 0.0, 0.0, 0.0, 0.0], sec=2),
             'non-finite joint position'),
            (JointState(name=PUMA_JOINTS, position=[0.0] * 7), '6 names but 7 position values'),
            (_joint_state(['joint_2'], [1e5], sec=2), '|position of joint_2| must be <='),
            (_joint_state(['joint_2'], [0.3], sec=2 ** 31 - 1), 'more than 3600.0 s from'),
            (_joint_state(['joint_2'], [0.3], sec=2, nanosec=10 ** 9), 'nanosec')]:
        # The guard logs one refusal per topic and second: resend until this one is logged.
        assert publish(executor, graph.joints, bad, lambda: reason in read_output(proc)), reason
    assert publish(executor, graph.joints, _joint_state(PUMA_JOINTS, [0.2] * 6, sec=3),
                   graph.stamped(3))
    assert {m.transforms[0].header.stamp.sec for m in graph.tf} == {1, 3}   # the bad dropped
    assert proc.poll() is None and 'Traceback' not in read_output(proc)


@pytest.mark.parametrize('args, reason', [
    (['vehicle.type:=hovercraft'], "vehicle.type must be one of ('', 'differential'"),
    (['vehicle.type:=bicycle', 'vehicle.wheelbase:=0.0'], 'wheelbase'),
    (['imu_height:=-1.0'], 'imu_height'),
])
def test_bad_configuration_exits_2(start_node, read_output, args, reason):
    proc = start_node('robotica_kin', 'state_publisher',
                      *[arg for a in args for arg in ('-p', a)])
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'invalid configuration' in text and reason in text, text
    assert 'Traceback' not in text
