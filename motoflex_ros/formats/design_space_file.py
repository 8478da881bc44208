"""The design space file of ``motoflex study design`` (config/design/*.yaml), read into a
:class:`~motoflex_ros.study.design_space.DesignSpace`, and the changed beam files it writes.

Beyond the paper (issue 26; the meaning of the keys: :mod:`motoflex_ros.study.design_space`).
The file names, per motorcycle component, its beam file (default: the shipped one), the
sections that may change with the bounds of each dimension [m], and optional floors on k about
the static axis [N m/rad] and on the first clamped frequency [Hz]; ``constraints`` puts floors
on the four stability indices of eq. (15). It is a file format at the edge, not a part of the
study, because it reads other files: each component's beam file, through the same reader as
``motoflex components`` (:func:`~motoflex_ros.formats.component_file.load_component_config`),
and it writes the beam files of the designs found (:func:`design_component_text`); the study
takes the validated space and never opens a file. Every problem is one ConfigError naming the
design space file and the key.
"""
import copy
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
from motoflex_ros.formats.component_file import load_component_config
from motoflex_ros.study.design_space import (
    SECTION_KEYS,
    SECTION_RANGES,
    DesignSpace,
    Variable,
    members_mass,
)
from motoflex_ros.study.stability_index import INDEX_NAMES

__all__ = ["load_design_space", "design_component_text", "held_members_mass"]

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
    lo_ok, hi_ok = SECTION_RANGES[key]
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


def held_members_mass(space, components):
    """Structural mass [kg] of the members of the ``components`` ({name: beam Component})
    that ``space`` does not vary, from their beam files (``source``): the part of the objective
    every design shares (:func:`~motoflex_ros.study.design_space.members_mass`)."""
    return sum(members_mass(load_component_config(c.source)) for name, c in components.items()
               if name not in space.components())
