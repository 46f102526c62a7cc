"""
Fuzz tests of the robotica_kin nodes: hostile messages and requests, then valid ones.

fk_node's joint_states subscriber gets a seeded burst of hostile messages
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
from robotica_msgs.srv import ForwardKinematics, InverseKinematics
from sensor_msgs.msg import JointState

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
