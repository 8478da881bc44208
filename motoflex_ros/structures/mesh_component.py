"""A component from the engineer's own volume mesh (``component: mesh``): solid elements, rigid
spiders at the interfaces, the same chain as a beam component.

The YAML (keys; positions in the mesh file's coordinates and ``units``, everything else SI)::

    component: mesh
    name: swingarm            # optional: the YAML file's name without .yaml
    mesh:
      file: swingarm.msh      # relative to this YAML (formats: motoflex_ros.structures.mesh_file)
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

Rigid spiders (RBE2-like) are exact multipoint constraints, eliminated by a transformation and
not enforced by penalties: each node s of a spider's set follows its master node m (six DOFs
at x_m) rigidly, u_s = u_m + theta_m x (x_s - x_m). With u = T v (v: the translations of the
free mesh nodes and the masters' six DOFs), K_v = T^T K T, M_v = T^T M T. A rigid part hangs on
the master of its set (a new spider when the set is not an interface), as on the beam
components.
"""
import math
import re
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from motoflex_ros.config import Field, number, positive
from motoflex_ros.errors import ConfigError
from motoflex_ros.inertia import check_inertia
from motoflex_ros.limits import check_limit
from motoflex_ros.spatial import skew
from motoflex_ros.structures.assembly import AssembledStructure, rigid_body_mass
from motoflex_ros.structures.component_model import DEFAULT_DAMPING_RATIO, ComponentModel
from motoflex_ros.structures.mesh_file import UNITS, read_mesh
from motoflex_ros.structures.physical_ranges import (
    COMPONENT_SIZE_M,
    DENSITY,
    MODULUS_PA,
    PART_INERTIA_MAX,
    PART_MASS_MAX_KG,
)
from motoflex_ros.structures.solid import CORNERS, ElementError, assemble_solid

__all__ = ["MeshComponent", "Spider", "MESH_SCHEMA", "load_mesh_component", "spider_transform",
           "boundary_edges", "plane_rotation", "mesh_component_name"]

NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

COORDINATE_MAX = 1e4  # [file units]: 10 m in mm
COLLINEAR_SHARE = 1e-6  # second singular value of a set's spread over its size: a line

_POSITION = Field("vec3", -COORDINATE_MAX, COORDINATE_MAX)
_NAMES = Field("list", min_items=1, item=Field("str"))

