"""Volume meshes made here, for verification and benchmarks: a box cantilever of any element type
(scikit-fem's structured mesh constructors) written with meshio in every format the mesh
reader takes, with its node sets in each format's own way.

Sets per format (what :mod:`motoflex_ros.formats.mesh_file` reads): Gmsh 2.2 physical groups
(surface elements of the linear meshes, physical points of the quadratic ones), Abaqus
``*NSET``, Nastran ``SET1`` cards (named by number: the i-th set is ``str(i + 1)``), VTK point
data flags.
"""
from pathlib import Path

import numpy as np

from motoflex_ros.structures.solid import _VTK_REFERENCE, CORNERS

__all__ = ["box_mesh", "tube_mesh", "bracket_mesh", "bracket_sets", "keep_cells",
           "write_bracket_component", "write_mesh", "FORMATS", "set_names"]

FORMATS = (".msh", ".inp", ".bdf", ".vtu")


def _mirror_order(cell_type):
    """Node permutation that mirrors an element (reverses its orientation): y -> 1 - y in the
    reference element, or x <-> y for a tetrahedron."""
    ref = _VTK_REFERENCE[cell_type]
    if cell_type.startswith("tetra"):
        mirrored = ref[:, [1, 0, 2]]
    else:
        mirrored = ref * [1, -1, 1] + [0, 1, 0]
    return np.array([int(np.argmin(np.linalg.norm(ref - m, axis=1))) for m in mirrored])


def _orient(points, cell_type, cells):
    """Cells renumbered so that every element has a positive volume (VTK convention)."""
    corners = points[cells[:, :CORNERS[cell_type]]]
    if cell_type.startswith("tetra"):
        a, b, c = (corners[:, i] - corners[:, 0] for i in (1, 2, 3))
    else:
        a, b, c = (corners[:, i] - corners[:, 0] for i in (1, 3, 4))
    negative = np.einsum("ei,ei->e", np.cross(a, b), c) < 0
    out = cells.copy()
    out[negative] = cells[negative][:, _mirror_order(cell_type)]
    return out


def box_mesh(length, width, height, divisions, cell_type="tetra10"):
    """A box [0, length] x [-width/2, width/2] x [-height/2, height/2] [m] of ``cell_type``
    elements on a structured grid of ``divisions`` = (n_x, n_y, n_z) cells.

    Returns (points (n, 3), cells (n_e, n_nodes) in VTK order, positively oriented); a
    tetrahedral grid splits each hexahedral cell into tetrahedra (scikit-fem's MeshTet1).
    """
    import skfem
    from skfem.io.meshio import to_meshio
    nx, ny, nz = divisions
    axes = (np.linspace(0.0, length, nx + 1), np.linspace(-width / 2, width / 2, ny + 1),
            np.linspace(-height / 2, height / 2, nz + 1))
    if cell_type in ("tetra", "tetra10"):
        mesh = skfem.MeshTet1.init_tensor(*axes)
        if cell_type == "tetra10":
            mesh = skfem.MeshTet2.from_mesh(mesh)
    elif cell_type in ("hexahedron", "hexahedron20", "hexahedron27"):
        mesh = skfem.MeshHex1.init_tensor(*axes)
        if cell_type != "hexahedron":
            mesh = skfem.MeshHex2.from_mesh(mesh)
    else:
        raise ValueError(f"no box mesh of {cell_type}")
    out = to_meshio(mesh)
    points = np.asarray(out.points, float)
    cells = np.asarray(out.cells[0].data)
    base = "hexahedron27" if cell_type == "hexahedron20" else cell_type
    cells = _orient(points, base, cells)
    if cell_type == "hexahedron20":   # the 20 first nodes of a hexahedron27 are a hexahedron20
        cells = cells[:, :20]
        used = np.unique(cells)
        compact = -np.ones(len(points), int)
        compact[used] = np.arange(len(used))
        points, cells = points[used], compact[cells]
    return points, cells


