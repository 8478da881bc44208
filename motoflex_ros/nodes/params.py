"""Node parameters declared with a type and a range, validated once at start-up.

Values come from ``--ros-args -p name:=value`` and ``--params-file FILE`` (read by
``rclpy.init``). Every problem (unknown name, wrong type, out of range, not one of the choices)
raises :class:`ParameterError` naming the node, the parameter and what is allowed; the node's
``main`` turns it into a one-line message and exit code 2. An unknown name that only a
wildcard section of a params file (``/**:``) gives is for another node: it is ignored, with a
debug message.
"""
import math
import sys
from dataclasses import dataclass

import yaml
from rcl_interfaces.msg import ParameterDescriptor

from motoflex_ros.config import shown
from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.ros_args import wildcard_only_names

__all__ = ["Param", "ParameterError", "declare_parameters", "BUILTIN_PARAMETERS",
           "parameters_help", "parameters_yaml"]

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
        converted = _coerce(self.kind, value)
        if converted is None:
            problem = "has the wrong type"
        elif (self.kind in ("int", "float") and not (
                math.isfinite(converted) and self.low <= converted <= self.high)) or (
                self.choices and converted not in self.choices):
            problem = "is not allowed"
        else:
            return converted
        raise ParameterError(f"node '{node_name}': parameter '{self.name}' = {shown(value)} "
                             f"{problem} (expected {self.allowed()})")


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


def declare_parameters(node, params, argv=None):
    """Declare ``params`` on an rclpy ``node``, validate them and return {name: value}.

    Parameters given to the node (``-p`` or a params file section named for it) that are not
    in ``params`` raise :class:`ParameterError` listing the known names; those only a wildcard
    section gives are ignored. ``argv`` is the command line rclpy.init read (default
    ``sys.argv``).
    """
    known = {p.name for p in params}
    unknown = sorted(set(node._parameter_overrides) - known - BUILTIN_PARAMETERS
                     - {n for n in node._parameter_overrides if n.startswith("qos_overrides.")})
    others = wildcard_only_names(sys.argv if argv is None else argv,
                                 node.get_fully_qualified_name())
    for name in (n for n in unknown if n in others):
        node.get_logger().debug(f"ignoring parameter '{name}' of a wildcard params file "
                                f"section: not a parameter of this node")
    unknown = [n for n in unknown if n not in others]
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


def parameters_help(params):
    """Lines describing ``params`` for ``--help``: name, type and range, default, meaning."""
    width = max((len(p.name) for p in params), default=0)
    return [f"  {p.name:<{width}}  {p.allowed()}, default {_default_text(p)}: {p.description}"
            for p in params]


def _default_text(param):
    return repr(list(param.default)) if param.kind == "str[]" else repr(param.default)


def _yaml_value(value):
    """A default as YAML flow text ('' for an empty string, [a, b] for a list)."""
    value = list(value) if isinstance(value, tuple) else value
    return yaml.safe_dump(value, default_flow_style=True).removesuffix("\n...\n").strip()


def parameters_yaml(node_name, params):
    """The text of config/nodes/<node>.yaml: every parameter of ``params`` at its default,
    with its meaning and allowed values (the same words as ``--help``) as a comment. An empty
    list cannot be given in a params file (rcl cannot tell its type): it is commented out."""
    lines = [f"# Default parameters of the {node_name} node:",
             f"#   ros2 run motoflex_ros {node_name} --ros-args --params-file <this file>",
             "# Each value: what it is [unit] (allowed values).",
             f"{node_name}:", "  ros__parameters:"]
    for p in params:
        meaning = f"{p.description} ({p.allowed()})" if p.description else f"({p.allowed()})"
        line = f"{p.name}: {_yaml_value(p.default)}  # {meaning}"
        if p.kind == "str[]" and not p.default:
            line = f"# {line}; empty lists cannot be written here"
        lines.append("    " + line)
    return "\n".join(lines) + "\n"
