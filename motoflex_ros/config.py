"""Loading and validating the YAML configuration in ``config/``.

Every file is checked against a declarative schema of :class:`Field` objects. Unknown keys,
missing keys, wrong types, NaN and values out of range raise :class:`ConfigError` with a message
that names the file, the dotted key and the allowed range. Numbers are SI unless the key says
otherwise (``pitch_deg``, ``speed_kmh``).

The shipped configuration lives inside the package (``motoflex_ros/config``, also reachable as
``config/`` at the repository root) and is found with :mod:`importlib.resources`, so it works in
a colcon install, a pip install and an editable install alike.

Why not jsonschema (measured 2026-12 with jsonschema 4.26 on this machine, the schemas
translated one to one): it accepts NaN where a range is given (NaN compares false with both
bounds), its message names neither the file nor the allowed range ("-5.0 is less than or equal
to the minimum of 0.0"), and it neither fills the defaults nor normalises (ints to floats, an
int of hundreds of digits), so a translation layer as long as this validator would remain;
and it took 9-10x as long (1.8 ms against 0.2 ms for config/vehicles/touring.yaml, 2.6 against
0.25 ms for config/components/frame.yaml, best of 20, in one run).
"""
import math
import re
import reprlib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import yaml

from motoflex_ros.errors import ConfigError
from motoflex_ros.files import missing_file_text
from motoflex_ros.input_pins import read_input

__all__ = ["MOTORCYCLE_COMPONENTS", "Field", "number", "positive", "angle", "validate",
           "load_yaml", "load_config", "config_path", "resolve_config", "shipped_configs",
           "MAX_YAML_BYTES", "MAX_ALIAS_VALUES", "shown", "number_text"]

_INF = math.inf

MOTORCYCLE_COMPONENTS = ("frame", "front_assembly", "swingarm")
"""The paper's three components, each with a shipped config/components/<name>.yaml."""


@dataclass(frozen=True)
class Field:
    """Schema of one configuration value.

    kind: 'float', 'int', 'str', 'bool', 'vec3', 'mapping' (with ``fields``), 'list' (with
    ``item``) or 'any'. Numeric bounds: ``low``/``high`` with ``open_low``/``open_high``
    saying whether the bound itself is excluded. ``required=False`` uses ``default``.
    ``extra=True`` on a mapping allows keys that are not in ``fields`` (validated by ``item``).
    """

    kind: str
    low: float = -_INF
    high: float = _INF
    open_low: bool = False
    open_high: bool = False
    required: bool = True
    default: object = None
    choices: tuple = ()
    fields: dict = field(default_factory=dict)
    item: "Field" = None
    extra: bool = False
    min_items: int = 0
    help: str = ""


def number(low=-_INF, high=_INF, open_low=False, open_high=False, **kw):
    """A real number in the given range."""
    return Field("float", low, high, open_low, open_high, **kw)


def positive(high=_INF, **kw):
    """A real number in (0, high] (stiffness, modulus, density, length, mass...)."""
    return Field("float", 0.0, high, True, False, **kw)


def angle(low_deg=-180.0, high_deg=180.0, **kw):
    """An angle in degrees within [low_deg, high_deg]."""
    return Field("float", low_deg, high_deg, **kw)


_SHORT = reprlib.Repr()
_SHORT.maxlevel, _SHORT.maxlist, _SHORT.maxdict, _SHORT.maxstring, _SHORT.maxother = \
    2, 4, 4, 60, 60


def shown(value):
    """``repr(value)`` cut short (at most a few items, two levels, 60 characters a string):
    what an error message quotes of a value, never the whole of a huge or recursive one."""
    return _SHORT.repr(value)


def number_text(value):
    """``value`` with as many digits as it needs to be read back exactly, shortest form:
    0.49999999 stays 0.49999999 (``:g`` would print 0.5), 2.1e11 stays 2.1e+11."""
    value = float(value)
    short = f"{value:g}"
    return short if float(short) == value else repr(value)


def _range_text(spec):
    lo = "[" if not spec.open_low else "("
    hi = "]" if not spec.open_high else ")"
    low = "-inf" if spec.low == -_INF else number_text(spec.low)
    high = "inf" if spec.high == _INF else number_text(spec.high)
    if spec.low == -_INF:
        lo = "("
    if spec.high == _INF:
        hi = ")"
    return f"{lo}{low}, {high}{hi}"


