"""
Speed of the mobile-robot loop: the pure core in one process (the ROS loop is ``robotica run``).

The core is what the nodes of ``figure_eight_differential`` compute, in one Python loop at
50 Hz: :class:`~robotica_sim.simulation.vehicle.VehicleSimulation` (differential drive, RK4),
two :class:`~robotica_sim.sensors.encoder.EncoderModel` counters, the gyro, compass and DGPS
models, the EKF (:class:`~robotica_kin.mobile.ekf_localization.EkfLocalization`, with the GPS
error as Gauss–Markov states, as the odometry node runs it) fed by the encoder increments and
corrected by every compass heading and GPS fix, and pure pursuit
(:class:`~robotica_ctrl.mobile.pure_pursuit.PurePursuit`) on the EKF's pose along a figure
eight of 2 m radius at 0.5 m/s. Reported: simulated seconds per wall-clock second (RTF), the
time per step, and the EKF's position error against the simulated truth (RMS over the run).
"""

import math
import time

import numpy as np
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import figure_eight
from robotica_ctrl.mobile.pure_pursuit import PurePursuit, PurePursuitParams
from robotica_kin.mobile.ekf_localization import EkfLocalization, OdometryNoise
from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
from robotica_sim.benchmarks.measurement_row import MeasurementRow
from robotica_sim.sensors.compass import CompassModel, CompassParams, heading_noise_stddev
from robotica_sim.sensors.encoder import EncoderModel, EncoderParams
from robotica_sim.sensors.gps import gps_preset, GpsModel
from robotica_sim.sensors.gyro import GYRO_PRESETS, GyroModel
from robotica_sim.simulation.vehicle import VehicleSimulation, VehicleSimulationParams

__all__ = ['mobile_core_benchmark']

STEP = 0.02   # [s] 50 Hz, as the scenarios


def mobile_core_benchmark(duration: float = 60.0, seed: int = 1) -> list[MeasurementRow]:
    """Run the figure-eight core for ``duration`` simulated seconds; return its rows."""
    geometry = VehicleGeometry(wheel_radius=0.1, track=0.4)
    sim = VehicleSimulation(vehicle_kinematics('differential', geometry),
                            VehicleSimulationParams(step_period=STEP, cmd_timeout=0.5))
    seeds = np.random.SeedSequence(seed).spawn(5)
    encoders = [EncoderModel(EncoderParams(500, 4), np.random.default_rng(s)) for s in seeds[:2]]
    gyro = GyroModel(GYRO_PRESETS['mems_consumer'], np.random.default_rng(seeds[2]))
    compass_params = CompassParams(noise_stddev=2e-7)
    compass = CompassModel(compass_params, np.random.default_rng(seeds[3]))
    heading_variance = heading_noise_stddev(compass_params) ** 2
    receiver = gps_preset('dgps')
    gps = GpsModel(receiver, np.random.default_rng(seeds[4]))
    ekf = EkfLocalization([0.0, 0.0, 0.0], np.zeros((3, 3)), OdometryNoise(),
                          position_bias_stddev=float(receiver.correlated_stddev[0]),
                          position_bias_correlation_time=receiver.correlation_time)
    tracker = PurePursuit(PolylinePath(figure_eight(2.0)),
                          PurePursuitParams(lookahead_distance=0.6))
    counts = encoders[0].params.ticks_per_revolution
    metres_per_tick = 2.0 * math.pi * geometry.wheel_radius / counts
    ticks = [0, 0]
    errors = []
    steps = round(duration / STEP)
    start = time.perf_counter()
    for _ in range(steps):
        command = tracker.update(ekf.pose)
        sim.set_command((command.linear, 0.0, command.angular), sim.t)
        sim.step()
        t, truth = sim.t, sim.pose
        readings = [encoder.ticks(angle) for encoder, angle in zip(encoders, sim.wheel_angles)]
        left, right = (metres_per_tick * (new - old) for new, old in zip(readings, ticks))
        ticks = readings
        ekf.predict(0.5 * (left + right), (right - left) / geometry.track, dt=STEP)
        gyro.measure(sim.twist[2], STEP)          # read, as the gyro node does (heading: encoders)
        _, heading = compass.measure(float(truth[2]))
        ekf.update_heading(heading, heading_variance)
        fix = gps.measure(t, (truth[0], truth[1], 0.0))
        if fix is not None:
            ekf.update_position(fix.enu[:2], fix.covariance[:2, :2],
                                white_variance=receiver.white_stddev ** 2)
        errors.append(math.hypot(*(ekf.pose[:2] - truth[:2])))
    wall = time.perf_counter() - start
    rms = math.sqrt(sum(e * e for e in errors) / len(errors))
    return [
        MeasurementRow('core step', wall / steps * 1e6, 'µs',
                       'simulator, 2 encoders, gyro, compass, DGPS, EKF and pure pursuit'),
        MeasurementRow('core loop RTF', duration / wall, '×',
                       f'figure eight (r = 2 m) at 50 Hz, {duration:g} s simulated; EKF position '
                       f'error RMS {rms:.2f} m'),
    ]
