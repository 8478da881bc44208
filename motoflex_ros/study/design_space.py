"""The design space of ``motoflex study design``: which sections may change, and the constraints.

Beyond the paper (Sect. 1 and 6 state the aim: "optimize the stiffness in the early design
phase of structural components so that the overall weight can be minimized while ensuring the
stability of weave and wobble"; issue 26). A design space file (config/design/*.yaml) names,
per component, the sections of its beam file that may change and the bounds of each dimension
(outer diameter, wall thickness, width, height [m]); everything else is held: geometry (nodes,
members), materials, springs, rigid parts, clamps, the rest of the motorcycle. The constraints
are floors on the four stability indices of eq. (15) (weave and wobble, 40-100 and 100-210
km/h): ``nominal`` (at least the nominal design's) or a number; and optional floors per
component on the static stiffness k about the static deformation axis [N m/rad] (eq. 8) and on
the first eigenfrequency of the clamped model [Hz], a stand-in for strength (a real design
needs stress checks this rig does not make).

The objective is the structural mass: the FE members' mass, density x section area x length,
summed over the members of the three components [kg] (rigid parts held, not counted).

Symbols: D outer diameter, t wall thickness, w width, h height [m]; rho density [kg/m^3].
"""
import copy
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import yaml

from motoflex_ros.config import (
    MOTORCYCLE_COMPONENTS,
    Field,
    load_yaml,
    number,
    resolve_config,
    validate,
)
from motoflex_ros.errors import ConfigError
from motoflex_ros.structures.beam import rectangular_tube_section, tube_section
from motoflex_ros.structures.component_loader import damping_ratio_setting, load_component_config
from motoflex_ros.structures.component_model import Component
from motoflex_ros.structures.component_schema import SECTION_SIZE_M, WALL_M, structure_from_config

__all__ = ["INDEX_NAMES", "SECTION_KEYS", "DesignSpace", "Variable", "load_design_space",
           "members_mass", "component_with", "design_configs", "design_component_text"]

INDEX_NAMES = ("weave_low", "weave_high", "wobble_low", "wobble_high")
"""The four stability indices of eq. (15): mode x speed range (low 40-100, high 100-210 km/h)."""
SECTION_KEYS = {"tube": ("outer_diameter", "wall_thickness"),
                "rectangular_tube": ("width", "height", "wall_thickness")}
"""The dimensions each section shape has (structures/schema.py), all in [m]."""
_RANGES = {"outer_diameter": SECTION_SIZE_M, "width": SECTION_SIZE_M,
           "height": SECTION_SIZE_M, "wall_thickness": WALL_M}

_BOUNDS = Field("list", min_items=2, item=number(0.0, 10.0, open_low=True))
_SPACE_SCHEMA = Field("mapping", fields={
    "design": Field("str"),
    "description": Field("str", required=False, default=""),
    "vehicle": Field("str", required=False, default="touring"),
    "components": Field("mapping", extra=True, fields={}, item=Field("mapping", fields={
        "file": Field("str", required=False, default=None),
        "sections": Field("mapping", extra=True, fields={}, item=Field(
            "mapping", extra=True, fields={}, item=_BOUNDS)),
        "min_static_k": number(0.0, 1e12, required=False, default=None,
                               help="floor on k about the static axis [N m/rad]"),
        "min_first_frequency_hz": number(0.0, 1e5, required=False, default=None,
                                         help="floor on the first clamped frequency [Hz]"),
    })),
    "constraints": Field("mapping", extra=True, fields={}, item=Field("any")),
})


@dataclass(frozen=True)
class Variable:
    """One design variable: ``component``'s section ``section``, dimension ``key`` [m], in
    [low, high], nominal value ``nominal`` [m]; ``name`` 'component.section.key'."""

    component: str
    section: str
    key: str
    low: float
    high: float
    nominal: float

    @property
    def name(self):
        """'component.section.key'."""
        return f"{self.component}.{self.section}.{self.key}"


