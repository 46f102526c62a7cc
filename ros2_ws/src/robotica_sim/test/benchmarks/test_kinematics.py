"""
Tests of robotica_sim.benchmarks.kinematics and ``robotica bench kin``.

The baselines must compute the same quantities as the library (or the comparison means
nothing); the table must hold every row with sane numbers.
"""
import json

import numpy as np
import pytest

from robotica_kin.forward_kinematics import fkine
from robotica_kin.jacobian import jacob0
from robotica_kin.robots import cylindrical_rpr, planar_rr, puma560
from robotica_sim.benchmarks.kinematics import (baseline_fkine, baseline_ikine, baseline_jacob0,
                                                run_kinematics_benchmark)
from robotica_sim.cli.bench import format_table
from robotica_sim.cli.main import main


@pytest.mark.parametrize('robot', [puma560(), planar_rr(4.0, 3.0), cylindrical_rpr(0.3)])
def test_baselines_agree_with_the_library(robot):
    rng = np.random.default_rng(2)
    for q in rng.uniform(robot.qlim[:, 0], robot.qlim[:, 1], size=(5, robot.n)):
        np.testing.assert_allclose(baseline_fkine(robot, q), fkine(robot, q), atol=1e-12)
        np.testing.assert_allclose(baseline_jacob0(robot, q), jacob0(robot, q), atol=1e-12)


def test_baseline_ikine_is_hemero_pinv_newton():
    robot = puma560()
    q_true = np.array([0.2, -0.4, 0.5, 0.1, 0.3, -0.2])   # close to q0 = 0: converges
    q, converged = baseline_ikine(robot, fkine(robot, q_true), np.ones(6))
    assert converged
    np.testing.assert_allclose(fkine(robot, q), fkine(robot, q_true), atol=1e-6)


def test_benchmark_rows_and_table():
    rows = run_kinematics_benchmark(count=5, baseline_ik_count=2, seed=1)
    assert len(rows) == 40
    pairs = {(r.robot, r.function) for r in rows}
    assert pairs >= {('puma560', 'ikine'), ('planar_rrr', 'jacob0')}
    for row in rows:
        assert row.median_us > 0.0
        if row.function == 'ikine':
            assert 0.0 <= row.success_rate <= 1.0
    table = format_table(rows)
    assert table.count('\n') == len(rows) + 1


def test_benchmark_has_each_dynamics_function_against_raw_pinocchio():
    rows = run_kinematics_benchmark(count=5, baseline_ik_count=1, seed=1)
    dynamics = [r for r in rows if r.route == 'robotica' and r.mode.startswith('per call, CPU')]
    assert [r.function for r in dynamics] == ['rne', 'inertia', 'gravity', 'coriolis',
                                              'coriolis_matrix', 'friction',
                                              'fdyn (per evaluation)']
    assert {r.robot for r in dynamics} == {'puma560'}    # the planar 3R has no dyn table
    for ours in dynamics:
        same = [r for r in rows if r.function == ours.function]
        raw = next(r for r in same if r.route.startswith('raw: '))
        assert ours.ratio == pytest.approx(ours.median_us / raw.median_us)
        assert raw.ratio is None and ours.count == raw.count
        floors = [r for r in same if r.route.startswith('floor')]
        if ours.function.startswith('fdyn'):
            assert not floors and ours.count > 5          # evaluations of the right-hand side
        else:
            (floor,) = floors
            assert floor.ratio == pytest.approx(floor.median_us / raw.median_us)
            assert ours.count == floor.count == 5
    assert format_table(rows).count('×') == 14    # the header, 7 robotica and 6 floor ratios


def test_bench_command_json(capsys):
    with pytest.raises(SystemExit) as info:
        main(['bench', 'kin', '--count', '3', '--baseline-ik-count', '1', '--json', '--quiet'])
    assert info.value.code == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == 40 and rows[0]['function'] == 'fkine'
    assert [r['ratio'] is None for r in rows].count(False) == 13


def test_bench_command_refuses_a_zero_count(capsys):
    with pytest.raises(SystemExit) as info:
        main(['bench', 'kin', '--count', '0'])
    assert info.value.code == 2
