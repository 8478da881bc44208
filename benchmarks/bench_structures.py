#!/usr/bin/env python3
"""Benchmark: build and reduce each component, and reduce a 1e5-DOF tube mesh.

Every time is printed with a ratio against a baseline measured in the same run: scipy's own
sparse LU (``scipy.sparse.linalg.splu`` with its default options) of the same stiffness matrix
that the reduction factorises (the interior block K_ii). Run from the project root:
    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_structures.py [--dofs 100000]
"""
import argparse
import time

import numpy as np
import scipy.sparse.linalg as spla

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.beam import Material
from motoflex_ros.structures.component_model import tube_component
from motoflex_ros.structures.craig_bampton import craig_bampton


def best_of(func, repeat):
    """Smallest wall time of ``repeat`` calls [s] and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def interior_stiffness(component):
    """K_ii of the component's Craig-Bampton partition (what the reduction factorises)."""
    asm = component.assembled()
    boundary = np.concatenate([asm.node_dofs(n) for n in component.interface_nodes])
    interior = np.setdiff1d(np.arange(asm.K.shape[0]), boundary)
    return asm, boundary, asm.K[interior][:, interior].tocsc()


def bench_component(name, repeat):
    t_build_reduce, _ = best_of(lambda: load_component(name).clamped_reduced(), repeat)
    comp = load_component(name)
    _, _, k_ii = interior_stiffness(comp)
    t_lu, _ = best_of(lambda: spla.splu(k_ii), repeat)
    return name, comp.dof_count(), t_build_reduce, t_lu


def bench_tube(dofs, repeat):
    """A 6 m steel tube (20 fixed-interface modes below 600 Hz) meshed to about ``dofs``."""
    elements = max(1, dofs // 6 - 1)
    steel = Material(2.1e11, 8.1e10, 7850.0)
    t_build, comp = best_of(lambda: tube_component(6.0, 0.04, 0.002, 0.0, steel, elements), 1)
    asm, boundary, k_ii = interior_stiffness(comp)
    t_reduce, cb = best_of(lambda: craig_bampton(asm.K, asm.M, boundary), repeat)
    t_lu, _ = best_of(lambda: spla.splu(k_ii), 3 * repeat)
    return asm.K.shape[0], t_build, t_reduce, t_lu, cb.n_modes


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dofs", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"{'case':<28}{'DOFs':>9}{'time [s]':>11}{'splu [s]':>11}{'ratio':>9}")
    for name in ("frame", "front_assembly", "swingarm"):
        name, dofs, t, t_lu = bench_component(name, args.repeat)
        print(f"{name + ' build+reduce':<28}{dofs:>9}{t:>11.4f}{t_lu:>11.5f}{t / t_lu:>9.1f}")
    dofs, t_build, t_reduce, t_lu, modes = bench_tube(args.dofs, max(1, args.repeat - 2))
    print(f"{'tube assemble':<28}{dofs:>9}{t_build:>11.3f}{t_lu:>11.3f}{t_build / t_lu:>9.1f}")
    print(f"{f'tube reduce ({modes} modes)':<28}{dofs:>9}{t_reduce:>11.3f}{t_lu:>11.3f}"
          f"{t_reduce / t_lu:>9.1f}")


if __name__ == "__main__":
    main()
