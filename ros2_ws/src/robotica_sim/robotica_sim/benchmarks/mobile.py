"""
Speed of the mobile-robot loop: the pure core in one process (the ROS loop is ``robotica run``).

The core is what the nodes of ``figure_eight_differential`` compute, in one Python loop at
50 Hz: :class:`~robotica_sim.simulation.vehicle.VehicleSimulation` (differential drive, RK4),
two :class:`~robotica_sim.sensors.encoder.EncoderModel` counters, the gyro, compass and DGPS
models, the odometry node's estimator
(:class:`~robotica_kin.mobile.odometry_fusion.OdometryFusion`: the EKF with the GPS error as
Gauss–Markov states) fed by the encoder counts and corrected by every compass heading and GPS
fix, and pure pursuit
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
from robotica_kin.mobile.odometry_fusion import OdometryFusion, OdometryFusionParams
from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
from robotica_sim.benchmarks.measurement_row import MeasurementRow
from robotica_sim.grading.metrics import rms
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
    fusion = OdometryFusion(
        OdometryFusionParams(wheel_radius=geometry.wheel_radius, wheel_separation=geometry.track,
                             gps_bias_stddev=float(receiver.correlated_stddev[0]),
                             gps_bias_correlation_time=receiver.correlation_time,
                             gps_white_stddev=receiver.white_stddev),
        [0.0, 0.0, 0.0], np.zeros((3, 3)))
    tracker = PurePursuit(PolylinePath(figure_eight(2.0)),
                          PurePursuitParams(lookahead_distance=0.6))
    counts = encoders[0].params.ticks_per_revolution
    fusion.add_encoders(0, 0, counts, sim.t)   # the counters start at 0
    errors = []
    steps = round(duration / STEP)
    start = time.perf_counter()
    for _ in range(steps):
        command = tracker.update(fusion.pose, sim.t)
        sim.set_command((command.linear, 0.0, command.angular), sim.t)
        sim.step()
        t, truth = sim.t, sim.pose
        left, right = (encoder.ticks(angle) for encoder, angle in zip(encoders, sim.wheel_angles))
        fusion.add_encoders(left, right, counts, t)
        fusion.update()
        gyro.measure(sim.twist[2], STEP)          # read, as the gyro node does (heading: encoders)
        _, heading = compass.measure(float(truth[2]))
        fusion.add_heading(t, heading, heading_variance)
        fix = gps.measure(t, (truth[0], truth[1], 0.0))
        if fix is not None:
            fusion.add_position(t, fix.enu[:2], fix.covariance[:2, :2])
        errors.append(math.hypot(*(fusion.pose[:2] - truth[:2])))
    wall = time.perf_counter() - start
    return [
        MeasurementRow('core step', wall / steps * 1e6, 'µs',
                       'simulator, 2 encoders, gyro, compass, DGPS, EKF and pure pursuit'),
        MeasurementRow('core loop RTF', duration / wall, '×',
                       f'figure eight (r = 2 m) at 50 Hz, {duration:g} s simulated; EKF position '
                       f'error RMS {rms(errors):.2f} m'),
    ]
