"""
Tests of robotica_kin.pinocchio_model: Pinocchio models from modified-DH tables (catalog §12.4).

The joint frames of the model must be Craig's link frames (compared with a NumPy product of
(4.4) matrices), and the ``dyn`` columns must land in the right inertias. The arm keeps the
model/data split: its model is built once and read, the scratch ``Data`` is the caller's or
the arm's own for the calling thread.
"""

from concurrent.futures import ThreadPoolExecutor
import gc
import weakref

import numpy as np
import pinocchio as pin
import pytest

from reference_models import link_transform
from robotica_kin.dh import dh_model
from robotica_kin.dynamics import rne
from robotica_kin.pinocchio_model import (build_model, data_for, dyn_arm, pinocchio_arm,
                                          robot_and_arm, TOOL_FRAME)
from robotica_kin.robots import planar_rr, puma560, two_link_arm


@pytest.mark.parametrize('seed', range(4))
def test_joint_frames_are_craig_link_frames(seed):
    rng = np.random.default_rng(seed)
    table = np.column_stack([rng.uniform(-2, 2, (5, 4)), [0, 1, 0, 1, 0]])
    robot = dh_model(table)
    model = build_model(robot)
    data = model.createData()
    q = rng.uniform(-1, 1, 5)
    pin.forwardKinematics(model, data, q)
    T = np.eye(4)
    for i, row in enumerate(table):
        theta, d = (row[2], q[i]) if row[4] else (q[i], row[3])
        T = T @ link_transform(row[0], row[1], theta, d)
        np.testing.assert_allclose(data.oMi[i + 1].homogeneous, T, atol=1e-12)
    pin.updateFramePlacements(model, data)
    np.testing.assert_allclose(data.oMf[model.getFrameId('link_5')].homogeneous, T, atol=1e-12)
    assert [model.joints[i].shortname() for i in range(1, 6)] == [
        'JointModelRZ', 'JointModelPZ', 'JointModelRZ', 'JointModelPZ', 'JointModelRZ']


def test_puma560_dynamic_parameters_of_fig_a7():
    model = pinocchio_arm(puma560()).model
    link2 = model.inertias[2]
    assert link2.mass == pytest.approx(17.4)
    np.testing.assert_allclose(link2.lever, [0.068, 0.006, -0.016])
    # Inertia about the centre of mass, Ixx Iyy Izz = .13 .524 .539, no products.
    np.testing.assert_allclose(link2.inertia, np.diag([0.13, 0.524, 0.539]), atol=1e-12)
    assert model.inertias[1].mass == 0.0
    assert model.inertias[1].inertia[1, 1] == pytest.approx(0.35)
    # Reflected motor inertia J_m G^2 as armature: joint 1, 291e-6 * 62.6111^2 = 1.1408 kg m^2.
    assert model.armature[0] == pytest.approx(291e-6 * 62.6111 ** 2)
    np.testing.assert_allclose(model.lowerPositionLimit, puma560().qlim[:, 0])


def test_massless_model_without_dyn_and_tool_frame():
    tool = np.eye(4)
    tool[2, 3] = 0.1
    model = build_model(dh_model([[0, 0, 0, 0], [0, 1, 0, 0]], tool=tool))
    assert all(model.inertias[i].mass == 0.0 for i in range(model.njoints))
    assert model.existFrame('tool0')
    np.testing.assert_allclose(model.frames[model.getFrameId('tool0')].placement.homogeneous,
                               tool)


