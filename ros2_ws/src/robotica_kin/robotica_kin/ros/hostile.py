"""
Hostile messages of any type, for the fuzz tests of the nodes (and of a user's own nodes).

:func:`hostile_message` fills every field of a message with a value drawn from what a broken or
malicious stack may send: NaN, ±inf, ±1e308, zero and ordinary numbers for floats; the extremes
of integers; absurd stamps (``sec`` = ±2**31, 0, 1e6 s away; ``nanosec`` >= 1e9, which is
malformed); empty, short (one short of a 6-joint arm) and long sequences; empty, odd and long
strings (frame ids). Seeded through the caller's ``random.Random``: a failure is replayed by its
seed.
:func:`fuzz` drives a node with them and then with valid input.
"""
import importlib
import math
import random
import time
from typing import Any, Callable

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

__all__ = ['HOSTILE_FLOATS', 'fuzz', 'hostile_message']

HOSTILE_FLOATS = (math.nan, math.inf, -math.inf, 1e308, -1e308, 1e200, -1e-300, 0.0, 1.0, -1.0)
_INTS = {'int8': (-2 ** 7, 2 ** 7 - 1), 'int16': (-2 ** 15, 2 ** 15 - 1),
         'int32': (-2 ** 31, 2 ** 31 - 1), 'int64': (-2 ** 63, 2 ** 63 - 1),
         'uint8': (0, 2 ** 8 - 1), 'uint16': (0, 2 ** 16 - 1), 'uint32': (0, 2 ** 32 - 1),
         'uint64': (0, 2 ** 64 - 1), 'octet': (0, 255), 'char': (0, 255), 'byte': (0, 255)}
_SIZES = (0, 1, 2, 3, 5, 6, 7, 100)
_SECONDS = (-2 ** 31, 2 ** 31 - 1, 0, 1, 10 ** 6)
_NANOSECONDS = (0, 999_999_999, 1_000_000_000, 2 ** 32 - 1)
_STRINGS = ('', 'x', ' ', '/', '\u00e9', 'a' * 100, 'f' * 10_000)
# Inputs are published transient-local, which serves volatile and transient-local readers alike.
_PUB_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
_SUB_QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)


def _scalar(kind: str, rng: random.Random) -> Any:
    if kind in ('float', 'double'):
        return rng.choice(HOSTILE_FLOATS + (rng.gauss(0.0, 10.0),))
    if kind in _INTS:
        low, high = _INTS[kind]
        value = rng.choice((low, high, 0, 1, rng.randint(low, high)))
        return bytes([value]) if kind == 'byte' else value
    if kind == 'boolean':
        return rng.random() < 0.5
    if kind.startswith('string') or kind.startswith('wstring'):
        return rng.choice(_STRINGS)
    return _message(kind, rng)


def _message_type(name: str) -> type:
    package, _, message = name.partition('/')
    return getattr(importlib.import_module(f'{package}.msg'), message)


def _message(kind: str, rng: random.Random) -> Any:
    return hostile_message(_message_type(kind), rng)


def hostile_message(msg_type: type, rng: random.Random, template: Any = None,
                    rate: float = 1.0) -> Any:
    """
    Return a ``msg_type`` whose fields hold hostile values drawn with ``rng``.

    Without ``template`` every field is hostile. With one (a valid message), each field is
    hostile with probability ``rate`` and otherwise the template's (nested messages are
    corrupted field by field): a message that gets past the first checks.
    """
    msg = msg_type()
    for name, kind in msg_type.get_fields_and_field_types().items():
        if template is not None and rng.random() >= rate:
            kept = getattr(template, name)
            if '/' in kind and not kind.startswith('sequence<') and not kind.endswith(']'):
                kept = hostile_message(type(kept), rng, kept, rate)
            setattr(msg, name, kept)
            continue
        if kind.startswith('sequence<'):
            base = kind[len('sequence<'):-1].split(',')[0]
            value = [_scalar(base, rng) for _ in range(rng.choice(_SIZES))]
        elif kind.endswith(']'):
            base, size = kind[:-1].split('[')
            value = [_scalar(base, rng) for _ in range(int(size))]
        elif kind == 'builtin_interfaces/Time' and name == 'stamp':
            value = _message_type(kind)(sec=rng.choice(_SECONDS),
                                        nanosec=rng.choice(_NANOSECONDS))
        else:
            value = _scalar(kind, rng)
        try:
            setattr(msg, name, value)
        except (AssertionError, TypeError, ValueError):
            pass   # a bound the message type itself enforces (a bounded string, a char)
    return msg


def fuzz(node: Any, executor: Any, inputs: dict, outputs: dict,
         recovered: Callable[[dict[str, list]], bool],
         rng: random.Random, count: int = 150, seconds: float = 3.0,
         recovery_timeout: float = 15.0) -> tuple[dict[str, list], bool]:
    """
    Send a node hostile messages on each input, then valid ones until it has ``recovered``.

    ``node`` and ``executor`` are the test's own; ``inputs`` maps a topic to (message type,
    ``valid(t)`` returning a valid message of time t [s]), ``outputs`` a topic to its message
    type. The burst is ``count`` messages per input, at most ``seconds`` of wall time; half are
    valid messages with some fields corrupted. Valid input then goes out at 50 Hz of message
    time from t = 100 s until ``recovered(received)`` (``received`` maps each output to the
    messages received so far) or ``recovery_timeout`` [s]. Returns ``received`` and whether the
    node recovered.
    """
    received: dict[str, list] = {topic: [] for topic in outputs}
    for topic, msg_type in outputs.items():
        node.create_subscription(msg_type, topic, received[topic].append, _SUB_QOS)
    pubs = {topic: node.create_publisher(msg_type, topic, _PUB_QOS)
            for topic, (msg_type, _) in inputs.items()}
    _spin(executor, lambda: all(p.get_subscription_count() > 0 for p in pubs.values()), 15.0)
    deadline = time.monotonic() + seconds
    for k in range(count):
        for topic, (msg_type, valid) in inputs.items():
            template = valid(1.0 + 0.02 * k) if rng.random() < 0.5 else None
            pubs[topic].publish(hostile_message(msg_type, rng, template, rate=0.3))
        executor.spin_once(timeout_sec=0.0)
        if time.monotonic() > deadline:
            break
    t = 100.0
    give_up = time.monotonic() + recovery_timeout
    while not recovered(received) and time.monotonic() < give_up:
        for topic, (_, valid) in inputs.items():
            pubs[topic].publish(valid(t))
        t += 0.02
        _spin(executor, lambda: False, 0.02)
    return received, recovered(received)


def _spin(executor: Any, done: Callable[[], bool], timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while not done() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.01)
