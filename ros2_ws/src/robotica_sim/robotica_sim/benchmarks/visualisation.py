"""
What the viewer costs: the demo with and without TF and markers, and the Foxglove relay's load.

:func:`visualisation_benchmark` runs ``robotica run demo`` ``n`` times with the scenario's
``visualisation`` on and ``n`` times off, alternating (on, off, on, off, ...: the same binary on
the same machine, so that a drift of its load hits both), and reports the real-time factor of
each setting (median, spread), the added wall time of TF and markers, and the RMS cross-track of
each (the viewer's nodes must not change the result). Then one run with ``--view`` (the
``view_relay`` node started with the run) compares the messages the relay forwarded per topic,
as its log's summary line gives them at exit, with the bag's count of each topic, and divides
the forwarded messages by the wall time of the simulated run (duration / real-time factor).
"""
import json
import os
from pathlib import Path
import statistics
import subprocess
import tempfile
from typing import Callable, Optional

from robotica_sim.bags.info import bag_info
from robotica_sim.benchmarks.measurement_row import MeasurementRow

SCENARIO = 'demo'
SUMMARY_PREFIX = 'forwarded '
VIEW_PORT = 8766   # the relay's port in the benchmark: not the default 8765 a user may hold


def parse_relay_summary(log: str) -> dict[str, int]:
    """
    Return the messages forwarded per topic from a view relay's log (its last summary line).

    >>> parse_relay_summary('[INFO] [1.0] [view_relay.summary]: forwarded 7 messages: '
    ...                     '/odom 5, /tf 2')
    {'/odom': 5, '/tf': 2}
    """
    lines = [line for line in log.splitlines() if '.summary]: forwarded ' in line]
    if not lines:
        raise ValueError('no summary line (forwarded N messages: ...) in the relay log')
    text = lines[-1].split('.summary]: ', 1)[1]
    head, _, body = text.partition(': ')
    total = int(head.removeprefix(SUMMARY_PREFIX).removesuffix(' messages'))
    counts = {}
    for item in filter(None, body.split(', ')):
        topic, count = item.rsplit(' ', 1)
        counts[topic] = int(count)
    if sum(counts.values()) != total:
        raise ValueError(f'relay summary: the topics add up to {sum(counts.values())}, '
                         f'not {total}')
    return counts


def spread_row(what: str, values: list[float], unit: str, detail: str) -> MeasurementRow:
    """
    Return the median of ``values`` with their spread (max - min) and each value in the detail.

    >>> spread_row('RTF', [4.0, 5.0, 3.0], '×', 'demo').detail
    'demo; 3 runs: 4.00, 5.00, 3.00; spread 2.00'
    """
    listed = ', '.join(f'{v:.2f}' for v in values)
    return MeasurementRow(what, statistics.median(values), unit,
                          f'{detail}; {len(values)} runs: {listed}; '
                          f'spread {max(values) - min(values):.2f}')


def cost_rows(on: list[dict], off: list[dict]) -> list[MeasurementRow]:
    """
    Return the rows of the with/without comparison from the runs' ``--json`` summaries.

    The added cost is the wall time per simulated second with TF and markers over the time
    without, minus one: ``median(off) / median(on) - 1``. The cross-track is in mm, with each
    run's value and its lockstep timeouts (a timeout lets the simulator step without a late
    node's answer: the result may change, with or without the viewer).
    """
    def values(runs: list[dict], key: str) -> list[float]:
        return [float(run[key]) for run in runs]

    rtf_on, rtf_off = values(on, 'real_time_factor'), values(off, 'real_time_factor')
    median_on, median_off = statistics.median(rtf_on), statistics.median(rtf_off)
    same = len(set(values(on + off, 'rms_cross_track'))) == 1

    def cross_track(runs: list[dict], setting: str, note: str = '') -> MeasurementRow:
        return MeasurementRow(
            f'RMS cross-track, visualisation {setting}',
            1e3 * statistics.median(values(runs, 'rms_cross_track')), 'mm',
            ', '.join(f'{run["rms_cross_track"]:.6f} m' for run in runs)
            + '; lockstep timeouts ' + ', '.join(str(run['lockstep_timeouts']) for run in runs)
            + note)

    return [
        spread_row('demo RTF, visualisation on', rtf_on, '×',
                   'state_publisher, markers, /tf of odometry and simulator'),
        spread_row('demo RTF, visualisation off', rtf_off, '×', 'visualisation: false'),
        MeasurementRow('added wall time of TF and markers', 100.0 * (median_off / median_on - 1.0),
                       '%', f'median RTF off / on - 1 ({median_off:.2f} / {median_on:.2f}); RTF '
                       f'difference {median_off - median_on:.2f}'),
        cross_track(on, 'on'),
        cross_track(off, 'off', '; identical in every run' if same else '; DIFFERS between runs'),
    ]


