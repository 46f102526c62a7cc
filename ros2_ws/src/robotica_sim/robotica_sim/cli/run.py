"""
Run a scenario: every node in its own process, the whole run recorded to a bag.

Starts the recorder and the nodes of the scenario's plan (a mobile robot: path publisher, sensor
emulators, odometry, path tracker and simulator; a manipulator: trajectory publisher, joint
controller and arm simulator) with the scenario's parameters; waits until the recorder has
matched every topic; starts the simulation; waits for its end time; stops every process (also
on Ctrl-C or when a node dies) and prints the bag's path and a one-line summary. A bag that
lacks messages of the per-step topics (the recorder fell behind: ``RECORDING INCOMPLETE`` in
the summary) is an error: exit code 1, the bag kept (docs/recording.md).
"""
import argparse
import json
import os
from pathlib import Path
import random
import shlex
import shutil
import signal
import sys
import time
from typing import Optional

from ament_index_python.packages import get_package_prefix, PackageNotFoundError
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from robotica_kin.mobile.vehicles import STEERED_TYPES
from robotica_sim.bags.info import BagError
from robotica_sim.bags.repair import partial_reason, repair_command
from robotica_sim.bags.run_record import COMPLETED, record_end, ROBOTICA, USER
from robotica_sim.cli.contract_watch import ContractWatch
from robotica_sim.cli.options import domain_id, domain_warning, nonempty, path, real
from robotica_sim.cli.view import add_host_port
from robotica_sim.grading.summary import RunSummary, summarize_bag
from robotica_sim.runs.plan import (external_roles, NodeSpec, optional_topics, plan_run,
                                    progress_topics, recorded_topics)
from robotica_sim.runs.scenario import load_scenario, with_overrides
from robotica_sim.runs.supervisor import child_environment, ProcessSupervisor
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger
import yaml

HELP = 'run a scenario and record it'
EPILOG = """examples:
  robotica run demo                        the shipped demo scenario, lockstep
  robotica run demo --pacing realtime      watch it at wall-clock speed
  robotica run ej8_2                       Ej. 8.2: computed torque with a wrong model
  robotica run my_scenario.yaml --json     machine-readable summary on stdout
  robotica run demo --pacing realtime --view    watch it live in Foxglove (docs/view.md)
"""
MATCH_SETTLE = 0.5   # [s] wall clock, see _wait_ready
GRAPH_WAIT = 5.0     # [s] wall clock, see _wait_for_graph
CALL_RETRY = 2.0     # [s] wall clock, see _call
SAFE_STOP = 1.0      # [s] simulated after a node died: the simulator's cmd_timeout 0.5 s + 0.5
SAFE_STOP_WALL = 5.0     # [s] wall clock, the longest wait for that stop
MIN_TIMEOUT = 1.0        # [s] wall clock: a shorter wait cannot cover one start of the nodes
WATCH_PERIOD = 0.1   # [s] wall clock between two looks at the run (clock, progress, faults)
CLOCK_REFRESH = 5    # spins (10 ms each at most) for the newest /clock before a fault's time
STOP_FIRST = ['simulator']   # no step without its controllers; then every other node at once
STOP_LAST = ['recorder']     # it records what the others publish until they stop


class RunFailed(Exception):
    """The run could not be completed; the message says why."""


