"""
The shell every robotica simulator node shares: it owns the time and paces the steps.

A subclass integrates one plant (a mobile robot, a manipulator) and implements
:meth:`SteppedSimulatorNode.step_plant` and :meth:`SteppedSimulatorNode.publish_plant`; it calls
:meth:`SteppedSimulatorNode.note_answer` from its command callback. This class declares the
pacing parameters, publishes ``/clock`` and ``~/status`` (robotica_msgs/SimulatorStatus), offers
the ``~/start`` service (std_srvs/Trigger) and runs the loop.

Pacing (DESIGN.md, time and recording):

* ``realtime``: one step per ``step_period`` of wall-clock time.
* ``lockstep``: as fast as possible; step k+1 starts when a command has answered step k, or after
  ``lockstep.timeout`` wall-clock seconds (counted in ``lockstep_timeouts`` and logged). Until the
  first answer, step 0 is published again every ``lockstep.timeout`` (discovery of the control loop
  may still be going on), for at most ``lockstep.start_timeout``; then the node gives up.
  Nodes off that loop (sensor emulators, odometry) are held to it through
  ``lockstep.follow_topics``: a step waits (at most ``lockstep.timeout``, counted in
  ``lockstep_timeouts``) while the newest header stamp on one of these topics is more than
  ``lockstep.max_lag`` simulated seconds behind the last step published. Without this, a
  lockstep loop outran them on a loaded machine and their input queues overflowed: a run lost up
  to a third of its ``/odom`` and ``/wheel_encoders`` messages, and its bag with them. A followed
  topic counts once a publisher of it is matched; a lockstep run starts once every followed topic
  has one (at most ``lockstep.start_timeout``), so that no follower is discovered mid-run. They
  are subscribed transient-local: discovery is not symmetric, and a gyro emulator's writer once
  matched the simulator's reader 1 s after the reader had matched it. A follower answers the
  steps published, so a stamp ahead of the simulated time (by more than a step) or malformed
  (``nanosec`` >= 1e9) is not from this run: it is refused (logged by the guard, no brake), else
  one stamp of 2**31 - 1 made the topic count as caught up for the rest of the run.

At ``end_time`` the node publishes a final status and exits with code 0.
"""
from abc import abstractmethod
import math
import time

from rclpy.clock import Clock as WallClock, ClockType
from rclpy.duration import Duration
from rclpy.executors import Executor
from robotica_kin.ros.convert import header_stamp, seconds_to_stamp
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_msgs.msg import SimulatorStatus
from robotica_sim.bags.typestore import message_class
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger

PACING_MODES = ('realtime', 'lockstep')
FOLLOW_DISCOVERY_PERIOD = 0.1   # [s, wall clock] search for the followed topics' types


