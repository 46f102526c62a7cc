"""
robotica_kin.urdf checked by parsers that are not ours: Pinocchio's URDF parser and yourdfpy.

Placements are compared with Craig's product of link transforms (``fkine``, ``link_frames``:
NumPy, book (4.6)); mass matrices with the project's ``inertia`` (CRBA on the model that
:mod:`robotica_kin.pinocchio_model` builds itself, not from the URDF) and, for the 2R of Ej. 5.1,
with the book's closed form (5.77). Vehicle wheels are compared with positions and drive
directions written from the geometry's definition (track b, wheel radius c, wheelbase l, ...),
the sensor frames with the heights given.
"""

import io
import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import pinocchio as pin
import pytest
from robotica_kin.dh import dh_model
from robotica_kin.dynamics import inertia
from robotica_kin.forward_kinematics import fkine, link_frames
from robotica_kin.mobile.vehicles import (GEOMETRY_PARAMETERS, vehicle_kinematics, VEHICLE_TYPES,
                                          VehicleGeometry)
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.robots import cylindrical_rpr, planar_rr, planar_rrr, puma560, two_link_arm
from robotica_kin.transforms import rpy2tr, transl
from robotica_kin.urdf import (arm_urdf, robot_description, ROBOT_DESCRIPTION_PARAMETERS,
                               SENSOR_FRAME_PARAMETERS, vehicle_urdf)
import yourdfpy

SAMPLES = 20


def _with_dyn(robot, seed):
    """Return ``robot`` with a made-up but physical dyn table (masses, CoMs, inertias, motors)."""
    rng = np.random.default_rng(seed)
    tail = np.zeros((robot.n, 15))
    for i in range(robot.n):
        a = rng.uniform(0.01, 0.2, 3)   # principal moments, rotated: a full tensor
        R = rpy2tr(rng.uniform(-math.pi, math.pi, 3))[:3, :3]
        tensor = R @ np.diag([a[1] + a[2], a[0] + a[2], a[0] + a[1]]) @ R.T
        tail[i, :4] = [rng.uniform(0.5, 5.0), *rng.uniform(-0.2, 0.2, 3)]
        tail[i, 4:10] = [tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[1, 2],
                         tensor[0, 2]]
        tail[i, 10:12] = [rng.uniform(1e-5, 1e-3), rng.uniform(10.0, 100.0)]
    return dh_model(robot.table, name=robot.name, qlim=robot.qlim, dyn=np.hstack(
        [robot.table, tail]), tool=robot.tool)


def _two_link():
    dh, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    return dh_model(dh, name='two_link', dyn=dyn)


ARMS = {
    'puma560': puma560,
    'two_link': _two_link,
    'planar_rr': planar_rr,
    'planar_rrr_tool': lambda: planar_rrr(4.0, 3.0, 0.5),
    'cylindrical_rpr': cylindrical_rpr,
    'cylindrical_rpr_dyn': lambda: _with_dyn(cylindrical_rpr(0.3, 0.8), 1),
    'puma560_full_tensors': lambda: _with_dyn(
        dh_model(puma560().table, name='puma', qlim=puma560().qlim,
                 tool=transl(0.0, 0.0, 0.1) @ rpy2tr(0.3, -0.2, 0.1)), 2),
}


def _samples(robot, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], (SAMPLES, robot.n))


@pytest.fixture(params=sorted(ARMS))
def arm(request):
    robot = ARMS[request.param]()
    text = arm_urdf(robot)
    return robot, text, pin.buildModelFromXML(text)


def test_pinocchio_frames_equal_fkine(arm):
    robot, _, model = arm
    data = model.createData()
    assert model.nq == robot.n
    assert [model.names[j] for j in range(1, model.njoints)] == list(robot.joint_names)
    for q in _samples(robot):
        pin.framesForwardKinematics(model, data, q)
        expected = link_frames(robot, q)
        for i in range(robot.n + 1):
            placement = data.oMf[model.getFrameId(f'link_{i}')].homogeneous
            np.testing.assert_allclose(placement, expected[i], rtol=0.0, atol=1e-12)
        tool = data.oMf[model.getFrameId('tool0')].homogeneous
        np.testing.assert_allclose(tool, fkine(robot, q), rtol=0.0, atol=1e-12)


def test_pinocchio_limits_are_the_model_limits(arm):
    robot, _, model = arm
    np.testing.assert_array_equal(model.lowerPositionLimit, robot.qlim[:, 0])
    np.testing.assert_array_equal(model.upperPositionLimit, robot.qlim[:, 1])
    assert np.all(model.effortLimit > 0.0) and np.all(model.velocityLimit > 0.0)


