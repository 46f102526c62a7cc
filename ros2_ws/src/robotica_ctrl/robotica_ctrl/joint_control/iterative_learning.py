"""
Iterative learning (repetitive) control, book §8.5 (seed catalogue Part 6, §6.5; Craig 1988).

A task repeated trial after trial: the law is computed torque (8.138) with a learned term,

``tau = M̂(q) [q_d'' + K_v e' + K_p e + D̂_k(t)] + V̂(q, q') + Ĝ(q) [+ F̂(q')]``,

``e = q_d - q``, ``k`` the trial and ``t`` the time since the trial's start. The learned term is
kept in acceleration units: the book's ``γ̂_k = M̂ D̂_k``, so that per joint (8.139)-(8.141)

``e'' + K_v e' + K_p e = D - D̂_k``, ``D = M̂⁻¹ F`` (what the model misses, F, as acceleration).

Between trials the learning law (8.142) with the filter (8.150), non-causal, is applied offline to
the stored error of trial k, on the trial's own time grid:

``D̂_{k+1}(t) = D̂_k(t) + e_k''(t) + (K_v - μ) e_k'(t) + (K_p - μ) e_k(t)``.

Then ``E_{k+1}(s) = G(s) E_k(s) + ...`` with ``G(s) = μ (s + 1) / (s² + K_v s + K_p)``
(8.143)-(8.149): the learning converges when ``|G(jω)| < 1`` for every ω
(:func:`learning_gain_margin`), and the smaller that maximum, the faster. What it cannot remove
is the response to the error a trial starts with: the trials converge to the solution of
``e'' + (K_v - μ) e' + (K_p - μ) e = 0`` from that initial error, the specified response
``e'' + K_v e' + K_p e = 0`` for μ ≪ K_v, K_p (Ej. 8.9: μ = 3, K_v = 50, K_p = 625).

Implementation choices:

- trial time: ``t = 0`` at the first :meth:`~IterativeLearningControl.update` of a trial (after
  construction, :meth:`~IterativeLearningControl.end_trial`, ``reset``, ``forget`` or ``load``);
  each later update advances it by its ``dt``. The ``dt`` of a trial's first update is the gap
  since the previous trial's last state, which is not trial time;
- every update stores ``t``, ``e``, ``e'`` (from the measured ``q'``) and the ``D̂`` it applied, in
  one preallocated block that doubles when full;
- the filter is applied where the applied ``D̂`` acted: the ``D̂`` of sample ``t_j`` is held over
  ``[t_j, t_j+1]``, so ``e''`` is the difference of the stored ``e'`` across that interval over
  its length and ``e'``, ``e`` the means of its two ends (second order at the interval's middle).
  ``np.gradient``'s central difference at ``t_j`` does not see an alternating (Nyquist)
  component of ``e'``, which then grows by ``1 + (K_v - μ) h / (2 - K_v h)`` per trial (1.05 for
  Ej. 8.9 at h = 2 ms: from round-off to 0.1 rad in some 300 trials); here it shrinks by
  ``K_v h / (2 - K_v h)`` (sample period h; keep ``K_v h < 1``). A forward difference with
  ``e'``, ``e`` at ``t_j`` is stable too but biased by O(h) (6e-4 rad on Ej. 8.9's learned
  error at 2 ms, against 7e-6 here). The last sample's ``D̂`` acted after the trial's last record
  and is not learnable: it keeps the value before it (updated, it would drift without end).
  Nothing is smoothed: filter a noisy velocity before the law, or bound ``D̂`` with
  ``max_feedforward``;
- between the samples of the learned grid ``D̂`` is interpolated linearly, and it is zero outside
  the learned span (a trial longer than the last one has no feed-forward past its end);
- memory is bounded: a trial records at most ``max_samples`` samples. Past that the law keeps
  controlling (with no feed-forward beyond the learned span) but records nothing more, counts
  the samples left out in ``dropped_samples`` (the node should log it) and learns only on the
  recorded span.
"""

import bisect
from dataclasses import dataclass
import os
from typing import NamedTuple
import zipfile

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import DHModel