class _Executor(SingleThreadedExecutor):
    """
    An executor that turns Ctrl-C and SIGTERM into KeyboardInterrupt between callbacks.

    Raised inside a callback that rclpy's C++ side is converting a message for, a
    KeyboardInterrupt surfaced as ``RuntimeError: Unable to convert call argument``: an
    "internal error" instead of "interrupted". While the executor is used, the signals are only
    noted (:meth:`interrupts`), and every spin ends by raising KeyboardInterrupt if one came.
    """

    def __init__(self) -> None:
        super().__init__()
        self._signals: list[int] = []

    def interrupts(self) -> dict:
        """Note SIGINT and SIGTERM from now on; return the handlers to restore."""
        def note(signum, frame) -> None:
            self._signals.append(signum)
        return {s: signal.signal(s, note) for s in (signal.SIGINT, signal.SIGTERM)}

    def _raise_if_interrupted(self) -> None:
        if self._signals:
            raise KeyboardInterrupt

    def spin_once(self, timeout_sec: Optional[float] = None) -> None:
        """Spin once, then raise KeyboardInterrupt if SIGINT or SIGTERM came."""
        super().spin_once(timeout_sec)
        self._raise_if_interrupted()

    def spin_once_until_future_complete(self, future, timeout_sec=None) -> None:
        """Spin once for ``future``, then raise KeyboardInterrupt if a signal came."""
        super().spin_once_until_future_complete(future, timeout_sec)
        self._raise_if_interrupted()


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``robotica run``."""
    parser.add_argument('scenario', type=nonempty,
                        help='scenario YAML file, or the name of a shipped one')
    parser.add_argument('--output-dir', type=path, default=None,
                        help='run directory to create (default: runs/<scenario>-<time>)')
    parser.add_argument('--pacing', choices=['lockstep', 'realtime'], default=None,
                        help="override the scenario's pacing")
    parser.add_argument('--duration', type=real(0.0, 1e7, low_open=True), default=None,
                        help="override the scenario's duration [s, simulated]")
    parser.add_argument('--visualisation', choices=['on', 'off'], default=None,
                        help="override the scenario's visualisation: off leaves out the state "
                        'publisher and the markers node and publishes no /tf (a quarter less '
                        'CPU; docs/benchmarks.md)')
    parser.add_argument('--domain-id', type=domain_id, default=None,
                        help='ROS_DOMAIN_ID of the run, 0-232 (above 101 with a warning: see '
                        'docs/scenarios.md) (default: $ROS_DOMAIN_ID, else random)')
    parser.add_argument('--discovery-timeout', type=real(MIN_TIMEOUT, 3600.0),
                        default=30.0,
                        help='longest wait for the nodes to discover each other [s]')
    parser.add_argument('--timeout', type=real(MIN_TIMEOUT, 1e7), default=None,
                        help='longest wall-clock time of the run [s] (default: 120 + 10 x '
                        'duration)')
    parser.add_argument('--json', action='store_true', help='print the summary as JSON')
    parser.add_argument('--quiet', action='store_true', help='no progress on stderr')
    parser.add_argument('--view', action='store_true',
                        help='relay the run to the Foxglove app on ws://HOST:PORT (the '
                        'view_relay node, as robotica view; docs/view.md)')
    add_host_port(parser)


def _log(args: argparse.Namespace, text: str) -> None:
    if not args.quiet:
        print(f'[robotica run] {text}', file=sys.stderr, flush=True)


def _executable(spec: NodeSpec) -> str:
    try:
        prefix = get_package_prefix(spec.package)
    except PackageNotFoundError:
        raise RunFailed(f'package {spec.package} is not installed: source scripts/env.sh '
                        '(or your workspace) first') from None
    path = Path(prefix) / 'lib' / spec.package / spec.executable
    if not os.access(path, os.X_OK):
        raise RunFailed(f'no executable {path}; rebuild the workspace (scripts/setup.sh)')
    return str(path)


def _argv(spec: NodeSpec, params_file: Path) -> list[str]:
    """Return the command line of a node: its executable, or a user's command, and ROS args."""
    argv = [*(spec.command or [_executable(spec)]), '--ros-args', '-r', f'__node:={spec.name}',
            '--params-file', str(params_file)]
    for source, target in spec.remappings.items():
        argv += ['-r', f'{source}:={target}']
    return argv


