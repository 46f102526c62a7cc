"""Tests of robotica_ctrl.trajectory.joint_reference: the trajectory publisher's samples."""
import math

import numpy as np
import pytest
from robotica_ctrl.trajectory.joint_reference import (MAX_TRAJECTORY_POINTS, reference_samples,
                                                      trajectory_samples)
from robotica_kin.parameter_specs import ParameterError


def test_sine_of_ej_8_1():
    # Ej. 8.1 (8.47): theta1d = A sin(2 pi t / T), theta2d = A cos(2 pi t / T), A = 0.15, T = 4.
    t, q, qd, qdd = reference_samples({
        'joint_names': ['joint_1', 'joint_2'], 'duration': 4.0, 'sample_period': 0.5,
        'sine.amplitude': [0.15], 'sine.period': [4.0], 'sine.phase': [0.0, math.pi / 2]})
    assert t.tolist() == [0.5 * k for k in range(9)]
    np.testing.assert_allclose(q[:, 0], 0.15 * np.sin(np.pi * t / 2), atol=1e-15)
    np.testing.assert_allclose(q[:, 1], 0.15 * np.cos(np.pi * t / 2), atol=1e-15)
    np.testing.assert_allclose(qd[:, 0], 0.15 * np.pi / 2 * np.cos(np.pi * t / 2), atol=1e-15)
    np.testing.assert_allclose(qdd[:, 0], -0.15 * (np.pi / 2) ** 2 * np.sin(np.pi * t / 2),
                               atol=1e-15)


def test_cubic_through_two_points():
    t, q, qd, _ = trajectory_samples('pol3', 1, 0.5, via={'positions': [0.0, 1.0],
                                                          'segment_durations': [1.0]})
    assert t.tolist() == [0.0, 0.5, 1.0]
    assert q[:, 0].tolist() == [0.0, 0.5, 1.0]   # 3 s^2 - 2 s^3 at s = 1/2: 1/2
    assert qd[0, 0] == qd[-1, 0] == 0.0


@pytest.mark.parametrize('parameters, name', [
    ({'sine.period': [0.0]}, 'sine.period'),
    ({'sine.amplitude': [math.nan]}, 'sine.amplitude'),
    ({'generator': 'spline'}, 'generator'),
    ({'sample_period': 20.0}, 'sample_period'),
    ({'generator': 'pol3', 'via.positions': [0.0, 1.0, 2.0]}, 'via.positions'),
    ({'generator': 'parab', 'via.positions': [0.0, 0.0, 1.0, 1.0],
      'via.segment_durations': [1.0], 'parab.acceleration': [1.0, 1.0, 1.0]},
     'parab.acceleration'),
])
def test_a_refusal_names_the_node_parameter(parameters, name):
    with pytest.raises(ParameterError) as info:
        reference_samples({'joint_names': ['a', 'b'], **parameters})
    assert info.value.name == name


def test_no_joints_is_refused():
    with pytest.raises(ParameterError, match='joint_names must name the joints'):
        reference_samples({'generator': 'sine'})


@pytest.mark.parametrize('parameters, name', [
    ({'duration': 200.0, 'sample_period': 1e-4}, 'duration'),
    ({'generator': 'pol3', 'via.positions': [0.0, 1.0], 'via.segment_durations': [200.0],
      'sample_period': 1e-4}, 'via.segment_durations'),
])
def test_a_trajectory_of_too_many_points_is_refused_before_it_is_sampled(parameters, name):
    assert 200.0 / 1e-4 > MAX_TRAJECTORY_POINTS
    with pytest.raises(ParameterError, match=f'more than {MAX_TRAJECTORY_POINTS}') as info:
        reference_samples({'joint_names': ['a'], **parameters})
    assert info.value.name == name


def test_a_sine_that_overflows_is_refused_without_a_warning(recwarn):
    # T = 1e-300 s: omega^2 = (2 pi / T)^2 overflows, the accelerations would be inf.
    with pytest.raises(ValueError, match='sine trajectory is not finite'):
        reference_samples({'joint_names': ['a'], 'sine.period': [1e-300]})
    assert not recwarn.list
