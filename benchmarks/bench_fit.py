"""Benchmark of the hinge fit (issue 14): one fit per component and the cost of one evaluation.

For each component of the touring motorcycle (identification: bags/example/identification.json,
the flexible reference on the accuracy study's 5 km/h grid, 35 speeds):

* the whole fit as the accuracy study runs it (set-up: one linearization of the chain
  motorcycle and one of the static motorcycle to name weave and wobble; the searches from the
  static hinge and the better of the road_load and vehicle_load hinges; the polish; the
  conditioning), wall and CPU time, evaluations;
* one evaluation of the objective three ways on the same hinge motorcycle's pencils:
  continued in the hinge from a nearby evaluated hinge (what the simplex mostly does),
  continued over speed from the first speed, and numpy's batched ``eigvals`` of E^-1 A at the
  35 speeds (eigenvalues only, no mode tracking: a floor for any full decomposition).

Ratios are measured in the same run; absolute times drift on the shared machine.
Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_fit.py
"""
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from bench_vehicle import best_time  # noqa: E402  (the same best-of timing)

from motoflex_ros.cli.inputs import motorcycle_components, study_speeds  # noqa: E402
from motoflex_ros.config import resolve_config  # noqa: E402
from motoflex_ros.study.fitted import fit_hinges  # noqa: E402
from motoflex_ros.study.hinge_fit_problem import HingeFitProblem  # noqa: E402
from motoflex_ros.study.hinge_geometry import hinge_of  # noqa: E402
from motoflex_ros.study.load_variants import road_load_tests, vehicle_load_tests  # noqa: E402
from motoflex_ros.study.lumped_accuracy import flexible_motorcycle  # noqa: E402
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def evaluation_costs(problem, hinges, speeds):
    """(continued in the hinge, over speed per run, batched eigvals) [s] of one evaluation."""
    x = problem.variables(hinges)
    problem.objective(x)                               # a nearby hinge in the cache
    steps = iter(range(10_000))
    warm = best_time(lambda: problem.objective(x + 0.3 + 0.01 * next(steps)))
    pair = [problem.hinges(x + 0.3), problem.hinges(x)]
    over = best_time(lambda: problem.errors(pair)) / 2
    e, a = problem.pencil.pencil([problem._vehicle_hinges(pair[0])], speeds)
    eig = best_time(lambda: np.linalg.eigvals(np.linalg.solve(e[0], a[0])))
    return warm, over, eig


def main():
    identified = json.loads((ROOT / "bags/example/identification.json").read_text())
    vehicle = load_vehicle(resolve_config("vehicles", "touring"))
    components = motorcycle_components()
    speeds = study_speeds(5.0, 85.0)
    total_wall = total_cpu = 0.0
    for name in components:
        lin, reference = flexible_motorcycle(vehicle, components, identified, [name], speeds)
        starts = {"road_load": road_load_tests(vehicle, components, [name])[name],
                  "vehicle_load": vehicle_load_tests({name: lin}, components, [name])[name][0]}
        starts = {k: {name: hinge_of(v.model.values)} for k, v in starts.items()}
        wall, cpu = time.perf_counter(), time.process_time()
        fit = fit_hinges(vehicle, components, identified, [name], reference, speeds,
                         starts=starts)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        total_wall, total_cpu = total_wall + wall, total_cpu + cpu
        print(f"{name}: fit {wall:.2f} s wall, {cpu:.2f} s CPU, {fit.evaluations} "
              f"evaluations, J {fit.objective:.3f} %")
        problem = HingeFitProblem(vehicle, components, identified, [name], reference, speeds)
        warm, over, eig = evaluation_costs(problem, fit.hinges, speeds)
        print(f"  one evaluation: continued in the hinge {warm * 1e3:.2f} ms, over speed "
              f"{over * 1e3:.2f} ms per run (batch of 2); batched eigvals of the same "
              f"{len(speeds)} matrices {eig * 1e3:.2f} ms; ratios {warm / eig:.2f}x, "
              f"{over / eig:.2f}x")
    print(f"three fits: {total_wall:.1f} s wall, {total_cpu:.1f} s CPU "
          f"(load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
