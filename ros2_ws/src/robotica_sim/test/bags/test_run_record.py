"""
Tests of robotica_sim.bags.run_record: what a bag says ran, not what the scenario file says.

References are the custom_data texts written here by hand, as ``robotica run`` and the recorder
store them.
"""
from robotica_sim.bags.run_record import custom_data, run_record
from robotica_sim.bags.writer import BagWriter

SCENARIO = 'name: demo\ndescription: Pure pursuit around a rectangle.\npacing: lockstep\n' \
    'duration: 32.0\nseed: 1\nstep_period: 0.02\n'
RUN = ('scenario: demo\nseed: 1\npacing: realtime\nduration: 3.0\nstep_period: 0.02\n'
       'overrides: {pacing: realtime, duration: 3.0}\n'
       'nodes:\n- {name: robotica_run, started_by: robotica, command: robotica run}\n'
       '- {name: path_tracker, started_by: robotica, command: robotica_ctrl/path_tracker}\n'
       '- {name: simulator, started_by: robotica, command: robotica_sim/simulator}\n')
PUBLISHERS = ('/clock: [/simulator]\n/cmd_vel: [/my_controller]\n'
              '/rosout: [/my_controller, /path_tracker, /simulator]\n')


def test_the_settings_are_those_that_ran_with_the_overrides():
    record = run_record({'robotica.scenario.yaml': SCENARIO, 'robotica.run.yaml': RUN})
    assert record.settings == {'seed': 1, 'pacing': 'realtime', 'duration': 3.0,
                               'step_period': 0.02}
    assert record.settings_from == 'run'
    lines = dict(record.lines())
    assert lines['Run'] == ('seed 1, pacing realtime, duration 3 s, step period 0.02 s (as run, '
                            'overridden: pacing realtime, duration 3.0)')
    assert lines['Nodes'] == 'robotica_run, path_tracker, simulator (started by robotica run)'


def test_an_old_bag_falls_back_to_the_scenario_file_and_says_so():
    record = run_record({'robotica.scenario.yaml': SCENARIO})
    assert record.settings['pacing'] == 'lockstep' and record.settings_from == 'scenario file'
    assert 'from the scenario file' in dict(record.lines())['Run']


def test_a_users_node_is_named_and_the_description_is_qualified():
    record = run_record({'robotica.scenario.yaml': SCENARIO, 'robotica.run.yaml': RUN,
                         'robotica.publishers': PUBLISHERS})
    assert [n.name for n in record.foreign_nodes] == ['my_controller']
    text = '\n'.join(t for _, t in record.lines())
    assert 'my_controller: not started by robotica run (published /cmd_vel)' in text
    assert ("Pure pursuit around a rectangle. (the scenario's words; nodes not started by "
            'robotica run also published: my_controller)') in text
    tracker = next(n for n in record.nodes if n.name == 'path_tracker')
    assert tracker.started_by == 'robotica' and tracker.topics == ('/rosout',)


def test_a_bag_recorded_by_hand_lists_its_publishers():
    record = run_record({'robotica.publishers': PUBLISHERS})
    lines = record.lines()
    assert lines[0] == ('Run', 'no run settings in the bag (recorded outside robotica run)')
    assert ('Nodes', 'my_controller: not started by robotica run (published /cmd_vel)') in lines


def test_custom_data_set_while_recording_reaches_the_metadata(tmp_path):
    writer = BagWriter(tmp_path / 'bag', custom_data={'robotica.run.yaml': RUN})
    writer.set_custom_data('robotica.publishers', PUBLISHERS)
    writer.close()
    assert custom_data(tmp_path / 'bag') == {'robotica.run.yaml': RUN,
                                             'robotica.publishers': PUBLISHERS}
    assert custom_data(tmp_path / 'missing') == {}