def _prepare(args: argparse.Namespace, scenario, plan: list[NodeSpec],
             run_dir: Path) -> list[NodeSpec]:
    bag = run_dir / 'bag'
    scenario_copy = run_dir / 'scenario.yaml'
    params_file = run_dir / 'params.yaml'
    run_file = run_dir / 'run.yaml'
    shutil.copy(scenario.source, scenario_copy)
    recorder = NodeSpec('robotica_sim', 'recorder', 'recorder', {
        'output': str(bag), 'topics': list(recorded_topics(scenario)),
        'optional_topics': list(optional_topics(scenario)) or [''],
        'progress_topics': list(progress_topics(scenario)),
        'metadata_files': [str(scenario_copy), str(params_file), str(run_file)]})
    relay = NodeSpec('robotica_sim', 'view_relay', 'view_relay',
                     {'host': args.host, 'port': args.port}, use_sim_time=False)
    nodes = [recorder] + plan + ([relay] if args.view else [])
    # What ran, as run (the recorder stores it in the bag: robotica_sim.bags.run_record).
    overrides = {k: v for k, v in (('pacing', args.pacing), ('duration', args.duration),
                                   ('visualisation', args.visualisation)) if v is not None}
    run_file.write_text(yaml.safe_dump({
        'scenario': scenario.name, 'seed': scenario.seed, 'pacing': scenario.pacing,
        'duration': scenario.duration, 'step_period': scenario.step_period,
        'overrides': overrides, 'domain_id': int(os.environ['ROS_DOMAIN_ID']),
        'scenario_file': str(scenario.source),
        'started': time.strftime('%Y-%m-%dT%H:%M:%S%z'),
        'nodes': [{'name': 'robotica_run', 'started_by': ROBOTICA, 'command': 'robotica run'}]
        + [{'name': spec.name, 'started_by': USER, 'role': spec.role,
            'command': shlex.join(spec.command), 'cwd': spec.cwd} if spec.command
           else {'name': spec.name, 'started_by': ROBOTICA,
                 'command': f'{spec.package}/{spec.executable}'} for spec in nodes]},
        sort_keys=False))
    params = {}
    for spec in nodes:
        params[spec.name] = {'ros__parameters': {'use_sim_time': spec.use_sim_time,
                                                 **spec.parameters}}
    params_file.write_text(yaml.safe_dump(params, sort_keys=False))
    return nodes


def _call(executor, client, deadline: float) -> Trigger.Response:
    """
    Call a Trigger service, resending the request every CALL_RETRY until ``deadline``.

    ``wait_for_service`` is true once the server's request reader is matched; its reply writer
    may not be matched to our reply reader yet, and a reply sent then is lost (a CI run waited
    30 s for /recorder/ready this way). Both services called here are idempotent.
    """
    while True:
        while not client.wait_for_service(timeout_sec=0.1):
            executor.spin_once(timeout_sec=0.0)
            if time.monotonic() > deadline:
                raise RunFailed(f'service {client.srv_name} did not appear')
        future = client.call_async(Trigger.Request())
        attempt = min(CALL_RETRY, max(0.1, deadline - time.monotonic()))
        executor.spin_until_future_complete(future, timeout_sec=attempt)
        if future.done():
            return future.result()
        client.remove_pending_request(future)
        if time.monotonic() > deadline:
            raise RunFailed(f'service {client.srv_name} did not answer')


def _exit_text(code: int) -> str:
    """
    Return how a process ended, from its exit code (negative: the signal that killed it).

    >>> _exit_text(-9), _exit_text(1)
    ('was killed by SIGKILL', 'exited with code 1')
    """
    if code < 0:
        try:
            return f'was killed by {signal.Signals(-code).name}'
        except ValueError:
            return f'was killed by signal {-code}'
    return f'exited with code {code}'


def _died(supervisor: ProcessSupervisor, names: list[str]) -> Optional[tuple[str, int]]:
    """Return the first of ``names`` that exited before it was asked to, with its code."""
    supervisor.watch()
    dead = {n: c for n, c in supervisor.died().items() if n in names}
    return next(iter(dead.items())) if dead else None


def _death(supervisor: ProcessSupervisor, name: str, code: int,
           watch: Optional[ContractWatch] = None, sim_time: Optional[float] = None
           ) -> RunFailed:
    who = (watch.label(name) if watch is not None else None) or f'node {name}'
    when = '' if sim_time is None else f' by t = {sim_time:.2f} s'
    return RunFailed(f'{who} {_exit_text(code)}{when} before the end:\n' + supervisor.tail(name))


def _check_alive(supervisor: ProcessSupervisor, names: list[str],
                 watch: Optional[ContractWatch] = None) -> None:
    dead = _died(supervisor, names)
    if dead:
        raise _death(supervisor, *dead, watch=watch)


