"""3D shear-deformable (Timoshenko) beam element with 6 DOF per node.

Node DOFs are (ux, uy, uz, rx, ry, rz) [m, rad]. The element's local x axis runs from node 1 to
node 2; the orientation vector ``up`` (global) fixes the local x-y plane, local z = x cross up.
Bending in the local x-y plane uses Iz and the shear area A_sy, bending in x-z uses Iy and A_sz.

Stiffness: the exact two-node Timoshenko element (Przemieniecki, *Theory of Matrix Structural
Analysis*, 1968, Sect. 5.6), shear parameter Phi = 12 E I / (G A_s L^2); it reproduces the
static cantilever solution exactly at the nodes. Mass: consistent translational + rotary
inertia of the same interpolation (Przemieniecki Sect. 11.5, Archer 1965). All element arrays
are built vectorised over elements, shape (n_elements, 12, 12).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError

__all__ = ["Section", "Material", "tube_section", "rectangular_tube_section", "element_frames",
           "local_stiffness", "local_mass", "global_element_matrices"]


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material: E, G [Pa], rho [kg/m^3]."""

    E: float
    G: float
    rho: float


@dataclass(frozen=True)
class Section:
    """Cross-section properties in the element's local axes.

    A [m^2]; Iy, Iz second moments about local y and z [m^4]; J torsion constant [m^4];
    A_sy, A_sz shear areas for shear along local y and z [m^2]; Ip polar moment for the rotary
    inertia [m^4] (Iy + Iz).
    """

    A: float
    Iy: float
    Iz: float
    J: float
    A_sy: float
    A_sz: float

    @property
    def Ip(self):
        """Polar second moment of area Iy + Iz [m^4] (rotary inertia about the beam axis)."""
        return self.Iy + self.Iz


def tube_section(outer_diameter, wall_thickness, nu=0.3):
    """Circular tube: section properties from D [m], t [m].

    Shear coefficient of a hollow circle after Cowper (1966), J. Appl. Mech. 33, 335-340:
    kappa = 6 (1+nu)(1+m^2)^2 / ((7+6 nu)(1+m^2)^2 + (20+12 nu) m^2), m = D_i / D.
    """
    d_out = float(outer_diameter)
    d_in = d_out - 2.0 * float(wall_thickness)
    area = np.pi / 4.0 * (d_out**2 - d_in**2)
    inertia = np.pi / 64.0 * (d_out**4 - d_in**4)
    m2 = (d_in / d_out) ** 2
    kappa = 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
    return Section(A=area, Iy=inertia, Iz=inertia, J=2.0 * inertia, A_sy=kappa * area,
                   A_sz=kappa * area)


def rectangular_tube_section(width, height, wall_thickness):
    """Thin-walled rectangular tube: width along local y, height along local z [m].

    Torsion constant by Bredt: J = 4 A_m^2 t / p_m (A_m, p_m area and perimeter of the wall's
    mid-line). Shear areas are the webs parallel to the shear: A_sz = 2 h t, A_sy = 2 w t.
    """
    w, h, t = float(width), float(height), float(wall_thickness)
    wi, hi = w - 2 * t, h - 2 * t
    area = w * h - wi * hi
    iy = (w * h**3 - wi * hi**3) / 12.0
    iz = (h * w**3 - hi * wi**3) / 12.0
    wm, hm = w - t, h - t
    torsion = 4.0 * (wm * hm) ** 2 * t / (2.0 * (wm + hm))
    return Section(A=area, Iy=iy, Iz=iz, J=torsion, A_sy=2 * w * t, A_sz=2 * h * t)


def element_frames(xyz1, xyz2, up):
    """Lengths [m] and rotation matrices (rows = local x, y, z in global axes), vectorised.

    ``up`` (n, 3) lies in the local x-y plane; it must not be parallel to the element.
    """
    axis = np.asarray(xyz2, float) - np.asarray(xyz1, float)
    length = np.linalg.norm(axis, axis=1)
    ex = axis / length[:, None]
    ez = np.cross(ex, np.asarray(up, float))
    nz = np.linalg.norm(ez, axis=1)
    if np.any(nz < 1e-8):
        raise ModelError("a member's orientation vector ('up') is parallel to the member "
                         "axis; give an 'up' vector across the member")
    ez /= nz[:, None]
    ey = np.cross(ez, ex)
    return length, np.stack([ex, ey, ez], axis=1)


def _bending_stiffness(ei, phi, length):
    """4x4 stiffness in the x-y plane, DOFs (v1, rz1, v2, rz2) [N/m, N, N m]."""
    L = length
    c = ei / ((1.0 + phi) * L**3)
    k = np.zeros(ei.shape + (4, 4))
    k[:, 0, 0] = k[:, 2, 2] = 12 * c
    k[:, 0, 2] = k[:, 2, 0] = -12 * c
    k[:, 0, 1] = k[:, 1, 0] = k[:, 0, 3] = k[:, 3, 0] = 6 * L * c
    k[:, 2, 1] = k[:, 1, 2] = k[:, 2, 3] = k[:, 3, 2] = -6 * L * c
    k[:, 1, 1] = k[:, 3, 3] = (4 + phi) * L**2 * c
    k[:, 1, 3] = k[:, 3, 1] = (2 - phi) * L**2 * c
    return k


