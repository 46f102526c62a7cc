"""
Linear-in-the-parameters regressors of the arm dynamics, book §8.4.2-§8.4.3 (catalogue §6.4).

The adaptive laws need the dynamics written as a known matrix times unknown parameters φ:

- adaptive computed torque (8.79): ``W(q, q', q'') φ = M(q) q'' + V(q, q') + G(q) [+ F]``;
- Slotine and Li (8.119): ``Y(q, q', v, a) φ = M(q) a + C(q, q') v + G(q) [+ F]`` with
  ``v = q_d' + Λ e`` and ``a = q_d'' + Λ e'``, C the Christoffel matrix (``M' - 2 C``
  skew-symmetric; the book's V_m of (8.133)).

Two sources, one interface (:class:`ParameterRegressor`):

- the 2R of Ej. 5.1 (point masses m1, m2 at the link ends, φ = [m1, m2]) in closed form:
  :func:`two_link_computed_torque_regressor` is W of (8.100) with the primes restored and
  :func:`two_link_slotine_li_regressor` Y of (8.134) corrected as the catalogue says (``q_d'`` in
  the velocity terms, ``+`` in the (2, 1) entry of (8.133)); :class:`TwoLinkRegressor` wraps them;
- any robot with a ``dyn`` table through Pinocchio's joint torque regressor R(q, q', q''), whose
  columns are the 10 inertial parameters of each body: :class:`LinkMassRegressor` adapts the link
  masses. Assumption: a link keeps its shape when its mass changes (its centre of mass stays and
  its inertia tensor scales with the mass), so body i's parameters are ``π_i = m_i π̄_i`` with
  ``π̄_i = π_i / m_i`` from the model's own table, and ``W = R Π̄``.

Everything the model knows and φ does not hold is the *known torque*, returned beside the
regressor and added by the laws: the reflected motor inertia ``J_m G²`` times the acceleration,
the friction F(q') of the table, and the links of zero mass in the table, which cannot be adapted
(their parameters do not scale with a mass; e.g. the PUMA 560's link 1, 0 kg with
I_zz = 0.35 kg m²): they are left out of φ and their whole dynamics is known.
So ``W φ + known = rne(q, q', q'')`` exactly for the true φ.

Y without the Christoffel matrix (the hint of the design): ``h(w) = C(q, w) w`` is the quadratic
velocity term, ``R(q, w, 0) φ - G``, and C(q, x) y is a symmetric bilinear form in (x, y), so
``C(q, q') v = ¼[h(q' + v) - h(q' - v)] = h((q' + v)/2) - h((q' - v)/2)``. One regressor call
with gravity at ``((q' + v)/2, a)`` gives ``M a + h((q' + v)/2) + G``; one on the same model
without gravity at ``((q' - v)/2, 0)`` gives ``h((q' - v)/2)``: Y is their difference, two calls.
"""

import math
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.dynamics import set_gravity
from robotica_kin.finite import finite_real
from robotica_kin.joint_friction import JointFriction
from robotica_kin.pinocchio_model import build_model

from .law import _checked_rows

__all__ = ['LinkMassRegressor', 'ParameterRegressor', 'TwoLinkRegressor',
           'two_link_computed_torque_regressor', 'two_link_slotine_li_regressor']

_PARAMETERS_PER_BODY = 10   # Pinocchio's order: m, m c (3), I about the joint frame (6)


