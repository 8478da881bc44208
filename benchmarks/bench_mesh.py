#!/usr/bin/env python3
"""Benchmark: a solid mesh component (issue 15) from file to Craig-Bampton, step by step.

A box cantilever of quadratic tetrahedra (or another type) of about ``--dofs`` DOFs is written
as a VTU file with its clamp and loaded-end node sets, then read, assembled (stiffness and mass),
its rigid spiders eliminated and reduced (20 fixed-interface modes up to ``--f-max`` plus the
constraint modes). Each step is timed; the reduction is put beside its floor, measured in the
same run on the same matrices: one sparse factorisation of the interior stiffness (the solver
the reduction uses, ``--solver``: PARDISO's Cholesky when pypardiso is installed, else SuperLU)
plus a 20-mode shift-invert eigsh with that factorisation. Peak memory is the process's resident
high-water mark (VmHWM: it counts MKL's own allocations, which tracemalloc does not see), reset
before each step (/proc/self/clear_refs) so each step's peak is its own. MKL's threads are
MKL_NUM_THREADS (1 when unset). Run from the project root, one large case per process:
    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mesh.py [--dofs 100000] [--type tetra10]
    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mesh.py --dofs 1000000 --type tetra
"""
import argparse
import gc
import math
import tempfile
import time
from functools import partial
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla
import yaml

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.mesh_examples import box_mesh, write_mesh
from motoflex_ros.structures.craig_bampton import craig_bampton, interior_blocks
from motoflex_ros.structures.sparse_solver import default_threads, factorize_spd

NODES_PER_CELL = {"tetra": 1.0, "tetra10": 8.0, "hexahedron": 1.0, "hexahedron20": 4.0,
                  "hexahedron27": 8.0}


def _status_mb(field):
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024
    return float("nan")


def peak_mb():
    """Resident memory high-water mark of this process since the last reset [MiB]."""
    return _status_mb("VmHWM")


def reset_peak():
    """Start a new high-water mark at the current resident size (Linux /proc/self/clear_refs);
    returns the resident size then [MiB]."""
    gc.collect()
    try:
        with open("/proc/self/clear_refs", "w") as refs:
            refs.write("5")
    except OSError:
        pass
    return _status_mb("VmRSS")


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


def floor(asm, boundary, n_modes, solver):
    """(slicing s, factorisation s, eigsh s, factor entries, solver name) of the reduction's own
    interior stiffness and mass: one factorisation and a 20-mode shift-invert eigsh on it."""
    t_slice, (_, k_ii, m_ii, _) = timed(lambda: interior_blocks(asm.K, asm.M, boundary))
    t_lu, factor = timed(lambda: factorize_spd(k_ii, solver))
    with factor:
        op = factor.operator()
        t_eig, _ = timed(lambda: spla.eigsh(op, k=n_modes, M=m_ii, sigma=0.0, OPinv=op,
                                            which="LM", v0=np.linspace(1.0, 2.0, k_ii.shape[0])))
    return t_slice, t_lu, t_eig, factor.factor_entries, factor.solver


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dofs", type=int, default=50_000)
    parser.add_argument("--type", default="tetra10", choices=sorted(NODES_PER_CELL))
    parser.add_argument("--f-max", type=float, default=1e5,
                        help="cut-off [Hz] (default 100 kHz: the box keeps all 20 modes)")
    parser.add_argument("--solver", default="auto", choices=("auto", "pardiso", "superlu"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        t_mesh, mesh = timed(lambda: box_for(args.dofs, args.type))
        t_write, path = timed(partial(write_component, Path(tmp), *mesh, args.type))
        n_points, n_cells = map(len, mesh)
        del mesh   # the component reads its own copy from the file
        t_read, comp = timed(lambda: load_component(path))
        t_assembly = timed(lambda: comp.solid_matrices is None)[0]   # kept by comp only
        t_spiders, asm = timed(comp.assembled)
        mem_assembled = peak_mb()
        boundary = np.concatenate([asm.node_dofs(n) for n in comp.interface_nodes])
        rss_cb = reset_peak()
        t_cb, cb = timed(lambda: craig_bampton(asm.K, asm.M, boundary, 20, args.f_max,
                                               solver=args.solver))
        mem_cb = peak_mb()
        n_modes, f_top = cb.n_modes, cb.frequencies_hz.max()
        del cb
        rss_floor = reset_peak()
        t_slice, t_lu, t_eig, entries, solver = floor(asm, boundary, 20, args.solver)
        mem_floor = peak_mb()
    print(f"{args.type} box: {n_cells:,} elements, {n_points:,} nodes, "
          f"{asm.K.shape[0]:,} DOFs after the spiders, {asm.K.nnz:,} stiffness entries; "
          f"solver {solver}, {default_threads()} MKL thread(s)")
    print(f"  mesh made {t_mesh:.2f} s, written (VTU) {t_write:.2f} s, read {t_read:.2f} s")
    print(f"  assembly K and M {t_assembly:.2f} s; spiders eliminated {t_spiders:.2f} s; "
          f"peak memory {mem_assembled:,.0f} MiB")
    print(f"  Craig-Bampton ({n_modes} modes up to {f_top:.0f} Hz + "
          f"{len(boundary)} constraint modes) {t_cb:.2f} s; peak memory {mem_cb:,.0f} MiB "
          f"({mem_cb - rss_cb:,.0f} MiB above the {rss_cb:,.0f} MiB held before)")
    base = t_lu + t_eig
    print(f"  floor: factorisation of K_ii {t_lu:.2f} s ({entries:,} factor entries) + 20-mode "
          f"shift-invert eigsh {t_eig:.2f} s = {base:.2f} s (slicing K_ii, M_ii {t_slice:.2f} s "
          f"more); peak memory {mem_floor:,.0f} MiB ({mem_floor - rss_floor:,.0f} MiB above "
          f"{rss_floor:,.0f} MiB)")
    print(f"  reduction / floor: time {t_cb / base:.2f}x, peak memory {mem_cb / mem_floor:.2f}x "
          f"(above what was held {(mem_cb - rss_cb) / (mem_floor - rss_floor):.2f}x)")
    total = t_read + t_assembly + t_spiders + t_cb
    print(f"  file to reduced model {total:.2f} s ({math.ceil(asm.K.shape[0] / total):,} DOFs/s)"
          f"; whole run peak {_status_mb('VmPeak'):,.0f} MiB virtual")


if __name__ == "__main__":
    main()
