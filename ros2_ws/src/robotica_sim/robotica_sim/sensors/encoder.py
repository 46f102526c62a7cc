"""
Incremental wheel-encoder model: wheel angle -> cumulative tick count.

Book §7.3.2 and the course slides (Part 13.6 of the seed catalogue): a counter of an
incremental encoder with ``ticks_per_revolution`` counts per wheel revolution (pulses per
revolution x quadrature decoding x gear ratio) changes by one count every
2 pi / ticks_per_revolution rad; the reading is the floor of the angle in counts, as a real
up/down counter reads at any instant between two edges.

:class:`EncoderModel` adds the encoder's parameters (catalogue Part 15: PPR, x1/x2/x4
decoding, gear ratio n between motor and wheel) and missed counts: each edge crossed is lost
with probability p (the decoder missed it, e.g. at a high pulse rate), and a lost count stays
lost, so the counter lags the true count for good. Wheel-radius and track errors are not here:
they are a mismatch between the true vehicle and the odometry's nominal geometry.
"""
from dataclasses import dataclass
import math
import numbers

from typing import Any, Mapping

import numpy as np
from robotica_kin.parameter_specs import parameter_values, ParameterSpec, seed_spec

__all__ = ['DECODINGS', 'ENCODER_PARAMETERS', 'EncoderModel', 'EncoderParams', 'encoder_params',
           'quantize_ticks']

DECODINGS = (1, 2, 4)
"""Quadrature decodings: counts per pulse of one channel (x1, x2, x4), book §7.3.2."""

_INTEGER_TOLERANCE = 1e-9  # relative: PPR x decoding x gear ratio must be this close to integer


def quantize_ticks(wheel_angle: float, ticks_per_revolution: int) -> int:
    """
    Return the cumulative count [ticks] of an encoder on a wheel at ``wheel_angle`` [rad].

    Raises ValueError for a non-finite angle or ticks_per_revolution < 1.

    >>> quantize_ticks(math.pi, 1024)
    512
    >>> quantize_ticks(-1e-9, 1024)
    -1
    """
    if ticks_per_revolution < 1:
        raise ValueError(f'ticks_per_revolution must be >= 1, got {ticks_per_revolution!r}')
    if not math.isfinite(wheel_angle):
        raise ValueError(f'wheel angle must be finite, got {wheel_angle!r}')
    return math.floor(wheel_angle * ticks_per_revolution / (2.0 * math.pi))


@dataclass(frozen=True)
class EncoderParams:
    """
    An incremental encoder on a wheel (catalogue Part 15, incremental-encoder row).

    ``ticks_per_revolution`` = PPR x decoding x gear ratio must be an integer >= 1 (to a
    relative 1e-9); x4 decoding of PPR pulses gives the slides' resolution 360°/(4 PPR) at the
    motor. Raises ValueError for a PPR that is not an integer >= 1, a decoding not in
    :data:`DECODINGS`, a gear ratio that is not finite and > 0, a probability outside [0, 1] or
    a non-integer ticks_per_revolution.

    >>> EncoderParams(pulses_per_revolution=500, decoding=4, gear_ratio=1.5).ticks_per_revolution
    3000
    """

    pulses_per_revolution: int = 500       # PPR: pulses of one channel per motor revolution
    decoding: int = 4                      # counts per pulse: 1, 2 or 4 (x1/x2/x4 quadrature)
    gear_ratio: float = 1.0                # n: motor (encoder) revolutions per wheel revolution
    missed_count_probability: float = 0.0  # p: probability that an edge is not counted

    def __post_init__(self) -> None:
        ppr = self.pulses_per_revolution
        if isinstance(ppr, bool) or not isinstance(ppr, numbers.Integral) or ppr < 1:
            raise ValueError(f'pulses_per_revolution must be an integer >= 1, got {ppr!r}')
        if isinstance(self.decoding, bool) or self.decoding not in DECODINGS:
            raise ValueError(f'decoding must be one of {DECODINGS}, got {self.decoding!r}')
        if not (math.isfinite(self.gear_ratio) and self.gear_ratio > 0.0):
            raise ValueError(f'gear_ratio must be finite and > 0, got {self.gear_ratio!r}')
        p = self.missed_count_probability
        if not (0.0 <= p <= 1.0):
            raise ValueError(f'missed_count_probability must be in [0, 1], got {p!r}')
        exact = ppr * self.decoding * self.gear_ratio
        if round(exact) < 1 or abs(exact - round(exact)) > _INTEGER_TOLERANCE * exact:
            raise ValueError('pulses_per_revolution x decoding x gear_ratio must be an integer '
                             f'>= 1, got {ppr} x {self.decoding} x {self.gear_ratio!r} '
                             f'= {exact!r}')

    @property
    def ticks_per_revolution(self) -> int:
        """Return the counts per wheel revolution N = PPR x decoding x gear ratio."""
        return int(round(self.pulses_per_revolution * self.decoding * self.gear_ratio))


