"""
Fuzz tests of the robotica_kin nodes: hostile messages and requests, then valid ones.

fk_node's and state_publisher's joint_states subscribers get a seeded burst of hostile messages
(:func:`robotica_kin.ros.hostile.fuzz`); both services get hostile requests (every field NaN,
±inf, ±1e308, extreme integers, empty or wrong-size arrays, odd strings). The nodes must stay
alive, answer every request, publish nothing non-finite, and answer valid input normally after.
"""
import random
import time

from geometry_msgs.msg import Point, Pose, PoseArray, PoseStamped, Quaternion
import pytest
from robotica_kin.ros.convert import seconds_to_stamp
from robotica_kin.ros.guarded import non_finite_fields
from robotica_kin.ros.hostile import fuzz, hostile_message
from robotica_msgs.msg import DHParameter, DHTable
from robotica_msgs.srv import ForwardKinematics, InverseKinematics
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

pytestmark = pytest.mark.ros
PUMA_JOINTS = [f'joint_{i}' for i in range(1, 7)]
REQUESTS = 25        # hostile requests per service
REQUEST_SECONDS = 20.0


def _joint_state(t):
    msg = JointState(name=PUMA_JOINTS, position=[0.1] * 6)
    msg.header.stamp = seconds_to_stamp(t)
    return msg


def test_fk_node_joint_states(start_node, ros_node, fuzz_survived):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'fk_node')
    outputs = {'/fk_node/end_effector_pose': PoseStamped, '/fk_node/link_poses': PoseArray}
    received, ok = fuzz(
        node, executor, {'joint_states': (JointState, _joint_state)}, outputs,
        lambda got: any(m.header.stamp.sec >= 100
                        for m in got['/fk_node/end_effector_pose'][-20:]),
        random.Random('fk_node-16'))
    fuzz_survived(proc, received, ok)


@pytest.mark.parametrize('node_name, srv_type, service, valid, answered', [
    ('fk_node', ForwardKinematics, '/fk_node/forward_kinematics',
     ForwardKinematics.Request(q=[0.1] * 6), lambda r: r.success),
    ('ik_server', InverseKinematics, '/ik_server/inverse_kinematics',
     InverseKinematics.Request(pose=Pose(position=Point(x=0.4, y=0.1, z=0.3),
                                         orientation=Quaternion(w=1.0))),
     lambda r: r.message is not None),
])
def test_hostile_requests(node_name, srv_type, service, valid, answered, start_node, ros_node,
                          call, read_output):
    node, executor = ros_node
    proc = start_node('robotica_kin', node_name)
    client = node.create_client(srv_type, service)
    rng = random.Random(f'{node_name}-16')
    deadline = time.monotonic() + REQUEST_SECONDS
    for _ in range(REQUESTS):
        template = valid if rng.random() < 0.5 else None
        request = hostile_message(srv_type.Request, rng, template, rate=0.3)
        assert call(executor, client, request, timeout=5.0) is not None, read_output(proc)
        if time.monotonic() > deadline:
            break
    assert proc.poll() is None
    response = call(executor, client, valid)
    assert response is not None and answered(response)
    assert not non_finite_fields(response)
    assert 'Traceback' not in read_output(proc)


BIG = 10 ** 6
FAR = Pose(position=Point(x=100.0), orientation=Quaternion(w=1.0))   # beyond the PUMA's reach
LONG_TABLE = DHTable(links=[DHParameter(a=0.01)] * 101)              # MAX_JOINTS = 100


@pytest.mark.parametrize('node_name, srv_type, service, requests, valid', [
    ('fk_node', ForwardKinematics, '/fk_node/forward_kinematics', [
        ForwardKinematics.Request(q=[0.1] * BIG),
        ForwardKinematics.Request(q=[]),
        ForwardKinematics.Request(dh=LONG_TABLE, q=[0.1] * 101),
        ForwardKinematics.Request(robot='p' * 10 ** 5, q=[0.1] * 6)],
     ForwardKinematics.Request(q=[0.1] * 6)),
    ('ik_server', InverseKinematics, '/ik_server/inverse_kinematics', [
        InverseKinematics.Request(pose=FAR, ilimit=2 ** 31 - 1),   # hours of iterations
        InverseKinematics.Request(pose=FAR, stol=1e308),           # 'converged' anywhere
        InverseKinematics.Request(pose=FAR, mask=[1.0] * BIG),     # 5 MB of message and log
        InverseKinematics.Request(pose=FAR, q0=[0.1] * BIG),
        InverseKinematics.Request(pose=FAR, dh=LONG_TABLE)],       # 500 joints: 4 GB, 20 s
     InverseKinematics.Request(pose=Pose(position=Point(x=0.4, y=0.1, z=0.3),
                                         orientation=Quaternion(w=1.0)))),
])
def test_requests_of_absurd_size_are_refused_at_once(node_name, srv_type, service, requests,
                                                     valid, start_node, ros_node, call,
                                                     read_output):
    node, executor = ros_node
    proc = start_node('robotica_kin', node_name)
    client = node.create_client(srv_type, service)
    for request in requests:   # refused before any work: answered (hours of work are not)
        response = call(executor, client, request, attempts=1, timeout=10.0)
        assert response is not None, read_output(proc)[-2000:]
        assert not getattr(response, 'success', False) and not getattr(response, 'q', [])
        assert 0 < len(response.message) < 600
    assert call(executor, client, valid) is not None
    text = read_output(proc)
    assert proc.poll() is None and 'Traceback' not in text
    assert max(map(len, text.splitlines())) < 1000


def test_state_publisher_joint_states(start_node, ros_node, fuzz_survived):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'state_publisher')
    received, ok = fuzz(
        node, executor, {'joint_states': (JointState, _joint_state)}, {'/tf': TFMessage},
        lambda got: any(m.transforms and m.transforms[0].header.stamp.sec >= 100
                        for m in got['/tf'][-20:]),
        random.Random('state_publisher-17'))
    fuzz_survived(proc, received, ok)
