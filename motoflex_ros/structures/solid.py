"""Linear elasticity on solid elements: sparse stiffness and mass of a volume mesh.

Element types (meshio's names and VTK node order, which meshio gives every format it reads):
linear and quadratic tetrahedra (``tetra``, ``tetra10``), linear, serendipity and triquadratic
hexahedra (``hexahedron``, ``hexahedron20``, ``hexahedron27``). Every element is isoparametric:
the geometry is interpolated with the element's own shape functions, so the midside nodes of a
curved quadratic mesh (a tube meshed by gmsh) keep the geometry curved.

The reference elements (shape functions and their derivatives) and the quadrature rules are
scikit-fem's (:mod:`skfem.element`, :func:`skfem.quadrature.get_quadrature`); the contraction
into element matrices and the sparse assembly are vectorised numpy here, element chunk by chunk.
Two reasons not to use scikit-fem's ``BilinearForm.assemble`` for this: it evaluates the form
once per pair of vector basis functions (900 calls for a quadratic tetrahedron), which made it
5-10x slower than this contraction on the same elements, and its global numbering is its own
(vertices, then edges, ...) where the bench needs the file's nodes; here a node's DOFs are
``3 * node + (0, 1, 2)`` for (u_x, u_y, u_z) [m] in the order of the given points.

Quadrature: Gauss rules exact for the mass matrix of an undistorted element (tetra 2nd/4th
order, hexahedra 2x2x2 and 3x3x3), the stiffness of the quadratic tetrahedron with the usual
4-point rule. Every element's Jacobian determinant is checked at its quadrature points and at its
nodes: an inverted, degenerate (zero-volume) or badly distorted element is refused by name.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from motoflex_ros.errors import ModelError

__all__ = ["SOLID_TYPES", "SolidBlock", "ElementError", "assemble_solid", "element_volumes",
           "solid_type", "block_dofs", "CORNERS"]

_TET = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
_TET_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
_HEX = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                 [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
_HEX_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
              (0, 4), (1, 5), (2, 6), (3, 7)]
# VTK_TRIQUADRATIC_HEXAHEDRON (vtkTriQuadraticHexahedron's parametric coordinates, as meshio and
# scikit-fem's meshio interface order them): mid-face nodes on x = 0, x = 1, y = 0, y = 1, z = 0,
# z = 1, then the centre
_HEX_FACES = [(0, 3, 7, 4), (1, 2, 6, 5), (0, 1, 5, 4), (3, 2, 6, 7), (0, 1, 2, 3),
              (4, 5, 6, 7)]


def _mids(corners, groups):
    return np.array([corners[list(g)].mean(axis=0) for g in groups])


# reference coordinates of the nodes in VTK (meshio) order
_VTK_REFERENCE = {
    "tetra": _TET,
    "tetra10": np.vstack([_TET, _mids(_TET, _TET_EDGES)]),
    "hexahedron": _HEX,
    "hexahedron20": np.vstack([_HEX, _mids(_HEX, _HEX_EDGES)]),
    "hexahedron27": np.vstack([_HEX, _mids(_HEX, _HEX_EDGES), _mids(_HEX, _HEX_FACES),
                               _HEX.mean(axis=0, keepdims=True)]),
}
CORNERS = {"tetra": 4, "tetra10": 4, "hexahedron": 8, "hexahedron20": 8, "hexahedron27": 8}
"""Number of corner nodes of each type (the first nodes in VTK order)."""

# scikit-fem element, quadrature order of the stiffness and of the mass
_RULES = {
    "tetra": ("ElementTetP1", 2, 2),
    "tetra10": ("ElementTetP2", 2, 4),
    "hexahedron": ("ElementHex1", 3, 3),
    "hexahedron20": ("ElementHexS2", 5, 5),
    "hexahedron27": ("ElementHex2", 5, 5),
}
SOLID_TYPES = tuple(_RULES)
"""The volume element types assembled (meshio names)."""

# a Jacobian determinant below this share of the element's mean one is "degenerate": the shape
# functions' gradients blow up (a flat or needle element, or a midside node pulled across)
DEGENERATE_SHARE = 1e-6


@dataclass(frozen=True)
class SolidBlock:
    """Elements of one type: ``cell_type`` (meshio name), ``cells`` (n_e, n_nodes) node
    indices in VTK order, ``ids`` the elements' numbers in the file (for messages)."""

    cell_type: str
    cells: np.ndarray
    ids: np.ndarray


class ElementError(ModelError):
    """An element that cannot be assembled: ``kind`` is 'inverted' or 'degenerate'; the
    element's type and its number in the file are in ``cell_type`` and ``element_id``."""

    def __init__(self, kind, cell_type, element_id, detail):
        self.kind, self.cell_type, self.element_id = kind, cell_type, element_id
        super().__init__(f"{cell_type} element {element_id} is {kind} ({detail})")


