"""Pre-reduced superelements: a Craig-Bampton (or any) reduction made by the engineer's own FE
tool, given as its reduced stiffness and mass matrices and its interface DOF map
(``component: superelement``), and the export of our own reductions in the same form.

The YAML (interface points in ``units``; the matrices in SI: N/m, N, N m/rad; kg, kg m, kg m^2)::

    component: superelement
    name: swingarm            # optional: the YAML file's name
    superelement:
      stiffness: swingarm_K.mtx   # Matrix Market (scipy.io.mmread), relative to this YAML
      mass: swingarm_M.mtx
      units: m                # of the points: m or mm
      interface:              # each node: six rows (ux, uy, uz, rx, ry, rz) from ``row`` (0-based)
        pivot: {point: [0.0, 0.0, 0.0], row: 0}
        axle: {point: [-0.6, 0.0, -0.045], row: 6}
      clamps: [pivot]
      loaded_end: axle
    damping_ratio: 0.01
    placement: {origin: [0.6, 0.0, 0.36]}   # optional: O in the vehicle frame [m]

Rows that belong to no interface node are the reduction's generalized (modal) coordinates. The
component read is a :class:`~motoflex_ros.structures.superelement_component.
SuperelementComponent` (the numerical core's: it enters the bench and the vehicle like our own
reductions); here is the file format: the schema, the checks of the Matrix Market files and of
the matrices (ConfigError naming the file and the key), and the export.
"""
import io
from pathlib import Path

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from motoflex_ros.config import Field
from motoflex_ros.errors import ConfigError
from motoflex_ros.files import atomic_write_bytes, atomic_write_text, missing_file_text
from motoflex_ros.formats.mesh_component_file import mesh_component_name
from motoflex_ros.formats.mesh_file import UNITS
from motoflex_ros.input_pins import read_input
from motoflex_ros.structures.component_schema import DAMPING_FIELD
from motoflex_ros.structures.craig_bampton import F_MAX_HZ, N_MODES
from motoflex_ros.structures.superelement_component import SuperelementComponent

__all__ = ["SUPERELEMENT_SCHEMA", "load_superelement_component", "export_superelement"]

MAX_SIZE = 20_000  # reduced coordinates (dense matrices: 3.2 GB each at the limit)
_POINT = Field("vec3", -1e4, 1e4)

SUPERELEMENT_SCHEMA = Field("mapping", fields={
    "component": Field("str", choices=("superelement",)),
    "name": Field("str", required=False, default=None),
    "description": Field("str", required=False, default=""),
    "damping_ratio": DAMPING_FIELD,
    "placement": Field("mapping", required=False, default=None, fields={
        "origin": Field("vec3", -10.0, 10.0)}),
    "superelement": Field("mapping", fields={
        "stiffness": Field("str", help="Matrix Market file of the reduced stiffness"),
        "mass": Field("str", help="Matrix Market file of the reduced mass"),
        "units": Field("str", choices=tuple(UNITS), required=False, default="m"),
        "interface": Field("mapping", extra=True, fields={}, item=Field("mapping", fields={
            "point": _POINT,
            "row": Field("int", 0, MAX_SIZE),
        })),
        "clamps": Field("list", min_items=1, item=Field("str")),
        "loaded_end": Field("str"),
    }),
})


