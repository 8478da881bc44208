"""Loading a component by name or YAML file: the tube, a beam structure, a mesh or a superelement.

Reads ``config/components/*.yaml`` (validated on load with :mod:`motoflex_ros.config`) and hands
each kind to its builder: :func:`~motoflex_ros.structures.component_model.tube_component`,
:func:`~motoflex_ros.structures.component_schema.structure_from_config` (both in the core, from
the parsed file), :func:`~motoflex_ros.formats.mesh_component_file.load_mesh_component` and
:func:`~motoflex_ros.formats.superelement_file.load_superelement_component` (the mesh and the
matrix files, read here at the edge). The numerical core takes the built component: the CLI,
the nodes, the launcher and the report load it with :func:`load_component`.
"""
import functools
from dataclasses import replace
from pathlib import Path

from motoflex_ros.config import load_yaml, resolve_config, validate
from motoflex_ros.errors import ConfigError, MotoflexError
from motoflex_ros.formats.mesh_component_file import (
    MESH_SCHEMA,
    load_mesh_component,
    mesh_component_name,
)
from motoflex_ros.formats.superelement_file import (
    SUPERELEMENT_SCHEMA,
    load_superelement_component,
)
from motoflex_ros.limits import check_limit
from motoflex_ros.structures.beam import Material
from motoflex_ros.structures.component_model import Component, tube_component
from motoflex_ros.structures.component_schema import (
    STRUCTURE_SCHEMA,
    TUBE_SCHEMA,
    damping_ratio_setting,
    structure_from_config,
)

__all__ = ["load_component", "load_components", "component_name", "load_component_config",
           "shipped_model"]


def load_component_config(path):
    """Read and validate a component YAML file (tube or structure schema)."""
    data = load_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(path, "(top level)", "expected a mapping")
    if "component" not in data:
        raise ConfigError(path, "component", "missing (required: tube, mesh, superelement, frame, "
                                             "front_assembly, swingarm or another name)")
    if data["component"] == "mesh":
        return validate(data, MESH_SCHEMA, path)
    if data["component"] == "superelement":
        return validate(data, SUPERELEMENT_SCHEMA, path)
    schema = TUBE_SCHEMA if data["component"] == "tube" else STRUCTURE_SCHEMA
    cfg = validate(data, schema, path)
    if cfg["component"] == "tube":
        t = cfg["tube"]
        if 2 * t["wall_thickness"] >= t["outer_diameter"]:
            raise ConfigError(path, "tube.wall_thickness", "must be less than half the outer "
                                                           "diameter")
        check_limit("dofs", 6 * (cfg["elements"] + 1), path, "elements",
                    f"{cfg['elements']} elements")
    return cfg


def load_component(name_or_file):
    """Load a shipped component by name ('frame', 'tube', ...) or a YAML file path (a beam
    structure, the tube, ``component: mesh``: a
    :class:`~motoflex_ros.structures.mesh_component.MeshComponent`, or ``component:
    superelement``: a :class:`~motoflex_ros.structures.superelement_component.
    SuperelementComponent`)."""
    path = resolve_config("components", name_or_file)
    cfg = load_component_config(path)
    damping = damping_ratio_setting(cfg.get("damping_ratio"), path)
    if cfg["component"] == "mesh":
        return load_mesh_component(cfg, path, damping)
    if cfg["component"] == "superelement":
        return load_superelement_component(cfg, path, damping)
    if cfg["component"] == "tube":
        t, m = cfg["tube"], cfg["material"]
        comp = tube_component(t["length"], t["outer_diameter"], t["wall_thickness"],
                              t["pitch_deg"], Material(m["E"], m["G"], m["rho"]),
                              cfg["elements"])
    else:
        comp = structure_from_config(cfg, path, Component)
    return replace(comp, source=str(Path(path)), damping_ratio=damping)


def load_components(names_or_files):
    """[component] of each shipped name or YAML file, in order (:func:`load_component`)."""
    return [load_component(given) for given in names_or_files]


def component_name(name_or_file):
    """The name a component (shipped name or YAML file) goes by, from its file alone (no model
    is built): ``component`` of a beam file, ``name`` (or the file's stem) of a mesh file."""
    path = resolve_config("components", name_or_file)
    cfg = load_component_config(path)
    if cfg["component"] in ("mesh", "superelement"):
        return mesh_component_name(cfg, path)
    return cfg["component"]


@functools.cache
def shipped_model(component):
    """(Component, ReducedComponent) of a shipped component name or a component YAML file (the
    clamped reduced model the component simulator integrates, as
    :mod:`motoflex_ros.bench.replayed_loads` re-runs it), or None when there is none."""
    try:
        comp = load_component(component)
        return comp, comp.clamped_reduced()
    except (MotoflexError, OSError, KeyError, ValueError):
        return None
