"""
Tests of robotica_kin.pinocchio_model: Pinocchio models from modified-DH tables (catalog §12.4).

The joint frames of the model must be Craig's link frames (compared with a NumPy product of
(4.4) matrices), and the ``dyn`` columns must land in the right inertias.
"""

import numpy as np
import pinocchio as pin
import pytest

from reference_models import link_transform
from robotica_kin.dh import dh_model
from robotica_kin.pinocchio_model import build_model
from robotica_kin.robots import puma560


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
    model = puma560().pinocchio_model
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
