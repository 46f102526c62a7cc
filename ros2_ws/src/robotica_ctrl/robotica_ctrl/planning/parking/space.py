"""
The parking space: a rectangle between two parked obstacles and the curb (catalogue §14.1).

slides ("Caracterización geométrica del espacio de estacionamiento"): J is the width of the
space, H its length, MS the safety margin to the obstacles; the effective width is J' = J
and the effective length H' = H − 2·MS. The obstacles are the front one (ahead of the space),
the rear one (behind it) and the lateral one (the curb or wall).

completion (ours), the frames. The *space frame* has its origin on the line of the parked
obstacles' sides (the street side of the parked cars), at the end of the rear obstacle; x
runs along the street in the direction of the reconnaissance pass (towards the front
obstacle), y to the left (REP-103). A space on the ``'right'`` of the pass is the rectangle
0 ≤ x ≤ H, −J ≤ y ≤ 0; one on the ``'left'`` its mirror image, 0 ≤ y ≤ J. The planner works
in the *canonical frame*, the space frame of a right-hand space: a left-hand space is planned
mirrored (y → −y, θ → −θ, steering → −steering) and mirrored back. :attr:`ParkingSpace.origin`
is the space frame's pose (x [m], y [m], heading [rad]) in the map frame.
"""

from dataclasses import dataclass
import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.angles import wrap_to_pi
from robotica_kin.finite import finite_real
from robotica_kin.world import World

__all__ = ['ParkingSpace', 'Side']

Side = Literal['right', 'left']


@dataclass(frozen=True)
class ParkingSpace:
    """
    A space of length H and depth J [m] beside a street, with its safety margin MS [m].

    ``origin`` (x [m], y [m], heading [rad]): the space frame in the map frame (module);
    ``side``: where the space lies from the pass, 'right' (y < 0) or 'left' (y > 0).

    >>> space = ParkingSpace((0.0, 0.0, 0.0), length=7.0, depth=2.2, margin=0.2)
    >>> round(space.effective_length, 6), space.effective_width
    (6.6, 2.2)
    """

    origin: tuple[float, float, float]
    length: float                # H [m]
    depth: float                 # J [m]
    side: Side = 'right'
    margin: float = 0.2          # MS [m]

    def __post_init__(self) -> None:
        pose = np.asarray(self.origin, dtype=np.float64)
        if pose.shape != (3,) or not np.isfinite(pose).all():
            raise ValueError(f'origin must be a finite (x, y, heading), got {self.origin!r}')
        object.__setattr__(self, 'origin', tuple(float(v) for v in pose))
        for name in ('length', 'depth'):
            if not finite_real(name, getattr(self, name)) > 0.0:
                raise ValueError(f'{name} must be > 0 m, got {getattr(self, name)!r}')
        if not finite_real('margin', self.margin) >= 0.0:
            raise ValueError(f'margin must be >= 0 m, got {self.margin!r}')
        if self.side not in ('right', 'left'):
            raise ValueError(f"side must be 'right' or 'left', got {self.side!r}")

    @property
    def effective_length(self) -> float:
        """Return H' = H − 2·MS [m]."""
        return self.length - 2.0 * self.margin

    @property
    def effective_width(self) -> float:
        """Return J' = J [m] (the slides keep the whole width)."""
        return self.depth

    @property
    def mirror(self) -> float:
        """Return +1 for a right-hand space, -1 for a left-hand one (canonical → space frame)."""
        return 1.0 if self.side == 'right' else -1.0

    def to_map(self, postures: ArrayLike) -> NDArray[np.float64]:
        """
        Return canonical-frame postures (N, 3) (x, y [m], θ [rad]) in the map frame.

        >>> ParkingSpace((1.0, 2.0, math.pi / 2), 7.0, 2.2, 'left').to_map([[1.0, -1.0, 0.0]])
        array([[0.        , 3.        , 1.57079633]])
        """
        q = np.array(postures, dtype=np.float64, ndmin=2)
        if q.shape[1] != 3:
            raise ValueError(f'postures must have shape (N, 3), got {q.shape}')
        x0, y0, heading = self.origin
        c, s = math.cos(heading), math.sin(heading)
        y = self.mirror * q[:, 1]
        return np.column_stack([x0 + c * q[:, 0] - s * y, y0 + s * q[:, 0] + c * y,
                                wrap_to_pi(heading + self.mirror * q[:, 2])])

    def from_map(self, postures: ArrayLike) -> NDArray[np.float64]:
        """
        Return map-frame postures (N, 3) in the canonical frame (the inverse of to_map).

        >>> space = ParkingSpace((1.0, 2.0, 0.3), 7.0, 2.2, 'left')
        >>> space.from_map(space.to_map([[1.0, -1.0, 0.2]])).round(12).tolist()
        [[1.0, -1.0, 0.2]]
        """
        q = np.array(postures, dtype=np.float64, ndmin=2)
        if q.shape[1] != 3:
            raise ValueError(f'postures must have shape (N, 3), got {q.shape}')
        x0, y0, heading = self.origin
        c, s = math.cos(heading), math.sin(heading)
        dx, dy = q[:, 0] - x0, q[:, 1] - y0
        return np.column_stack([c * dx + s * dy, self.mirror * (-s * dx + c * dy),
                                self.mirror * wrap_to_pi(q[:, 2] - heading)])

    def obstacle_world(self, extent: float = 10.0) -> World:
        """
        Return the space's obstacles in the map frame: two blocks and the curb.

        The rear and front obstacles are blocks of depth J and length ``extent`` [m] beyond
        either end of the space; the curb a wall along y = −J over the whole length.

        >>> len(ParkingSpace((0.0, 0.0, 0.0), 7.0, 2.2).obstacle_world().polygons)
        2
        """
        if not finite_real('extent', extent) > 0.0:
            raise ValueError(f'extent must be > 0 m, got {extent!r}')
        h, j = self.length, self.depth
        rear = [[-extent, -j], [0.0, -j], [0.0, 0.0], [-extent, 0.0]]
        front = [[h, -j], [h + extent, -j], [h + extent, 0.0], [h, 0.0]]
        curb = [[-extent, -j], [h + extent, -j]]

        def place(points: list[list[float]]) -> NDArray[np.float64]:
            return self.to_map(np.column_stack([points, np.zeros(len(points))]))[:, :2]

        return World(walls=place(curb).reshape(1, 4),
                     polygons=(place(rear), place(front)))
