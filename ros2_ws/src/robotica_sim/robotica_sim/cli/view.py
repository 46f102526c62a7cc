"""
Relay the running graph to the Foxglove app: a Foxglove WebSocket server in the foreground.

Relays every topic of the current ROS domain (``ROS_DOMAIN_ID``, set by ``scripts/env.sh``) on
``ws://HOST:PORT`` until Ctrl-C or SIGTERM (exit code 0), as the ``view_relay`` node does
(:func:`robotica_sim.nodes.view_relay.serve`); see docs/view.md for the Foxglove side. A port in
use or a host it cannot listen on: one line and exit code 2.
"""
import argparse
import sys

from robotica_sim.cli.options import integer, nonempty
from robotica_sim.view.relay import DEFAULT_HOST, DEFAULT_PORT

HELP = 'relay the running graph to the Foxglove app (live view)'
EPILOG = """examples:
  robotica view                            ws://127.0.0.1:8765, beside a run in another shell
  robotica view --port 8766                another port
  robotica run demo --view                 a run and its relay together
"""


def add_host_port(parser: argparse.ArgumentParser) -> None:
    """Add ``--host`` and ``--port`` of the relay (shared by ``robotica run --view``)."""
    parser.add_argument('--host', type=nonempty, default=DEFAULT_HOST,
                        help='address the relay listens on (0.0.0.0 exposes every topic to the '
                        'network)')
    parser.add_argument('--port', type=integer(1, 65535), default=DEFAULT_PORT,
                        help='TCP port of the relay')


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica view``."""
    add_host_port(parser)


def main(args: argparse.Namespace) -> int:
    """Relay until Ctrl-C or SIGTERM; return the exit code."""
    from robotica_sim.nodes.view_relay import serve
    from robotica_sim.view.relay import RelayStartError
    try:
        serve(args.host, args.port, [])
    except RelayStartError as err:
        print(f'robotica view: error: {err}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:   # the way a relay is stopped: not an interruption of work
        pass
    return 0
