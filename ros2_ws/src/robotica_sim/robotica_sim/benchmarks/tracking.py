"""
Tracking benchmark of issue 6: every tracking law on three vehicles, four paths, two pose sources.

Each run is one closed loop in one process (no ROS) at 50 Hz, as
:mod:`robotica_sim.benchmarks.mobile`: a law of
:mod:`robotica_ctrl.mobile.tracking_laws` (chosen by name, gains :data:`BENCHMARK_GAINS`)
drives a :class:`~robotica_sim.simulation.vehicle.VehicleSimulation` (RK4, traction lag
0.05 s, steering lag 0.1 s, as the ``figure_eight_*`` scenarios) of a differential, tricycle
or Ackermann vehicle (c = 0.1 m, b = 0.4 m, l = 0.5 m, |α| <= 1.2 rad) along one of
:data:`PATHS`:

* ``line_offset``: the straight line from (0, 0) to (10, 0) m, started 0.5 m to its left
  at (0, 0.5) m heading along it (θ = 0);
* ``circle``: the circle of radius 2 m centred at (0, 2) m, counter-clockwise from (0, 0);
* ``figure_eight``: two tangent circles of radius 2 m through the origin (25.1 m);
* ``sharp_turn``: 4 m along +x, then a right-angle corner to the left and 4 m along +y
  (the heading jumps by π/2; no cusp).

The closed paths start on the path heading along it. The law sees either the simulated truth
(``ground_truth``) or the estimate of the odometry node's EKF,
:class:`~robotica_kin.mobile.odometry_fusion.OdometryFusion` (``ekf_dgps``), fed, every step,
the counts of two 2000-count encoders on the odometry wheels (the drive wheels of the
differential base, the passive rear wheels of the steered ones), corrected by every compass
heading and every DGPS fix (5 Hz, GPS error as two Gauss–Markov states, as the odometry node
runs it). The ``speed`` argument of
``update`` is the true forward speed, or the encoders' mean wheel speed of the last step.
A steered vehicle gets the law's (v, ω) as the speed v and the steering angle
α = atan(l ω / v) (α = 0 when v = 0), as the ``path_tracker`` node sends it, book (4.121).

A run ends when the law reports the path finished (``completed``), or times out after
:data:`TIMEOUT_FACTOR` times the nominal time (path length / 0.5 m/s). The sensor noise is
drawn from the same seed in every run (common random numbers).

**Metrics** (:class:`TrackingResult`), over the samples k = 0..N of the *true* pose, at the
start and after every step (Δt = 0.02 s), projected onto the path by this module
with the project's one projection (:func:`robotica_sim.grading.metrics.path_errors`, as
``robotica grade`` does), not taken from what the law reports:

* cross-track error e_k [m]: signed lateral offset of the true guide point from its closest
  path point (searched within 1 m of arc length around the previous one, so a closed path is
  followed lap by lap); ``rms_cross_track`` = sqrt(mean e_k²), ``max_cross_track`` =
  max |e_k|;
* heading error ψ_k [rad]: θ_k minus the heading of the path segment of that closest point,
  wrapped to (-π, π]; ``rms_heading_error`` = sqrt(mean ψ_k²) (a sharp corner, where the
  path heading jumps by π/2, counts in full);
* ``settling_distance`` [m]: distance the true guide point has travelled (sum of the
  lengths of its steps) when |e_k| falls below :data:`SETTLING_THRESHOLD` (0.1 m) for the
  rest of the run; 0 when it never leaves the band, ``inf`` when the last sample is outside.
  The band is wider than the DGPS-fused estimate's error (up to about 7 cm), so that on the
  EKF pose it measures the law, not the sensor;
* ``control_effort`` [rad²/s]: ∫ ω² dt of the commanded yaw rate ω of the law, each command
  held for one step, Σ ω_k² Δt;
* compute time of each ``law.update`` call: the CPU time of the calling thread
  (``time.thread_time_ns``, about 1 µs of it the clock itself), so that other processes on
  a shared machine do not count; median and 99th percentile [µs] over the run (GPC
  computes once per ``sample_time`` = 0.1 s, every 5th call, and holds in between: its
  percentile is the cost of a solve).
"""

