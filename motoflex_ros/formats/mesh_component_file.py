"""The ``component: mesh`` YAML: a component from the engineer's own volume mesh, read into a
:class:`~motoflex_ros.structures.mesh_component.MeshComponent` (solid elements, rigid spiders at
the interfaces, the same chain as a beam component).

The YAML (keys; positions in the mesh file's coordinates and ``units``, everything else SI)::

    component: mesh
    name: swingarm            # optional: the YAML file's name without .yaml
    mesh:
      file: swingarm.msh      # relative to this YAML (formats: motoflex_ros.formats.mesh_file)
      units: m                # of the file's coordinates: m or mm
      clamps: [pivot]         # node sets, each joined by a rigid spider to a 6-DOF node
      loaded_end: axle        # node set joined by a rigid spider to the loaded end q0
      points: {axle: [x, y, z]}   # optional: a spider's master point (default: mean of its nodes)
      origin: [x, y, z]       # optional: the component frame's origin O (default the file's 0)
      plane_normal: [0, 1, 0] # optional: the symmetry plane's normal, turned onto y
    material: {E: 7.0e10, nu: 0.33, rho: 2700}
    damping_ratio: 0.01       # optional, as for beam components
    rigid_parts: {brake: {set: caliper, mass: 0.7, cg: [x, y, z], inertia: [ix, iy, iz]}}
    placement: {origin: [x, y, z]}   # optional: O in the vehicle frame [m] (vehicle use only)

Component frame: x_c = R (s (x_file - origin)) with s the unit scale and R the rotation that
turns ``plane_normal`` onto y (the bench loads F_y, normal to the symmetry plane x-z: Passigato
et al. 2023, Sect. 4.2).

The spiders, the model and the frame are the core's
(:mod:`motoflex_ros.structures.mesh_component`); here is the file format: the schema, the checks
of the sets (ConfigError naming the YAML, the key and the mesh file) and the component's name.
"""
import math
import re
from pathlib import Path

import numpy as np

from motoflex_ros.config import Field, number, positive
from motoflex_ros.errors import ConfigError
from motoflex_ros.formats import mesh_file
from motoflex_ros.formats.mesh_file import UNITS, read_mesh
from motoflex_ros.inertia import check_inertia
from motoflex_ros.limits import check_limit
from motoflex_ros.structures.component_schema import DAMPING_FIELD
from motoflex_ros.structures.mesh_component import MeshComponent, Spider, plane_rotation
from motoflex_ros.structures.physical_ranges import (
    COMPONENT_SIZE_M,
    DENSITY,
    MODULUS_PA,
    PART_INERTIA_MAX,
    PART_MASS_MAX_KG,
)

__all__ = ["MESH_SCHEMA", "load_mesh_component", "mesh_component_name", "READER_FILES"]

NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

READER_FILES = (__file__, mesh_file.__file__)
"""The reader's source files: a changed reader never returns an old cached reduction."""
COORDINATE_MAX = 1e4  # [file units]: 10 m in mm
COLLINEAR_SHARE = 1e-6  # second singular value of a set's spread over its size: a line

_POSITION = Field("vec3", -COORDINATE_MAX, COORDINATE_MAX)
_NAMES = Field("list", min_items=1, item=Field("str"))

MESH_SCHEMA = Field("mapping", fields={
    "component": Field("str", choices=("mesh",)),
    "name": Field("str", required=False, default=None),
    "description": Field("str", required=False, default=""),
    "damping_ratio": DAMPING_FIELD,
    "placement": Field("mapping", required=False, default=None, fields={
        "origin": Field("vec3", -COMPONENT_SIZE_M, COMPONENT_SIZE_M)}),
    "mesh": Field("mapping", fields={
        "file": Field("str", help="the mesh file, relative to this YAML"),
        "units": Field("str", choices=tuple(UNITS), help="m or mm"),
        "clamps": _NAMES,
        "loaded_end": Field("str"),
        "points": Field("mapping", required=False, default={}, extra=True, item=_POSITION,
                        fields={}),
        "origin": Field("vec3", -COORDINATE_MAX, COORDINATE_MAX, required=False,
                        default=[0.0, 0.0, 0.0]),
        "plane_normal": Field("vec3", -1e3, 1e3, required=False, default=[0.0, 1.0, 0.0]),
    }),
    "material": Field("mapping", fields={
        "E": number(*MODULUS_PA, help="Young's modulus [Pa]"),
        "nu": number(-0.99, 0.499, help="Poisson's ratio in [-0.99, 0.499]"),
        "rho": number(*DENSITY, help="density [kg/m^3]"),
    }),
    "rigid_parts": Field("mapping", required=False, default={}, extra=True, fields={},
                         item=Field("mapping", fields={
                             "set": Field("str"),
                             "mass": positive(PART_MASS_MAX_KG, help="mass [kg]"),
                             "cg": _POSITION,
                             "inertia": Field("vec3", 0.0, PART_INERTIA_MAX, open_low=True),
                         })),
})



