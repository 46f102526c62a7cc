"""
Angle wrapping and the book's heading convention.

The book (Ollero 2001, §3.1, §4.7, ch. 9) takes the robot's forward axis as its local y axis
and measures the heading φ from the world y axis, counter-clockwise, so its kinematics read
x' = -v sin φ, y' = v cos φ, φ' = ω (4.97)-(4.99). The core uses REP-103 instead: θ from the
world x axis, x' = v cos θ, y' = v sin θ. The two differ by a constant, θ = φ + π/2, and the
world x, y axes are the same; only these named conversions cross between them.
"""

import math
from typing import overload

import numpy as np
from numpy.typing import ArrayLike

from robotica_kin.types import Vector

__all__ = ['heading_from_book', 'heading_to_book', 'wrap_to_pi']


@overload
def wrap_to_pi(angle: float) -> float: ...


@overload
def wrap_to_pi(angle: ArrayLike) -> Vector: ...


def wrap_to_pi(angle: ArrayLike) -> float | Vector:
    """
    Wrap an angle [rad] to the interval (-π, π].

    Parameters
    ----------
    angle : float or array_like
        Angle or angles [rad], any shape. NaN propagates.

    Returns
    -------
    float or ndarray
        A float for a scalar input, else a float64 array of the input's shape, each value
        in (-π, π] and equal to the input modulo 2π.

    Examples
    --------
    >>> wrap_to_pi(3.0 * math.pi)
    3.141592653589793
    >>> wrap_to_pi([-math.pi, 2.0 * math.pi, 4.0])
    array([ 3.14159265,  0.        , -2.28318531])

    """
    a = np.asarray(angle, dtype=np.float64)
    wrapped = math.pi - np.mod(math.pi - a, 2.0 * math.pi)
    # np.mod may round up to exactly 2π for arguments just below a multiple of 2π.
    wrapped = np.where(wrapped <= -math.pi, wrapped + 2.0 * math.pi, wrapped)
    if wrapped.ndim == 0:
        return float(wrapped)
    return wrapped


@overload
def heading_from_book(phi: float) -> float: ...


@overload
def heading_from_book(phi: ArrayLike) -> Vector: ...


def heading_from_book(phi: ArrayLike) -> float | Vector:
    """
    Convert the book's heading φ [rad] (from the world y axis) to REP-103 θ [rad].

    θ = φ + π/2, wrapped to (-π, π]; the book's (4.97)-(4.98) x' = -v sin φ, y' = v cos φ
    then read x' = v cos θ, y' = v sin θ (catalog §2.7, [CONV]).

    Parameters
    ----------
    phi : float or array_like
        Book heading φ [rad], counter-clockwise from the world y axis.

    Returns
    -------
    float or ndarray
        REP-103 heading θ [rad] from the world x axis, in (-π, π]; a float for a scalar.

    Examples
    --------
    >>> heading_from_book(-math.pi / 4.0)  # Ejemplo 4.9's φ0
    0.7853981633974483

    """
    return wrap_to_pi(np.asarray(phi, dtype=np.float64) + 0.5 * math.pi)


@overload
def heading_to_book(theta: float) -> float: ...


@overload
def heading_to_book(theta: ArrayLike) -> Vector: ...


def heading_to_book(theta: ArrayLike) -> float | Vector:
    """
    Convert a REP-103 heading θ [rad] (from the world x axis) to the book's φ [rad].

    φ = θ - π/2, wrapped to (-π, π]; the inverse of :func:`heading_from_book`.

    Parameters
    ----------
    theta : float or array_like
        REP-103 heading θ [rad], counter-clockwise from the world x axis.

    Returns
    -------
    float or ndarray
        Book heading φ [rad] from the world y axis, in (-π, π]; a float for a scalar.

    Examples
    --------
    >>> heading_to_book(0.0)  # facing +x is φ = -π/2 in the book
    -1.5707963267948966

    """
    return wrap_to_pi(np.asarray(theta, dtype=np.float64) - 0.5 * math.pi)
