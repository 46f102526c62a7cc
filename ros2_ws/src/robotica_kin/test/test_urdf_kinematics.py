"""
robotica_kin.urdf_kinematics: the joint transforms a state publisher sends, against other routes.

An arm's transforms, composed here in NumPy, are Craig's link frames (``link_frames``, ``fkine``:
the DH product (4.6)); a vehicle's wheel and steering frames are written from the geometry
(centre at (x, y, c), turned about the axle y by the wheel angle, about z by the steering angle);
a mimic joint follows its joint as the URDF ``<mimic>`` element defines.
"""
import numpy as np
import pytest
from robotica_kin.forward_kinematics import fkine, link_frames
from robotica_kin.mobile.vehicles import VehicleGeometry
from robotica_kin.robots import cylindrical_rpr, planar_rrr, puma560
from robotica_kin.transforms import roty, rotz, transl
from robotica_kin.urdf import arm_urdf, vehicle_urdf
from robotica_kin.urdf_kinematics import URDFKinematics

GEOMETRY = VehicleGeometry(wheel_radius=0.15, track=0.5, wheelbase=0.9, half_length=0.35)
C, B, L, H = 0.15, 0.5, 0.9, 0.35


def _edges(transforms):
    return {t.child: (t.parent, t.T) for t in transforms}


@pytest.mark.parametrize('robot', [puma560(), planar_rrr(4.0, 3.0, 0.5), cylindrical_rpr()],
                         ids=lambda robot: robot.name)
def test_arm_transforms_compose_to_the_dh_frames(robot):
    kinematics = URDFKinematics(arm_urdf(robot))
    assert kinematics.joint_names == robot.joint_names and not kinematics.continuous
    rng = np.random.default_rng(3)
    for q in rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], (10, robot.n)):
        edges = _edges(kinematics.moving(q) + list(kinematics.fixed))
        frames = link_frames(robot, q)
        for i in range(1, robot.n + 1):
            parent, T = edges[f'link_{i}']
            assert parent == f'link_{i - 1}'
            np.testing.assert_allclose(frames[i - 1] @ T, frames[i], atol=1e-12)
        parent, T = edges['tool0']
        assert parent == f'link_{robot.n}'
        np.testing.assert_allclose(frames[-1] @ T, fkine(robot, q), atol=1e-12)


def test_mimic_wheels_follow_theirs_and_continuous_angles_are_unbounded():
    kinematics = URDFKinematics(vehicle_urdf('skid_steer', GEOMETRY))
    assert kinematics.joint_names == ('left_wheel_joint', 'right_wheel_joint')
    assert kinematics.continuous == {'left_wheel_joint', 'right_wheel_joint',
                                     'rear_left_wheel_joint', 'rear_right_wheel_joint'}
    left, right = 0.4, 1e4 + 0.3
    edges = _edges(kinematics.moving([left, right]))
    expected = {'left_wheel_link': transl(H, B / 2, C) @ roty(left),
                'rear_left_wheel_link': transl(-H, B / 2, C) @ roty(left),
                'right_wheel_link': transl(H, -B / 2, C) @ roty(right),
                'rear_right_wheel_link': transl(-H, -B / 2, C) @ roty(right)}
    assert sorted(edges) == sorted(expected)
    for link, T in expected.items():
        assert edges[link][0] == 'base_link'
        np.testing.assert_allclose(edges[link][1], T, atol=1e-11)


def test_steered_wheels_hang_from_their_steering_links():
    kinematics = URDFKinematics(vehicle_urdf('ackermann', GEOMETRY, imu_height=0.3,
                                             antenna_height=1.2))
    names = kinematics.joint_names
    q = {'front_left_steering_joint': 0.3, 'front_left_wheel_joint': 2.0,
         'front_right_steering_joint': 0.25, 'front_right_wheel_joint': -1.0,
         'left_wheel_joint': 5.0, 'right_wheel_joint': 6.0}
    assert sorted(names) == sorted(q)
    edges = _edges(kinematics.moving([q[name] for name in names]))
    for side, y in (('left', B / 2), ('right', -B / 2)):
        parent, T = edges[f'front_{side}_steering_link']
        assert parent == 'base_link'
        np.testing.assert_allclose(T, transl(L, y, C) @ rotz(q[f'front_{side}_steering_joint']),
                                   atol=1e-12)
        parent, T = edges[f'front_{side}_wheel_link']
        assert parent == f'front_{side}_steering_link'
        np.testing.assert_allclose(T, roty(q[f'front_{side}_wheel_joint']), atol=1e-12)
    fixed = _edges(kinematics.fixed)
    assert sorted(fixed) == ['gps_link', 'imu_link']
    np.testing.assert_allclose(fixed['imu_link'][1], transl(0.0, 0.0, 0.3), atol=1e-15)
    np.testing.assert_allclose(fixed['gps_link'][1], transl(0.0, 0.0, 1.2), atol=1e-15)


FLOATING = """<robot name="f"><link name="a"/><link name="b"/>
<joint name="j" type="floating"><parent link="a"/><child link="b"/></joint></robot>"""
BAD_MIMIC = """<robot name="m"><link name="a"/><link name="b"/>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="nowhere"/></joint></robot>"""


@pytest.mark.parametrize('urdf, message', [
    ('<robot name="x"><link', 'cannot be read'),
    (FLOATING, "joint 'j' .* is not revolute, continuous, prismatic or fixed"),
    (BAD_MIMIC, "mimic joint 'j' follows 'nowhere', not a moving joint"),
])
def test_unusable_urdfs_are_refused(urdf, message):
    with pytest.raises(ValueError, match=message):
        URDFKinematics(urdf)


def test_positions_must_be_one_per_joint():
    with pytest.raises(ValueError, match=r'one value per joint \(6,\), got shape \(5,\)'):
        URDFKinematics(arm_urdf(puma560())).moving(np.zeros(5))
