"""Benchmark of the vehicle engine: A(v) for 171 speeds plus all eigenvalues, against numpy's
batched eigvals on the same stacked matrices alone (docs/performance.md; target <= 2 for the
touring motorcycle).

Printed (best of several repeats, all measured in this run):
* one-off cost of the linearization (three complex-step linearizations + one check speed);
* build: A(v) = E(v)^-1 A(v) from the speed polynomial for 171 speeds (40-210 km/h, 1 km/h);
* build + eigvals, and its ratio to eigvals alone on the same (171, n, n) stack;
* the full modal sweep (eigenvectors on the tracking grid, MAC tracking of weave, wobble and
  capsize) and its ratio to eigvals alone;
* the same for the flexible touring motorcycle (three Craig-Bampton superelements, and the
  per-body superelements joined by the vehicle's joints; target <= 2),
  and the wall time of the whole accuracy study (bench identification + 20 models; target
  <= 30 s).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_vehicle.py
"""
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from motoflex_ros.config import config_path  # noqa: E402
from motoflex_ros.units import kmh_to_ms  # noqa: E402
from motoflex_ros.vehicle.linearize import linearize  # noqa: E402
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402
from motoflex_ros.vehicle.modes import modal_sweep  # noqa: E402

SPEEDS = kmh_to_ms(np.linspace(40.0, 210.0, 171))
REPEATS = 15


def best_time(fun, repeats=REPEATS):
    """Smallest wall time [s] of ``repeats`` calls of fun()."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fun()
        best = min(best, time.perf_counter() - start)
    return best


def bench(name, model):
    start = time.perf_counter()
    lin = linearize(model)
    t_lin = time.perf_counter() - start
    stack = lin.state_matrix(SPEEDS)
    t_eig = best_time(lambda: np.linalg.eigvals(stack))
    t_build = best_time(lambda: lin.state_matrix(SPEEDS))
    t_total = best_time(lambda: np.linalg.eigvals(lin.state_matrix(SPEEDS)))
    t_sweep = best_time(lambda: modal_sweep(lin, SPEEDS), repeats=5)
    n = stack.shape[-1]
    print(f"{name}: n = {n} states, {len(SPEEDS)} speeds")
    print(f"  linearization (one-off)           {t_lin * 1e3:8.1f} ms")
    print(f"  numpy eigvals on the stack        {t_eig * 1e3:8.2f} ms  (baseline)")
    print(f"  build A(v), 171 speeds            {t_build * 1e3:8.2f} ms")
    print(f"  build + eigvals                   {t_total * 1e3:8.2f} ms  ratio "
          f"{t_total / t_eig:.2f}")
    print(f"  modal sweep (eig + MAC tracking)  {t_sweep * 1e3:8.2f} ms  ratio "
          f"{t_sweep / t_eig:.2f}")


def flexible_touring(variant="flexible"):
    """The touring motorcycle with all three components flexible: ``variant`` 'flexible' (one
    clamped superelement each) or 'flexible_bodies' (per-body superelements, issue 12)."""
    from motoflex_ros.formats.component_file import load_component
    from motoflex_ros.study.identified_variants import build_variant
    from motoflex_ros.vehicle.lumped import COMPONENTS

    components = {name: load_component(name) for name in COMPONENTS}
    return build_variant(load_vehicle(config_path("vehicles", "touring")), variant,
                         list(COMPONENTS), {}, components)


def bench_accuracy_study():
    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.formats.component_file import load_component, load_components
    from motoflex_ros.study.identified_variants import carried_inertias
    from motoflex_ros.study.lumped_accuracy import accuracy_study
    from motoflex_ros.vehicle.lumped import COMPONENTS

    start = time.perf_counter()
    built = load_components(list(COMPONENTS))
    # with the carried inertias, as a campaign identifies: the principal variant needs them
    runs = identify_components(built, carried=carried_inertias(built))
    identified = {name: run.identification.to_dict() for name, (_, run) in runs.items()}
    t_ident = time.perf_counter() - start
    components = {name: load_component(name) for name in COMPONENTS}
    swept = []
    accuracy_study(load_vehicle(config_path("vehicles", "touring")), components, identified,
                   kmh_to_ms(np.unique(np.append(np.arange(40.0, 210.0, 5.0), 210.0))),
                   progress=lambda: swept.append(1))
    total = time.perf_counter() - start
    print(f"accuracy study: {total:.1f} s wall (bench identification {t_ident:.1f} s, "
          f"{len(swept)} models {total - t_ident:.1f} s; target 30 s)")


if __name__ == "__main__":
    for vehicle in ("touring", "whipple_benchmark"):
        bench(vehicle, load_vehicle(config_path("vehicles", vehicle)))
    bench("touring+flexible", flexible_touring())
    bench("touring+flexible_bodies", flexible_touring("flexible_bodies"))
    bench_accuracy_study()
