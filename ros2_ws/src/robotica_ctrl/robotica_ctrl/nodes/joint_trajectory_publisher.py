"""
Joint trajectory publisher node: a reference of book ch. 8/10 as one latched JointTrajectory.

``generator`` selects how the trajectory is made; it is sampled every ``sample_period`` (with
positions, velocities and accelerations, which a controller interpolates exactly enough) and
published once on ``joint_trajectory`` (trajectory_msgs/JointTrajectory, transient local, so a
controller started later still gets it):

* ``sine``: ``offset + amplitude sin(2π t / period + phase)`` per joint for ``duration`` s
  (Ej. 8.1 (8.47), the appendix's PUMA reference (A.2)),
  :func:`robotica_ctrl.trajectory.sinusoid.sinusoid`;
* ``pol3``, ``pol5``: cubic or quintic segments through ``via.positions`` (HEMERO ``pol3``,
  ``pol5``, §10.3.1, §10.6), with ``via.velocities`` (``via.accelerations``) at the points,
  zero when not given;
* ``parab``: linear segments with parabolic blends (HEMERO ``parab``, §10.6.4), blend
  accelerations ``parab.acceleration``.

The header stamp is ``start_time`` (0: the controller starts it when it receives it).
"""
from builtin_interfaces.msg import Duration
import numpy as np
from numpy.typing import NDArray
from rclpy.parameter import Parameter
from robotica_ctrl.trajectory import parab, pol3, pol5
from robotica_ctrl.trajectory.sinusoid import sinusoid
from robotica_kin.ros.convert import seconds_to_stamp
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import LATCHED_QOS
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

GENERATORS = ('sine', 'pol3', 'pol5', 'parab')
Samples = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                NDArray[np.float64]]


def _via(values: list[float] | None, n: int, name: str) -> NDArray[np.float64]:
    array = np.asarray(values or [], dtype=np.float64)
    if array.size == 0 or array.size % n:
        raise ValueError(f'{name} must hold points x {n} values (row-major), got {array.size}')
    return array.reshape(-1, n)


def trajectory_samples(generator: str, n: int, sample_period: float, *,
                       duration: float = 0.0, sine: dict | None = None,
                       via: dict | None = None, acceleration: list[float] | None = None
                       ) -> Samples:
    """
    Return ``(t, q, qd, qdd)`` of a generator, t (m,) [s] from 0, the others (m, n).

    ``sine`` holds the keyword arguments of :func:`sinusoid` but ``t``; ``via`` the flattened
    ``positions`` and, optionally, ``velocities`` / ``accelerations`` (points x n, row-major)
    and the ``segment_durations`` [s]; ``acceleration`` the blend accelerations of ``parab``
    (1 or n values) [/s²].

    Raises
    ------
    ValueError
        For an unknown generator or arguments the generator refuses (with its reason).

    Examples
    --------
    >>> t, q, qd, qdd = trajectory_samples('pol3', 1, 0.5, via={
    ...     'positions': [0.0, 1.0], 'segment_durations': [1.0]})
    >>> t.tolist(), q[:, 0].tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.5, 1.0])

    """
    if generator == 'sine':
        if not duration > 0.0:
            raise ValueError(f'duration must be > 0 s for a sine, got {duration!r}')
        t = np.arange(0.0, duration + 0.5 * sample_period, sample_period)
        q, qd, qdd = sinusoid(t, **(sine or {}))
        if q.shape[1] not in (1, n):
            raise ValueError(f'sine parameters give {q.shape[1]} joints, expected {n}')
        ones = np.ones((1, n))
        return t, q * ones, qd * ones, qdd * ones
    if generator not in GENERATORS:
        raise ValueError(f'generator must be one of {GENERATORS}, got {generator!r}')
    via = via or {}
    positions = _via(via.get('positions'), n, 'via.positions')
    durations = via.get('segment_durations') or []
    zeros = np.zeros_like(positions)
    velocities = (zeros if not via.get('velocities')
                  else _via(via['velocities'], n, 'via.velocities'))
    if generator == 'pol3':
        _, t, q, qd, qdd = pol3(positions, velocities, 0.0, durations, sample_period)
    elif generator == 'pol5':
        accelerations = (zeros if not via.get('accelerations')
                         else _via(via['accelerations'], n, 'via.accelerations'))
        _, t, q, qd, qdd = pol5(positions, velocities, accelerations, 0.0, durations,
                                sample_period)
    else:
        ac = np.asarray(acceleration or [], dtype=np.float64)
        if ac.size not in (1, n):
            raise ValueError(f'parab.acceleration must hold 1 or {n} values, got {ac.size}')
        _, t, q, qd, qdd, _ = parab(positions, ac if ac.size > 1 else float(ac[0]), 0.0,
                                    durations, sample_period)
    return t, q, qd, qdd


