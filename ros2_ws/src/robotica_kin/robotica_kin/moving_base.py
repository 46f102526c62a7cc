"""
Manipulator dynamics on a moving base (book §5.5.2 and §A.3; catalog Part 3.5, §12.3, §12.6).

HEMERO's moving-base dynamics blocks take the motion of the base (ω, ω' and v' of the base)
of a manipulator mounted on a vehicle, e.g. the PUMA on a tricycle of the appendix. In Craig's
recursive Newton-Euler this is just the start of the outward recursion: instead of
``ω_0 = ω'_0 = 0`` (5.35) and ``v'_0 = -g`` it starts from the base's angular velocity ω,
angular acceleration α and linear acceleration ``a - g``.

Conventions (all vectors in the manipulator's base frame {0}, SI units):

- ``base_velocity = [v; ω]``: v [m/s] the velocity of the origin of {0}, ω [rad/s] the angular
  velocity of {0}, both relative to an inertial frame.
- ``base_acceleration = [a; α]``: a [m/s²] the **classical** acceleration of the origin of {0}
  (the second time derivative of its position in the inertial frame, then expressed in {0}:
  what an accelerometer at the origin reads, plus gravity; Craig's v'_0), α [rad/s²] the
  angular acceleration of {0} (the same in {0} and in the inertial frame, since ω × ω = 0).
- ``grav`` is the gravity acceleration expressed in {0} at that instant.

With these conventions the torques do not depend on v (only ω, α, a and g enter Craig's
recursion); v is taken for completeness and to build Pinocchio's state. The computation is
Pinocchio's RNEA on the robot's model appended below a free-flyer joint (a model built for
the call, with its scratch; the robot's own is not changed), whose velocity and
acceleration are the base motion (Pinocchio's free-flyer coordinates are the spatial velocity
in the body frame and its time derivative: linear part ``a - ω × v``), at the identity pose,
so that the inertial frame coincides with {0} at that instant. The joint torques are the last
n entries of the result, plus the joint friction of the ``dyn`` table as in
:func:`robotica_kin.dynamics.rne`. The motor inertia ``J_m G²`` is reflected on the joint's
own acceleration only, as in :func:`~robotica_kin.dynamics.rne` (the rotors' gyroscopic terms
are neglected).
"""

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
import pinocchio as pin
from robotica_kin.dh import DHModel
from robotica_kin.dynamics import _single, _vectors, friction, set_gravity
from robotica_kin.pinocchio_model import dyn_arm, PinocchioArm

__all__ = ['base_motion_from_planar', 'rne_moving_base']

_BASE_JOINT = 'moving_base'
"""Name of the free-flyer joint that carries the manipulator in the moving-base model."""


def _free_flyer_model(arm: PinocchioArm) -> Any:
    """Return a new Pinocchio model: the arm's model below a free-flyer joint."""
    root = pin.Model()
    root.name = f'{arm.model.name}_on_moving_base'
    joint = root.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), _BASE_JOINT)
    frame = root.addFrame(pin.Frame(f'{_BASE_JOINT}_frame', joint, 0, pin.SE3.Identity(),
                                    pin.FrameType.OP_FRAME))
    model = pin.appendModel(root, arm.model, frame, pin.SE3.Identity())
    # appendModel does not carry the motor parameters over: copy them to the arm's joints.
    for name in ('armature', 'rotorInertia', 'rotorGearRatio'):
        values = np.array(getattr(model, name))
        values[6:] = np.array(getattr(arm.model, name))
        setattr(model, name, values)
    return model


def _base_array(value: ArrayLike, name: str, rows: int, single: bool) -> NDArray[np.float64]:
    """Return a base motion as (rows, 6) float64, or raise ValueError naming the argument."""
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (6,) and (single or arr.shape != (rows, 6)):
        expected = '(6,)' if single else f'(6,) or ({rows}, 6)'
        raise ValueError(f'{name} must have shape {expected} like q, got shape {arr.shape}')
    if not np.isfinite(arr).all():
        raise ValueError(f'{name} must be finite, got {arr!r}')
    return np.broadcast_to(arr, (rows, 6))


