"""Tests of robotica_ctrl.trajectory.sinusoid: Ej. 8.1 (8.47) and the PUMA reference (A.2)."""
import math

import numpy as np
import pytest

from robotica_ctrl.trajectory.sinusoid import sinusoid


def test_ejemplo_8_1_reference_and_derivatives():
    t = np.linspace(0.0, 8.0, 81)
    q, qd, qdd = sinusoid(t, 0.15, 4.0, [0.0, math.pi / 2])
    w = 2 * math.pi / 4.0
    np.testing.assert_allclose(q[:, 0], 0.15 * np.sin(w * t), atol=1e-15)
    np.testing.assert_allclose(q[:, 1], 0.15 * np.cos(w * t), atol=1e-15)
    np.testing.assert_allclose(qd[:, 1], -0.15 * w * np.sin(w * t), atol=1e-15)
    np.testing.assert_allclose(qdd[:, 0], -0.15 * w * w * np.sin(w * t), atol=1e-15)


def test_derivatives_match_central_differences():
    t = np.array([0.3, 1.1, 2.9])
    h = 1e-5
    q, qd, qdd = sinusoid(t, [1.0, 0.5, 2.0], [2 * math.pi, 3.0, 1.5], 0.4, [0.0, 1.0, -1.0])
    qp, qdp, _ = sinusoid(t + h, [1.0, 0.5, 2.0], [2 * math.pi, 3.0, 1.5], 0.4, [0.0, 1.0, -1.0])
    qm, qdm, _ = sinusoid(t - h, [1.0, 0.5, 2.0], [2 * math.pi, 3.0, 1.5], 0.4, [0.0, 1.0, -1.0])
    np.testing.assert_allclose(qd, (qp - qm) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(qdd, (qdp - qdm) / (2 * h), atol=1e-7)


def test_puma_reference_is_sin_t_on_six_joints():
    q, _, _ = sinusoid([1.0], [1.0] * 6, 2 * math.pi)
    np.testing.assert_allclose(q, np.full((1, 6), math.sin(1.0)))


@pytest.mark.parametrize(('kwargs', 'match'), [
    ({'period': 0.0}, 'period'),
    ({'period': [1.0, 2.0], 'amplitude': [1.0, 2.0, 3.0]}, 'expected 1 or 3'),
    ({'phase': math.nan}, 'phase'),
])
def test_bad_arguments_are_refused(kwargs, match):
    args = {'amplitude': 1.0, 'period': 1.0, **kwargs}
    with pytest.raises(ValueError, match=match):
        sinusoid([0.0, 1.0], **args)
