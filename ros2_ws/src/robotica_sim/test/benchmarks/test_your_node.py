"""Tests of robotica_sim.benchmarks.your_node: the rows of the built-in/external comparison."""
import pytest
from robotica_sim.benchmarks.your_node import overhead_rows


def summary(rtf: float, cross_track: float, timeouts: int = 0) -> dict:
    return {'real_time_factor': rtf, 'rms_cross_track': cross_track,
            'lockstep_timeouts': timeouts}


def test_overhead_rows():
    builtin = [summary(9.0, 0.0166), summary(11.0, 0.0166), summary(10.0, 0.0166)]
    external = [summary(8.0, 0.0211), summary(7.0, 0.0212, 1), summary(9.0, 0.0211)]
    rows = {row.what: row for row in overhead_rows(builtin, external)}
    assert rows['demo RTF, built-in pure pursuit'].value == 10.0            # median
    assert rows['demo RTF, Python tracker template'].value == 8.0
    assert rows['added wall time of the Python tracker'].value == pytest.approx(25.0)  # 10/8
    assert rows['RMS cross-track, built-in pure pursuit'].value == pytest.approx(16.6)
    assert 'identical in every run' in rows['RMS cross-track, built-in pure pursuit'].detail
    template = rows['RMS cross-track, Python tracker template']
    assert 'DIFFERS between runs' in template.detail
    assert template.detail.endswith('lockstep timeouts 0, 1, 0')