MESH_SCHEMA = Field("mapping", fields={
    "component": Field("str", choices=("mesh",)),
    "name": Field("str", required=False, default=None),
    "description": Field("str", required=False, default=""),
    "damping_ratio": Field("any", required=False, default=None,
                           help="a number in [0, 1) or a list of them, one per mode"),
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


@dataclass(frozen=True)
class Spider:
    """A rigid spider: the node set ``name``, its master point [m] (component frame) and the
    mesh nodes it holds (``slaves``)."""

    name: str
    master: np.ndarray
    slaves: np.ndarray


def spider_transform(n_nodes, xyz, spiders):
    """The constraint transformation u = T v of rigid spiders on a mesh of ``n_nodes`` nodes.

    Parameters
    ----------
    n_nodes : int
        Mesh nodes (three DOFs each: 3 i + (x, y, z)).
    xyz : array (n_nodes, 3)
        Their coordinates [m].
    spiders : sequence of Spider
        Disjoint sets; master j has the DOFs 3 n_nodes + 6 j + (ux, uy, uz, rx, ry, rz).

    Returns
    -------
    T : scipy.sparse.csr_matrix (3 n_nodes + 6 n_spiders, n_free)
        Columns: the free (non-slave) mesh nodes' translations in node order, then the masters'
        six DOFs. A slave's rows are u_s = u_m - [x_s - x_m]x theta_m, exactly.
    free_nodes : array
        The mesh nodes that no spider holds (their columns are 3 k + (0, 1, 2)).

    """
    owner = -np.ones(n_nodes, int)
    for j, spider in enumerate(spiders):
        owner[spider.slaves] = j
    free_nodes = np.flatnonzero(owner < 0)
    n_free = 3 * len(free_nodes)
    rows, cols, vals = [], [], []
    node_dofs = 3 * free_nodes[:, None] + np.arange(3)
    rows.append(node_dofs.ravel())
    cols.append(np.arange(n_free))
    vals.append(np.ones(n_free))
    for j, spider in enumerate(spiders):
        master_col = n_free + 6 * j
        rows.append(3 * n_nodes + 6 * j + np.arange(6))
        cols.append(master_col + np.arange(6))
        vals.append(np.ones(6))
        slaves = np.asarray(spider.slaves, int)
        lever = np.asarray(xyz, float)[slaves] - spider.master
        # u_s = u_m - [r]x theta: rows (slave, c), columns master u_c and theta_d
        block = np.zeros((len(slaves), 3, 6))
        block[:, :, :3] = np.eye(3)
        block[:, :, 3:] = -np.moveaxis(skew(lever.T), -1, 0)
        r = np.repeat(3 * slaves[:, None] + np.arange(3), 6, axis=1).reshape(len(slaves), 3, 6)
        c = np.broadcast_to(master_col + np.arange(6), (len(slaves), 3, 6))
        keep = block != 0.0
        rows.append(r[keep])
        cols.append(c[keep])
        vals.append(block[keep])
    shape = (3 * n_nodes + 6 * len(spiders), n_free + 6 * len(spiders))
    t = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=shape)
    return t, free_nodes


def plane_rotation(normal):
    """Rotation matrix that turns the unit vector along ``normal`` onto +y (the smallest turn;
    a half turn about z for -y)."""
    n = np.asarray(normal, float)
    n = n / np.linalg.norm(n)
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(n, y)
    s, c = np.linalg.norm(axis), float(n @ y)
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([-1.0, -1.0, 1.0])
    k = skew(axis / s)
    return np.eye(3) + s * k + (1 - c) * (k @ k)


_FACES = {
    4: [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)],
    8: [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)],
}


def boundary_edges(blocks):
    """Corner-to-corner edges (n, 2) of the mesh's outer surface (faces that one element has)."""
    faces = []
    for block in blocks:
        corners = np.asarray(block.cells)[:, :CORNERS[block.cell_type]]
        for local in _FACES[corners.shape[1]]:
            faces.append((len(local), corners[:, list(local)]))
    edges = []
    for size in (3, 4):
        group = [f for n, f in faces if n == size]
        if not group:
            continue
        allf = np.vstack(group)
        _, first, count = np.unique(np.sort(allf, axis=1), axis=0, return_index=True,
                                    return_counts=True)
        outer = allf[first[count == 1]]
        for i in range(size):
            edges.append(np.column_stack([outer[:, i], outer[:, (i + 1) % size]]))
    if not edges:
        return np.zeros((0, 2), int)
    return np.unique(np.sort(np.vstack(edges), axis=1), axis=0)