from dataclasses import dataclass, field
import math
from pathlib import Path
import time
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import circle, figure_eight, straight_line
from robotica_ctrl.mobile.tracking_laws import LAWS, make_law, steering_angle
from robotica_kin.mobile.odometry_fusion import OdometryFusion, OdometryFusionParams
from robotica_kin.mobile.vehicles import vehicle_kinematics, VehicleGeometry
from robotica_sim.grading.metrics import path_errors, rms
from robotica_sim.sensors.compass import CompassModel, CompassParams, heading_noise_stddev
from robotica_sim.sensors.encoder import EncoderModel, EncoderParams
from robotica_sim.sensors.gps import gps_preset, GpsModel
from robotica_sim.simulation.vehicle import VehicleSimulation, VehicleSimulationParams

__all__ = ['BENCHMARK_GAINS', 'PATHS', 'POSE_SOURCES', 'SETTLING_THRESHOLD', 'TIMEOUT_FACTOR',
           'TrackingResult', 'VEHICLES', 'benchmark_path', 'control_effort',
           'format_tracking_table', 'plot_tracking', 'run_tracking', 'settling_distance',
           'tracking_benchmark']

STEP = 0.02                 # [s] 50 Hz, as the scenarios
CRUISE_SPEED = 0.5          # [m/s] of every law
TIMEOUT_FACTOR = 2.5        # a run stops after this times length / CRUISE_SPEED
SETTLING_THRESHOLD = 0.1    # [m] band of |cross-track| of the settling distance
PROJECTION_WINDOW = 1.0     # [m] arc-length half-window of the metric's path projection
VEHICLES = ('differential', 'tricycle', 'ackermann')
PATHS = ('line_offset', 'circle', 'figure_eight', 'sharp_turn')
POSE_SOURCES = ('ground_truth', 'ekf_dgps')

# Gains of the benchmark, by law (names of LAW_PARAMETERS; the others keep their defaults).
# Every law runs at the same cruise speed, 0.5 m/s. GPC solves every 0.1 s (5 steps) and, as
# it has no yaw-rate limit, its curvature is limited to 3 1/m: the 1.5 rad/s yaw-rate limit of
# the other laws at 0.5 m/s (without it GPC commands |ω| of tens of rad/s at the sharp turn).
BENCHMARK_GAINS: dict[str, dict[str, float | str]] = {
    'pure_pursuit': {'desired_linear_velocity': CRUISE_SPEED},
    'adaptive_pure_pursuit': {'desired_linear_velocity': CRUISE_SPEED},
    'quintic': {'desired_linear_velocity': CRUISE_SPEED},
    'trajectory_tracking': {'reference_speed': CRUISE_SPEED},
    'frenet': {'desired_linear_velocity': CRUISE_SPEED},
    'gpc': {'linear_velocity': CRUISE_SPEED, 'sample_time': 0.1, 'max_curvature': 3.0},
}

_GEOMETRY = VehicleGeometry(wheel_radius=0.1, track=0.4, wheelbase=0.5)
_SIMULATION = VehicleSimulationParams(step_period=STEP, cmd_timeout=0.5,
                                      traction_time_constant=0.05,
                                      steering_time_constant=0.1)


@dataclass(frozen=True)
class TrackingResult:
    """
    One run of the benchmark: the combination, the completion and the metrics.

    The metrics are defined in the module docstring; lengths [m], angles [rad], times [s].

    Attributes
    ----------
    law, vehicle, path, pose_source : str
        The combination (names of ``LAWS``, :data:`VEHICLES`, :data:`PATHS`,
        :data:`POSE_SOURCES`).
    completed : bool
        Whether the law reported the end of the path before the time-out.
    duration : float
        Simulated time of the run [s].
    distance : float
        Distance travelled by the true guide point [m].
    rms_cross_track, max_cross_track : float
        RMS and largest |cross-track error| of the true pose [m].
    rms_heading_error : float
        RMS heading error of the true pose [rad].
    settling_distance : float
        Distance travelled until |cross-track| stays below 0.1 m [m]; ``inf`` if never.
    control_effort : float
        ∫ ω² dt of the commanded yaw rate [rad²/s].
    median_update_us, p99_update_us : float
        Median and 99th percentile of the CPU time of one ``law.update`` call [µs].
    trajectory : ndarray, shape (N + 1, 3)
        True poses (x [m], y [m], θ [rad]) at the samples, world frame; read-only, left out
        of comparisons and of the text form.

    """

    law: str
    vehicle: str
    path: str
    pose_source: str
    completed: bool
    duration: float
    distance: float
    rms_cross_track: float
    max_cross_track: float
    rms_heading_error: float
    settling_distance: float
    control_effort: float
    median_update_us: float
    p99_update_us: float
    trajectory: NDArray[np.float64] = field(repr=False, compare=False)

    def metrics(self) -> dict[str, str | bool | float]:
        """Return every field but the trajectory, by name (for JSON)."""
        return {name: getattr(self, name) for name in self.__dataclass_fields__
                if name != 'trajectory'}


