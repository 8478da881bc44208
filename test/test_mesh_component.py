"""Solid mesh components (issue 15) against closed form, scikit-fem and the beam component.

Meshes are made here (scikit-fem's structured constructors, mapped onto a tube for curved
quadratic elements: motoflex_ros.structures.mesh_examples) and written with meshio in each
supported format, so the reader is exercised. Closed form: the shear-deformable (Timoshenko)
cantilever, kappa after Cowper (1966), J. Appl. Mech. 33, 335-340, as in test_identify_tube.py;
the Euler-Bernoulli cantilever's first bending frequency (1.8751^2 / (2 pi)) sqrt(E I /
(rho A L^4)) and the clamped-free shaft's first torsion frequency sqrt(G / rho) / (4 L).
Sizes are a few thousand DOFs so that each test takes seconds.
"""
import numpy as np
import pytest
import scipy.sparse.linalg as spla
import yaml

from motoflex_ros.structures.beam import Material
from motoflex_ros.structures.component_loader import load_component
from motoflex_ros.structures.component_model import tube_component
from motoflex_ros.structures.full_model import full_clamped_matrices, full_clamped_modes
from motoflex_ros.structures.mesh_examples import box_mesh, tube_mesh, write_mesh
from motoflex_ros.structures.solid import SolidBlock, assemble_solid
from motoflex_ros.vehicle.superelement import rigid_field

L, D, T = 0.6, 0.04, 0.002           # the validation tube of config/components/tube.yaml
E, G, RHO = 2.1e11, 8.1e10, 7850.0
NU = E / (2 * G) - 1
FORCE = 100.0
TUBE_DIVISIONS = (20, 16, 1)         # along, around, through the wall: 6,492 DOFs in hex20


def tube_properties():
    d_in = D - 2 * T
    area = np.pi / 4 * (D**2 - d_in**2)
    inertia = np.pi / 64 * (D**4 - d_in**4)
    m2 = (d_in / D) ** 2
    kappa = 6 * (1 + NU) * (1 + m2) ** 2 / ((7 + 6 * NU) * (1 + m2) ** 2 + (20 + 12 * NU) * m2)
    return area, inertia, kappa


def timoshenko_tip(force=FORCE):
    """Tip deflection [m] and slope [rad] of the tube under a tip force (shear deformable)."""
    area, inertia, kappa = tube_properties()
    return (force * L**3 / (3 * E * inertia) + force * L / (kappa * G * area),
            force * L**2 / (2 * E * inertia))


def tube_frequencies():
    """First bending (Euler-Bernoulli cantilever) and torsion (clamped-free shaft) frequencies
    of the tube [Hz]."""
    area, inertia, _ = tube_properties()
    return (1.875104**2 / (2 * np.pi) * np.sqrt(E * inertia / (RHO * area * L**4)),
            np.sqrt(G / RHO) / (4 * L))


def assert_tube_frequencies(component, rel=0.01):
    """The full clamped model's first bending and torsion frequencies within ``rel``."""
    full = full_clamped_modes(component, n_modes=12)
    bending, torsion = tube_frequencies()
    assert full.frequency("bending") == pytest.approx(bending, rel=rel)
    assert full.frequency("torsion") == pytest.approx(torsion, rel=rel)


def mesh_yaml(tmp_path, points, cells, cell_type, suffix=".vtu", units="m", name="part",
              **extra):
    """Write the mesh (clamp at x = 0, loaded end at the far face) and its component YAML."""
    x = points[:, 0]
    sets = {"clamp": np.flatnonzero(np.isclose(x, x.min())),
            "tip": np.flatnonzero(np.isclose(x, x.max()))}
    mesh_file = tmp_path / f"{name}_{cell_type}{suffix}"
    names = write_mesh(mesh_file, points, cells, cell_type, sets, units)
    cfg = {"component": "mesh", "name": name,
           "mesh": {"file": mesh_file.name, "units": units, "clamps": [names["clamp"]],
                    "loaded_end": names["tip"], **extra.pop("mesh", {})},
           "material": {"E": E, "nu": NU, "rho": RHO}, **extra}
    path = tmp_path / f"{name}_{cell_type}_{suffix[1:]}_{units}.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return str(path)