def _bending_mass(rho_a, rho_i, phi, length):
    """4x4 consistent mass in the x-y plane (translational + rotary), DOFs (v1, rz1, v2, rz2)."""
    L, p = length, phi
    ct = rho_a * L / (1 + p) ** 2
    cr = rho_i / ((1 + p) ** 2 * L)
    m = np.zeros(L.shape + (4, 4))
    t11 = ct * (13 / 35 + 7 * p / 10 + p**2 / 3) + cr * 6 / 5
    t12 = ct * (11 / 210 + 11 * p / 120 + p**2 / 24) * L + cr * (1 / 10 - p / 2) * L
    t13 = ct * (9 / 70 + 3 * p / 10 + p**2 / 6) - cr * 6 / 5
    t14 = -ct * (13 / 420 + 3 * p / 40 + p**2 / 24) * L + cr * (1 / 10 - p / 2) * L
    t22 = ct * (1 / 105 + p / 60 + p**2 / 120) * L**2 + cr * (2 / 15 + p / 6 + p**2 / 3) * L**2
    t24 = -ct * (1 / 140 + p / 60 + p**2 / 120) * L**2 + cr * (-1 / 30 - p / 6 + p**2 / 6) * L**2
    rows = [[t11, t12, t13, t14], [t12, t22, -t14, t24],
            [t13, -t14, t11, -t12], [t14, t24, -t12, t22]]
    for i in range(4):
        for j in range(4):
            m[:, i, j] = rows[i][j]
    return m


_XY = [1, 5, 7, 11]   # v1, rz1, v2, rz2
_XZ = [2, 4, 8, 10]   # w1, ry1, w2, ry2
_FLIP = np.array([1.0, -1.0, 1.0, -1.0])   # x-z plane: ry = -dw/dx


def _place(target, block, index, flip=None):
    if flip is not None:
        block = block * flip[None, :, None] * flip[None, None, :]
    target[:, np.ix_(index, index)[0], np.ix_(index, index)[1]] = block


def _two_node(target, value, i, j):
    target[:, i, i] = target[:, j, j] = value
    target[:, i, j] = target[:, j, i] = -value


def local_stiffness(length, E, G, A, Iy, Iz, J, A_sy, A_sz):
    """Local 12x12 Timoshenko stiffness matrices [N/m, N, N m], arrays over elements."""
    n = len(length)
    k = np.zeros((n, 12, 12))
    _two_node(k, E * A / length, 0, 6)
    _two_node(k, G * J / length, 3, 9)
    phi_y = 12 * E * Iz / (G * A_sy * length**2)
    phi_z = 12 * E * Iy / (G * A_sz * length**2)
    _place(k, _bending_stiffness(E * Iz, phi_y, length), _XY)
    _place(k, _bending_stiffness(E * Iy, phi_z, length), _XZ, _FLIP)
    return k


def local_mass(length, E, G, rho, A, Iy, Iz, A_sy, A_sz):
    """Local 12x12 consistent mass matrices [kg, kg m, kg m^2], arrays over elements."""
    n = len(length)
    m = np.zeros((n, 12, 12))
    axial = rho * A * length / 6.0
    torsional = rho * (Iy + Iz) * length / 6.0
    for a, b, value in ((0, 6, axial), (3, 9, torsional)):
        m[:, a, a] = m[:, b, b] = 2 * value
        m[:, a, b] = m[:, b, a] = value
    phi_y = 12 * E * Iz / (G * A_sy * length**2)
    phi_z = 12 * E * Iy / (G * A_sz * length**2)
    _place(m, _bending_mass(rho * A, rho * Iz, phi_y, length), _XY)
    _place(m, _bending_mass(rho * A, rho * Iy, phi_z, length), _XZ, _FLIP)
    return m


def global_element_matrices(xyz1, xyz2, up, props):
    """Global 12x12 stiffness and mass of many elements.

    ``props`` maps E, G, rho, A, Iy, Iz, J, A_sy, A_sz to arrays (one value per element).
    Returns (K_e, M_e), each (n, 12, 12), in global axes: K_e = T^T K_local T.
    """
    length, rot = element_frames(xyz1, xyz2, up)
    p = props
    k_loc = local_stiffness(length, p["E"], p["G"], p["A"], p["Iy"], p["Iz"], p["J"],
                            p["A_sy"], p["A_sz"])
    m_loc = local_mass(length, p["E"], p["G"], p["rho"], p["A"], p["Iy"], p["Iz"],
                       p["A_sy"], p["A_sz"])
    t = np.zeros((len(length), 12, 12))
    for b in range(4):
        t[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = rot
    tt = np.transpose(t, (0, 2, 1))
    return tt @ k_loc @ t, tt @ m_loc @ t