class SteppedSimulatorNode(GuardedNode):
    """A node that steps a simulated plant at a fixed period; run it with :meth:`run`."""

    def __init__(self, name: str, *, default_step_period: float, command_topic: str) -> None:
        super().__init__(name)
        self.step_period = declare(self, 'step_period', default_step_period,
                                   'Simulated time per step [s] (publishing period)',
                                   low=1e-4, high=1.0, read_only=True)
        self._pacing = declare(self, 'pacing', 'realtime',
                               'realtime (wall-clock paced) or lockstep (as fast as the '
                               'controller answers)', read_only=True)
        if self._pacing not in PACING_MODES:
            raise ValueError(f'pacing must be one of {PACING_MODES}, got {self._pacing!r}')
        self._lockstep_timeout = declare(
            self, 'lockstep.timeout', 1.0,
            'Wall-clock seconds to wait for the answer to a step before going on',
            low=1e-3, high=60.0, read_only=True)
        self._start_timeout = declare(
            self, 'lockstep.start_timeout', 30.0,
            'Wall-clock seconds to wait for the first answer (discovery) before giving up',
            low=0.1, high=600.0, read_only=True)
        self._end_time = declare(self, 'end_time', 0.0,
                                 'Simulated time [s] at which the run ends; 0: never',
                                 low=0.0, high=1e7, read_only=True)
        self._autostart = declare(self, 'autostart', True,
                                  'Start stepping at once (else wait for ~/start)',
                                  read_only=True)
        self._status_period = declare(self, 'status_period', 1.0,
                                      'Period of ~/status [s, simulated]', low=1e-3, high=1e3,
                                      read_only=True)
        self._follow_topics = [t for t in declare(
            self, 'lockstep.follow_topics', [''],
            'Topics (stamped messages) of nodes off the control loop that each lockstep step '
            'waits for; [""]: none', read_only=True) if t]
        self._max_lag = declare(self, 'lockstep.max_lag', 0.5,
                                'Simulated seconds a followed topic may lag behind the steps',
                                low=0.0, high=60.0, read_only=True)
        self._followed: dict[str, float] = {}   # topic -> newest header stamp [s]
        self._follow_subscriptions: dict = {}
        if self._follow_topics:
            self._follow_timer = self.create_timer(
                FOLLOW_DISCOVERY_PERIOD, self._subscribe_followed,
                clock=WallClock(clock_type=ClockType.STEADY_TIME))
        self._command_topic = command_topic
        self._clock_pub = self.create_publisher(Clock, '/clock', STREAM_PUB_QOS)
        self._status_pub = self.create_publisher(SimulatorStatus, '~/status', STREAM_PUB_QOS)
        self.create_service(Trigger, '~/start', self._on_start)
        self._started = False
        self._answers = 0
        self._timeouts = 0
        self.stale_steps = 0
        self.contacts = 0              # contacts with the world (the plant counts them)
        self.time_in_contact = 0.0     # [s] simulated time in contact with the world
        self._steps = 0
        self._next_status = 0.0
        self._wall_start = 0.0

    # -- what a plant provides --------------------------------------------------------------
    @abstractmethod
    def step_plant(self) -> None:
        """Advance the plant by one ``step_period`` with the newest command."""

    @abstractmethod
    def publish_plant(self, t: float) -> None:
        """Publish the plant's state at simulated time ``t`` [s] (besides clock and status)."""

    def note_answer(self) -> None:
        """Count a command received: in lockstep it releases the next step."""
        self._answers += 1

    @property
    def sim_time(self) -> float:
        """Return the simulated time [s] (steps times the step period)."""
        return round(self._steps * self.step_period, 12)

    @property
    def publishers_to_flush(self) -> list:
        """Return the publishers whose last messages must be acknowledged before exiting."""
        return [self._clock_pub, self._status_pub]

    # -- followed topics ----------------------------------------------------------------------
    def _subscribe_followed(self) -> None:
        types = dict(self.get_topic_names_and_types())
        for topic in self._follow_topics:
            if topic in self._follow_subscriptions or topic not in types:
                continue
            try:
                msg_class = message_class(types[topic][0])
            except (AttributeError, ModuleNotFoundError, ValueError) as err:
                self.get_logger().error(f'cannot follow {topic}: {err}')
                self._follow_subscriptions[topic] = None
                continue

            def newest(data: bytes, topic: str = topic) -> None:
                stamp = header_stamp(data)
                if stamp > self.sim_time + self.step_period + 1e-9:
                    raise ValueError(f'stamp {stamp!r} s is ahead of the simulated time '
                                     f'{self.sim_time!r} s: not an answer to this run')
                self._followed[topic] = max(self._followed[topic], stamp)
            self._followed[topic] = 0.0
            self._follow_subscriptions[topic] = self.create_subscription(
                msg_class, topic, newest, STREAM_REPLAY_SUB_QOS, raw=True, safe_output=False)
        if len(self._follow_subscriptions) == len(self._follow_topics):
            self._follow_timer.cancel()

    def _lagging(self, lag: float | None = None) -> list[str]:
        """Return the followed topics more than ``lag`` (default max_lag) behind the steps."""
        oldest = self.sim_time - self.step_period - (
            self._max_lag if lag is None else lag) - 1e-9
        return [t for t, stamp in self._followed.items() if stamp < oldest
                and self._follow_subscriptions[t].get_publisher_count() > 0]

    # -- callbacks ----------------------------------------------------------------------------
    def _on_start(self, request: Trigger.Request, response: Trigger.Response
                  ) -> Trigger.Response:
        response.success = not self._started
        response.message = 'started' if not self._started else 'already running'
        self._started = True
        return response

    # -- publishing -----------------------------------------------------------------------
    def _publish_state(self) -> None:
        t = self.sim_time
        self.publish_plant(t)   # first: the controller waits for it (each publish costs 50-110 µs)
        self._clock_pub.publish(Clock(clock=seconds_to_stamp(t)))
        if t >= self._next_status - 1e-9:
            self._publish_status(finished=False)
            self._next_status += self._status_period

    def _publish_status(self, finished: bool) -> None:
        wall = time.monotonic() - self._wall_start
        status = SimulatorStatus(step=self._steps, lockstep_timeouts=self._timeouts,
                                 stale_command_stops=self.stale_steps, finished=finished,
                                 real_time_factor=self.sim_time / wall if wall > 0 else 0.0,
                                 contacts=self.contacts,
                                 time_in_contact=float(self.time_in_contact))
        status.header.stamp = seconds_to_stamp(self.sim_time)
        self._status_pub.publish(status)

    # -- the stepping loop ------------------------------------------------------------------
    def _spin_until(self, executor: Executor, done, deadline: float) -> bool:
        """Spin until ``done()`` or the wall-clock ``deadline``; return ``done()``."""
        while not done():
            remaining = deadline - time.monotonic()
            if remaining <= 0.0:
                break
            executor.spin_once(timeout_sec=min(remaining, 1.0))
        return done()

    def _wait_for_followers(self, executor: Executor) -> None:
        """Wait (at most ``lockstep.start_timeout``) until each followed topic has a publisher."""
        def missing() -> list[str]:
            return [t for t in self._follow_topics if t not in self._follow_subscriptions or (
                self._follow_subscriptions[t] is not None
                and self._follow_subscriptions[t].get_publisher_count() == 0)]
        give_up = time.monotonic() + self._start_timeout
        while missing() and time.monotonic() < give_up:
            executor.spin_once(timeout_sec=FOLLOW_DISCOVERY_PERIOD)   # matching wakes nothing
        if missing():
            self.get_logger().warn(f'no publisher of {", ".join(missing())} after '
                                   f'{self._start_timeout} s; starting without')

    def _wait_for_first_answer(self, executor: Executor) -> bool:
        give_up = time.monotonic() + self._start_timeout
        while time.monotonic() < give_up:
            seen = self._answers
            self._publish_state()
            deadline = min(give_up, time.monotonic() + self._lockstep_timeout)
            if self._spin_until(executor, lambda: self._answers > seen, deadline):
                return True
            self.get_logger().info(
                f'waiting for the controller to answer step 0 on {self._command_topic}',
                throttle_duration_sec=5.0)
        return False

    def run(self, executor: Executor) -> int:
        """Step until ``end_time`` (or shutdown); return the process exit code."""
        self._spin_until(executor, lambda: self._started or self._autostart, math.inf)
        self.get_logger().info(f'started: pacing {self._pacing}, step {self.step_period} s, '
                               f'end time {self._end_time or "none"} s')
        self._wall_start = time.monotonic()
        lockstep = self._pacing == 'lockstep'
        if lockstep:
            self._wait_for_followers(executor)
            if not self._wait_for_first_answer(executor):
                self.get_logger().error(
                    f'no command on {self._command_topic} within {self._start_timeout} s: is a '
                    'controller running and connected? Stopping.')
                return 1
            # The real-time factor is that of the steps: the waits above (discovery, whole
            # seconds of lockstep.timeout) are not part of them.
            self._wall_start = time.monotonic()
        else:
            self._publish_state()
        while self._end_time == 0.0 or self.sim_time < self._end_time - 1e-9:
            if lockstep:
                seen = self._answers
            else:
                target = self._wall_start + (self._steps + 1) * self.step_period
                self._spin_until(executor, lambda: False, target)
            self.step_plant()
            self._steps += 1
            self._publish_state()
            if lockstep:
                deadline = time.monotonic() + self._lockstep_timeout
                if not self._spin_until(executor, lambda: self._answers > seen
                                        and not self._lagging(), deadline):
                    self._timeouts += 1
                    lagging = self._lagging()
                    self.get_logger().warn(
                        f'lockstep: step {self._steps} went on after {self._lockstep_timeout} '
                        's without ' + (f'{", ".join(lagging)} catching up' if lagging
                                        else 'an answer') + f' ({self._timeouts} so far)',
                        throttle_duration_sec=1.0)
        if lockstep:   # the followers' answers to the last steps belong to the run
            self._spin_until(executor, lambda: not self._lagging(lag=0.0),
                             time.monotonic() + self._lockstep_timeout)
        self._publish_status(finished=True)
        for pub in self.publishers_to_flush:
            pub.wait_for_all_acked(Duration(seconds=2.0))
        wall = time.monotonic() - self._wall_start
        self.get_logger().info(
            f'finished at t = {self.sim_time:.3f} s after {self._steps} steps in '
            f'{wall:.2f} s wall (real-time factor {self.sim_time / max(wall, 1e-9):.1f}); '
            f'lockstep timeouts {self._timeouts}, stale-command steps {self.stale_steps}'
            + (f', contacts {self.contacts} ({self.time_in_contact:.2f} s)' if self.contacts
               else ''))
        return 0