from .computed_torque import ComputedTorque, ComputedTorqueGains
from .law import gain_field, JointControlLaw, JointReference, JointState, per_joint

__all__ = ['DEFAULT_MAX_SAMPLES', 'IterativeLearningControl', 'LearnedFeedforward',
           'LearningGains', 'learning_gain_margin']

DEFAULT_MAX_SAMPLES = 120_000
"""Samples a trial records at most by default: 2 min at 1 kHz (18 MB for six joints)."""
_FIRST_BLOCK = 4096            # rows of the first sample block; it doubles when full
_FILE_FIELDS = ('kp', 'kv', 'mu', 'trial', 'trial_errors', 'time', 'feedforward')


@dataclass(frozen=True, eq=False)
class LearningGains:
    """
    Gains of :class:`IterativeLearningControl` (scalar or (n,)); defaults are Ej. 8.9's.

    μ is subtracted from K_v [1/s] and from K_p [1/s²] alike, as the book's filter (8.150) does;
    choose it so that ``learning_gain_margin(kp, kv, mu) < 1`` (the law refuses it otherwise).

    >>> LearningGains().mu
    array(3.)
    """

    kp: ArrayLike = 625.0                 # K_p [1/s²], (8.138); Ej. 8.9: ω_n = 25 rad/s (8.151)
    kv: ArrayLike = 50.0                  # K_v [1/s]; Ej. 8.9: critically damped, 2 ω_n
    mu: ArrayLike = 3.0                   # μ of the filter P(s) (8.150), >= 0
    max_feedforward: ArrayLike = np.inf   # bound of |D̂| [rad/s² | m/s²], > 0

    def __post_init__(self) -> None:
        for name in ('kp', 'kv', 'mu'):
            gain_field(self, name)
        gain_field(self, 'max_feedforward', positive=True, allow_inf=True)


def learning_gain_margin(kp: ArrayLike, kv: ArrayLike, mu: ArrayLike) -> NDArray[np.float64]:
    """
    Return max over ω of ``|G(jω)|``, ``G(s) = μ (s + 1) / (s² + K_v s + K_p)`` (8.147)-(8.150).

    The learning of :class:`IterativeLearningControl` converges where this is < 1 (catalogue
    §6.5: choose μ from ``|G(jω)| < 1``). In closed form: ``|G|² = μ² (1 + x) / ((K_p - x)² +
    K_v² x)`` with ``x = ω²`` peaks at ``x* = max(0, sqrt((K_p + 1)² - K_v²) - 1)``. The inputs
    broadcast against each other (per joint); the result is inf where G has a pole on the
    imaginary axis (K_p = 0, or K_v = 0) and μ > 0.

    Raises
    ------
    ValueError
        For a gain that is not a finite number >= 0, or shapes that do not broadcast.

    Examples
    --------
    Ej. 8.9 (K_p = 625, K_v = 50, μ = 3) and the appendix's PUMA (125, 50, 2):

    >>> learning_gain_margin([625.0, 125.0], 50.0, [3.0, 2.0]).round(4)
    array([0.06  , 0.0402])

    """
    arrays = []
    for name, value in (('kp', kp), ('kv', kv), ('mu', mu)):
        try:
            array = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError) as err:
            raise ValueError(f'{name} must be numbers, got {value!r}') from err
        if not (np.isfinite(array).all() and (array >= 0.0).all()):
            raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        arrays.append(array)
    try:
        p, v, m = np.broadcast_arrays(*arrays)
    except ValueError as err:
        raise ValueError(f'kp, kv and mu must broadcast, got shapes '
                         f'{[a.shape for a in arrays]}') from err
    x = np.maximum(0.0, np.sqrt(np.maximum(0.0, (p + 1.0) ** 2 - v * v)) - 1.0)
    denominator = (p - x) ** 2 + v * v * x
    with np.errstate(divide='ignore', invalid='ignore'):
        peak = m * np.sqrt((1.0 + x) / denominator)
    return np.where(m == 0.0, 0.0, peak)