def test_pinocchio_mass_matrix_equals_the_project_s(arm):
    robot, _, model = arm
    if robot.dyn is None:
        assert all(model.inertias[j].mass == 0.0 for j in range(model.njoints))
        return
    # URDF has no motor inertia: add J_m G² (dyn columns 16, 17) as Pinocchio's armature.
    model.armature = robot.dyn[:, 15] * robot.dyn[:, 16] ** 2
    data = model.createData()
    for q in _samples(robot, seed=1):
        upper = pin.crba(model, data, q)
        M = np.triu(upper) + np.triu(upper, 1).T
        np.testing.assert_allclose(M, inertia(robot, q), rtol=0.0, atol=1e-10)


def test_two_link_mass_matrix_is_the_book_s():
    m1, m2, l1, l2 = 2.0, 1.0, 3.0, 1.0
    model = pin.buildModelFromXML(arm_urdf(_two_link()))
    data = model.createData()
    for q in _samples(_two_link()):
        c2 = math.cos(q[1])   # (5.77), point masses at the link ends
        m12 = l2 ** 2 * m2 + l1 * l2 * m2 * c2
        expected = [[l2 ** 2 * m2 + 2.0 * l1 * l2 * m2 * c2 + l1 ** 2 * (m1 + m2), m12],
                    [m12, l2 ** 2 * m2]]
        upper = pin.crba(model, data, q)
        np.testing.assert_allclose(np.triu(upper) + np.triu(upper, 1).T, expected, atol=1e-12)


def test_yourdfpy_loads_and_agrees(arm):
    robot, text, _ = arm
    urdf = yourdfpy.URDF.load(io.StringIO(text))
    assert urdf.validate()
    assert list(urdf.actuated_joint_names) == list(robot.joint_names)
    for q in _samples(robot, seed=2)[:3]:
        urdf.update_cfg(q)
        np.testing.assert_allclose(urdf.get_transform('tool0', 'link_0'), fkine(robot, q),
                                   atol=1e-12)
        if robot.dyn is not None:
            masses = [urdf.link_map[f'link_{i + 1}'].inertial.mass for i in range(robot.n)]
            assert masses == robot.dyn[:, 5].tolist()


def test_visuals_draw_every_link():
    root = ElementTree.fromstring(arm_urdf(puma560()))
    drawn = {link.get('name') for link in root.iter('link') if link.find('visual') is not None}
    assert drawn == {f'link_{i}' for i in range(7)} | {'tool0'}
    tool_axes = [v.find('material').get('name') for v in root.find("link[@name='tool0']")]
    assert tool_axes == ['x_axis', 'y_axis', 'z_axis']


@pytest.mark.parametrize('table, message', [
    ([[0, 0, 0, 0], [0, 1.0, math.inf, 0]], 'DH table row 2 has a non-finite entry'),
    ([[0, 0, 0, 0], [0, 1.0, 0]], 'numeric'),
    ([[0, 0, 0]], r'shape \(n, 4\), \(n, 5\) or \(n, 20\), got \(1, 3\)'),
    (np.vstack([np.zeros(20), np.r_[np.zeros(9), np.nan, np.zeros(10)]]),
     'dyn table row 2 has a non-finite entry'),
])
def test_malformed_tables_are_refused_naming_the_row(table, message):
    with pytest.raises(ValueError, match=message):
        arm_urdf(table)


def test_unphysical_dyn_rows_are_refused_naming_the_row():
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    negative_mass = dyn.copy()
    negative_mass[1, 5] = -1.0
    with pytest.raises(ValueError, match=r'dyn table row 2 \(joint_2\): the mass must be >= 0'):
        arm_urdf(negative_mass)
    indefinite = dyn.copy()
    indefinite[0, 9:15] = [1.0, 1.0, 1.0, 2.0, 0.0, 0.0]   # eigenvalues -1, 1, 3
    with pytest.raises(ValueError, match=r'dyn table row 1 \(joint_1\): the inertia tensor'):
        arm_urdf(indefinite)


def test_bad_limits_and_radius_are_refused():
    robot = planar_rr()
    with pytest.raises(ValueError, match=r'effort must have one value per joint \(2,\)'):
        arm_urdf(robot, effort=[1.0])
    with pytest.raises(ValueError, match='velocity of joint_2 must be finite and > 0'):
        arm_urdf(robot, velocity=[1.0, -1.0])
    with pytest.raises(ValueError, match='link_radius'):
        arm_urdf(robot, link_radius=math.nan)
    limits = pin.buildModelFromXML(arm_urdf(robot, effort=[30.0, 10.0], velocity=[2.0, 3.0]))
    assert limits.effortLimit.tolist() == [30.0, 10.0]
    assert limits.velocityLimit.tolist() == [2.0, 3.0]


