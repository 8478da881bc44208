"""Schemas of the beam component YAML files and the builder of a beam structure from a parsed
one (the file is read at the edge: :mod:`motoflex_ros.formats.component_file`).

Every value is checked on load (unknown/missing keys, types, NaN, ranges, references between
keys such as a member naming an unknown node) and reported as ConfigError(file, key, problem).
"""
import math

import numpy as np

from motoflex_ros.config import Field, angle, number, positive, validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.inertia import check_inertia
from motoflex_ros.limits import check_limit
from motoflex_ros.structures.assembly import Structure
from motoflex_ros.structures.beam import Material, rectangular_tube_section, tube_section
from motoflex_ros.structures.component_model import DEFAULT_DAMPING_RATIO
from motoflex_ros.structures.physical_ranges import (
    COMPONENT_SIZE_M,
    DENSITY,
    MODULUS_PA,
    PART_INERTIA_MAX,
    PART_MASS_MAX_KG,
)

__all__ = ["TUBE_SCHEMA", "STRUCTURE_SCHEMA", "DAMPING_FIELD", "structure_from_config",
           "damping_ratio_setting"]

# Physical ranges of every number (SI); those the mesh schema shares are in physical_ranges.
SECTION_SIZE_M = (1e-4, 2.0)  # outer diameter, width, height [m]
WALL_M = (1e-5, 1.0)
SPRING_MAX = 1e12  # [N/m] and [N m/rad]; a rigid connection is a rigid link

_MATERIAL = Field("mapping", fields={
    "E": number(*MODULUS_PA, help="Young's modulus [Pa]"),
    "G": number(*MODULUS_PA, help="shear modulus [Pa]"),
    "rho": number(*DENSITY, help="density [kg/m^3]"),
})
_POINT = Field("vec3", -COMPONENT_SIZE_M, COMPONENT_SIZE_M)
_DIRECTION = Field("vec3", -1e3, 1e3, required=False, default=None)

# modal damping ratio of the clamped reduced model (every component schema's key): checked by
# damping_ratio_setting
DAMPING_FIELD = Field("any", required=False, default=None,
                      help="a number in [0, 1) or a list of them, one per mode")

TUBE_SCHEMA = Field("mapping", fields={
    "component": Field("str", choices=("tube",)),
    "description": Field("str", required=False, default=""),
    "damping_ratio": DAMPING_FIELD,
    "tube": Field("mapping", fields={
        "length": number(1e-3, COMPONENT_SIZE_M, help="length [m]"),
        "outer_diameter": number(*SECTION_SIZE_M, help="outer diameter [m]"),
        "wall_thickness": number(*WALL_M, help="wall thickness [m]"),
        "pitch_deg": angle(-90.0, 90.0, help="pitch in [-90, 90] deg"),
    }),
    "material": _MATERIAL,
    "elements": Field("int", 1, 100000, help="number of elements in [1, 100000]"),
})

_SECTION = Field("mapping", fields={
    "shape": Field("str", choices=("tube", "rectangular_tube")),
    "outer_diameter": number(*SECTION_SIZE_M, required=False),
    "width": number(*SECTION_SIZE_M, required=False),
    "height": number(*SECTION_SIZE_M, required=False),
    "wall_thickness": number(*WALL_M),
})
_NONNEG3 = Field("vec3", 0.0, SPRING_MAX)