def test_arm_holds_the_robot_its_model_and_the_tool_frame():
    tool = np.eye(4)
    tool[:3, 3] = [0.1, -0.2, 0.3]
    robot = dh_model([[0, 0, 0, 0], [0, 1, 0, 0]], tool=tool)
    arm = pinocchio_arm(robot)
    assert arm.robot is robot
    np.testing.assert_array_equal(arm.tool.homogeneous, tool)
    assert arm.model.frames[arm.tool_frame].name == TOOL_FRAME
    q = np.array([0.4, -0.7])
    data = arm.model.createData()
    pin.forwardKinematics(arm.model, data, q)
    expected = link_transform(0, 0, q[0], 0) @ link_transform(0, 1, q[1], 0) @ tool
    np.testing.assert_allclose((data.oMi[2] * arm.tool).homogeneous, expected, atol=1e-12)
    # A raw table gets dh_model's defaults.
    assert pinocchio_arm([[0, 0, 0, 0]]).robot.joint_names == ('joint_1',)


def test_data_for_makes_scratch_or_checks_the_callers():
    arm = pinocchio_arm(puma560())
    data = arm.model.createData()
    assert data_for(arm, data) is data
    assert data_for(arm, None) is not data_for(arm, None)      # one per call when not given
    with pytest.raises(ValueError, match='Data of the model'):
        data_for(arm, pinocchio_arm(planar_rr(1.0, 1.0)).model.createData())
    with pytest.raises(ValueError, match='Data of the model'):
        data_for(arm, object())


def test_robot_and_arm_takes_data_only_with_an_arm():
    robot = planar_rr(1.0, 2.0)
    arm = pinocchio_arm(robot)
    assert robot_and_arm(robot, None) == (robot, None)
    assert robot_and_arm(arm, arm.model.createData()) == (robot, arm)
    with pytest.raises(ValueError, match='pass the arm'):
        robot_and_arm(robot, arm.model.createData())


def test_dyn_arm_needs_dynamics():
    _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    arm = dyn_arm(dyn)
    assert dyn_arm(arm) is arm
    np.testing.assert_array_equal(arm.robot.dyn, dyn)
    with pytest.raises(ValueError, match='no dyn table'):
        dyn_arm(pinocchio_arm(planar_rr(1.0, 1.0)))


def test_dyn_arm_keeps_one_arm_per_robot_object_while_the_robot_lives():
    robot = puma560()
    arm = dyn_arm(robot)
    assert dyn_arm(robot) is arm                       # built once for this robot object
    assert dyn_arm(puma560()) is not arm               # another object, another arm
    np.testing.assert_array_equal(arm.robot.dyn, robot.dyn)
    alive = weakref.ref(robot)
    del robot
    gc.collect()
    assert alive() is None                             # the kept arm does not keep it alive


def test_scratch_is_one_data_per_thread_and_checks_the_callers():
    arm = pinocchio_arm(puma560())
    own = arm.scratch()
    assert arm.scratch(None) is own and arm.model.check(own)
    with ThreadPoolExecutor(1) as pool:
        other = pool.submit(arm.scratch).result()
    assert other is not own and arm.model.check(other)
    data = arm.model.createData()
    assert arm.scratch(data) is data and arm.scratch(data) is data
    wrong = pinocchio_arm(planar_rr(1.0, 1.0)).model.createData()
    with pytest.raises(ValueError, match='Data of the model'):
        arm.scratch(wrong)                             # refused after a good one was checked
    assert arm.scratch(data) is data


def test_torque_bound_needs_dynamics():
    with pytest.raises(ValueError, match='no dyn table'):
        pinocchio_arm(planar_rr(1.0, 1.0)).torque_bound


def test_arm_model_is_shared_and_never_changed():
    """Another gravity goes to a copy; the arm's model keeps Pinocchio's default one."""
    arm = pinocchio_arm(puma560())
    data = arm.model.createData()
    q = np.array([0.1, -0.5, 0.6, 0.2, 0.4, -0.3])
    zero = np.zeros(6)
    tau_moon = rne(arm, q, zero, zero, grav=[0.0, 0.0, -1.62], data=data)
    np.testing.assert_array_equal(arm.model.gravity.linear, [0.0, 0.0, -9.81])
    np.testing.assert_allclose(rne(arm, q, zero, zero, data=data) * 1.62 / 9.81, tau_moon,
                               atol=1e-9)
