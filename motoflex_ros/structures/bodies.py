"""A component as the paper's flexible bodies: one Craig-Bampton reduction per body, assembled.

Paper, Appendix and Table A.1: the front assembly is fork bridge, two stanchions, lower fork and
longitudinal arm; the swingarm lower link, upper link and wheel carrier; the frame one body on
a rigid engine. Each body is reduced by Craig-Bampton (20 fixed-interface modes, content up to
600 Hz) with its joint points as boundary nodes, and the reduced bodies are joined by the
joints. Here the bodies of a beam component are found from its model, not declared:

- a body is a connected set of nodes held together by beam elements and full rigid links;
- a joint is what joins two bodies: a spring (the component's joint springs: bearings,
  bushings, ball joints) or a rigid link of the translations only (a spherical joint);
- a node held by springs alone (an engine mount, the steering-head clamp) is a body without
  elasticity, its six DOFs all boundary.

The boundary nodes of a body are its nodes that a joint uses, plus the component's own
interface nodes (clamps, loaded end) that lie in it. :func:`assemble_bodies` joins the reduced
bodies (component-mode synthesis): coordinates are each body's (u_b, eta) in turn; springs add
their 12 x 12 stiffness on the two boundary nodes; a spherical link eliminates the slave's
translations (u_s = u_m + theta_m x (x_s - x_m), as :class:`Structure` does); the clamps are
removed. With every boundary DOF kept, the static response is the full model's exactly (the
constraint modes span it); the frequencies converge from above as modes are added.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import skew
from motoflex_ros.structures.assembly import Structure, rigid_body_mass, rigid_field
from motoflex_ros.structures.craig_bampton import F_MAX_HZ, N_MODES, craig_bampton

__all__ = ["FlexibleBody", "BodyAssembly", "split_bodies", "body_mass_properties",
           "reduce_bodies", "assemble_bodies"]


@dataclass(frozen=True)
class FlexibleBody:
    """One body of a component, reduced: ``name`` (its first named node), ``nodes`` and
    ``boundary`` (component node indices), reduced M [kg..] and K [N/m..] in coordinates
    (6 DOFs per boundary node in ``boundary`` order, then ``n_modes`` modal amplitudes),
    ``fe_dofs`` the DOF count of the body's own unreduced model."""

    name: str
    nodes: tuple
    boundary: tuple
    M: np.ndarray
    K: np.ndarray
    n_modes: int
    fe_dofs: int

    @property
    def n(self):
        """Number of reduced coordinates (boundary DOFs + modes)."""
        return self.K.shape[0]

    def table_a1(self):
        """Reduced DOFs as Table A.1 writes them: 'modes+boundary'."""
        return f"{self.n_modes}+{6 * len(self.boundary)}"


@dataclass(frozen=True)
class BodyAssembly:
    """The joined reduced bodies with the clamps removed: K, M over ``n`` coordinates and the
    coordinates of each non-clamped boundary node (``node_dofs[node]``: six indices)."""

    K: np.ndarray
    M: np.ndarray
    node_dofs: dict

    def static_compliance(self, node):
        """6 x 6 compliance [m/N, rad/(N m)..] of boundary ``node`` (load and motion there)."""
        dofs = self.node_dofs[node]
        rhs = np.zeros((self.K.shape[0], 6))
        rhs[dofs, np.arange(6)] = 1.0
        return np.linalg.solve(self.K, rhs)[dofs]

    def frequencies_hz(self):
        """Natural frequencies [Hz], ascending."""
        w2 = sla.eigh(self.K, self.M, eigvals_only=True)
        return np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)


def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


