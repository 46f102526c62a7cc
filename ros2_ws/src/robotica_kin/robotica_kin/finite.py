"""Finiteness checks: a fast test for the short vectors of every step, and a checked real."""

import math
import numbers

import numpy as np
from numpy.typing import NDArray

__all__ = ['all_finite', 'finite_real']


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


def finite_real(name: str, value: object) -> float:
    """
    Return ``value`` as a float if it is a finite real number (not a bool), else ValueError.

    ``name`` names the value in the error message. A number of NumPy or a 0-d array of one is
    accepted; a string, a bool or a sequence is not. The one scalar check of every core module.

    >>> finite_real('t', 2)
    2.0
    >>> finite_real('t', True)
    Traceback (most recent call last):
    ...
    ValueError: t must be a real number, got True
    """
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in 'fiu':
        value = value.item()   # a 0-d array, e.g. one element of a computation
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f'{name} must be a real number, got {value!r}')
    if not math.isfinite(value):
        raise ValueError(f'{name} must be finite, got {value!r}')
    return float(value)
