"""
HEMERO's function names in one namespace, so a MATLAB script ports line by line.

``from robotica_kin.hemero import *`` is deliberately not supported (no star imports); write
``from robotica_kin import hemero as h`` and call ``h.fkine(dh, q)``, or import the names you
use. The implementations live in topical modules, where each function documents its book
equation:

=====================  ============================================================
HEMERO (book, [H])     robotica_kin module
=====================  ============================================================
transl rotx roty rotz  :mod:`robotica_kin.transforms` (ch. 3, §A.2)
rotvec trinv ishomog
rpy2tr tr2rpy eul2tr
tr2eul (+ tr2q q2tr
tr2angvec angvec2tr)
linktrans              :mod:`robotica_kin.dh` (4.5)
fkine                  :mod:`robotica_kin.forward_kinematics` (4.6)
ikine                  :mod:`robotica_kin.ik` (§4.4, [H] ikine; ``ikine_solve``, ``IKError``)
jacob0 jacobn          :mod:`robotica_kin.jacobian` ([H] (3.13)-(3.22))
velprop                :mod:`robotica_kin.velocity_propagation` (4.52)-(4.58)
tr2diff diff2tr        :mod:`robotica_kin.differential_motion` ([H] (3.1)-(3.27))
tr2jac
plotbot                :mod:`robotica_kin.plotbot`
rne inertia gravity    :mod:`robotica_kin.dynamics` (ch. 5, §A.3; Pinocchio RNEA, CRBA, ABA)
coriolis friction fdyn
dhp560 (+ dyn)         :func:`robotica_kin.robots.puma560`
=====================  ============================================================

HEMERO's Simulink blocks for mobile robots ([H] (3.28)-(3.35), catalog §12.3) become functions
named after the blocks ("triciclo clásico", "guiado diferencial", "config. síncrona"),
defined below on top of :mod:`robotica_kin.mobile` (``tricycle``, ``differential_drive``,
``unicycle``):

=================================  ==============================
HEMERO block ([H] equation)        function
=================================  ==============================
Modelo directo bicicleta (3.28)    ``modelo_directo_bicicleta``
Modelo directo triciclo (3.29)     ``modelo_directo_triciclo``
Modelo directo diferencial (3.30)  ``modelo_directo_diferencial``
Modelo directo síncrona (3.31)     ``modelo_directo_sincrona``
Modelo inverso bicicleta (3.32)    ``modelo_inverso_bicicleta``
Modelo inverso triciclo (3.33)     ``modelo_inverso_triciclo``
Modelo inverso diferencial (3.34)  ``modelo_inverso_diferencial``
Modelo inverso síncrona (3.35)     ``modelo_inverso_sincrona``
=================================  ==============================

A direct block integrates its model; here it is the model's right-hand side
``f(t, state, u, ...)``, to integrate with :func:`robotica_kin.integrators.rk4_step` or
``scipy.integrate.solve_ivp``. An inverse block differentiates the path (x(t), y(t)); here it
takes the path's derivatives at one instant. Headings are REP-103 unless ``convention='book'``
(HEMERO's φ from the y axis).

Differences from MATLAB: NumPy arrays, rows are configurations (q of shape (m, n)), a
"trajectory of transforms" is an (m, 4, 4) array, ``ikine`` takes its optional arguments by
keyword (the book's examples and its manual disagree on their order, catalog §17), and
``ikine`` raises :class:`IKError` where HEMERO stopped with an error.
"""

from numpy.typing import ArrayLike

from robotica_kin.dh import linktrans
from robotica_kin.differential_motion import diff2tr, tr2diff, tr2jac
from robotica_kin.dynamics import coriolis, fdyn, friction, gravity, inertia, rne
from robotica_kin.forward_kinematics import fkine
from robotica_kin.ik import IKError, ikine, ikine_solve, IKResult
from robotica_kin.jacobian import jacob0, jacobn
from robotica_kin.mobile.differential_drive import (DifferentialDriveParams,
                                                    twist_to_wheel_speeds,
                                                    wheel_speeds_to_twist)
from robotica_kin.mobile.tricycle import tricycle_deriv, tricycle_path_inverse, TricycleParams
from robotica_kin.mobile.unicycle import _vector, path_twist, unicycle_deriv
from robotica_kin.plotbot import plotbot
from robotica_kin.robots import puma560
from robotica_kin.transforms import (angvec2tr, eul2tr, ishomog, q2tr, rotvec, rotx, roty, rotz,
                                     rpy2tr, tr2angvec, tr2eul, tr2q, tr2rpy, transl, trinv)
from robotica_kin.types import Vector
from robotica_kin.velocity_propagation import velprop