class ParameterRegressor(Protocol):
    """
    The dynamics of an arm as a regressor times parameters φ (p,), what the adaptive laws use.

    Attributes ``n`` (joints) and ``parameter_names`` (p names, e.g. ``'link_2.mass'``).
    """

    n: int
    parameter_names: tuple[str, ...]

    def computed_torque_terms(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
                              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return ``(W, known)``: ``W φ + known = M q'' + V + G + F`` (8.79); W (n, p)."""

    def slotine_li_terms(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return ``(Y, known)``: ``Y φ + known = M a + C(q, q') v + G + F`` (8.119)."""

    def inertia(self, q: ArrayLike, phi: ArrayLike) -> NDArray[np.float64]:
        """Return M(q) (n, n) [kg m²] with the parameters ``phi``, motor inertia included."""


def _two_link_constants(l1: float, l2: float, g: float) -> tuple[float, float, float]:
    """Return l1, l2 [m] (finite, > 0) and g [m/s²] (finite) as floats, or raise ValueError."""
    lengths = finite_real('l1', l1), finite_real('l2', l2)
    for name, length in zip(('l1', 'l2'), lengths):
        if length <= 0.0:
            raise ValueError(f'{name} must be a length > 0 m, got {length!r}')
    return lengths[0], lengths[1], finite_real('g', g)


def _two_link_rows(names: tuple[str, ...], values: tuple[ArrayLike, ...]) -> NDArray[np.float64]:
    """Return the rows of ``values``, each of shape (2,) and finite, or raise ValueError."""
    rows = _checked_rows(names, values)
    if rows.shape[1] != 2:
        raise ValueError(f'{", ".join(names)} must have shape (2,) for the 2R, got '
                         f'{rows.shape[1:]}')
    return rows


def two_link_computed_torque_regressor(q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, l1: float,
                                       l2: float, g: float) -> NDArray[np.float64]:
    """
    Return W (2, 2) of the 2R of Ej. 5.1 with φ = [m1, m2] [kg], book (8.100), primes restored.

    ``W φ = M q'' + V + G`` of (5.76)-(5.77): point masses at the link ends l1, l2 [m], gravity
    g [m/s²] along -y of {0}; q [rad], q' [rad/s], q'' [rad/s²].

    Examples
    --------
    At rest with the arm along x, only gravity: W = [[l1 g, (l1 + l2) g], [0, l2 g]].

    >>> two_link_computed_torque_regressor([0, 0], [0, 0], [0, 0], 1.0, 1.0, 9.8)
    array([[ 9.8, 19.6],
           [ 0. ,  9.8]])

    """
    l1, l2, g = _two_link_constants(l1, l2, g)
    (q1, q2), (qd1, qd2), (qdd1, qdd2) = _two_link_rows(('q', 'qd', 'qdd'), (q, qd, qdd))
    c1, c2, s2, c12 = math.cos(q1), math.cos(q2), math.sin(q2), math.cos(q1 + q2)
    w11 = l1 ** 2 * qdd1 + l1 * g * c1
    w12 = (l2 ** 2 * (qdd1 + qdd2) + l1 * l2 * c2 * (2.0 * qdd1 + qdd2) + l1 ** 2 * qdd1
           - l1 * l2 * s2 * qd2 ** 2 - 2.0 * l1 * l2 * s2 * qd1 * qd2 + l2 * g * c12 + l1 * g * c1)
    w22 = l2 ** 2 * (qdd1 + qdd2) + l1 * l2 * c2 * qdd1 + l1 * l2 * s2 * qd1 ** 2 + l2 * g * c12
    return np.array([[w11, w12], [0.0, w22]])


def two_link_slotine_li_regressor(q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike,
                                  l1: float, l2: float, g: float) -> NDArray[np.float64]:
    """
    Return Y (2, 2) of the 2R of Ej. 5.1 with φ = [m1, m2] [kg], book (8.134) corrected.

    ``Y φ = M a + V_m(q, q') v + G`` with V_m of (8.133) (the Christoffel matrix, ``+`` in its
    (2, 1) entry) and, in the law, ``v = q_d' + Λ e`` [rad/s], ``a = q_d'' + Λ e'`` [rad/s²].
    With ``v = q'`` and ``a = q''`` it is W of (8.100).

    Examples
    --------
    >>> two_link_slotine_li_regressor([0, 0], [0, 0], [0, 0], [1, 0], 1.0, 1.0, 0.0)
    array([[1., 4.],
           [0., 2.]])

    """
    l1, l2, g = _two_link_constants(l1, l2, g)
    rows = _two_link_rows(('q', 'qd', 'v', 'a'), (q, qd, v, a))
    (q1, q2), (qd1, qd2), (v1, v2), (a1, a2) = rows
    c1, c2, s2, c12 = math.cos(q1), math.cos(q2), math.sin(q2), math.cos(q1 + q2)
    y11 = l1 ** 2 * a1 + l1 * g * c1
    y12 = ((l2 ** 2 + 2.0 * l1 * l2 * c2 + l1 ** 2) * a1 + (l2 ** 2 + l1 * l2 * c2) * a2
           - l1 * l2 * s2 * qd2 * v1 - l1 * l2 * s2 * (qd1 + qd2) * v2 + l2 * g * c12
           + l1 * g * c1)
    y22 = (l1 * l2 * c2 + l2 ** 2) * a1 + l2 ** 2 * a2 + l1 * l2 * s2 * qd1 * v1 + l2 * g * c12
    return np.array([[y11, y12], [0.0, y22]])


class TwoLinkRegressor:
    """
    The closed forms (8.100) and (8.134) of the 2R of Ej. 5.1 as a :class:`ParameterRegressor`.

    φ = [m1, m2] [kg]; lengths l1, l2 [m] and gravity g [m/s²] (along -y) known. The closed form
    has no motor inertia and no friction: the known torque is zero.

    Examples
    --------
    >>> TwoLinkRegressor(1.0, 1.0, 9.8).inertia([0.0, 0.0], [0.8, 2.3])   # (5.77)
    array([[10. ,  4.6],
           [ 4.6,  2.3]])

    """

    n = 2
    parameter_names = ('link_1.mass', 'link_2.mass')

    def __init__(self, l1: float, l2: float, g: float) -> None:
        self.l1, self.l2, self.g = _two_link_constants(l1, l2, g)

    def computed_torque_terms(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
                              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return ``(W, zeros(2))``: W of (8.100), :func:`two_link_computed_torque_regressor`."""
        return (two_link_computed_torque_regressor(q, qd, qdd, self.l1, self.l2, self.g),
                np.zeros(2))

    def slotine_li_terms(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return ``(Y, zeros(2))``: Y of (8.134), :func:`two_link_slotine_li_regressor`."""
        return (two_link_slotine_li_regressor(q, qd, v, a, self.l1, self.l2, self.g),
                np.zeros(2))

    def inertia(self, q: ArrayLike, phi: ArrayLike) -> NDArray[np.float64]:
        """Return M(q) of (5.77) [kg m²] with the masses ``phi`` = [m1, m2] [kg] (any sign)."""
        (_, q2), (m1, m2) = _two_link_rows(('q', 'phi'), (q, phi))
        l1, l2, c2 = self.l1, self.l2, math.cos(q2)
        m12 = l2 ** 2 * m2 + l1 * l2 * m2 * c2
        return np.array([[l2 ** 2 * m2 + 2.0 * l1 * l2 * m2 * c2 + l1 ** 2 * (m1 + m2), m12],
                         [m12, l2 ** 2 * m2]])


class LinkMassRegressor:
    """
    The link masses of any arm with a ``dyn`` table as parameters, through Pinocchio's regressor.

    φ holds the masses [kg] of the links whose mass in the table is not zero (the others cannot
    be adapted: their dynamics is known, see the module docstring), in link order. Built once;
    each call uses the object's own Pinocchio models and scratch, without allocating a model:
    one object per thread.

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 20)
        The robot with its ``dyn`` table: the geometry of each link (centre of mass, inertia per
        kg), motor inertia, friction, and the masses :attr:`masses` it gives.
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²]; default ``[0, 0, -9.81]`` (the book's planar
        examples: ``[0, -9.8, 0]``).

    Attributes
    ----------
    n, p : int
        Joints and parameters.
    links : tuple of int
        The adapted links (1 … n), in the order of φ.
    parameter_names : tuple of str
        ``'link_<i>.mass'`` for each adapted link.
    masses : ndarray, shape (p,)
        φ of the table [kg] (the true φ when the table is the robot).

    Raises
    ------
    ValueError
        For a model without dynamics, a bad ``grav``, or a table with no link of non-zero mass.

    Examples
    --------
    >>> from robotica_kin.robots import puma560
    >>> regressor = LinkMassRegressor(puma560())
    >>> regressor.parameter_names[0], regressor.masses.tolist()
    ('link_2.mass', [17.4, 4.8, 0.82, 0.34, 0.09])

    """

    def __init__(self, model: DHModel | ArrayLike, grav: ArrayLike | None = None) -> None:
        robot = as_dyn_model(model)
        assert robot.dyn is not None
        self._model = build_model(robot)
        set_gravity(self._model, grav)
        self._model_without_gravity = pin.Model(self._model)
        self._model_without_gravity.gravity = pin.Motion.Zero()
        self._data = self._model.createData()
        masses = robot.dyn[:, 5]
        adapted = np.flatnonzero(masses != 0.0)
        if adapted.size == 0:
            raise ValueError(f'{robot.name}: every link has zero mass in the dyn table; a link '
                             'mass is adapted relative to the table, so at least one must be > 0')
        self.n, self.p = robot.n, int(adapted.size)
        self.links = tuple(int(i) + 1 for i in adapted)
        self.parameter_names = tuple(f'link_{i}.mass' for i in self.links)
        self.masses = masses[adapted].copy()
        # Column k < p: the parameters of adapted body i per kg (π̄_i); column p: the known
        # parameters of the links of zero mass. The regressor times this (10 n, p + 1) matrix
        # gives W and the known links' torque in one product.
        basis = np.zeros((_PARAMETERS_PER_BODY * self.n, self.p + 1))
        for i in range(self.n):
            rows = slice(_PARAMETERS_PER_BODY * i, _PARAMETERS_PER_BODY * (i + 1))
            parameters = self._model.inertias[i + 1].toDynamicParameters()
            if masses[i] != 0.0:
                basis[rows, int(np.searchsorted(adapted, i))] = parameters / masses[i]
            else:
                basis[rows, self.p] = parameters
        self._basis = basis
        self._armature = np.array(self._model.armature)
        self._friction = JointFriction(robot)
        self._zeros = np.zeros(self.n)
        self._known_model, self._link_models = self._inertia_models(adapted)

    def _inertia_models(self, adapted: NDArray[np.intp]) -> tuple[Any, list[Any]]:
        """Return the model of the known inertia and, per adapted link, one of its inertia/kg."""
        known_model = pin.Model(self._model_without_gravity)
        link_models = []
        for link in (int(i) + 1 for i in adapted):
            model = pin.Model(self._model_without_gravity)
            model.armature = np.zeros(self.n)
            for body in range(1, self.n + 1):
                model.inertias[body] = pin.Inertia.Zero()
            inertia = self._model.inertias[link]
            model.inertias[link] = pin.Inertia(1.0, inertia.lever, inertia.inertia / inertia.mass)
            known_model.inertias[link] = pin.Inertia.Zero()
            link_models.append(model)
        return known_model, link_models

    def _joint_rows(self, names: tuple[str, ...],
                    values: tuple[ArrayLike, ...]) -> NDArray[np.float64]:
        """Return the rows of ``values`` (each (n,), finite), or raise ValueError."""
        rows = _checked_rows(names, values)
        if rows.shape[1] != self.n:
            raise ValueError(f'{", ".join(names)} must have shape ({self.n},), got '
                             f'{rows.shape[1:]}')
        return rows

    def _split(self, regressor: NDArray[np.float64], acceleration: NDArray[np.float64],
               qd: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return ``(W, known)`` from the full regressor (n, 10 n) of the motion."""
        product = regressor @ self._basis
        known = product[:, self.p] + self._armature * acceleration
        if not self._friction.is_zero:
            known += self._friction(qd)
        return product[:, :self.p], known

    def computed_torque_terms(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike
                              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """
        Return ``(W, known)`` with ``W φ + known = M q'' + V + G + F``, book (8.79).

        W (n, p): one Pinocchio regressor call. ``known`` (n,) [N m]: motor inertia
        ``J_m G² q''``, friction F(q') and the links of zero mass.

        Raises ValueError for vectors that are not finite or not of shape (n,).
        """
        x, v, acc = self._joint_rows(('q', 'qd', 'qdd'), (q, qd, qdd))
        regressor = pin.computeJointTorqueRegressor(self._model, self._data, x, v, acc)
        return self._split(regressor, acc, v)

    def computed_torque(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> NDArray[np.float64]:
        """
        Return W (n, p) of (8.79): ``W φ = M q'' + V + G`` minus the known terms.

        q [rad | m], q' [/s], q'' [/s²], each (n,); see :meth:`computed_torque_terms`.

        >>> from robotica_kin.robots import two_link_arm
        >>> regressor = LinkMassRegressor(two_link_arm(0.8, 2.3, 1.0, 1.0)[1], [0, -9.8, 0])
        >>> regressor.computed_torque([0, 0], [0, 0], [0, 0])     # (8.100) at rest
        array([[ 9.8, 19.6],
               [ 0. ,  9.8]])

        """
        return self.computed_torque_terms(q, qd, qdd)[0]

    def slotine_li_terms(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """
        Return ``(Y, known)`` with ``Y φ + known = M a + C(q, q') v + G + F``, book (8.119).

        Two regressor calls (module docstring). ``known`` (n,) [N m]: ``J_m G² a``, F(q') and
        the links of zero mass.

        Raises ValueError for vectors that are not finite or not of shape (n,).
        """
        x, rate, velocity, acc = self._joint_rows(('q', 'qd', 'v', 'a'), (q, qd, v, a))
        with_gravity = pin.computeJointTorqueRegressor(
            self._model, self._data, x, 0.5 * (rate + velocity), acc)
        regressor = with_gravity - pin.computeJointTorqueRegressor(
            self._model_without_gravity, self._data, x, 0.5 * (rate - velocity), self._zeros)
        return self._split(regressor, acc, rate)

    def slotine_li(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike,
                   a: ArrayLike) -> NDArray[np.float64]:
        """
        Return Y (n, p) of (8.119): ``Y φ = M a + C(q, q') v + G`` minus the known terms.

        q [rad | m], q' and v [/s], a [/s²], each (n,); see :meth:`slotine_li_terms`.
        """
        return self.slotine_li_terms(q, qd, v, a)[0]

    def inertia(self, q: ArrayLike, phi: ArrayLike) -> NDArray[np.float64]:
        """
        Return M(q) (n, n) [kg m²] of the arm with the link masses ``phi`` (p,) [kg], any sign.

        M is linear in φ: ``M = M_known + Σ_k φ_k M_k`` with M_k the CRBA of a copy of the model
        that holds only link k's inertia per kg (made once) and M_known that of the links of
        zero mass plus the motor inertia. An estimate that passed through a negative mass
        (Ej. 8.8) still has its inertia matrix, not necessarily positive definite.

        Raises ValueError for a q or phi that is not finite or of the wrong size.
        """
        (x,) = self._joint_rows(('q',), (q,))
        masses = _checked_rows(('phi',), (phi,))[0]
        if masses.shape != (self.p,):
            raise ValueError(f'phi must have shape ({self.p},), got {masses.shape}')
        mass_matrix = pin.crba(self._known_model, self._data, x)
        for mass, model in zip(masses, self._link_models):
            mass_matrix += mass * pin.crba(model, self._data, x)
        return mass_matrix