def relay_rows(forwarded: dict[str, int], recorded: dict[str, int],
               wall: float) -> list[MeasurementRow]:
    """
    Return the relay's throughput and, per topic it forwarded, forwarded vs recorded.

    ``lost`` is recorded - forwarded, counted only where the bag has more; a topic the bag does
    not record (``/parameter_events``) is forwarded only.
    """
    total = sum(forwarded.values())
    lost = sum(max(recorded.get(topic, 0) - count, 0) for topic, count in forwarded.items()
               if topic in recorded)
    rows = [MeasurementRow('view relay throughput', total / wall, 'msg/s',
                           f'{total} messages forwarded in {wall:.2f} s (duration / RTF), '
                           f'{lost} lost')]
    for topic, count in sorted(forwarded.items(), key=lambda item: (-item[1], item[0])):
        if topic in recorded:
            detail = (f'recorded {recorded[topic]}, lost '
                      f'{max(recorded[topic] - count, 0)}')
            if count > recorded[topic]:
                detail += f' (the bag has {count - recorded[topic]} fewer)'
        else:
            detail = 'not recorded'
        rows.append(MeasurementRow(f'relay {topic}', count, 'msg', detail))
    return rows


def demo_run(run_dir: Path, visualisation: bool = True, view: bool = False,
             scenario: str = SCENARIO) -> dict:
    """Run ``robotica run demo`` (or ``scenario``) into ``run_dir``; return its JSON summary."""
    command = ['robotica', 'run', scenario, '--output-dir', str(run_dir), '--json', '--quiet',
               '--visualisation', 'on' if visualisation else 'off']
    if view:
        command += ['--view', '--port', str(VIEW_PORT)]
    proc = subprocess.run(command, capture_output=True, text=True, env=dict(os.environ),
                          timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f'robotica run failed ({proc.returncode}): {proc.stderr.strip()}')
    return json.loads(proc.stdout)


def relay_run(run_dir: Path) -> list[MeasurementRow]:
    """Run the demo with ``--view`` into ``run_dir``; return the relay's rows and the RTF."""
    summary = demo_run(run_dir, view=True)
    forwarded = parse_relay_summary((run_dir / 'logs' / 'view_relay.log').read_text())
    recorded = {t.name: t.count for t in bag_info(run_dir / 'bag').topics}
    wall = summary['duration'] / summary['real_time_factor']
    return relay_rows(forwarded, recorded, wall) + [
        MeasurementRow('demo RTF with --view', summary['real_time_factor'], '×',
                       'visualisation on and the relay (no client connected)')]


def visualisation_benchmark(count: int = 3, view: bool = True,
                            progress: Optional[Callable[[str], None]] = None
                            ) -> list[MeasurementRow]:
    """Run the demo ``count`` times each way, interleaved, then once with ``--view``."""
    with tempfile.TemporaryDirectory() as tmp:
        runs: dict[bool, list[dict]] = {True: [], False: []}
        for k in range(count):
            for on in (True, False):
                if progress:
                    progress(f'demo {k + 1}/{count}, visualisation {"on" if on else "off"}')
                runs[on].append(demo_run(Path(tmp) / f'{k}-{on}', visualisation=on))
        rows = cost_rows(runs[True], runs[False])
        if view:
            if progress:
                progress('demo with --view')
            rows += relay_run(Path(tmp) / 'view')
    return rows