__all__ = [
    'IKError', 'IKResult', 'angvec2tr', 'coriolis', 'diff2tr', 'eul2tr', 'fdyn', 'fkine',
    'friction', 'gravity', 'ikine', 'ikine_solve', 'inertia', 'ishomog', 'jacob0', 'jacobn',
    'linktrans', 'plotbot', 'puma560', 'q2tr', 'rne', 'rotvec', 'rotx', 'roty', 'rotz', 'rpy2tr',
    'tr2angvec', 'tr2diff', 'tr2eul', 'tr2jac', 'tr2q', 'tr2rpy', 'transl', 'trinv', 'velprop',
    'modelo_directo_bicicleta', 'modelo_directo_diferencial', 'modelo_directo_sincrona',
    'modelo_directo_triciclo', 'modelo_inverso_bicicleta', 'modelo_inverso_diferencial',
    'modelo_inverso_sincrona', 'modelo_inverso_triciclo',
]


def modelo_directo_triciclo(
    t: float, state: ArrayLike, u: ArrayLike, wheel_radius: float, wheelbase: float,
    convention: str = 'rep103',
) -> Vector:
    """
    Return the state rate of HEMERO's block "Modelo directo triciclo clásico" ([H] (3.29)).

    [x'; y'; φ'; α'] = [[-c sin φ cos α, 0], [c cos φ cos α, 0], [(c sin α)/l, 0], [0, 1]]
    [ω_t; ω_α], book (4.118); REP-103 replaces (-sin φ, cos φ) by (cos θ, sin θ). The same
    model as :func:`robotica_kin.mobile.tricycle.tricycle_deriv`.

    Parameters
    ----------
    t : float
        Time [s] (unused; for the integrator).
    state : array_like, shape (4,)
        (x [m], y [m], heading [rad], α [rad]) of the rear-axle midpoint.
    u : array_like, shape (2,)
        (ω_t [rad/s] front wheel speed, ω_α [rad/s] steering rate).
    wheel_radius : float
        Front wheel radius c [m], > 0.
    wheelbase : float
        Wheelbase l [m], > 0: front wheel to the rear axle.
    convention : str
        ``'rep103'`` (θ from x) or ``'book'`` (φ from y).

    Returns
    -------
    ndarray, shape (4,)
        (x' [m/s], y' [m/s], heading' [rad/s], α' [rad/s]).

    Raises
    ------
    ValueError
        On a non-positive dimension, a wrong shape, a non-finite value or an unknown
        convention.

    Examples
    --------
    >>> modelo_directo_triciclo(0.0, [0.0, 0.0, 0.0, 0.0], [2.0, 0.1], 0.5, 1.0, 'book')
    array([-0. ,  1. ,  0. ,  0.1])

    """
    return tricycle_deriv(t, state, u, TricycleParams(wheelbase, wheel_radius), convention)


def modelo_directo_bicicleta(
    t: float, state: ArrayLike, u: ArrayLike, wheel_radius: float, wheelbase: float,
    convention: str = 'rep103',
) -> Vector:
    """
    Return the state rate of HEMERO's block "Modelo directo bicicleta" ([H] (3.28)).

    HEMERO's bicycle is driven by its front wheel, so its equations are those of the classic
    tricycle (:func:`modelo_directo_triciclo`); for the bicycle model driven by the rear-axle
    speed (book (4.121)) see :func:`robotica_kin.mobile.bicycle.bicycle_deriv`.

    Parameters
    ----------
    t : float
        Time [s] (unused; for the integrator).
    state : array_like, shape (4,)
        (x [m], y [m], heading [rad], α [rad]) of the rear wheel's contact point.
    u : array_like, shape (2,)
        (ω_t [rad/s] front wheel speed, ω_α [rad/s] steering rate).
    wheel_radius : float
        Wheel radius c [m], > 0.
    wheelbase : float
        Distance l [m] between the front and rear wheels, > 0.
    convention : str
        ``'rep103'`` (θ from x) or ``'book'`` (φ from y).

    Returns
    -------
    ndarray, shape (4,)
        (x' [m/s], y' [m/s], heading' [rad/s], α' [rad/s]).

    Raises
    ------
    ValueError
        As :func:`modelo_directo_triciclo`.

    Examples
    --------
    >>> modelo_directo_bicicleta(0.0, [0.0, 0.0, 0.0, 0.0], [2.0, 0.1], 0.5, 1.0)
    array([1. , 0. , 0. , 0.1])

    """
    return modelo_directo_triciclo(t, state, u, wheel_radius, wheelbase, convention)


