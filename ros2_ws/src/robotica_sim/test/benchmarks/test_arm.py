"""
Tests of robotica_sim.benchmarks.arm's core measurement (the ROS parts run in ``robotica bench``).

The core loop must be a real closed loop: with an exact model, computed torque makes the error
obey e'' + 10 e' + 25 e = 0 (8.35); from e(0) = 0, e'(0) = 1 rad/s (reference sin t, arm at rest)
that is e(t) = t exp(-5 t), 7e-11 rad at t = 5 s, so only the 1 kHz zero-order hold remains.
"""
from robotica_sim.benchmarks.arm import core_benchmark, dynamics_benchmark


def test_core_benchmark_runs_a_converging_loop():
    rows = {row.what: row for row in core_benchmark(5000)}
    assert set(rows) == {'core simulator step', 'core controller step', 'core loop RTF'}
    assert rows['core simulator step'].value > 0.0 and rows['core controller step'].value > 0.0
    assert rows['core loop RTF'].unit == '×' and rows['core loop RTF'].value > 0.0
    error = float(rows['core loop RTF'].detail.rsplit('max |e| at the end ', 1)[1].split()[0])
    assert error < 1e-3


def test_dynamics_benchmark_gives_a_ratio_per_function():
    rows = dynamics_benchmark(20, repeats=2)
    assert [row.what for row in rows] == [f'{name} / bare call' for name in
                                          ('rne', 'inertia', 'gravity', 'coriolis',
                                           'coriolis_matrix', 'friction', 'fdyn')]
    for row in rows:
        assert row.unit == '×' and row.value > 0.0 and 'µs' in row.detail
        assert f'= {row.value:.2f}×' in row.detail
        assert ('floor' in row.detail) is (row.what != 'fdyn / bare call')
