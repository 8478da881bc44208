#!/usr/bin/env python3
"""Benchmark: a solid mesh component (issue 15) from file to Craig-Bampton, step by step.

A box cantilever of quadratic tetrahedra (or another type) of about ``--dofs`` DOFs is written
as a VTU file with its clamp and loaded-end node sets, then read, assembled (stiffness and mass),
its rigid spiders eliminated and reduced (20 fixed-interface modes up to ``--f-max`` plus the
constraint modes). Each step is timed; the reduction is put beside its floor, measured in the
same run on the same matrices: one sparse factorisation of the interior stiffness (the solver
the reduction uses) plus a 20-mode shift-invert eigsh with that factorisation. Peak memory is
the process's resident maximum. Run from the project root:
    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mesh.py [--dofs 50000] [--type tetra10]
"""
import argparse
import math
import resource
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla
import yaml

from motoflex_ros.structures.components import load_component
from motoflex_ros.structures.craig_bampton import craig_bampton, symmetric_lu
from motoflex_ros.structures.mesh_examples import box_mesh, write_mesh

NODES_PER_CELL = {"tetra": 1.0, "tetra10": 8.0, "hexahedron": 1.0, "hexahedron20": 4.0,
                  "hexahedron27": 8.0}


def peak_mb():
    """Resident memory high-water mark of this process [MB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def timed(func):
    t0 = time.perf_counter()
    out = func()
    return time.perf_counter() - t0, out


def box_for(dofs, cell_type, aspect=10):
    """A box of about ``dofs`` DOFs, length ``aspect`` times its square section."""
    cells = dofs / 3 / NODES_PER_CELL[cell_type]
    n = max(1, round((cells / aspect) ** (1 / 3)))
    return box_mesh(0.1 * aspect, 0.1, 0.1, (aspect * n, n, n), cell_type)


def write_component(folder, points, cells, cell_type):
    x = points[:, 0]
    sets = {"clamp": np.flatnonzero(np.isclose(x, 0.0)),
            "tip": np.flatnonzero(np.isclose(x, x.max()))}
    write_mesh(folder / "box.vtu", points, cells, cell_type, sets)
    path = folder / "box.yaml"
    path.write_text(yaml.safe_dump({
        "component": "mesh", "name": "box",
        "mesh": {"file": "box.vtu", "units": "m", "clamps": ["clamp"], "loaded_end": "tip"},
        "material": {"E": 2.1e11, "nu": 0.3, "rho": 7850.0}}))
    return path


def floor(asm, boundary, n_modes):
    """(factorisation s, eigsh s) of the reduction's own interior stiffness and mass."""
    interior = np.setdiff1d(np.arange(asm.K.shape[0]), boundary)
    k_ii = asm.K[interior][:, interior].tocsc()
    m_ii = asm.M[interior][:, interior].tocsc()
    t_lu, lu = timed(lambda: symmetric_lu(k_ii))
    op = spla.LinearOperator(k_ii.shape, matvec=lu.solve, dtype=float)
    t_eig, _ = timed(lambda: spla.eigsh(k_ii, k=n_modes, M=m_ii, sigma=0.0, OPinv=op,
                                        which="LM", v0=np.linspace(1.0, 2.0, k_ii.shape[0])))
    return t_lu, t_eig


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dofs", type=int, default=50_000)
    parser.add_argument("--type", default="tetra10", choices=sorted(NODES_PER_CELL))
    parser.add_argument("--f-max", type=float, default=5000.0,
                        help="cut-off [Hz] (default 5 kHz: the box keeps all 20 modes)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        t_mesh, (points, cells) = timed(lambda: box_for(args.dofs, args.type))
        t_write, path = timed(lambda: write_component(Path(tmp), points, cells, args.type))
        t_read, comp = timed(lambda: load_component(path))
        t_assembly = timed(lambda: comp.solid_matrices is None)[0]   # kept by comp only
        t_spiders, asm = timed(comp.assembled)
        mem_assembled = peak_mb()
        boundary = np.concatenate([asm.node_dofs(n) for n in comp.interface_nodes])
        t_cb, cb = timed(lambda: craig_bampton(asm.K, asm.M, boundary, 20, args.f_max))
        mem_cb = peak_mb()
        t_lu, t_eig = floor(asm, boundary, 20)
    print(f"{args.type} box: {len(cells):,} elements, {len(points):,} nodes, "
          f"{asm.K.shape[0]:,} DOFs after the spiders, {asm.K.nnz:,} stiffness entries")
    print(f"  mesh made {t_mesh:.2f} s, written (VTU) {t_write:.2f} s, read {t_read:.2f} s")
    print(f"  assembly K and M {t_assembly:.2f} s; spiders eliminated {t_spiders:.2f} s; "
          f"peak memory {mem_assembled:,.0f} MB")
    print(f"  Craig-Bampton ({cb.n_modes} modes up to {cb.frequencies_hz.max():.0f} Hz + "
          f"{len(boundary)} constraint modes) {t_cb:.2f} s; peak memory {mem_cb:,.0f} MB")
    base = t_lu + t_eig
    print(f"  floor: factorisation of K_ii {t_lu:.2f} s + 20-mode shift-invert eigsh "
          f"{t_eig:.2f} s = {base:.2f} s; reduction / floor {t_cb / base:.2f}x")
    total = t_read + t_assembly + t_spiders + t_cb
    print(f"  file to reduced model {total:.2f} s ({math.ceil(asm.K.shape[0] / total):,} DOFs/s)")


if __name__ == "__main__":
    main()