@dataclass(frozen=True, eq=False)
class DesignSpace:
    """A validated design space.

    source: its file; vehicle: the vehicle name or file; variables: tuple of Variable;
    configs: {component: validated beam config (the nominal design)}; sources: {component:
    its beam file}; index_floors: {index: 'nominal' or a number} (eq. 15); floors: {component:
    {'min_static_k' [N m/rad], 'min_first_frequency_hz' [Hz]}} (strength stand-ins).
    """

    source: str
    vehicle: str
    variables: tuple
    configs: dict
    sources: dict
    index_floors: dict
    floors: dict

    @property
    def names(self):
        """Variable names in order."""
        return tuple(v.name for v in self.variables)

    @property
    def lower(self):
        """Lower bounds (variables,) [m]."""
        return np.array([v.low for v in self.variables])

    @property
    def upper(self):
        """Upper bounds (variables,) [m]."""
        return np.array([v.high for v in self.variables])

    @property
    def nominal(self):
        """Nominal values (variables,) [m]."""
        return np.array([v.nominal for v in self.variables])

    def components(self):
        """Components whose sections may change, in file order."""
        return tuple(dict.fromkeys(v.component for v in self.variables))

    def with_floors(self, index_floors):
        """The same space with other index floors ({index: 'nominal' or number})."""
        return replace(self, index_floors=dict(index_floors))


def _variable(component, section, key, bounds, cfg, source):
    where = f"components.{component}.sections.{section}.{key}"
    spec = cfg["sections"].get(section)
    if spec is None:
        known = ", ".join(sorted(cfg["sections"])) or "none"
        raise ConfigError(source, f"components.{component}.sections.{section}",
                          f"the {component} has no section '{section}' (sections: {known})")
    allowed = SECTION_KEYS[spec["shape"]]
    if key not in allowed:
        raise ConfigError(source, where, f"a {spec['shape']} section has no '{key}' "
                                         f"(dimensions: {', '.join(allowed)})")
    if len(bounds) != 2:
        raise ConfigError(source, where, f"give [low, high] [m], got {len(bounds)} values")
    low, high = (float(b) for b in bounds)
    lo_ok, hi_ok = _RANGES[key]
    if not lo_ok <= low < high <= hi_ok:
        raise ConfigError(source, where, f"bounds [{low:g}, {high:g}] m must satisfy "
                                         f"{lo_ok:g} <= low < high <= {hi_ok:g}")
    nominal = float(spec[key])
    if not low <= nominal <= high:
        raise ConfigError(source, where, f"the nominal {nominal:g} m is outside the bounds "
                                         f"[{low:g}, {high:g}] m")
    return Variable(component, section, key, low, high, nominal)


def _check_walls(variables, cfg, component, source):
    """Every corner of the box must stay a valid section: 2 t < D (tube), 2 t < min(w, h)."""
    for section, spec in cfg["sections"].items():
        mine = {v.key: v for v in variables if v.section == section}
        if not mine:
            continue
        wall = mine["wall_thickness"].high if "wall_thickness" in mine else spec["wall_thickness"]
        sizes = [mine[k].low if k in mine else spec[k] for k in SECTION_KEYS[spec["shape"]]
                 if k != "wall_thickness"]
        if 2.0 * wall >= min(sizes):
            key = "wall_thickness" if "wall_thickness" in mine else next(iter(mine))
            raise ConfigError(source, f"components.{component}.sections.{section}.{key}",
                              f"at the bounds' corner the wall {wall:g} m is not less than half "
                              f"the section's smallest size {min(sizes):g} m")


def _index_floors(constraints, source):
    floors = {}
    for name, value in constraints.items():
        key = f"constraints.{name}"
        if name not in INDEX_NAMES:
            raise ConfigError(source, key, f"unknown stability index '{name}' (allowed: "
                                           f"{', '.join(INDEX_NAMES)})")
        if value == "nominal":
            floors[name] = "nominal"
            continue
        floors[name] = validate(value, number(0.0, 1e3, help="'nominal' or an index floor"),
                                source, key)
    return floors


