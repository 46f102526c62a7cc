"""
Node tests of fk_node: poses from real joint states, the FK service, start-up and shutdown.

References are computed here by an independent route: the product of Craig's link transforms
``linktrans(row, q_i)`` (book (4.5)-(4.6)) of the PUMA 560 table, and the closed form (4.10) of
the planar 3R of Ej. 4.1 (catalog §2.6), not by ``fkine``.
"""
import math
import signal

from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseArray, PoseStamped
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.dh import linktrans
from robotica_kin.robots import puma560
from robotica_msgs.msg import DHParameter, DHTable
from robotica_msgs.srv import ForwardKinematics
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import JointState

pytestmark = pytest.mark.ros
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
# fk_node's streams keep a transient-local history (nodes/qos.py) so that a reader matched a
# little after the first message still gets it; the test's readers ask for it too.
STREAM = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                    durability=DurabilityPolicy.TRANSIENT_LOCAL)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
PUMA_JOINTS = [f'joint_{i}' for i in range(1, 7)]


def _chain(table, q):
    """Return T_0_i, i = 0 … n, as products of link transforms (4.5)."""
    frames = [np.eye(4)]
    for row, qi in zip(table, q):
        frames.append(frames[-1] @ linktrans(row, qi))
    return frames


def _matrix(pose):
    T = np.eye(4)
    o = pose.orientation
    T[:3, :3] = Rotation.from_quat([o.x, o.y, o.z, o.w]).as_matrix()
    T[:3, 3] = [pose.position.x, pose.position.y, pose.position.z]
    return T


def _planar_3r(l1, l2, q):
    """Ej. 4.1, (4.10): T_0_3 of the planar 3R with links l1, l2."""
    t1, t12, t123 = q[0], q[0] + q[1], q[0] + q[1] + q[2]
    T = np.eye(4)
    T[:2, :2] = [[math.cos(t123), -math.sin(t123)], [math.sin(t123), math.cos(t123)]]
    T[:2, 3] = [l1 * math.cos(t1) + l2 * math.cos(t12), l1 * math.sin(t1) + l2 * math.sin(t12)]
    return T


def _joint_state(names, q, sec=0):
    msg = JointState(name=list(names), position=[float(v) for v in q])
    msg.header.stamp = Time(sec=sec, nanosec=123)
    return msg


def _dh_table(l1, l2):
    return DHTable(name='ej_4_1', links=[
        DHParameter(), DHParameter(a=l1), DHParameter(a=l2, sigma=DHParameter.REVOLUTE)])


@pytest.fixture
def fk(start_node, ros_node, spin):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'fk_node')
    poses, links = [], []
    node.create_subscription(PoseStamped, '/fk_node/end_effector_pose', poses.append, STREAM)
    node.create_subscription(PoseArray, '/fk_node/link_poses', links.append, STREAM)
    joints = node.create_publisher(JointState, 'joint_states', QOS)
    assert spin(executor, lambda: joints.get_subscription_count() > 0 and
                node.count_publishers('/fk_node/end_effector_pose') > 0 and
                node.count_publishers('/fk_node/link_poses') > 0)
    return proc, node, executor, joints, poses, links


def _call(node, executor, call, client, request):
    response = call(executor, client, request)
    assert response is not None, 'no answer from fk_node'
    return response


def test_end_effector_pose_and_link_frames(fk, publish):
    proc, node, executor, joints, poses, links = fk
    table = puma560().table
    rng = np.random.default_rng(560)
    q_random = rng.uniform(-2.5, 2.5, 6)
    order = [4, 0, 5, 2, 1, 3]   # shuffled, plus a joint the robot does not have
    shuffled = _joint_state(['gripper'] + [PUMA_JOINTS[i] for i in order],
                            [0.5] + [q_random[i] for i in order], sec=3)
    cases = [(_joint_state(PUMA_JOINTS, np.zeros(6), sec=1), np.zeros(6)),
             (_joint_state(PUMA_JOINTS, q_random, sec=2), q_random),
             (shuffled, q_random)]
    for k, (msg, q) in enumerate(cases):
        assert publish(executor, joints, msg, lambda: poses and links and
                       poses[-1].header.stamp.sec == links[-1].header.stamp.sec == k + 1)
        expected = _chain(table, q)
        assert poses[-1].header.stamp == Time(sec=k + 1, nanosec=123)
        assert poses[-1].header.frame_id == 'link_0'
        np.testing.assert_allclose(_matrix(poses[-1].pose), expected[-1], atol=1e-9)
        assert len(links[-1].poses) == 6 + 2
        assert links[-1].header == poses[-1].header
        for pose, T in zip(links[-1].poses, expected + [expected[-1]]):
            np.testing.assert_allclose(_matrix(pose), T, atol=1e-9)


