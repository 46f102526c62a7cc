"""
Outward velocity propagation along a serial manipulator (book §4.5.3; HEMERO ``velprop``).

From the base, each link frame's angular and linear velocity follows from the previous one
and the rate of the joint between them, (4.52)-(4.58), with ``{}^{i+1}_i R = ({}^i_{i+1} R)^T``
and ``{}^i P_{i+1}`` from the link transform (4.5):

- revolute joint i+1: ``ω_{i+1} = R^T ω_i + θ'_{i+1} Z``, ``v_{i+1} = R^T (v_i + ω_i × P)``;
- prismatic joint i+1: ``ω_{i+1} = R^T ω_i``, ``v_{i+1} = R^T (v_i + ω_i × P) + d'_{i+1} Z``

(the printed (4.58) has ``d_{i+1}`` and ``{}^i R``: misprints for ``d'_{i+1}`` and
``{}^{i+1}_i R``). The listing of ``velprop`` printed in the book (catalogue §2.4) is this loop.
A model's ``tool`` is a rigid offset on link n, applied last. The result equals
``jacobn(dh, q) @ qd`` for a fixed base (4.77); Paul's method is the cheaper route to the
Jacobian itself (book Table 4.4).
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.forward_kinematics import link_transforms

__all__ = ['velprop']


def _vector3(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return ``value`` as a finite float64 vector of shape (3,), or raise ValueError."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f'velprop: {name} is not a numeric array ({error})') from None
    if array.shape != (3,):
        raise ValueError(f'velprop: {name} must have shape (3,), got {array.shape}')
    if not np.all(np.isfinite(array)):
        raise ValueError(f'velprop: {name} must be finite, got {array.tolist()}')
    return array


def _transposed_times(R: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return ``R^T x`` for stacks of rotations (..., 3, 3) and vectors (..., 3)."""
    product: NDArray[np.float64] = np.einsum('...ji,...j->...i', R, x)
    return product


def velprop(dh: DHModel | ArrayLike, q: ArrayLike, qd: ArrayLike,
            v0: ArrayLike = (0.0, 0.0, 0.0), w0: ArrayLike = (0.0, 0.0, 0.0)
            ) -> NDArray[np.float64]:
    """
    Return the velocity ``[v; ω]`` of the tool frame in its own axes (book (4.52)-(4.58)).

    HEMERO ``velprop(dh, q, qd, v0, w0)``: outward propagation from the base frame {0},
    whose origin moves at ``v0`` and which turns at ``w0``, through every joint; then the
    model's rigid tool offset ``T_n_tool = [R p]``: ``v_tool = R^T (v_n + ω_n × p)``,
    ``ω_tool = R^T ω_n``. Book examples: (4.65)-(4.70), (4.78), (4.79).

    Parameters
    ----------
    dh : DHModel or array_like, shape (n, 4) or (n, 5)
        The robot (Craig's modified DH, rows ``[alpha a theta d sigma]``).
    q : array_like, shape (n,) or (m, n)
        Joint values [rad or m].
    qd : array_like, same shape as ``q``
        Joint rates [rad/s or m/s].
    v0 : array_like, shape (3,)
        Velocity of the origin of {0} [m/s], in {0} axes; zero for a fixed base.
    w0 : array_like, shape (3,)
        Angular velocity of {0} [rad/s], in {0} axes.

    Returns
    -------
    ndarray, shape (6,) or (m, 6)
        ``[vx vy vz ωx ωy ωz]``: velocity of the tool frame's origin [m/s] and its angular
        velocity [rad/s], in the tool frame's axes (frame {n} without a tool).

    Raises
    ------
    ValueError
        For a bad table, q or qd of the wrong shape or not finite, or v0, w0 not finite
        vectors of shape (3,).

    Examples
    --------
    Ej. 4.5 (4.78), planar 3R with l1 = 4, l2 = 3 at q = 0, turning joint 1 at 1 rad/s:

    >>> velprop([[0, 0, 0, 0], [0, 4, 0, 0], [0, 3, 0, 0]], [0, 0, 0], [1, 0, 0])
    array([0., 7., 0., 0., 0., 1.])

    """
    robot = as_dh_model(dh)
    qq = robot.check_q(q)
    rates = robot.check_q(qd, 'qd')
    if rates.shape != qq.shape:
        raise ValueError(f'velprop: qd must have the shape of q {qq.shape}, got {rates.shape}')
    batch = qq.shape[:-1]
    v = np.broadcast_to(_vector3(v0, 'v0'), batch + (3,))
    w = np.broadcast_to(_vector3(w0, 'w0'), batch + (3,))
    links = link_transforms(robot, qq)
    for i in range(robot.n):
        R = links[..., i, :3, :3]
        p = links[..., i, :3, 3]
        v = _transposed_times(R, v + np.cross(w, p))
        w = _transposed_times(R, w)
        if robot.prismatic[i]:
            v[..., 2] += rates[..., i]
        else:
            w[..., 2] += rates[..., i]
    R_tool = robot.tool[:3, :3]
    p_tool = robot.tool[:3, 3]
    return np.concatenate([(v + np.cross(w, p_tool)) @ R_tool, w @ R_tool], axis=-1)