def split_bodies(structure):
    """Node sets of the bodies of ``structure`` (beam elements and full rigid links hold a body
    together; springs and translation-only links join bodies), each sorted, ordered by their
    first node."""
    parent = list(range(len(structure.nodes)))
    pairs = [(e[0], e[1]) for e in structure.elements]
    pairs += [(m, s) for m, s, dofs in structure.links if len(dofs) == 6]
    for a, b in pairs:
        ra, rb = _find(parent, a), _find(parent, b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    groups = {}
    for node in range(len(parent)):
        groups.setdefault(_find(parent, node), []).append(node)
    return [tuple(g) for _, g in sorted(groups.items())]


def _joints(structure, body_of):
    """Springs and translation-only links between two different bodies."""
    springs = [s for s in structure.springs if body_of[s[0]] != body_of[s[1]]]
    links = [lk for lk in structure.links if body_of[lk[0]] != body_of[lk[1]]]
    if any(len(dofs) != 3 for _, _, dofs in links):
        raise ModelError("a rigid link joining two bodies must link the translations only")
    return springs, links


def _body_structure(structure, nodes):
    """The sub-structure of one body (its elements, internal links and springs, rigid parts),
    nodes renumbered in ``nodes`` order."""
    local = {n: i for i, n in enumerate(nodes)}
    sub = Structure()
    for n in nodes:
        sub.add_node(structure.nodes[n])
    for n1, n2, section, material, up in structure.elements:
        if n1 in local:
            sub.add_element(local[n1], local[n2], section, material, up)
    for master, slave, dofs in structure.links:
        if master in local and slave in local:
            sub.add_link(local[master], local[slave], dofs)
    for n1, n2, block in structure.springs:
        if n1 in local and n2 in local:
            sub.springs.append((local[n1], local[n2], block))
    for node, mass, inertia, cg in structure.parts:
        if node in local:
            sub.add_part(local[node], mass, inertia, cg)
    return sub, local


def body_mass_properties(structure, nodes):
    """Mass [kg], centre of mass [m] and inertia tensor about it [kg m^2] (structure frame) of
    ``nodes`` (one body or several, :func:`split_bodies`) as one rigid body: the consistent
    beam mass matrices and rigid parts on them moved by one rigid motion, the nodes clamped on
    the bench or linked to another body included (a clamp or a spherical link holds a node,
    it takes none of its mass away)."""
    sub, _ = _body_structure(structure, nodes)
    if sub.elements:
        asm = sub.assemble()
        gamma = rigid_field(sub.xyz)[asm.free_index >= 0]
        rigid = gamma.T @ (asm.M @ gamma)
    else:
        rigid, _ = _bare_node(structure, nodes[0])
        gamma = rigid_field(sub.xyz)
        rigid = gamma.T @ rigid @ gamma
    mass = rigid[3, 3]
    lever = -rigid[3:, :3] / mass            # [c]x (rows v_0, columns omega)
    com = np.array([lever[2, 1], lever[0, 2], lever[1, 0]])
    inertia = rigid[:3, :3] - mass * (com @ com * np.eye(3) - np.outer(com, com))
    return mass, com, (inertia + inertia.T) / 2


def _bare_node(structure, node):
    """(M, K) of a body that is one node without elements: its rigid parts' mass, no stiffness
    of its own (the joints hold it)."""
    m = np.zeros((6, 6))
    for n, mass, inertia, cg in structure.parts:
        if n == node:
            m += rigid_body_mass(mass, inertia, cg - structure.nodes[node])
    return m, np.zeros((6, 6))


def _body_name(component, nodes):
    """The name the component's ``bodies`` key gives the body of ``nodes``, else its first
    named node; ModelError when two names are given to one body."""
    given = [b for b, n in (component.body_names or {}).items() if n in nodes]
    if len(given) > 1:
        raise ModelError(f"{component.source or component.name}: bodies.{given[0]} and "
                         f"bodies.{given[1]} name the same body; give each body one name")
    names = {i: n for n, i in component.node_names.items()}
    return given[0] if given else next((names[n] for n in nodes if n in names),
                                       f"node{nodes[0]}")


def reduce_bodies(component, n_modes=N_MODES, f_max_hz=F_MAX_HZ):
    """FlexibleBody list of ``component``: each body reduced by Craig-Bampton with all DOFs of
    its boundary nodes kept (Table A.1: 20 modes per body, content up to 600 Hz)."""
    structure = component.structure
    bodies = split_bodies(structure)
    body_of = {n: b for b, nodes in enumerate(bodies) for n in nodes}
    springs, links = _joints(structure, body_of)
    joint_nodes = {n for s in springs for n in s[:2]} | {n for lk in links for n in lk[:2]}
    joint_nodes |= set(component.interface_nodes)
    out = []
    for nodes in bodies:
        boundary = tuple(n for n in nodes if n in joint_nodes)
        name = _body_name(component, nodes)
        if not boundary:
            raise ModelError(f"{component.source or component.name}: body '{name}' is joined "
                             "to nothing (no spring, link or interface node holds it)")
        if len(nodes) == 1:
            m, k = _bare_node(structure, nodes[0])
            out.append(FlexibleBody(name, nodes, boundary, m, k, 0, 6))
            continue
        sub, local = _body_structure(structure, nodes)
        asm = sub.assemble()
        try:
            dofs = np.concatenate([asm.node_dofs(local[n]) for n in boundary])
        except ModelError:
            raise ModelError(f"{component.source or component.name}: body '{name}': a joint "
                             "or interface node is the slave of a rigid link; attach the joint "
                             "to its master") from None
        cb = craig_bampton(asm.K, asm.M, dofs, n_modes, f_max_hz, 0.0)
        out.append(FlexibleBody(name, nodes, boundary, cb.M, cb.K, cb.n_modes,
                                int(asm.K.shape[0])))
    return out


def assemble_bodies(component, bodies):
    """BodyAssembly: the reduced ``bodies`` (:func:`reduce_bodies`) of ``component`` joined by
    its springs and spherical links, clamps removed (module docstring)."""
    structure = component.structure
    body_of = {n: b for b, body in enumerate(bodies) for n in body.nodes}
    springs, links = _joints(structure, body_of)
    offsets = np.cumsum([0] + [b.n for b in bodies])
    n = int(offsets[-1])
    node_dofs = {node: offsets[b] + 6 * i + np.arange(6)
                 for b, body in enumerate(bodies) for i, node in enumerate(body.boundary)}
    k = sp.block_diag([b.K for b in bodies]).toarray()
    m = sp.block_diag([b.M for b in bodies]).toarray()
    for n1, n2, block in springs:
        d1, d2 = node_dofs[n1], node_dofs[n2]
        k[np.ix_(d1, d1)] += block
        k[np.ix_(d2, d2)] += block
        k[np.ix_(d1, d2)] -= block
        k[np.ix_(d2, d1)] -= block
    t = np.eye(n)
    for master, slave, _ in links:   # translations only (checked in _joints)
        lever = structure.nodes[slave] - structure.nodes[master]
        s, mdofs = node_dofs[slave][:3], node_dofs[master]
        t[s] = 0.0
        t[np.ix_(s, mdofs[:3])] = np.eye(3)
        t[np.ix_(s, mdofs[3:])] = -skew(lever)
    removed = {int(i) for _, slave, _ in links for i in node_dofs[slave][:3]}
    removed |= {int(i) for c in component.clamp_nodes for i in node_dofs[c]}
    keep = np.array([i for i in range(n) if i not in removed])
    t = t[:, keep]
    where = -np.ones(n, int)
    where[keep] = np.arange(len(keep))
    kept_dofs = {node: where[d] for node, d in node_dofs.items()
                 if node not in component.clamp_nodes and np.all(where[d] >= 0)}
    return BodyAssembly(t.T @ k @ t, t.T @ m @ t, kept_dofs)