def benchmark_path(name: str) -> tuple[PolylinePath, NDArray[np.float64]]:
    """
    Return the path named ``name`` (one of :data:`PATHS`) and the initial pose (3,) on it.

    The pose is (x [m], y [m], θ [rad]), REP-103; see the module docstring for the shapes.

    Raises
    ------
    ValueError
        For an unknown name.

    >>> path, pose = benchmark_path('sharp_turn')
    >>> path.length, pose.tolist()
    (8.0, [0.0, 0.0, 0.0])

    """
    if name == 'line_offset':
        points = straight_line([0.0, 0.0], [10.0, 0.0])
        pose = [0.0, 0.5, 0.0]
    elif name == 'circle':
        points = circle([0.0, 2.0], 2.0, start_angle=-0.5 * math.pi)
        pose = [0.0, 0.0, 0.0]
    elif name == 'figure_eight':
        points = figure_eight(2.0)
        pose = [0.0, 0.0, 0.0]
    elif name == 'sharp_turn':
        first = straight_line([0.0, 0.0], [4.0, 0.0])
        points = np.concatenate((first, straight_line([4.0, 0.0], [4.0, 4.0])[1:]))
        pose = [0.0, 0.0, 0.0]
    else:
        raise ValueError(f'path must be one of {PATHS}, got {name!r}')
    return PolylinePath(points), np.array(pose)


def settling_distance(cross_track: ArrayLike, travelled: ArrayLike,
                      threshold: float = SETTLING_THRESHOLD) -> float:
    """
    Return the distance travelled [m] when |cross_track| enters ``threshold`` for good.

    ``cross_track`` (N,) [m] are the errors at the samples and ``travelled`` (N,) [m] the
    distance travelled up to each. The result is ``travelled`` at the first sample from which
    every |error| is below ``threshold`` [m], 0 if all are, ``inf`` if the last one is not.

    >>> settling_distance([0.5, 0.2, 0.01, 0.18, 0.02, 0.0], [0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    4.0

    """
    error = np.abs(np.asarray(cross_track, dtype=np.float64))
    outside = np.flatnonzero(~(error < threshold))
    if outside.size == 0:
        return 0.0
    last = int(outside[-1])
    if last == len(error) - 1:
        return math.inf
    return float(np.asarray(travelled, dtype=np.float64)[last + 1])


def control_effort(angular: ArrayLike, step: float = STEP) -> float:
    """
    Return ∫ ω² dt [rad²/s] of yaw-rate commands ω (N,) [rad/s], each held ``step`` [s].

    >>> control_effort([0.5, -0.5, 1.0], step=0.1)
    0.15
    """
    w = np.asarray(angular, dtype=np.float64)
    return float(np.sum(w * w) * step)


