"""
The two execution modes of a parking manoeuvre: stop between the arcs, or steer progressively.

Seed catalogue §14.4, slides "Las maniobras se calculan con una caracterización geométrica, o
se aplican acciones de control preestablecidas":

slides: (a) geometric characterisation: each manoeuvre is two circular arcs with the
equivalent steering wheel at one extreme and then the other; the vehicle stops in the middle
of the manoeuvre to re-orient the steering wheels (:class:`GeometricMode`). (b) pre-established
control actions: the wheels are re-oriented progressively while moving, with no stop,
producing equivalent manoeuvres (:class:`ProgressiveMode`).

completion (ours), the progressive profile: the slides give none. The steering angle φ
changes linearly with the distance s travelled by P_f, at ``steering_per_metre`` σ [rad/m]
(a steering rate [rad/s] over the manoeuvring speed [m/s]): 0 → −φ_m (right), hold −φ_m for
L_h, −φ_m → +φ_m, hold +φ_m for L_h, +φ_m → 0. The profile is odd about its middle, so the
heading change ∫ tan φ / h1 ds is zero: the vehicle is parallel to the space at both ends,
like the two arcs, and it shifts to the right. Its size u ∈ [0, 2] orders the family by
lateral shift: u ≤ 1 ramps only, φ_m = u·φ_d; u ≥ 1 holds φ_m = φ_d for L_h = (u − 1)·ρ·π/2
(up to a quarter turn on each hold, as ξ ≤ π/2 on each arc). "Equivalent manoeuvre" is read
as: the same lateral shift and parallel ends; the longitudinal room it takes is its own
(longer than the arcs', the ramps turn less).

Both modes answer the planner's questions about the manoeuvre of a given size that shifts
P_f to the right, in its start frame (P_f at the origin, x forward, y left): the lateral
and longitudinal shift (X, Y), the extents of the swept body (closed form for the arcs,
:func:`.two_arc_extents`; from postures sampled every 1 cm for the progressive curve), the
size that shifts by a given X, and the pieces to drive. :func:`sample_pieces` integrates the
bicycle model of the equivalent tricycle, x' = v cos θ, y' = v sin θ, θ' = v tan φ / h1 (book
(4.121), REP-103): the heading in closed form (∫ tan φ ds = −ln cos φ / σ on a ramp), the
position by Simpson's rule on each step.
"""

from dataclasses import dataclass, replace
import math
from typing import Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.planning.parking.collision_predicates import (
    sampled_extents, SweptExtents, two_arc_extents)
from robotica_ctrl.planning.parking.manoeuvre_arcs import two_arc_displacement
from robotica_ctrl.planning.parking.vehicle import ParkingVehicle
from robotica_kin.finite import finite_real

__all__ = ['ExecutionMode', 'GeometricMode', 'ManoeuvreShape', 'Piece', 'ProgressiveMode',
           'SampledMotion', 'make_mode', 'sample_pieces']

PieceKind = Literal['arc', 'straight', 'ramp']
FINE_STEP = 0.01          # [m] sampling of a progressive manoeuvre for its shift and extents
_BISECTIONS = 60          # halvings of a size interval (to 2^-60 of it)


@dataclass(frozen=True)
class Piece:
    """
    A stretch driven in one direction with the steering linear in the distance.

    ``direction`` +1 forward, -1 reverse; ``length`` [m] travelled by P_f; ``steering_start``
    and ``steering_end`` [rad] the equivalent wheel's angle φ (positive to the left) at its
    ends; ``kind`` 'arc' (constant φ ≠ 0), 'straight' (φ = 0) or 'ramp' (φ changing).
    """

    direction: int
    length: float
    steering_start: float
    steering_end: float
    kind: PieceKind

    def __post_init__(self) -> None:
        if self.direction not in (-1, 1):
            raise ValueError(f'direction must be +1 or -1, got {self.direction!r}')
        if not finite_real('length', self.length) >= 0.0:
            raise ValueError(f'length must be >= 0 m, got {self.length!r}')
        finite_real('steering_start', self.steering_start)
        finite_real('steering_end', self.steering_end)

    def mirrored(self) -> 'Piece':
        """Return the mirror-image piece (steering of the opposite sign)."""
        return replace(self, steering_start=-self.steering_start,
                       steering_end=-self.steering_end)


