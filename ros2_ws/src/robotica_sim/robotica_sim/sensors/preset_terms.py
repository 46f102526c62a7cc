"""
A sensor's error terms as node parameters whose defaults come from a named preset.

The pattern of :mod:`robotica_sim.sensors.gyro`, for models with many terms: a ``preset``
parameter names a datasheet-like set of values (a frozen params dataclass), and every term is
a parameter declared with the preset's value as its default, so that a term given explicitly
(``-p``, ``--params-file``, a scenario) overrides the preset's and an absent one keeps it.
"""

import dataclasses
from typing import Any, Mapping, TypeVar

from robotica_kin.parameter_specs import named_error, parameter_values, ParameterSpec

__all__ = ['params_from_parameters', 'preset_term_specs']

P = TypeVar('P')


def preset_term_specs(terms: Mapping[str, ParameterSpec], presets: Mapping[str, Any],
                      preset_spec: ParameterSpec, preset: str) -> dict[str, ParameterSpec]:
    """
    Return ``terms`` with the values of ``presets[preset]`` as their defaults.

    Raises ParameterError (naming ``preset``) for an unknown preset. A tuple-valued term
    keeps a tuple default (a list parameter).
    """
    preset_spec.check('preset', preset)
    params = presets[preset]
    return {name: dataclasses.replace(spec, default=_plain(getattr(params, name)))
            for name, spec in terms.items()}


def _plain(value: Any) -> Any:
    return tuple(float(v) for v in value) if isinstance(value, tuple) else value


def params_from_parameters(parameters: Mapping[str, Any], specs: Mapping[str, ParameterSpec],
                           terms: Mapping[str, ParameterSpec], presets: Mapping[str, P]) -> P:
    """
    Return the params dataclass of a node's ``parameters``: the preset's, terms replaced.

    ``specs`` holds ``preset`` (and whatever else the node declares); each term of ``terms``
    given in ``parameters`` replaces the preset's value. Raises ParameterError naming the
    parameter for a value out of its range or choices, or refused by the dataclass.
    """
    preset = parameters.get('preset', specs['preset'].default)
    all_specs = {**specs, **preset_term_specs(terms, presets, specs['preset'], preset)}
    values = parameter_values(all_specs, parameters)
    changes = {name: (tuple(values[name]) if isinstance(terms[name].default, tuple)
                      else values[name]) for name in terms}
    try:
        return dataclasses.replace(presets[preset], **changes)   # type: ignore[type-var]
    except ValueError as err:
        raise named_error(err, terms) from None