def modelo_directo_diferencial(
    t: float, state: ArrayLike, u: ArrayLike, wheel_radius: float,
    wheel_separation: float, convention: str = 'rep103',
) -> Vector:
    """
    Return the pose rate of HEMERO's block "Modelo directo guiado diferencial" ([H] (3.30)).

    [x'; y'; φ'] = [[-(c sin φ)/2, -(c sin φ)/2], [(c cos φ)/2, (c cos φ)/2], [-c/b, c/b]]
    [ω_i; ω_d], book (4.113)-(4.114): (v, ω) of
    :func:`robotica_kin.mobile.differential_drive.wheel_speeds_to_twist` moved along the
    heading. (:func:`~robotica_kin.mobile.differential_drive.differential_drive_deriv` also
    integrates the wheel angles.)

    Parameters
    ----------
    t : float
        Time [s] (unused; for the integrator).
    state : array_like, shape (3,)
        (x [m], y [m], heading [rad]) of the axle midpoint.
    u : array_like, shape (2,)
        (ω_i [rad/s] left, ω_d [rad/s] right wheel speed).
    wheel_radius : float
        Wheel radius c [m], > 0.
    wheel_separation : float
        Distance b [m] between the wheels, > 0.
    convention : str
        ``'rep103'`` (θ from x) or ``'book'`` (φ from y).

    Returns
    -------
    ndarray, shape (3,)
        (x' [m/s], y' [m/s], heading' [rad/s]).

    Raises
    ------
    ValueError
        On a non-positive dimension, a wrong shape, a non-finite value or an unknown
        convention.

    Examples
    --------
    >>> modelo_directo_diferencial(0.0, [0.0, 0.0, 0.0], [1.0, 1.2], 0.25, 1.0)  # Ej. 4.9 (b)
    array([0.275, 0.   , 0.05 ])

    """
    omega_left, omega_right = _vector(u, 2, 'u')
    params = DifferentialDriveParams(wheel_radius, wheel_separation)
    twist = wheel_speeds_to_twist(params, omega_left, omega_right)
    return unicycle_deriv(t, state, twist, convention)


def modelo_directo_sincrona(
    t: float, state: ArrayLike, u: ArrayLike, convention: str = 'rep103'
) -> Vector:
    """
    Return the pose rate of HEMERO's block "Modelo directo config. síncrona" ([H] (3.31)).

    [x'; y'; φ'] = [[-sin φ, 0], [cos φ, 0], [0, 1]] [v; ω], book (4.102)-(4.103): the
    unicycle, :func:`robotica_kin.mobile.unicycle.unicycle_deriv`.

    Parameters
    ----------
    t : float
        Time [s] (unused; for the integrator).
    state : array_like, shape (3,)
        (x [m], y [m], heading [rad]).
    u : array_like, shape (2,)
        (v [m/s], ω [rad/s]).
    convention : str
        ``'rep103'`` (θ from x) or ``'book'`` (φ from y).

    Returns
    -------
    ndarray, shape (3,)
        (x' [m/s], y' [m/s], heading' [rad/s]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value or an unknown convention.

    Examples
    --------
    >>> modelo_directo_sincrona(0.0, [0.0, 0.0, 0.0], [1.0, 0.5], 'book')
    array([-0. ,  1. ,  0.5])

    """
    return unicycle_deriv(t, state, u, convention)


def modelo_inverso_triciclo(
    velocity: ArrayLike,
    acceleration: ArrayLike,
    jerk: ArrayLike,
    wheelbase: float,
    convention: str = 'rep103',
) -> tuple[float, float, float, float]:
    """
    Return the outputs of HEMERO's block "Modelo inverso triciclo clásico" ([H] (3.33)).

    From the path (x(t), y(t)) of the rear-axle midpoint: v_t = l (-l cos α sin φ x' +
    l cos α cos φ y' + sin α φ') / ((l cos α)² + sin² α), ω_α = α', φ = atan(-x'/y') (taken
    as atan2, driving forwards) and α = atan(l γ); the corrected (4.123) of Ejemplo 4.8.
    See :func:`robotica_kin.mobile.tricycle.tricycle_path_inverse`.

    Parameters
    ----------
    velocity, acceleration, jerk : array_like, shape (2,)
        (x', y') [m/s], (x'', y'') [m/s²], (x''', y''') [m/s³] of the path at one instant;
        the velocity must not be zero.
    wheelbase : float
        Wheelbase l [m], > 0.
    convention : str
        Heading convention of the returned heading: ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (v_t [m/s] front wheel rim speed (ω_t = v_t / c), ω_α [rad/s], α [rad],
        heading [rad]).

    Raises
    ------
    ValueError
        On l <= 0, a wrong shape, a non-finite value, a zero velocity or an unknown
        convention.

    Examples
    --------
    Ejemplo 4.8 at t = π/4 on the unit circle (l = 1.5 m):

    >>> import math
    >>> s = math.sqrt(0.5)
    >>> v_t, w_alpha, alpha, phi = modelo_inverso_triciclo(
    ...     [-s, s], [-s, -s], [s, -s], 1.5, convention='book')
    >>> round(v_t, 4), round(w_alpha, 12), round(math.degrees(alpha), 2), round(phi, 12)
    (1.8028, 0.0, 56.31, 0.785398163397)

    """
    return tricycle_path_inverse(TricycleParams(wheelbase, wheel_radius=1.0), velocity,
                                 acceleration, jerk, convention)


