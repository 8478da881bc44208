"""Node parameters declared with a type and a range, validated once at start-up.

Values come from ``--ros-args -p name:=value`` and ``--params-file FILE`` (read by
``rclpy.init``). Every problem (unknown name, wrong type, out of range, not one of the choices)
raises :class:`ParameterError` naming the node, the parameter and what is allowed; the node's
``main`` turns it into a one-line message and exit code 2.
"""
import math
from dataclasses import dataclass

from motoflex_ros.errors import MotoflexError

__all__ = ["Param", "ParameterError", "declare_parameters", "BUILTIN_PARAMETERS"]

# parameters every rclpy node may receive without declaring them here
BUILTIN_PARAMETERS = frozenset({"use_sim_time", "start_type_description_service"})


class ParameterError(MotoflexError):
    """A node parameter is unknown, of the wrong type or out of its range."""


@dataclass(frozen=True)
class Param:
    """One node parameter: name, default (its type is the parameter's type), closed range
    ``[low, high]`` for numbers, allowed ``choices`` for strings, and a description with units.
    """

    name: str
    default: object
    low: float = -math.inf
    high: float = math.inf
    choices: tuple = ()
    description: str = ""

    @property
    def kind(self):
        """'bool', 'int', 'float', 'str' or 'str[]'."""
        if isinstance(self.default, bool):
            return "bool"
        if isinstance(self.default, (list, tuple)):
            return "str[]"
        return type(self.default).__name__

    def allowed(self):
        """Human-readable allowed values."""
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind in ("int", "float"):
            return f"{self.kind} in [{self.low:g}, {self.high:g}]"
        return self.kind

    def check(self, node_name, value):
        """Return ``value`` converted to the parameter's type, or raise ParameterError."""
        value = _coerce(self.kind, value)
        bad = value is None
        if not bad and self.kind in ("int", "float"):
            bad = not (math.isfinite(value) and self.low <= value <= self.high)
        if not bad and self.choices:
            bad = value not in self.choices
        if bad:
            raise ParameterError(f"node '{node_name}': parameter '{self.name}' = {value!r} is "
                                 f"not allowed (expected {self.allowed()})"
                                 .replace("= None", "has the wrong type"))
        return value


def _coerce(kind, value):
    if kind == "bool":
        return value if isinstance(value, bool) else None
    if kind == "int":
        return value if isinstance(value, int) and not isinstance(value, bool) else None
    if kind == "float":
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        return float(value) if ok else None
    if kind == "str":
        return value if isinstance(value, str) else None
    if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        return tuple(value)
    return None


def declare_parameters(node, params):
    """Declare ``params`` on an rclpy ``node``, validate them and return {name: value}.

    Parameters given to the node (command line or params file) that are not in ``params`` raise
    :class:`ParameterError` listing the known names.
    """
    from rcl_interfaces.msg import ParameterDescriptor

    known = {p.name for p in params}
    unknown = sorted(set(node._parameter_overrides) - known - BUILTIN_PARAMETERS
                     - {n for n in node._parameter_overrides if n.startswith("qos_overrides.")})
    if unknown:
        raise ParameterError(f"node '{node.get_name()}': unknown parameter '{unknown[0]}' "
                             f"(known: {', '.join(sorted(known))})")
    values = {}
    for p in params:
        descriptor = ParameterDescriptor(description=f"{p.description} ({p.allowed()})",
                                         dynamic_typing=True)
        default = list(p.default) if p.kind == "str[]" else p.default
        value = node.declare_parameter(p.name, default, descriptor).value
        values[p.name] = p.check(node.get_name(), value)
    return values
