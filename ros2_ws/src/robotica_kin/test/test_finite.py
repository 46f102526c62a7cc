"""Tests of robotica_kin.finite: the fast test agrees with numpy's elementwise one."""

from hypothesis import given, strategies as st
from hypothesis.extra.numpy import arrays
import numpy as np
import pytest
from robotica_kin.finite import all_finite


@given(arrays(np.float64, st.integers(1, 12),
              elements=st.floats(allow_nan=True, allow_infinity=True, width=64)))
def test_agrees_with_isfinite_on_any_vector(values):
    assert all_finite(values) == bool(np.isfinite(values).all())


@pytest.mark.parametrize('values, expected', [
    ([0.0], True),
    ([1e200, 1e200], True),            # a·a overflows: the exact test decides
    ([np.finfo(float).max, -1.0], True),
    ([1.0, np.nan], False),
    ([np.inf, -np.inf], False),        # a·a = inf, not NaN
    ([-np.inf], False),
])
def test_edge_values(values, expected):
    assert all_finite(np.array(values)) is expected