GEOMETRY = VehicleGeometry(wheel_radius=0.15, track=0.5, wheelbase=0.9, base_radius=0.3,
                           half_length=0.35, max_steering_angle=0.6)
C, B, L = GEOMETRY.wheel_radius, GEOMETRY.track, GEOMETRY.wheelbase
H, R = GEOMETRY.half_length, GEOMETRY.base_radius
FORWARD = (1.0, 0.0, 0.0)
# Passive measuring wheels under the guide point, where a type has no wheels of its own there.
MEASURING = {'left_odometry_wheel_joint': ((0.0, B / 2, C), FORWARD),
             'right_odometry_wheel_joint': ((0.0, -B / 2, C), FORWARD)}
BETAS = (0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)
# Wheel joint: (centre in base_link at zero steering, direction its positive rate drives along).
WHEELS = {
    'differential': {'left_wheel_joint': ((0.0, B / 2, C), FORWARD),
                     'right_wheel_joint': ((0.0, -B / 2, C), FORWARD)},
    'skid_steer': {'left_wheel_joint': ((H, B / 2, C), FORWARD),
                   'right_wheel_joint': ((H, -B / 2, C), FORWARD),
                   'rear_left_wheel_joint': ((-H, B / 2, C), FORWARD),
                   'rear_right_wheel_joint': ((-H, -B / 2, C), FORWARD)},
    'mecanum': {f'{xn}_{yn}_wheel_joint': ((x, y, C), FORWARD)
                for xn, x in (('front', H), ('rear', -H))
                for yn, y in (('left', B / 2), ('right', -B / 2))} | MEASURING,
    # Omni wheel i drives tangentially, d_i = (-sin β_i, cos β_i) (omnidirectional.py).
    'omni_three': {f'wheel_{k}_joint': ((R * math.cos(b), R * math.sin(b), C),
                                        (-math.sin(b), math.cos(b), 0.0))
                   for k, b in enumerate(BETAS)} | MEASURING,
    'synchronous': {f'wheel_{k}_joint': ((R * math.cos(b), R * math.sin(b), C), FORWARD)
                    for k, b in enumerate(BETAS)} | MEASURING,
    'tricycle': {'front_wheel_joint': ((L, 0.0, C), FORWARD),
                 'left_wheel_joint': ((0.0, B / 2, C), FORWARD),
                 'right_wheel_joint': ((0.0, -B / 2, C), FORWARD)},
    'bicycle': {'front_wheel_joint': ((L, 0.0, C), FORWARD),
                'rear_wheel_joint': ((0.0, 0.0, C), FORWARD)} | MEASURING,
    'ackermann': {'front_left_wheel_joint': ((L, B / 2, C), FORWARD),
                  'front_right_wheel_joint': ((L, -B / 2, C), FORWARD),
                  'left_wheel_joint': ((0.0, B / 2, C), FORWARD),
                  'right_wheel_joint': ((0.0, -B / 2, C), FORWARD)},
}
STEERING = {'tricycle': {'steering_joint': (L, 0.0, C)},
            'bicycle': {'steering_joint': (L, 0.0, C)},
            'ackermann': {'front_left_steering_joint': (L, B / 2, C),
                          'front_right_steering_joint': (L, -B / 2, C)}}


def test_every_vehicle_type_is_covered():
    assert sorted(WHEELS) == sorted(VEHICLE_TYPES)


@pytest.mark.parametrize('vehicle_type', VEHICLE_TYPES)
def test_vehicle_wheels_are_where_the_geometry_says(vehicle_type):
    text = vehicle_urdf(vehicle_type, GEOMETRY)
    model = pin.buildModelFromXML(text)
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    expected = WHEELS[vehicle_type] | STEERING.get(vehicle_type, {})
    assert sorted(model.names[j] for j in range(1, model.njoints)) == sorted(expected)
    for name, where in expected.items():
        placement = data.oMi[model.getJointId(name)]
        centre = where[0] if name in WHEELS[vehicle_type] else where
        np.testing.assert_allclose(placement.translation, centre, atol=1e-12)
        if name in WHEELS[vehicle_type]:
            # A wheel turning by +dθ about its axis a rolls its centre by c dθ (a × z).
            joint = model.getJointId(name)
            local = pin.computeJointJacobian(model, data, pin.neutral(model), joint)
            axis = placement.rotation @ local[3:, model.joints[joint].idx_v]
            np.testing.assert_allclose(np.cross(axis, [0.0, 0.0, 1.0]), where[1], atol=1e-12)
    urdf = yourdfpy.URDF.load(io.StringIO(text))
    assert urdf.validate()
    for name, where in WHEELS[vehicle_type].items():
        child = urdf.joint_map[name].child
        np.testing.assert_allclose(urdf.get_transform(child, 'base_link')[:3, 3], where[0],
                                   atol=1e-12)