def _wait_ready(args, executor, node, supervisor, names, published, watch) -> None:
    started = time.monotonic()
    deadline = started + args.discovery_timeout
    ready = node.create_client(Trigger, '/recorder/ready')
    while True:
        _check_alive(supervisor, names, watch)
        broken = watch.unpublished(time.monotonic() - started)
        if broken:
            raise RunFailed(broken)
        answer = _call(executor, ready, deadline)
        if answer.success:
            _wait_for_graph(args, executor, node, names, published)
            # The recorder sees its own side of each match; a publisher may match it a moment
            # later. Streams keep a history for that (robotica_kin.ros.qos), commands do not:
            # give the publishers' side of discovery this long to complete.
            settle = time.monotonic() + MATCH_SETTLE
            while time.monotonic() < settle:
                executor.spin_once(timeout_sec=settle - time.monotonic())
            return
        if time.monotonic() > deadline:
            raise RunFailed(f'discovery incomplete after {args.discovery_timeout} s: '
                            f'{answer.message}')
        executor.spin_once(timeout_sec=0.2)


def _unpublished_subscriptions(node, names: list[str], published: set[str]) -> list[str]:
    """
    Return '<node>: <topic>' for each subscription of the run's nodes with no publisher yet.

    Only the topics of ``published`` (those the run's nodes publish) count: a subscription to a
    topic no node of this run publishes is an optional input (the markers node's GPS fixes in a
    run without GPS) and would only hold the start for GRAPH_WAIT.
    """
    waiting = []
    for name in names:
        try:
            topics = node.get_subscriber_names_and_types_by_node(name, '/')
        except Exception:   # rclpy raises NodeNameNonExistentError before the node is seen
            waiting.append(f'{name}: (not discovered)')
            continue
        waiting += [f'{name}: {topic}' for topic, _ in topics
                    if topic in published and not node.get_publishers_info_by_topic(topic)]
    return waiting


def _wait_for_graph(args, executor, node, names: list[str], published: set[str]) -> None:
    """
    Wait (up to GRAPH_WAIT) until every subscription of the run's nodes has a publisher.

    A node whose subscription is matched late misses the first messages of a volatile topic:
    an odometry node that saw its gyro 1 s late on a loaded machine lost the first second of
    turn (a flaky end-to-end test). Some subscriptions may have no publisher in a run (an
    optional input), so the wait is bounded, and what is still missing is logged.
    """
    deadline = time.monotonic() + GRAPH_WAIT
    waiting = _unpublished_subscriptions(node, names, published)
    while waiting and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
        waiting = _unpublished_subscriptions(node, names, published)
    if waiting:
        _log(args, f'no publisher yet for {", ".join(waiting)}; starting anyway')


def _progress(args, t: float, duration: float) -> None:
    if args.quiet or not sys.stderr.isatty():
        return
    done = min(1.0, t / duration)
    bar = '#' * int(30 * done)
    print(f'\r[robotica run] [{bar:<30}] {t:7.2f} / {duration:.2f} s', end='',
          file=sys.stderr, flush=True)


