"""Benchmark of the sensitivity study: mode continuation against batched eigenvalues.

Motorcycles from the vehicle engine, 171 speeds (40-210 km/h, 1 km/h steps):

* rigid touring motorcycle (12 states): weave and wobble by continuation against the
  engine's modal sweep (QZ + MAC) and numpy's batched eigvals of E^-1 A (the baseline);
* decomposed lumped touring motorcycle (24 states; axes from the components' finite-element
  mode shapes, k_t and k_b from the paper's Table 2): the 64-run 2-level study and the 729-run
  3-level study (tracking, indices, ANOVA, Pearson), against batched eigvals of the same
  runs' matrices (eigenvalues only: no mode tracking, so a floor for a full decomposition);
  with --dask the 729-run study also on a 2-process LocalCluster.

Ratios are measured in the same run (docs/performance.md); absolute times drift on shared
machines, so the CPU time of this process is printed next to the wall time.
Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_study.py [--dask]
"""
import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from motoflex_ros.config import config_path  # noqa: E402
from motoflex_ros.study.continuation import continue_eigenpairs, nearest_eigenpairs  # noqa: E402
from motoflex_ros.study.factorial import PAPER_TABLE2_NOMINAL, full_factorial  # noqa: E402
from motoflex_ros.study.motorcycle import decomposed_study, with_stiffness  # noqa: E402
from motoflex_ros.study.sensitivity import run_sensitivity  # noqa: E402
from motoflex_ros.units import kmh_to_ms  # noqa: E402
from motoflex_ros.vehicle.linearize import linearize  # noqa: E402
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402
from motoflex_ros.vehicle.modes import modal_sweep  # noqa: E402

SPEEDS = kmh_to_ms(np.linspace(40.0, 210.0, 171))
COMPONENTS = ("frame", "front_assembly", "swingarm")


def best_of(repeats, function):
    """Smallest (wall, CPU) time [s] of ``repeats`` calls."""
    times = []
    for _ in range(repeats):
        wall, cpu = time.perf_counter(), time.process_time()
        function()
        times.append((time.perf_counter() - wall, time.process_time() - cpu))
    return min(times)


def row(label, seconds, baseline, extra=""):
    """One line: label, wall and CPU time, ratio of the wall (CPU) times to the baseline's."""
    wall, cpu = seconds
    print(f"  {label:<46s}{wall:7.3f} s wall {cpu:7.3f} s CPU   ratio {wall / baseline[0]:5.2f} "
          f"({cpu / baseline[1]:5.2f}){extra}")


def bench_rigid(vehicle, repeats):
    lin = linearize(vehicle)
    e, a = lin.pencil(SPEEDS)
    t_eigvals = best_of(repeats, lambda: np.linalg.eigvals(np.linalg.solve(e, a)))
    t_sweep = best_of(repeats, lambda: modal_sweep(lin, SPEEDS))
    sweep = modal_sweep(lin, SPEEDS)
    targets = [sweep.modes["weave"][0], sweep.modes["wobble"][0]]

    def track():
        lam0, vec0 = nearest_eigenpairs(a[None, 0], targets, descriptor=e[None, 0])
        return continue_eigenpairs((e[None], a[None]), lam0, vec0, speeds=SPEEDS)

    t_track = best_of(repeats, track)
    result = track()
    error = max(np.max(np.abs(result.eigenvalues[0, :, i] - sweep.modes[m])
                       / np.abs(sweep.modes[m])) for i, m in enumerate(STUDIED_MODES))
    print(f"rigid touring motorcycle, n = {a.shape[-1]}, one run, {SPEEDS.size} speeds:")
    row("batched eigvals of E^-1 A (baseline)", t_eigvals, t_eigvals)
    row("engine modal_sweep (QZ + MAC)", t_sweep, t_eigvals)
    row("continuation of weave and wobble", t_track, t_eigvals,
        f"   (max relative difference to the engine {error:.1e})")


def fe_identification():
    """Axes from the components' FE mode shapes, k_t and k_b from the paper's Table 2."""
    from motoflex_ros.formats.component_file import load_component

    components = {name: load_component(name) for name in COMPONENTS}
    identified = {}
    for name, component in components.items():
        reduced = component.clamped_reduced()
        identified[name] = {test: {"l": reduced.mode_axis(test).l,
                                   "beta": reduced.mode_axis(test).beta}
                            for test in ("torsion", "bending")}
    return components, with_stiffness(identified, PAPER_TABLE2_NOMINAL)


def eigvals_baseline(study, levels, max_runs=64):
    """Batched eigvals of E^-1 A of (at most max_runs of) the design's runs, scaled per run."""
    design = full_factorial(study.nominal, levels=levels)
    values = design.values(0, min(max_runs, len(design)))
    pencil = study.study.state_matrices
    runs = len(next(iter(values.values())))

    def all_speeds():
        e, a = zip(*(pencil(values, v) for v in SPEEDS))
        return np.linalg.eigvals(np.linalg.solve(np.stack(e, 1), np.stack(a, 1)))

    return tuple(t * len(design) / runs for t in best_of(1, all_speeds))


def bench_lumped(scheduler):
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    start = time.perf_counter()
    components, identified = fe_identification()
    study = decomposed_study(vehicle, components, identified, SPEEDS)
    n = study.study.state_matrices.A_coeffs.shape[-1]
    print(f"decomposed lumped touring motorcycle, n = {n}, {SPEEDS.size} speeds (set-up: FE "
          f"axes, 1 linearization, 12 for the stiffness directions, nominal modal sweep: "
          f"{time.perf_counter() - start:.1f} s)")
    run_sensitivity(study.study, study.nominal, SPEEDS, levels=2, progress=False)  # warm-up
    for levels, label in ((2, "64-run study (target <= 1 s)"),
                          (3, "729-run study (target <= 10 s)")):
        baseline = eigvals_baseline(study, levels)
        row(f"batched eigvals, {levels ** 6} runs (baseline)", baseline, baseline,
            "" if levels == 2 else "   (from 64 runs x 729/64)")
        out = {}

        def study_run(levels=levels, scheduler=None, out=out):
            out["result"], out["run"] = run_sensitivity(study.study, study.nominal, SPEEDS,
                                                        levels=levels, scheduler=scheduler,
                                                        progress=False)

        total = best_of(1, study_run)
        shares = min(out["result"].anova_main_share.values())
        row(f"{label}, all", total, baseline, f"   (main-effect share min {shares:.4f}, "
            f"modes alone {out['run'].seconds:.3f} s wall)")
        if scheduler and levels == 3:
            from motoflex_ros.study.runner import local_cluster

            with local_cluster(n_workers=2) as cluster:
                row(f"{label} on Dask (2 processes)",
                    best_of(1, lambda: study_run(3, cluster)), baseline,
                    "   (CPU: this process only)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dask", action="store_true",
                        help="also run the 729-run study on a 2-process LocalCluster")
    args = parser.parse_args()
    bench_rigid(load_vehicle(config_path("vehicles", "touring")), repeats=3)
    bench_lumped(args.dask)


if __name__ == "__main__":
    main()
