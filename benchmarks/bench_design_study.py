"""Benchmark of ``motoflex study design`` (issue 26): one evaluation against a full one.

One evaluation = re-reduction of the three varied components, the exact update of E(v), A(v)
(study/design_update.py), weave and wobble continued from the nominal and over 40-210 km/h
(5 km/h, 35 speeds), the four indices of eqs. 13-15 and the mass. The baseline is the full
path the update replaces: re-reduction, building and linearizing the flexible motorcycle
(vehicle.linearize.linearize, four complex-step linearizations), then the same tracking.
Ratios in the same run. With ``--dask`` also a batch of 32 designs in this process against a
2-worker LocalCluster (the scaling).
Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_design_study.py [--dask]
"""
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from motoflex_ros.cli.inputs import motorcycle_components, study_speeds  # noqa: E402
from motoflex_ros.config import resolve_config  # noqa: E402
from motoflex_ros.formats.design_space_file import (  # noqa: E402
    held_members_mass,
    load_design_space,
)
from motoflex_ros.study.design_evaluate import DesignBatch, design_evaluator  # noqa: E402
from motoflex_ros.study.design_study import FullEvaluator  # noqa: E402
from motoflex_ros.study.runner import local_cluster, run_study  # noqa: E402
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402


def _timed(function, *args, repeat=1):
    start = time.perf_counter()
    for _ in range(repeat):
        out = function(*args)
    return (time.perf_counter() - start) / repeat, out


def main():
    space = load_design_space("touring")
    vehicle = load_vehicle(resolve_config("vehicles", space.vehicle))
    components = motorcycle_components()
    speeds = study_speeds(5.0, 10.0)
    setup, evaluator = _timed(design_evaluator, space, vehicle, components, speeds,
                              held_members_mass(space, components))
    print(f"set-up (recording linearization, nominal sweep) {setup:.2f} s")
    rng = np.random.default_rng(0)
    X = space.lower + rng.random((8, len(space.names))) * (space.upper - space.lower)
    one = [_timed(evaluator, DesignBatch(space.names, x[None]).values())[0] for x in X]
    full = FullEvaluator(space, vehicle, components, tuple(speeds))
    full_time = [_timed(full.one, x)[0] for x in X[:2]]
    cheap, slow = float(np.median(one)), float(np.mean(full_time))
    print(f"one evaluation {cheap:.3f} s (median of 8; target 0.2 s); full linearization path "
          f"{slow:.2f} s; ratio {slow / cheap:.1f}x (load average {os.getloadavg()[0]:.1f})")
    if "--dask" in sys.argv:
        batch = DesignBatch(space.names, space.lower + rng.random((32, len(space.names)))
                            * (space.upper - space.lower))
        local = run_study(evaluator, batch, None, progress=False, block_size=32).seconds
        cluster = local_cluster(n_workers=2)
        try:
            dask = run_study(evaluator, batch, cluster, progress=False, block_size=8).seconds
        finally:
            cluster.close()
        print(f"32 designs: in process {local:.2f} s, 2-worker Dask {dask:.2f} s; speed-up "
              f"{local / dask:.2f}x")


if __name__ == "__main__":
    main()