@pytest.fixture(scope="module")
def tube_files(tmp_path_factory):
    """The tube as hex20, hex27 and tet10 meshes: {cell_type: yaml path}."""
    tmp = tmp_path_factory.mktemp("tube")
    return {ct: mesh_yaml(tmp, *tube_mesh(L, D, T, TUBE_DIVISIONS, ct), ct, name="tube")
            for ct in ("hexahedron20", "hexahedron27", "tetra10")}


@pytest.fixture(scope="module")
def hex20_tube(tube_files):
    comp = load_component(tube_files["hexahedron20"])
    return comp, comp.clamped_reduced()


# --- the assembler --------------------------------------------------------------------------

@pytest.mark.parametrize("cell_type", ["tetra", "tetra10", "hexahedron", "hexahedron20",
                                       "hexahedron27"])
def test_assembly_equals_scikit_fem(cell_type):
    """K and M equal scikit-fem's own BilinearForm assembly of linear elasticity (and its mass)
    on the same elements, mapped onto the file's node order by DOF location. On a box both
    quadratures are exact, so the matrices agree to round-off."""
    import meshio
    import skfem
    from scipy.spatial import cKDTree
    from skfem.helpers import dot
    from skfem.io.meshio import from_meshio
    from skfem.models.elasticity import lame_parameters, linear_elasticity
    points, cells = box_mesh(0.3, 0.04, 0.03, (4, 2, 2), "hexahedron27" if cell_type ==
                             "hexahedron20" else cell_type)
    k, m = assemble_solid(points, [SolidBlock(cell_type, cells[:, :20] if cell_type ==
                                              "hexahedron20" else cells,
                                              np.arange(len(cells)))], E, NU, RHO)
    if cell_type == "hexahedron20":   # scikit-fem: serendipity field on the 27-node geometry
        mesh = from_meshio(meshio.Mesh(points, [("hexahedron27", cells)]))
        element = skfem.ElementHexS2()
    else:
        mesh = from_meshio(meshio.Mesh(points, [(cell_type, cells)]))
        element = {"tetra": skfem.ElementTetP1, "tetra10": skfem.ElementTetP2,
                   "hexahedron": skfem.ElementHex1, "hexahedron27": skfem.ElementHex2}[
                       cell_type]()
    basis = skfem.Basis(mesh, skfem.ElementVector(element), intorder=5)
    k_ref = linear_elasticity(*lame_parameters(E, NU)).assemble(basis)

    @skfem.BilinearForm
    def mass(u, v, w):
        return RHO * dot(u, v)

    m_ref = mass.assemble(basis)
    dist, node = cKDTree(points).query(basis.doflocs.T)
    assert dist.max() < 1e-12
    component = np.zeros(basis.N, int)
    for dofs in (basis.nodal_dofs, basis.edge_dofs, basis.facet_dofs, basis.interior_dofs):
        for c in range(min(3, dofs.shape[0])):
            component[dofs[c]] = c
    perm = 3 * node + component
    if cell_type == "hexahedron20":   # our mesh has no face/centre nodes: compare the rest
        used = np.unique(cells[:, :20])
        keep = np.flatnonzero(np.isin(node, used))
        k_ref, m_ref, perm = k_ref[keep][:, keep], m_ref[keep][:, keep], perm[keep]
    ours_k, ours_m = k[perm][:, perm], m[perm][:, perm]
    assert abs(ours_m - m_ref).max() <= 1e-12 * abs(m_ref).max()
    assert abs(ours_k - k_ref).max() <= 1e-12 * abs(k_ref).max()


