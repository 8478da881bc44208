"""Memory of the live measured-mode identification over a long stream (issue 23, point 3).

    python benchmarks/bench_live_memory.py [--minutes 30] [--rate-hz 1000] [--max-frames N]

A real identification node's measured-mode inputs (:class:`motoflex_ros.nodes.measured_inputs.
MeasuredInputs`, an rclpy node of this process) take ``minutes`` of a rig streaming at ``rate_hz``:
one geometry_msgs/WrenchStamped and one PoseArray of 4 markers per sample, as the serialized bytes
DDS hands a raw subscription (byte-identical to rclpy's serialization; the subscription callbacks
are called with them directly: the transport is not what is measured, and its queue is bounded on
its own, QUEUE_DEPTH). Printed: the resident set size (VmRSS) every simulated 5 minutes, the peak
(ru_maxrss), the kept arrays' bytes, and the counts of dropped oldest messages.

Stated bound: with the default max_frames (600,000: 10 minutes at 1 kHz) the kept arrays hold at
most 600,000 x (64 + 4 x 40) bytes = 134 MB, and the process's peak RSS stays under MEMORY_BOUND_MB
whatever the stream's length. Before issue 23 every frame was kept as Python tuples (about 600
bytes a sample: 1 GB for 30 minutes at 1 kHz, and without end). Exit code 1 if the peak is above
the bound.
"""
import argparse
import resource
import time

from motoflex_ros.units import NS_PER_S

MEMORY_BOUND_MB = 450.0
MARKERS = ((0.0, 0.0, 0.0), (0.05, 0.0, 0.0), (0.0, 0.05, 0.0), (0.05, 0.05, 0.01))


def rss_mb():
    """Resident set size of this process now [MB]."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=30.0)
    parser.add_argument("--rate-hz", type=float, default=1000.0)
    parser.add_argument("--max-frames", type=int, default=None)
    args = parser.parse_args()

    import tempfile
    from pathlib import Path

    import rclpy

    from motoflex_ros.nodes.cdr import points_cdr, wrench_cdr
    from motoflex_ros.nodes.measured_inputs import MEASURED_PARAMS, MeasuredInputs

    folder = Path(tempfile.mkdtemp(prefix="bench_live_memory_"))
    bench = folder / "bench.yaml"
    bench.write_text("bench: rig\nloaded_end: [0.5, 0.0, 0.0]\nmarkers: "
                     f"{[list(m) for m in MARKERS]}\n"
                     "sensor: {noise_m: 5.0e-6, latency_s: 0.0}\n")
    params = {p.name: p.default for p in MEASURED_PARAMS}
    params.update(bench_file=str(bench), qos="reliable")
    if args.max_frames:
        params["max_frames"] = args.max_frames
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=101)
    node = rclpy.create_node("identification", context=context)
    live = MeasuredInputs(node, params)
    take_load, take_markers = (sub.callback for sub in live.subscriptions)
    samples = int(args.minutes * 60.0 * args.rate_hz)
    step_ns = int(round(NS_PER_S / args.rate_hz))
    report_every = int(5 * 60 * args.rate_hz)
    start = time.perf_counter()
    print(f"{samples} samples ({args.minutes:g} min at {args.rate_hz:g} Hz), max_frames "
          f"{live.max_frames}; RSS at start {rss_mb():.0f} MB", flush=True)
    for k in range(samples):
        ns = 10**9 + k * step_ns
        take_load(wrench_cdr(ns, "rig_clamp", float(k % 1000)))
        take_markers(points_cdr(ns, "rig_clamp", MARKERS))
        if (k + 1) % report_every == 0:
            print(f"  {(k + 1) / args.rate_hz / 60:5.1f} min: RSS {rss_mb():6.0f} MB, kept "
                  f"{live.loads.size} loads and {live.frames.size // len(MARKERS)} frames "
                  f"({(live.loads.nbytes() + live.frames.nbytes()) / 1e6:.0f} MB of arrays)",
                  flush=True)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"dropped oldest: {live.received.get('dropped_oldest_load', 0)} loads, "
          f"{live.received.get('dropped_oldest_markers', 0)} marker messages; "
          f"{time.perf_counter() - start:.0f} s")
    print(f"peak RSS {peak:.0f} MB (bound {MEMORY_BOUND_MB:.0f} MB): "
          f"{'within' if peak <= MEMORY_BOUND_MB else 'ABOVE'} the bound")
    rclpy.try_shutdown(context=context)
    return 0 if peak <= MEMORY_BOUND_MB else 1


if __name__ == "__main__":
    raise SystemExit(main())