class _DeadReckoning:
    """Encoders, compass and DGPS fused by the odometry node's estimator, as in a scenario."""

    def __init__(self, sim: VehicleSimulation, seed: int) -> None:
        seeds = np.random.SeedSequence(seed).spawn(4)
        self._sim = sim
        self._encoders = [EncoderModel(EncoderParams(500, 4), np.random.default_rng(s))
                          for s in seeds[:2]]
        compass_params = CompassParams(noise_stddev=2e-7)
        self._compass = CompassModel(compass_params, np.random.default_rng(seeds[2]))
        self._heading_variance = heading_noise_stddev(compass_params) ** 2
        receiver = gps_preset('dgps')
        self._gps = GpsModel(receiver, np.random.default_rng(seeds[3]))
        self._fusion = OdometryFusion(
            OdometryFusionParams(wheel_radius=_GEOMETRY.wheel_radius,
                                 wheel_separation=_GEOMETRY.track,
                                 gps_bias_stddev=float(receiver.correlated_stddev[0]),
                                 gps_bias_correlation_time=receiver.correlation_time,
                                 gps_white_stddev=receiver.white_stddev),
            sim.pose, np.zeros((3, 3)))
        self._read_encoders()

    def _read_encoders(self) -> None:
        """Apply the encoder counts of the current state (the first ones start the estimate)."""
        counts = self._encoders[0].params.ticks_per_revolution
        left, right = (encoder.ticks(angle)
                       for encoder, angle in zip(self._encoders, self._sim.wheel_angles))
        self._fusion.add_encoders(left, right, counts, self._sim.t)
        self._fusion.update()

    def update(self) -> None:
        """Fuse the readings of the step just taken."""
        sim = self._sim
        truth = sim.pose
        self._read_encoders()
        _, heading = self._compass.measure(float(truth[2]))
        self._fusion.add_heading(sim.t, heading, self._heading_variance)
        fix = self._gps.measure(sim.t, (truth[0], truth[1], 0.0))
        if fix is not None:
            self._fusion.add_position(sim.t, fix.enu[:2], fix.covariance[:2, :2])

    @property
    def pose(self) -> NDArray[np.float64]:
        """Estimated pose in the world frame: x [m], y [m], θ [rad]."""
        return self._fusion.pose

    @property
    def speed(self) -> float:
        """Mean wheel speed [m/s] of the last step."""
        return self._fusion.twist[0]


def run_tracking(law: str, vehicle: str, path: str, pose_source: str,
                 seed: int = 1) -> TrackingResult:
    """
    Run one combination of the benchmark and return its metrics.

    Parameters
    ----------
    law : str
        One of ``robotica_ctrl.mobile.tracking_laws.LAWS``, with :data:`BENCHMARK_GAINS`.
    vehicle : str
        One of :data:`VEHICLES`.
    path : str
        One of :data:`PATHS`.
    pose_source : str
        ``ground_truth`` (the law sees the simulated pose) or ``ekf_dgps`` (the EKF's).
    seed : int
        Seed of the sensor noise.

    Raises
    ------
    ValueError
        For an unknown name.

    """
    if vehicle not in VEHICLES:
        raise ValueError(f'vehicle must be one of {VEHICLES}, got {vehicle!r}')
    if pose_source not in POSE_SOURCES:
        raise ValueError(f'pose_source must be one of {POSE_SOURCES}, got {pose_source!r}')
    reference, start = benchmark_path(path)
    tracker = make_law(law, reference, BENCHMARK_GAINS.get(law))
    kinematics = vehicle_kinematics(vehicle, _GEOMETRY)
    sim = VehicleSimulation(kinematics, _SIMULATION, start)
    estimator = _DeadReckoning(sim, seed) if pose_source == 'ekf_dgps' else None
    steps = math.ceil(TIMEOUT_FACTOR * reference.length / CRUISE_SPEED / STEP)
    poses = [sim.pose]
    angular: list[float] = []
    call_ns: list[int] = []
    completed = False
    for _ in range(steps):
        if estimator is None:
            pose, speed = sim.pose, sim.twist[0]
        else:
            pose, speed = estimator.pose, estimator.speed
        begin = time.thread_time_ns()
        output = tracker.update(pose, sim.t, speed)
        call_ns.append(time.thread_time_ns() - begin)
        if output.finished:
            completed = True
            break
        angular.append(output.angular)
        sim.set_command(_vehicle_command(kinematics.steered, output.linear, output.angular),
                        sim.t)
        sim.step()
        poses.append(sim.pose)
        if estimator is not None:
            estimator.update()
    trajectory = np.array(poses)
    trajectory.flags.writeable = False
    _, cross, heading = path_errors(reference, trajectory[:, 0], trajectory[:, 1],
                                    trajectory[:, 2], PROJECTION_WINDOW)
    travelled = _travelled(trajectory)
    times_us = np.array(call_ns) * 1e-3
    return TrackingResult(
        law=law, vehicle=vehicle, path=path, pose_source=pose_source, completed=completed,
        duration=sim.t, distance=float(travelled[-1]), rms_cross_track=rms(cross),
        max_cross_track=float(np.max(np.abs(cross))), rms_heading_error=rms(heading),
        settling_distance=settling_distance(cross, travelled),
        control_effort=control_effort(angular), median_update_us=float(np.median(times_us)),
        p99_update_us=float(np.percentile(times_us, 99.0)), trajectory=trajectory)


