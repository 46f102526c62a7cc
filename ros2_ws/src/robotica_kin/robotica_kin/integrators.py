"""
Fixed-step integration of ordinary differential equations.

The book simulates its models (Ejemplo 4.9, §4.7.5; forward dynamics, §5.7) by integrating
x' = f(t, x) numerically. A simulator advancing at a fixed control period needs a fixed-step
method; this module holds the classic fourth-order Runge–Kutta step (SciPy offers only
adaptive steppers).
"""

from collections.abc import Callable
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.types import Vector

__all__ = ['rk4_step']


def rk4_step(
    f: Callable[..., ArrayLike], t: float, x: ArrayLike, h: float, *args: Any
) -> Vector:
    """
    Advance x' = f(t, x, *args) by one classic fourth-order Runge–Kutta step.

    k1 = f(t, x), k2 = f(t + h/2, x + h k1/2), k3 = f(t + h/2, x + h k2/2),
    k4 = f(t + h, x + h k3); x(t + h) ≈ x + h (k1 + 2 k2 + 2 k3 + k4) / 6. The local
    error is O(h**5), the global error O(h**4).

    Parameters
    ----------
    f : callable
        ``f(t, x, *args)`` returning dx/dt with the shape of ``x``.
    t : float
        Time at the start of the step [s].
    x : array_like, shape (n,)
        State at ``t``.
    h : float
        Step [s], finite and > 0.
    *args
        Extra arguments passed unchanged to ``f`` (held constant over the step).

    Returns
    -------
    ndarray, shape (n,)
        State at ``t + h``, float64.

    Raises
    ------
    ValueError
        If ``h`` is not finite and > 0, ``t`` is not finite, ``x`` is not a vector, or ``f``
        returns a different shape.

    Examples
    --------
    >>> rk4_step(lambda t, x: [3.0 * t**2], 0.0, [1.0], 2.0)  # x = 1 + t**3
    array([9.])

    """
    if not (math.isfinite(h) and h > 0.0):
        raise ValueError(f'step h must be finite and > 0 s, got {h!r}')
    if not math.isfinite(t):
        raise ValueError(f'time t must be finite, got {t!r}')
    x0 = np.asarray(x, dtype=np.float64)
    if x0.ndim != 1:
        raise ValueError(f'state x must have shape (n,), got {x0.shape}')

    def slope(ti: float, xi: Vector) -> Vector:
        k = np.asarray(f(ti, xi, *args), dtype=np.float64)
        if k.shape != x0.shape:
            raise ValueError(f'f returned shape {k.shape}, expected {x0.shape}')
        return k

    k1 = slope(t, x0)
    k2 = slope(t + 0.5 * h, x0 + 0.5 * h * k1)
    k3 = slope(t + 0.5 * h, x0 + 0.5 * h * k2)
    k4 = slope(t + h, x0 + h * k3)
    return x0 + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
