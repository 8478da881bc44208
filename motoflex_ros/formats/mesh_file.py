"""Volume meshes from the engineer's own FE tool, read with meshio, and their node sets.

Formats: Gmsh ``.msh`` (2.2 and 4.1), Abaqus ``.inp``, Nastran bulk data ``.bdf``/``.nas``/
``.dat``, VTK ``.vtu`` (and legacy ``.vtk``). The volume elements (types in
:data:`motoflex_ros.structures.solid.SOLID_TYPES`) make the structure; every other cell (faces,
edges, points) only carries node sets.

A node set is found by its name, in this order of sources (all that have the name are united):

- Abaqus ``*NSET`` (meshio's point sets) and ``*ELSET`` (cell sets: the nodes of the elements);
- Gmsh physical groups of any dimension (``$PhysicalNames``): the nodes of their elements;
- Nastran ``SET1`` cards: the name is the set's number (``clamps: ["10"]``), the members are
  GRID ids (``THRU`` ranges too);
- VTK point data or cell data of that name: the nodes (of the cells) where it is non-zero.

Only nodes of the volume mesh count; a set that has none there is an error.
"""
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from motoflex_ros.errors import ConfigError
from motoflex_ros.files import missing_file_text
from motoflex_ros.input_pins import note_input, read_input
from motoflex_ros.structures.solid import SOLID_TYPES, SolidBlock

__all__ = ["MeshData", "read_mesh", "MESH_SUFFIXES", "UNITS"]

MESH_SUFFIXES = (".msh", ".inp", ".bdf", ".nas", ".dat", ".vtu", ".vtk")
UNITS = {"m": 1.0, "mm": 1e-3}
_NASTRAN = (".bdf", ".nas", ".dat")
# cell types of each dimension (meshio names) that carry sets
_DIM = {"vertex": 0, "line": 1, "line3": 1, "triangle": 2, "triangle6": 2, "quad": 2,
        "quad8": 2, "quad9": 2}
_VOLUME_OTHER = ("wedge", "wedge15", "wedge18", "pyramid", "pyramid13", "pyramid14",
                 "tetra4", "hexahedron24", "polyhedron")


@dataclass(frozen=True)
class MeshData:
    """The volume mesh of a file, compacted to the nodes that volume elements use.

    ``points`` (n, 3) [m]; ``blocks`` the volume elements (SolidBlock, indices into points);
    ``node_sets`` {name: sorted node indices}; ``file_ids`` (n,) the nodes' numbers in the file
    (GRID ids for Nastran, else 1-based position); ``source`` the mesh file; ``id_kind`` how
    elements are numbered in messages.
    """

    points: np.ndarray
    blocks: tuple
    node_sets: dict
    file_ids: np.ndarray
    source: str
    id_kind: str

    def node_set(self, name, yaml_source, key):
        """Node indices of set ``name``; ConfigError naming both files and the key if unknown."""
        if name not in self.node_sets:
            known = ", ".join(sorted(self.node_sets)[:30]) or "none"
            raise ConfigError(yaml_source, key, f"no node set or physical group '{name}' in "
                                                f"{self.source} (sets there: {known})")
        return self.node_sets[name]


def _read(path, yaml_source, key):
    import meshio
    if not path.is_file():
        raise ConfigError(yaml_source, key, f"mesh file {path}: {missing_file_text(path)}")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise ConfigError(yaml_source, key, f"{path}: unsupported mesh format "
                                            f"'{path.suffix}' (supported: "
                                            f"{', '.join(MESH_SUFFIXES)})")
    fmt = "nastran" if path.suffix.lower() in _NASTRAN else None
    note_input(path)   # meshio reads it itself: hashed (and checked against the run's pins)
    try:
        return meshio.read(str(path), file_format=fmt)
    except Exception as exc:   # meshio raises many kinds (ReadError, KeyError, ValueError...)
        text = str(exc).strip() or type(exc).__name__
        raise ConfigError(yaml_source, key, f"{path}: meshio cannot read this file "
                                            f"({text})") from None


def _nastran_sets(path, points_id):
    """{str(SID): point indices} of the SET1 cards of a Nastran file (free or small field)."""
    text = read_input(path).decode(errors="replace")
    lookup = {int(g): i for i, g in enumerate(points_id)}
    cards, current = [], None
    for line in text.splitlines():
        if not line.strip() or line.startswith("$"):
            continue
        if line[:1] in "+*," or (current is not None and line[:8].strip() == ""):
            if current is not None:
                current.extend(_fields(line)[1:])
            continue
        current = None
        if line.upper().startswith("SET1"):
            current = _fields(line)
            cards.append(current)
    sets = {}
    for card in cards:
        values = [v for v in card[1:] if v]
        if not values:
            continue
        sid, members, i = values[0], [], 1
        while i < len(values):
            if values[i].upper() == "THRU" and members and i + 1 < len(values):
                members.extend(range(members[-1] + 1, int(values[i + 1]) + 1))
                i += 2
                continue
            if values[i].upper() != "SKIN":
                members.append(int(values[i]))
            i += 1
        found = [lookup[g] for g in members if g in lookup]
        sets.setdefault(str(int(sid)), []).extend(found)
    return {k: np.array(v, int) for k, v in sets.items()}