def _check_number(value, spec, source, key):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(source, key, f"expected a number in {_range_text(spec)}, "
                                       f"got {type(value).__name__} {shown(value)}")
    try:
        value = float(value)
    except OverflowError:   # a whole number with hundreds of digits
        value = _INF if value > 0 else -_INF
    if math.isnan(value) or math.isinf(value):
        raise ConfigError(source, key, f"expected a finite number in {_range_text(spec)}, "
                                       f"got {value}")
    too_low = value < spec.low or (spec.open_low and value == spec.low)
    too_high = value > spec.high or (spec.open_high and value == spec.high)
    if too_low or too_high:
        raise ConfigError(source, key, f"value {number_text(value)} is out of the allowed range "
                                       f"{_range_text(spec)}")
    return value


def _check_mapping(value, spec, source, key):
    if not isinstance(value, dict):
        raise ConfigError(source, key or "(top level)",
                          f"expected a mapping, got {type(value).__name__}")
    out = {}
    for name, sub in spec.fields.items():
        sub_key = f"{key}.{name}" if key else name
        if name in value:
            out[name] = validate(value[name], sub, source, sub_key)
        elif sub.required:
            allowed = sub.help or sub.kind
            raise ConfigError(source, sub_key, f"missing (required: {allowed})")
        else:
            out[name] = sub.default
    for name in value:
        if name in spec.fields:
            continue
        sub_key = f"{key}.{name}" if key else str(name)
        if not spec.extra:
            known = ", ".join(sorted(spec.fields)) or "none"
            raise ConfigError(source, sub_key, f"unknown key (allowed keys: {known})")
        out[name] = validate(value[name], spec.item, source, sub_key) if spec.item else value[name]
    return out


def _check_list(value, spec, source, key):
    if not isinstance(value, list):
        raise ConfigError(source, key, f"expected a list, got {type(value).__name__}")
    if len(value) < spec.min_items:
        raise ConfigError(source, key, f"expected at least {spec.min_items} items, "
                                       f"got {len(value)}")
    if spec.item is None:
        return list(value)
    return [validate(v, spec.item, source, f"{key}[{i}]") for i, v in enumerate(value)]


def validate(value, spec, source, key=""):
    """Validate ``value`` against ``spec``; return the normalised value or raise ConfigError."""
    if spec.kind in ("float", "int"):
        out = _check_number(value, spec, source, key)
        if spec.kind == "int":
            if out != int(out):
                raise ConfigError(source, key, f"expected a whole number in {_range_text(spec)}")
            out = int(out)
        return out
    if spec.kind == "str":
        if not isinstance(value, str):
            raise ConfigError(source, key, f"expected a string, got {type(value).__name__}")
        if spec.choices and value not in spec.choices:
            raise ConfigError(source, key, f"'{value}' is not one of: {', '.join(spec.choices)}")
        return value
    if spec.kind == "bool":
        if not isinstance(value, bool):
            raise ConfigError(source, key, f"expected true or false, got {shown(value)}")
        return value
    if spec.kind == "vec3":
        if not isinstance(value, list) or len(value) != 3:
            raise ConfigError(source, key, f"expected a list of 3 numbers [m], got "
                                           f"{shown(value)}")
        elem = Field("float", spec.low, spec.high, spec.open_low, spec.open_high)
        return [_check_number(v, elem, source, f"{key}[{i}]") for i, v in enumerate(value)]
    if spec.kind == "mapping":
        return _check_mapping(value, spec, source, key)
    if spec.kind == "list":
        return _check_list(value, spec, source, key)
    return value


