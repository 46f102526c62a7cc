"""
Node tests of ik_server: solutions checked by forward kinematics, refused requests, shutdown.

Goal poses and the checks of the answers are computed here by an independent route: the
product of Craig's link transforms ``linktrans(row, q_i)`` (book (4.5)-(4.6)) for the PUMA 560,
and the closed form (4.10) of the planar 3R of Ej. 4.1 (catalog §2.6).
"""
import math
import signal

from geometry_msgs.msg import Point, Pose, Quaternion
import numpy as np
import pytest
from robotica_kin.dh import linktrans
from robotica_kin.robots import puma560
from robotica_msgs.msg import DHParameter, DHTable
from robotica_msgs.srv import InverseKinematics
from scipy.spatial.transform import Rotation

pytestmark = pytest.mark.ros


def _chain(table, q):
    """Return T_0_n as the product of the link transforms (4.5)."""
    T = np.eye(4)
    for row, qi in zip(table, q):
        T = T @ linktrans(row, qi)
    return T


def _pose(T):
    x, y, z, w = Rotation.from_matrix(T[:3, :3]).as_quat()
    return Pose(position=Point(x=T[0, 3], y=T[1, 3], z=T[2, 3]),
                orientation=Quaternion(x=x, y=y, z=z, w=w))


def _planar_3r(l1, l2, q):
    """Ej. 4.1, (4.10): (x, y, phi) of frame {3} of the planar 3R."""
    t1, t12 = q[0], q[0] + q[1]
    return np.array([l1 * math.cos(t1) + l2 * math.cos(t12),
                     l1 * math.sin(t1) + l2 * math.sin(t12), t12 + q[2]])


@pytest.fixture
def ik(start_node, ros_node, call):
    node, executor = ros_node
    proc = start_node('robotica_kin', 'ik_server')
    client = node.create_client(InverseKinematics, '/ik_server/inverse_kinematics')
    assert client.wait_for_service(timeout_sec=15.0)

    def request(**fields):
        response = call(executor, client, InverseKinematics.Request(**fields))
        assert response is not None, 'no answer from ik_server'
        return response

    return proc, request


def test_puma_pose_is_reached(ik):
    proc, call = ik
    table = puma560().table
    q_goal = np.random.default_rng(560).uniform(-1.5, 1.5, 6)
    goal = _chain(table, q_goal)
    response = call(pose=_pose(goal))
    assert response.converged, response.message
    assert response.message == '' and response.residual <= 1e-6
    assert len(response.q) == 6 and response.iterations > 0
    np.testing.assert_allclose(_chain(table, response.q), goal, atol=1e-6)


def test_planar_3r_table_with_mask(ik):
    proc, call = ik
    l1, l2 = 4.0, 3.0   # Ej. H.3.1 dimensions
    dh = DHTable(links=[DHParameter(), DHParameter(a=l1), DHParameter(a=l2)])
    x, y, phi = _planar_3r(l1, l2, [0.3, 1.2, -0.5])
    goal = np.eye(4)
    goal[:3, :3] = Rotation.from_euler('z', phi).as_matrix()
    goal[:3, 3] = x, y, 0.5   # z out of the arm's plane: reachable only through the mask
    response = call(dh=dh, pose=_pose(goal), mask=[1.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                    q0=[0.0, 0.5, 0.0])
    assert response.converged, response.message
    got = _planar_3r(l1, l2, response.q)
    np.testing.assert_allclose(got[:2], [x, y], atol=1e-6)
    assert math.remainder(got[2] - phi, math.tau) == pytest.approx(0.0, abs=1e-6)


def test_unreachable_pose_then_next_request(ik):
    proc, call = ik
    far = np.eye(4)
    far[0, 3] = 10.0   # the PUMA reaches under 1 m
    response = call(pose=_pose(far))
    assert not response.converged
    assert 'no solution' in response.message and response.residual > 1.0
    assert len(response.q) == 6   # the last iterate
    q_goal = [0.2, -0.4, 0.3, 0.1, 0.5, -0.2]
    goal = _chain(puma560().table, q_goal)
    response = call(pose=_pose(goal), q0=[0.0] * 6)
    assert response.converged, response.message
    np.testing.assert_allclose(_chain(puma560().table, response.q), goal, atol=1e-6)


BAD_REQUESTS = [
    ({'pose': Pose(position=Point(x=math.nan))}, 'finite'),
    ({'pose': Pose(orientation=Quaternion(w=0.5))}, 'unit quaternion'),
    ({'q0': [0.0] * 5}, 'q0'),
    ({'mask': [1.0, 1.0, 1.0]}, 'mask'),
    ({'robot': 'kuka'}, "unknown robot 'kuka'"),
    ({'dh': DHTable(links=[DHParameter(a=math.inf)])}, 'finite'),
    ({'ilimit': -1}, 'ilimit'),
    ({'stol': math.nan}, 'stol'),
]


def test_bad_requests_are_answered_with_the_reason(ik):
    proc, call = ik
    q_goal = np.array([0.2, -0.4, 0.3, 0.1, 0.5, -0.2])
    goal = _chain(puma560().table, q_goal)
    for fields, reason in BAD_REQUESTS:
        response = call(**fields)
        assert not response.converged and len(response.q) == 0, fields
        assert reason in response.message, (fields, response.message)
        response = call(pose=_pose(goal), q0=(q_goal + 0.05).tolist())   # still answering
        assert response.converged, response.message
    assert proc.poll() is None


def test_unknown_robot_exits_2_and_sigint_exits_0(ik, start_node, read_output):
    proc, call = ik
    bad = start_node('robotica_kin', 'ik_server', '-p', 'robot:=kuka')
    assert bad.wait(timeout=30) == 2
    assert "unknown robot 'kuka'" in read_output(bad)
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=15) == 0
