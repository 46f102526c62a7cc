"""
Declaring ROS 2 parameters with descriptions, units and ranges in one call.

Every robotica node declares its parameters through :func:`declare`, so that each has a
``ParameterDescriptor`` (description with unit and book symbol, range, read-only flag) and rclpy
refuses an out-of-range value at start-up and at run time (STYLE.md §5).
"""
from typing import Any, Mapping, Optional

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
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
