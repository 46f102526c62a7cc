"""
A joint trajectory known at sample times, evaluated at any instant (the controller's reference).

A ``trajectory_msgs/JointTrajectory`` carries points ``(t_k, q_k, q_k', q_k'')``; a controller
running at another rate needs ``(q_d, q_d', q_d'')`` in between. As ros2_controllers' joint
trajectory controller does, each interval is the Hermite polynomial that matches what the points
give: quintic with positions, velocities and accelerations (book (10.40)-(10.52)), cubic with
positions and velocities ((10.25)-(10.39)), linear with positions only. Before the first point
the reference holds the first position at rest; after the last, the last position at rest.
"""

import bisect

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.joint_control.law import JointReference
from scipy.interpolate import PPoly

__all__ = ['SampledTrajectory', 'trajectory_from_points']


def _samples(name: str, value: ArrayLike, shape: tuple[int, int]) -> NDArray[np.float64]:
    array = np.asarray(value, dtype=np.float64)
    if array.shape != shape:
        raise ValueError(f'{name} must have shape {shape} (points, joints), got {array.shape}')
    if not np.isfinite(array).all():
        raise ValueError(f'{name} must be finite (no NaN or inf)')
    return array


def _hermite_coefficients(t: NDArray[np.float64], columns: list[NDArray[np.float64]]
                          ) -> NDArray[np.float64]:
    """
    Return the power-basis coefficients (k, m - 1, n) of the Hermite interval polynomials.

    Each interval [t_i, t_i+1] of length h gets, in its local time τ = t - t_i, the polynomial
    of lowest degree matching the given derivatives at both ends: linear (positions), cubic
    (and velocities, book (10.25)-(10.39)) or quintic (and accelerations, (10.40)-(10.52)).
    Rows go from the highest power down (scipy's PPoly convention). All intervals at once:
    scipy's BPoly.from_derivatives loops over them in Python and took 9 s for 1e5 points of 6
    joints (42 s with accelerations), a trajectory message that wedged the joint controller.
    """
    h = np.diff(t)[:, None]          # (m - 1, 1)
    q0, q1 = columns[0][:-1], columns[0][1:]
    dq = q1 - q0
    if len(columns) == 1:
        return np.stack([dq / h, q0])
    v0, v1 = columns[1][:-1], columns[1][1:]
    if len(columns) == 2:
        return np.stack([(v0 + v1 - 2.0 * dq / h) / h ** 2,
                         (3.0 * dq / h - 2.0 * v0 - v1) / h,
                         v0, q0])
    a0, a1 = columns[2][:-1], columns[2][1:]
    return np.stack([
        (12.0 * dq - 6.0 * (v0 + v1) * h + (a1 - a0) * h ** 2) / (2.0 * h ** 5),
        (-30.0 * dq + (16.0 * v0 + 14.0 * v1) * h + (3.0 * a0 - 2.0 * a1) * h ** 2)
        / (2.0 * h ** 4),
        (20.0 * dq - (12.0 * v0 + 8.0 * v1) * h - (3.0 * a0 - a1) * h ** 2) / (2.0 * h ** 3),
        a0 / 2.0, v0, q0])