# --- the reader: every format, both units ---------------------------------------------------

FORMATS_OF = {"tetra": (".msh", ".inp", ".bdf", ".vtu"), "tetra10": (".msh", ".inp", ".bdf",
                                                                       ".vtu"),
              "hexahedron": (".msh", ".inp", ".bdf", ".vtu"),
              "hexahedron20": (".msh", ".inp", ".bdf", ".vtu"),
              # Abaqus and Nastran have no 27-node brick that meshio writes
              "hexahedron27": (".msh", ".vtu")}


@pytest.mark.parametrize("cell_type", list(FORMATS_OF))
def test_every_format_and_unit_reads_the_same_model(tmp_path, cell_type):
    """The same box written as Gmsh, Abaqus, Nastran and VTU files, in m and in mm, gives the
    same DOFs, spiders and static loaded-end response (to round-off)."""
    points, cells = box_mesh(0.3, 0.04, 0.03, (6, 2, 2), cell_type)
    reference = None
    for suffix in FORMATS_OF[cell_type]:
        for units in ("m", "mm"):
            comp = load_component(mesh_yaml(tmp_path, points, cells, cell_type, suffix, units))
            motion = comp.clamped_reduced().static_end_motion([10.0, FORCE, -20.0, 1.0, 2.0,
                                                               3.0])
            spiders = [len(s.slaves) for s in comp.spiders]
            if reference is None:
                reference = (comp.dof_count(), spiders, motion)
                assert spiders == [int(np.sum(np.isclose(points[:, 0], 0.0)))] * 2
                continue
            assert (comp.dof_count(), spiders) == reference[:2], (suffix, units)
            np.testing.assert_allclose(motion, reference[2], rtol=1e-9,
                                       atol=1e-9 * abs(reference[2]).max())


# --- closed form ------------------------------------------------------------------------------

@pytest.mark.parametrize("cell_type", ["hexahedron20", "hexahedron27", "tetra10"])
def test_tube_tip_deflection_and_slope_match_timoshenko(tube_files, cell_type):
    """Quadratic solid tube (curved elements): tip deflection and slope under a tip force
    within 1 % of the shear-deformable cantilever."""
    reduced = load_component(tube_files[cell_type]).clamped_reduced()
    motion = reduced.static_end_motion([0.0, FORCE, 0.0, 0.0, 0.0, 0.0])
    deflection, slope = timoshenko_tip()
    assert motion[1] == pytest.approx(deflection, rel=0.01)
    assert motion[5] == pytest.approx(slope, rel=0.01)


def test_tube_converges_to_timoshenko(tmp_path, hex20_tube):
    """Refining the hex20 tube (10 x 8 -> 20 x 16 elements) brings tip deflection and slope
    closer to the shear-deformable cantilever (the rigid clamp spider, which holds the section
    from warping, keeps the solid a little stiffer: -0.6 % at 20 x 16)."""
    deflection, slope = timoshenko_tip()
    coarse = load_component(mesh_yaml(tmp_path, *tube_mesh(L, D, T, (10, 8, 1),
                                                           "hexahedron20"), "hexahedron20",
                                      name="coarse")).clamped_reduced()
    errors = []
    for reduced in (coarse, hex20_tube[1]):
        motion = reduced.static_end_motion([0.0, FORCE, 0.0, 0.0, 0.0, 0.0])
        errors.append((abs(motion[1] / deflection - 1), abs(motion[5] / slope - 1)))
    assert errors[1][0] < errors[0][0] and errors[1][1] < errors[0][1], errors


