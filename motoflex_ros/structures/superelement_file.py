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
superelement enters the bench and the vehicle like our own reductions: its matrices are the
Craig-Bampton model (no reduction is made again), the clamps' rows are deleted for the bench.
"""
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from motoflex_ros.config import Field, validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.input_pins import read_input
from motoflex_ros.structures.assembly import AssembledStructure
from motoflex_ros.structures.components import DEFAULT_DAMPING_RATIO, ComponentModel
from motoflex_ros.structures.craig_bampton import CraigBamptonModel, checked_damping_ratio
from motoflex_ros.structures.mesh_file import UNITS

__all__ = ["SuperelementComponent", "SUPERELEMENT_SCHEMA", "load_superelement_component",
           "export_superelement"]

MAX_SIZE = 20_000  # reduced coordinates (dense matrices: 3.2 GB each at the limit)
_POINT = Field("vec3", -1e4, 1e4)

SUPERELEMENT_SCHEMA = Field("mapping", fields={
    "component": Field("str", choices=("superelement",)),
    "name": Field("str", required=False, default=None),
    "description": Field("str", required=False, default=""),
    "damping_ratio": Field("any", required=False, default=None,
                           help="a number in [0, 1) or a list of them, one per mode"),
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


@dataclass(frozen=True, eq=False)
class SuperelementComponent(ComponentModel):
    """A component given as a reduced model: ``K``, ``M`` (dense, coordinates ordered clamps,
    loaded end, other interface nodes (six each), then the generalized coordinates) and the
    interface nodes' points ``points`` [m] (component frame)."""

    name: str
    K: np.ndarray
    M: np.ndarray
    points: np.ndarray
    clamp_nodes: tuple
    loaded_end: int
    interface_nodes: tuple
    node_names: dict
    origin: np.ndarray
    source: str = ""
    damping_ratio: object = DEFAULT_DAMPING_RATIO

    kind = "superelement"
    singular_hint = "check the superelement's matrices and its interface rows"

    @property
    def node_xyz(self):
        """The interface nodes, (n, 3) [m] in the component frame."""
        return np.asarray(self.points, float)

    @property
    def elements(self):
        """Lines from each clamp to the loaded end (there is no mesh to draw)."""
        return np.array([(c, self.loaded_end) for c in self.clamp_nodes], int)

    def assembled(self):
        """The reduced matrices as the 'full' model; ``expand`` gives the interface nodes' DOFs
        (the generalized coordinates move no node)."""
        n, nb = self.K.shape[0], 6 * len(self.points)
        expand = sp.csr_matrix((np.ones(nb), (np.arange(nb), np.arange(nb))), shape=(nb, n))
        return AssembledStructure(K=sp.csc_matrix(self.K), M=sp.csc_matrix(self.M),
                                  expand=expand, free_index=np.arange(nb))

    def craig_bampton(self, n_modes=20, f_max_hz=600.0, zeta=None):
        """The superelement's own reduction (``n_modes`` and ``f_max_hz`` do not apply: its
        generalized coordinates are what the FE tool kept). Returns (CraigBamptonModel,
        AssembledStructure)."""
        nb, n = 6 * len(self.points), self.K.shape[0]
        modal = np.arange(nb, n)
        freq = np.sqrt(np.maximum(sla.eigh(self.K[np.ix_(modal, modal)],
                                           self.M[np.ix_(modal, modal)],
                                           eigvals_only=True), 0.0)) / (2 * np.pi) \
            if len(modal) else np.zeros(0)
        zeta = self.damping_ratio if zeta is None else zeta
        cb = CraigBamptonModel(M=self.M, K=self.K, transform=np.eye(n), boundary=np.arange(nb),
                               frequencies_hz=freq, zeta=checked_damping_ratio(zeta))
        self._check_damping_count(cb)
        return cb, self.assembled()


def _matrix(path, source, key, size=None):
    from scipy.io import mmread
    if not path.is_file():
        raise ConfigError(source, key, f"matrix file not found: {path}")
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


def load_superelement_component(cfg, path, damping_ratio):
    """SuperelementComponent from a validated SUPERELEMENT_SCHEMA configuration."""
    from motoflex_ros.structures.mesh_component import mesh_component_name
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
    return SuperelementComponent(
        name=mesh_component_name(cfg, path), K=k[np.ix_(order, order)],
        M=m[np.ix_(order, order)], points=points, clamp_nodes=tuple(range(nc)), loaded_end=nc,
        interface_nodes=tuple(range(len(names))), node_names={n: i for i, n in
                                                               enumerate(names)},
        origin=np.zeros(3) if placement is None else np.asarray(placement["origin"], float),
        source=source, damping_ratio=damping_ratio)


def validate_superelement_config(data, path):
    """The validated SUPERELEMENT_SCHEMA configuration of the YAML mapping ``data``."""
    return validate(data, SUPERELEMENT_SCHEMA, path)


def export_superelement(component, directory, n_modes=20, f_max_hz=600.0):
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
        mmwrite(str(directory / f"{stem}_{suffix}.mtx"), np.asarray(matrix), precision=17,
                symmetry="symmetric")
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
    path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return path
