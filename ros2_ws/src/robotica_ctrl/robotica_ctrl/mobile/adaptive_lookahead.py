"""
Adaptive look-ahead distance for pure pursuit (book §9.3.1, Ejemplo 9.1-9.2).

The book shows that the look-ahead L of pure pursuit is a gain, 2/L² on the lateral offset
(9.5): a small L tracks closely but oscillates, a large L converges slowly and cuts corners
(Ejemplo 9.1); on the Romeo 4R a larger L improved the start from an offset but degraded the
later tracking, and the best results came from adjusting L automatically as a function of the
current error and the path curvature (Ejemplo 9.2, Ollero et al. 1994); at high speed (trucks
at up to 100 km/h) L must grow with the speed. Three rules, each a small free function in the
style of Nav2's Regulated Pure Pursuit (``lookahead_time``, ``min_lookahead_dist``,
``max_lookahead_dist``), all clamped to [minimum, maximum]:

* speed: L = gain |v| (gain [s], a look-ahead time), so the goal is a fixed time ahead;
* curvature: L = gain / |κ| (gain dimensionless, a fraction of the turning radius), so
  L shrinks on tight bends where a long chord cuts the corner; maximum on a straight;
* error: L = minimum + gain |e| (gain dimensionless), long while far from the path for a
  smooth approach, short once on it for close tracking.

:class:`AdaptivePurePursuit` wraps :class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`
and sets its ``lookahead_distance`` before each update. Its gains, as the ``path_tracker``
node names them, are those of pure pursuit but ``lookahead_distance``, and the rule's
``rule``, ``gain``, ``min_lookahead``, ``max_lookahead`` and ``curvature_spacing``
(:func:`adaptive_params`). Frames are REP-103.
"""

from dataclasses import dataclass, replace
import math
from typing import Any, Mapping

from numpy.typing import ArrayLike

from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_ctrl.mobile.quintic_tracker import path_curvature
from robotica_ctrl.mobile.tracker_base import check_pose, replace_gains, TrackerOutput

__all__ = [
    'AdaptivePurePursuit', 'LOOKAHEAD_RULES', 'LookaheadRule', 'adaptive_params',
    'lookahead_by_curvature', 'lookahead_by_error', 'lookahead_by_speed',
]

LOOKAHEAD_RULES = ('speed', 'curvature', 'error')


def _check(value: float, gain: float, minimum: float, maximum: float) -> None:
    """Raise ValueError unless all are finite, gain >= 0 and 0 < minimum <= maximum."""
    if not all(math.isfinite(v) for v in (value, gain, minimum, maximum)):
        raise ValueError(f'need finite values, got {(value, gain, minimum, maximum)!r}')
    if gain < 0.0:
        raise ValueError(f'gain must be >= 0, got {gain!r}')
    if not 0.0 < minimum <= maximum:
        raise ValueError(f'need 0 < minimum <= maximum [m], got {minimum!r}, {maximum!r}')


def lookahead_by_speed(v: float, gain: float, minimum: float, maximum: float) -> float:
    """
    Return L = clamp(gain |v|, minimum, maximum) [m]: the goal a fixed time ahead.

    Parameters
    ----------
    v : float
        Forward speed [m/s] (its magnitude is used).
    gain : float
        Look-ahead time [s], >= 0.
    minimum, maximum : float
        Bounds of L [m], 0 < minimum <= maximum.

    Raises
    ------
    ValueError
        If a value is not finite, gain < 0 or the bounds are not 0 < minimum <= maximum.

    >>> lookahead_by_speed(2.0, 1.5, 0.3, 5.0)
    3.0

    """
    _check(v, gain, minimum, maximum)
    return min(max(gain * abs(v), minimum), maximum)


def lookahead_by_curvature(c: float, gain: float, minimum: float, maximum: float) -> float:
    """
    Return L = clamp(gain / |c|, minimum, maximum) [m]: a fraction of the turning radius.

    Parameters
    ----------
    c : float
        Path curvature [1/m] near the vehicle (its magnitude is used); 0 gives ``maximum``.
    gain : float
        Fraction of the radius 1/|c|, >= 0 (dimensionless).
    minimum, maximum : float
        Bounds of L [m], 0 < minimum <= maximum.

    Raises
    ------
    ValueError
        If a value is not finite, gain < 0 or the bounds are not 0 < minimum <= maximum.

    >>> lookahead_by_curvature(0.5, 0.4, 0.3, 5.0)
    0.8

    """
    _check(c, gain, minimum, maximum)
    if gain >= maximum * abs(c):  # gain / |c| >= maximum, also for c = 0
        return maximum
    return max(gain / abs(c), minimum)