@dataclass(frozen=True)
class SampledMotion:
    """
    Postures (N, 3) (x [m], y [m], θ [rad]) and, per segment (N - 1,), what drives it.

    ``steering`` [rad] the equivalent wheel's angle at the segment's middle, ``directions``
    +1 forward / -1 reverse, ``piece`` the index of the piece the segment belongs to.
    """

    postures: NDArray[np.float64]
    steering: NDArray[np.float64]
    directions: NDArray[np.int8]
    piece: NDArray[np.int64]


def _turn(piece: Piece, u: NDArray[np.float64], wheelbase: float) -> NDArray[np.float64]:
    """Return the heading change [rad] after driving ``u`` [m] into ``piece``: exact."""
    phi0, phi1 = piece.steering_start, piece.steering_end
    if abs(phi1 - phi0) <= 1e-9:
        integral = math.tan(0.5 * (phi0 + phi1)) * u
    else:                       # ∫ tan(φ0 + σ t) dt = (ln cos φ0 − ln cos φ(u)) / σ
        rate = (phi1 - phi0) / piece.length
        integral = (math.log(math.cos(phi0)) - np.log(np.cos(phi0 + rate * u))) / rate
    return np.asarray(piece.direction * integral / wheelbase)


def sample_pieces(start: ArrayLike, pieces: tuple[Piece, ...], wheelbase: float,
                  step: float) -> SampledMotion:
    """
    Return the postures of driving ``pieces`` from ``start`` (x, y, θ), ``step`` [m] apart.

    The bicycle model of the equivalent tricycle with wheelbase h1 = ``wheelbase`` [m]; each
    piece is cut into equal steps <= ``step`` [m]. The heading is exact (∫ tan φ ds in
    closed form, φ linear in s), the position Simpson's rule on each step (below 1e-10 m
    for the arcs of a car at 5 cm, fourth order in the step for the ramps). Pieces of zero
    length are skipped; ``steering`` per segment is φ at its middle.

    >>> m = sample_pieces([0, 0, 0], (Piece(1, math.pi / 2, math.atan(1.0), math.atan(1.0),
    ...                                     'arc'),), 1.0, 0.1)
    >>> m.postures[-1].round(6).tolist(), len(m.steering)
    ([1.0, 1.0, 1.570796], 16)
    """
    pose = np.asarray(start, dtype=np.float64)
    if pose.shape != (3,) or not np.isfinite(pose).all():
        raise ValueError(f'start must be a finite (x, y, theta), got {start!r}')
    h = finite_real('wheelbase', wheelbase)
    if not (h > 0.0 and finite_real('step', step) > 0.0):
        raise ValueError(f'wheelbase and step must be > 0 m, got {wheelbase!r}, {step!r}')
    postures, steering, directions, index = [pose[None, :].copy()], [], [], []
    heading, x, y = float(pose[2]), float(pose[0]), float(pose[1])
    for k, piece in enumerate(pieces):
        if piece.length <= 0.0:
            continue
        n = max(1, math.ceil(piece.length / step - 1e-9))
        u = np.linspace(0.0, piece.length, 2 * n + 1)          # step ends and middles
        theta = heading + _turn(piece, u, h)
        c, s = piece.direction * np.cos(theta), piece.direction * np.sin(theta)
        weight = piece.length / n / 6.0
        dx = weight * (c[:-1:2] + 4.0 * c[1::2] + c[2::2])
        dy = weight * (s[:-1:2] + 4.0 * s[1::2] + s[2::2])
        postures.append(np.column_stack([x + np.cumsum(dx), y + np.cumsum(dy), theta[2::2]]))
        heading, x, y = float(theta[-1]), float(postures[-1][-1, 0]), float(postures[-1][-1, 1])
        steering.append(piece.steering_start
                        + (piece.steering_end - piece.steering_start) * (u[1::2] / piece.length))
        directions.append(np.full(n, piece.direction, dtype=np.int8))
        index.append(np.full(n, k, dtype=np.int64))
    if not steering:
        return SampledMotion(postures[0], np.zeros(0), np.zeros(0, dtype=np.int8),
                             np.zeros(0, dtype=np.int64))
    return SampledMotion(np.vstack(postures), np.concatenate(steering),
                         np.concatenate(directions), np.concatenate(index))