def rne_moving_base(dyn: DHModel | PinocchioArm | ArrayLike, q: ArrayLike, qd: ArrayLike,
                    qdd: ArrayLike, base_velocity: ArrayLike, base_acceleration: ArrayLike,
                    grav: ArrayLike | None = None) -> NDArray[np.float64]:
    """
    Return the joint torques of a manipulator whose base frame {0} moves (HEMERO §A.3).

    Craig's recursive Newton-Euler (§5.5.2) started from the base motion instead of a fixed
    base (5.35): ``ω_0 = ω``, ``ω'_0 = α``, ``v'_0 = a - g``, by Pinocchio's RNEA on the
    robot below a free-flyer joint, plus the joint friction F(q').

    Parameters
    ----------
    dyn : DHModel, PinocchioArm or array_like, shape (n, 20)
        The robot with its dynamic parameters.
    q, qd, qdd : array_like, shape (n,) or (m, n)
        Joint positions [rad | m], velocities and accelerations relative to the base.
    base_velocity : array_like, shape (6,) or (m, 6)
        ``[v; ω]`` in {0}: velocity of the origin of {0} [m/s] and angular velocity of {0}
        [rad/s] relative to an inertial frame. One row per sample, or one row for all.
    base_acceleration : array_like, shape (6,) or (m, 6)
        ``[a; α]`` in {0}: classical (not spatial) acceleration of the origin of {0} [m/s²]
        and angular acceleration of {0} [rad/s²].
    grav : array_like, shape (3,), optional
        Gravity acceleration in {0} [m/s²]; default ``[0, 0, -9.81]``.

    Returns
    -------
    ndarray, shape (n,) or (m, n)
        Joint torques [N m] (forces [N] for prismatic joints), the shape of ``q``.

    Raises
    ------
    ValueError
        For a robot without dynamics, sizes that do not match (a (m, 6) base motion needs
        q of shape (m, n)), or NaN, naming the argument.

    Examples
    --------
    Ej. 5.1 arm (m1 = 2, m2 = 1 kg, l1 = 3, l2 = 1 m) stretched on a turntable that turns
    about Z_0 with α = 1 rad/s²: τ1 = α (m1 l1² + m2 (l1 + l2)²), τ2 = α m2 l2 (l1 + l2).

    >>> from robotica_kin.robots import two_link_arm
    >>> _, dyn = two_link_arm(2.0, 1.0, 3.0, 1.0)
    >>> rne_moving_base(dyn, [0, 0], [0, 0], [0, 0], [0, 0, 0, 0, 0, 0.5],
    ...                 [0, 0, 0, 0, 0, 1.0]).round(9)
    array([34.,  4.])

    """
    arm = dyn_arm(dyn)
    robot = arm.robot
    qq, vv, aa = _vectors(robot, q=q, qd=qd, qdd=qdd)
    rows, single = qq.shape[0], np.ndim(q) == 1
    base_v = _base_array(base_velocity, 'base_velocity', rows, single)
    base_a = _base_array(base_acceleration, 'base_acceleration', rows, single)
    model = _free_flyer_model(arm)
    set_gravity(model, grav)
    data = model.createData()
    pose = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])   # free flyer at identity: world = {0}
    tau = np.empty((rows, robot.n))
    for k in range(rows):
        linear, angular = base_v[k, :3], base_v[k, 3:]
        # Pinocchio's free-flyer acceleration is the derivative of the body-frame velocity
        # coordinates: its linear part is the classical acceleration minus ω × v.
        spatial = np.concatenate((base_a[k, :3] - np.cross(angular, linear), base_a[k, 3:]))
        full = pin.rnea(model, data, np.concatenate((pose, qq[k])),
                        np.concatenate((base_v[k], vv[k])), np.concatenate((spatial, aa[k])))
        tau[k] = full[6:]
    return _single(tau + np.atleast_2d(friction(robot, vv)), q, 'rne_moving_base')


