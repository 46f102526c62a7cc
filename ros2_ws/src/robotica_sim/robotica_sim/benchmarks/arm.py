"""
Speed of the manipulator loop: the pure core, the DDS round trip, the full ROS loop.

Three measurements, each in simulated seconds per wall-clock second (real-time factor, RTF) for
the PUMA 560 at 1 kHz under computed torque (the appendix's example: reference sin t on every
joint, K_p = 25, K_v = 10):

- **core**: :class:`~robotica_sim.simulation.arm.ArmSimulation` (RK4, four ABA calls per step)
  and :class:`~robotica_ctrl.joint_control.ComputedTorque` (one RNEA call) in one Python loop,
  with the reference sampled each step, as the nodes do; also each part alone [µs per step];
- **dynamics**: each function of :mod:`robotica_kin.dynamics` per call (the arm and one
  ``data`` kept, inputs checked) as a ratio to the bare call it wraps, with the floor of a
  checked Python wrapper, timed in the same run on the same model, data and configurations
  (:mod:`robotica_sim.benchmarks.dynamics`);
- **round trip**: the fastest a lockstep loop over DDS can be here: a JointState published by
  this process, answered by an echo process (:func:`run_echo`) with a Float64MultiArray, with
  the QoS and the executor of the arm nodes (EventsExecutor); the RTF limit is step / round
  trip;
- **ROS loop**: ``robotica run puma_computed_torque`` (trajectory publisher, joint controller,
  arm simulator and recorder as separate processes, lockstep), its own RTF.
"""

import json
import os
from pathlib import Path
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Callable

import numpy as np
from robotica_ctrl.joint_control import (ComputedTorque, ComputedTorqueGains, JointReference,
                                         JointState)
from robotica_ctrl.trajectory.sinusoid import sinusoid
from robotica_kin.pinocchio_model import pinocchio_arm
from robotica_kin.robots import puma560
from robotica_sim.benchmarks.dynamics import time_dynamics
from robotica_sim.benchmarks.measurement_row import MeasurementRow
from robotica_sim.simulation.arm import ArmSimulation, ArmSimulationParams

__all__ = ['core_benchmark', 'dynamics_benchmark', 'loop_benchmark', 'round_trip_benchmark',
           'run_echo']

STEP = 1e-3   # [s] 1 kHz
PING_TOPIC, ECHO_TOPIC = 'bench_joint_states', 'bench_joint_torques'


def _per_step(function: Callable[[int], object], steps: int) -> float:
    """Return the wall-clock time per call of ``function(k)``, k = 0..steps-1 [µs]."""
    start = time.perf_counter()
    for k in range(steps):
        function(k)
    return (time.perf_counter() - start) / steps * 1e6


def core_benchmark(steps: int = 5000) -> list[MeasurementRow]:
    """Time the simulator, the law and both in one loop (PUMA 560, 1 kHz, ``steps`` steps)."""
    robot = puma560()
    t = np.arange(steps) * STEP
    q_d, qd_d, qdd_d = (np.repeat(x, 6, axis=1) for x in sinusoid(t, 1.0, 2.0 * np.pi))
    law = ComputedTorque(robot, ComputedTorqueGains(kp=25.0, kv=10.0))
    params = ArmSimulationParams(step_period=STEP, respect_limits=False)
    sim = ArmSimulation(robot, params, np.zeros(6), np.zeros(6))
    hold = np.zeros(6)

    def simulator(k: int) -> None:
        sim.step(hold)

    def controller(k: int) -> None:
        law.update(JointReference(q_d[k], qd_d[k], qdd_d[k]), JointState(sim.q, sim.qd), STEP)

    def loop(k: int) -> None:
        sim.step(law.update(JointReference(q_d[k], qd_d[k], qdd_d[k]),
                            JointState(sim.q, sim.qd), STEP))

    sim_us = _per_step(simulator, steps)
    law_us = _per_step(controller, steps)
    sim.reset(np.zeros(6), np.zeros(6))
    loop_us = _per_step(loop, steps)
    error = float(np.abs(sim.q - q_d[-1]).max())
    return [
        MeasurementRow('core simulator step', sim_us, 'µs', 'ArmSimulation.step, RK4, 4 ABA'),
        MeasurementRow('core controller step', law_us, 'µs', 'ComputedTorque.update, 1 RNEA'),
        MeasurementRow('core loop RTF', STEP * 1e6 / loop_us, '×',
                       f'{steps} steps, {loop_us:.1f} µs each; max |e| at the end '
                       f'{error:.1e} rad'),
    ]