class LearnedFeedforward(NamedTuple):
    """The learned term on its time grid: ``t`` (m,) [s] from a trial's start, ``d`` (m, n)."""

    t: NDArray[np.float64]   # [s] since the start of the trial, increasing
    d: NDArray[np.float64]   # D̂ [rad/s² | m/s²] per joint at each t


class IterativeLearningControl(JointControlLaw):
    """
    Computed torque with a feed-forward learned trial after trial, book (8.138)-(8.150).

    Parameters
    ----------
    model : DHModel or array_like, shape (n, 20)
        The controller's estimate of the robot's dynamics (M̂, V̂, Ĝ, F̂).
    gains : LearningGains, optional
        K_p, K_v, μ and the bound of D̂; default Ej. 8.9's (625, 50, 3, unbounded).
    grav : array_like, shape (3,), optional
        Gravity in {0} [m/s²] for Ĝ; default ``[0, 0, -9.81]`` (planar examples:
        ``[0, -9.81, 0]``).
    use_friction : bool
        Add F̂(q') of the model's ``dyn`` table (default True).
    max_samples : int
        Samples a trial records at most (>= 2); see the module notes.

    Raises
    ------
    ValueError
        For a model without dynamics, a bad ``grav``, gains of the wrong size, a μ for which the
        learning diverges (``learning_gain_margin >= 1``) or ``max_samples < 2``.

    Examples
    --------
    A trial on the reference learns nothing; the next one starts at t = 0.

    >>> from robotica_kin.robots import two_link_arm
    >>> law = IterativeLearningControl(two_link_arm(2.0, 1.0, 3.0, 1.0)[1],
    ...                                grav=[0.0, -9.81, 0.0])
    >>> for _ in range(3):
    ...     tau = law.update(JointReference([0.0, 0.0]), JointState([0.0, 0.0], [0.0, 0.0]), 0.01)
    >>> tau, law.end_trial(), law.trial
    (array([98.1 ,  9.81]), array([0., 0.]), 2)
    >>> law.learned_feedforward.d.tolist()
    [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]

    """

    def __init__(self, model: DHModel | ArrayLike, gains: LearningGains | None = None,
                 grav: ArrayLike | None = None, *, use_friction: bool = True,
                 max_samples: int = DEFAULT_MAX_SAMPLES) -> None:
        if gains is not None and not isinstance(gains, LearningGains):
            raise ValueError(f'gains must be LearningGains, got {type(gains).__name__}')
        if isinstance(max_samples, bool) or not isinstance(max_samples, (int, np.integer)) \
                or max_samples < 2:
            raise ValueError(f'max_samples must be an integer >= 2, got {max_samples!r}')
        self.gains = LearningGains() if gains is None else gains
        # The feedback part is computed torque's PD law (one RNEA); the learned term enters as
        # an extra desired acceleration.
        self._tracking = ComputedTorque(
            model, ComputedTorqueGains(kp=self.gains.kp, kv=self.gains.kv), grav,
            use_friction=use_friction)
        n = self._tracking.n
        self.model = model
        self.n = n
        self.use_friction = bool(use_friction)
        self.max_samples = int(max_samples)
        self._kp, self._kv, self._mu, self._max_feedforward = (
            per_joint(name, getattr(self.gains, name), n)
            for name in ('kp', 'kv', 'mu', 'max_feedforward'))
        margin = learning_gain_margin(self._kp, self._kv, self._mu)
        if (margin >= 1.0).any():
            raise ValueError(f'mu = {self._mu.tolist()} makes the learning diverge: max |G(jw)| '
                             f'= {margin.tolist()} must be < 1 on every joint (book (8.150))')
        self._zeros = np.zeros(n)
        self._zeros.setflags(write=False)
        # One row a sample: t, e (n), e' (n), the D̂ applied (n).
        self._samples = np.empty((min(_FIRST_BLOCK, self.max_samples), 1 + 3 * n))
        self.forget()

    # --- state -------------------------------------------------------------------------------

    def _start_trial(self) -> None:
        """Begin a trial at t = 0 with no samples (the learned term is kept)."""
        self._time = 0.0
        self._updates = 0
        self._count = 0
        self.dropped_samples = 0
        self._cursor = 0

    def _set_learning(self, t: NDArray[np.float64], d: NDArray[np.float64]) -> None:
        """Keep ``d`` (m, n) on the grid ``t`` (m,) as the learned term, bounded."""
        np.clip(d, -self._max_feedforward, self._max_feedforward, out=d)
        self._learned_t, self._learned_d = t, d
        # For update(): the grid as floats (fast comparisons) and the slope of each interval.
        self._grid: list[float] = t.tolist()
        self._slopes = np.diff(d, axis=0) / np.diff(t)[:, None]

    def reset(self) -> None:
        """Restart the current trial: clear its samples, t = 0; the learned term is kept."""
        self._start_trial()

    def forget(self) -> None:
        """Clear the learned term and the trial history too (back to trial 1)."""
        self._set_learning(np.empty(0), np.empty((0, self.n)))
        self._trial = 1
        self._errors: list[NDArray[np.float64]] = []
        self._start_trial()

    @property
    def trial(self) -> int:
        """Return the number of the current trial, counted from 1."""
        return self._trial

    @property
    def trial_errors(self) -> list[NDArray[np.float64]]:
        """Return the mean squared error (8.153) (n,) [rad²] of each finished trial, in order."""
        return [error.copy() for error in self._errors]

    @property
    def learned_feedforward(self) -> LearnedFeedforward:
        """Return a copy of the learned term D̂ and its time grid (empty before any learning)."""
        return LearnedFeedforward(self._learned_t.copy(), self._learned_d.copy())

    @property
    def samples(self) -> int:
        """Return the number of samples recorded in the current trial."""
        return self._count

    # --- control -----------------------------------------------------------------------------

    def _feedforward_at(self, t: float) -> NDArray[np.float64]:
        """Return D̂_k(t) (n,): linear between the learned samples, zero outside their span."""
        grid = self._grid
        if not grid or t > grid[-1] or t < grid[0]:
            return self._zeros
        i = self._cursor              # grid[i] <= t: t only grows within a trial
        if grid[i + 1] < t:
            i += 1                    # the usual case: one sample on
            if grid[i + 1] < t:
                i = bisect.bisect_left(grid, t) - 1
            self._cursor = i
        return self._learned_d[i] + (t - grid[i]) * self._slopes[i]

    def _record(self, t: float, e: NDArray[np.float64], ed: NDArray[np.float64],
                feedforward: NDArray[np.float64]) -> None:
        """Store one sample, growing the block (doubling, up to max_samples) when full."""
        k = self._count
        if k == len(self._samples):
            if k >= self.max_samples:
                self.dropped_samples += 1
                return
            block = np.empty((min(2 * k, self.max_samples), self._samples.shape[1]))
            block[:k] = self._samples
            self._samples = block
        n = self.n
        row = self._samples[k]
        row[0] = t
        row[1:1 + n] = e
        row[1 + n:1 + 2 * n] = ed
        row[1 + 2 * n:] = feedforward
        self._count = k + 1

    def update(self, reference: JointReference, state: JointState,
               dt: float) -> NDArray[np.float64]:
        """
        Return tau (8.138) (n,) [N m] at the trial time t; store e, e' and the D̂(t) applied.

        t = 0 at the trial's first update, then advances by ``dt`` [s] per update. ValueError
        for ``dt <= 0``, NaN, or a number of joints other than the model's (nothing stored).
        """
        n = self.check_inputs(reference, state, dt)
        if n != self.n:
            raise ValueError(f'the model has {self.n} joints, got {n}')
        if self._updates:
            self._time += float(dt)
        self._updates += 1
        feedforward = self._feedforward_at(self._time)
        self._record(self._time, reference.q_d - state.q, reference.qd_d - state.qd,
                     feedforward)
        desired = JointReference(reference.q_d, reference.qd_d, reference.qdd_d + feedforward)
        return self._tracking.update(desired, state, dt)

    # --- learning ----------------------------------------------------------------------------

    def end_trial(self) -> NDArray[np.float64]:
        """
        Learn from the trial that ends (8.142), (8.150); return its mean squared error (8.153).

        ``D̂_{k+1} = D̂_k + e'' + (K_v - μ) e' + (K_p - μ) e`` on the trial's time grid, bounded
        by ``max_feedforward``; the error is ``(1/T) ∫₀ᵀ e² dt`` per joint [rad²] by the
        trapezoid rule on the samples. The next trial starts (t = 0).

        Raises
        ------
        ValueError
            For a trial of fewer than 2 samples (nothing is changed).

        """
        count = self._count
        if count < 2:
            raise ValueError(f'a trial needs at least 2 samples to learn from, got {count}')
        n = self.n
        rows = self._samples[:count]
        t = rows[:, 0].copy()
        e, ed, applied = rows[:, 1:1 + n], rows[:, 1 + n:1 + 2 * n], rows[:, 1 + 2 * n:]
        # At the middle of each interval [t_j, t_j+1], where the D̂ of t_j was held (module notes).
        edd = np.diff(ed, axis=0) / np.diff(t)[:, None]
        learned = np.empty_like(e)
        learned[:-1] = (applied[:-1] + edd + (0.5 * (self._kv - self._mu)) * (ed[:-1] + ed[1:])
                        + (0.5 * (self._kp - self._mu)) * (e[:-1] + e[1:]))
        learned[-1] = learned[-2]
        error = np.trapezoid(e * e, t, axis=0) / (t[-1] - t[0])
        self._set_learning(t, learned)
        self._errors.append(error)
        self._trial += 1
        self._start_trial()
        return error.copy()

    # --- persistence -------------------------------------------------------------------------

    def save(self, path: str | os.PathLike[str]) -> None:
        """
        Write the learning (gains, trial index and errors, D̂ and its grid) to ``path`` (npz).

        The samples of an unfinished trial are not saved: save after :meth:`end_trial`.
        NumPy adds ``.npz`` to a name without it.
        """
        np.savez(path, kp=self._kp, kv=self._kv, mu=self._mu, trial=np.int64(self._trial),
                 trial_errors=np.array(self._errors).reshape(-1, self.n),
                 time=self._learned_t, feedforward=self._learned_d)

    def load(self, path: str | os.PathLike[str]) -> None:
        """
        Continue the learning saved by :meth:`save` in ``path``; a new trial starts (t = 0).

        Raises
        ------
        ValueError
            For a file that is not such a learning, or one of another number of joints or
            other K_p, K_v or μ (nothing is changed).
        OSError
            For a file that cannot be read.

        """
        try:
            with np.load(path, allow_pickle=False) as data:
                fields = {name: np.asarray(data[name], dtype=np.float64)
                          for name in _FILE_FIELDS}
        except (KeyError, ValueError, zipfile.BadZipFile) as err:
            raise ValueError(f'{os.fspath(path)!r} is not a saved learning ({err})') from None
        n = self.n
        if fields['kp'].shape != (n,):
            raise ValueError(f'{os.fspath(path)!r} holds a learning of '
                             f'{fields["kp"].size} joints; this law has {n}')
        for name, mine in (('kp', self._kp), ('kv', self._kv), ('mu', self._mu)):
            if not np.array_equal(fields[name], mine):
                raise ValueError(f'{os.fspath(path)!r} was learned with {name} = '
                                 f'{fields[name].tolist()}; this law has {mine.tolist()}')
        t, d, errors = fields['time'], fields['feedforward'], fields['trial_errors']
        trial = fields['trial']
        m = t.size
        if not (t.shape == (m,) and d.shape == (m, n) and (m == 0 or 2 <= m <= self.max_samples)
                and np.isfinite(t).all() and np.isfinite(d).all() and (np.diff(t) > 0.0).all()
                and trial.shape == () and np.isfinite(trial) and trial == int(trial) and trial >= 1
                and errors.shape == (int(trial) - 1, n)):
            raise ValueError(f'{os.fspath(path)!r} is not a consistent saved learning (time '
                             f'{t.shape}, feedforward {d.shape}, trial {trial.tolist()}, '
                             f'trial_errors {errors.shape}, max_samples {self.max_samples})')
        self._set_learning(t, d)
        self._trial = int(trial)
        self._errors = list(errors)
        self._start_trial()
