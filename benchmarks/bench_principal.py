"""What the principal hinges' two moment tests cost (issue 22: at most +30 %).

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_principal.py [--repeat N]

Per motorcycle component, the offline campaign and identification (``motoflex identify``) with
the shipped protocol and with the same protocol without its ``moments`` section, run in
alternation in one process (the fastest of ``--repeat`` runs each). Printed: samples and
seconds of both and their ratios. The ROS graph's campaign runs paced by its samples
(:mod:`motoflex_ros.nodes.pacing`), so its added share is the samples' ratio (printed too).
"""
import argparse
import os
import time
from dataclasses import replace

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from motoflex_ros.bench.campaign import run_campaign, setup_campaign  # noqa: E402
from motoflex_ros.bench.plan import plan_campaign  # noqa: E402
from motoflex_ros.study.variants import carried_inertias  # noqa: E402

COMPONENTS = ("frame", "front_assembly", "swingarm")


def timed(setup):
    start = time.perf_counter()
    run = run_campaign(setup)
    return time.perf_counter() - start, run


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    components, carried = carried_inertias(list(COMPONENTS))
    totals = {"with": [0.0, 0], "without": [0.0, 0]}
    print(f"{'component':15s} {'samples +/-':>14s} {'time with [s]':>14s} "
          f"{'without [s]':>12s} {'ratio':>6s}")
    for component in components:
        full = setup_campaign(component, carried=carried[component.name])
        protocol = replace(full.protocol, moments=None)
        bare = replace(full, protocol=protocol,
                       plan=plan_campaign(protocol, full.reduced, full.modes))
        best = {"with": float("inf"), "without": float("inf")}
        samples = {}
        for _ in range(args.repeat):
            for key, setup in (("with", full), ("without", bare)):
                seconds, run = timed(setup)
                best[key] = min(best[key], seconds)
                samples[key] = run.n_samples
        for key in totals:
            totals[key][0] += best[key]
            totals[key][1] += samples[key]
        print(f"{component.name:15s} {samples['with']:6d}/{samples['without']:<7d} "
              f"{best['with']:14.3f} {best['without']:12.3f} "
              f"{best['with'] / best['without']:6.3f}")
    (t_with, n_with), (t_without, n_without) = totals["with"], totals["without"]
    print(f"identify (3 components): {t_with:.2f} s with the moment tests, {t_without:.2f} s "
          f"without: ratio {t_with / t_without:.3f} (target <= 1.30)")
    print(f"campaign samples: {n_with} with, {n_without} without: ratio "
          f"{n_with / n_without:.3f} (the graph is paced by samples; target <= 1.30)")


if __name__ == "__main__":
    main()