def dynamics_benchmark(count: int = 5000, seed: int = 0,
                       repeats: int = 15) -> list[MeasurementRow]:
    """Return each dynamics function's time per call over the bare call's (PUMA 560) [×]."""
    arm = pinocchio_arm(puma560())
    rng = np.random.default_rng(seed)
    q = rng.uniform(arm.robot.qlim[:, 0], arm.robot.qlim[:, 1], size=(count, 6))
    qd, qdd = rng.uniform(-1.0, 1.0, size=(2, count, 6))
    rows = []
    for t in time_dynamics(arm, q, qd, qdd, repeats):
        floor = ('' if t.floor_us is None else
                 f'; floor (one Python call + norm checks) {t.floor_us:.2f} µs = '
                 f'{t.floor_ratio:.2f}×')
        per, calls = ((' per evaluation', 'evaluations a run') if t.function == 'fdyn'
                      else ('', 'calls a block'))
        rows.append(MeasurementRow(
            f'{t.function} / bare call', t.ratio, '×',
            f'{t.function} {t.robotica_us:.2f} µs, {t.raw_name} {t.raw_us:.2f} µs{per} = '
            f'{t.ratio:.2f}×{floor}; {t.count} {calls}, CPU time, best of {t.blocks}'))
    return rows


def run_echo(count: int) -> None:
    """Answer ``count`` JointState messages with a Float64MultiArray each, then exit."""
    import rclpy
    from rclpy.experimental import EventsExecutor
    from robotica_kin.ros.qos import COMMAND_PUB_QOS, STREAM_SUB_QOS
    from sensor_msgs.msg import JointState as JointStateMsg
    from std_msgs.msg import Float64MultiArray

    rclpy.init()
    node = rclpy.create_node('bench_echo')
    answered = [0]
    publisher = node.create_publisher(Float64MultiArray, ECHO_TOPIC, COMMAND_PUB_QOS)

    def answer(msg: JointStateMsg) -> None:
        publisher.publish(Float64MultiArray(data=list(msg.position)))
        answered[0] += 1

    node.create_subscription(JointStateMsg, PING_TOPIC, answer, STREAM_SUB_QOS)
    executor = EventsExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + 120.0
    while answered[0] < count and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    time.sleep(0.5)   # let the last answer go out
    node.destroy_node()
    rclpy.try_shutdown()


def round_trip_benchmark(count: int = 2000) -> list[MeasurementRow]:
    """Time ``count`` JointState → Float64MultiArray round trips through an echo process."""
    import rclpy
    from rclpy.experimental import EventsExecutor
    from robotica_kin.ros.qos import COMMAND_QOS, STREAM_PUB_QOS
    from sensor_msgs.msg import JointState as JointStateMsg
    from std_msgs.msg import Float64MultiArray

    warm_up = 50
    script = f'from robotica_sim.benchmarks.arm import run_echo; run_echo({count + warm_up})'
    echo = subprocess.Popen([sys.executable, '-c', script])
    rclpy.init()
    node = rclpy.create_node('bench_ping')
    received = [0]
    node.create_subscription(Float64MultiArray, ECHO_TOPIC,
                             lambda _: received.__setitem__(0, received[0] + 1), COMMAND_QOS)
    publisher = node.create_publisher(JointStateMsg, PING_TOPIC, STREAM_PUB_QOS)
    executor = EventsExecutor()
    executor.add_node(node)
    msg = JointStateMsg(name=[f'joint_{i}' for i in range(1, 7)], position=[0.0] * 6,
                        velocity=[0.0] * 6, effort=[0.0] * 6)
    times = []
    try:
        deadline = time.monotonic() + 60.0
        while (publisher.get_subscription_count() == 0 or node.count_publishers(ECHO_TOPIC) == 0
               ) and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
        # The first answers may be lost while the echo's writer matches: resend until one comes.
        while received[0] == 0 and time.monotonic() < deadline:
            publisher.publish(msg)
            executor.spin_once(timeout_sec=0.1)
        sent = received[0]
        for k in range(count + warm_up):
            start = time.perf_counter()
            publisher.publish(msg)
            while received[0] <= sent + k and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=1.0)
            if k >= warm_up:
                times.append(time.perf_counter() - start)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
        echo.wait(timeout=30)
    if len(times) < count:
        raise RuntimeError(f'only {len(times)} of {count} round trips completed')
    median = statistics.median(times) * 1e6
    p95 = float(np.percentile(times, 95)) * 1e6
    return [
        MeasurementRow('DDS round trip', median, 'µs',
                       f'median of {count}, p95 {p95:.0f} µs; JointState out, '
                       'Float64MultiArray back, EventsExecutor at both ends'),
        MeasurementRow('lockstep RTF limit', STEP * 1e6 / median, '×',
                       '1 ms step / median round trip'),
    ]


def loop_benchmark(duration: float = 5.0, scenario: str = 'puma_computed_torque',
                   processes: str = '3 node processes') -> list[MeasurementRow]:
    """Run ``robotica run <scenario>`` for ``duration`` simulated s; return its RTF."""
    with tempfile.TemporaryDirectory() as tmp:
        command = ['robotica', 'run', scenario, '--duration', str(duration),
                   '--output-dir', str(Path(tmp) / 'run'), '--json', '--quiet']
        proc = subprocess.run(command, capture_output=True, text=True, env=dict(os.environ),
                              timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f'robotica run failed ({proc.returncode}): {proc.stderr.strip()}')
    summary = json.loads(proc.stdout)
    return [MeasurementRow('ROS loop RTF', float(summary['real_time_factor']), '×',
                           f'robotica run {scenario} --duration {duration:g}: '
                           f'{processes} + recorder, lockstep; '
                           f'{summary["lockstep_timeouts"]} lockstep timeouts')]
