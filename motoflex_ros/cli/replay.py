"""``motoflex replay BAG [--rate R] [--wait-for NODE] [--identify FILE]``: republish a run.

Without --identify: runs the bag_replay node in this process on the current ROS_DOMAIN_ID, so
that other nodes (a viewer, your own identification node) can listen; ``--rate 0`` publishes
as fast as possible; ``--wait-for NODE`` holds the first message until NODE has announced
itself on /rig/ready (otherwise a listener that joins late misses the first messages). With
--identify FILE: replays the bench topics into a fresh identification node on a private domain
and writes its results to FILE (the format of ``motoflex identify --out``), which reproduces
the live run's identification.json. A run whose status.json is not "complete" (failed,
interrupted, killed) is refused unless --allow-incomplete. Every chunk's CRC is checked before
anything is published (a corrupt bag: an error naming the chunk and its byte offset); a bag
written by ``motoflex bag repair`` is replayed with a warning that says so.
"""
from motoflex_ros.cli.output import add_force_option, check_new_file
from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.units import NS_PER_S

__all__ = ["register", "run", "bag_components", "replay_logs"]

CANONICAL = MOTORCYCLE_COMPONENTS


def register(subparsers):
    """Add the ``replay`` verb."""
    parser = subparsers.add_parser(
        "replay", help="republish a recorded bag with its /clock",
        description="Republish every topic of a bag (its /clock included) in recording order.")
    parser.add_argument("bag", help="bag directory, e.g. bags/<run>")
    parser.add_argument("--rate", type=float, default=None,
                        help="speed factor against the recorded time (0: as fast as possible; "
                             "default 1, or 0 with --identify)")
    parser.add_argument("--identify", metavar="FILE",
                        help="identify the components again from the replay; write FILE (an "
                             "existing file only with --force)")
    add_force_option(parser)
    parser.add_argument("--wait-for", action="append", default=[], metavar="NODE",
                        help="wait until node NODE has announced itself on /rig/ready (its "
                             "subscriptions see the replay) before the first message, so it "
                             "misses nothing; repeatable")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="replay a run that failed or did not finish (its status.json is "
                             "not 'complete')")
    parser.set_defaults(func=run)


def bag_components(info):
    """Components whose bench topics the bag holds (campaign order: frame, front, swingarm)."""
    names = {t.name.split("/")[2] for t in info.topics
             if t.name.startswith("/bench/") and t.name.endswith("/phase")}
    return [n for n in CANONICAL if n in names] + sorted(names - set(CANONICAL))


def run(args):
    """Check the bag (and that its run completed), then replay it (optionally into an
    identification node)."""
    import os
    import sys

    from motoflex_ros.errors import MotoflexError
    from motoflex_ros.launcher.status import require_complete
    from motoflex_ros.record.mcap_bag import bag_info
    rate = args.rate if args.rate is not None else (0.0 if args.identify else 1.0)
    if not 0.0 <= rate <= 1000.0:
        raise MotoflexError(f"--rate {rate:g} is out of range [0, 1000]")
    if args.identify:
        check_new_file(args.identify, args.force, "--identify")
    info = bag_info(args.bag, verify=True)   # every chunk's CRC, before anything is published
    incomplete = require_complete(info.path, args.allow_incomplete)
    if incomplete:
        print(f"warning: {incomplete}; replayed anyway (--allow-incomplete)", file=sys.stderr)
    if info.repaired:
        print(f"warning: {info.path} is a repaired bag, not as recorded: {info.repaired}",
              file=sys.stderr)
    if args.identify:
        return _identify(info, rate, args.identify)
    from motoflex_ros.nodes.bag_replay import BagReplay
    from motoflex_ros.nodes.node_main import run_node
    domain = os.environ.get("ROS_DOMAIN_ID", "").strip() or "0 (unset)"
    print(f"replaying {info.path}: {info.message_count} messages at rate {rate:g} on "
          f"ROS_DOMAIN_ID {domain}", flush=True)
    params = ["-p", f"bag:={info.path}", "-p", f"rate:={rate!r}"]
    if args.wait_for:
        params += ["-p", f"wait_for:={list(args.wait_for)!r}"]
    return run_node(BagReplay, ["motoflex_replay", "--ros-args", *params])


def replay_logs(out):
    """Where a failed ``replay --identify OUT`` keeps its node logs: OUT's folder,
    ``<OUT stem>_replay/log/<node>.log``."""
    from pathlib import Path
    out = Path(out)
    return out.parent / f"{out.stem}_replay"


def _identify(info, rate, out):
    from pathlib import Path

    from motoflex_ros.errors import MotoflexError
    from motoflex_ros.launcher.graph import NodeSpec
    from motoflex_ros.launcher.run import run_graph, work_folder
    components = bag_components(info)
    if not components:
        raise MotoflexError(f"{info.path}: no /bench/<component>/phase topic to identify from")
    out = Path(out).resolve()
    specs = [NodeSpec("identification", {"components": components, "result_file": str(out),
                                         "exit_when_done": True}),
             NodeSpec("bag_replay", {"bag": str(info.path), "rate": rate,
                                     "wait_for": ["identification"],
                                     "exclude": ["/rig/", "/identification/", "/vehicle/"]})]
    # removed at the end; on a failure the node logs are kept beside the output (not in
    # ~/.ros/log), and the message names them there
    with work_folder("motoflex_run_", keep_logs_in=replay_logs(out)) as work_dir:
        run = run_graph(specs, "bag_replay", info.duration_ns / NS_PER_S, work_dir=work_dir,
                        finishers=["identification"])
    print(f"identified {', '.join(components)} from {info.path} -> {out} "
          f"({run.wall_s:.1f} s)")
    return 0
