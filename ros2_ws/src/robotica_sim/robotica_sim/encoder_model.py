"""
Incremental wheel-encoder model: wheel angle -> cumulative tick count.

Book §7.3.2 and the course slides (Part 13.6 of the seed catalogue): a counter of an
incremental encoder with ``ticks_per_revolution`` counts per wheel revolution (pulses per
revolution x quadrature decoding x gear ratio) changes by one count every
2 pi / ticks_per_revolution rad; the reading is the floor of the angle in counts, as a real
up/down counter reads at any instant between two edges.
"""
import math


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
