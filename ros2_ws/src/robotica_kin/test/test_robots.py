"""Tests of robotica_kin.robots: the book's manipulators (catalog §2.6, §12.4)."""
import math

import numpy as np
import pytest

from robotica_kin.robots import (cylindrical_rpr, planar_rr, planar_rrr, puma560, robot_by_name,
                                 ROBOT_NAMES)


def test_puma560_tables_are_hemero_dhp560_and_fig_a7():
    robot = puma560()
    np.testing.assert_allclose(robot.alpha, [0, -math.pi / 2, 0, math.pi / 2, -math.pi / 2,
                                             math.pi / 2])
    np.testing.assert_allclose(robot.a, [0, 0, 0.4318, -0.0203, 0, 0])
    np.testing.assert_allclose(robot.d, [0, 0.2435, -0.0934, 0.4331, 0, 0])
    assert not robot.prismatic.any()
    # Fig. A.7: masses, gear ratios, motor inertias; link 1 massless with Iyy = 0.35.
    np.testing.assert_allclose(robot.dyn[:, 5], [0, 17.4, 4.8, 0.82, 0.34, 0.09])
    np.testing.assert_allclose(robot.dyn[:, 16], [-62.6111, 107.815, -53.7063, 76.0364, 71.923,
                                                  76.686])
    np.testing.assert_allclose(robot.dyn[:, 15], [291e-6, 409e-6, 299e-6, 35e-6, 35e-6, 35e-6])
    assert robot.dyn[0, 10] == 0.35
    np.testing.assert_allclose(robot.dyn[:, 17:], 0.0)
    assert robot.within_limits(np.zeros(6))


def test_puma560_joint_limits_are_opt_in():
    # HEMERO's dhp560 has none: the default ±π bounds no revolute joint. Craig's PUMA 560 ranges
    # [deg] in the same frames come with joint_limits=True.
    np.testing.assert_array_equal(puma560().qlim, [[-math.pi, math.pi]] * 6)
    craig = [[-160, 160], [-225, 45], [-45, 225], [-110, 170], [-100, 100], [-266, 266]]
    np.testing.assert_allclose(np.degrees(puma560(joint_limits=True).qlim), craig, rtol=1e-12)


def test_planar_and_cylindrical_tables():
    np.testing.assert_allclose(planar_rrr(4.0, 3.0).a, [0, 4, 3])
    np.testing.assert_allclose(planar_rr(4.0, 3.0).tool[:3, 3], [3, 0, 0])
    rpr = cylindrical_rpr(0.25, d2_max=0.8)
    assert rpr.prismatic.tolist() == [False, True, False]
    np.testing.assert_allclose(rpr.alpha, [0, math.pi / 2, 0])
    np.testing.assert_allclose(rpr.d, [0, 0, 0.25])
    np.testing.assert_allclose(rpr.qlim[1], [0.0, 0.8])


@pytest.mark.parametrize('name', ROBOT_NAMES)
def test_robot_by_name(name):
    assert robot_by_name(name).name == name


@pytest.mark.parametrize('call', [lambda: robot_by_name('puma561'), lambda: planar_rr(-1.0, 1.0),
                                  lambda: planar_rrr(1.0, 1.0, -0.1),
                                  lambda: cylindrical_rpr(math.nan)])
def test_bad_robots_are_refused(call):
    with pytest.raises(ValueError):
        call()