class JointTrajectoryPublisherNode(GuardedNode):
    """Publish one generated trajectory, latched, and keep it available."""

    def __init__(self) -> None:
        super().__init__('joint_trajectory_publisher')
        generator = declare(self, 'generator', 'sine', f'One of {GENERATORS}', read_only=True)
        names = declare(self, 'joint_names', Parameter.Type.STRING_ARRAY,
                        'Joint names of the trajectory, in column order', read_only=True)
        if not names:
            raise ValueError('joint_names must name the joints of the trajectory')
        period = declare(self, 'sample_period', 0.01, 'Time between trajectory points [s]',
                         low=1e-4, high=10.0, read_only=True)
        start = declare(self, 'start_time', 0.0,
                        'Header stamp [s]: when the trajectory starts; 0: on receipt',
                        low=0.0, high=1e7, read_only=True)
        duration = declare(self, 'duration', 10.0, 'Length of a sine reference [s]',
                           low=0.0, high=1e6, read_only=True)
        sine = {key: declare(self, f'sine.{key}', default, description, read_only=True)
                for key, default, description in (
                    ('amplitude', [1.0], 'A [rad | m] per joint (one value: all joints)'),
                    ('period', [6.283185307179586], 'T [s] per joint'),
                    ('phase', [0.0], 'phi [rad] per joint'),
                    ('offset', [0.0], 'Offset [rad | m] per joint'))}
        via = {key: declare(self, f'via.{key}', Parameter.Type.DOUBLE_ARRAY, description,
                            read_only=True)
               for key, description in (
                   ('positions', 'Via points [rad | m], points x joints, row-major'),
                   ('velocities', 'Velocities at the via points (pol3, pol5); default zero'),
                   ('accelerations', 'Accelerations at the via points (pol5); default zero'),
                   ('segment_durations', 'Duration of each segment [s]'))}
        acceleration = declare(self, 'parab.acceleration', [1.0],
                               'Blend acceleration magnitudes [/s^2] (1 or one per joint)',
                               read_only=True)
        t, q, qd, qdd = trajectory_samples(generator, len(names), period, duration=duration,
                                           sine=sine, via=via, acceleration=acceleration)
        msg = JointTrajectory(joint_names=list(names))
        msg.header.stamp = seconds_to_stamp(start)
        msg.points = [JointTrajectoryPoint(positions=q[k].tolist(), velocities=qd[k].tolist(),
                                           accelerations=qdd[k].tolist(),
                                           time_from_start=seconds_to_stamp(t[k], Duration))
                      for k in range(t.size)]
        self._pub = self.create_publisher(JointTrajectory, 'joint_trajectory', LATCHED_QOS)
        self._pub.publish(msg)
        self.get_logger().info(f'{generator} trajectory of {t.size} points over {t[-1]:.3f} s '
                               f'for joints {list(names)} published')


def main(args=None) -> None:
    """Publish the trajectory and stay up (it is latched) until Ctrl-C."""
    run_node(JointTrajectoryPublisherNode, args)
