"""
The ``main()`` of every robotica node: init, build, spin, shut down cleanly (Jazzy).

A node whose parameters are invalid raises ``ValueError`` (or rclpy refuses an override out of
its range or of the wrong type) while it is built; that is logged as one clear line and the
process exits with code 2, without a traceback. Only the construction counts: an error inside
a callback is the guard's (:mod:`robotica_kin.ros.guarded`), which drops the message and keeps
the node running. Ctrl-C (SIGINT) and SIGTERM end the process with code 0 (STYLE.md §5,
shutdown).
"""
import sys
import time
from typing import Callable, Optional

import rclpy
from rclpy._rclpy_pybind11 import RCLError
from rclpy.exceptions import ParameterException
from rclpy.executors import Executor, ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

SIGNAL_SHUTDOWN_GRACE = 2.0   # [s] wall clock: rclpy's shutdown after a signal comes by then


def _spin_forever(node: Node, executor: Executor) -> int:
    # A loop of spin_once, not executor.spin(): rclpy Jazzy's EventsExecutor.spin() busy-loops
    # without delivering anything (measured: 0 of 550 messages, 100 % CPU, deaf to shutdown),
    # while its spin_once delivers, with or without use_sim_time.
    while rclpy.ok(context=node.context):
        executor.spin_once(timeout_sec=0.5)
    return 0


def _shut_down_by_signal(grace: float = SIGNAL_SHUTDOWN_GRACE) -> bool:
    """
    Return whether rclpy shuts down within ``grace`` [s, wall clock] (SIGINT or SIGTERM came).

    rclpy's signal handler shuts the contexts down from a thread of its own, a moment after the
    signal; in between, a call into the executor or the node can already fail. The
    EventsExecutor raises ``RuntimeError: Unable to convert call argument`` when the Python
    KeyboardInterrupt of SIGINT lands while it converts a callback's argument, and rclpy is
    then still "ok" for a few milliseconds (seen in 2 of some 60 SIGINTs under load).
    """
    deadline = time.monotonic() + grace
    while rclpy.ok():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


def run_node(factory: Callable[[], Node], args: Optional[list[str]] = None,
             run: Callable[[Node, Executor], int] = _spin_forever,
             executor_factory: Callable[[], Executor] = SingleThreadedExecutor,
             signal_handler_options: SignalHandlerOptions = SignalHandlerOptions.ALL) -> None:
    """
    Build the node with ``factory``, run it with ``run(node, executor)`` and exit.

    ``run`` returns the exit code; the default spins until shutdown. A node that must act on
    SIGINT/SIGTERM itself (e.g. drain and close a file) passes ``SignalHandlerOptions.NO``.
    """
    rclpy.init(args=args, signal_handler_options=signal_handler_options)
    code = 0
    node = None
    try:
        try:
            node = factory()
        except (ValueError, ParameterException) as err:
            name = getattr(factory, '__name__', 'node')
            rclpy.logging.get_logger(name).error(f'invalid configuration: {err}')
            code = 2
        else:
            executor = executor_factory()
            executor.add_node(node)
            code = run(node, executor)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except (RCLError, RuntimeError):   # a call racing the shutdown of SIGINT/SIGTERM while
        if not _shut_down_by_signal():    # the node is built or spins: not an error
            raise
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    sys.exit(code)
