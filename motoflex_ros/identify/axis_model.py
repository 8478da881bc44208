"""The identified lumped model or axis: values by name, their 95 % intervals, counts."""
from dataclasses import dataclass, field

from motoflex_ros.identify.uncertainty import LEVEL

__all__ = ["AxisModel"]


@dataclass(frozen=True)
class AxisModel:
    """A lumped model or axis: values by name (l [m], beta [rad], b [m], k [N m/rad], J
    [kg m^2], c [N m s/rad], f_hz [Hz]), their intervals and bookkeeping (counts, flags)."""

    values: dict
    ci: dict
    info: dict = field(default_factory=dict)

    def __getitem__(self, key):
        return self.values[key]

    def to_dict(self):
        """Values with their intervals (and counts) under 'ci'."""
        return {**self.values, "ci": {**self.ci, "level": LEVEL, **self.info}}