def test_malformed_joint_states_are_refused(fk, spin, publish, read_output):
    proc, node, executor, joints, poses, links = fk
    for bad, reason in [
            (_joint_state(PUMA_JOINTS[:5], np.zeros(5), sec=1), "lacks positions of ['joint_6']"),
            (_joint_state(PUMA_JOINTS, [0.0, math.nan, 0.0, 0.0, 0.0, 0.0], sec=2),
             'non-finite joint position'),
            (_joint_state(PUMA_JOINTS + ['joint_1'], [0.0] * 6 + [2.0], sec=2),   # which joint_1?
             "names ['joint_1'] more than once"),
            (JointState(name=PUMA_JOINTS, position=[0.0] * 7), '6 names but 7 position values')]:
        # The guard logs one refusal per topic and second: resend until this one is logged.
        assert publish(executor, joints, bad, lambda: reason in read_output(proc)), reason
    assert publish(executor, joints, _joint_state(PUMA_JOINTS, np.zeros(6), sec=3), lambda: poses)
    spin(executor, lambda: False, timeout=0.5)
    assert {p.header.stamp.sec for p in poses} == {3}   # the malformed ones dropped
    assert proc.poll() is None


def test_service_planar_3r_closed_form_and_errors(fk, call):
    proc, node, executor, joints, poses, links = fk
    client = node.create_client(ForwardKinematics, '/fk_node/forward_kinematics')
    rng = np.random.default_rng(41)
    for _ in range(3):
        l1, l2 = rng.uniform(0.5, 5.0, 2)
        q = rng.uniform(-math.pi, math.pi, 3)
        response = _call(node, executor, call, client,
                         ForwardKinematics.Request(dh=_dh_table(l1, l2), q=q.tolist()))
        assert response.success, response.message
        np.testing.assert_allclose(_matrix(response.pose), _planar_3r(l1, l2, q), atol=1e-9)

    response = _call(node, executor, call, client, ForwardKinematics.Request(q=[0.0] * 5))
    assert not response.success and 'shape (6,)' in response.message
    response = _call(node, executor, call, client,
                     ForwardKinematics.Request(q=[0.0, math.nan, 0.0, 0.0, 0.0, 0.0]))
    assert not response.success and 'finite' in response.message
    response = _call(node, executor, call, client,
                     ForwardKinematics.Request(robot='kuka', q=[0.0] * 6))
    assert not response.success and "unknown robot 'kuka'" in response.message
    bad = _dh_table(1.0, 1.0)
    bad.links[1].sigma = 7
    response = _call(node, executor, call, client,
                     ForwardKinematics.Request(dh=bad, q=[0.0] * 3))
    assert not response.success and 'sigma' in response.message
    q = [0.3, -0.2, 0.1]   # named robot, default dimensions l1 = l2 = 1
    response = _call(node, executor, call, client,
                     ForwardKinematics.Request(robot='planar_rrr', q=q))
    assert response.success
    np.testing.assert_allclose(_matrix(response.pose), _planar_3r(1.0, 1.0, q), atol=1e-9)
    assert proc.poll() is None


def test_dh_table_parameter_and_joint_names(start_node, ros_node, spin, publish):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'fk_node', '-p', "robot:=''",
                      '-p', 'dh_table:=[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, '
                      '0.0, 3.0, 0.0, 0.0, 0.0]', '-p', 'joint_names:=[a, b, c]',
                      '-p', 'base_frame_id:=arm_base')
    poses = []
    node.create_subscription(PoseStamped, '/fk_node/end_effector_pose', poses.append, STREAM)
    joints = node.create_publisher(JointState, 'joint_states', QOS)
    assert spin(executor, lambda: joints.get_subscription_count() > 0 and
                node.count_publishers('/fk_node/end_effector_pose') > 0)
    q = [0.4, -1.1, 0.7]
    assert publish(executor, joints, _joint_state(['c', 'a', 'b'], [q[2], q[0], q[1]]),
                   lambda: poses)
    assert poses[0].header.frame_id == 'arm_base'
    np.testing.assert_allclose(_matrix(poses[0].pose), _planar_3r(4.0, 3.0, q), atol=1e-9)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=15) == 0


@pytest.mark.parametrize('args, reason', [
    (['robot:=kuka'], "unknown robot 'kuka'"),
    (["robot:=''", 'dh_table:=[0.0, 1.0, 0.0]'], 'got 3 values'),
    (["robot:=''", 'dh_table:=[0.0, 1.0, 0.0, .nan, 0.0]'], 'finite'),
])
def test_bad_configuration_exits_2(start_node, read_output, args, reason):
    ros_args = [arg for a in args for arg in ('-p', a)]
    proc = start_node('robotica_kin', 'fk_node', *ros_args)
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert 'invalid configuration' in text and reason in text
    assert 'Traceback' not in text


def test_dh_table_is_latched_and_sigint_exits_0(fk, spin):
    proc, node, executor, joints, poses, links = fk
    tables = []
    node.create_subscription(DHTable, '/fk_node/robot_description_dh', tables.append, LATCHED)
    assert spin(executor, lambda: tables)
    msg = tables[0]
    assert msg.name == 'puma560' and list(msg.joint_names) == PUMA_JOINTS
    assert msg.header.frame_id == 'link_0'
    got = [[p.alpha, p.a, p.theta, p.d, p.sigma] for p in msg.links]
    dhp560 = [[0, 0, 0, 0, 0], [-math.pi / 2, 0, 0, 0.2435, 0], [0, 0.4318, 0, -0.0934, 0],
              [math.pi / 2, -0.0203, 0, 0.4331, 0], [-math.pi / 2, 0, 0, 0, 0],
              [math.pi / 2, 0, 0, 0, 0]]   # HEMERO dhp560, book §A.2
    np.testing.assert_allclose(got, dhp560)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=15) == 0
