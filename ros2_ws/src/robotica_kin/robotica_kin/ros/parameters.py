"""
Declaring ROS 2 parameters with descriptions, units and ranges in one call.

Every robotica node declares its parameters through :func:`declare`, so that each has a
``ParameterDescriptor`` (description with unit and book symbol, range, read-only flag) and rclpy
refuses an out-of-range value at start-up and at run time (STYLE.md §5).
"""
from typing import Any, Callable, Mapping, Optional

from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
from rclpy.node import Node
from robotica_kin.parameter_specs import ParameterSpec


def declare(node: Node, name: str, default: Any, description: str, *,
            low: Optional[float] = None, high: Optional[float] = None,
            read_only: bool = False) -> Any:
    """
    Declare parameter ``name`` on ``node`` and return its value.

    ``low``/``high`` give an inclusive range for a float or integer parameter (both or neither).
    """
    descriptor = ParameterDescriptor(description=description, read_only=read_only)
    if low is not None and high is not None:
        if isinstance(default, bool) or not isinstance(default, (int, float)):
            raise TypeError(f'parameter {name}: a range needs a numeric default')
        if isinstance(default, int):
            descriptor.integer_range = [IntegerRange(from_value=int(low), to_value=int(high))]
        else:
            descriptor.floating_point_range = [FloatingPointRange(from_value=float(low),
                                                                  to_value=float(high))]
    return node.declare_parameter(name, default, descriptor).value


def declare_specs(node: Node, specs: Mapping[str, ParameterSpec], *,
                  read_only: bool = True) -> dict[str, Any]:
    """
    Declare every parameter of ``specs`` (name -> spec) on ``node``; return their values.

    Each with its spec's default, description (and choices) and range: the specs are the ones
    a plan checks before the node starts (:mod:`robotica_kin.parameter_specs`). rclpy bounds
    only a number, so the choices and the range of a list are left to the core function that
    takes the values (through :func:`~robotica_kin.parameter_specs.parameter_values`).
    """
    values = {}
    for name, spec in specs.items():
        is_list = isinstance(spec.default, tuple)
        values[name] = declare(
            node, name, list(spec.default) if is_list else spec.default,
            spec.description + (f': one of {spec.choices}' if spec.choices else ''),
            low=None if is_list else spec.low, high=None if is_list else spec.high,
            read_only=read_only)
    return values


def check_on_set(node: Node, values: dict[str, Any], build: Callable[[dict[str, Any]], Any],
                 apply: Callable[[Any], None]) -> None:
    """
    Check each run-time set of the parameters named in ``values`` and apply what passes.

    ``values`` holds the node's current values of those parameters (it is updated in place);
    ``build`` turns a whole set of them into the core's object (a params dataclass) and raises
    ValueError for an invalid one: a set is refused with that reason (STYLE.md §5, never
    accepted and ignored), an accepted one is built again and handed to ``apply``. Other
    parameters are left to their own callbacks.
    """
    def changes(parameters) -> dict[str, Any]:
        return {p.name: p.value for p in parameters if p.name in values}

    def validate(parameters) -> SetParametersResult:
        try:   # the ranges and the core's own checks, on a throw-away copy
            build({**values, **changes(parameters)})
        except ValueError as err:
            return SetParametersResult(successful=False, reason=str(err))
        return SetParametersResult(successful=True)

    def post_set(parameters) -> None:
        changed = changes(parameters)
        if changed:
            values.update(changed)
            apply(build(values))
            node.get_logger().info(f'parameters changed: {changed}')

    node.add_on_set_parameters_callback(validate)
    node.add_post_set_parameters_callback(post_set)