class _Reference:
    """Shape functions of one type at given reference points, in VTK node order."""

    def __init__(self, cell_type):
        import skfem
        name, self.k_order, self.m_order = _RULES[cell_type]
        self.element = getattr(skfem, name)()
        locs = np.asarray(self.element.doflocs, float)
        vtk = _VTK_REFERENCE[cell_type]
        # skfem's local function j sits at the VTK node order[j]
        dist = np.linalg.norm(locs[:, None, :] - vtk[None, :, :], axis=2)
        self.order = np.argmin(dist, axis=1)
        if not (np.allclose(dist[np.arange(len(locs)), self.order], 0.0)
                and len(set(self.order)) == len(vtk)):
            raise AssertionError(f"node order of {cell_type} does not match scikit-fem's")
        self.n = len(vtk)

    def at(self, points):
        """(N (n_q, n), dN/dxi (n_q, n, 3)) in VTK node order at reference ``points`` (n_q, 3)."""
        x = np.asarray(points, float).T
        n = np.zeros((x.shape[1], self.n))
        dn = np.zeros((x.shape[1], self.n, 3))
        for j in range(self.n):
            phi, dphi = self.element.lbasis(x, j)
            n[:, self.order[j]] = phi
            dn[:, self.order[j], :] = np.asarray(dphi).T
        return n, dn

    def rule(self, order):
        """Quadrature points (n_q, 3) and weights (n_q,) of scikit-fem's rule of ``order``."""
        from skfem.quadrature import get_quadrature
        x, w = get_quadrature(self.element.refdom, order)
        return x.T, w

    def nodes(self):
        """Reference coordinates of the nodes, VTK order."""
        return _VTK_REFERENCE_BY_N[self.n]


_VTK_REFERENCE_BY_N = {len(v): v for v in _VTK_REFERENCE.values()}
_REFERENCES = {}


def _reference(cell_type):
    if cell_type not in _REFERENCES:
        _REFERENCES[cell_type] = _Reference(cell_type)
    return _REFERENCES[cell_type]


def solid_type(cell_type):
    """True when ``cell_type`` (a meshio cell type name) is a volume element assembled here."""
    return cell_type in _RULES


def _jacobians(xyz, dn):
    """J (n_e, n_q, 3, 3) with J[.., i, j] = d x_i / d xi_j, from node coordinates (n_e, n, 3)
    and reference gradients (n_q, n, 3)."""
    return np.einsum("eai,qaj->eqij", xyz, dn)


def _check_jacobians(det, block, rows):
    """ElementError for the first element whose Jacobian determinant ``det`` (n_e, n_q) is not
    positive everywhere (``rows``: the elements' rows in ``block``)."""
    scale = np.abs(det).max(axis=1)
    bad = np.any(det <= DEGENERATE_SHARE * scale[:, None], axis=1) | (scale == 0)
    if not np.any(bad):
        return
    e = int(np.flatnonzero(bad)[0])
    element_id = int(block.ids[rows[e]])
    if scale[e] > 0 and np.all(det[e] < 0):
        raise ElementError("inverted", block.cell_type, element_id,
                           "negative volume: its nodes are numbered the wrong way round")
    if scale[e] > 0 and np.any(det[e] < -DEGENERATE_SHARE * scale[e]):
        raise ElementError("inverted", block.cell_type, element_id,
                           "the Jacobian changes sign inside it: a node is pulled across the "
                           "element")
    raise ElementError("degenerate", block.cell_type, element_id,
                       "zero or nearly zero volume: coincident or coplanar nodes")


def element_volumes(points, block):
    """Volume [m^3] of each element of ``block`` (positive; ElementError as in assembly)."""
    ref = _reference(block.cell_type)
    xq, wq = ref.rule(ref.m_order)
    _, dn = ref.at(xq)
    xyz = np.asarray(points, float)[block.cells]
    det = np.linalg.det(_jacobians(xyz, dn))
    _check_jacobians(det, block, np.arange(len(block.cells)))
    return det @ wq


def block_dofs(cells):
    """Global DOF numbers (n_e, 3 n) of elements ``cells`` (n_e, n): 3 node + (x, y, z)."""
    return (3 * cells[:, :, None] + np.arange(3)).reshape(len(cells), -1)


