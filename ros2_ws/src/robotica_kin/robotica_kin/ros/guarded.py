"""
The guard every robotica node runs under: a bad message costs that message, never the node.

:class:`GuardedNode` is the base class of every node in ``nodes/``. By construction:

* each subscription, timer and service callback runs inside a guard: an exception raised in it
  (a refused input, a value out of the physical bounds of :mod:`robotica_kin.bounds`, a
  non-finite output, a bug) is caught and logged as one line naming the topic (or timer,
  service) and the reason, at most once per ``ERROR_LOG_PERIOD`` per source (with the count of
  those not logged in between); the message is dropped, :meth:`GuardedNode.on_callback_error`
  issues the node's safe output (a simulator brakes, a tracker commands a stop, a joint
  controller does not answer, which brakes the arm simulator on its stale command), unless the
  subscription was created with ``safe_output=False`` (an input that only observes, such as the
  followed topics of a lockstep simulator), and the node keeps running. A service answers with its
  default (empty, unsuccessful) response.
* the ``/clock`` of a node on simulated time (``use_sim_time``) passes a
  :class:`~robotica_kin.bounds.StampGate`: a tick more than ``MAX_TIME_JUMP`` from the node's
  time, or malformed (``nanosec`` >= 1e9, negative), is refused and the time stays where it was
  (one tick of 2**31 - 1 s moved every timer and every receive time of a recorder by 68 years).
* each publisher is a :class:`GuardedPublisher`: a message with a non-finite float (``inf``
  anywhere; NaN outside the fields the node declares as "not known") is not published, and
  :class:`NonFiniteOutput` is raised instead, so that inside a callback the guard logs it and
  issues the safe output; so is one whose header stamp is malformed (``nanosec`` >= 1e9: a node
  that passes on the stamp of its input would pass on a hostile one); after shutdown (the
  context invalid, e.g. on SIGINT while a loop still publishes) a publish does nothing instead
  of raising.

Configuration errors at start-up are not the guard's: the node's constructor raises
``ValueError`` and :func:`robotica_kin.ros.entry_point.run_node` exits 2 with one line.
"""
import importlib
import math
from operator import attrgetter
import time
from typing import Any, Callable, Iterable, NamedTuple

import numpy as np
from rclpy._rclpy_pybind11 import RCLError
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.time_source import TimeSource
from robotica_kin.bounds import StampGate
from robotica_kin.ros.convert import stamp_to_seconds

__all__ = ['ERROR_LOG_PERIOD', 'ERROR_TEXT_LIMIT', 'GuardedNode', 'GuardedPublisher',
           'NonFiniteOutput', 'error_text', 'non_finite_fields']

ERROR_LOG_PERIOD = 1.0   # [s, wall clock] at most one log line per source and period
ERROR_TEXT_LIMIT = 500   # characters of an error's text in a log line or a response

_FLOATS = ('float', 'double')


def error_text(err: BaseException) -> str:
    """
    Return the text of ``err``, cut to ``ERROR_TEXT_LIMIT`` characters.

    An error may quote the input it refuses: a request of a million values once put 5 MB into
    one log line and its response.

    >>> text = error_text(ValueError('got ' + str([1.0] * 10 ** 6)))
    >>> len(text), text[-24:]
    (524, '... (5000004 characters)')
    """
    text = str(err)
    return text if len(text) <= ERROR_TEXT_LIMIT else (
        f'{text[:ERROR_TEXT_LIMIT]}... ({len(text)} characters)')


class NonFiniteOutput(ValueError):
    """A message to publish holds a non-finite number; it was not published."""


class _Plan(NamedTuple):
    """Where the floats of a message type are: dotted paths and one C getter for each kind."""

    scalars: tuple[str, ...]
    arrays: tuple[str, ...]
    sequences: tuple[tuple[str, type], ...]   # sequences of messages: (path, element type)
    get_scalars: Callable[[Any], tuple]
    get_arrays: Callable[[Any], tuple]


_plans: dict[type, _Plan] = {}


def _getter(paths: list[str]) -> Callable[[Any], tuple]:
    if not paths:
        return lambda msg: ()
    get = attrgetter(*paths)
    return get if len(paths) > 1 else (lambda msg: (get(msg),))