def _merge_coincident(points, cells, tol):
    """Points closer than ``tol`` merged into one (the seam of a closed tube)."""
    from scipy.spatial import cKDTree
    pairs = cKDTree(points).query_pairs(tol, output_type="ndarray")
    target = np.arange(len(points))
    for i, j in sorted(map(tuple, np.sort(pairs, axis=1)), reverse=True):
        target[j] = target[i]
    used, compact = np.unique(target, return_inverse=True)
    return points[used], compact[cells]


def tube_mesh(length, outer_diameter, wall, divisions, cell_type="hexahedron20"):
    """A circular tube along x from 0 to ``length`` [m] of ``cell_type`` elements on a
    structured grid of ``divisions`` = (along, around, through the wall).

    The grid of the box (x, angle, radius) is mapped onto the tube, node by node, so the
    midside nodes of quadratic elements lie on the circles (curved, isoparametric elements).
    """
    n_x, n_phi, n_r = divisions
    r_out = outer_diameter / 2
    points, cells = box_mesh(1.0, 1.0, 1.0, (n_x, n_phi, n_r), cell_type)
    s_x, s_phi, s_r = points[:, 0], points[:, 1] + 0.5, points[:, 2] + 0.5
    phi = 2 * np.pi * s_phi
    radius = r_out - wall + wall * s_r
    mapped = np.column_stack([length * s_x, radius * np.cos(phi), radius * np.sin(phi)])
    mapped, cells = _merge_coincident(mapped, cells, 1e-9 * outer_diameter)
    if cell_type == "hexahedron20":
        return mapped, _orient20(mapped, cells)
    return mapped, _orient(mapped, cell_type, cells)


def _orient20(points, cells):
    """_orient for hexahedron20 cells (mirrored as the first 20 nodes of a hexahedron27)."""
    full = np.column_stack([cells, np.zeros((len(cells), 7), int)])
    return _orient(points, "hexahedron27", full)[:, :20]


def keep_cells(points, cells, cell_type, inside):
    """The elements whose centroid (of the corners) satisfies ``inside(xyz (n, 3)) -> bool``,
    with the nodes they use (compacted)."""
    centroids = points[cells[:, :CORNERS[cell_type]]].mean(axis=1)
    cells = cells[inside(centroids)]
    used = np.unique(cells)
    compact = -np.ones(len(points), int)
    compact[used] = np.arange(len(used))
    return points[used], compact[cells]


BRACKET = {"arm": 0.5, "drop": 0.16, "section": 0.04}
"""The L bracket [m]: an arm along x from the clamp at x = 0, a leg dropping from its far end to
the loaded end; square solid section."""


def bracket_mesh(cell_type="hexahedron20", size=0.02, arm=BRACKET["arm"],
                 drop=BRACKET["drop"], section=BRACKET["section"]):
    """An L bracket like a single-sided swingarm: a lateral force at the foot of the leg bends
    the arm and twists it, so the bench sees torsion and bending (both below 600 Hz in
    aluminium). Structured elements of edge ``size`` [m]; sets: :func:`bracket_sets`."""
    half = section / 2
    n = (round(arm / size), round(section / size), round((drop + section) / size))
    points, cells = box_mesh(arm, section, drop + section, n, cell_type)
    points = points + [0.0, 0.0, half - (drop + section) / 2]   # arm's axis on z = 0

    def inside(c):
        return (c[:, 2] > -half) | (c[:, 0] > arm - section)

    return keep_cells(points, cells, cell_type, inside)


def bracket_sets(points, drop=BRACKET["drop"], section=BRACKET["section"]):
    """{'clamp': the face x = 0, 'axle': the leg's foot} node indices of a bracket mesh."""
    bottom = -(drop + section / 2)
    return {"clamp": np.flatnonzero(np.isclose(points[:, 0], 0.0)),
            "axle": np.flatnonzero(np.isclose(points[:, 2], bottom))}


