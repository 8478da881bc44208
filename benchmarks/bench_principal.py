"""What the principal hinges' two moment tests cost (issue 22: at most +30 %).

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_principal.py [--repeat N] [--campaign NAME]

Per motorcycle component, the offline campaign and identification (``motoflex identify``) with
the shipped protocol and with the same protocol without its ``moments`` section, run in
alternation in one process (the fastest of ``--repeat`` runs each). Printed: samples and
seconds of both and their ratios. The ROS graph's campaign runs paced by its samples
(:mod:`motoflex_ros.nodes.pacing`), so its added share is the samples' ratio (printed too);
``--campaign NAME`` also runs ``motoflex campaign --component NAME --report none`` with the
shipped protocol and without its moments and prints the graph's wall times (the campaign's
own timings.json) and their ratio.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign  # noqa: E402
from motoflex_ros.bench.plan import plan_campaign  # noqa: E402
from motoflex_ros.formats.component_file import load_components  # noqa: E402
from motoflex_ros.study.identified_variants import carried_inertias  # noqa: E402

COMPONENTS = ("frame", "front_assembly", "swingarm")


def timed(setup):
    start = time.perf_counter()
    run = run_campaign(setup)
    return time.perf_counter() - start, run


def graph_seconds(component, protocol=None):
    """The graph's wall time [s] of one ROS campaign (timings.json of the run)."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "run"
        extra = ["--protocol", str(protocol)] if protocol else []
        subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                        "--component", component, "--out", str(out), "--report", "none",
                        *extra], check=True, capture_output=True, text=True,
                       env=dict(os.environ, TMPDIR=folder))
        return json.loads((out / "timings.json").read_text())["graph"]


def campaign_ratio(component):
    """Graph wall times with the shipped protocol and with it less its moments."""
    import yaml

    from motoflex_ros.config import config_path, load_yaml
    data = load_yaml(config_path("protocols", component))
    data.pop("moments", None)
    with tempfile.TemporaryDirectory() as folder:
        bare = Path(folder) / f"{component}_no_moments.yaml"
        bare.write_text(yaml.safe_dump(data))
        with_moments, without = graph_seconds(component), graph_seconds(component, bare)
    print(f"campaign graph ({component}): {with_moments:.1f} s with the moment tests, "
          f"{without:.1f} s without: ratio {with_moments / without:.3f} (target <= 1.30)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--campaign", metavar="NAME",
                        help="also time the ROS graph's campaign of this component")
    args = parser.parse_args()
    components = load_components(list(COMPONENTS))
    carried = carried_inertias(components)
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
    if args.campaign:
        campaign_ratio(args.campaign)


if __name__ == "__main__":
    main()