def modelo_inverso_bicicleta(
    velocity: ArrayLike,
    acceleration: ArrayLike,
    jerk: ArrayLike,
    wheelbase: float,
    convention: str = 'rep103',
) -> tuple[float, float, float, float]:
    """
    Return the outputs of HEMERO's block "Modelo inverso bicicleta" ([H] (3.32)).

    The same equations as :func:`modelo_inverso_triciclo` (HEMERO's bicycle is driven by its
    front wheel); l is the distance between the front and rear wheels.

    Parameters
    ----------
    velocity, acceleration, jerk : array_like, shape (2,)
        Derivatives of the rear wheel's path (x(t), y(t)) at one instant [m/s, m/s², m/s³].
    wheelbase : float
        Wheelbase l [m], > 0.
    convention : str
        Heading convention of the returned heading: ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (v_t [m/s], ω_α [rad/s], α [rad], heading [rad]).

    Raises
    ------
    ValueError
        As :func:`modelo_inverso_triciclo`.

    Examples
    --------
    >>> v_t, w_alpha, alpha, theta = modelo_inverso_bicicleta([1.0, 0.0], [0.0, 0.0],
    ...                                                       [0.0, 0.0], 2.0)
    >>> v_t, w_alpha, alpha, theta  # straight along x
    (1.0, 0.0, 0.0, 0.0)

    """
    return modelo_inverso_triciclo(velocity, acceleration, jerk, wheelbase, convention)


def modelo_inverso_diferencial(
    velocity: ArrayLike,
    acceleration: ArrayLike,
    wheel_radius: float,
    wheel_separation: float,
    convention: str = 'rep103',
) -> tuple[float, float, float]:
    """
    Return the outputs of HEMERO's block "Modelo inverso guiado diferencial" ([H] (3.34)).

    ω_i = (-sin φ x' + cos φ y' - (b/2) φ')/c, ω_d = (-sin φ x' + cos φ y' + (b/2) φ')/c,
    φ = atan(-x'/y') (taken as atan2, driving forwards): the path's (v, ω)
    (:func:`robotica_kin.mobile.unicycle.path_twist`) through (4.111)-(4.112).

    Parameters
    ----------
    velocity, acceleration : array_like, shape (2,)
        (x', y') [m/s] and (x'', y'') [m/s²] of the axle midpoint's path at one instant;
        the velocity must not be zero.
    wheel_radius : float
        Wheel radius c [m], > 0.
    wheel_separation : float
        Distance b [m] between the wheels, > 0.
    convention : str
        Heading convention of the returned heading: ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (ω_i [rad/s] left, ω_d [rad/s] right wheel speed, heading [rad]).

    Raises
    ------
    ValueError
        On a non-positive dimension, a wrong shape, a non-finite value, a zero velocity or
        an unknown convention.

    Examples
    --------
    >>> modelo_inverso_diferencial([0.0, 1.0], [-0.5, 0.0], 0.25, 1.0, 'book')  # R = 2 m
    (3.0, 5.0, 0.0)

    """
    v, omega, heading = path_twist(velocity, acceleration, convention)
    params = DifferentialDriveParams(wheel_radius, wheel_separation)
    omega_left, omega_right = twist_to_wheel_speeds(params, v, omega)
    return omega_left, omega_right, heading


def modelo_inverso_sincrona(
    velocity: ArrayLike, acceleration: ArrayLike, convention: str = 'rep103'
) -> tuple[float, float, float]:
    """
    Return the outputs of HEMERO's block "Modelo inverso config. síncrona" ([H] (3.35)).

    v = -sin φ x' + cos φ y', ω = φ', φ = atan(-x'/y') (taken as atan2, driving forwards):
    :func:`robotica_kin.mobile.unicycle.path_twist`.

    Parameters
    ----------
    velocity, acceleration : array_like, shape (2,)
        (x', y') [m/s] and (x'', y'') [m/s²] of the path at one instant; the velocity must
        not be zero.
    convention : str
        Heading convention of the returned heading: ``'rep103'`` or ``'book'``.

    Returns
    -------
    tuple of float
        (v [m/s], ω [rad/s], heading [rad]).

    Raises
    ------
    ValueError
        On a wrong shape, a non-finite value, a zero velocity or an unknown convention.

    Examples
    --------
    >>> modelo_inverso_sincrona([0.0, 2.0], [-4.0, 0.0], 'book')  # R = 1 m at 2 m/s
    (2.0, 2.0, 0.0)

    """
    return path_twist(velocity, acceleration, convention)