STRUCTURE_SCHEMA = Field("mapping", fields={
    "component": Field("str"),
    "description": Field("str", required=False, default=""),
    "damping_ratio": DAMPING_FIELD,
    "placement": Field("mapping", fields={"origin": _POINT}),
    "materials": Field("mapping", extra=True, item=_MATERIAL, fields={}),
    "sections": Field("mapping", extra=True, item=_SECTION, fields={}),
    "nodes": Field("mapping", extra=True, item=_POINT, fields={}),
    "mesh": Field("mapping", fields={
        "max_element_length": number(1e-4, COMPONENT_SIZE_M, help="element length [m]")}),
    "members": Field("list", min_items=1, item=Field("mapping", fields={
        "from": Field("str"), "to": Field("str"), "section": Field("str"),
        "material": Field("str"),
        "up": _DIRECTION,
    })),
    "rigid_links": Field("list", required=False, default=[], item=Field("mapping", fields={
        "master": Field("str"), "slave": Field("str"),
        "dofs": Field("str", choices=("all", "translations"), required=False, default="all"),
    })),
    "springs": Field("list", required=False, default=[], item=Field("mapping", fields={
        "from": Field("str"), "to": Field("str"),
        "k_translation": _NONNEG3, "k_rotation": _NONNEG3,
        "axis_z": _DIRECTION,
    })),
    "rigid_parts": Field("mapping", required=False, default={}, extra=True,
                         fields={}, item=Field("mapping", fields={
                             "node": Field("str"),
                             "mass": positive(PART_MASS_MAX_KG, help="mass [kg]"),
                             "cg": _POINT,
                             "inertia": Field("vec3", 0.0, PART_INERTIA_MAX, open_low=True),
                         })),
    "interfaces": Field("mapping", fields={
        "loaded_end": Field("str"),
        "clamps": Field("list", min_items=1, item=Field("str")),
        "others": Field("list", required=False, default=[], item=Field("str")),
    }),
    # optional names of the flexible bodies (paper Table A.1): {body name: a node of it}
    "bodies": Field("mapping", required=False, default={}, extra=True, fields={},
                    item=Field("str")),
})


def _section(spec, source, key):
    need = ("outer_diameter",) if spec["shape"] == "tube" else ("width", "height")
    for name in need:
        if spec[name] is None:
            raise ConfigError(source, f"{key}.{name}", f"missing (required for shape "
                                                       f"{spec['shape']}, > 0 [m])")
    t = spec["wall_thickness"]
    if spec["shape"] == "tube":
        if 2 * t >= spec["outer_diameter"]:
            raise ConfigError(source, f"{key}.wall_thickness", "must be less than half the "
                                                               "outer diameter")
        return tube_section(spec["outer_diameter"], t)
    if 2 * t >= min(spec["width"], spec["height"]):
        raise ConfigError(source, f"{key}.wall_thickness", "must be less than half the width "
                                                           "and the height")
    return rectangular_tube_section(spec["width"], spec["height"], t)


def _lookup(table, name, source, key, what):
    if name not in table:
        known = ", ".join(sorted(table)) or "none"
        raise ConfigError(source, key, f"unknown {what} '{name}' (defined: {known})")
    return table[name]


def _default_up(axis):
    """Orientation vector: global y for members in the x-z plane... unless parallel."""
    axis = axis / np.linalg.norm(axis)
    up = np.array([0.0, 1.0, 0.0])
    return up if abs(axis @ up) < 0.9 else np.array([0.0, 0.0, 1.0])


def _add_members(s, cfg, names, source):
    materials = {k: Material(v["E"], v["G"], v["rho"]) for k, v in cfg["materials"].items()}
    sections = {k: _section(v, source, f"sections.{k}") for k, v in cfg["sections"].items()}
    max_len = cfg["mesh"]["max_element_length"]
    ends, counts = [], []
    for i, mem in enumerate(cfg["members"]):
        key = f"members[{i}]"
        n1 = _lookup(names, mem["from"], source, f"{key}.from", "node")
        n2 = _lookup(names, mem["to"], source, f"{key}.to", "node")
        length = np.linalg.norm(s.nodes[n2] - s.nodes[n1])
        if length < 1e-6:
            raise ConfigError(source, f"{key}.to", "member has zero length")
        ends.append((n1, n2))
        counts.append(max(1, math.ceil(length / max_len - 1e-9)))
    # sized before anything is meshed: each element adds one node (6 DOFs) inside its member
    dofs = 6 * (len(s.nodes) + sum(counts) - len(counts))
    check_limit("dofs", dofs, source, "mesh.max_element_length",
                f"the mesh of max_element_length {max_len:g} m ({sum(counts)} elements)")
    for i, (mem, (n1, n2), count) in enumerate(zip(cfg["members"], ends, counts)):
        key = f"members[{i}]"
        sec = _lookup(sections, mem["section"], source, f"{key}.section", "section")
        mat = _lookup(materials, mem["material"], source, f"{key}.material", "material")
        up = mem["up"] if mem["up"] is not None else _default_up(s.nodes[n2] - s.nodes[n1])
        s.add_member(n1, n2, count, sec, mat, up=up)