def base_motion_from_planar(v: ArrayLike, omega: ArrayLike, a_t: ArrayLike, alpha: ArrayLike,
                            offset: ArrayLike = (0.0, 0.0, 0.0)
                            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Return ``(base_velocity, base_acceleration)`` of a manipulator on a planar vehicle.

    The vehicle moves on horizontal ground (book §4.7, §A.5; catalog §12.6 "PUMA on a
    tricycle"): its reference point (e.g. the middle of the rear axle of a tricycle, which
    has no lateral velocity) moves forward at speed v with yaw rate ω; the vehicle frame has
    x forward and z up. The manipulator's base frame {0} has the vehicle frame's axes and its
    origin at ``offset`` in the vehicle frame (the reference point by default). Rigid-body
    kinematics (5.22)-(5.23) with the centripetal term of the turn:

    - reference point: velocity ``(v, 0, 0)``, classical acceleration ``(v', v ω, 0)``;
    - {0}: ``v_0 = v_ref + ω × r``, ``a_0 = a_ref + α × r + ω × (ω × r)`` with
      ``ω = (0, 0, ω)``, ``α = (0, 0, ω')`` and r = ``offset``.

    Parameters
    ----------
    v : float or array_like, shape (m,)
        Forward speed of the reference point [m/s].
    omega : float or array_like, shape (m,)
        Yaw rate [rad/s], > 0 turning left (counter-clockwise seen from above).
    a_t : float or array_like, shape (m,)
        Forward (tangential) acceleration v' [m/s²].
    alpha : float or array_like, shape (m,)
        Yaw acceleration ω' [rad/s²].
    offset : array_like, shape (3,), optional
        Origin of {0} in the vehicle frame [m]; default the reference point.

    Returns
    -------
    base_velocity, base_acceleration : ndarray, shape (6,) or (m, 6)
        ``[v; ω]`` and ``[a; α]`` of {0} in {0}, the inputs of :func:`rne_moving_base`
        (a classical).

    Raises
    ------
    ValueError
        For NaN or infinite values, arrays of more than one dimension or of different lengths,
        or an offset that is not a 3-vector, naming the argument.

    Examples
    --------
    Turning left at 2 m/s on a circle of radius 4 m: lateral acceleration v ω = v²/R = 1 m/s².

    >>> velocity, acceleration = base_motion_from_planar(2.0, 0.5, 0.0, 0.0)
    >>> velocity, acceleration
    (array([2. , 0. , 0. , 0. , 0. , 0.5]), array([0., 1., 0., 0., 0., 0.]))

    """
    values = {}
    for name, value in (('v', v), ('omega', omega), ('a_t', a_t), ('alpha', alpha)):
        arr = np.asarray(value, dtype=np.float64)
        if arr.ndim > 1:
            raise ValueError(f'{name} must be a number or a 1-D array, got shape {arr.shape}')
        if not np.isfinite(arr).all():
            raise ValueError(f'{name} must be finite, got {arr!r}')
        values[name] = arr
    try:
        speed, yaw_rate, accel, yaw_accel = np.broadcast_arrays(*values.values())
    except ValueError:
        raise ValueError(f'v, omega, a_t and alpha must have the same length, got shapes '
                         f'{[a.shape for a in values.values()]}') from None
    r = np.asarray(offset, dtype=np.float64)
    if r.shape != (3,) or not np.isfinite(r).all():
        raise ValueError(f'offset must be a finite 3-vector [m], got {offset!r}')
    zeros = np.zeros_like(speed)
    w = np.stack((zeros, zeros, yaw_rate), axis=-1)
    dw = np.stack((zeros, zeros, yaw_accel), axis=-1)
    velocity_ref = np.stack((speed, zeros, zeros), axis=-1)
    accel_ref = np.stack((accel, speed * yaw_rate, zeros), axis=-1)
    velocity = velocity_ref + np.cross(w, r)
    acceleration = accel_ref + np.cross(dw, r) + np.cross(w, np.cross(w, r))
    return (np.concatenate((velocity, w), axis=-1),
            np.concatenate((acceleration, dw), axis=-1))