def box_tip_error(cell_type, divisions, length=0.4, width=0.02, height=0.02):
    """Relative error of the box cantilever's tip deflection against Timoshenko."""
    points, cells = box_mesh(length, width, height, divisions, cell_type)
    sets = {"clamp": np.flatnonzero(np.isclose(points[:, 0], 0.0)),
            "tip": np.flatnonzero(np.isclose(points[:, 0], length))}
    import tempfile
    from pathlib import Path
    with tempfile.TemporaryDirectory() as tmp:
        path = mesh_yaml(Path(tmp), points, cells, cell_type)
        assert sets["clamp"].size
        comp = load_component(path)
        y = comp.clamped_reduced().static_end_motion([0.0, FORCE, 0.0, 0.0, 0.0, 0.0])[1]
    inertia, area = height * width**3 / 12, width * height
    kappa = 10 * (1 + NU) / (12 + 11 * NU)   # rectangle (Cowper)
    exact = FORCE * length**3 / (3 * E * inertia) + FORCE * length / (kappa * G * area)
    return y / exact - 1


@pytest.mark.parametrize("cell_type, meshes, tolerance", [
    ("tetra10", [(5, 1, 1), (10, 2, 2), (20, 3, 3)], 0.01),
    ("hexahedron20", [(5, 1, 1), (10, 2, 2), (20, 3, 3)], 0.01),
    ("hexahedron", [(10, 2, 2), (20, 4, 4), (40, 6, 6)], None),
    ("tetra", [(10, 2, 2), (20, 4, 4), (40, 6, 6)], None),
])
def test_box_cantilever_converges_under_refinement(cell_type, meshes, tolerance):
    """Tip deflection of a square box cantilever (L/h = 20) against Timoshenko: the error
    shrinks at every refinement; the quadratic elements end within 1 %, the linear ones (which
    lock in bending) are still converging."""
    errors = [abs(box_tip_error(cell_type, m)) for m in meshes]
    assert errors[0] > errors[1] > errors[2], errors
    if tolerance is not None:
        assert errors[-1] < tolerance, errors


def test_tube_first_bending_and_torsion_frequencies(hex20_tube):
    """The full clamped model: first bending within 1 % of Euler-Bernoulli (the tube is slender:
    shear and rotary inertia lower it by ~0.1 %), first torsion within 1 % of the shaft's
    sqrt(G / rho) / (4 L)."""
    assert_tube_frequencies(hex20_tube[0])


def test_tube_mesh_and_beam_component_agree(hex20_tube):
    """The same tube as the project's beam component (40 Timoshenko elements) and as a solid
    mesh: Craig-Bampton frequencies below 600 Hz, and l, b, k of the static test within 1 %."""
    _, mesh_red = hex20_tube
    beam = tube_component(L, D, T, 0.0, Material(E, G, RHO), 40).clamped_reduced()
    low = beam.frequencies_hz < 600.0
    assert low.sum() >= 2
    np.testing.assert_allclose(mesh_red.frequencies_hz[:low.sum()], beam.frequencies_hz[low],
                               rtol=0.01)
    ours, theirs = mesh_red.static_lateral(FORCE), beam.static_lateral(FORCE)
    assert ours.axis.beta == pytest.approx(np.pi / 2, abs=1e-6)
    for key in ("l", "b"):
        assert getattr(ours.axis, key) == pytest.approx(getattr(theirs.axis, key), rel=0.01)
    assert ours.k == pytest.approx(theirs.k, rel=0.01)


# --- spiders and the reduction ------------------------------------------------------------