def _simulate(args, scenario, plan: list[NodeSpec], run_dir: Path,
              supervisor: ProcessSupervisor) -> float:
    """Start the nodes, run the simulation to its end; return the wall-clock run time [s]."""
    nodes = _prepare(args, scenario, plan, run_dir)
    names = [spec.name for spec in nodes]
    for spec in nodes:
        try:
            # The params file absolute: a user's command runs in its scenario's folder.
            argv = _argv(spec, (run_dir / 'params.yaml').resolve())
            supervisor.start(spec.name, argv, cwd=spec.cwd)
        except OSError as err:   # a user's command removed since the plan checked it
            raise RunFailed(f'cannot start {spec.label}: {err.strerror or err}') from None
    _log(args, f'started {len(nodes)} nodes (domain {os.environ["ROS_DOMAIN_ID"]}), '
               'waiting for discovery')
    node = rclpy.create_node('robotica_run')
    executor = _Executor()
    executor.add_node(node)
    handlers = executor.interrupts()
    sim_time = [0.0]
    node.create_subscription(
        Clock, '/clock', lambda m: sim_time.__setitem__(0, m.clock.sec + m.clock.nanosec * 1e-9),
        QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
    watch = ContractWatch(node, nodes, scenario.robot.type in STEERED_TYPES,
                          {role.name: spec.answer_timeout
                           for role, spec in external_roles(scenario)})
    try:
        _wait_ready(args, executor, node, supervisor, names,
                    set(recorded_topics(scenario)) - {'/clock'} - set(optional_topics(scenario)),
                    watch)
        _call(executor, node.create_client(Trigger, '/simulator/start'),
              time.monotonic() + args.discovery_timeout)
        _log(args, f'running {scenario.name}: {scenario.duration} s simulated, '
                   f'{scenario.pacing} pacing')
        start = time.monotonic()
        timeout = args.timeout if args.timeout is not None else \
            120.0 + 10.0 * scenario.duration
        others = [n for n in names if n != 'simulator']
        fault = None    # the first node that died: (name, code), and when the run ends for it
        while supervisor.returncode('simulator') is None:
            # Ten looks a second: the newest /clock waits in its keep-last-1 queue. Spinning on
            # every /clock cost this process 9 s of CPU in a 30-s run of 3000 steps.
            time.sleep(WATCH_PERIOD)
            for _ in range(1 + len(watch)):   # /clock and each watched answer
                executor.spin_once(timeout_sec=0.0)
            _progress(args, sim_time[0], scenario.duration)
            if fault is None:
                broken = watch.failure(sim_time[0], start)
                fault = _died(supervisor, others)
                if broken or fault is not None:
                    # The message gives the time: take the newest /clock, not the last look's
                    # (a simulated second old at 10x real time).
                    for _ in range(CLOCK_REFRESH):
                        executor.spin_once(timeout_sec=0.01)
                if broken:   # the simulator has braked (a NaN) or holds its step: end now
                    raise RunFailed(watch.failure(sim_time[0], start) or broken)
                if fault is not None:
                    fault_time = sim_time[0]
                    if fault[0] == 'recorder':
                        raise _death(supervisor, *fault)
                    # Let the simulator go on a little: on a stale command it stops the robot,
                    # and the bag records that stop.
                    _log(args, f'node {fault[0]} {_exit_text(fault[1])}; the simulator stops '
                               'the robot, then the run ends')
                    safe_stop = (sim_time[0] + SAFE_STOP, time.monotonic() + SAFE_STOP_WALL)
            elif sim_time[0] >= safe_stop[0] or time.monotonic() >= safe_stop[1]:
                break
            if time.monotonic() - start > timeout:
                raise RunFailed(f'the run took longer than {timeout:g} s wall clock')
        if fault is not None:
            raise _death(supervisor, *fault, watch=watch, sim_time=fault_time)
        broken = watch.failure(sim_time[0], start, running=False)
        if broken:
            raise RunFailed(broken)
        wall = time.monotonic() - start
        if not args.quiet and sys.stderr.isatty():
            print(file=sys.stderr)
        if supervisor.returncode('simulator') != 0:
            raise RunFailed('the simulator failed:\n' + supervisor.tail('simulator'))
        return wall
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)
        executor.shutdown()
        node.destroy_node()