def _paths(msg_type: type, prefix: str, plan: tuple[list, list, list]) -> None:
    scalars, arrays, sequences = plan
    for name, kind in msg_type.get_fields_and_field_types().items():
        sequence = kind.startswith('sequence<') or kind.endswith(']')
        base = kind.removeprefix('sequence<').split('[')[0].split(',')[0].rstrip('>')
        path = prefix + name
        if base in _FLOATS:
            (arrays if sequence else scalars).append(path)
        elif '/' in base:
            sub = _message_type(base)
            if sequence:
                sequences.append((path, sub))
            else:
                _paths(sub, path + '.', plan)


def _message_type(name: str) -> type:
    package, _, message = name.partition('/')
    return getattr(importlib.import_module(f'{package}.msg'), message)


def _plan(msg_type: type) -> _Plan:
    plan = _plans.get(msg_type)
    if plan is None:
        scalars: list[str] = []
        arrays: list[str] = []
        sequences: list[tuple[str, type]] = []
        _paths(msg_type, '', (scalars, arrays, sequences))
        plan = _Plan(tuple(scalars), tuple(arrays), tuple(sequences), _getter(scalars),
                     _getter(arrays))
        _plans[msg_type] = plan
    return plan


def non_finite_fields(msg: Any, allow_nan: Iterable[str] = (), prefix: str = '',
                      allow_inf: Iterable[str] = ()) -> list[str]:
    """
    Return the dotted names of the fields of ``msg`` that hold a non-finite float.

    A field named in ``allow_nan`` (dotted, e.g. ``velocity``) may hold NaN ("not known"), one
    named in ``allow_inf`` may hold ±inf (REP-117's ``ranges``: +inf no return, -inf too
    close); any other non-finite value is named.
    """
    plan = _plan(type(msg))
    bad: list[str] = []
    scalars = plan.get_scalars(msg)
    arrays = [np.asarray(a, dtype=np.float64) for a in plan.get_arrays(msg)]
    if not (all(map(math.isfinite, scalars)) and all(np.isfinite(a).all() for a in arrays)):
        nan_ok, inf_ok = set(allow_nan), set(allow_inf)
        for path, values in [*zip(plan.scalars, scalars), *zip(plan.arrays, arrays)]:
            refused = ~np.isfinite(values)
            if prefix + path in nan_ok:
                refused &= ~np.isnan(values)
            if prefix + path in inf_ok:
                refused &= ~np.isinf(values)
            if np.any(refused):
                bad.append(prefix + path)
    for path, _ in plan.sequences:
        for i, item in enumerate(attrgetter(path)(msg)):
            bad += non_finite_fields(item, allow_nan, f'{prefix}{path}[{i}].', allow_inf)
    return bad


class GuardedPublisher(Publisher):
    """A publisher that refuses non-finite messages and is silent after shutdown."""

    allow_nan: frozenset[str] = frozenset()
    allow_inf: frozenset[str] = frozenset()
    context: Any = None

    def publish(self, msg: Any) -> None:
        """
        Publish ``msg`` unless it holds a non-finite float (then raise NonFiniteOutput).

        A header stamp with ``nanosec`` >= 1e9 is refused too (ValueError).

        After shutdown (the node's context no longer valid) nothing is published or raised.
        """
        if not isinstance(msg, bytes):
            bad = non_finite_fields(msg, self.allow_nan, allow_inf=self.allow_inf)
            if bad:
                raise NonFiniteOutput(f'non-finite {", ".join(bad)} on {self.topic_name}: '
                                      'not published')
            header = getattr(msg, 'header', None)
            if header is not None:
                stamp_to_seconds(header.stamp)   # ValueError for a malformed one
        if self.context is not None and not self.context.ok():
            return
        try:
            super().publish(msg)
        except RCLError:
            if self.context is None or self.context.ok():
                raise


def _gated_clock(clock_callback: Callable[[Any], None]) -> Callable[[Any], None]:
    """Return rclpy's ``/clock`` callback behind a StampGate (ValueError: tick refused)."""
    gate = StampGate()

    def gated(msg: Any) -> None:
        t = stamp_to_seconds(msg.clock)
        if t < 0.0:
            raise ValueError(f'clock {t!r} s is negative')
        gate.check(t)
        clock_callback(msg)
    return gated