class _Loader(getattr(yaml, "CSafeLoader", yaml.SafeLoader)):
    """Safe loader (libyaml when present) that also reads floats like 2.1e11 (YAML 1.2)."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"))


MAX_YAML_BYTES = 1_000_000
"""Largest configuration file read [bytes] (the shipped ones are below 20 kB)."""

MAX_ALIAS_VALUES = 100_000
"""Most values aliases (``*name``) may add to a configuration file when expanded; a 600-byte
file of nested aliases otherwise stands for billions of values (an alias bomb)."""


def _check_aliases(root, source):
    """ConfigError when the aliases of the composed YAML node tree ``root`` expand to more than
    MAX_ALIAS_VALUES values beyond the file's own, or an alias refers to the value that holds
    it (a loop). Each node is counted once (linear in the file, whatever the expansion)."""
    sizes, stack = {}, [(root, False)]
    while stack:
        node, children_done = stack.pop()
        if children_done:
            children = _children(node)
            sizes[id(node)] = 1 + sum(sizes[id(c)] for c in children)
            continue
        if id(node) in sizes:
            if sizes[id(node)] is None:   # still being counted: the node contains itself
                mark = node.start_mark
                raise ConfigError(source, "", f"the value at line {mark.line + 1} column "
                                              f"{mark.column + 1} contains itself through an "
                                              f"alias (a loop)")
            continue
        sizes[id(node)] = None
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node))
    extra = sizes[id(root)] - len(sizes)
    if extra > MAX_ALIAS_VALUES:
        raise ConfigError(source, "", f"its aliases (*name) expand to {extra:,} more values, "
                                      f"above the limit of {MAX_ALIAS_VALUES:,} (an alias bomb?)")


def _children(node):
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    return []


def _check_duplicate_keys(node, source, key="", seen=None):
    """ConfigError naming the first key given twice in one mapping (YAML would keep the last
    silently), with both lines; ``node`` is the composed YAML node tree."""
    seen = set() if seen is None else seen
    if id(node) in seen:   # an alias: its node was checked where the anchor is
        return
    seen.add(id(node))
    if isinstance(node, yaml.MappingNode):
        lines = {}
        for k, v in node.value:
            name = k.value if isinstance(k, yaml.ScalarNode) else "(complex key)"
            sub = f"{key}.{name}" if key else str(name)
            line = f"line {k.start_mark.line + 1} column {k.start_mark.column + 1}"
            if name in lines and name != "<<":
                raise ConfigError(source, sub, f"given twice ({lines[name]} and {line}); each "
                                               f"key may appear once in a mapping")
            lines[name] = line
            _check_duplicate_keys(v, source, sub, seen)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _check_duplicate_keys(item, source, f"{key}[{i}]", seen)


def _yaml_problem(exc):
    """A YAML error on one line: what is wrong and where (line and column of the file)."""
    mark = getattr(exc, "problem_mark", None)
    problem = getattr(exc, "problem", None)
    if problem is None:   # a reader error: a character YAML does not allow
        return " ".join(str(exc).split()).replace('in "<unicode string>", position',
                                                  "at character")
    context = getattr(exc, "context", None)
    where = f" at line {mark.line + 1} column {mark.column + 1}" if mark is not None else ""
    return f"{context + ': ' if context else ''}{problem}{where}"


def load_yaml(path):
    """Read a YAML file; a missing, oversized, binary or malformed file and a key given twice
    become a ConfigError naming the file."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(path, "", missing_file_text(path))
    size = path.stat().st_size
    if size > MAX_YAML_BYTES:
        raise ConfigError(path, "", f"{size} bytes is too large for a configuration file "
                                    f"(at most {MAX_YAML_BYTES} bytes)")
    try:
        text = read_input(path).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(path, "", f"not a text YAML file (not UTF-8: byte "
                                    f"0x{exc.object[exc.start]:02x} at offset {exc.start})"
                          ) from None
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is not None:
            _check_aliases(node, path)
            _check_duplicate_keys(node, path)
            data = loader.construct_document(node)
        else:
            data = None
    except yaml.YAMLError as exc:
        raise ConfigError(path, "", f"not valid YAML: {_yaml_problem(exc)}") from None
    except RecursionError:
        raise ConfigError(path, "", "not valid YAML: nested too deeply") from None
    finally:
        loader.dispose()
    if data is None:
        raise ConfigError(path, "", "the file is empty")
    return data


def load_config(path, spec):
    """Load and validate a YAML file against a mapping schema."""
    return validate(load_yaml(path), spec, Path(path))


def config_path(kind, name):
    """Path of a shipped configuration file, e.g. ``config_path('components', 'frame')``."""
    root = resources.files("motoflex_ros") / "config" / kind
    return Path(str(root / f"{name}.yaml"))


def shipped_configs(kind):
    """Names of the shipped configuration files of one kind (components, vehicles, protocols)."""
    root = Path(str(resources.files("motoflex_ros") / "config" / kind))
    return sorted(p.stem for p in root.glob("*.yaml"))


def resolve_config(kind, name_or_file):
    """A shipped configuration by name, or a file path given by the user."""
    candidate = Path(name_or_file)
    if candidate.suffix in (".yaml", ".yml") or candidate.exists():
        if not candidate.is_file():
            raise ConfigError(candidate, "", missing_file_text(candidate))
        return candidate
    path = config_path(kind, name_or_file)
    if not path.is_file():
        names = ", ".join(shipped_configs(kind)) or "none"
        raise ConfigError(name_or_file, "", f"no shipped {kind} configuration of that name "
                                            f"(shipped: {names}); give a .yaml path instead")
    return path
