"""Benchmark of the sensitivity study on the flexible motorcycle (issue 14, 100 states).

Set-up (the nominal linearization, the six analytic modal-stiffness directions, the check
against a direct linearization, the nominal sweep that names weave and wobble), then the
64-run 2-level study (continuation, indices, ANOVA, Pearson) on the 5 km/h grid (35 speeds),
against numpy's batched ``eigvals`` of E^-1 A of the same runs' matrices (eigenvalues only, no
tracking; timed on 8 runs and scaled to 64). Ratios in the same run; CPU time beside wall.
Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_flexible_study.py
"""
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from motoflex_ros.cli.inputs import motorcycle_components, study_speeds  # noqa: E402
from motoflex_ros.config import resolve_config  # noqa: E402
from motoflex_ros.study.factorial import full_factorial  # noqa: E402
from motoflex_ros.study.flexible_sensitivity import flexible_study  # noqa: E402
from motoflex_ros.study.sensitivity import run_sensitivity  # noqa: E402
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main():
    identified = json.loads((ROOT / "bags/example/identification.json").read_text())
    vehicle = load_vehicle(resolve_config("vehicles", "touring"))
    components = motorcycle_components()
    speeds = study_speeds(5.0, 10.0)
    wall, cpu = time.perf_counter(), time.process_time()
    setup = flexible_study(vehicle, components, identified, speeds)
    print(f"set-up {time.perf_counter() - wall:.2f} s wall, {time.process_time() - cpu:.2f} s "
          "CPU")
    wall, cpu = time.perf_counter(), time.process_time()
    _, run = run_sensitivity(setup.study, setup.nominal, speeds, progress=False)
    study_wall, study_cpu = time.perf_counter() - wall, time.process_time() - cpu
    design = full_factorial(setup.nominal)
    values = design.values(0, 8)
    start = time.perf_counter()
    for speed in speeds:
        e, a = setup.study.state_matrices(values, speed)
        np.linalg.eigvals(np.linalg.solve(e, a))
    eig = (time.perf_counter() - start) * len(design) / 8
    print(f"64-run study {study_wall:.2f} s wall, {study_cpu:.2f} s CPU; batched eigvals of the "
          f"same matrices {eig:.2f} s (from 8 runs); ratio {study_wall / eig:.2f}x "
          f"(load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