def _stiffness(g, w, lam, mu):
    """Element stiffness as 3x3 node blocks (n_e, n, n, 3, 3) from physical gradients g
    (n_e, n_q, n, 3) and quadrature weights times |J| w (n_e, n_q) of an isotropic material
    (Lame lam, mu): K_ab = lam A_ab + mu A_ab^T + mu tr(A_ab) 1, A_ab = sum_q w g_a g_b^T."""
    a = np.einsum("eqai,eqbj,eq->eabij", g, g, w, optimize=True)
    k = lam * a + mu * a.transpose(0, 1, 2, 4, 3)
    trace = np.einsum("eabkk->eab", a)
    for i in range(3):
        k[..., i, i] += mu * trace
    # exactly symmetric: K_ba = K_ab^T
    return 0.5 * (k + k.transpose(0, 2, 1, 4, 3))


def _gradients(xyz, dn, block, rows):
    jac = _jacobians(xyz, dn)
    det = np.linalg.det(jac)
    _check_jacobians(det, block, rows)
    inv = np.linalg.inv(jac)
    # dN/dx_i = sum_j dN/dxi_j (J^-1)_ji
    return np.einsum("qaj,eqji->eqai", dn, inv, optimize=True), det


def _pattern(blocks, n_points):
    """Node-pair pattern of all elements: unique pairs (row, col) sorted row-major and, per
    block, the index of every element's (a, b) pair among them (n_e * n * n,)."""
    keys = []
    for block in blocks:
        cells = np.asarray(block.cells, np.int64)
        keys.append((cells[:, :, None] * n_points + cells[:, None, :]).ravel())
    unique, inverse = np.unique(np.concatenate(keys), return_inverse=True)
    splits = np.cumsum([k.size for k in keys])[:-1]
    return unique // n_points, unique % n_points, np.split(inverse, splits)


def assemble_solid(points, blocks, young, poisson, density, chunk=20000, progress=None):
    """Sparse stiffness K [N/m] and mass M [kg] (CSR, 3 n_points square) of solid ``blocks``.

    Parameters
    ----------
    points : array (n_points, 3)
        Node coordinates [m]; a node's DOFs are 3 i + (0, 1, 2).
    blocks : sequence of SolidBlock
        The elements, one block per type.
    young, poisson, density : float
        E [Pa], nu [-] (in (-1, 0.5)), rho [kg/m^3] of the isotropic material.
    chunk : int
        Elements contracted at a time (bounds the temporaries: about 15 kB per quadratic
        tetrahedron).
    progress : callable or None
        Called with the number of elements done after each chunk.

    Returns
    -------
    (K, M) : scipy.sparse.csr_matrix
        Exactly symmetric. Nodes that no element uses have empty rows and columns.

    """
    points = np.asarray(points, float)
    n_points = len(points)
    if not any(len(b.cells) for b in blocks):
        raise ModelError("the mesh has no volume elements")
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    rows, cols, inverses = _pattern(blocks, n_points)
    nnz = len(rows)
    k_data = np.zeros((nnz, 3, 3))
    m_data = np.zeros(nnz)
    for block, inverse in zip(blocks, inverses):
        ref = _reference(block.cell_type)
        xk, wk = ref.rule(ref.k_order)
        xm, wm = ref.rule(ref.m_order)
        _, dnk = ref.at(xk)
        nm, dnm = ref.at(xm)
        _, dn_nodes = ref.at(ref.nodes())
        cells = np.asarray(block.cells)
        pairs = cells.shape[1] ** 2
        for start in range(0, len(cells), chunk):
            sel = np.arange(start, min(start + chunk, len(cells)))
            xyz = points[cells[sel]]
            # the Jacobian at the nodes too: a quadratic element can fold between Gauss points
            _check_jacobians(np.linalg.det(_jacobians(xyz, dn_nodes)), block, sel)
            g, detk = _gradients(xyz, dnk, block, sel)
            ke = _stiffness(g, detk * wk, lam, mu).reshape(-1, 9)
            detm = np.linalg.det(_jacobians(xyz, dnm))
            _check_jacobians(detm, block, sel)
            me = density * np.einsum("qa,qb,eq->eab", nm, nm, detm * wm, optimize=True)
            index = inverse[start * pairs:(start + len(sel)) * pairs]
            for c in range(9):
                k_data[:, c // 3, c % 3] += np.bincount(index, ke[:, c], minlength=nnz)
            m_data += np.bincount(index, me.ravel(), minlength=nnz)
            if progress is not None:
                progress(len(sel))
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n_points))])
    shape = (3 * n_points, 3 * n_points)
    k = sp.bsr_matrix((k_data, cols, indptr), shape=shape, blocksize=(3, 3))
    m = sp.bsr_matrix((m_data[:, None, None] * np.eye(3), cols, indptr), shape=shape,
                      blocksize=(3, 3))
    return k.tocsr(), m.tocsr()
