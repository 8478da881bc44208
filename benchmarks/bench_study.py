"""Benchmark of the study core: mode continuation against batched eigenvalues, whole studies.

Until the vehicle engine exists, the state matrices come from a synthetic 12-DOF linear
vehicle of the same size as the lumped motorcycle (24 states): M q'' + (C + v G) q' +
(K(k) + v^2 K2) q = 0 with six stiffness factors, each a rank-one spring. The numbers printed
are ratios against numpy's batched eigvals measured in the same run (design.md Sect. 8):

* continuation of 2 modes (weave, wobble) vs np.linalg.eigvals / np.linalg.eig on the same
  (runs, 171, 24, 24) matrices;
* the 64-run 2-level study (matrices built on the fly, tracking, indices, ANOVA, Pearson);
* the 729-run 3-level study; with --dask, the same on a 2-worker LocalCluster;
* the vehicle engine's rigid touring motorcycle (12 states, descriptor pencil): weave and
  wobble by continuation against the engine's modal sweep (QZ + MAC) on the same speeds.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_study.py [--dask] [--full]
"""
import argparse
import os
import time
from dataclasses import dataclass, field

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from motoflex_ros.study.continuation import continue_eigenpairs, nearest_eigenpairs  # noqa: E402
from motoflex_ros.study.factorial import (  # noqa: E402
    FACTORS,
    PAPER_TABLE2_NOMINAL,
    full_factorial,
)
from motoflex_ros.study.runner import run_study  # noqa: E402
from motoflex_ros.study.sensitivity import analyse_sensitivity  # noqa: E402
from motoflex_ros.study.tracked import NearestTargets, TrackedModeStudy  # noqa: E402

SPEEDS = np.linspace(40.0, 210.0, 171) / 3.6  # 1 km/h steps [m/s]
DOF = 12


@dataclass(frozen=True, eq=False)
class SyntheticVehicle:
    """A damped gyroscopic 12-DOF system whose stiffness depends on the six factors."""

    seed: int = 1
    parts: tuple = field(init=False, repr=False)

    def __post_init__(self):
        rng = np.random.default_rng(self.seed)
        root = rng.standard_normal((DOF, DOF)) / np.sqrt(DOF)
        mass = root @ root.T + np.eye(DOF)
        stiff = 400.0 * (root.T @ root + np.eye(DOF))
        springs = rng.standard_normal((len(FACTORS), DOF))
        springs = 150.0 * springs[:, :, None] * springs[:, None, :]
        damping = 0.8 * np.eye(DOF) + 0.2 * (root + root.T) ** 2
        gyro = rng.standard_normal((DOF, DOF))
        k2 = 0.02 * rng.standard_normal((DOF, DOF))
        parts = (np.linalg.inv(mass), stiff, springs, damping, 0.3 * (gyro - gyro.T), k2)
        object.__setattr__(self, "parts", parts)

    def __call__(self, values, speed):
        m_inv, stiff, springs, damping, gyro, k2 = self.parts
        scale = np.column_stack([values[f] / PAPER_TABLE2_NOMINAL[f] for f in FACTORS])
        k = stiff + np.einsum("rf,fij->rij", scale, springs) + speed**2 * k2
        runs = scale.shape[0]
        a = np.zeros((runs, 2 * DOF, 2 * DOF))
        a[:, :DOF, DOF:] = np.eye(DOF)
        a[:, DOF:, :DOF] = -m_inv @ k
        a[:, DOF:, DOF:] = -m_inv @ (damping + speed * gyro)
        return a


def targets(vehicle):
    """Lowest and fifth oscillatory mode of the nominal vehicle at the first speed."""
    nominal = {f: np.array([PAPER_TABLE2_NOMINAL[f]]) for f in FACTORS}
    values = np.linalg.eigvals(vehicle(nominal, SPEEDS[0]))[0]
    upper = np.sort_complex(values[values.imag > 0] * 1j) / 1j  # by frequency
    return (upper[-1], upper[-5])


def best_of(repeats, function):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def bench_tracking(vehicle, runs, repeats):
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    values = design.values(0, runs)
    a = np.stack([vehicle(values, v) for v in SPEEDS], axis=1)
    t_eigvals = best_of(repeats, lambda: np.linalg.eigvals(a))
    t_eig = best_of(repeats, lambda: np.linalg.eig(a))

    def track():
        lam0, vec0 = nearest_eigenpairs(a[:, 0], np.asarray(targets(vehicle)))
        return continue_eigenpairs(a, lam0, vec0, speeds=SPEEDS)

    t_track = best_of(repeats, track)
    result = track()
    print(f"tracking {runs} runs x {SPEEDS.size} speeds, n = {2 * DOF}:")
    print(f"  np.linalg.eigvals (baseline)  {t_eigvals:8.3f} s   1.00")
    print(f"  np.linalg.eig (with vectors)  {t_eig:8.3f} s   {t_eig / t_eigvals:.2f}")
    print(f"  continuation, 2 modes         {t_track:8.3f} s   {t_track / t_eigvals:.2f}"
          f"   (Newton steps/point {result.iterations.mean():.2f}, "
          f"max residual {result.residual.max():.1e}, min step MAC "
          f"{result.step_mac.min():.4f})")
    reference = np.linalg.eigvals(a[:, ::10])
    error = np.abs(reference[..., None] - result.eigenvalues[:, ::10, None, :]).min(axis=2)
    print(f"  continuation vs eigvals: max |lambda difference| {error.max():.1e} 1/s")
    return t_eigvals