class EncoderModel:
    """
    The up/down counter of one wheel's encoder, with missed counts.

    :meth:`ticks` is called with the cumulative wheel angle; the counter starts at 0 at angle
    0. Between two calls the wheel is taken to move monotonically, so the edges crossed are the
    difference of the ideal counts (:func:`quantize_ticks`); the number missed is drawn from a
    binomial distribution (edges, p) and accumulates, signed, in :attr:`missed`: the reading is
    the ideal count minus the missed ones (it lags the true count in either direction).

    Parameters
    ----------
    params : EncoderParams
        The encoder.
    seed : int or numpy.random.Generator
        Seed of the model's generator, or a generator to draw from (then shared).

    Examples
    --------
    >>> encoder = EncoderModel(EncoderParams(pulses_per_revolution=500, decoding=4), seed=0)
    >>> encoder.ticks(1.0)   # 2000 counts per revolution: floor(2000 / (2 pi)) = 318
    318
    >>> encoder.ticks(-1e-9)
    -1

    """

    def __init__(self, params: EncoderParams, seed: int | np.random.Generator) -> None:
        if not isinstance(params, EncoderParams):
            raise ValueError(f'params must be EncoderParams, got {type(params).__name__}')
        self._params = params
        self._ticks_per_revolution = params.ticks_per_revolution
        self._rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self._ideal = 0
        self._missed = 0

    @property
    def params(self) -> EncoderParams:
        """Return the encoder parameters."""
        return self._params

    @property
    def missed(self) -> int:
        """Return the net missed counts so far [ticks] (ideal count minus reading)."""
        return self._missed

    def reset(self) -> None:
        """Zero the counter at wheel angle 0 and forget the missed counts."""
        self._ideal = 0
        self._missed = 0

    def ticks(self, wheel_angle: float) -> int:
        """
        Return the counter's reading [ticks] with the wheel at ``wheel_angle`` [rad].

        Raises ValueError for a non-finite angle.
        """
        ideal = quantize_ticks(wheel_angle, self._ticks_per_revolution)
        edges = ideal - self._ideal
        p = self._params.missed_count_probability
        if edges != 0 and p > 0.0:
            lost = int(self._rng.binomial(abs(edges), p))
            self._missed += lost if edges > 0 else -lost
        self._ideal = ideal
        return ideal - self._missed


ENCODER_PARAMETERS: dict[str, ParameterSpec] = {
    'pulses_per_revolution': ParameterSpec(1024, 'Pulses of one channel per encoder (motor) '
                                           'revolution, book §7.3.2', 1, 10_000_000),
    'decoding': ParameterSpec(4, 'Quadrature decoding: 1, 2 or 4 counts per pulse', 1, 4),
    'gear_ratio': ParameterSpec(1.0, 'Encoder revolutions per wheel revolution (the encoder on '
                                'the motor shaft)', 1e-3, 1e4),
    'missed_count_probability': ParameterSpec(0.0, 'Probability that an edge is not counted',
                                              0.0, 0.5),
    'seed': seed_spec('Seed of the missed-count draws'),
}
"""The encoder emulator node's parameters by name: :func:`encoder_params`."""


def encoder_params(parameters: Mapping[str, Any]) -> EncoderParams:
    """
    Return the encoder of the emulator node's ``parameters`` (names of ENCODER_PARAMETERS).

    Missing names take their defaults, others are ignored. Raises
    :class:`~robotica_kin.parameter_specs.ParameterError` for a value out of its range and
    ValueError as :class:`EncoderParams` (e.g. a count per revolution that is not an integer).

    >>> encoder_params({'pulses_per_revolution': 500}).ticks_per_revolution
    2000
    """
    values = parameter_values(ENCODER_PARAMETERS, parameters)
    return EncoderParams(**{name: values[name] for name in (
        'pulses_per_revolution', 'decoding', 'gear_ratio', 'missed_count_probability')})