@dataclass(frozen=True)
class ManoeuvreShape:
    """
    What a manoeuvre of one size does from its start: shifts X, Y [m] and swept extents.

    ``lateral`` X to the right, ``longitudinal`` Y along the direction of motion (both >= 0),
    ``extents`` of the swept body in the start frame (:class:`.SweptExtents`).
    """

    lateral: float
    longitudinal: float
    extents: SweptExtents


class ExecutionMode(Protocol):
    """The questions the planner asks of an execution mode (see the module)."""

    @property
    def name(self) -> str:
        """Return the mode's name."""

    @property
    def vehicle(self) -> ParkingVehicle:
        """Return the vehicle."""

    @property
    def steering(self) -> float:
        """Return the largest steering angle φ_d [rad] of a manoeuvre."""

    @property
    def stops_between_arcs(self) -> bool:
        """Return whether the vehicle stops to re-orient its wheels within a manoeuvre."""

    @property
    def max_size(self) -> float:
        """Return the largest size of a manoeuvre."""

    def pieces(self, size: float, direction: int) -> tuple[Piece, ...]:
        """Return the pieces of the manoeuvre of ``size`` shifting right in ``direction``."""

    def shape(self, size: float, direction: int) -> ManoeuvreShape:
        """Return the shifts and swept extents of that manoeuvre."""

    def size_for_shift(self, lateral: float) -> float:
        """Return the size whose lateral shift is ``lateral`` [m] (max_size beyond reach)."""

    def with_steering(self, steering: float) -> 'ExecutionMode':
        """Return the same mode with the largest steering angle ``steering`` [rad]."""


def _check_steering(vehicle: ParkingVehicle, steering: float) -> float:
    phi = finite_real('steering', steering)
    if not 0.0 < phi <= vehicle.theta_dmax:
        raise ValueError(f'steering must be in (0, theta_dmax = {vehicle.theta_dmax}] rad, '
                         f'got {steering!r}')
    return phi


def _size(size: float, largest: float) -> float:
    value = finite_real('size', size)
    if not 0.0 <= value <= largest * (1.0 + 1e-12):
        raise ValueError(f'size must be in [0, {largest}], got {size!r}')
    return min(value, largest)


@dataclass(frozen=True)
class GeometricMode:
    """
    Mode (a): two arcs of radius ρ = h1 / tan(φ_d) and angle ξ = size [rad], stop between.

    >>> mode = GeometricMode(ParkingVehicle(h1=2.0), math.atan(0.5))
    >>> s = mode.shape(math.pi / 2, -1)
    >>> round(s.lateral, 6), round(s.longitudinal, 6), round(mode.size_for_shift(8.0), 6)
    (8.0, 8.0, 1.570796)
    """

    vehicle: ParkingVehicle
    steering: float
    name: str = 'geometric'
    stops_between_arcs: bool = True

    def __post_init__(self) -> None:
        _check_steering(self.vehicle, self.steering)

    @property
    def radius(self) -> float:
        """Return the arcs' radius ρ = h1 / tan(φ_d) [m]."""
        return self.vehicle.turning_radius(self.steering)

    @property
    def max_size(self) -> float:
        """Return π/2: beyond it Y of (A) shrinks again."""
        return 0.5 * math.pi

    def pieces(self, size: float, direction: int) -> tuple[Piece, ...]:
        """Return the two arcs: steering right (-φ_d) then left (+φ_d), ρ ξ each."""
        length = self.radius * _size(size, self.max_size)
        return (Piece(direction, length, -self.steering, -self.steering, 'arc'),
                Piece(direction, length, self.steering, self.steering, 'arc'))

    def shape(self, size: float, direction: int) -> ManoeuvreShape:
        """Return X, Y of (A) and the closed-form extents (:func:`.two_arc_extents`)."""
        xi = _size(size, self.max_size)
        lateral, longitudinal, _ = two_arc_displacement(self.radius, xi)
        return ManoeuvreShape(lateral, longitudinal,
                              two_arc_extents(self.vehicle, self.radius, xi, direction))

    def size_for_shift(self, lateral: float) -> float:
        """Return ξ = arccos(1 − X / 2ρ) [rad], π/2 for X >= 2ρ (catalogue §14.4)."""
        x = max(finite_real('lateral', lateral), 0.0)
        return math.acos(max(1.0 - x / (2.0 * self.radius), 0.0))

    def with_steering(self, steering: float) -> 'GeometricMode':
        """Return the mode with arcs of steering ``steering`` [rad]."""
        return replace(self, steering=steering)


