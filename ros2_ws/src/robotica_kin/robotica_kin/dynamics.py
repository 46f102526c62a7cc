"""
Manipulator dynamics on Pinocchio with HEMERO's names (book ch. 5, §A.3; catalog Part 3, §12.4).

The model is (A.1), ``tau = M(q) q'' + G(q) + V(q, q') + F(q')``:

- ``M`` inertia matrix (Pinocchio's CRBA), including the reflected motor inertia ``J_m G²``;
- ``G`` gravity torques for the gravity acceleration ``grav`` in the base frame {0}
  (default ``[0, 0, -9.81]`` m/s²: the base's z axis points up; the book's planar examples use
  ``[0, -9.81, 0]``);
- ``V`` centrifugal and Coriolis torques (5.82);
- ``F`` joint friction from the ``dyn`` table, referred to the motor shaft as in HEMERO:
  ``F = G² B q' + |G| Tc`` with ``Tc = Tc+`` for q' > 0, ``Tc-`` for q' < 0 and 0 at rest
  (the book leaves sgn(0) undefined, (5.4)).

``rne`` is Pinocchio's recursive Newton-Euler (Craig's algorithm, §5.5.2) plus ``F``; ``fdyn``
integrates (5.88) with Pinocchio's ABA and an adaptive Runge-Kutta 4(5) (SciPy's ``RK45``, the
method of MATLAB's ``ode45``).

Every entry point refuses, with ValueError, joint positions, velocities and accelerations that
are not finite or beyond the physical bounds of :mod:`robotica_kin.bounds`
(``MAX_JOINT_POSITION``, ``MAX_JOINT_VELOCITY``, ``MAX_JOINT_ACCELERATION``), and a result that
is not finite (a robot of absurd mass or inertia): q' = 1e200 once gave NaN torques silently.

``dyn`` is a :class:`~robotica_kin.dh.DHModel` that carries a ``dyn`` table (e.g.
``robots.puma560()``), a raw HEMERO table of 20 columns (book §A.3), or the
:class:`~robotica_kin.pinocchio_model.PinocchioArm` of such a robot. A robot object gets its
arm from :func:`~robotica_kin.pinocchio_model.dyn_arm`, built on first use and kept while the
robot lives (a raw table: built for the call). Each arm keeps, per thread, a scratch ``Data`` of
its own; a caller may pass its own ``data`` (``arm.model.createData()``), checked on its first
use. A gravity other than the model's is applied to a copy of the model: the arm's own is
shared, never changed.

One configuration of (n,) vectors with the default gravity takes the fast route when the arm's
:attr:`~robotica_kin.pinocchio_model.PinocchioArm.torque_bound` is far below overflow (no joint
values within the bounds can then make a result overflow, so results go unchecked): each vector
is cleared by the Euclidean norm of its values, ``math.hypot(*x.tolist()) <= bound`` (NaN and
inf fail it; every ``|x_i|`` is then within the bound; 0.13 µs for six values), and Pinocchio
itself refuses a size or dtype not its own. Anything else (a batch, a list, another gravity, a
value the norm cannot clear, a robot of absurd mass) takes the full route, whose checks decide
and raise. PUMA 560, the arm and a ``data`` kept: 1.5-1.95× the bare Pinocchio call (``friction``
2.3× its bare NumPy law); the floor of any checked Python wrapper, one call and the norm of each
vector, is 1.3-1.8× (``robotica bench kin``, docs/benchmarks.md).
"""

from dataclasses import dataclass
import math
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.bounds import (bounded_array, MAX_JOINT_ACCELERATION, MAX_JOINT_POSITION,
                                 MAX_JOINT_VELOCITY)
from robotica_kin.dh import as_dyn_model, DHModel
from robotica_kin.finite import all_finite
from robotica_kin.joint_friction import JointFriction
from robotica_kin.pinocchio_model import dyn_arm, PinocchioArm
from scipy.integrate import solve_ivp

__all__ = ['DEFAULT_GRAVITY', 'FdynResult', 'coriolis', 'coriolis_matrix', 'fdyn', 'friction',
           'gravity', 'inertia', 'rne', 'set_gravity']

DEFAULT_GRAVITY = (0.0, 0.0, -9.81)
"""Gravity acceleration in the base frame {0} [m/s²] when ``grav`` is not given."""

_BOUNDS = {'q': MAX_JOINT_POSITION, 'q0': MAX_JOINT_POSITION, 'qd': MAX_JOINT_VELOCITY,
           'qd0': MAX_JOINT_VELOCITY, 'qdd': MAX_JOINT_ACCELERATION}