def test_spider_constraint_is_exact_rigid_motion(hex20_tube):
    """Every slave row of T is u_s = u_m + theta_m x (x_s - x_m) exactly; a rigid motion of the
    whole model (mesh nodes and masters) stores no strain energy."""
    comp, _ = hex20_tube
    t, free_nodes = comp.constraint()
    n = comp.n_mesh_nodes
    rng = np.random.default_rng(1)
    for j, spider in enumerate(comp.spiders):
        v = np.zeros(t.shape[1])
        master = rng.normal(size=6)
        v[3 * len(free_nodes) + 6 * j:3 * len(free_nodes) + 6 * j + 6] = master
        u = (t @ v)[:3 * n].reshape(-1, 3)
        lever = comp.mesh_xyz[spider.slaves] - spider.master
        expected = master[:3] + np.cross(master[3:], lever)
        np.testing.assert_allclose(u[spider.slaves], expected, rtol=0, atol=1e-15)
        others = np.setdiff1d(np.arange(n), spider.slaves)
        assert not np.any(u[others])
    asm = comp.assembled()
    # the rigid field on the free DOFs: mesh nodes' translations, masters' six DOFs
    gamma = rigid_field(comp.node_xyz)                     # (6 n_nodes, 6): omega, v_0
    rows = np.flatnonzero(asm.free_index >= 0)
    free = np.zeros((asm.K.shape[0], 6))
    free[asm.free_index[rows]] = gamma[rows]
    moved = (asm.expand @ free).reshape(-1, 6, 6)
    np.testing.assert_allclose(moved[:, :3], gamma.reshape(-1, 6, 6)[:, :3], rtol=0,
                               atol=1e-15)   # slaves follow exactly
    energy = np.einsum("ij,ij->j", free, asm.K @ free)
    scale = spla.norm(asm.K, 1) * np.sum(free**2, axis=0)
    assert np.all(abs(energy) < 1e-12 * scale)


def test_spider_nodes_move_rigidly_and_reactions_balance(hex20_tube):
    """Full clamped model under a tip wrench: the loaded end's set moves as a rigid body with
    its master (to 1e-12), and the reaction at the clamp master balances the load (forces and
    moments about O)."""
    comp, _ = hex20_tube
    k_c, _, asm_c = full_clamped_matrices(comp)
    wrench = np.array([20.0, FORCE, -30.0, 2.0, -1.0, 4.0])
    f = np.zeros(k_c.shape[0])
    end = asm_c.node_dofs(comp.loaded_end)
    f[end] = wrench
    x = spla.spsolve(k_c.tocsc(), f)
    nodes = (asm_c.expand @ x).reshape(-1, 6)
    master = nodes[comp.loaded_end]
    spider = comp.spiders[list(comp.node_names).index("tip")]
    lever = comp.mesh_xyz[spider.slaves] - spider.master
    rigid = master[:3] + np.cross(master[3:], lever)
    np.testing.assert_allclose(nodes[spider.slaves, :3], rigid, rtol=0,
                               atol=1e-12 * abs(master[:3]).max())
    # reaction at the clamp master: K_cf x with the unclamped matrices
    asm = comp.assembled()
    full_x = np.zeros(asm.K.shape[0])
    clamp = asm.node_dofs(comp.clamp_nodes[0])
    keep = np.setdiff1d(np.arange(asm.K.shape[0]), clamp)
    full_x[keep] = x
    reaction = (asm.K @ full_x)[clamp]
    r_end, r_clamp = comp.q0, comp.clamp_xyz[0]
    forces = reaction[:3] + wrench[:3]
    moments = (reaction[3:] + np.cross(r_clamp, reaction[:3]) + wrench[3:]
               + np.cross(r_end, wrench[:3]))
    # round-off of the solve: |K| |x| eps ~ 1e-8 of the load
    assert abs(forces).max() < 1e-6 * FORCE
    assert abs(moments).max() < 1e-6 * FORCE * L