def _fields(line):
    """Fields of one bulk data line: comma separated (free field) or 8 characters wide."""
    line = line.rstrip("\n")
    if "," in line:
        return [f.strip() for f in line.split(",")]
    return [line[i:i + 8].strip() for i in range(0, min(len(line), 72), 8)]


def _flag_sets(data, cells):
    """Sets from point or cell data arrays: {name: node indices where it is non-zero}."""
    out = {}
    for name, values in data.items():
        if re.match(r"^(gmsh|nastran|medit|abaqus):", name):
            continue
        if cells is None:
            arr = np.asarray(values)
            if arr.ndim == 1 and arr.dtype.kind in "biuf":
                out[name] = np.flatnonzero(arr)
        else:
            nodes = []
            for block, arr in zip(cells, values):
                arr = np.asarray(arr)
                if arr.ndim == 1 and arr.dtype.kind in "biuf" and len(arr) == len(block.data):
                    nodes.append(block.data[arr != 0].ravel())
            if nodes:
                out[name] = np.unique(np.concatenate(nodes))
    return out


def _all_sets(mesh, path):
    """{name: point indices (of the file's points)} from every source (module docstring)."""
    sets = {}

    def add(name, nodes):
        nodes = np.asarray(nodes, int).ravel()
        sets[str(name)] = np.union1d(sets.get(str(name), np.zeros(0, int)), nodes)

    for name, nodes in mesh.point_sets.items():
        add(name, nodes)
    for name, per_block in mesh.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        for block, idx in zip(mesh.cells, per_block):
            if idx is not None and len(idx):
                add(name, block.data[np.asarray(idx, int)])
    physical = mesh.cell_data.get("gmsh:physical")
    if physical is not None:
        for name, (tag, dim) in ((n, v[:2]) for n, v in mesh.field_data.items()
                                 if len(v) >= 2):
            for block, tags in zip(mesh.cells, physical):
                block_dim = 3 if block.type in SOLID_TYPES or block.type in _VOLUME_OTHER \
                    else _DIM.get(block.type, -1)
                if block_dim == int(dim):
                    add(name, block.data[np.asarray(tags) == tag])
    if path.suffix.lower() in _NASTRAN and getattr(mesh, "points_id", None) is not None:
        for name, nodes in _nastran_sets(path, mesh.points_id).items():
            add(name, nodes)
    for name, nodes in _flag_sets(mesh.point_data, None).items():
        add(name, nodes)
    for name, nodes in _flag_sets(mesh.cell_data, mesh.cells).items():
        add(name, nodes)
    return sets


def read_mesh(path, units, yaml_source, key="mesh.file"):
    """MeshData of the volume mesh in ``path`` with coordinates scaled from ``units``.

    ConfigError (naming ``yaml_source`` and ``key``, and the mesh file) when the file is
    missing, of an unsupported format, unreadable, has no volume elements or has volume
    elements of a type that is not supported.
    """
    path = Path(path)
    mesh = _read(path, yaml_source, key)
    if units not in UNITS:
        raise ConfigError(yaml_source, "mesh.units", f"'{units}' is not one of: m, mm")
    types = [c.type for c in mesh.cells]
    unsupported = sorted({t for t in types if t in _VOLUME_OTHER})
    if unsupported:
        count = sum(len(c.data) for c in mesh.cells if c.type in unsupported)
        raise ConfigError(yaml_source, key, f"{path}: unsupported element type "
                                            f"{', '.join(unsupported)} ({count} element"
                                            f"{'s' if count != 1 else ''}); "
                                            f"supported volume elements: "
                                            f"{', '.join(SOLID_TYPES)}")
    volume = [(i, c) for i, c in enumerate(mesh.cells) if c.type in SOLID_TYPES]
    if not volume:
        found = ", ".join(sorted(set(types))) or "no elements at all"
        raise ConfigError(yaml_source, key, f"{path}: the mesh has no volume elements (found "
                                            f"{found}; supported: {', '.join(SOLID_TYPES)})")
    used = np.unique(np.concatenate([c.data.ravel() for _, c in volume]))
    compact = -np.ones(len(mesh.points), int)
    compact[used] = np.arange(len(used))
    nastran_ids = getattr(mesh, "cells_id", None)
    blocks, counters = [], {}
    for i, cell in volume:
        if nastran_ids is not None:
            ids = np.asarray(nastran_ids[i])
        else:
            start = counters.get(cell.type, 0)
            ids = np.arange(start + 1, start + 1 + len(cell.data))
            counters[cell.type] = start + len(cell.data)
        blocks.append(SolidBlock(cell.type, compact[cell.data], ids))
    sets = {}
    for name, nodes in _all_sets(mesh, path).items():
        nodes = compact[nodes[(nodes >= 0) & (nodes < len(compact))]]
        sets[name] = np.unique(nodes[nodes >= 0])
    points_id = getattr(mesh, "points_id", None)
    file_ids = np.asarray(points_id)[used] if points_id is not None else used + 1
    points = np.asarray(mesh.points, float)[used, :3] * UNITS[units]
    if points.shape[1] < 3:
        points = np.column_stack([points, np.zeros((len(points), 3 - points.shape[1]))])
    return MeshData(points=points, blocks=tuple(blocks), node_sets=sets, file_ids=file_ids,
                    source=str(path), id_kind="number in the file" if nastran_ids is not None
                    else "counted from 1 among the file's elements of that type")
