"""``motoflex campaign``: the whole bench campaign through the ROS 2 node graph.

Starts every node as its own process on the run's ROS domain (ROS_DOMAIN_ID if set and free,
else a free one) with DDS on loopback (MOTOFLEX_DDS=network for a real bench), waits until
all are up, runs the campaign of each component, shows progress, prints the identified values
against the finite-element model's own and the paper's Table 2 and the identified motorcycle's
stability verdict (:mod:`.campaign_summary`; ``--json``: also the bag and the stability table),
stops every node and leaves the bag in ``--out``
(bags/<name>/: rosbag2 MCAP + identification.json, the same file ``motoflex identify --out``
writes, and provenance.json: command, version, git commit, seed, sensor noise). A node that
dies, SIGINT or SIGTERM stop the run with a message naming what happened.
status.json is written last: "complete", or "failed" with the reason (and then no
identification.json or report.html is left; see :mod:`motoflex_ros.launcher.status`).
"""
import json
import time
from pathlib import Path

from motoflex_ros.cli.inputs import namespace_argument, noise_argument, seed_argument
from motoflex_ros.cli.options import add_component_option, components_of
from motoflex_ros.cli.output import emit_json
from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.files import atomic_write_text

__all__ = ["register", "run"]

DEFAULT_COMPONENTS = MOTORCYCLE_COMPONENTS


def register(subparsers):
    """Add the ``campaign`` verb."""
    p = subparsers.add_parser("campaign", help="run the bench campaign through the ROS 2 graph",
                              description=__doc__.splitlines()[0])
    add_component_option(p, "a component: shipped name or YAML file; repeatable (default: "
                            "frame, front_assembly, swingarm)", metavar="NAME|FILE")
    p.add_argument("--protocol", metavar="FILE", help="protocol YAML (default: each "
                   "component's shipped protocol)")
    p.add_argument("--noise", type=noise_argument, metavar="SIGMA",
                   help="sensor noise standard deviation [m], in [0, 1e-3] (overrides the "
                        "protocol)")
    p.add_argument("--seed", type=seed_argument, default=0,
                   help="seed of the sensor noise, a whole number >= 0 (default 0)")
    p.add_argument("--out", metavar="DIR", help="bag directory to create (default "
                   "bags/campaign_<UTC time>)")
    p.add_argument("--namespace", type=namespace_argument, metavar="NS",
                   help="run every node and topic under this ROS namespace (e.g. /rig_a: two "
                        "rigs side by side in one ROS_DOMAIN_ID; default: the root, /)")
    p.add_argument("--json", action="store_true", help="print the results as JSON only")
    p.add_argument("--report", choices=("full", "quick", "none"), default="full",
                   help="at the end write <run>.rrd and report.html: 'full' computes the "
                        "studies the report shows (accuracy, sensitivity, ...; about a minute), "
                        "'quick' reports only what the run produced, 'none' writes neither")
    p.set_defaults(func=run)


def run(args):
    """Run the graph; print the table (or JSON); returns the exit code."""
    from motoflex_ros.cli.campaign_summary import (
        fe_static_k,
        json_output,
        stiffness_table,
        vehicle_table,
    )
    from motoflex_ros.launcher.campaign_graph import (
        RESULT_FILE,
        VEHICLE_COMPONENTS,
        VEHICLE_VARIANT,
        run_campaign_graph,
    )
    from motoflex_ros.launcher.provenance import write_provenance
    from motoflex_ros.launcher.status import run_status
    from motoflex_ros.record.mcap_bag import bag_info
    out = args.out or time.strftime("bags/campaign_%Y%m%d_%H%M%S", time.gmtime())
    results = [RESULT_FILE]
    if args.report != "none":
        from motoflex_ros.report.build import REPORT_FILE
        results.append(REPORT_FILE)
    started = time.time()
    with run_status(out, results):   # status.json last: complete, or failed and no results
        # progress on stderr, also with --json (stdout then holds the JSON alone)
        components = components_of(args, DEFAULT_COMPONENTS)
        outcome = run_campaign_graph(components, out, args.noise, args.seed, args.protocol,
                                     progress=True, namespace=args.namespace)
        write_provenance(outcome.bag, getattr(args, "argv", ["campaign"]), components,
                         args.seed, args.noise, args.protocol, started, outcome.inputs,
                         bag_info(outcome.bag).mcap_file)
        timings = {"graph": outcome.wall_s}
        written = _recording_and_report(outcome.bag, args.report, timings, progress=True)
    if args.json:
        emit_json(json_output(outcome, VEHICLE_VARIANT, VEHICLE_COMPONENTS))
        return 0
    info = bag_info(outcome.bag)
    stiffness_table(outcome.results, fe_static_k(components))
    if outcome.vehicle:
        print(f"\nlumped '{VEHICLE_VARIANT}' motorcycle of the identified values:")
        vehicle_table(outcome.vehicle)
    print(f"\nbag: {outcome.bag} ({info.message_count} messages, {len(info.topics)} topics); "
          f"results: {outcome.result_file} (ROS_DOMAIN_ID {outcome.domain_id})")
    for path in written:
        print(f"wrote {path}")
    print(_wall_times(outcome.wall_s, time.time() - started))
    return 0


def _wall_times(graph_s, whole_s):
    """The line of the run's wall times [s]: the node graph's part and the whole command's."""
    return (f"wall time {whole_s:.1f} s for the whole command (set-up, node graph, rerun "
            f"recording, report), of which the node graph {graph_s:.1f} s (nodes started to "
            f"the last result)")


def _recording_and_report(bag, mode, timings, progress):
    """The run's timings.json [s], rerun recording and report (issue 9); the paths written.

    ``timings``: {step: wall seconds} so far; the rerun conversion's time is added, and the
    report shows them beside its own steps.
    """
    written = []
    if mode != "none":
        from motoflex_ros.cli.recording import write_recording
        start = time.perf_counter()
        rrd, _ = write_recording(bag, progress=progress)
        timings["rerun recording"] = time.perf_counter() - start
        written.append(rrd)
    timings_file = Path(bag) / "timings.json"
    atomic_write_text(timings_file, json.dumps(timings, indent=1) + "\n")
    written.insert(0, timings_file)
    if mode != "none":
        from motoflex_ros.report.build import build_report
        report, _ = build_report(Path(bag), compute=mode == "full", progress=progress,
                                 outcome=_graph_outcome())
        written.append(report)
    return written


def _graph_outcome():
    """The run's outcome as the report states it: the report is the last result written
    before status.json ("complete"); if it cannot be written the run fails and loses it."""
    return {"status": "complete", "reason": None,
            "time_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "source": "motoflex campaign: every node finished; status.json follows this report"}
