"""A fast finiteness test for the short vectors checked on every control or simulation step."""

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ['all_finite']


def all_finite(array: NDArray[np.float64]) -> bool:
    """
    Return True if every element of the float64 vector ``array`` is finite.

    The dot product ``a·a`` is NaN or inf when any element is, and costs a third of
    ``np.isfinite(a).all()`` on a short vector (0.5 µs against 1.8 µs for six joints); only when
    it overflows (elements above about 1e154) does the exact test decide.

    >>> all_finite(np.array([1.0, -2.0])), all_finite(np.array([1.0, np.nan]))
    (True, False)
    >>> all_finite(np.array([1e300, -1e300])), all_finite(np.array([np.inf, -np.inf]))
    (True, False)
    """
    return math.isfinite(array.dot(array)) or bool(np.isfinite(array).all())