_FLOAT64 = np.dtype(np.float64)
_SAFE_TORQUE = 1e150   # [N m] a torque_bound this far below overflow (1.8e308): results finite
_REFUSED = (TypeError, ValueError)   # what Pinocchio raises for a wrong size or dtype


def _fast_scratch(arm: PinocchioArm, data: Any, q: object, qd: object = None,
                  qdd: object = None) -> Any:
    """
    Return the scratch Data of the fast route for these joint values, or None to take the full.

    The fast route takes an arm whose :attr:`~PinocchioArm.torque_bound` is far below overflow
    (its results need no check) and q, qd, qdd (those not None) that are 1-d ndarrays within
    their bounds: ``math.hypot(*x.tolist())``, the norm of x's values (0.13 µs for six, half of
    ``x.dot(x)``), is NaN or inf when an element is, never overflows, and bounds every
    ``|x_i|``: within ``MAX_JOINT_POSITION`` for q, ``MAX_JOINT_VELOCITY`` for qd,
    ``MAX_JOINT_ACCELERATION`` for qdd. The size and the dtype are left to the Pinocchio call
    that follows: it refuses others (:data:`_REFUSED`). None, or a refusal, sends the caller to
    the full route (:func:`_vectors`), whose checks decide and raise (a list, a batch, a value
    beyond its bound, a wrong size, a robot of absurd mass). ValueError for a robot without
    dynamics or a ``data`` not of the arm's model.
    """
    try:
        plain = (arm.torque_bound < _SAFE_TORQUE
                 and (q is None or math.hypot(*q.tolist()) <= MAX_JOINT_POSITION)  # type: ignore
                 and (qd is None
                      or math.hypot(*qd.tolist()) <= MAX_JOINT_VELOCITY)  # type: ignore
                 and (qdd is None
                      or math.hypot(*qdd.tolist()) <= MAX_JOINT_ACCELERATION))  # type: ignore
    except (AttributeError, TypeError):   # not an ndarray; a 0-d or 2-d one
        return None
    return arm.scratch(data) if plain else None


def _finite(result: NDArray[np.float64], name: str) -> NDArray[np.float64]:
    """Return ``result`` if every element is finite, else ValueError (one dot product)."""
    if not all_finite(result.ravel()):
        raise ValueError(f'{name} is not finite for these joint values (a robot of absurd mass, '
                         f'inertia or friction?): {result}')
    return result


def _gravity_vector(grav: ArrayLike | None) -> NDArray[np.float64]:
    """Return ``grav`` (None: :data:`DEFAULT_GRAVITY`) as a finite 3-vector, or raise."""
    g = np.asarray(DEFAULT_GRAVITY if grav is None else grav, dtype=np.float64)
    if g.shape != (3,) or not np.isfinite(g).all():
        raise ValueError(f'grav must be a finite 3-vector [m/s^2] in frame {{0}}, got {grav!r}')
    return g


def set_gravity(model: Any, grav: ArrayLike | None) -> None:
    """
    Set the gravity of a Pinocchio ``model`` to ``grav`` [m/s²] in frame {0}.

    ``None`` means :data:`DEFAULT_GRAVITY`; anything but three finite values raises ValueError.
    Use it on a model of the caller's own (``build_model(robot)``, or a copy
    ``pinocchio.Model(arm.model)``): a :class:`~robotica_kin.pinocchio_model.PinocchioArm`'s
    model is shared.
    """
    model.gravity = pin.Motion(_gravity_vector(grav), np.zeros(3))


def _model_and_data(arm: PinocchioArm, grav: ArrayLike | None, data: Any) -> tuple[Any, Any]:
    """Return the arm's model, or a copy of it when ``grav`` differs, and the scratch ``data``."""
    g = _gravity_vector(grav)
    model = arm.model
    if not np.array_equal(model.gravity.linear, g):
        model = pin.Model(model)
        set_gravity(model, g)
    return model, arm.scratch(data)


def _vectors(robot: DHModel, **arrays: ArrayLike) -> tuple[NDArray[np.float64], ...]:
    """
    Return the arrays as (m, n) float64, all with the same m, or raise ValueError.

    Each is named by its keyword (``q``, ``qd``, ``qdd``, ``q0``, ``qd0``) and must lie within
    that quantity's physical bound.
    """
    out = [bounded_array(name, robot.check_q(value, name), _BOUNDS[name])
           for name, value in arrays.items()]
    shapes = {a.shape for a in out}
    if len(shapes) != 1:
        raise ValueError(f'{", ".join(arrays)} must have the same shape, got '
                         f'{[a.shape for a in out]}')
    return tuple(np.atleast_2d(a) for a in out)