@dataclass(frozen=True)
class ProgressiveMode:
    """
    Mode (b): the steering changes at σ = ``steering_per_metre`` [rad/m] while moving.

    >>> mode = ProgressiveMode(ParkingVehicle(), 0.6, 1.0)
    >>> s = mode.shape(1.5, 1)
    >>> round(s.lateral, 3), round(mode.size_for_shift(s.lateral), 6)
    (3.592, 1.5)
    """

    vehicle: ParkingVehicle
    steering: float
    steering_per_metre: float
    name: str = 'progressive'
    stops_between_arcs: bool = False

    def __post_init__(self) -> None:
        _check_steering(self.vehicle, self.steering)
        if not finite_real('steering_per_metre', self.steering_per_metre) > 0.0:
            raise ValueError(f'steering_per_metre must be > 0 rad/m, got '
                             f'{self.steering_per_metre!r}')

    @property
    def max_size(self) -> float:
        """Return 2: full steering held for a quarter turn on each side."""
        return 2.0

    def pieces(self, size: float, direction: int) -> tuple[Piece, ...]:
        """Return ramp, hold, ramp through zero, hold, ramp (see the module)."""
        u = _size(size, self.max_size)
        peak = self.steering * min(u, 1.0)
        hold = max(u - 1.0, 0.0) * self.vehicle.turning_radius(self.steering) * 0.5 * math.pi
        ramp = peak / self.steering_per_metre
        return (Piece(direction, ramp, 0.0, -peak, 'ramp'),
                Piece(direction, hold, -peak, -peak, 'arc'),
                Piece(direction, 2.0 * ramp, -peak, peak, 'ramp'),
                Piece(direction, hold, peak, peak, 'arc'),
                Piece(direction, ramp, peak, 0.0, 'ramp'))

    def shape(self, size: float, direction: int) -> ManoeuvreShape:
        """Return X, Y and the extents from postures sampled every :data:`FINE_STEP`."""
        motion = sample_pieces(np.zeros(3), self.pieces(size, direction), self.vehicle.h1,
                               FINE_STEP)
        end = motion.postures[-1]
        return ManoeuvreShape(float(-end[1]), float(abs(end[0])),
                              sampled_extents(motion.postures, self.vehicle.footprint))

    def size_for_shift(self, lateral: float) -> float:
        """Return the size whose shift is ``lateral`` [m], by bisection (X grows with u)."""
        target = finite_real('lateral', lateral)
        if target <= 0.0:
            return 0.0
        if self.shape(self.max_size, 1).lateral <= target:
            return self.max_size
        lo, hi = 0.0, self.max_size
        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if self.shape(mid, 1).lateral < target:
                lo = mid
            else:
                hi = mid
            if hi - lo < 1e-9:
                break
        return hi

    def with_steering(self, steering: float) -> 'ProgressiveMode':
        """Return the mode with the largest steering ``steering`` [rad]."""
        return replace(self, steering=steering)


def make_mode(name: str, vehicle: ParkingVehicle, steering: float,
              steering_per_metre: float) -> ExecutionMode:
    """
    Return the execution mode named ``name``: 'geometric' or 'progressive'.

    >>> make_mode('geometric', ParkingVehicle(), 0.6, 1.0).stops_between_arcs
    True
    """
    if name == 'geometric':
        return GeometricMode(vehicle, steering)
    if name == 'progressive':
        return ProgressiveMode(vehicle, steering, steering_per_metre)
    raise ValueError(f"mode must be 'geometric' or 'progressive', got {name!r}")