def lookahead_by_error(cross_track: float, gain: float, minimum: float,
                       maximum: float) -> float:
    """
    Return L = clamp(minimum + gain |e|, minimum, maximum) [m]: longer when far off the path.

    Parameters
    ----------
    cross_track : float
        Lateral offset e from the path [m] (its magnitude is used).
    gain : float
        Metres of look-ahead per metre of offset, >= 0 (dimensionless).
    minimum, maximum : float
        Bounds of L [m], 0 < minimum <= maximum.

    Raises
    ------
    ValueError
        If a value is not finite, gain < 0 or the bounds are not 0 < minimum <= maximum.

    >>> lookahead_by_error(-0.5, 2.0, 0.5, 5.0)
    1.5

    """
    _check(cross_track, gain, minimum, maximum)
    return min(minimum + gain * abs(cross_track), maximum)


@dataclass(frozen=True)
class LookaheadRule:
    """
    Which rule sets L, and its gain and bounds (see the module notes).

    Attributes
    ----------
    kind : str
        One of ``LOOKAHEAD_RULES``: 'speed', 'curvature' or 'error'.
    gain : float
        [s] for 'speed', dimensionless otherwise; >= 0.
    minimum, maximum : float
        Bounds of L [m], 0 < minimum <= maximum.
    curvature_spacing : float
        Spacing [m] of the three path points of the curvature estimate ('curvature' only).

    Raises
    ------
    ValueError
        If ``kind`` is unknown or a value is out of range.

    >>> LookaheadRule('error', 2.0, 0.5, 3.0).lookahead(1.0)
    2.5

    """

    kind: str = 'speed'
    gain: float = 1.0
    minimum: float = 0.3
    maximum: float = 3.0
    curvature_spacing: float = 0.2

    def __post_init__(self) -> None:
        if self.kind not in LOOKAHEAD_RULES:
            raise ValueError(f'kind must be one of {LOOKAHEAD_RULES}, got {self.kind!r}')
        _check(0.0, self.gain, self.minimum, self.maximum)
        if not (math.isfinite(self.curvature_spacing) and self.curvature_spacing > 0.0):
            raise ValueError(
                f'curvature_spacing must be positive and finite, got {self.curvature_spacing!r}')

    def lookahead(self, value: float) -> float:
        """Return L [m] for ``value``: speed [m/s], curvature [1/m] or cross-track [m]."""
        rule = {'speed': lookahead_by_speed, 'curvature': lookahead_by_curvature,
                'error': lookahead_by_error}[self.kind]
        return rule(value, self.gain, self.minimum, self.maximum)


_RULE_GAINS = {'rule': 'kind', 'gain': 'gain', 'min_lookahead': 'minimum',
               'max_lookahead': 'maximum', 'curvature_spacing': 'curvature_spacing'}


def adaptive_params(gains: Mapping[str, Any], params: PurePursuitParams | None = None,
                    rule: LookaheadRule | None = None
                    ) -> tuple[PurePursuitParams, LookaheadRule]:
    """
    Return ``params`` and ``rule`` (the defaults if None) with adaptive pure pursuit's gains.

    ``rule``, ``gain``, ``min_lookahead``, ``max_lookahead`` and ``curvature_spacing`` go to
    the :class:`LookaheadRule` (fields ``kind``, ``gain``, ``minimum``, ``maximum``,
    ``curvature_spacing``), the others to :class:`PurePursuitParams`, whose
    ``lookahead_distance`` becomes the rule's minimum (each update overwrites it).

    Raises
    ------
    ValueError
        For an unknown name or a value the dataclasses refuse.

    >>> params, rule = adaptive_params({'rule': 'error', 'min_lookahead': 0.4})
    >>> rule.kind, params.lookahead_distance
    ('error', 0.4)

    """
    rule = replace(LookaheadRule() if rule is None else rule,
                   **{_RULE_GAINS[name]: value for name, value in gains.items()
                      if name in _RULE_GAINS})
    others = {name: value for name, value in gains.items() if name not in _RULE_GAINS}
    return replace_gains(PurePursuitParams() if params is None else params,
                         {**others, 'lookahead_distance': rule.minimum}), rule


