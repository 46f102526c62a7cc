"""Tests of robotica_ctrl.joint_control.control_laws: the joint laws by name, gains checked."""
import numpy as np
import pytest
from robotica_ctrl.joint_control import (ComputedTorque, DecoupledPID, JointReference,
                                         JointState)
from robotica_ctrl.joint_control.control_laws import JOINT_LAWS, make_joint_law
from robotica_kin.parameter_specs import ParameterError
from robotica_kin.robots import puma560, two_link_arm


def test_computed_torque_at_rest_gives_the_gravity_torques():
    # Ej. 5.1 arm (m1 = 2, m2 = 1 kg at l1 = 3, l2 = 1 m) stretched along x, g along -y:
    # tau1 = (m1 l1 + m2 (l1 + l2)) g = 10 g, tau2 = m2 l2 g = g.
    law = make_joint_law('computed_torque', two_link_arm(2.0, 1.0, 3.0, 1.0)[1], {},
                         [0.0, -9.81, 0.0])
    assert isinstance(law, ComputedTorque)
    tau = law.update(JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 1e-3)
    np.testing.assert_allclose(tau, [98.1, 9.81], atol=1e-12)


def test_pid_gains_by_name():
    law = make_joint_law('pid', puma560(), {'kp': [100.0], 'kv': [1.0] * 6})
    assert isinstance(law, DecoupledPID)
    tau = law.update(JointReference([0.1] * 6), JointState([0.0] * 6, [0.0] * 6), 1e-3)
    np.testing.assert_allclose(tau, [10.0] * 6, atol=1e-12)   # K_p e


@pytest.mark.parametrize('law, gains, name, reason', [
    ('pid', {'kp': [-1.0]}, 'kp', 'must be >= 0'),
    ('pid', {'tau_max': [0.0]}, 'tau_max', 'must be > 0'),
    ('pid', {'kv': [1.0, 2.0]}, 'kv', 'must be a scalar or have shape (6,)'),
    ('computed_torque', {'ki': [1.0, 2.0, 3.0]}, 'ki', 'must be a scalar or have shape (6,)'),
    ('computed_torque', {'kp': 25.0}, 'kp', 'must be a list of numbers'),
    ('lqr', {}, 'law', f'must be one of {JOINT_LAWS}'),
])
def test_a_refused_gain_names_itself(law, gains, name, reason):
    with pytest.raises(ParameterError) as info:
        make_joint_law(law, puma560(), gains)
    assert info.value.name == name
    assert info.value.reason.startswith(reason)


def test_an_unknown_gain_is_refused():
    with pytest.raises(ValueError, match=r"computed_torque has no gain \['kd'\]"):
        make_joint_law('computed_torque', puma560(), {'kd': [1.0]})