def main(args: argparse.Namespace) -> int:
    """Run the scenario; return the exit code."""
    # Every error of the scenario and its plan (a law, a shape, a gain) before anything starts;
    # a ScenarioError is one line and exit 2 (robotica_sim.cli.main).
    scenario = with_overrides(
        load_scenario(args.scenario), pacing=args.pacing, duration=args.duration,
        visualisation=None if args.visualisation is None else args.visualisation == 'on')
    plan = plan_run(scenario)
    domain = args.domain_id
    if domain is None:
        try:
            domain = domain_id(os.environ.get('ROS_DOMAIN_ID') or str(random.randint(1, 101)))
        except argparse.ArgumentTypeError as err:
            print(f'robotica run: error: ROS_DOMAIN_ID {err}', file=sys.stderr)
            return 2
    if domain_warning(domain):
        _log(args, f'warning: {domain_warning(domain)}')
    os.environ.update(child_environment(domain))
    run_dir = args.output_dir or Path('runs') / (
        f'{scenario.name}-{time.strftime("%Y%m%d-%H%M%S")}')
    try:
        run_dir.mkdir(parents=True, exist_ok=False)
    except FileExistsError:
        print(f'robotica run: error: {run_dir} exists already', file=sys.stderr)
        return 2
    except OSError as err:
        print(f'robotica run: error: cannot create {run_dir}: {err.strerror or err}',
              file=sys.stderr)
        return 2
    supervisor = ProcessSupervisor(run_dir / 'logs', dict(os.environ))
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    code, ended = 0, COMPLETED
    try:
        _simulate(args, scenario, plan, run_dir, supervisor)
    except RunFailed as err:
        print(f'robotica run: failed: {err}', file=sys.stderr)
        code, ended = 1, f'failed: {str(err).splitlines()[0]}'
    except KeyboardInterrupt:
        print('\nrobotica run: interrupted; stopping the nodes', file=sys.stderr)
        code, ended = 130, 'interrupted (Ctrl-C or SIGTERM)'
    finally:
        codes = supervisor.stop_all(STOP_FIRST, STOP_LAST)
        rclpy.try_shutdown()
    faults = _faults(supervisor)
    if faults and ended == COMPLETED:
        ended = '; '.join(f'node {name} {text}' for name, text in faults.items())
    if codes.get('recorder') not in (0, None) and 'recorder' not in faults:
        print(f'robotica run: the recorder exited with {codes["recorder"]}:\n'
              + supervisor.tail('recorder'), file=sys.stderr)
        code = code or 1
    for name, text in faults.items():
        print(f'robotica run: fault: node {name} {text}; its log: '
              f'{supervisor.log_path(name)}', file=sys.stderr)
    code = code or (1 if faults else 0)
    bag = run_dir / 'bag'
    partial = partial_reason(bag)
    if partial:
        print(f'robotica run: the bag is partial ({partial}): `{repair_command(bag)}` recovers '
              f'what was recorded; logs in {run_dir / "logs"}', file=sys.stderr)
        return code or 1
    if not (bag / 'metadata.yaml').is_file():
        print(f'robotica run: no bag was written; logs in {run_dir / "logs"}', file=sys.stderr)
        return code or 1
    try:   # what info, grade and report show of the run: how it ended, not only how it began
        record_end(bag, ended)
    except OSError as err:
        print(f'robotica run: cannot record how the run ended ({ended}) in {bag}: '
              f'{err.strerror or err}', file=sys.stderr)
        code = code or 1
    try:
        summary = summarize_bag(bag)
    except BagError as err:
        print(f'robotica run: cannot summarise the run: {err}; logs in {run_dir / "logs"}',
              file=sys.stderr)
        return code or 1
    return _print_summary(args, scenario.name, bag, summary, faults, code,
                          supervisor.log_path('view_relay'))


def _print_summary(args: argparse.Namespace, name: str, bag: Path, summary: RunSummary,
                   faults: dict[str, str], code: int, view_log: Path) -> int:
    """
    Print the bag's path and the run's summary (one line, or JSON); return the exit code.

    A bag that lacks messages of per-step topics (``summary.missing``: the recorder fell
    behind) did not record what ran: one error line on stderr, the bag kept, and exit code 1
    unless the run already failed otherwise.
    """
    if summary.missing:
        print(f'robotica run: error: the recording is incomplete: the bag lacks '
              f'{sum(summary.missing.values())} messages of per-step topics (the recorder fell '
              f'behind; an overloaded machine?); the bag is kept: {bag}', file=sys.stderr)
        code = code or 1
    view = {'view': f'ws://{args.host}:{args.port}'} if args.view else {}
    if args.json:
        print(json.dumps({**summary.as_dict(), **view, 'faults': faults, 'exit_code': code}))
    else:
        print(f'bag: {bag}')
        if view:
            print(f'view: relayed on {view["view"]} (log: {view_log})')
        print(f'{name}: {summary.line()}'
              + ''.join(f'; node {node} {text}' for node, text in faults.items()))
    return code


def _faults(supervisor: ProcessSupervisor) -> dict[str, str]:
    """Return the nodes that died or stalled during the run, each with what happened."""
    faults = {name: _exit_text(code) for name, code in supervisor.died().items()
              if not (name == 'simulator' and code == 0)}    # its normal end
    for name, seen in supervisor.stalled.items():
        faults.setdefault(name, f'stalled (found stopped, {seen} check'
                          f'{"s" if seen > 1 else ""} 0.1 s apart)')
    return faults