def _spider(name, nodes, points, master, cfg_source, key, mesh_file):
    """A Spider on ``nodes``; ConfigError when the set is empty or its nodes lie on a line."""
    if len(nodes) == 0:
        raise ConfigError(cfg_source, key, f"node set '{name}' in {mesh_file} has no node of "
                                           "the volume mesh")
    xyz = points[nodes]
    size = max(float(np.ptp(xyz, axis=0).max()), 1e-300)
    spread = np.linalg.svd(xyz - xyz.mean(axis=0), compute_uv=False) / math.sqrt(len(nodes))
    if len(nodes) < 3 or (spread[1] if len(spread) > 1 else 0.0) < COLLINEAR_SHARE * size:
        shape = "a single node" if len(nodes) == 1 or size <= 1e-300 else "on one line"
        raise ConfigError(cfg_source, key, f"node set '{name}' in {mesh_file}: its "
                                           f"{len(nodes)} nodes lie {shape}, so a rigid "
                                           "spider on them cannot hold the rotation about that "
                                           "line; give a set of nodes spread over a face")
    centre = xyz.mean(axis=0) if master is None else np.asarray(master, float)
    return Spider(name, centre, np.asarray(nodes, int))


def load_mesh_component(cfg, path, damping_ratio):
    """MeshComponent from a validated MESH_SCHEMA configuration read from ``path``."""
    source = str(path)
    spec = cfg["mesh"]
    scale = UNITS[spec["units"]]
    mesh_path = Path(spec["file"])
    if not mesh_path.is_absolute():
        mesh_path = Path(path).parent / mesh_path
    normal = np.asarray(spec["plane_normal"], float)
    if np.linalg.norm(normal) < 1e-9:
        raise ConfigError(source, "mesh.plane_normal", "must be a non-zero direction")
    data = read_mesh(mesh_path, spec["units"], source, "mesh.file")
    check_limit("mesh_dofs", 3 * len(data.points), source, "mesh.file",
                f"the mesh {mesh_path} ({len(data.points)} nodes)")
    extent = float(np.ptp(data.points, axis=0).max())
    if extent > COMPONENT_SIZE_M:
        raise ConfigError(source, "mesh.units", f"the mesh {mesh_path} read in "
                                                f"{spec['units']} spans {extent:g} m, more "
                                                f"than {COMPONENT_SIZE_M:g} m: are its "
                                                "coordinates in mm?")
    rot = plane_rotation(normal)
    origin = np.asarray(spec["origin"], float) * scale

    def to_frame(p):
        return (np.asarray(p, float) * scale - origin) @ rot.T

    xyz = (data.points - origin) @ rot.T
    for name in spec["points"]:
        if name not in spec["clamps"] + [spec["loaded_end"]] + [
                p["set"] for p in cfg["rigid_parts"].values()]:
            raise ConfigError(source, f"mesh.points.{name}", f"'{name}' is not a spider's set "
                                                             "(mesh.clamps, mesh.loaded_end or "
                                                             "a rigid part's set)")
    names = [(n, f"mesh.clamps[{i}]") for i, n in enumerate(spec["clamps"])]
    names.append((spec["loaded_end"], "mesh.loaded_end"))
    for part_name, part in cfg["rigid_parts"].items():
        if part["set"] not in [n for n, _ in names]:
            names.append((part["set"], f"rigid_parts.{part_name}.set"))
    seen, spiders, owner = {}, [], {}
    for name, key in names:
        if name in seen:
            raise ConfigError(source, key, f"node set '{name}' is already used by "
                                           f"{seen[name]}; a set has one spider")
        seen[name] = key
        nodes = data.node_set(name, source, key)
        for other, other_nodes in owner.items():
            common = np.intersect1d(nodes, other_nodes)
            if len(common):
                raise ConfigError(source, key, f"node set '{name}' shares {len(common)} nodes "
                                               f"(e.g. node {data.file_ids[common[0]]}) with "
                                               f"set '{other}' in {mesh_path}: a node can "
                                               "follow only one rigid spider")
        owner[name] = nodes
        master = spec["points"].get(name)
        spiders.append(_spider(name, nodes, xyz, None if master is None else to_frame(master),
                               source, key, mesh_path))
    n = len(xyz)
    node_names = {s.name: n + j for j, s in enumerate(spiders)}
    clamps = tuple(node_names[c] for c in spec["clamps"])
    end = node_names[spec["loaded_end"]]
    parts = []
    for part_name, part in cfg["rigid_parts"].items():
        key = f"rigid_parts.{part_name}"
        inertia = np.diag(part["inertia"])
        check_inertia(inertia, source, f"{key}.inertia")
        parts.append((node_names[part["set"]], part["mass"], rot @ inertia @ rot.T,
                      to_frame(part["cg"])))
    placement = cfg["placement"]
    name = mesh_component_name(cfg, path)
    return MeshComponent(name=name, mesh_xyz=xyz, blocks=data.blocks, spiders=tuple(spiders),
                         material=dict(cfg["material"]), clamp_nodes=clamps, loaded_end=end,
                         interface_nodes=clamps + (end,), node_names=node_names,
                         origin=np.zeros(3) if placement is None
                         else np.asarray(placement["origin"], float),
                         parts=tuple(parts), source=source, mesh_file=str(mesh_path),
                         damping_ratio=damping_ratio, element_ids=data.id_kind,
                         reader_files=READER_FILES)


def mesh_component_name(cfg, path):
    """The component's name: ``name``, else the YAML file's stem with every character that a
    ROS topic name cannot hold replaced by '_' (the bench's topics are /bench/<name>/...)."""
    if cfg["name"] is not None:
        if not NAME.match(cfg["name"]):
            raise ConfigError(path, "name", f"'{cfg['name']}' is not a name of letters, digits "
                                            "and '_' starting with a letter (it names the "
                                            "component's bench topics)")
        return cfg["name"]
    stem = re.sub(r"[^A-Za-z0-9_]", "_", Path(path).stem)
    return stem if stem[:1].isalpha() else f"mesh_{stem}"
