"""A component of solid elements from the engineer's own volume mesh: rigid spiders at the
interfaces, the same chain as a beam component.

Built by :mod:`motoflex_ros.formats.mesh_component_file` from the ``component: mesh`` YAML and
the mesh file (the reader, :mod:`motoflex_ros.formats.mesh_file`); here is what the numerical
core needs of it: the model and the spiders' constraint.

Rigid spiders (RBE2-like) are exact multipoint constraints, eliminated by a transformation and
not enforced by penalties: each node s of a spider's set follows its master node m (six DOFs
at x_m) rigidly, u_s = u_m + theta_m x (x_s - x_m). With u = T v (v: the translations of the
free mesh nodes and the masters' six DOFs), K_v = T^T K T, M_v = T^T M T. A rigid part hangs on
the master of its set (a new spider when the set is not an interface), as on the beam
components.
"""
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from motoflex_ros.errors import ConfigError
from motoflex_ros.spatial import skew
from motoflex_ros.structures.assembly import AssembledStructure, rigid_body_mass
from motoflex_ros.structures.component_model import DEFAULT_DAMPING_RATIO, ComponentModel
from motoflex_ros.structures.solid import CORNERS, ElementError, assemble_solid

__all__ = ["MeshComponent", "Spider", "spider_transform", "boundary_edges", "plane_rotation"]


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
    ``source``, ``mesh_file``: the YAML and the mesh file it was read from; ``reader_files``:
    the reader's own source files (part of the reduction cache's key, as the solid elements'
    code is: :mod:`~motoflex_ros.structures.reduction_cache`).
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
    reader_files: tuple = field(default=(), repr=False)

    kind = "mesh"
    singular_hint = "check that the mesh is one connected body and that mesh.clamps hold it"

    def reduction_inputs(self):
        """The YAML, the mesh file and the source of the reader that read them
        (``reader_files``): their bytes decide the reduction (cached on disk)."""
        if not (self.source and self.mesh_file):
            return ()
        return (self.source, self.mesh_file, *self.reader_files)

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