def load_design_space(name_or_file):
    """A :class:`DesignSpace` from a shipped name ('touring') or a YAML file; ConfigError
    naming the file and key for a section the component lacks, a dimension its shape lacks,
    bounds reversed or outside the component schema's ranges, a nominal outside its bounds, a
    wall that could reach half the section, or a constraint on an unknown index."""
    path = resolve_config("design", name_or_file)
    source = str(path)
    cfg = validate(load_yaml(path), _SPACE_SCHEMA, Path(path))
    variables, configs, sources, floors = [], {}, {}, {}
    for component, spec in cfg["components"].items():
        if component not in MOTORCYCLE_COMPONENTS:
            raise ConfigError(source, f"components.{component}",
                              "unknown component (allowed: "
                              f"{', '.join(MOTORCYCLE_COMPONENTS)})")
        comp_path = resolve_config("components", spec["file"] or component)
        comp_cfg = load_component_config(comp_path)
        if comp_cfg.get("component") != component:
            raise ConfigError(source, f"components.{component}.file",
                              f"{comp_path} is not a {component} beam file")
        mine = [_variable(component, section, key, bounds, comp_cfg, source)
                for section, keys in spec["sections"].items() for key, bounds in keys.items()]
        if not mine:
            raise ConfigError(source, f"components.{component}.sections", "no section to vary")
        _check_walls(mine, comp_cfg, component, source)
        variables += mine
        configs[component], sources[component] = comp_cfg, str(comp_path)
        floors[component] = {k: spec[k] for k in ("min_static_k", "min_first_frequency_hz")
                             if spec[k] is not None}
    if not variables:
        raise ConfigError(source, "components", "no component to vary")
    return DesignSpace(source, cfg["vehicle"], tuple(variables), configs, sources,
                       _index_floors(cfg["constraints"], source), floors)


def design_configs(space, values):
    """{component: beam config} of the design ``values`` (variables,) [m]: copies of the
    nominal configs with the varied dimensions set."""
    out = {}
    for variable, value in zip(space.variables, np.asarray(values, float)):
        cfg = out.setdefault(variable.component, copy.deepcopy(space.configs[variable.component]))
        cfg["sections"][variable.section][variable.key] = float(value)
    return out


def component_with(cfg, source):
    """The beam Component of a (validated, possibly changed) config dict ``cfg`` read from the
    file ``source``."""
    comp = structure_from_config(copy.deepcopy(cfg), source, Component)
    return replace(comp, source=str(source),
                   damping_ratio=damping_ratio_setting(cfg.get("damping_ratio"), source))


def _area(spec):
    if spec["shape"] == "tube":
        return tube_section(spec["outer_diameter"], spec["wall_thickness"]).A
    return rectangular_tube_section(spec["width"], spec["height"], spec["wall_thickness"]).A


def members_mass(cfg):
    """Structural mass of a beam config's members [kg]: sum of rho A L over the members
    (rigid parts not counted).

    Parameters
    ----------
    cfg : dict
        A beam component config (config/components/*.yaml as read): ``nodes`` [m],
        ``materials`` (``rho`` [kg/m^3]), ``sections`` (dimensions [m]) and ``members``.

    Returns
    -------
    float
        The members' mass [kg].

    Examples
    --------
    >>> cfg = {"nodes": {"a": [0, 0, 0], "b": [2.0, 0, 0]},
    ...        "materials": {"steel": {"rho": 7850.0}},
    ...        "sections": {"s": {"shape": "rectangular_tube", "width": 0.02, "height": 0.02,
    ...                           "wall_thickness": 0.001}},
    ...        "members": [{"from": "a", "to": "b", "section": "s", "material": "steel"}]}
    >>> round(members_mass(cfg), 6)   # 7850 kg/m^3 x (0.02^2 - 0.018^2) m^2 x 2 m
    1.1932

    """
    nodes = {k: np.asarray(v, float) for k, v in cfg["nodes"].items()}
    areas = {k: _area(v) for k, v in cfg["sections"].items()}
    return float(sum(cfg["materials"][m["material"]]["rho"] * areas[m["section"]]
                     * np.linalg.norm(nodes[m["to"]] - nodes[m["from"]])
                     for m in cfg["members"]))


def design_component_text(space, component, x, label):
    """YAML text of ``component``'s beam file for the design x [m]: the nominal file as it was
    read (the reader's own keys), with the varied section dimensions set, under a header that
    says where it came from (``label``, e.g. 'lightest feasible design')."""
    raw = copy.deepcopy(load_yaml(space.sources[component]))
    changed = []
    for variable, value in zip(space.variables, np.asarray(x, float)):
        if variable.component == component:
            raw["sections"][variable.section][variable.key] = float(value)
            changed.append(f"#   {variable.section}.{variable.key}: {variable.nominal:.6g} -> "
                           f"{float(value):.6g} m")
    header = [f"# {component} of the {label} of `motoflex study design` (design space "
              f"{Path(space.source).name}),", f"# from {space.sources[component]}; changed:"]
    return "\n".join(header + changed) + "\n" + yaml.safe_dump(raw, sort_keys=False)