class GuardedNode(Node):
    """A node whose callbacks are guarded and whose publishers are :class:`GuardedPublisher`."""

    def __init__(self, node_name: str, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)   # its /parameter_events publisher: rclpy's own
        self._guard_log: dict[str, tuple[float, int]] = {}   # source -> (last logged, dropped)
        self.callback_errors = 0

    # -- what a node provides ----------------------------------------------------------------
    def on_callback_error(self, source: str) -> None:
        """Issue the node's safe output after a callback on ``source`` failed (default: none)."""

    # -- the guard ---------------------------------------------------------------------------
    def _guard(self, source: str, callback: Callable[..., Any],
               fallback: Callable[..., Any] | None = None,
               safe_output: bool = True) -> Callable[..., Any]:
        def guarded(*args: Any) -> Any:
            try:
                return callback(*args)
            except Exception as err:   # noqa: B902 - the guard's purpose: any error, one message
                if not self.context.ok():   # shutting down (SIGINT, SIGTERM): its logger and
                    return None             # publishers are gone, and there is nothing to save
                self._callback_failed(source, err, safe_output)
                return fallback(*args) if fallback is not None else None
        return guarded

    def _callback_failed(self, source: str, err: Exception, safe_output: bool = True) -> None:
        self.callback_errors += 1
        now = time.monotonic()
        last, dropped = self._guard_log.get(source, (-math.inf, 0))
        if now - last >= ERROR_LOG_PERIOD:
            more = f' ({dropped} more since the last report)' if dropped else ''
            self.get_logger().error(f'{source}: {type(err).__name__}: {error_text(err)}; '
                                    f'message dropped{more}')
            self._guard_log[source] = (now, 0)
        else:
            self._guard_log[source] = (last, dropped + 1)
        if not safe_output:
            return
        try:
            self.on_callback_error(source)
        except Exception as safe_err:   # noqa: B902 - the safe output must not kill the node
            self.get_logger().error(f'{source}: safe output failed: {error_text(safe_err)}',
                                    throttle_duration_sec=ERROR_LOG_PERIOD)

    # -- guarded construction ----------------------------------------------------------------
    def create_subscription(self, msg_type, topic, callback, qos_profile, *,  # noqa: D417
                            safe_output: bool = True, **kwargs):
        """
        Create a subscription whose callback is guarded.

        ``safe_output=False``: a message refused on this topic does not issue the safe output.
        """
        if getattr(callback, '__func__', None) is TimeSource.clock_callback:
            callback, safe_output = _gated_clock(callback), False
        return super().create_subscription(
            msg_type, topic, self._guard(topic, callback, safe_output=safe_output), qos_profile,
            **kwargs)

    def create_timer(self, timer_period_sec, callback, *args, **kwargs):  # noqa: D102
        name = getattr(callback, '__name__', 'callback')
        return super().create_timer(timer_period_sec, self._guard(f'timer {name}', callback),
                                    *args, **kwargs)

    def create_service(self, srv_type, srv_name, callback, **kwargs):  # noqa: D102
        return super().create_service(
            srv_type, srv_name,
            self._guard(f'service {srv_name}', callback, lambda request, response: response),
            **kwargs)

    def create_publisher(self, msg_type, topic, qos_profile, *,  # noqa: D417
                         allow_nan: Iterable[str] = (), allow_inf: Iterable[str] = (),
                         **kwargs):
        """
        Create a :class:`GuardedPublisher`.

        ``allow_nan``: the dotted fields where NaN means "not known" and may be published;
        ``allow_inf``: those where ±inf has a documented meaning (REP-117 ranges).
        """
        if not hasattr(self, '_guard_log'):   # Node.__init__: parameter events carry inf
            return super().create_publisher(msg_type, topic, qos_profile, **kwargs)
        publisher = super().create_publisher(msg_type, topic, qos_profile,
                                             publisher_class=GuardedPublisher, **kwargs)
        publisher.allow_nan = frozenset(allow_nan)
        publisher.allow_inf = frozenset(allow_inf)
        publisher.context = self.context
        return publisher
