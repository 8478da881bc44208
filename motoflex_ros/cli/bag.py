"""``motoflex bag info PATH`` and ``motoflex bag repair PATH``: inspect and salvage bags."""
from motoflex_ros.cli.output import emit_json, print_table
from motoflex_ros.units import NS_PER_S

__all__ = ["register", "run"]


def register(subparsers):
    """Add the ``bag`` verb."""
    parser = subparsers.add_parser(
        "bag", help="inspect a recorded bag, or repair one whose recorder was killed",
        description="info: topics, types and message counts of a rosbag2 MCAP bag, every "
                    "chunk's CRC checked. repair: salvage what can be read (every chunk whose "
                    "CRC holds, up to the last complete record) into a valid bag marked as "
                    "repaired: a bag whose recorder was killed is rewritten in place, a "
                    "finished bag is never touched (the salvage goes to --out, default "
                    "<bag>_repaired).")
    parser.add_argument("action", choices=("info", "repair"))
    parser.add_argument("path", help="bag directory (or its .mcap file)")
    parser.add_argument("--out", metavar="DIR", help="repair: the new bag directory (must not "
                                                     "exist; default <bag>_repaired for a "
                                                     "finished bag)")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.set_defaults(func=run)


def run(args):
    """Print the bag's summary (of the repaired bag for ``repair``)."""
    from motoflex_ros.record.mcap_bag import bag_info, repair
    info = (repair(args.path, args.out) if args.action == "repair"
            else bag_info(args.path, verify=True))
    summary = {"path": str(info.path), "mcap_file": str(info.mcap_file),
               "message_count": info.message_count, "start_ns": info.start_ns,
               "duration_s": info.duration_ns / NS_PER_S, "repaired": info.repaired or None,
               "topics": [{"name": t.name, "type": t.type, "count": t.count}
                          for t in info.topics]}
    if args.json:
        emit_json(summary)
        return 0
    verb = "repaired" if args.action == "repair" else "bag"
    print(f"{verb}: {info.path}  ({info.message_count} messages, "
          f"{info.duration_ns / NS_PER_S:.3f} s)")
    if info.repaired:
        print(f"REPAIRED BAG (not as recorded): {info.repaired}")
    print_table(("topic", "type", "messages"),
                [(t.name, t.type, t.count) for t in info.topics])
    return 0