def test_craig_bampton_against_full_model(hex20_tube):
    """The reduced model's static loaded-end response equals the full model's to round-off (the
    constraint modes are exact statically); its frequencies below 300 Hz within 0.5 %.

    Round-off here is 1e-9 to 5e-9 relative: the full solve itself moves by that much under one
    step of iterative refinement, and by a different amount with another OpenBLAS kernel (3e-9
    against the reduced model with Prescott, 5e-9 with Haswell), so the test holds 1e-8.

    The tube's fixed-interface modes (both ends held) start at ~690 Hz, above the default
    600 Hz cut-off, so the default reduction keeps none and its 108 Hz bending comes from the
    constraint modes alone (0.5 % high; the summary warns of this); with the cut-off at 3 kHz
    it keeps them."""
    comp, default = hex20_tube
    reduced = comp.clamped_reduced(20, 3000.0)
    assert default.n_modes == 0 and reduced.n_modes > 0
    k_c, _, asm_c = full_clamped_matrices(comp)
    end = asm_c.node_dofs(comp.loaded_end)
    for i in range(6):
        wrench = np.eye(6)[i] * (FORCE if i < 3 else FORCE * L)
        f = np.zeros(k_c.shape[0])
        f[end] = wrench
        full = spla.spsolve(k_c.tocsc(), f)[end]
        for model in (default, reduced):
            np.testing.assert_allclose(model.static_end_motion(wrench), full, rtol=1e-8,
                                       atol=1e-8 * abs(full).max())
    full_modes = full_clamped_modes(comp, n_modes=8).frequencies_hz
    low = full_modes[full_modes < 300.0]
    assert len(low) >= 2
    np.testing.assert_allclose(reduced.frequencies_hz[:len(low)], low, rtol=0.005)


# --- the optional keys ----------------------------------------------------------------------

def test_frame_keys_origin_plane_normal_and_points(tmp_path, hex20_tube):
    """The tube written in another frame (shifted by 1.2 m, in mm, the symmetry plane's normal
    along z) with ``origin`` and ``plane_normal`` set back gives the same bench model; a master
    point moved with ``points`` moves q0."""
    _, reference = hex20_tube
    points, cells = tube_mesh(L, D, T, TUBE_DIVISIONS, "hexahedron20")
    shift = np.array([1.2, -0.3, 0.5])
    # component y (the load direction) is the file's z; component z is the file's -y
    turned = np.column_stack([points[:, 0], -points[:, 2], points[:, 1]]) + shift
    path = mesh_yaml(tmp_path, turned, cells, "hexahedron20", ".inp", "mm", name="turned",
                     mesh={"origin": (shift * 1e3).tolist(), "plane_normal": [0, 0, 1]})
    comp = load_component(path)
    np.testing.assert_allclose(comp.q0, [L, 0, 0], atol=1e-12)
    red = comp.clamped_reduced()
    np.testing.assert_allclose(red.frequencies_hz, reference.frequencies_hz, rtol=1e-8)
    np.testing.assert_allclose(red.static_lateral(FORCE).k, reference.static_lateral(FORCE).k,
                               rtol=1e-8)
    moved = yaml.safe_load(open(path))
    moved["mesh"]["points"] = {"tip": (shift * 1e3 + [650.0, 0.0, 0.0]).tolist()}
    other = tmp_path / "moved.yaml"
    other.write_text(yaml.safe_dump(moved))
    np.testing.assert_allclose(load_component(str(other)).q0, [0.65, 0, 0], atol=1e-12)


def test_rigid_part_on_the_loaded_end(tmp_path):
    """A tip mass (rigid part on the loaded end's set) lowers the first bending frequency to
    the cantilever-with-tip-mass value sqrt(3 E I / L^3 / (m + 0.2357 m_beam)) / (2 pi) within
    2 %."""
    points, cells = tube_mesh(L, D, T, (12, 12, 1), "hexahedron20")
    mass = 2.0
    path = mesh_yaml(tmp_path, points, cells, "hexahedron20", name="tipmass",
                     rigid_parts={"weight": {"set": "tip", "mass": mass, "cg": [L, 0.0, 0.0],
                                             "inertia": [1e-4, 1e-4, 1e-4]}})
    comp = load_component(path)
    area, inertia, _ = tube_properties()
    beam_mass = RHO * area * L
    expected = np.sqrt(3 * E * inertia / L**3 / (mass + 0.2357 * beam_mass)) / (2 * np.pi)
    assert comp.clamped_reduced().frequency("bending") == pytest.approx(expected, rel=0.02)
