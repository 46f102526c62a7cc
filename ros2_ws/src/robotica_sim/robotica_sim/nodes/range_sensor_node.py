"""
The shell the range sensor emulators share: the world, the truth's poses, the sample times.

A range emulator (``sonar_emulator``, ``infrared_emulator``, ``laser_emulator``) reads the world
from ``world_file`` (required: a map_server map or a YAML file with a ``world:`` section,
:func:`robotica_kin.world.world_file.load_world_file`; missing or malformed: exit 2 with one
line), takes the robot's true pose in the map from ``ground_truth/odom`` (nav_msgs/Odometry)
and makes a reading whenever a truth stamp crosses the sensor's next sample time
(:class:`~robotica_sim.sensors.range_beams.SampleSchedule`), stamped with that truth stamp, so
that a lockstep run is deterministic for a given ``seed``. A non-finite pose, or a stamp that
jumps, is refused by the guard (logged, dropped) and the node keeps running.
"""
from typing import Any, Callable, Mapping, Sequence

from builtin_interfaces.msg import Time
from nav_msgs.msg import Odometry
import numpy as np
from numpy.typing import NDArray
from robotica_kin.bounds import StampGate
from robotica_kin.parameter_specs import ParameterSpec
from robotica_kin.ros.convert import pose2d_from_odometry, stamp_to_seconds
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_kin.world.shapes import World
from robotica_kin.world.world_file import load_world_file
from robotica_sim.sensors.range_beams import check_mounts, SampleSchedule
from sensor_msgs.msg import Range


class RangeSensorNode(GuardedNode):
    """A node that reads the world and calls :meth:`sample` at ``rate`` on the truth's time."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self._world_file = declare(
            self, 'world_file', '', 'The world the sensor sees: a map_server map or a YAML '
            'file with a world: section (a scenario); required', read_only=True)
        self.world = World()
        self._stamps = StampGate()
        self._schedule: SampleSchedule | None = None

    def declare_terms(self, parameters: Mapping[str, ParameterSpec],
                      term_specs: Callable[[str], dict[str, ParameterSpec]]) -> dict[str, Any]:
        """
        Declare ``preset`` and ``seed``, then each term with the preset's value as default.

        A term given explicitly (``-p``, ``--params-file``) overrides the preset's value; all
        are read-only. Return the values by name.
        """
        values = declare_specs(self, {k: parameters[k] for k in ('preset', 'seed')})
        values.update(declare_specs(self, term_specs(values['preset'])))
        return values

    def declare_sensors(self, kind: str, default_mounts: Sequence[float],
                        ) -> tuple[NDArray[np.float64], list[str], list[Any]]:
        """
        Declare ``mounts`` and ``frame_prefix``; return the mounts, frames and publishers.

        Sensor i of ``kind`` (``sonar``) publishes sensor_msgs/Range on ``<kind>_<i>`` in
        frame ``<frame_prefix><i>_link``. ValueError (exit 2) for mounts that are not
        finite (x, y, yaw) triples.
        """
        mounts = declare(self, 'mounts', list(default_mounts), f'The {kind} sensors (x [m], '
                         'y [m], yaw [rad]) in base_link, three numbers each', read_only=True)
        if len(mounts) % 3:
            raise ValueError(f'mounts must hold (x, y, yaw) triples, got {len(mounts)} numbers')
        prefix = declare(self, 'frame_prefix', f'{kind}_', 'Sensor i is frame '
                         '<frame_prefix><i>_link', read_only=True)
        triples = check_mounts(np.reshape(mounts, (-1, 3)))
        frames = [f'{prefix}{i}_link' for i in range(len(triples))]
        pubs = [self.create_publisher(Range, f'{kind}_{i}', STREAM_PUB_QOS)
                for i in range(len(triples))]
        return triples, frames, pubs

    def start(self, rate: float) -> None:
        """
        Load the world, subscribe to the truth and sample at ``rate`` [Hz] from now on.

        Called once every parameter is declared (so that ``robotica params`` lists them all):
        ValueError (exit 2) for a missing or malformed world file.
        """
        if not self._world_file:
            raise ValueError('world_file is required (a map_server map or a YAML file with a '
                             'world: section)')
        self.world = load_world_file(self._world_file)   # WorldError (a ValueError): exit 2
        self._schedule = SampleSchedule(rate)
        self.create_subscription(Odometry, 'ground_truth/odom', self._on_truth,
                                 STREAM_REPLAY_SUB_QOS)

    def _on_truth(self, msg: Odometry) -> None:
        t = stamp_to_seconds(msg.header.stamp)
        self._stamps.check(t)   # raises when it jumps; a restart: the schedule starts again
        pose = pose2d_from_odometry(msg)
        if not np.isfinite(pose).all():
            raise ValueError(f'non-finite pose {pose.tolist()}: no reading')
        assert self._schedule is not None
        if self._schedule.due(t):
            self.sample(pose, msg.header.stamp)

    def sample(self, pose: NDArray[np.float64], stamp: Time) -> Any:
        """Make and publish a reading from the robot's ``pose`` (x, y, θ), at ``stamp``."""
        raise NotImplementedError