@dataclass(frozen=True, eq=False)
class MeshComponent(ComponentModel):
    """A clamped component of solid elements (module docstring).

    Nodes: the mesh's nodes (``mesh_xyz``, component frame [m]) first, then one master node per
    spider (clamps in their order, the loaded end, then the rigid parts' sets). ``clamp_nodes``,
    ``loaded_end``, ``interface_nodes`` and ``node_names`` (set name -> master node) index them.
    ``parts``: (master node, mass [kg], inertia about cg (3x3) [kg m^2], cg [m]).
    """

    name: str
    mesh_xyz: np.ndarray
    blocks: tuple
    spiders: tuple
    material: dict
    clamp_nodes: tuple
    loaded_end: int
    interface_nodes: tuple
    node_names: dict
    origin: np.ndarray
    parts: tuple = ()
    source: str = ""
    mesh_file: str = ""
    damping_ratio: object = DEFAULT_DAMPING_RATIO
    element_ids: str = field(default="", repr=False)

    kind = "mesh"
    singular_hint = "check that the mesh is one connected body and that mesh.clamps hold it"

    def reduction_inputs(self):
        """The YAML and the mesh file: their bytes decide the reduction (cached on disk)."""
        return (self.source, self.mesh_file) if self.source and self.mesh_file else ()

    @property
    def n_mesh_nodes(self):
        """Number of mesh nodes (the spider masters follow them)."""
        return len(self.mesh_xyz)

    @property
    def node_xyz(self):
        """Mesh nodes, then spider masters, (n, 3) [m] in the component frame."""
        return np.vstack([self.mesh_xyz, [s.master for s in self.spiders]])

    @cached_property
    def elements(self):
        """The mesh's surface edges (n, 2) node indices, for drawing."""
        return boundary_edges(self.blocks)

    @cached_property
    def solid_matrices(self):
        """(K, M) of the solid elements alone, 3 DOFs per mesh node [N/m, kg]."""
        mat = self.material
        try:
            return assemble_solid(self.mesh_xyz, self.blocks, mat["E"], mat["nu"], mat["rho"])
        except ElementError as exc:
            raise ConfigError(self.source, "mesh.file",
                              f"{self.mesh_file}: {exc}; element numbers are "
                              f"{self.element_ids}") from None

    def constraint(self):
        """(T, free_nodes) of the spiders (:func:`spider_transform`)."""
        return spider_transform(self.n_mesh_nodes, self.mesh_xyz, self.spiders)

    @cached_property
    def _assembled(self):
        k_solid, m_solid = self.solid_matrices
        n, ns = self.n_mesh_nodes, len(self.spiders)
        n_full = 3 * n + 6 * ns
        pad = sp.csr_matrix((n_full, n_full))
        k_full = pad + sp.block_diag([k_solid, sp.csr_matrix((6 * ns, 6 * ns))], format="csr")
        m_full = pad + sp.block_diag([m_solid, sp.csr_matrix((6 * ns, 6 * ns))], format="csr")
        if self.parts:
            rows, cols, vals = [], [], []
            xyz = self.node_xyz
            for node, mass, inertia, cg in self.parts:
                block = rigid_body_mass(mass, inertia, cg - xyz[node])
                dofs = 3 * n + 6 * (node - n) + np.arange(6)
                rows.append(np.repeat(dofs, 6))
                cols.append(np.tile(dofs, 6))
                vals.append(block.ravel())
            m_full = m_full + sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                                    np.concatenate(cols))),
                                            shape=(n_full, n_full))
        # the solid elements' own matrices are not needed any more: free them before the
        # reduction factorises (they are as large as K and M)
        self.__dict__.pop("solid_matrices", None)
        del k_solid, m_solid
        t, free_nodes = self.constraint()
        k = (t.T @ k_full @ t).tocsc()
        m = (t.T @ m_full @ t).tocsc()
        del k_full, m_full
        k, m = 0.5 * (k + k.T), 0.5 * (m + m.T)
        # expand: free DOFs -> six DOFs per node (mesh nodes: translations; rotations zero)
        n_nodes = n + ns
        six = np.concatenate([(6 * np.arange(n)[:, None] + np.arange(3)).ravel(),
                              6 * n + np.arange(6 * ns)])
        select = sp.csr_matrix((np.ones(n_full), (six, np.arange(n_full))),
                               shape=(6 * n_nodes, n_full))
        expand = (select @ t).tocsr()
        free_index = -np.ones(6 * n_nodes, int)
        free_index[(6 * free_nodes[:, None] + np.arange(3)).ravel()] = np.arange(
            3 * len(free_nodes))
        free_index[6 * n:] = 3 * len(free_nodes) + np.arange(6 * ns)
        return AssembledStructure(K=k.tocsc(), M=m.tocsc(), expand=expand,
                                  free_index=free_index)

    def assembled(self):
        """Sparse K, M over the free DOFs (spiders eliminated); computed once."""
        return self._assembled


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
                         damping_ratio=damping_ratio, element_ids=data.id_kind)


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
