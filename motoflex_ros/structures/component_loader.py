"""Loading a component by name or YAML file: the tube, a beam structure, a mesh or a superelement.

Reads ``config/components/*.yaml`` (validated on load with :mod:`motoflex_ros.config`) and hands
each kind to its builder: :func:`~motoflex_ros.structures.component_model.tube_component`,
:func:`~motoflex_ros.structures.component_schema.structure_from_config`,
:func:`~motoflex_ros.structures.mesh_component.load_mesh_component` and
:func:`~motoflex_ros.structures.superelement_file.load_superelement_component`. It stands above
all of them, so none of them imports it (no import cycle).
"""
from dataclasses import replace
from pathlib import Path

from motoflex_ros.config import Field, load_yaml, number, resolve_config, validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.limits import check_limit
from motoflex_ros.structures.beam import Material
from motoflex_ros.structures.component_model import (
    DEFAULT_DAMPING_RATIO,
    Component,
    tube_component,
)
from motoflex_ros.structures.component_schema import (
    STRUCTURE_SCHEMA,
    TUBE_SCHEMA,
    structure_from_config,
)
from motoflex_ros.structures.mesh_component import (
    MESH_SCHEMA,
    load_mesh_component,
    mesh_component_name,
)
from motoflex_ros.structures.superelement_file import (
    SUPERELEMENT_SCHEMA,
    load_superelement_component,
)

__all__ = ["load_component", "component_name", "load_component_config", "damping_ratio_setting"]


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
    superelement``: a :class:`~motoflex_ros.structures.superelement_file.
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


def component_name(name_or_file):
    """The name a component (shipped name or YAML file) goes by, from its file alone (no model
    is built): ``component`` of a beam file, ``name`` (or the file's stem) of a mesh file."""
    path = resolve_config("components", name_or_file)
    cfg = load_component_config(path)
    if cfg["component"] in ("mesh", "superelement"):
        return mesh_component_name(cfg, path)
    return cfg["component"]


def damping_ratio_setting(value, source):
    """The ``damping_ratio`` key [-]: None (default 1 %), a number in [0, 1) or a non-empty list
    of them (one per mode of the clamped reduced model); ConfigError naming file and key."""
    if value is None:
        return DEFAULT_DAMPING_RATIO
    ratio = number(0.0, 1.0, open_high=True)
    if isinstance(value, list):
        return tuple(validate(value, Field("list", min_items=1, item=ratio), source,
                              "damping_ratio"))
    return validate(value, ratio, source, "damping_ratio")
