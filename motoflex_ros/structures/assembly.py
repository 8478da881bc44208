"""A beam structure and its global sparse stiffness and mass matrices.

A :class:`Structure` holds nodes, Timoshenko beam elements (section + material), rigid links
(the slave node's DOFs are eliminated: u_s = u_m + theta_m x (x_s - x_m), theta_s = theta_m, for
the linked DOFs only, so a link on translations alone is a spherical joint), lumped rigid parts
(mass and 3x3 inertia about their centre of gravity, attached to a node), springs between nodes
(joints, diagonal in global axes) and clamped nodes. :meth:`Structure.assemble` returns an
:class:`AssembledStructure`: K and M over the independent, unclamped DOFs and the sparse map
from those DOFs to all node DOFs (ux, uy, uz, rx, ry, rz per node).
"""
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import skew
from motoflex_ros.structures.beam import global_element_matrices

__all__ = ["Structure", "AssembledStructure", "rigid_body_mass", "rigid_field"]


def _concat(parts):
    return np.concatenate(parts) if parts else np.zeros(0)


def rigid_body_mass(mass, inertia_cg, offset):
    """6x6 mass matrix of a rigid part seen at a node [kg, kg m, kg m^2].

    The part's centre of gravity sits at ``offset`` [m] from the node; ``inertia_cg`` [kg m^2]
    (3x3) is about the centre of gravity. Its velocity is v + omega x c, so M = G^T diag(m 1,
    I_cg) G with G = [[1, -[c]x], [0, 1]].
    """
    g = np.eye(6)
    g[:3, 3:] = -skew(np.asarray(offset, float))
    d = np.zeros((6, 6))
    d[:3, :3] = mass * np.eye(3)
    d[3:, 3:] = np.asarray(inertia_cg, float)
    return g.T @ d @ g


def rigid_field(xyz):
    """Rigid-motion field (6 n_nodes, 6) of nodes at ``xyz`` [m]: columns (omega, v_0).

    Node translation v_0 + omega x r = v_0 - [r]x omega; node rotation omega.
    """
    n = len(xyz)
    field = np.zeros((n, 6, 6))
    r = np.asarray(xyz, float)
    field[:, 0:3, 0:3] = -np.moveaxis(skew(r.T), -1, 0)
    field[:, 0:3, 3:6] = np.eye(3)
    field[:, 3:6, 0:3] = np.eye(3)
    return field.reshape(6 * n, 6)


@dataclass(frozen=True)
class AssembledStructure:
    """K [N/m..], M [kg..] over the free DOFs; ``expand`` maps them to all node DOFs.

    ``free_index[6 * node + dof]`` is the free-DOF index of a node DOF that is independent and
    unclamped, -1 otherwise.
    """

    K: sp.csc_matrix
    M: sp.csc_matrix
    expand: sp.csr_matrix
    free_index: np.ndarray

    def node_dofs(self, node):
        """Free-DOF indices of the 6 DOFs of ``node``; raises if any is eliminated/clamped."""
        idx = self.free_index[6 * node:6 * node + 6]
        if np.any(idx < 0):
            raise ModelError(f"node {node} has clamped or linked DOFs; it cannot be an "
                             "interface node")
        return idx


