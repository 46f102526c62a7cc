"""Tests of robotica_kin.parameter_specs: a node parameter's range, choices and type as data."""
import math

import pytest
from robotica_kin.parameter_specs import (check_parameters, MAX_SEED, named_error,
                                          parameter_values, ParameterError, ParameterSpec,
                                          seed_spec)

LOOKAHEAD = ParameterSpec(0.5, 'L [m]', 0.01, 100.0)


@pytest.mark.parametrize('value', [0.01, 0.5, 100.0, 1])
def test_a_number_within_the_range_passes(value):
    LOOKAHEAD.check('lookahead_distance', value)   # the bounds are inclusive


@pytest.mark.parametrize('value', [0.0, -1.0, 100.5, math.nan, math.inf, 'far', True])
def test_a_number_outside_the_range_names_the_parameter_and_the_range(value):
    with pytest.raises(ParameterError) as info:
        LOOKAHEAD.check('lookahead_distance', value)
    assert info.value.name == 'lookahead_distance'
    assert info.value.reason == f'must be in [0.01, 100], got {value!r}'
    assert str(info.value) == f'lookahead_distance must be in [0.01, 100], got {value!r}'
    assert isinstance(info.value, ValueError)


def test_every_number_of_a_list_is_checked():
    spec = ParameterSpec((0.0, 0.0, 0.0), 'h [T]', -1e-3, 1e-3)
    spec.check('hard_iron', [1e-4, 0.0, -1e-3])
    with pytest.raises(ParameterError, match=r'must be in \[-0.001, 0.001\], got \[0.0, 0.1\]'):
        spec.check('hard_iron', [0.0, 0.1])


def test_an_integer_parameter_takes_integers_only():
    spec = ParameterSpec(1, 'N1', 1, 200)
    spec.check('n1', 5)
    spec.check('n1', 5.0)   # a YAML 5.0: the plan passes int(5.0)
    with pytest.raises(ParameterError, match='must be an integer, got 2.5'):
        spec.check('n1', 2.5)


def test_choices_and_the_shape_of_a_value():
    spec = ParameterSpec('odom', 'Pose source', choices=('odom', 'ground_truth'))
    spec.check('pose_source', 'ground_truth')
    with pytest.raises(ParameterError, match=r"must be one of \('odom', 'ground_truth'\), got 5"):
        spec.check('pose_source', 5)
    with pytest.raises(ParameterError, match='must be a list of numbers, got 1.0'):
        ParameterSpec((0.0,), 'Times [s]').check('times', 1.0)
    with pytest.raises(ParameterError, match=r'must be one number, got \[0.5, 1.0\]'):
        LOOKAHEAD.check('lookahead_distance', [0.5, 1.0])


def test_values_are_checked_and_defaults_filled_by_name():
    specs = {'seed': seed_spec('Seed'), 'lookahead_distance': LOOKAHEAD}
    assert parameter_values(specs, {'seed': 7, 'frame_id': 'odom'}) == {
        'seed': 7, 'lookahead_distance': 0.5}   # an unknown name is not the specs' business
    check_parameters(specs, {'seed': MAX_SEED})
    with pytest.raises(ParameterError, match='seed must be in'):
        parameter_values(specs, {'seed': MAX_SEED + 1})
    assert MAX_SEED == 2**31 - 1


def test_a_model_error_that_opens_with_a_name_becomes_a_parameter_error():
    err = named_error(ValueError('period must be > 0 s, got [0.0]'), {'period': 0}, 'sine.')
    assert isinstance(err, ParameterError)
    assert (err.name, err.reason) == ('sine.period', 'must be > 0 s, got [0.0]')
    other = ValueError('the model has 6 joints, got 2')
    assert named_error(other, ['kp']) is other
