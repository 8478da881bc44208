"""Full offline bench campaign of the three motorcycle components (``motoflex identify``).

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_identify.py [--repeat N]

Per component: building and reducing the component, planning, and the campaign (static,
harmonic at the first torsion and bending frequencies, sweep, free decay) through the stage
objects, with the default 5 micrometre sensor. Baseline in the same run: simulating the same
load histories with scipy.signal.lsim (first-order hold, vectorised, no sensing, no
identification); the ratio says what the per-sample stages (step, markers and rigid fit, peak
fits, settling) cost on top of the bare time response. Target: whole campaign <= 5 s.
"""
import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy import signal  # noqa: E402

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign  # noqa: E402
from motoflex_ros.bench.response import lateral_state_space  # noqa: E402
from motoflex_ros.formats.component_file import load_component  # noqa: E402

COMPONENTS = ("frame", "front_assembly", "swingarm")


def campaign(component):
    start = time.perf_counter()
    setup = setup_campaign(load_component(component))
    built = time.perf_counter()
    run = run_campaign(setup, trace=True)
    done = time.perf_counter()
    return setup, run, built - start, done - built


def lsim_baseline(setup, trace):
    """Time to simulate the same load history, test by test, with scipy.signal.lsim."""
    system = lateral_state_space(setup.reduced)
    n = system.A.shape[0]
    c = np.zeros((6, n))
    c[np.arange(6), system.end_dofs] = 1.0
    lti = signal.StateSpace(system.A, system.b[:, None], c, np.zeros((6, 1)))
    tests = np.array(trace["test"])
    start = time.perf_counter()
    for name in dict.fromkeys(trace["test"]):
        mask = tests == name
        t = trace["t"][mask]
        signal.lsim(lti, trace["force"][mask], t - t[0], interp=True)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    for _ in range(args.repeat):
        total = base = 0.0
        print(f"{'component':15s} {'samples':>8s} {'build [s]':>10s} {'campaign [s]':>13s} "
              f"{'us/sample':>10s} {'lsim [s]':>9s}")
        for component in COMPONENTS:
            setup, run, build, elapsed = campaign(component)
            baseline = lsim_baseline(setup, run.trace)
            total += build + elapsed
            base += baseline
            print(f"{component:15s} {run.n_samples:8d} {build:10.3f} {elapsed:13.3f} "
                  f"{1e6 * elapsed / run.n_samples:10.1f} {baseline:9.3f}")
        print(f"whole campaign: {total:.2f} s (target <= 5 s); lsim baseline {base:.2f} s; "
              f"ratio campaign/lsim = {total / base:.1f}")


if __name__ == "__main__":
    main()