def _travelled(trajectory: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the distance travelled [m] (N,) up to each pose of a trajectory (N, 3)."""
    steps = np.hypot(*np.diff(trajectory[:, :2], axis=0).T)
    return np.concatenate(([0.0], np.cumsum(steps)))


def _vehicle_command(steered: bool, linear: float, angular: float) -> tuple[float, float, float]:
    """Return the simulator's command: (v, 0, ω), or (v, α, 0) with α = atan(l ω / v)."""
    if not steered:
        return linear, 0.0, angular
    return linear, steering_angle(linear, angular, _GEOMETRY.wheelbase), 0.0


def tracking_benchmark(laws: Sequence[str] = LAWS, vehicles: Sequence[str] = VEHICLES,
                       paths: Sequence[str] = PATHS,
                       poses: Sequence[str] = POSE_SOURCES, seed: int = 1,
                       progress: Callable[[str], None] | None = None) -> list[TrackingResult]:
    """
    Run every combination of ``laws`` x ``vehicles`` x ``paths`` x ``poses``; return the rows.

    Rows come in that nesting order. ``progress``, when given, is called with a short message
    before the runs of each law on each vehicle. See :func:`run_tracking` for the arguments
    and the errors.
    """
    results = []
    groups = [(law, vehicle) for law in laws for vehicle in vehicles]
    for number, (law, vehicle) in enumerate(groups, 1):
        if progress is not None:
            progress(f'tracking: {law} on {vehicle} ({number}/{len(groups)})')
        for path in paths:
            for pose_source in poses:
                results.append(run_tracking(law, vehicle, path, pose_source, seed))
    return results


def format_tracking_table(results: Sequence[TrackingResult]) -> str:
    """Return the results as a Markdown table, one row per run (errors in m and rad)."""
    lines = ['| law | vehicle | path | pose | done | RMS e [m] | max e [m] | RMS ψ [rad] '
             '| settling [m] | ∫ω² dt [rad²/s] | median [µs] | p99 [µs] |',
             '|---|---|---|---|:---:|---:|---:|---:|---:|---:|---:|---:|']
    for r in results:
        lines.append(
            f'| {r.law} | {r.vehicle} | {r.path} | {r.pose_source} '
            f'| {"yes" if r.completed else "no"} | {r.rms_cross_track:.3f} '
            f'| {r.max_cross_track:.3f} | {r.rms_heading_error:.3f} '
            f'| {r.settling_distance:.2f} | {r.control_effort:.2f} '
            f'| {r.median_update_us:.1f} | {r.p99_update_us:.1f} |')
    return '\n'.join(lines)


def plot_tracking(results: Sequence[TrackingResult], directory: str | Path) -> list[Path]:
    """
    Write the benchmark's figures as PNG files into ``directory``; return their paths.

    * ``trajectories_<path>_<pose>.png``, per path and pose source: one column per vehicle,
      the true trajectories of every law over the path (equal axes [m]) and, below, their
      cross-track error [m] against the distance travelled [m];
    * ``rms_cross_track_<pose>.png``, per pose source: the RMS cross-track error [m] as a
      law x vehicle map, one panel per path;
    * ``compute_time.png``: the median and 99th percentile of the CPU time of one ``update``
      call of each law [µs], worst over its runs, against 50 µs and 1 ms.

    Runs that timed out are marked "(timed out)" in the legends.
    """
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    index = {(r.law, r.vehicle, r.path, r.pose_source): r for r in results}
    laws, vehicles, paths, sources = (list(dict.fromkeys(key[i] for key in index))
                                      for i in range(4))
    written = []
    for path in paths:
        for source in sources:
            fig = _trajectory_figure(plt, [[index.get((law, vehicle, path, source))
                                            for law in laws] for vehicle in vehicles])
            fig.suptitle(f'Path {path}, laws fed the {source} pose: true trajectories and '
                         f'cross-track errors ({CRUISE_SPEED} m/s, 50 Hz)')
            written.append(_save(plt, fig, out / f'trajectories_{path}_{source}.png'))
    for source in sources:
        fig, axes = plt.subplots(1, len(paths), figsize=(max(4.5 * len(paths), 8.0), 4.5),
                                 squeeze=False)
        for ax, path in zip(axes[0], paths):
            grid = np.array([[_rms_cross_track(index.get((law, vehicle, path, source)))
                              for vehicle in vehicles] for law in laws])
            image = ax.imshow(grid, cmap='viridis_r', aspect='auto')
            for (i, j), value in np.ndenumerate(grid):
                ax.text(j, i, f'{value:.3f}', ha='center', va='center', fontsize='small',
                        color='white' if value > np.nanmean(grid) else 'black')
            ax.set_xticks(range(len(vehicles)), vehicles)
            if ax is axes[0][0]:   # the rows are the same laws in every panel
                ax.set_yticks(range(len(laws)), laws)
            else:
                ax.set_yticks([])
            ax.set_xlabel('vehicle')
            ax.set_title(path)
            fig.colorbar(image, ax=ax, label='RMS cross-track error [m]')
        fig.suptitle(f'RMS cross-track error of the true pose [m]\nlaws fed the {source} pose')
        written.append(_save(plt, fig, out / f'rms_cross_track_{source}.png'))
    fig, ax = plt.subplots(figsize=(8.0, 4.5))
    positions = np.arange(len(laws))
    ax.bar(positions - 0.2, [max(r.median_update_us for r in results if r.law == law)
                             for law in laws], 0.4, label='median (worst run)')
    ax.bar(positions + 0.2, [max(r.p99_update_us for r in results if r.law == law)
                             for law in laws], 0.4, label='99th percentile (worst run)')
    ax.axhline(1000.0, color='red', linestyle='--', label='1 ms')
    ax.axhline(50.0, color='grey', linestyle=':', label='50 µs')
    ax.set_yscale('log')
    ax.set_xticks(positions, laws, rotation=20)
    ax.set_ylabel('CPU time per update call [µs]')
    ax.set_title(f'Compute time of law.update in the loop, {len(results)} runs')
    ax.legend(fontsize='small')
    ax.grid(True, axis='y', alpha=0.3)
    written.append(_save(plt, fig, out / 'compute_time.png'))
    return written


def _trajectory_figure(plt: Any, runs: list[list[TrackingResult | None]]) -> Any:
    """Return a figure: per vehicle (column), trajectories (top) and cross-track (bottom)."""
    fig, axes = plt.subplots(2, len(runs), figsize=(max(5.0 * len(runs), 8.0), 9.0),
                             squeeze=False, height_ratios=(3.0, 2.0))
    colours = plt.get_cmap('tab10')
    for column, vehicle_runs in enumerate(runs):
        top, bottom = axes[0][column], axes[1][column]
        present = [run for run in vehicle_runs if run is not None]
        if not present:
            continue
        reference = benchmark_path(present[0].path)[0]
        top.plot(reference.points[:, 0], reference.points[:, 1], 'k--', linewidth=2.0,
                 label='path')
        top.set_title(present[0].vehicle)
        for number, run in enumerate(vehicle_runs):
            if run is None:
                continue
            label = run.law + ('' if run.completed else ' (timed out)')
            top.plot(run.trajectory[:, 0], run.trajectory[:, 1], color=colours(number),
                     linewidth=1.2, label=label)
            _, cross, _ = path_errors(reference, run.trajectory[:, 0], run.trajectory[:, 1],
                                      run.trajectory[:, 2], PROJECTION_WINDOW)
            bottom.plot(_travelled(run.trajectory), cross, color=colours(number),
                        linewidth=1.0, label=label)
        top.set_aspect('equal', adjustable='datalim')
        top.set_xlabel('x [m]')
        top.set_ylabel('y [m]')
        top.grid(True, alpha=0.3)
        top.legend(fontsize='small')
        for band in (-SETTLING_THRESHOLD, SETTLING_THRESHOLD):
            bottom.axhline(band, color='grey', linestyle=':', linewidth=1.0)
        bottom.set_xlabel('distance travelled [m]')
        bottom.set_ylabel('cross-track error [m] (> 0 left)')
        bottom.grid(True, alpha=0.3)
    return fig


def _rms_cross_track(result: TrackingResult | None) -> float:
    return math.nan if result is None else result.rms_cross_track


def _save(plt: Any, fig: Any, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