@dataclass
class Structure:
    """Mutable builder of a beam structure; node coordinates in metres."""

    nodes: list = field(default_factory=list)
    elements: list = field(default_factory=list)
    links: list = field(default_factory=list)
    parts: list = field(default_factory=list)
    springs: list = field(default_factory=list)
    clamped: set = field(default_factory=set)

    def add_node(self, xyz):
        """Add a node at ``xyz`` [m]; returns its index."""
        self.nodes.append(np.asarray(xyz, float))
        return len(self.nodes) - 1

    def add_element(self, n1, n2, section, material, up=(0.0, 0.0, 1.0)):
        """Add a beam element between nodes n1 and n2 (section, material, orientation up)."""
        self.elements.append((n1, n2, section, material, np.asarray(up, float)))

    def add_member(self, n1, n2, count, section, material, up=(0.0, 0.0, 1.0)):
        """Add a straight member split into ``count`` elements; returns its node indices."""
        a, b = self.nodes[n1], self.nodes[n2]
        chain = [n1] + [self.add_node(a + (b - a) * s / count) for s in range(1, count)] + [n2]
        for i, j in zip(chain[:-1], chain[1:]):
            self.add_element(i, j, section, material, up)
        return chain

    def add_link(self, master, slave, dofs=tuple(range(6))):
        """Rigid link: the slave node's ``dofs`` follow the master node rigidly."""
        self.links.append((master, slave, tuple(dofs)))

    def add_part(self, node, mass, inertia_cg, cg):
        """Rigid part of ``mass`` [kg], inertia about its cg [kg m^2] (3x3), cg at ``cg`` [m]."""
        self.parts.append((node, float(mass), np.asarray(inertia_cg, float),
                           np.asarray(cg, float)))

    def add_spring(self, n1, n2, k_translation, k_rotation, axes=None):
        """Spring between two nodes: [N/m] x3 and [N m/rad] x3, diagonal in ``axes``.

        ``axes`` (3x3, columns = the spring's x, y, z in global axes) defaults to global.
        """
        rot = np.eye(3) if axes is None else np.asarray(axes, float)
        block = np.zeros((6, 6))
        block[:3, :3] = rot @ np.diag(k_translation) @ rot.T
        block[3:, 3:] = rot @ np.diag(k_rotation) @ rot.T
        self.springs.append((n1, n2, block))

    def clamp(self, node):
        """Fix all six DOFs of ``node``."""
        self.clamped.add(node)

    @property
    def xyz(self):
        """Node coordinates, shape (n_nodes, 3) [m]."""
        return np.array(self.nodes)

    def _element_triplets(self):
        xyz = self.xyz
        n1 = np.array([e[0] for e in self.elements])
        n2 = np.array([e[1] for e in self.elements])
        props = {key: np.array([getattr(e[2], key) for e in self.elements])
                 for key in ("A", "Iy", "Iz", "J", "A_sy", "A_sz")}
        for key in ("E", "G", "rho"):
            props[key] = np.array([getattr(e[3], key) for e in self.elements])
        up = np.array([e[4] for e in self.elements])
        k_e, m_e = global_element_matrices(xyz[n1], xyz[n2], up, props)
        dofs = np.concatenate([6 * n1[:, None] + np.arange(6), 6 * n2[:, None] + np.arange(6)],
                              axis=1)
        rows = np.repeat(dofs, 12, axis=1).ravel()
        cols = np.tile(dofs, (1, 12)).ravel()
        return rows, cols, k_e.ravel(), m_e.ravel()

    def _extra_triplets(self):
        """Lumped parts (mass) and springs (stiffness) as COO triplets."""
        m_rows, m_cols, m_vals, k_rows, k_cols, k_vals = [], [], [], [], [], []
        xyz = self.xyz
        for node, mass, inertia, cg in self.parts:
            block = rigid_body_mass(mass, inertia, cg - xyz[node])
            dofs = 6 * node + np.arange(6)
            m_rows.append(np.repeat(dofs, 6))
            m_cols.append(np.tile(dofs, 6))
            m_vals.append(block.ravel())
        for n1, n2, block in self.springs:
            for a, b, sign in ((n1, n1, 1), (n2, n2, 1), (n1, n2, -1), (n2, n1, -1)):
                k_rows.append(np.repeat(6 * a + np.arange(6), 6))
                k_cols.append(np.tile(6 * b + np.arange(6), 6))
                k_vals.append(sign * block.ravel())
        return [_concat(x) for x in (m_rows, m_cols, m_vals, k_rows, k_cols, k_vals)]

    def _link_map(self):
        """Sparse map T (n_dof x n_dof) from DOFs to themselves with linked slaves expressed
        through their masters; the columns of slave DOFs are empty."""
        n_dof = 6 * len(self.nodes)
        t = sp.lil_matrix((n_dof, n_dof))
        linked = np.zeros(n_dof, bool)
        for master, slave, dofs in self.links:
            lever = self.nodes[slave] - self.nodes[master]
            full = np.eye(6, 6)
            full[:3, 3:] = -skew(lever)
            for d in dofs:
                if linked[6 * slave + d]:
                    raise ModelError(f"node {slave} DOF {d} is linked twice")
                linked[6 * slave + d] = True
                t[6 * slave + d, 6 * master:6 * master + 6] = full[d]
        for i in np.flatnonzero(~linked):
            t[i, i] = 1.0
        t = t.tocsr()
        # chains of links: resolve until no column refers to a linked DOF
        for _ in range(len(self.links)):
            if not np.any(linked[t.nonzero()[1]]):
                break
            t = t @ t
        return t, linked

    def assemble(self):
        """Global sparse K and M over the free (independent, unclamped) DOFs."""
        if not self.elements:
            raise ModelError("the structure has no beam elements")
        n_dof = 6 * len(self.nodes)
        rows, cols, k_vals, m_vals = self._element_triplets()
        mr, mc, mv, kr, kc, kv = self._extra_triplets()
        k_full = sp.coo_matrix((np.r_[k_vals, kv], (np.r_[rows, kr], np.r_[cols, kc])),
                               shape=(n_dof, n_dof)).tocsr()
        m_full = sp.coo_matrix((np.r_[m_vals, mv], (np.r_[rows, mr], np.r_[cols, mc])),
                               shape=(n_dof, n_dof)).tocsr()
        link, linked = self._link_map()
        clamped = np.zeros(n_dof, bool)
        for node in self.clamped:
            clamped[6 * node:6 * node + 6] = True
        free = np.flatnonzero(~linked & ~clamped)
        expand = link[:, free].tocsr()
        free_index = -np.ones(n_dof, int)
        free_index[free] = np.arange(len(free))
        k_red = (expand.T @ k_full @ expand).tocsc()
        m_red = (expand.T @ m_full @ expand).tocsc()
        return AssembledStructure(K=k_red, M=m_red, expand=expand, free_index=free_index)
