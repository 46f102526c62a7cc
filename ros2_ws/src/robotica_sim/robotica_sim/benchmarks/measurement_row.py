"""One row of a loop benchmark (``robotica bench arm|mobile``): what, value, unit, how."""

from dataclasses import dataclass

__all__ = ['MeasurementRow']


@dataclass(frozen=True)
class MeasurementRow:
    """One measurement: what, its value and unit, and how it was obtained."""

    what: str
    value: float
    unit: str
    detail: str