def _spring_axes(axis_z, source, key):
    """Spring axes (columns x, y, z): z given, y = global y made orthogonal to z."""
    z = np.asarray(axis_z, float)
    if np.linalg.norm(z) < 1e-9:
        raise ConfigError(source, key, "must be a non-zero direction")
    z = z / np.linalg.norm(z)
    y = np.array([0.0, 1.0, 0.0]) - z[1] * z
    if np.linalg.norm(y) < 1e-6:
        y = np.array([0.0, 0.0, 1.0]) - z[2] * z
    y /= np.linalg.norm(y)
    return np.column_stack([np.cross(y, z), y, z])


def _add_joints_and_parts(s, cfg, names, source):
    for i, link in enumerate(cfg["rigid_links"]):
        key = f"rigid_links[{i}]"
        master = _lookup(names, link["master"], source, f"{key}.master", "node")
        slave = _lookup(names, link["slave"], source, f"{key}.slave", "node")
        dofs = range(6) if link["dofs"] == "all" else range(3)
        s.add_link(master, slave, dofs)
    for i, spring in enumerate(cfg["springs"]):
        key = f"springs[{i}]"
        n1 = _lookup(names, spring["from"], source, f"{key}.from", "node")
        n2 = _lookup(names, spring["to"], source, f"{key}.to", "node")
        axes = None if spring["axis_z"] is None else _spring_axes(spring["axis_z"], source,
                                                                   f"{key}.axis_z")
        s.add_spring(n1, n2, spring["k_translation"], spring["k_rotation"], axes)
    for part_name, part in cfg["rigid_parts"].items():
        key = f"rigid_parts.{part_name}"
        node = _lookup(names, part["node"], source, f"{key}.node", "node")
        inertia = np.diag(part["inertia"])
        check_inertia(inertia, source, f"{key}.inertia")
        s.add_part(node, part["mass"], inertia, part["cg"])


def _check_nodes_connected(cfg, source):
    """ConfigError naming the first node that no member, spring or rigid link holds.

    Such a node has no stiffness: the interior stiffness would be singular (Craig-Bampton),
    or, for an interface node, its motion undetermined. A rigid part on it adds only mass.
    """
    held = {end for item in cfg["members"] + cfg["springs"] for end in (item["from"],
                                                                         item["to"])}
    held |= {link[end] for link in cfg["rigid_links"] for end in ("master", "slave")}
    for name in cfg["nodes"]:
        if name not in held:
            raise ConfigError(source, f"nodes.{name}", "the node is not connected: no member, "
                                                       "spring or rigid link uses it (a rigid "
                                                       "part adds only mass); connect it or "
                                                       "remove it")


def structure_from_config(cfg, source, component_cls):
    """Build a Component (``component_cls``) from a validated structure configuration."""
    _check_nodes_connected(cfg, source)
    s = Structure()
    names = {name: s.add_node(xyz) for name, xyz in cfg["nodes"].items()}
    _add_members(s, cfg, names, source)
    _add_joints_and_parts(s, cfg, names, source)
    itf = cfg["interfaces"]
    clamps = tuple(_lookup(names, n, source, f"interfaces.clamps[{i}]", "node")
                   for i, n in enumerate(itf["clamps"]))
    end = _lookup(names, itf["loaded_end"], source, "interfaces.loaded_end", "node")
    others = tuple(_lookup(names, n, source, f"interfaces.others[{i}]", "node")
                   for i, n in enumerate(itf["others"]))
    if end in clamps:
        raise ConfigError(source, "interfaces.loaded_end", "the loaded end cannot be clamped")
    body_names = {body: _lookup(names, node, source, f"bodies.{body}", "node")
                  for body, node in cfg["bodies"].items()}
    return component_cls(name=cfg["component"], structure=s, clamp_nodes=clamps,
                         loaded_end=end, interface_nodes=clamps + (end,) + others,
                         node_names=names, origin=np.asarray(cfg["placement"]["origin"]),
                         body_names=body_names)


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
