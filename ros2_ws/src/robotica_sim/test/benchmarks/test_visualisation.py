"""
Tests of robotica_sim.benchmarks.visualisation: the relay log's summary, the tables, one run.

The pure parts are checked on hand-written logs and counts against values computed by hand;
one short end-to-end benchmark (slow) checks that the viewer's nodes leave the result alone.
"""
import pytest
from robotica_sim.bags.info import bag_info
from robotica_sim.benchmarks.visualisation import (cost_rows, demo_run, parse_relay_summary,
                                                   relay_rows, relay_run)

LOG = """\
[INFO] [1795594627.008542480] [view_relay]: relaying /robot_description [std_msgs/msg/String]
[INFO] [1795594642.416262952] [view_relay.summary]: forwarded 8160 messages: /tf 4803, \
/clock 1601, /odom 1601, /markers 65, /parameter_events 44, /rosout 43, /tf_static 2, /path 1
"""


def test_parse_relay_summary():
    assert parse_relay_summary(LOG) == {
        '/tf': 4803, '/clock': 1601, '/odom': 1601, '/markers': 65, '/parameter_events': 44,
        '/rosout': 43, '/tf_static': 2, '/path': 1}


def test_parse_relay_summary_takes_the_last_and_refuses_a_wrong_total():
    second = '[INFO] [2.0] [view_relay.summary]: forwarded 3 messages: /odom 3\n'
    assert parse_relay_summary(LOG + second) == {'/odom': 3}
    with pytest.raises(ValueError, match='add up to 3, not 4'):
        parse_relay_summary('[INFO] [2.0] [view_relay.summary]: forwarded 4 messages: /a 1, '
                            '/b 2\n')
    with pytest.raises(ValueError, match='no summary line'):
        parse_relay_summary('[INFO] [1.0] [view_relay]: relaying /odom\n')


def test_relay_rows():
    forwarded = {'/tf': 300, '/odom': 100, '/parameter_events': 4}
    recorded = {'/tf': 297, '/odom': 102, '/markers': 5}
    rows = relay_rows(forwarded, recorded, 2.0)
    assert rows[0].what == 'view relay throughput'
    assert rows[0].value == pytest.approx(202.0)          # 404 messages / 2 s
    assert '2 lost' in rows[0].detail                     # the bag's 2 more /odom
    by_topic = {row.what: row for row in rows[1:]}
    assert [row.what for row in rows[1:]] == ['relay /tf', 'relay /odom',
                                              'relay /parameter_events']
    assert by_topic['relay /odom'].detail == 'recorded 102, lost 2'
    assert by_topic['relay /tf'].detail == 'recorded 297, lost 0 (the bag has 3 fewer)'
    assert by_topic['relay /parameter_events'].detail == 'not recorded'


def runs(rtfs, crosses, timeouts):
    """Return the ``robotica run --json`` summaries the cost rows read."""
    return [{'real_time_factor': r, 'rms_cross_track': c, 'lockstep_timeouts': t}
            for r, c, t in zip(rtfs, crosses, timeouts)]


def test_cost_rows():
    rows = cost_rows(runs([4.0, 3.0, 3.5], [0.0166] * 3, [0, 0, 0]),
                     runs([5.0, 4.5, 4.0], [0.0166] * 3, [0, 0, 0]))
    on, off, cost, cross_on, cross_off = rows
    assert (on.value, off.value) == (3.5, 4.5)
    assert on.detail.endswith('3 runs: 4.00, 3.00, 3.50; spread 1.00')
    assert cost.value == pytest.approx(100.0 * (4.5 / 3.5 - 1.0))   # 28.57 %
    assert 'RTF difference 1.00' in cost.detail
    assert cross_on.value == cross_off.value == pytest.approx(16.6)  # mm
    assert cross_on.detail == '0.016600 m, 0.016600 m, 0.016600 m; lockstep timeouts 0, 0, 0'
    assert cross_off.detail.endswith('identical in every run')
    differs = cost_rows(runs([1.0], [0.0166], [0]), runs([1.0], [0.0167], [3]))[-1]
    assert differs.detail == '0.016700 m; lockstep timeouts 3; DIFFERS between runs'


@pytest.mark.slow
def test_relay_run_and_a_run_without_the_viewer(tmp_path):
    """
    The demo once with the relay, once without TF and markers (76 s at load average 11).

    The cross-track is the demo's 0.0166 m both ways (to 0.1 mm: a lockstep timeout on a loaded
    machine moves it by up to 0.04 mm). The interleaved on/off runs are the benchmark's.
    """
    rows = {row.what: row for row in relay_run(tmp_path / 'view')}
    assert rows['view relay throughput'].value > 0.0
    assert rows['relay /odom'].value > 0
    # What the bag holds of the relay's topics: every step (32 s at 50 Hz + the first; 3
    # transforms a step), or one more when a node answers the run's stop (seen once for /odom).
    in_bag = {topic: int(rows[f'relay {topic}'].detail.split(',')[0].split()[1])
              for topic in ('/odom', '/tf')}
    assert in_bag['/odom'] in (1601, 1602) and in_bag['/tf'] in (4803, 4806)
    off = demo_run(tmp_path / 'off', visualisation=False)
    assert off['rms_cross_track'] == pytest.approx(0.016551, abs=1e-4)
    recorded = {topic.name for topic in bag_info(tmp_path / 'off' / 'bag').topics}
    assert '/odom' in recorded
    assert not recorded & {'/tf', '/tf_static', '/robot_description', '/markers'}