def _rows(algorithm: Callable[..., NDArray[np.float64]], model: Any, scratch: Any,
          *batches: NDArray[np.float64]) -> NDArray[np.float64]:
    """
    Return ``algorithm(model, scratch, *row)`` for each row of the (m, n) batches, stacked.

    The full route's loop, out of the public functions: a comprehension in one of them would
    make its variables closure cells, and its fast route pay for them on every call (0.08 µs).
    """
    return np.array([algorithm(model, scratch, *row) for row in zip(*batches)])


def _single(result: NDArray[np.float64], like: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return ``result`` (one row for a ``like`` of shape (n,)) if finite, else ValueError."""
    _finite(result, name)
    return result[0] if np.ndim(like) == 1 else result


def friction(dyn: DHModel | PinocchioArm | ArrayLike, qd: ArrayLike) -> NDArray[np.float64]:
    """
    Return the joint friction torques F(q') [N m or N] of the ``dyn`` table (book (5.84)-(5.86)).

    ``F = G² B q' + |G| Tc`` per joint, with B the viscous and Tc± the Coulomb friction of
    columns 18-20, referred to the motor shaft, and G the gear ratio (HEMERO §A.3); Tc is
    Tc+ for q' > 0, Tc- for q' < 0 and 0 for q' = 0. Shape of ``qd``: (n,) or (m, n).

    Examples
    --------
    >>> row = [0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2.0, 0.5, 0.1, -0.1]
    >>> friction([row], [3.0]), friction([row], [-3.0])
    (array([6.2]), array([-6.2]))

    """
    if type(dyn) is not PinocchioArm and not isinstance(dyn, (DHModel, PinocchioArm)):
        # A raw table: no arm to keep.
        robot = as_dyn_model(dyn)
        (v,) = _vectors(robot, qd=qd)
        return _single(JointFriction(robot)(v), qd, 'friction')
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    law = arm.friction   # ValueError for a robot without dynamics
    # The fast route of the others, with the size and dtype checked here: no Pinocchio call.
    if (arm.torque_bound < _SAFE_TORQUE and type(qd) is np.ndarray
            and qd.shape == law.viscous.shape and qd.dtype is _FLOAT64
            and math.hypot(*qd.tolist()) <= MAX_JOINT_VELOCITY):
        return law(qd)
    (v,) = _vectors(arm.robot, qd=qd)
    return _single(law(v), qd, 'friction')


def rne(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
        grav: ArrayLike | None = None, *, data: Any = None) -> NDArray[np.float64]:
    """
    Return the joint torques ``tau = M q'' + G + V + F`` (recursive Newton-Euler, §5.5.2).

    Parameters
    ----------
    dyn : DHModel, PinocchioArm or array_like, shape (n, 20)
        The robot with its dynamic parameters.
    q, qd, qdd : array_like, shape (n,) or (m, n)
        Joint positions [rad | m], velocities and accelerations (one row per sample).
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²]; default ``[0, 0, -9.81]``.
    data : pinocchio.Data, optional
        Scratch of the arm's model (``arm.model.createData()``), the caller's; a new one per
        call when omitted. The other functions of this module take it too.

    Returns
    -------
    ndarray, shape (n,) or (m, n)
        Joint torques [N m] (forces [N] for prismatic joints).

    Raises
    ------
    ValueError
        For a robot without dynamics, sizes that do not match, NaN, joint values beyond the
        bounds of :mod:`robotica_kin.bounds`, a non-finite result, or a ``data`` not of the
        arm's model.

    Examples
    --------
    Ej. 5.1 at rest, stretched horizontally: tau = g (l1 (m1 + m2) + l2 m2, l2 m2).

    >>> from robotica_kin.robots import two_link_arm
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> rne(dyn, [0, 0], [0, 0], [0, 0], grav=[0, -9.81, 0]).round(6)
    array([98.1 ,  9.81])

    """
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    law = arm.friction   # ValueError for a robot without dynamics
    scratch = None if grav is not None else _fast_scratch(arm, data, q, qd, qdd)
    if scratch is not None:
        try:
            tau = pin.rnea(arm.model, scratch, q, qd, qdd)
        except _REFUSED:   # the full route below says what
            pass
        else:
            return tau if law.is_zero else tau + law(qd)  # type: ignore[arg-type]
    qq, vv, aa = _vectors(arm.robot, q=q, qd=qd, qdd=qdd)
    model, scratch = _model_and_data(arm, grav, data)
    return _single(_rows(pin.rnea, model, scratch, qq, vv, aa) + law(vv), q, 'rne')


def inertia(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, *,
            data: Any = None) -> NDArray[np.float64]:
    """
    Return the joint-space inertia matrix M(q) [kg m²] (book (5.7); Pinocchio's CRBA).

    Symmetric positive definite; includes the reflected motor inertias ``J_m G²``. Shape
    (n, n) for q of shape (n,), (m, n, n) for (m, n).

    Examples
    --------
    >>> from robotica_kin.robots import two_link_arm
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> inertia(dyn, [0.0, 0.0])     # (5.77): [[l2² m2 + 2 l1 l2 m2 + l1² (m1 + m2), ...]]
    array([[34.,  4.],
           [ 4.,  1.]])

    """
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    # Pinocchio's Python crba returns the whole symmetric matrix (since 3.0; pinned 4.1).
    scratch = _fast_scratch(arm, data, q)
    if scratch is not None:
        try:
            return pin.crba(arm.model, scratch, q)
        except _REFUSED:   # the full route below says what
            pass
    (qq,) = _vectors(arm.robot, q=q)
    model, scratch = _model_and_data(arm, None, data)
    out = np.empty((qq.shape[0], arm.robot.n, arm.robot.n))
    for k in range(qq.shape[0]):
        out[k] = pin.crba(model, scratch, qq[k])
    return _single(out, q, 'inertia')


def gravity(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike,
            grav: ArrayLike | None = None, *, data: Any = None) -> NDArray[np.float64]:
    """
    Return the gravity torques G(q) [N m] (book (5.7); HEMERO ``gravity``/``gravedad``).

    ``grav`` is the gravity acceleration in {0} [m/s²], default ``[0, 0, -9.81]``.

    Examples
    --------
    >>> from robotica_kin.robots import two_link_arm
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> gravity(dyn, [0.0, 0.0], grav=[0, -9.81, 0]).round(6)
    array([98.1 ,  9.81])

    """
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    scratch = None if grav is not None else _fast_scratch(arm, data, q)
    if scratch is not None:
        try:
            return pin.computeGeneralizedGravity(arm.model, scratch, q)
        except _REFUSED:   # the full route below says what
            pass
    (qq,) = _vectors(as_dyn_model(arm.robot), q=q)   # ValueError for an arm without dynamics
    model, scratch = _model_and_data(arm, grav, data)
    return _single(_rows(pin.computeGeneralizedGravity, model, scratch, qq), q, 'gravity')


def coriolis(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, qd: ArrayLike, *,
             data: Any = None) -> NDArray[np.float64]:
    """
    Return the centrifugal and Coriolis torques V(q, q') [N m] (book (5.7), (5.82)).

    Examples
    --------
    Ej. 5.1, (5.77): V = (-m2 l1 l2 s2 θ2'² - 2 m2 l1 l2 s2 θ1' θ2', m2 l1 l2 s2 θ1'²).

    >>> from robotica_kin.robots import two_link_arm
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> coriolis(dyn, [0.0, np.pi / 2], [1.0, 0.0]).round(9)
    array([-0.,  3.])

    """
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    model = arm.model_without_gravity
    scratch = _fast_scratch(arm, data, q, qd)
    if scratch is not None:
        try:
            return pin.nonLinearEffects(model, scratch, q, qd)
        except _REFUSED:   # the full route below says what
            pass
    qq, vv = _vectors(arm.robot, q=q, qd=qd)
    return _single(_rows(pin.nonLinearEffects, model, arm.scratch(data), qq, vv), q, 'coriolis')


def coriolis_matrix(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, qd: ArrayLike, *,
                    data: Any = None) -> NDArray[np.float64]:
    """
    Return V_m(q, q') with ``V = V_m q'`` and ``M' - 2 V_m`` skew-symmetric (book (5.82)-(5.83)).

    Pinocchio's ``computeCoriolisMatrix``; q and qd of shape (n,).
    """
    arm = dyn if type(dyn) is PinocchioArm else dyn_arm(dyn)
    scratch = _fast_scratch(arm, data, q, qd)
    if scratch is not None:
        try:
            return pin.computeCoriolisMatrix(arm.model, scratch, q, qd)
        except _REFUSED:   # the full route below says what
            pass
    qq, vv = _vectors(arm.robot, q=q, qd=qd)
    if qq.shape[0] != 1 or np.ndim(q) != 1:
        raise ValueError('coriolis_matrix takes one configuration, q of shape (n,)')
    model, scratch = _model_and_data(arm, None, data)
    return _single(_rows(pin.computeCoriolisMatrix, model, scratch, qq, vv), q,
                   'coriolis_matrix')


@dataclass(frozen=True)
class FdynResult:
    """Trajectory of :func:`fdyn`: times (k,) [s], q and qd of shape (k, n)."""

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]


def fdyn(dyn: DHModel | PinocchioArm | ArrayLike, t0: float, tf: float,
         torquefun: Callable[[float, NDArray[np.float64], NDArray[np.float64]], ArrayLike] | None,
         q0: ArrayLike, qd0: ArrayLike, grav: ArrayLike | None = None, *,
         max_step: float = np.inf, rtol: float = 1e-8, atol: float = 1e-10,
         t_eval: ArrayLike | None = None) -> FdynResult:
    """
    Integrate the forward dynamics (5.88) from t0 to tf (HEMERO ``fdyn``, book §5.7).

    ``q'' = M^-1 (tau - V - G - F)`` by Pinocchio's articulated-body algorithm, with the
    adaptive Runge-Kutta 4(5) of SciPy (``RK45``, MATLAB's ``ode45``).

    Parameters
    ----------
    dyn : DHModel, PinocchioArm or array_like, shape (n, 20)
        The robot with its dynamic parameters.
    t0, tf : float
        Start and end time [s], tf > t0.
    torquefun : callable or None
        ``torquefun(t, q, qd)`` → joint torques (n,) [N m]; None for zero torque.
    q0, qd0 : array_like, shape (n,)
        Initial joint positions and velocities.
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²]; default ``[0, 0, -9.81]``.
    max_step, rtol, atol : float
        Integrator settings (largest step [s], relative and absolute tolerances).
    t_eval : array_like, optional
        Times at which to report the solution; default the integrator's own steps.

    Returns
    -------
    FdynResult

    Raises
    ------
    ValueError
        For bad sizes, NaN, q0 or qd0 beyond the bounds of :mod:`robotica_kin.bounds`,
        tf <= t0, a torque function that returns a wrong size or NaN, or accelerations that are
        not finite.

    """
    arm = dyn_arm(dyn)
    robot = arm.robot
    start, speed = _vectors(robot, q0=q0, qd0=qd0)
    if start.shape[0] != 1 or np.ndim(q0) != 1:
        raise ValueError(f'q0 and qd0 must have shape ({robot.n},)')
    if not (np.isfinite(t0) and np.isfinite(tf) and tf > t0):
        raise ValueError(f'need finite t0 < tf, got t0={t0!r}, tf={tf!r}')
    model, data = _model_and_data(arm, grav, None)
    n = robot.n
    law = arm.friction   # built once per arm, not in each of the integrator's evaluations
    no_torque = np.zeros(n)

    def derivative(t: float, x: NDArray[np.float64]) -> NDArray[np.float64]:
        q, qd = x[:n], x[n:]
        if torquefun is None:
            tau = no_torque
        else:
            tau = np.asarray(torquefun(t, q, qd), dtype=np.float64)
            if tau.shape != (n,) or not all_finite(tau):
                raise ValueError(f'torquefun must return {n} finite torques at t = {t}, '
                                 f'got {tau!r}')
        if not math.hypot(*qd.tolist()) <= MAX_JOINT_VELOCITY:   # else each velocity decides
            bounded_array('qd', qd, MAX_JOINT_VELOCITY)
        qdd = pin.aba(model, data, q, qd, tau if law.is_zero else tau - law(qd))
        if not math.isfinite(math.hypot(*qdd.tolist())) and not all_finite(qdd):
            raise ValueError(f'fdyn: the joint accelerations are not finite at t = {t} s '
                             f'(q = {q}, qd = {qd})')
        return np.concatenate((qd, qdd))

    solution = solve_ivp(derivative, (float(t0), float(tf)), np.concatenate((start[0], speed[0])),
                         method='RK45', max_step=max_step, rtol=rtol, atol=atol, t_eval=t_eval)
    if not solution.success:
        raise ValueError(f'fdyn: integration failed: {solution.message}')
    states = solution.y.T
    return FdynResult(t=solution.t, q=states[:, :n].copy(), qd=states[:, n:].copy())