class AdaptivePurePursuit:
    """
    Pure pursuit whose look-ahead follows a :class:`LookaheadRule` (book §9.3.1).

    Each :meth:`update` computes the rule's input (the speed: the measured one if given,
    else the last commanded one, the desired speed at first; the path curvature at the
    vehicle's projection; or its cross-track error), sets ``lookahead_distance`` of the
    wrapped :class:`PurePursuit` with ``set_params`` and returns its command.

    Parameters
    ----------
    path : PolylinePath
        Reference path, in the frame of the poses.
    params : PurePursuitParams
        Tunables of the wrapped tracker; its ``lookahead_distance`` is overwritten.
    rule : LookaheadRule
        Rule, gain and bounds of L.

    Examples
    --------
    >>> tracker = AdaptivePurePursuit(PolylinePath([[0.0, 0.0], [9.0, 0.0]]),
    ...                               PurePursuitParams(), LookaheadRule('error', 2.0, 0.5, 3.0))
    >>> out = tracker.update([0.0, 0.5, 0.0], 0.0)
    >>> tracker.lookahead_distance, out.target_point
    (1.5, array([1.5, 0. ]))

    """

    def __init__(self, path: PolylinePath, params: PurePursuitParams,
                 rule: LookaheadRule) -> None:
        self._tracker = PurePursuit(path, params)
        self._rule = rule
        self._speed = params.desired_linear_velocity

    @property
    def tracker(self) -> PurePursuit:
        """Return the wrapped pure-pursuit tracker."""
        return self._tracker

    @property
    def rule(self) -> LookaheadRule:
        """Return the look-ahead rule."""
        return self._rule

    @property
    def lookahead_distance(self) -> float:
        """Return the look-ahead L [m] used by the last update."""
        return self._tracker.params.lookahead_distance

    def set_params(self, params: PurePursuitParams, rule: LookaheadRule) -> None:
        """Use ``params`` and ``rule`` from the next :meth:`update` on; the progress is kept."""
        self._tracker.set_params(params)
        self._rule = rule

    def set_gains(self, gains: Mapping[str, Any]) -> None:
        """Replace some gains (:func:`adaptive_params`); ValueError keeps the old."""
        self.set_params(*adaptive_params(gains, self._tracker.params, self._rule))

    def reset(self) -> None:
        """Restart the wrapped tracker from the beginning of the path."""
        self._tracker.reset()
        self._speed = self._tracker.params.desired_linear_velocity

    def update(self, pose: ArrayLike, time: float, speed: float | None = None) -> TrackerOutput:
        """
        Set L by the rule, then return the wrapped tracker's output for ``pose``.

        Parameters
        ----------
        pose : array_like, shape (3,)
            Vehicle pose (x [m], y [m], θ [rad]) in the path frame.
        time : float
            Time of the pose [s]; not used.
        speed : float, optional
            Measured forward speed [m/s] for the 'speed' rule; the last command when omitted.

        Returns
        -------
        TrackerOutput
            As :meth:`PurePursuit.update`.

        Raises
        ------
        ValueError
            If ``pose`` is not a finite (3,) vector or ``speed`` is not finite.

        """
        x = check_pose(pose)
        if speed is not None and not math.isfinite(speed):
            raise ValueError(f'speed must be finite, got {speed!r}')
        tracker = self._tracker
        params = tracker.params
        rule = self._rule
        if rule.kind == 'speed':
            value = self._speed if speed is None else float(speed)
        else:
            projection = tracker.path.project(x[:2], s_hint=tracker.progress,
                                              window=params.search_window)
            if rule.kind == 'curvature':
                value = path_curvature(tracker.path, projection.s, rule.curvature_spacing)
            else:
                value = projection.cross_track
        tracker.set_params(replace(params, lookahead_distance=rule.lookahead(value)))
        output = tracker.update(x, time)
        self._speed = output.linear
        return output
