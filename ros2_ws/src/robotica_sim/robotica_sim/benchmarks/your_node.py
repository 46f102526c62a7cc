"""
What a user's node costs a run: the demo with robotica's tracker and with a Python one.

:func:`your_node_benchmark` writes the tracker template of ``robotica new`` (a proportional
heading tracker in plain rclpy, its scenario: the demo's robot, path and sensors) into a
temporary folder and runs ``robotica run demo`` (the built-in pure pursuit) and the template's
scenario ``n`` times each, alternating (so that a drift of the machine's load hits both), with
the visualisation on as in the demo. It reports the real-time factor of each (median, spread),
the wall time the user's node adds per simulated second, and each run's RMS cross-track (the
laws differ, so the values do; each must be the same in every run: lockstep runs of one seed).
"""
from pathlib import Path
import statistics
import tempfile
from typing import Callable, Optional

from robotica_sim.benchmarks.measurement_row import MeasurementRow
from robotica_sim.benchmarks.visualisation import demo_run, spread_row
from robotica_sim.runs.templates import render_template

NAME = 'bench_tracker'


def overhead_rows(builtin: list[dict], external: list[dict]) -> list[MeasurementRow]:
    """
    Return the comparison rows from the runs' ``--json`` summaries.

    The added cost is the wall time per simulated second with the user's node over the time
    with robotica's, minus one: ``median(RTF built-in) / median(RTF external) - 1``.

    >>> rows = overhead_rows([{'real_time_factor': 10.0, 'rms_cross_track': 0.0166,
    ...                        'lockstep_timeouts': 0}],
    ...                      [{'real_time_factor': 8.0, 'rms_cross_track': 0.0211,
    ...                        'lockstep_timeouts': 0}])
    >>> rows[2].what, rows[2].value
    ('added wall time of the Python tracker', 25.0)
    """
    rtf_in = [float(run['real_time_factor']) for run in builtin]
    rtf_out = [float(run['real_time_factor']) for run in external]
    median_in, median_out = statistics.median(rtf_in), statistics.median(rtf_out)

    def cross_track(runs: list[dict], which: str) -> MeasurementRow:
        values = [run['rms_cross_track'] for run in runs]
        same = 'identical in every run' if len(set(values)) == 1 else 'DIFFERS between runs'
        return MeasurementRow(f'RMS cross-track, {which}', 1e3 * statistics.median(values), 'mm',
                              f'{values[0]:.6f} m; {same}; lockstep timeouts '
                              + ', '.join(str(run['lockstep_timeouts']) for run in runs))

    return [
        spread_row('demo RTF, built-in pure pursuit', rtf_in, '×', 'robotica run demo'),
        spread_row('demo RTF, Python tracker template', rtf_out, '×',
                   f'robotica new tracker {NAME}; robotica run {NAME}.yaml'),
        MeasurementRow('added wall time of the Python tracker',
                       100.0 * (median_in / median_out - 1.0), '%',
                       f'median RTF built-in / external - 1 ({median_in:.2f} / {median_out:.2f})'),
        cross_track(builtin, 'built-in pure pursuit'),
        cross_track(external, 'Python tracker template'),
    ]


def your_node_benchmark(count: int = 3, progress: Optional[Callable[[str], None]] = None
                        ) -> list[MeasurementRow]:
    """Run the demo and the tracker template's scenario ``count`` times each, interleaved."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for file_name, text in render_template('tracker', NAME).items():
            (folder / file_name).write_text(text)
        runs: dict[str, list[dict]] = {'demo': [], NAME: []}
        for k in range(count):
            for which in runs:
                if progress:
                    progress(f'run {k + 1}/{count}: {which}')
                scenario = 'demo' if which == 'demo' else str(folder / f'{NAME}.yaml')
                runs[which].append(demo_run(folder / f'{which}-{k}', scenario=scenario))
    return overhead_rows(runs['demo'], runs[NAME])