def bench_study(vehicle, levels, scheduler=None, label="in-process"):
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=levels, rel_range=0.10)
    study = TrackedModeStudy(state_matrices=vehicle, speeds=tuple(SPEEDS),
                             start=NearestTargets(targets=targets(vehicle)))
    start = time.perf_counter()
    run = run_study(study, design, scheduler=scheduler, progress=False)
    t_modes = time.perf_counter() - start
    analysis = analyse_sensitivity(design, SPEEDS, run.outputs)
    t_total = time.perf_counter() - start
    shares = ", ".join(f"{k} {v:.3f}" for k, v in analysis.anova_main_share.items())
    print(f"study {len(design)} runs ({label}): modes {t_modes:.3f} s, with indices/ANOVA/"
          f"Pearson {t_total:.3f} s   (main-effect shares: {shares})")
    return t_total


def bench_touring(repeats):
    from motoflex_ros.config import resolve_config
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.model import load_vehicle
    from motoflex_ros.vehicle.modes import modal_sweep

    lin = linearize(load_vehicle(resolve_config("vehicles", "touring")))
    e, a = lin.pencil(SPEEDS)
    t_sweep = best_of(repeats, lambda: modal_sweep(lin, SPEEDS))
    t_eigvals = best_of(repeats, lambda: np.linalg.eigvals(np.linalg.solve(e, a)))
    sweep = modal_sweep(lin, SPEEDS)
    targets = [sweep.modes["weave"][0], sweep.modes["wobble"][0]]

    def track(runs):
        lam0, vec0 = nearest_eigenpairs(a[None, 0], targets, descriptor=e[None, 0])
        batch = (np.broadcast_to(e, (runs,) + e.shape), np.broadcast_to(a, (runs,) + a.shape))
        return continue_eigenpairs(batch, np.repeat(lam0, runs, 0), np.repeat(vec0, runs, 0),
                                   speeds=SPEEDS)

    t_one = best_of(repeats, lambda: track(1))
    t_64 = best_of(1, lambda: track(64))
    error = max(np.max(np.abs(track(1).eigenvalues[0, :, i] - sweep.modes[m])
                       / np.abs(sweep.modes[m])) for i, m in enumerate(("weave", "wobble")))
    print(f"touring motorcycle (rigid, n = {a.shape[-1]}), {SPEEDS.size} speeds:")
    print(f"  eigvals of E^-1 A, batched (baseline) {t_eigvals:8.3f} s   1.00")
    print(f"  engine modal_sweep (QZ + MAC)         {t_sweep:8.3f} s   {t_sweep / t_eigvals:.2f}")
    print(f"  continuation, 1 run                   {t_one:8.3f} s   {t_one / t_eigvals:.2f}")
    print(f"  continuation, 64 runs                 {t_64:8.3f} s   {t_64 / t_eigvals:.2f}"
          f"   (per run {t_64 / 64 / t_eigvals:.2f})")
    print(f"  continuation vs engine: max relative difference {error:.1e}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dask", action="store_true", help="also run the 729-run study on a "
                        "2-worker LocalCluster")
    parser.add_argument("--full", action="store_true", help="also time eigvals on 729 runs")
    args = parser.parse_args()
    bench_touring(repeats=3)
    vehicle = SyntheticVehicle()
    baseline = bench_tracking(vehicle, 64, repeats=3)
    t64 = bench_study(vehicle, levels=2)
    print(f"  64-run study / eigvals of its matrices: {t64 / baseline:.2f} (target: <= 1 s)")
    if args.full:
        baseline729 = bench_tracking(vehicle, 729, repeats=1)
    else:
        baseline729 = baseline * 729 / 64
        print(f"(eigvals baseline for 729 runs extrapolated from 64: {baseline729:.2f} s)")
    t729 = bench_study(vehicle, levels=3)
    print(f"  729-run study / eigvals of its matrices: {t729 / baseline729:.2f} "
          "(target: <= 10 s)")
    if args.dask:
        from motoflex_ros.study.runner import local_cluster

        with local_cluster(n_workers=2) as cluster:
            t_dask = bench_study(vehicle, levels=3, scheduler=cluster, label="Dask, 2 workers")
        print(f"  Dask / in-process: {t_dask / t729:.2f}")


if __name__ == "__main__":
    main()