@pytest.mark.parametrize('vehicle_type', VEHICLE_TYPES)
def test_the_simulated_odometry_wheels_are_wheels_of_the_urdf(vehicle_type):
    # The simulator publishes the odometry wheels under these names: the URDF must have them
    # as wheels on the guide axle's line (y = +-b/2), turning forward with a positive rate.
    left, right = vehicle_kinematics(vehicle_type, GEOMETRY).odometry_wheel_joints
    assert WHEELS[vehicle_type][left][0][1:] == (B / 2, C)
    assert WHEELS[vehicle_type][right][0][1:] == (-B / 2, C)
    model = pin.buildModelFromXML(vehicle_urdf(vehicle_type, GEOMETRY))
    for name in (left, right):
        assert model.joints[model.getJointId(name)].shortname() == 'JointModelRUBY'


def test_steering_joints_have_the_steering_limit():
    model = pin.buildModelFromXML(vehicle_urdf('ackermann', GEOMETRY))
    joint = model.getJointId('front_left_steering_joint')
    index = model.joints[joint].idx_q
    assert model.lowerPositionLimit[index] == -0.6
    assert model.upperPositionLimit[index] == 0.6


def test_bad_vehicle_requests_are_refused():
    with pytest.raises(ValueError, match="unknown vehicle type 'hovercraft'"):
        vehicle_urdf('hovercraft')
    with pytest.raises(ValueError, match='geometry must be a VehicleGeometry, got dict'):
        vehicle_urdf('differential', {'track': 0.5})


@pytest.mark.parametrize('vehicle_type', VEHICLE_TYPES)
def test_sensor_frames_are_fixed_over_the_guide_point(vehicle_type):
    text = vehicle_urdf(vehicle_type, GEOMETRY, imu_height=0.25, antenna_height=1.5)
    model = pin.buildModelFromXML(text)
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    for link, height in (('imu_link', 0.25), ('gps_link', 1.5)):
        frame = model.frames[model.getFrameId(link)]
        assert frame.parentJoint == 0   # fixed to base_link, which is the root
        np.testing.assert_allclose(data.oMf[model.getFrameId(link)].homogeneous,
                                   transl(0.0, 0.0, height), atol=1e-15)
    urdf = yourdfpy.URDF.load(io.StringIO(text))
    assert urdf.validate()
    assert {urdf.joint_map[name].type for name in ('imu_joint', 'gps_joint')} == {'fixed'}
    np.testing.assert_allclose(urdf.get_transform('gps_link', 'base_link'),
                               transl(0.0, 0.0, 1.5), atol=1e-15)


def test_sensor_heights_default_to_their_parameters_and_bad_ones_are_refused():
    root = ElementTree.fromstring(vehicle_urdf('differential'))
    origins = {j.get('name'): j.find('origin').get('xyz') for j in root.iter('joint')}
    assert origins['imu_joint'] == f'0.0 0.0 {SENSOR_FRAME_PARAMETERS["imu_height"].default!r}'
    assert origins['gps_joint'] == '0.0 0.0 0.0'   # the GPS emulator's antenna_height default
    with pytest.raises(ValueError, match='imu_height must be >= 0 m, got -0.1'):
        vehicle_urdf('differential', imu_height=-0.1)
    with pytest.raises(ValueError, match='antenna_height'):
        vehicle_urdf('differential', antenna_height=math.inf)


def test_robot_description_chooses_with_the_simulator_s_geometry_specs():
    for name, spec in GEOMETRY_PARAMETERS.items():
        assert ROBOT_DESCRIPTION_PARAMETERS[f'vehicle.{name}'] is spec
    assert robot_description({}, planar_rr()) == arm_urdf(planar_rr())
    values = {'vehicle.type': 'tricycle', 'vehicle.wheelbase': 0.9, 'vehicle.wheel_radius': 0.15,
              'vehicle.track': 0.5, 'antenna_height': 1.0, 'other': 'ignored'}
    assert robot_description(values, planar_rr()) == vehicle_urdf(
        'tricycle', VehicleGeometry(wheel_radius=0.15, track=0.5, wheelbase=0.9),
        antenna_height=1.0)
    with pytest.raises(ParameterError, match='vehicle.track must be in'):
        robot_description({'vehicle.type': 'differential', 'vehicle.track': 0.0}, planar_rr())
    with pytest.raises(ParameterError, match='vehicle.type must be one of'):
        robot_description({'vehicle.type': 'hovercraft'}, planar_rr())
