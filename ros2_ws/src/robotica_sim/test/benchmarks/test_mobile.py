"""
Tests of robotica_sim.benchmarks.mobile's core loop (the ROS loop runs in ``robotica bench``).

The core must be a real closed loop: pure pursuit on the EKF's pose keeps the simulated robot on
the figure eight, and the EKF, fed quantised ticks, a noisy compass and DGPS fixes (2DRMS 1 m per
fix), stays well inside a fix's error of the simulated truth.
"""
from robotica_sim.benchmarks.mobile import mobile_core_benchmark


def test_core_benchmark_runs_a_tracking_and_estimating_loop():
    rows = {row.what: row for row in mobile_core_benchmark(20.0)}
    assert set(rows) == {'core step', 'core loop RTF'}
    assert rows['core step'].unit == 'µs' and rows['core step'].value > 0.0
    assert rows['core loop RTF'].unit == '×' and rows['core loop RTF'].value > 0.0
    rms = float(rows['core loop RTF'].detail.rsplit('error RMS ', 1)[1].split()[0])
    assert rms < 0.35
