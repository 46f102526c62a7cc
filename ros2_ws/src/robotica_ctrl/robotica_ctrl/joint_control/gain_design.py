"""
Gain design of computed-torque control against a model's mass error (book §8.3.3, Ej. 8.6).

One link of length l with a point mass m at its end (the camera arm of Ej. 8.6), controlled by
computed torque (8.54) with a model mass m̂ (μ = m − m̂, (8.58)): the error obeys
e'' + K_v e' + K_p e = (μ / m̂) θ'' + (μ / (m̂ l)) g cos θ (8.60), so at rest it settles to
e = μ g cos θ / (K_p m̂ l) (8.61)-(8.63), largest at θ = nπ: ē = μ g / (K_p m̂ l) (8.64). The tool
then misses its place by the chord Δs = √2 l √(1 − cos Δθ) (8.65)-(8.70); the gain that keeps
the largest chord below Δs̄ is K_p = μ g / (m̂ l arccos(1 − Δs̄² / (2 l²))) (8.73). SI units,
angles in radians.
"""
import math

from robotica_kin.finite import finite_real

__all__ = ['GRAVITY', 'chord_error', 'max_steady_state_error', 'proportional_gain_for_chord',
           'steady_state_error']

GRAVITY = 9.8   # [m/s^2] the book's g in Ej. 8.6


def _positive(name: str, value: float) -> float:
    v = finite_real(name, value)
    if v <= 0.0:
        raise ValueError(f'{name} must be > 0, got {value!r}')
    return v


def steady_state_error(mass_error: float, model_mass: float, length: float, kp: float,
                       theta: float = 0.0, g: float = GRAVITY) -> float:
    """
    Return the steady-state joint error e [rad] at the angle θ, (8.61)-(8.63).

    e = μ g cos θ / (K_p m̂ l); ``mass_error`` μ = m − m̂ [kg], ``model_mass`` m̂ [kg],
    ``length`` l [m], ``kp`` K_p [1/s²], ``theta`` θ [rad], ``g`` [m/s²]. ValueError for
    non-finite values or m̂, l, K_p not > 0.

    >>> round(steady_state_error(0.1, 1.0, 1.0, 9.8), 12)
    0.1
    """
    mu = finite_real('mass_error', mass_error)
    return (mu * finite_real('g', g) * math.cos(finite_real('theta', theta))
            / (_positive('kp', kp) * _positive('model_mass', model_mass)
               * _positive('length', length)))


def max_steady_state_error(mass_error: float, model_mass: float, length: float, kp: float,
                           g: float = GRAVITY) -> float:
    """
    Return the largest steady-state error ē = |μ| g / (K_p m̂ l) [rad], at θ = nπ (8.64).

    >>> round(max_steady_state_error(0.1, 1.0, 1.0, 9.8), 12)
    0.1
    """
    return abs(steady_state_error(mass_error, model_mass, length, kp, 0.0, g))


def chord_error(length: float, angle_error: float) -> float:
    """
    Return the tool's displacement Δs = √2 l √(1 − cos Δθ) [m] for a joint error Δθ (8.65)-(8.70).

    >>> round(chord_error(1.0, math.pi / 3), 12)   # the chord of 60° on a unit circle
    1.0
    """
    dtheta = finite_real('angle_error', angle_error)
    return math.sqrt(2.0) * _positive('length', length) * math.sqrt(1.0 - math.cos(dtheta))


def proportional_gain_for_chord(mass_error: float, model_mass: float, length: float,
                                max_chord: float, g: float = GRAVITY) -> float:
    """
    Return K_p = |μ| g / (m̂ l arccos(1 − Δs̄² / (2 l²))) [1/s²] (8.73).

    With that gain the largest steady-state chord error of the tool is ``max_chord`` Δs̄ [m];
    any larger gain keeps it below. ValueError for Δs̄ not in (0, 2 l] (a chord of a circle of
    radius l) or non-finite values.

    >>> round(proportional_gain_for_chord(0.1, 1.0, 1.0, 0.1), 3)   # Ej. 8.6, (8.74)
    9.796
    """
    radius = _positive('length', length)
    chord = _positive('max_chord', max_chord)
    if chord > 2.0 * radius:
        raise ValueError(f'max_chord must be at most 2 l = {2.0 * radius!r} m, got '
                         f'{max_chord!r}')
    angle = math.acos(1.0 - chord ** 2 / (2.0 * radius ** 2))   # the largest Δθ allowed
    mu = abs(finite_real('mass_error', mass_error))
    return mu * finite_real('g', g) / (_positive('model_mass', model_mass) * radius * angle)
