"""
Tests of robotica_sim.benchmarks.raycast and ``robotica bench raycast``.

The baselines must compute the same ranges as ``cast_rays`` (or the comparison means nothing).
"""
import json
import math

import numpy as np
import pytest

from robotica_kin.world import cast_rays, OccupancyGrid, World
from robotica_sim.benchmarks.raycast import baseline_grid, baseline_segments, raycast_benchmark
from robotica_sim.cli.main import main


def test_baselines_agree_with_cast_rays():
    rng = np.random.default_rng(4)
    segments = rng.uniform(0.0, 5.0, (30, 4))
    angles = rng.uniform(-math.pi, math.pi, 50)
    origin = np.array([2.5, 2.5])
    np.testing.assert_allclose(baseline_segments(segments, origin, angles, 4.0),
                               cast_rays(World(walls=segments), origin, angles, 4.0).ranges)
    grid = OccupancyGrid(np.where(rng.random((40, 40)) < 0.05, 100, 0).astype(np.int8), 0.1)
    free = np.array([1.234, 2.345])
    if grid.occupied[23, 12]:
        free = np.array([0.05, 0.05])
    np.testing.assert_allclose(baseline_grid(grid, free, angles, 3.0),
                               cast_rays(World(grid=grid), free, angles, 3.0).ranges)


def test_rows_and_cli(capsys):
    rows = raycast_benchmark(scans=2)
    assert len(rows) == 7
    assert all(row.value > 0.0 for row in rows)
    assert all('same ranges: False' not in row.detail for row in rows)
    with pytest.raises(SystemExit) as info:
        main(['bench', 'raycast', '--count', '2', '--json', '--quiet'])
    assert info.value.code == 0
    printed = json.loads(capsys.readouterr().out)
    assert [row['what'] for row in printed] == [row.what for row in rows]