_ENTRIES = {"general": lambda n: n * n, "symmetric": lambda n: n * (n + 1) // 2,
            "skew-symmetric": lambda n: n * (n - 1) // 2}


def _mtx_size(path, source, key):
    """Check a Matrix Market file's header and count its entries before it is read: a size
    above MAX_SIZE, or fewer (or more) entries than the header says (a truncated file, which
    scipy pads with zeros), is a ConfigError naming the file. Returns the number of rows."""
    with open(path, encoding="utf-8", errors="replace") as stream:
        banner = stream.readline(200).split()
        line = stream.readline(200)
        lines = 2
        while line.startswith("%") or (line and not line.strip()):
            line, lines = stream.readline(200), lines + 1
        if len(banner) != 5 or banner[0].lower() != "%%matrixmarket" or \
                banner[2].lower() not in ("array", "coordinate"):
            raise ConfigError(source, key, f"{path}: not a Matrix Market file (line 1 must "
                                           f"be '%%MatrixMarket matrix array|coordinate ...')")
        layout, symmetry = banner[2].lower(), banner[4].lower()
        try:
            sizes = [int(v) for v in line.split()]
        except ValueError:
            sizes = []
        if len(sizes) != (2 if layout == "array" else 3) or min(sizes) < 0:
            raise ConfigError(source, key, f"{path}: line {lines}: expected the size "
                                           f"('rows columns' or 'rows columns entries'), got "
                                           f"'{line.strip()[:60]}'")
        rows, columns = sizes[:2]
        if max(rows, columns) > MAX_SIZE:
            raise ConfigError(source, key, f"{path}: {max(rows, columns)} coordinates, more "
                                           f"than {MAX_SIZE}")
        if layout == "coordinate":
            expected = sizes[2]
        elif symmetry in _ENTRIES and rows == columns:
            expected = _ENTRIES[symmetry](rows)
        else:
            expected = rows * columns
        found = sum(1 for text in stream if text.strip() and not text.startswith("%"))
    if found != expected:
        raise ConfigError(source, key, f"{path}: {found} entries, its header (line {lines}) "
                                       f"says {expected}: the file is "
                                       f"{'truncated' if found < expected else 'too long'}")
    return rows


def _matrix(path, source, key, size=None):
    from scipy.io import mmread
    if not path.is_file():
        raise ConfigError(source, key, f"matrix file {path}: {missing_file_text(path)}")
    _mtx_size(path, source, key)
    data = read_input(path)   # checked against the run's pins
    try:
        matrix = mmread(io.BytesIO(data))
    except Exception as exc:   # scipy raises ValueError, OSError, IndexError...
        raise ConfigError(source, key, f"{path}: not a Matrix Market file ({exc})") from None
    matrix = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, float)
    if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or not matrix.shape[0]:
        raise ConfigError(source, key, f"{path}: a square matrix is needed, got shape "
                                       f"{matrix.shape}")
    if matrix.shape[0] > MAX_SIZE:
        raise ConfigError(source, key, f"{path}: {matrix.shape[0]} coordinates, more than "
                                       f"{MAX_SIZE}")
    if size is not None and matrix.shape[0] != size:
        raise ConfigError(source, key, f"{path}: {matrix.shape[0]} rows, the stiffness has "
                                       f"{size}")
    if not np.all(np.isfinite(matrix)):
        raise ConfigError(source, key, f"{path}: has entries that are not finite")
    asym = np.abs(matrix - matrix.T).max()
    if asym > 1e-9 * max(np.abs(matrix).max(), 1e-300):
        raise ConfigError(source, key, f"{path}: not symmetric (largest |A - A^T| {asym:.3g})")
    return 0.5 * (matrix + matrix.T)


SCALE_RANGE = {"superelement.stiffness": (1e-6, 1e16), "superelement.mass": (1e-12, 1e9)}
"""Allowed largest |entry| of the reduced K [N/m, N, N m/rad; 1/s^2 on modal rows] and M [kg,
kg m, kg m^2] in SI: wide enough for a watch spring and a bridge, not for a file scaled by
1e-300 or 1e290 (whose eigenvalues underflow or overflow)."""


def _check_scale(matrix, file, source, key):
    low, high = SCALE_RANGE[key]
    largest = float(np.abs(matrix).max())
    if not low <= largest <= high:
        raise ConfigError(source, key, f"{file}: largest |entry| {largest:.3g}, outside "
                                       f"[{low:g}, {high:g}] (SI units: N/m and N m/rad, kg "
                                       f"and kg m^2; zero, or scaled?)")


def _check_definite(matrix, file, source, key, what):
    """ConfigError unless ``matrix`` is positive definite (a Cholesky factorisation)."""
    _, info = sla.lapack.dpotrf(np.asarray(matrix, float), lower=True, clean=False)
    if info > 0:
        raise ConfigError(source, key, f"{file}: {what} is not positive definite (its leading "
                                       f"minor of order {info} is not positive): negated, "
                                       f"singular or truncated?")


def _check_physical(k, m, n_clamped, files, source):
    """The reduced K and M (ordered clamps first) as a structure has them: entries of SI
    size, M positive definite, K positive definite once the clamps' rows are deleted (the
    clamped structure resists every motion)."""
    _check_scale(k, files[0], source, "superelement.stiffness")
    _check_scale(m, files[1], source, "superelement.mass")
    _check_definite(m, files[1], source, "superelement.mass", "the mass matrix")
    free = np.arange(n_clamped, k.shape[0])
    _check_definite(k[np.ix_(free, free)], files[0], source, "superelement.stiffness",
                    "the stiffness with the clamps' rows deleted")