class SampledTrajectory:
    """
    Piecewise Hermite interpolation of joint samples; :meth:`sample` gives a JointReference.

    Parameters
    ----------
    times : array_like, shape (m,)
        Sample times [s], strictly increasing (m >= 1).
    positions : array_like, shape (m, n)
        Joint positions [rad | m].
    velocities, accelerations : array_like, shape (m, n), optional
        Joint velocities [/s] and accelerations [/s²]; accelerations need velocities.

    Raises
    ------
    ValueError
        For times that do not increase, shapes that disagree, or non-finite values.

    Examples
    --------
    >>> traj = SampledTrajectory([0.0, 1.0], [[0.0], [1.0]], [[0.0], [0.0]])
    >>> ref = traj.sample(0.5)          # rest-to-rest cubic (10.89)-(10.90): midpoint, 1.5/s
    >>> float(ref.q_d[0]), float(ref.qd_d[0])
    (0.5, 1.5)

    """

    def __init__(self, times: ArrayLike, positions: ArrayLike,
                 velocities: ArrayLike | None = None,
                 accelerations: ArrayLike | None = None) -> None:
        t = np.asarray(times, dtype=np.float64)
        if t.ndim != 1 or t.size == 0 or not np.isfinite(t).all():
            raise ValueError(f'times must be a non-empty finite vector, got {times!r}')
        if np.any(np.diff(t) <= 0.0):
            raise ValueError('times must be strictly increasing')
        q = np.asarray(positions, dtype=np.float64)
        if q.ndim != 2 or q.shape[0] != t.size or q.shape[1] == 0:
            raise ValueError(f'positions must have shape ({t.size}, n), got {q.shape}')
        q = _samples('positions', q, q.shape)
        columns = [q]
        if velocities is not None:
            columns.append(_samples('velocities', velocities, q.shape))
        if accelerations is not None:
            if velocities is None:
                raise ValueError('accelerations need velocities')
            columns.append(_samples('accelerations', accelerations, q.shape))
        self.times = t
        self.n = q.shape[1]
        self._first = q[0].copy()
        self._last = q[-1].copy()
        self._zero = np.zeros(self.n)
        self._breaks = t.tolist()
        # Per derivative order: the local power-basis coefficients (k, m - 1, n) of PPoly's
        # convention (c[j, i] multiplies (t - t_i)**(k - 1 - j)) and the exponents k - 1 … 0.
        self._polynomials: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = []
        if t.size > 1:
            position = PPoly(_hermite_coefficients(t, columns), t, extrapolate=False)
            for poly in (position, position.derivative(1), position.derivative(2)):
                k = poly.c.shape[0]
                self._polynomials.append((np.ascontiguousarray(poly.c),
                                          np.arange(k - 1, -1, -1, dtype=np.float64)))

    @property
    def start_time(self) -> float:
        """Return the time of the first sample [s]."""
        return float(self.times[0])

    @property
    def end_time(self) -> float:
        """Return the time of the last sample [s]."""
        return float(self.times[-1])

    def sample(self, t: float) -> JointReference:
        """Return the reference ``(q_d, q_d', q_d'')`` at ``t`` [s] (held outside the samples)."""
        if not np.isfinite(t):
            raise ValueError(f't must be finite, got {t!r}')
        if t < self._breaks[0] or not self._polynomials:
            return JointReference(self._first, self._zero, self._zero)
        if t > self._breaks[-1]:
            return JointReference(self._last, self._zero, self._zero)
        # The segment [t_i, t_i+1] holding t (the last one for t = t_m), evaluated in its own
        # local time as one small product per order: 3 µs instead of PPoly's 30 µs per call.
        i = min(bisect.bisect_right(self._breaks, t), len(self._breaks) - 1) - 1
        dt = t - self._breaks[i]
        position, velocity, acceleration = (dt ** exponents @ c[:, i, :]
                                            for c, exponents in self._polynomials)
        return JointReference(position, velocity, acceleration)


def trajectory_from_points(joint_names: list[str], points: list, names: list[str]
                           ) -> SampledTrajectory:
    """
    Return the SampledTrajectory of a JointTrajectory's points, in the joint order ``names``.

    ``points`` are ``trajectory_msgs/JointTrajectoryPoint``-like objects (``time_from_start``
    with ``sec``/``nanosec``, ``positions``, optional ``velocities`` and ``accelerations``, in
    the order of ``joint_names``): the messages of rclpy and of a bag reader alike.

    Raises
    ------
    ValueError
        If ``joint_names`` does not cover ``names``, there are no points, a point lacks a
        field the others have, or the samples are not a trajectory (see SampledTrajectory).

    """
    try:
        order = [list(joint_names).index(name) for name in names]
    except ValueError:
        raise ValueError(f'joints {list(joint_names)} do not cover {list(names)}') from None
    if not points:
        raise ValueError('no points')
    times = [p.time_from_start.sec + p.time_from_start.nanosec * 1e-9 for p in points]
    columns = []
    for field in ('positions', 'velocities', 'accelerations'):
        sizes = {len(getattr(p, field)) for p in points}
        if sizes == {0}:
            break
        if sizes != {len(joint_names)}:
            raise ValueError(f'every point needs {len(joint_names)} {field}')
        columns.append(np.array([getattr(p, field) for p in points])[:, order])
    if not columns:
        raise ValueError('points have no positions')
    return SampledTrajectory(times, *columns)