def write_bracket_component(directory, cell_type="hexahedron20", suffix=".msh", size=0.02,
                            name="bracket"):
    """Write an aluminium bracket mesh and its ``component: mesh`` YAML into ``directory``;
    returns the YAML's path. ``size`` 0.02 m: 2,919 DOFs in hexahedron20, bending 87 Hz,
    torsion 318 Hz."""
    import yaml
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    points, cells = bracket_mesh(cell_type, size)
    mesh_file = directory / f"{name}{suffix}"
    names = write_mesh(mesh_file, points, cells, cell_type, bracket_sets(points))
    path = directory / f"{name}.yaml"
    path.write_text(yaml.safe_dump({
        "component": "mesh", "name": name,
        "description": "L bracket (single-sided swingarm-like), clamped at x = 0",
        "mesh": {"file": mesh_file.name, "units": "m", "clamps": [names["clamp"]],
                 "loaded_end": names["axle"]},
        "material": {"E": 7.0e10, "nu": 0.33, "rho": 2700.0}}, sort_keys=False))
    return path


def set_names(suffix, names):
    """The names the sets ``names`` get in a file of ``suffix`` (Nastran: '1', '2', ...)."""
    if suffix == ".bdf":
        return {n: str(i + 1) for i, n in enumerate(names)}
    return {n: n for n in names}


def _gmsh_faces(points, cells, cell_type, nodes):
    """Surface elements (type, array) of the element faces whose corners are all in ``nodes``."""
    inside = np.zeros(len(points), bool)
    inside[nodes] = True
    if cell_type == "tetra":
        local, face_type = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)], "triangle"
    else:
        local, face_type = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5),
                            (2, 3, 7, 6), (3, 0, 4, 7)], "quad"
    faces = np.vstack([cells[:, list(f)] for f in local])
    faces = faces[np.all(inside[faces], axis=1)]
    return face_type, np.unique(faces, axis=0)


def write_mesh(path, points, cells, cell_type, sets, units="m"):
    """Write the mesh and its node sets ``sets`` {name: node indices} to ``path`` (a suffix of
    :data:`FORMATS`); ``units`` 'mm' writes the coordinates in mm. Returns the set names as the
    file knows them (:func:`set_names`)."""
    import meshio
    path = Path(path)
    suffix = path.suffix.lower()
    scale = 1e3 if units == "mm" else 1.0
    pts = np.asarray(points, float) * scale
    names = set_names(suffix, list(sets))
    if suffix == ".msh":
        blocks = [(cell_type, cells)]
        tags = [np.full(len(cells), 100)]
        field_data = {"volume": np.array([100, 3])}
        for i, (name, nodes) in enumerate(sets.items()):
            if cell_type in ("tetra", "hexahedron"):
                face_type, faces = _gmsh_faces(pts, cells, cell_type, nodes)
                dim = 2
            else:
                face_type, faces, dim = "vertex", np.asarray(nodes, int)[:, None], 0
            blocks.append((face_type, faces))
            tags.append(np.full(len(faces), i + 1))
            field_data[name] = np.array([i + 1, dim])
        mesh = meshio.Mesh(pts, blocks, cell_data={"gmsh:physical": tags,
                                                   "gmsh:geometrical": tags},
                           field_data=field_data)
        meshio.write(str(path), mesh, file_format="gmsh22", binary=False)
    elif suffix == ".inp":
        meshio.write(str(path), meshio.Mesh(pts, [(cell_type, cells)],
                                            point_sets={n: np.asarray(v) for n, v in
                                                        sets.items()}))
    elif suffix == ".bdf":
        meshio.write(str(path), meshio.Mesh(pts, [(cell_type, cells)]), file_format="nastran")
        text = path.read_text()
        cards = []
        for name, nodes in sets.items():
            ids = [str(int(i) + 1) for i in nodes]   # meshio writes GRID ids from 1
            fields = ["SET1", names[name]] + ids
            cards.append(",".join(fields[:9]))
            rest = fields[9:]
            while rest:
                cards.append("+," + ",".join(rest[:8]))
                rest = rest[8:]
        path.write_text(text.replace("ENDDATA", "\n".join(cards) + "\nENDDATA"))
    elif suffix == ".vtu":
        flags = {}
        for name, nodes in sets.items():
            flag = np.zeros(len(pts), np.int32)
            flag[np.asarray(nodes, int)] = 1
            flags[name] = flag
        meshio.write(str(path), meshio.Mesh(pts, [(cell_type, cells)], point_data=flags))
    else:
        raise ValueError(f"no writer for {suffix}")
    return names