def load_superelement_component(cfg, path, damping_ratio):
    """SuperelementComponent from a validated SUPERELEMENT_SCHEMA configuration."""
    source = str(path)
    spec = cfg["superelement"]
    base = Path(path).parent

    def rel(name):
        p = Path(name)
        return p if p.is_absolute() else base / p

    k = _matrix(rel(spec["stiffness"]), source, "superelement.stiffness")
    m = _matrix(rel(spec["mass"]), source, "superelement.mass", k.shape[0])
    interface = spec["interface"]
    names = list(spec["clamps"]) + [spec["loaded_end"]]
    for i, name in enumerate(names):
        key = f"superelement.clamps[{i}]" if i < len(spec["clamps"]) else \
            "superelement.loaded_end"
        if name not in interface:
            raise ConfigError(source, key, f"'{name}' is not an interface node (defined: "
                                           f"{', '.join(sorted(interface)) or 'none'})")
        if name in names[:i]:
            raise ConfigError(source, key, f"'{name}' is given twice")
    names += [n for n in interface if n not in names]
    rows, taken = [], {}
    for name in names:
        row = interface[name]["row"]
        key = f"superelement.interface.{name}.row"
        if row + 6 > k.shape[0]:
            raise ConfigError(source, key, f"rows {row}-{row + 5} are beyond the matrices' "
                                           f"{k.shape[0]} rows")
        for r in range(row, row + 6):
            if r in taken:
                raise ConfigError(source, key, f"row {r} is also {taken[r]}'s")
            taken[r] = name
        rows.extend(range(row, row + 6))
    modal = [r for r in range(k.shape[0]) if r not in taken]
    order = np.array(rows + modal)
    scale = UNITS[spec["units"]]
    points = np.array([interface[n]["point"] for n in names], float) * scale
    placement = cfg["placement"]
    nc = len(spec["clamps"])
    k, m = k[np.ix_(order, order)], m[np.ix_(order, order)]
    _check_physical(k, m, 6 * nc, (rel(spec["stiffness"]), rel(spec["mass"])), source)
    return SuperelementComponent(
        name=mesh_component_name(cfg, path), K=k, M=m, points=points,
        clamp_nodes=tuple(range(nc)), loaded_end=nc,
        interface_nodes=tuple(range(len(names))), node_names={n: i for i, n in
                                                               enumerate(names)},
        origin=np.zeros(3) if placement is None else np.asarray(placement["origin"], float),
        source=source, damping_ratio=damping_ratio)


def export_superelement(component, directory, n_modes=N_MODES, f_max_hz=F_MAX_HZ):
    """Write ``component``'s Craig-Bampton model as a superelement: ``<name>_K.mtx``,
    ``<name>_M.mtx`` (Matrix Market, 17 digits) and ``<name>.yaml`` in ``directory``; returns
    the YAML's path. The interface nodes are named as in the component (node<i> otherwise)."""
    import yaml
    from scipy.io import mmwrite
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    cb, _ = component.craig_bampton(n_modes, f_max_hz)
    by_index = {i: n for n, i in component.node_names.items()}
    names = [by_index.get(i, f"node{i}") for i in component.interface_nodes]
    stem = component.name
    for suffix, matrix in (("K", cb.K), ("M", cb.M)):
        buffer = io.BytesIO()
        mmwrite(buffer, np.asarray(matrix), precision=17, symmetry="symmetric")
        atomic_write_bytes(directory / f"{stem}_{suffix}.mtx", buffer.getvalue())
    zeta = component.damping_ratio
    cfg = {
        "component": "superelement", "name": stem,
        "description": f"Craig-Bampton model of {component.source or component.name}: "
                       f"{cb.n_modes} fixed-interface modes up to {f_max_hz:g} Hz",
        "superelement": {
            "stiffness": f"{stem}_K.mtx", "mass": f"{stem}_M.mtx", "units": "m",
            "interface": {n: {"point": [float(v) for v in component.node_xyz[i]],
                              "row": 6 * k}
                          for k, (n, i) in enumerate(zip(names, component.interface_nodes))},
            "clamps": names[:len(component.clamp_nodes)],
            "loaded_end": by_index.get(component.loaded_end, f"node{component.loaded_end}"),
        },
        "damping_ratio": list(zeta) if np.ndim(zeta) else float(zeta),
    }
    if np.any(component.origin):
        cfg["placement"] = {"origin": [float(v) for v in component.origin]}
    path = directory / f"{stem}.yaml"
    return atomic_write_text(path, yaml.safe_dump(cfg, sort_keys=False))
